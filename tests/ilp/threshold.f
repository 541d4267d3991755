heavy(p1).
heavy(p2).
heavy(p3).
heavy(p4).
heavy(p5).
heavy(p6).
heavy(p7).
heavy(p8).
