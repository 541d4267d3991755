"""A solid that runs beside a flight of stairs: the flight's side wall, not a box (wall56).

A staircase is built between walls, knee walls or strings that run along it: their faces are
parallel to the flight's run (or square to it at their ends), they stand at the treads' ends,
as long as the flight along the run and higher than its treads.  Seen in part (the wall's top
strip over its end face, or its side cut by the image's border) such a wall has a box's
faces; :func:`beside_flight` measures an object against a flight found in the same scan
(:func:`flight_geometry`, once a flight).  Not :func:`planerel.features.walls.flight_side`,
which asks of one large face, before proposals, whether its top edge follows a flight's
nosings (a string kept out of the support planes); this asks of a decided ``box`` answer
where it stands against a decided ``stairs`` answer.  :func:`side_planes` finds such walls
inside a ``stairs`` answer's own proposal (a flight merged with the wall it runs along), so
the answer's extent is the flight's.

The flight's frame: ``up``; the run ``r``, the horizontal direction of its risers' normals
(area-weighted), or, with no riser, square to the largest tread's long axis; the lateral
``l = up x r``.  The flight's extent along ``l`` and ``r`` is the 2-98 percentile range of
its planes' points; the object's the 5-95 range of its own.  Across the flight the object is
measured along its own largest upright face parallel to the run, when it has one (a wall's
side; a slightly turned estimate of ``r`` would otherwise spread a long side across), else
along ``l``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["FlightSide", "SKEW_SHARE", "beside_flight", "flight_frame", "flight_geometry",
           "side_planes"]

#: A plane of the object under this share of its points sets no :attr:`FlightSide.skew`
#: (slab101: a 0.0045 m^2 inclined sliver of a 1.4 m^2 side wall's top made the wall "skewed")
SKEW_SHARE = 0.05


@dataclass(frozen=True)
class FlightSide:
    """An object measured against a flight (metres, degrees)."""

    #: the object's extent across the flight (its thickness, for a wall)
    thick: float
    #: how far the object lies beyond the flight's lateral edge (negative: over the treads)
    gap: float
    #: how far the object lies beyond the flight's run interval (0 when they overlap)
    run_gap: float
    #: the object's highest point over the flight's highest point
    rise: float
    #: the largest angle of an upright plane of the object off the flight's axes (0: parallel
    #: or square to the run), or 90 when the object has an inclined plane (planes under
    #: :data:`SKEW_SHARE` of its points left out)
    skew: float

    def beside(self, thick: float, gap: float, reach: float, rise: float, angle: float,
               inside: float = 0.05) -> bool:
        """Whether this is a flight's side: thin across the flight (``<= thick``), at its
        edge (``-inside <= gap <= gap``), along its run (``run_gap <= reach``), higher than
        its treads (``rise >= rise``) and square to it (``skew <= angle``)."""
        return (self.thick <= thick and -inside <= self.gap <= gap and self.run_gap <= reach
                and self.rise >= rise and self.skew <= angle)


def _horizontal(v, up):
    v = np.asarray(v, dtype=np.float64)
    h = v - up * float(v @ up)
    n = float(np.linalg.norm(h))
    return None if n < 1e-6 else h / n


def _points(xyz, seg_labels, labels):
    m = np.isin(seg_labels, list(labels))
    p = xyz[m]
    return p[np.isfinite(p).all(axis=1)]


def flight_frame(planes, flight, xyz, seg_labels):
    """``(up, r, l)`` of the flight whose planes are the labels ``flight`` (module docstring),
    or None when it has neither an upright nor a horizontal plane."""
    up = np.asarray(planes.up, dtype=np.float64)
    up = up / np.linalg.norm(up)
    members = [planes.by_label(x) for x in flight]
    risers = [p for p in members if p.orientation == "vertical"]
    r = None
    if risers:
        acc, ref = np.zeros(3), None
        for p in risers:
            n = _horizontal(p.normal, up)
            if n is None:
                continue
            ref = n if ref is None else ref
            acc += p.n_points * (n if n @ ref >= 0 else -n)
        r = _horizontal(acc, up) if ref is not None else None
    if r is None:
        treads = [p for p in members if p.orientation == "horizontal"]
        if not treads:
            return None
        t = max(treads, key=lambda p: p.area)
        pts = _points(xyz, seg_labels, (t.label,))
        if len(pts) < 3:
            return None
        q = pts - np.outer(pts @ up, up)
        q = q - q.mean(axis=0)
        _w, v = np.linalg.eigh(q.T @ q)
        r = _horizontal(np.cross(up, v[:, -1]), up)
        if r is None:
            return None
    lat = np.cross(up, r)
    return up, r, lat / np.linalg.norm(lat)


def flight_geometry(planes, flight, xyz, seg_labels):
    """``(up, r, l, points)`` of the flight whose planes are the labels ``flight``: its frame
    (:func:`flight_frame`) and its planes' finite points ``(n, 3)``, or None when it has no
    frame or fewer than 3 points.  Measured once a flight, for every object against it."""
    flight = tuple(flight)
    frame = flight_frame(planes, flight, xyz, seg_labels)
    if frame is None:
        return None
    s = _points(xyz, seg_labels, flight)
    return None if len(s) < 3 else (*frame, s)


def beside_flight(planes, geometry, obj, xyz, seg_labels) -> FlightSide | None:
    """The object whose planes are the labels ``obj`` measured against a flight
    (:class:`FlightSide`), or None when the object has fewer than 3 points.

    Parameters
    ----------
    planes : PlaneSet
    geometry : tuple
        The flight's :func:`flight_geometry` (not None).
    obj : iterable of int
        Plane labels of the object's proposal.
    xyz : ndarray (H, W, 3)
        The scan's organized points.
    seg_labels : ndarray (H, W)
        The plane label of each pixel (the description's ``labels``).
    """
    obj = tuple(obj)
    up, r, lat, s = geometry
    b = _points(xyz, seg_labels, obj)
    if len(b) < 3:
        return None
    sl = np.percentile(s @ lat, [2, 98])
    sr = np.percentile(s @ r, [2, 98])
    bl = np.percentile(b @ lat, [5, 95])
    br = np.percentile(b @ r, [5, 95])
    # across the flight along the object's own side face, when it has one parallel to the run
    skew = 0.0
    side, side_n = None, 0
    # a sliver (under SKEW_SHARE of the object's points: a wall's top edge cut off at an angle)
    # does not make the object skewed
    members = [planes.by_label(x) for x in obj]
    least = SKEW_SHARE * sum(p.n_points for p in members)
    for p in members:
        if p.n_points < least:
            continue
        if p.orientation == "inclined":
            skew = 90.0
            continue
        if p.orientation != "vertical":
            continue
        n = _horizontal(p.normal, up)
        if n is None:
            continue
        a = float(np.degrees(np.arccos(min(1.0, abs(float(n @ r))))))
        skew = max(skew, min(a, 90.0 - a))
        if 90.0 - a <= 10.0 and p.n_points > side_n:
            side, side_n = (n if n @ lat >= 0 else -n), p.n_points
    across = side if side is not None else lat
    ba = np.percentile(b @ across, [5, 95])
    gap = max(bl[0] - sl[1], sl[0] - bl[1])
    run_gap = max(0.0, br[0] - sr[1], sr[0] - br[1])
    rise = float(np.percentile(b @ up, 95) - np.percentile(s @ up, 98))
    return FlightSide(float(ba[1] - ba[0]), float(gap), float(run_gap), rise, skew)


def side_planes(planes, labels, steps, xyz, seg_labels, angle: float, edge: float,
                rise: float) -> tuple:
    """The planes of a ``stairs`` answer's proposal that are a side of the flight, not a step
    (``decision.flight_trim``).

    The flight is the proposal's step planes (those in a ``stair_step/2`` pair): its run ``r``
    the area-weighted horizontal normal of its risers, its lateral extent the 2-98 percentile
    range of its treads' points along ``l = up x r``.  A side plane is an upright plane of the
    proposal that is in no step pair, whose horizontal normal lies within ``angle`` degrees of
    ``l`` (parallel to the run: a wall, a knee wall or a string, not a riser), whose points'
    median along ``l`` lies at or beyond either lateral edge, within ``edge`` m inside it, and
    which rises at least ``rise`` m over the treads' line (95th percentile of its points' heights
    over the line through the treads' centroids along the run, or over the treads' top when
    they are one level): a wall the flight runs along, not the flight's own stepped side face,
    which stays under its treads.

    Parameters
    ----------
    planes : PlaneSet
    labels : iterable of int
        Plane labels of the proposal.
    steps : iterable of (int, int)
        The scene's ``stair_step/2`` pairs (labels).
    xyz : ndarray (H, W, 3)
        The scan's organized points.
    seg_labels : ndarray (H, W)
        The plane label of each pixel.
    angle, edge, rise : float
        Degrees, metres, metres.

    Returns
    -------
    tuple of int
        The side planes' labels, in the proposal's order (empty: none, or no riser or tread
        among the step planes).
    """
    labels = tuple(labels)
    mine = set(labels)
    flight = {x for pair in steps for x in pair if set(pair) <= mine}
    risers = [planes.by_label(x) for x in flight if planes.by_label(x).orientation == "vertical"]
    treads = [x for x in flight if planes.by_label(x).orientation == "horizontal"]
    if not risers or not treads:
        return ()
    up = np.asarray(planes.up, dtype=np.float64)
    up = up / np.linalg.norm(up)
    acc, ref = np.zeros(3), None
    for p in sorted(risers, key=lambda p: p.label):
        n = _horizontal(p.normal, up)
        if n is None:
            continue
        ref = n if ref is None else ref
        acc += p.n_points * (n if n @ ref >= 0 else -n)
    r = None if ref is None else _horizontal(acc, up)
    if r is None:
        return ()
    lat = np.cross(up, r)
    lat = lat / np.linalg.norm(lat)
    tread_pts = _points(xyz, seg_labels, treads)
    if len(tread_pts) < 3:
        return ()
    lo, hi = np.percentile(tread_pts @ lat, [2, 98])
    # the treads' line along the run (their centroids' heights against their run positions),
    # which goes on over steps the segmentation left out of the pairs; one level: flat
    cent = np.array([[float(q @ r), float(q @ up)] for q in
                     (_points(xyz, seg_labels, (t,)).mean(axis=0) for t in sorted(treads))])
    if np.ptp(cent[:, 0]) > 1e-3 and np.ptp(cent[:, 1]) > 1e-3:
        slope, base = np.polyfit(cent[:, 0], cent[:, 1], 1)
    else:
        slope, base = 0.0, float(np.percentile(tread_pts @ up, 98))
    cos_max = np.cos(np.radians(angle))
    out = []
    for x in labels:
        p = planes.by_label(x)
        if x in flight or p.orientation != "vertical":
            continue
        n = _horizontal(p.normal, up)
        if n is None or abs(float(n @ lat)) < cos_max:
            continue
        q = _points(xyz, seg_labels, (x,))
        if len(q) < 3:
            continue
        med = float(np.median(q @ lat))
        over = q @ up - (base + slope * (q @ r))   # height over the treads' line
        if (med <= lo + edge or med >= hi - edge) and np.percentile(over, 95) >= rise:
            out.append(x)
    return tuple(out)
