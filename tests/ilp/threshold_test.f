heavy(t1).
heavy(t2).
heavy(t3).
