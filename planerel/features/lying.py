"""``lying/1``: the planes that lie on the ground as the top of something flat lying there
(:func:`lying_tops`): a top over a larger horizontal plane, adjacent to it or seen with that
ground around it across a depth jump (:func:`_ground_around`).

The settings are :class:`~planerel.features.relations.RelationParams`' ``lying_*``.  Moved out
of :mod:`planerel.features.relations` (split95), which still gives every name here.
"""

from __future__ import annotations

import math

import numpy as np

from planerel.features.relations import Relations, adjacent_only, noise_tilt

__all__ = ["lying_tops", "top_sized", "SMALL_NOISE_LENGTH"]

#: m: ``lying_small_noise`` reads the incline of a top at most this long as its noise may make
#: it (a block's top of 2.5-4.6 cm seen from 1 m); a longer top's incline is its own (a 9 cm
#: patch at 5.1 degrees with 4.1 mm of RMS on m2t2-real scene00 is no box's top) (level100)
SMALL_NOISE_LENGTH = 0.06


def lying_tops(planes, relations: Relations, support=(), cloud=None) -> frozenset:
    """Labels of the planes that lie on the ground as the top of something flat lying there
    (``lying/1``): what a book or a flat box lying on a table shows when its sides are seen
    edge-on (a few pixels, unsegmented) or hidden.

    A plane ``t`` is lying when

    - it is horizontal, or inclined by at most ``skirt_tilted`` degrees (a book leaning on
      another, a box resting on one edge), no support plane itself, ``lying_min_length`` to
      ``lying_length`` long and at least ``lying_width`` wide (a book, a flat box: something
      one can lift; a strip along a wall's foot is narrower), or, level within
      ``lying_small_tilt``, down to ``lying_small_length`` x ``lying_small_width`` (a product
      pack lying flat);
    - a horizontal plane ``g``, at least ``lying_ground`` times its area, lies under it:
      ``t``'s centroid stands over ``g``'s fit (along ``up``, where the line through the
      centroid meets ``g``) by at least ``lying_rise`` (or ``lying_snr`` times ``t``'s RMS
      fit residual, the sensor's depth noise where it lies, when more) and at most
      ``lying_rise_max``, and no point of ``t``'s hull is more than ``lying_rise`` below
      ``g`` (``t`` does not cross it);
    - ``g`` is adjacent to it (the relations' ``adjacent``), or, when no adjacent ground
      passes and ``cloud`` is given, ``g`` shows around it across a depth jump
      (:func:`_ground_around`; its pixel box within ``lying_ring`` pixels of the top's, past
      the ``lying_ring_band`` hugging its outline): a box seen from straight above, its sides
      hidden.

    A table's top (0.45-0.8 m over the floor), a chair's seat, a shelf's board, a landing or
    a tread stand higher over what is under them; a far piece of the floor that the sensor
    bends is level with the floor within the noise; a large platform is too long.  A
    laptop's base or a tin's lid lying on a table is lying too: what tells a book from them
    is the learner's to find (the lid, the curved side).

    Parameters
    ----------
    planes : PlaneSet
        Measured planes (``up`` set; its ``labels`` image for the ring test).
    relations : Relations
        From :func:`relate` on ``planes`` (its ``params`` give the tolerances).
    support : iterable of int
        Labels of the support planes (:func:`support_planes`): they are grounds, not tops.
    cloud : Cloud, optional
        The organized cloud (``xyz`` (H, W, 3)): with it, a top with no adjacent ground may
        lie on one around it (``lying_ring``).

    Returns
    -------
    frozenset of int
    """
    p = relations.params
    if p.lying_rise <= 0:
        return frozenset()
    by_label = {q.label: q for q in planes}
    sup = {int(x) for x in support}

    def top_like(t):
        return t is not None and t.label not in sup and top_sized(t, p)

    cand: dict[int, list] = {}
    for r in adjacent_only(relations):
        # adjacent only: a top within a few cm of the table but apart from it in the grid
        # (a tin's lid over its side) is no lying top (top25: with any ground within
        # lying_rise_max, the mOSD set's round objects got 6 box answers)
        if not r.adjacent:
            continue
        t, g = by_label.get(r.a), by_label.get(r.b)
        if not top_like(t) or g is None or g.orientation != "horizontal":
            continue
        if g.area < p.lying_ground * t.area:
            continue
        cand.setdefault(t.label, []).append(g)
    up = np.asarray(planes.up, float)
    out = {lbl for lbl, grounds in cand.items()
           if any(_lies_on(by_label[lbl], g, up, p) for g in grounds)}
    grounds = [g for g in planes if g.orientation == "horizontal"]
    if cloud is None or p.lying_ring <= 0 or planes.labels is None:
        if p.lying_ground_union:
            out |= _union_grounded(planes, relations, by_label, top_like, out, grounds, up,
                                   None, 0, p)
        return frozenset(out)
    k = _ring_width(planes.labels, p) + _ring_band(planes.labels, p)
    for t in planes:
        if t.label in out or not top_like(t):
            continue
        # a ground shows around the top: its pixel box meets the top's grown by the ring
        box = (t.bbox[0] - k, t.bbox[1] - k, t.bbox[2] + k, t.bbox[3] + k)
        under = [g for g in grounds if g.label != t.label and g.area >= p.lying_ground * t.area
                 and _boxes_meet(g.bbox, box) and _lies_on(t, g, up, p)]
        if under and _ground_around(t, under, up, planes, cloud, p):
            out.add(t.label)
    if p.lying_ground_union:
        out |= _union_grounded(planes, relations, by_label, top_like, out, grounds, up,
                               cloud, k, p)
    return frozenset(out)


def _union_grounded(planes, relations, by_label, top_like, done, grounds, up, cloud, k, p):
    """Labels of top-like planes (not in ``done``) that lie on a ground in pieces
    (``lying_ground_union``): horizontal planes ``t`` lies on (:func:`_lies_on`) whose rise
    under ``t``'s centroid agrees within ``max(5 mm, 3 x the larger fit RMS)`` of one
    anchor's form one ground of their summed area (their pixels are disjoint); it must be
    at least ``lying_ground`` times ``t``'s area, and one piece adjacent to ``t`` or the
    ring test (:func:`_ground_around`) against the pieces near it passes (ground56)."""
    adj: dict[int, set] = {}
    for r in adjacent_only(relations):
        if r.adjacent:
            adj.setdefault(r.a, set()).add(r.b)
            adj.setdefault(r.b, set()).add(r.a)
    out = set()
    for t in planes:
        if t.label in done or not top_like(t):
            continue
        box = (t.bbox[0] - k, t.bbox[1] - k, t.bbox[2] + k, t.bbox[3] + k)
        pieces = [g for g in grounds if g.label != t.label and _lies_on(t, g, up, p)]
        if not pieces:
            continue
        tc = np.asarray(t.centroid, float)
        rise = {}
        for g in pieces:
            gn = np.asarray(g.normal, float)
            rise[g.label] = float(gn @ (tc - np.asarray(g.centroid, float))) / float(gn @ up)
        for a in pieces:
            level = [g for g in pieces
                     if abs(rise[g.label] - rise[a.label])
                     <= max(0.005, 3.0 * max(float(g.rms), float(a.rms)))]
            if sum(g.area for g in level) < p.lying_ground * t.area:
                continue
            if any(g.label in adj.get(t.label, ()) for g in level):
                out.add(t.label)
                break
            if cloud is None or p.lying_ring <= 0 or planes.labels is None:
                continue
            near = [g for g in level if _boxes_meet(g.bbox, box)]
            if near and _ground_around(t, near, up, planes, cloud, p):
                out.add(t.label)
                break
    return out


def top_sized(t, p) -> bool:
    """Whether the plane ``t`` passes :func:`lying_tops`' size and incline tests with the
    :class:`~planerel.features.relations.RelationParams` ``p`` (not vertical; a top's size
    within ``skirt_tilted``, or a smaller top's level within its bounds)."""
    if t.orientation == "vertical" or t.length > p.lying_length:
        return False
    if t.incline <= p.skirt_tilted and t.length >= p.lying_min_length \
            and t.width >= p.lying_width:
        return True
    # a smaller top lying flat (lying56), level within its own noise (lying_small_noise)
    least = p.lying_small_length
    if p.lying_small_length > 0 and 0 < p.lying_tiny_length < least:
        least = p.lying_tiny_length   # a tiny top: squat over its ground (_lies_on)
    return (p.lying_small_length > 0 and _small_level(t, p)
            and t.length >= least and t.width >= p.lying_small_width)


def _small_level(t, p) -> bool:
    """A smaller top's incline test (:func:`lying_tops`): within ``lying_small_tilt`` degrees,
    or, with ``lying_small_noise``, within twice that where the rise the tilt makes along
    the top's length is at most ``lying_small_noise`` times its RMS fit residual (a tilt its
    own noise can make)."""
    if t.incline <= p.lying_small_tilt:
        return True
    if t.incline > 2.0 * p.lying_small_tilt or t.length > SMALL_NOISE_LENGTH:
        return False
    return t.incline <= noise_tilt(t.rms, t.length, p.lying_small_noise)


def _lies_on(t, g, up: np.ndarray, p) -> bool:
    """True when ``t``'s centroid rises over ``g``'s fit (along ``up``) within
    ``[max(lying_rise, lying_snr x t.rms), lying_rise_max]`` and no point of ``t``'s hull is
    more than ``lying_rise`` below ``g``, or, when ``t`` is more than ``lying_lean`` degrees off
    parallel to ``g`` (leaning on something), less than ``lying_rise`` above it
    (:func:`lying_tops`)."""
    gn = np.asarray(g.normal, float)
    den = float(gn @ up)
    if abs(den) < 0.5:
        return False
    # cosine of the angle between the top and its ground
    parallel = abs(float(np.asarray(t.normal, float) @ gn))
    if p.lying_tilt > 0 and parallel < math.cos(math.radians(p.lying_tilt)):
        return False  # not parallel to the ground: leaning on something, or no flat thing
    gc = np.asarray(g.centroid, float)
    # the sensor's noise where the plane is: its own fit's RMS residual
    least = max(p.lying_rise, p.lying_snr * float(t.rms))
    rise = float(gn @ (np.asarray(t.centroid, float) - gc)) / den
    if not least <= rise <= p.lying_rise_max:
        return False
    if (p.lying_tiny_length > 0 and t.length < p.lying_small_length
            and rise > p.lying_tiny_squat * t.length):
        return False   # a tiny top standing tall: a peg, a cylinder, a marker (tiny102)
    hull = np.asarray(t.hull3d, float)
    if not hull.size:
        return True
    low = float(((hull - gc) @ gn).min()) / den
    if p.lying_lean > 0 and parallel < math.cos(math.radians(p.lying_lean)):
        return low >= p.lying_rise  # leaning: its low edge stands its thickness up
    return low >= -p.lying_rise


def _ground_around(t, grounds, up: np.ndarray, planes, cloud, p) -> bool:
    """True when one of ``grounds`` shows around ``t`` across a depth jump: of the measured
    points within ``lying_ring`` pixels (scaled from 640 columns to the image's width; a
    square neighbourhood) of ``t``'s pixels, ``t``'s own pieces left out (a sliver tilted off
    it, a top in two pieces: planes within ``skirt_tilted`` of its normal whose centroid lies
    within ``lying_rise`` of its fit), at least ``lying_ring_ground`` lie at the ground's
    level and at most ``lying_ring_between`` between the ground's level and ``t``'s (a side
    in view: a tin's wall, a box seen from the side), each level within 3 times ``t``'s RMS
    (at least 5 mm, at most a quarter of ``t``'s rise over the ground).  The points are read
    once for every ground (``_top_kernels.ring_counts``)."""
    from planerel.features._top_kernels import ring_counts

    labels = planes.labels
    H, W = labels.shape
    k = _ring_width(labels, p)
    band = _ring_band(labels, p)
    r0, c0, r1, c1 = (int(v) for v in t.bbox)
    r0, c0 = max(r0 - k - band, 0), max(c0 - k - band, 0)
    r1, c1 = min(r1 + k + band + 1, H), min(c1 + k + band + 1, W)
    tn, tc = np.asarray(t.normal, float), np.asarray(t.centroid, float)
    cos_tilt = math.cos(math.radians(p.skirt_tilted))
    own = [q.label for q in planes
           if q.label != t.label and _boxes_meet(q.bbox, (r0, c0, r1, c1))
           and abs(float(np.asarray(q.normal, float) @ tn)) >= cos_tilt
           and abs(float((np.asarray(q.centroid, float) - tc) @ tn)) <= p.lying_rise]
    gn = np.array([g.normal for g in grounds], float).reshape(-1, 3)
    gc = np.array([g.centroid for g in grounds], float).reshape(-1, 3)
    den = gn @ up
    rise = ((tc - gc) * gn).sum(axis=1) / den
    # a level is a fit within the sensor's noise there (3 x the top's RMS, at least 5 mm),
    # never past a quarter of the rise: a side in view is "between" but for its last rows
    noise = np.full(len(gn), float(t.rms))
    if p.lying_ring_ground_noise:
        noise = np.maximum(noise, np.array([float(g.rms) for g in grounds], float))
    tol = np.minimum(0.25 * rise, np.maximum(0.005, 3.0 * noise))
    counts = ring_counts(labels, cloud.xyz, r0, r1, c0, c1, int(t.label), k,
                         np.asarray(own, np.int64), tn, tc, gn, gc, den, rise, tol, band)
    n = np.maximum(counts[:, 0], 1)
    return bool(((counts[:, 0] > 0) & (counts[:, 1] >= p.lying_ring_ground * n)
                 & (counts[:, 2] <= p.lying_ring_between * n)).any())


def _ring_band(labels: np.ndarray, p) -> int:
    """Pixels: ``lying_ring_band`` (given at 640 columns) at the image's width, 0 when off."""
    if p.lying_ring_band <= 0:
        return 0
    return max(1, int(round(p.lying_ring_band * labels.shape[1] / 640.0)))


def _ring_width(labels: np.ndarray, p) -> int:
    """Pixels: ``lying_ring`` (given at 640 columns) at the image's width, at least 2."""
    return max(2, int(round(p.lying_ring * labels.shape[1] / 640.0)))


def _boxes_meet(a, b) -> bool:
    """True when two pixel boxes ``(row0, col0, row1, col1)`` overlap."""
    return a[0] <= b[2] and b[0] <= a[2] and a[1] <= b[3] and b[1] <= a[3]
