"""Steps and flights: pairs of parallel faces one staircase step apart, and whether one
object's planes show a flight.

:func:`step_chain_pairs` (the proposals' step-chain join rule and ``stair_step/2``'s step
test) with its step measures (:func:`step_offset`, :func:`_step_kind`, the cut treads' and
two risers' steps), the tread-and-riser test of the convexity rule (:func:`_step_like`,
:func:`_regular_step`), and the flight evidence of ``classify``'s flight gate
(:func:`flight_faces`, :func:`flight_steps`, :func:`flight_evidence`,
:func:`flight_fragments`).  Moved out of :mod:`planerel.features.relations` (split95), which
still gives every name here.
"""

from __future__ import annotations

import math

import numpy as np

from planerel.features.cavities import edge_overlap
from planerel.features.open_treads import open_tread_pairs
from planerel.features.proposal_params import ProposalParams
from planerel.features.step_geometry import (
    _border_share,
    _cut_lengthwise,
    _extent,
    _horizontal_basis,
    _tread_depth_axis,
)
from planerel.features.tread_pieces import tread_unions
from planerel.features.vectors import cross3

__all__ = [
    "flight_faces",
    "flight_steps",
    "flight_evidence",
    "steps_of_one_flight",
    "stacked_riser_steps",
    "flight_fragments",
]


#: An open-riser tread's slab (``ProposalParams.open_treads``): at most this high along up
#: (metres; the real Kinect room's treads at 2-3 m: 0.01-0.13 with the front edge) and at most
#: this tilted from horizontal (degrees; their strips: 0-58).
OPEN_THICK = 0.15
OPEN_TILT = 60.0


def _regular_step(pa, pb, byl, nbrs, cos_tol, flight_riser_max: float | None = None,
                  seat_depth: float | None = None, turned: bool = False,
                  floor_low: bool = False, riser_pieces: bool = False) -> bool:
    """False when a tread and the riser above it are not one step of a regular flight: the
    tread has a riser below it (a vertical neighbour parallel to the one above, lower than
    the tread) and the two risers' heights differ by more than 30 %: a box standing on a
    box of the same width, not a staircase, whose steps rise alike.  With
    ``flight_riser_max`` (metres), a riser above higher than that (a flight's risers are not)
    is taken only as a seat's backrest: the tread at most ``seat_depth`` metres deep across
    the edge and with no vertical neighbour lower than it (a chair's seat stands on legs; a
    box's top has its sides below it, a platform or floor is deeper).  With ``turned``, a
    tread with vertical neighbours lower than it none of which is parallel or perpendicular
    (within the angle of ``cos_tol``) to the riser above is no step either: a box standing
    turned on another box (a flight's riser above is parallel to the riser below, a solid
    flight's side is perpendicular to both; tabletop22).  With ``floor_low``, the riser
    below counts no higher than the tread's height above the floor when that is lower (and
    above 0): a hull's outliers made a low box's side as high as the taller box's face over
    it (synth22r).  With ``riser_pieces`` the risers
    below are measured together (the height range of all their hulls) rather than each on its
    own: a real riser below a rounded nosing comes in pieces, and a 5 cm strip of it measured
    alone against the riser above cut a real staircase (2026-11-29)."""
    if "horizontal" not in (pa.orientation, pb.orientation):
        return True
    tread, riser = (pa, pb) if pa.orientation == "horizontal" else (pb, pa)
    if (riser.orientation != "vertical" or getattr(tread, "height", None) is None
            or getattr(riser, "height", None) is None or riser.height <= tread.height):
        return True
    up = np.asarray(tread.normal, float)
    nr = np.asarray(riser.normal, float)
    high = float(np.ptp(np.asarray(riser.hull3d, float) @ up))
    if flight_riser_max is not None and high > flight_riser_max:
        # higher than a flight's riser: only a seat's backrest, a seat deep and with no face
        # below it (a chair's seat stands on legs; a box's top has its sides below it)
        if seat_depth is not None and float(np.ptp(np.asarray(tread.hull3d, float) @ nr)) > seat_depth:
            return False
        for k in nbrs.get(tread.label, ()):
            q = byl[k]
            if (q is not riser and q.orientation == "vertical"
                    and getattr(q, "height", None) is not None and q.height < tread.height):
                return False
    if turned:
        below = [abs(float(np.asarray(byl[k].normal, float) @ nr)) for k in nbrs.get(tread.label, ())
                 if byl[k] is not riser and byl[k].orientation == "vertical"
                 and getattr(byl[k], "height", None) is not None and byl[k].height < tread.height]
        sin_tol = math.sqrt(max(0.0, 1.0 - cos_tol * cos_tol))
        if below and all(sin_tol < c < cos_tol for c in below):
            return False
    lows = []
    for k in nbrs.get(tread.label, ()):
        q = byl[k]
        if (q is riser or q.orientation != "vertical" or getattr(q, "height", None) is None
                or q.height >= tread.height
                or abs(float(np.asarray(q.normal, float) @ nr)) < cos_tol):
            continue
        h = np.asarray(q.hull3d, float) @ up
        if riser_pieces:
            lows.append(h)
            continue
        low = float(np.ptp(h))
        if floor_low and 0.0 < tread.height < low:
            low = float(tread.height)
        if abs(high - low) > 0.3 * max(high, low):
            return False
    if lows:
        # the riser below in however many pieces (a strip under a real stair's nosing apart
        # from the rest of its riser): their height range together
        h = np.concatenate(lows)
        low = float(h.max() - h.min())
        if floor_low and 0.0 < tread.height < low:
            low = float(tread.height)
        if abs(high - low) > 0.3 * max(high, low):
            return False
    return True


def _step_kind(p, tilt) -> str | None:
    """``"tread"`` for a face within ``tilt`` degrees of horizontal, ``"riser"`` within ``tilt``
    of vertical, else None (a far tread's strip measures a few degrees off horizontal).
    ``tilt`` is one angle for both or a pair ``(tread tilt, riser tilt)``
    (:attr:`ProposalParams.step_tilts`: a carpeted or raked riser leans back from its nosing)."""
    tread, riser = (tilt, tilt) if isinstance(tilt, (int, float)) else tilt
    if p.orientation == "horizontal" or p.incline <= tread:
        return "tread"
    if p.orientation == "vertical" or p.incline >= 90.0 - riser:
        return "riser"
    return None


def _anchor_offset(face, anchor, up) -> np.ndarray:
    """Horizontal offset ``(3,)`` from a face's centroid to the nearest point of another plane's
    hull (zero when the centroid lies over the hull)."""
    import shapely
    from shapely.geometry import Point, Polygon
    from shapely.ops import nearest_points

    c = np.asarray(face.centroid, float)
    H = np.asarray(anchor.hull3d, float)
    e1, e2 = _horizontal_basis(up)
    P = np.stack([H @ e1, H @ e2], 1)
    q = (float(c @ e1), float(c @ e2))
    geom = Polygon(P) if len(P) >= 3 else shapely.LineString(P) if len(P) == 2 else Point(P[0])
    if not geom.is_valid:
        geom = geom.convex_hull
    if geom.contains(Point(q)):
        return np.zeros(3)
    near = nearest_points(geom, Point(q))[0]
    return (near.x - q[0]) * e1 + (near.y - q[1]) * e2


#: a two-rise step whose face between is seen needs its other end within this fraction of a
#: rise of one rise beyond that face (``skip_missing``)
SKIP_GRID = 0.15


def _surely_deep(p, up, limit: float) -> bool:
    """True when ``p``'s hull, projected on the horizontal plane, is more than ``limit`` wide
    across every direction, known without :func:`_tread_depth_axis`' rotating calipers.

    The projection's area ``A`` over its diameter ``D`` (the largest distance between two
    of its vertices) bounds its smallest width ``w`` from below: a convex polygon lies in a
    strip ``w`` wide and at most ``D`` long, so ``A <= w D``; ``hull3d`` is the outline of a
    convex hull (a subset of its vertices when simplified), so its projection is a simple
    polygon with at most its own hull's area and the same diameter.  The extent across any
    horizontal direction, the calipers' included, is at least ``w``; the margin (relative
    ``1e-6``) covers the rounding of either computation.  In Python floats: a hull has 3-20
    vertices, and the calipers' numpy calls take 30 us warm, 150 us in the flow.  False for
    fewer than 3 vertices or no area (the calipers decide)."""
    H = p.hull3d
    m = len(H)
    if m < 3:
        return False
    (a0, a1, a2), (b0, b1, b2) = (e.tolist() for e in _horizontal_basis(up))
    xs, ys = [], []
    for x, y, z in np.asarray(H, float).tolist():
        xs.append(x * a0 + y * a1 + z * a2)
        ys.append(x * b0 + y * b1 + z * b2)
    twice = 0.0
    for i in range(m):
        twice += xs[i] * ys[i - 1] - xs[i - 1] * ys[i]
    need = limit * (1 + 1e-6)
    # the diagonal of the vertices' box first (at least D); the diameter itself only then
    diag = math.hypot(max(xs) - min(xs), max(ys) - min(ys))
    if diag > 0 and 0.5 * abs(twice) > need * diag:
        return True
    d2 = max((xs[i] - xs[j]) ** 2 + (ys[i] - ys[j]) ** 2 for i in range(m) for j in range(i))
    return d2 > 0 and 0.5 * abs(twice) > need * math.sqrt(d2)


def _some_rise(dv: float, rise, spans) -> bool:
    """Whether ``dv`` is one rise of a step over one of ``spans`` (1 or 2 faces apart): the
    rise half of :func:`step_chain_pairs`' step test, asked before the pair's run and its
    treads' step directions (``_tread_depth_axis``, 30-300 us a tread) are measured."""
    for k in spans:  # (a loop, not any() over a generator: about 1 us a pair less)
        if rise[0] <= dv / k <= rise[1]:
            return True
    return False


def flight_faces(planes, labels, params: ProposalParams | None = None) -> bool:
    """Whether the planes ``labels`` of one object hold a flight's faces in a regular row: a
    step of :func:`step_chain_pairs` (three treads or three risers or more, each one rise above
    and one run beyond the last), with the proposals' step settings ``params``.

    With ``params.open_treads``, three open-riser treads or more in a row
    (:func:`planerel.features.open_treads.open_tread_pairs`) are such a row too: seen at
    range their tops and front edges are fitted as strips 15-55 degrees off horizontal, and
    such a flight can show no horizontal plane at all (riser26).
    A flight seen from below shows its risers and no tread; a wall with the posts of a banister
    before it, or a cabinet's faces, hold no such row (hunt25: the decision's level gate,
    :func:`planerel.ilp.metrics.level_refusals`, keeps ``stairs`` for such an object).

    Parameters
    ----------
    planes : PlaneSet
    labels : iterable of int
    params : ProposalParams, optional
    """
    p = params or ProposalParams()
    labels = tuple(labels)
    if step_chain_pairs(planes, labels, (p.step_rise_min, p.step_rise_max),
                        (p.step_run_min, p.step_run_max), p.step_overlap or 0.5,
                        p.concave_tol, tilt=p.step_tilts, cut_long_side=p.cut_long_side,
                        skip_missing=p.skip_missing, tread_axes=p.step_tread_axes,
                        cut_top=p.step_cut_top, cut_chain=p.step_cut_chain,
                        tread_pieces=p.step_tread_pieces, two_risers=p.step_two_risers):
        return True
    # an open-riser flight's treads, fitted as strips tilted off horizontal at range
    return p.open_treads and bool(open_tread_pairs(planes, labels, (p.step_rise_min, p.step_rise_max),
                                                   p.step_run_max, OPEN_THICK, OPEN_TILT))


#: Where :func:`flight_steps` looks for steps (rise and run per step, metres): wider than a
#: staircase's, so that every level change between parallel faces of an object is found.
STEP_WINDOW_RISE = (0.05, 0.35)
STEP_WINDOW_RUN = (0.08, 0.8)
#: A staircase's step (rise, run; metres): the demo's training flights rise 0.12-0.22 m and
#: run 0.22-0.36 m (:mod:`planerel.synth.generator`, :class:`planerel.synth.world.WorldRange`),
#: widened by a third of a rise and of a run for what a sensor measures of them
#: (:func:`flight_evidence`).
STAIR_RISE = (0.08, 0.25)
STAIR_RUN = (0.15, 0.45)
#: Two steps of one flight: their rises and runs per step within this ratio (the regular row's
#: tolerance of :func:`step_chain_pairs`).
STEP_AGREE = 0.7


def flight_steps(planes, labels, params: ProposalParams | None = None, *,
                 keep_cut: bool = False) -> list:
    """Every step between parallel faces of the planes ``labels`` of one object: two treads or
    two risers :data:`STEP_WINDOW_RISE` above and :data:`STEP_WINDOW_RUN` beyond each other
    (one span, no chain asked: :func:`step_chain_pairs` with ``chain=False``), with the
    proposals' step settings ``params``.  With ``keep_cut``, treads the image border cuts
    along their length take part too (:func:`flight_fragments`).

    Returns
    -------
    list of (int, int, float, float)
        ``(lower label, higher label, rise, run)`` per step, metres.
    """
    p = params or ProposalParams()
    steps = step_chain_pairs(planes, tuple(labels), STEP_WINDOW_RISE, STEP_WINDOW_RUN,
                             p.step_overlap or 0.5, p.concave_tol, tilt=p.step_tilts, skip=False,
                             cut_long_side=p.cut_long_side, tread_axes=p.step_tread_axes,
                             chain=False, drop_cut=not keep_cut)
    return [(int(lo), int(hi), float(r), float(g)) for lo, hi, r, _d, _k, g in steps]


def flight_evidence(planes, labels, params: ProposalParams | None = None, *,
                    fragments: bool = True) -> bool:
    """Whether the planes ``labels`` of one object show a staircase's steps: a regular row of
    three faces (:func:`flight_faces`), or steps that are one flight's (pile26).

    Without a row (a flight of two steps: two treads and two risers), the object's steps
    (:func:`flight_steps`: every level change between two parallel treads or risers) must be
    one flight's: the lowest step a stair's (:data:`STAIR_RISE`, :data:`STAIR_RUN`), and
    every other step one, two or three of it, rise and run alike (within :data:`STEP_AGREE`).
    Cartons packed on a pallet at three heights (a step of 0.10 m beside one of 0.20 m whose
    run is no longer) and boxes of two heights touching (one step 0.30 m high and 0.67 m
    deep) are no flight, nor is an object with no step at all (a machine's faces, a room
    wall's posts).  Two levels one stair rise above and one run beyond each other are a step
    to this test whatever they are made of: a pile of two heights of stair-like cartons stays
    a flight.  With ``fragments`` (``decision.flight_fragments``), a flight seen in fragments
    counts too (:func:`flight_fragments`: risers stacked one on the other, treads the image
    border cuts; flight48).

    Parameters
    ----------
    planes : PlaneSet
    labels : iterable of int
    params : ProposalParams, optional
    fragments : bool
        Ask :func:`flight_fragments` when the steps above are not one flight's.
    """
    labels = tuple(labels)
    return (flight_faces(planes, labels, params)
            or steps_of_one_flight(flight_steps(planes, labels, params))
            or (fragments and flight_fragments(planes, labels, params)))


def steps_of_one_flight(steps) -> bool:
    """Whether ``steps`` (``(lower, higher, rise, run)`` per step, :func:`flight_steps`) are
    one flight's: at least one, the lowest (least rise) a stair's (:data:`STAIR_RISE`,
    :data:`STAIR_RUN`), and every other one, two or three of it in rise and run alike, each
    within :data:`STEP_AGREE` (:func:`flight_evidence`)."""
    if not steps:
        return False
    _lo, _hi, rise, run = min(steps, key=lambda s: (s[2], s[3]))
    if not (STAIR_RISE[0] <= rise <= STAIR_RISE[1] and STAIR_RUN[0] <= run <= STAIR_RUN[1]):
        return False

    def agrees(r: float, g: float) -> bool:
        return any(STEP_AGREE <= r / (k * rise) <= 1 / STEP_AGREE
                   and STEP_AGREE <= g / (k * run) <= 1 / STEP_AGREE for k in (1, 2, 3))

    return all(agrees(r, g) for _a, _b, r, g in steps)


#: Two risers of one flight are stacked: the higher one's foot lies within this fraction of a
#: rise of the lower one's top edge, and the higher one is at most this fraction taller than a
#: rise (:func:`stacked_riser_steps`; on the varied world's fragmented flights the foot lies
#: within 0.08 of a rise and the higher riser at most 1.07 rises high, flight48).
STACK_TOL = 0.15
#: ... and they overlap across the flight by at least this fraction of the narrower one's
#: width (a riser seen in part, cut by the image border or hidden, lies within its flight).
STACK_OVERLAP = 0.5


def stacked_riser_steps(planes, labels, params: ProposalParams | None = None) -> list:
    """Steps between two risers of the planes ``labels`` (faces within ``params.step_tilt``
    degrees of vertical, normals within ``params.concave_tol``) that stand one on the other:
    a flight's risers, however much of their width is seen.

    The varied world's flights at 160x120 come in fragments (accept45, flight48): a riser's
    width seen in part (the border, a rail, too few pixels) makes two risers' areas differ
    more than :func:`step_chain_pairs` allows (3 times), and the centroid of a riser whose top
    the image cuts lies under its middle.  What a fragment keeps is its height: a flight's
    riser is one rise high and the next one starts where it ends.  So two risers are a step
    when the higher one's foot lies within :data:`STACK_TOL` of a rise of the lower one's top
    edge, the rise (foot to foot) is a stair's (:data:`STAIR_RISE`), the higher one is no
    taller than a rise (within :data:`STACK_TOL`; it may be cut shorter), their horizontal
    offset along the lower one's normal is a stair's run (:data:`STAIR_RUN`) and they overlap
    across the flight by :data:`STACK_OVERLAP` of the narrower one.  Boxes standing on the
    floor side by side or one behind the other have their faces' feet at one level: no step;
    a carton behind a lower one shows its face from the lower one's top up, a step only when
    no taller than the lower one (a pile of two heights 0.25 and 0.55 m is none).

    Returns
    -------
    list of (int, int, float, float)
        ``(lower label, higher label, rise, run)`` per step, metres (as :func:`flight_steps`).
    """
    p = params or ProposalParams()
    up = np.asarray(planes.up, float)
    cos_tol = math.cos(math.radians(p.concave_tol))
    want = set(labels)
    risers = []
    for q in planes:
        if q.label not in want or _step_kind(q, p.step_tilts) != "riser":
            continue
        h = np.asarray(q.hull3d, float)
        if len(h) < 2:
            continue
        t = h @ up
        n = np.asarray(q.normal, float)
        nh = n - (n @ up) * up
        norm = float(np.linalg.norm(nh))
        if norm < 1e-9:
            continue
        risers.append((q, float(t.min()), float(t.max()), nh / norm, h))
    out = []
    for i, (a, a0, a1, na, ha) in enumerate(risers):
        for b, b0, b1, nb, hb in risers[i + 1:]:
            if abs(float(np.asarray(a.normal, float) @ np.asarray(b.normal, float))) < cos_tol:
                continue
            lo, l0, l1, nl, hl, hi, h0, h1, hh = ((a, a0, a1, na, ha, b, b0, b1, hb) if a0 <= b0
                                                  else (b, b0, b1, nb, hb, a, a0, a1, ha))
            rise = h0 - l0
            if not STAIR_RISE[0] <= rise <= STAIR_RISE[1]:
                continue
            if abs(h0 - l1) > STACK_TOL * rise or h1 - h0 > (1.0 + STACK_TOL) * rise:
                continue
            d = np.asarray(hi.centroid, float) - np.asarray(lo.centroid, float)
            run = abs(float(d @ nl))
            if not STAIR_RUN[0] <= run <= STAIR_RUN[1]:
                continue
            across = cross3(up, nl)
            pl, ph = hl @ across, hh @ across
            inter = min(pl.max(), ph.max()) - max(pl.min(), ph.min())
            if inter < STACK_OVERLAP * min(np.ptp(pl), np.ptp(ph)) or inter <= 0:
                continue
            out.append((int(lo.label), int(hi.label), float(rise), float(run)))
    return out


def flight_fragments(planes, labels, params: ProposalParams | None = None) -> bool:
    """Whether the planes ``labels`` of one object show a flight seen in fragments
    (flight48): its stacked risers (:func:`stacked_riser_steps`) are one flight's steps
    (:func:`steps_of_one_flight`), or its steps with the treads the image border cuts along
    their length (:func:`flight_steps` with ``keep_cut``; a flight seen from its top, the far
    treads running out of the image) are.

    The second part of :func:`flight_evidence`'s test, asked when the object's faces make no
    regular row and its whole faces' steps are not one flight's: accept45 measured 27-52 true
    160x120 flights a varied model refused so (risers whose areas differ more than 3 times,
    treads cut by the border); each list must still be one flight's as a whole, so a pile's
    unequal steps keep it out.

    Parameters
    ----------
    planes : PlaneSet
    labels : iterable of int
    params : ProposalParams, optional
    """
    labels = tuple(labels)
    stacked = stacked_riser_steps(planes, labels, params)
    if stacked and steps_of_one_flight(stacked):
        return True
    return steps_of_one_flight(flight_steps(planes, labels, params, keep_cut=True))


def step_offset(lo, hi, kind: str, up, tread_axis=None) -> tuple[float, np.ndarray]:
    """How far, horizontally, the higher face ``hi`` of a step lies beyond the lower ``lo``,
    and in which direction: for risers along the lower one's horizontal normal, for treads
    between their centroids, or (``tread_axis``, a function giving a tread's depth axis and
    elongation, :func:`_tread_depth_axis`) across two long treads whatever the lateral offset
    of their centroids (a tread partly hidden by a leg or the image border).

    Parameters
    ----------
    lo, hi : Plane
    kind : str
        ``"riser"`` or ``"tread"``.
    up : ndarray, shape (3,)
    tread_axis : callable, optional

    Returns
    -------
    (float, ndarray of shape (3,))
        The run (m) and the unit horizontal step direction.
    """
    d = np.asarray(hi.centroid, float) - np.asarray(lo.centroid, float)
    dh = d - (d @ up) * up
    if kind == "riser":
        nh = np.asarray(lo.normal, float) - (np.asarray(lo.normal, float) @ up) * up
        nh /= max(float(np.linalg.norm(nh)), 1e-9)
        dist = abs(float(dh @ nh))
        return dist, (nh if float(dh @ nh) >= 0 else -nh)
    dist = float(np.linalg.norm(dh))
    direction = dh / max(dist, 1e-9)
    if tread_axis is not None:
        (da, ea), (db, eb) = tread_axis(lo), tread_axis(hi)
        if min(ea, eb) >= 1.5 and abs(float(da @ db)) >= _COS_25:
            along = float(dh @ da)
            return abs(along), (da if along >= 0 else -da)
    return dist, direction


#: cos 25 degrees: two step directions (or tread axes) that agree
_COS_25 = math.cos(math.radians(25.0))


def step_chain_pairs(planes, labels=(), rise=(0.08, 0.30), run=(0.12, 0.60),
                     min_overlap: float = 0.5, angle_tol: float = 10.0,
                     max_ratio: float = 3.0, tilt=12.0, skip: bool = True,
                     min_width: float = 0.5, cut_long_side: bool = True,
                     skip_missing: bool = False, tread_axes: bool = False,
                     chain: bool = True, cut_top: bool = False, drop_cut: bool = True,
                     cut_chain: bool = False, tread_pieces: bool = False,
                     two_risers: bool = False):
    """Pairs of parallel faces that are consecutive steps of a staircase (in a chain of >= 3).

    Two treads (faces within ``tilt`` degrees of horizontal) or two risers (within ``tilt`` of
    vertical; ``tilt`` one angle or ``(tread, riser)`` angles: :attr:`ProposalParams.step_tilts`)
    with normals within ``angle_tol`` degrees are a *step* when the higher one's
    centroid lies ``rise`` above and ``run`` beyond the lower one's (horizontally; for risers
    along their normal), their extents across that direction overlap by at least
    ``min_overlap`` (interval IoU: one flight's width), their areas differ by at most
    ``max_ratio`` times and each is at most one step deep (a tread's extent along the step
    direction at most ``run[1]``, a riser's height at most ``rise[1]``): not a landing or the
    floor a flight goes down from.  With ``skip``, two faces two rises above and two runs
    beyond each other are a step too (the face between them not found: cut by a rail, too few
    pixels), counted as two.  A step counts only when one of its faces is also a face of
    another step in the same direction (unit horizontal offsets within 25 degrees) with a rise
    per step within 30 %: three faces in a regular row.  Two boxes, one behind the other, make
    one step, not a chain; a staircase seen from above (treads only) or below (risers only)
    makes many.  A tread the image border cuts along its length (the landing the camera stands
    on, seen to the bottom edge) is no member: its depth is not seen (``cut_long_side``: only
    the border on the sides of its pixel box's long side counts, :func:`_cut_lengthwise`).
    With ``skip_missing``, a two-rise step spans a *missing* face only: when one of its faces
    already makes a one-rise step (same direction) with a face lying between the two in
    height, makes none with the other end, and the other end lies more than ``SKIP_GRID``
    (15 %) of a rise off one rise beyond it, the two-rise step is dropped (a box's top 0.21 m
    high two runs before a flight's tread, the tread between at 0.33 m, rise 0.17 m; a
    flight's lowest riser, partly hidden and no step of the next, lies on the flight's
    rises; synth22r).  Two treads alone make
    a step that counts when both are at least ``min_width`` wide across the flight and 1.5
    times wider than deep, and a third horizontal plane (any: the landing, the floor) lies
    one more rise (within 30 %) above or below and comes within ``run[1]`` of them
    horizontally, on the flight's line: a short flight seen from above.  With ``cut_top``, the
    higher of those two treads may be one the border cuts along its length (a flight going
    down from the landing the camera stands on: the top tread, nearest the camera, runs out of
    the image's bottom edge; :func:`_cut_top_steps`), counted only when the lower tread is in
    no step already counted (above a row of treads the cut strip may be the landing); with
    ``chain=False`` such steps are listed too.

    Parameters
    ----------
    planes : PlaneSet
    labels : iterable of int
        Planes to consider (e.g. the non-support planes); empty = all.

    cut_chain : bool
        With ``chain``, a tread the border cuts along its length still extends a counted row
        by one step at either end when the step passes every test a step of whole treads
        passes and repeats the row's rise and run (:func:`_cut_chain_steps`): a flight seen
        at a yaw whose treads run out of the image's bottom edge at a slant.
    tread_pieces : bool
        Treads lying as coplanar pieces of one tread side by side
        (:func:`planerel.features.tread_pieces.tread_unions`) also take part as their
        union: a counted pair of the union names each piece (they join the flight), a step
        of ``chain=False`` its largest piece only (one step, as a whole face's).  A tread in
        two pieces, each half the flight's width, fails the overlap and area tests against
        the whole tread below it.
    two_risers : bool
        With ``chain``, two risers alone make a step that counts when both are flight-like
        and the lower one stands on a horizontal plane (:func:`_two_riser_steps`).
    chain : bool
        False: return every step found, before the chain test (a list of ``(lower, higher,
        rise per step, unit horizontal direction (3,), span, run per step)``;
        :func:`flight_step`).
    drop_cut : bool
        False: treads the image border cuts along their length take part like any other
        (:func:`flight_fragments`; no ``cut_top`` steps then).

    Returns
    -------
    set of (int, int)
        ``(lower, higher)`` label pairs of the steps that count.
    """
    want = set(labels)
    up = np.asarray(planes.up, float)
    cos_tol = math.cos(math.radians(angle_tol))
    kind = {p.label: _step_kind(p, tilt) for p in planes}
    # the border cut is asked of the candidate treads only (the same candidates)
    cut = _cut_lengthwise([p for p in planes if (not want or p.label in want)
                           and kind[p.label] == "tread"], cut_long_side,
                          getattr(planes, "labels", None)) if drop_cut else set()
    cands = [p for p in planes if (not want or p.label in want) and kind[p.label]
             and not (kind[p.label] == "tread" and p.label in cut)]
    unions: dict = {}
    if tread_pieces:
        unions = tread_unions([p for p in cands if kind[p.label] == "tread"], up, cos_tol,
                              max((p.label for p in planes), default=0) + 1)
        for k, (u, _) in unions.items():
            cands.append(u)
            kind[k] = "tread"
    steps = []  # (lower, higher, rise per step, unit horizontal direction)
    spans = (1, 2) if skip else (1,)
    axes_of: dict = {}

    def tread_axis(q):
        if q.label not in axes_of:
            axes_of[q.label] = _tread_depth_axis(q, up)
        return axes_of[q.label]

    for i, pa in enumerate(cands):
        na = np.asarray(pa.normal, float)
        for pb in cands[i + 1:]:
            if kind[pb.label] != kind[pa.label]:
                continue
            # the tests on Python floats first (each test only rejects: their order does not
            # change which pairs pass), the normals' product only for a pair that passes them
            if max(pa.area, pb.area) > max_ratio * min(pa.area, pb.area):
                continue
            lo, hi = (pa, pb) if pa.height <= pb.height else (pb, pa)
            dv = hi.height - lo.height
            if not _some_rise(dv, rise, spans):
                continue  # no span's rise: the step test below fails whatever the run
            if abs(float(na @ np.asarray(pb.normal, float))) < cos_tol:
                continue
            dist, direction = step_offset(lo, hi, kind[lo.label], up,
                                          tread_axis if tread_axes else None)
            k = next((k for k in spans if rise[0] <= dv / k <= rise[1]
                      and run[0] <= dist / k <= run[1]), None)
            if k is None:
                continue
            # each face is one step deep (treads) or high (risers): not a floor or a landing
            depth_axis = direction if kind[lo.label] == "tread" else up
            limit = run[1] if kind[lo.label] == "tread" else rise[1]
            if not _step_faces(lo, hi, up, direction, depth_axis, limit, min_overlap):
                continue
            steps.append((lo.label, hi.label, dv / k, direction, k, dist / k))
    cos_dir = math.cos(math.radians(25.0))
    if skip_missing and any(s[4] == 2 for s in steps):
        hgt = {p.label: p.height for p in cands}
        one = [s for s in steps if s[4] == 1]
        ones = {(s[0], s[1]) for s in one}

        def spans_seen(s2) -> bool:
            lo_l, hi_l, r, dirn = s2[:4]
            for s1 in one:
                if float(s1[3] @ dirn) < cos_dir:
                    continue
                for end, other, mid in ((hi_l, lo_l, s1[0]), (lo_l, hi_l, s1[1])):
                    if (s1[1] if end == hi_l else s1[0]) != end or mid in (lo_l, hi_l):
                        continue
                    if abs(hgt[mid] - (hgt[lo_l] + r)) > 0.3 * r:
                        continue  # not the face between them
                    if ((other, mid) if end == hi_l else (mid, other)) in ones:
                        continue
                    # the face between is seen: the other end lies one rise beyond it
                    step = s1[2]
                    want = hgt[mid] - step if end == hi_l else hgt[mid] + step
                    if abs(hgt[other] - want) > SKIP_GRID * step:
                        return True
            return False

        steps = [s2 for s2 in steps if s2[4] != 2 or not spans_seen(s2)]
    extra = []
    if cut_top and cut:
        tops = [p for p in planes if p.label in cut and (not want or p.label in want)]
        lows = [p for p in cands if kind[p.label] == "tread"]
        extra = _cut_top_steps(lows, tops, up, rise, run, min_overlap, max_ratio, cos_tol,
                               tread_axis)
    if not chain:
        # each union's largest piece only: one step, not one a piece (the stair_step/2 facts)
        return _spread_steps(steps + extra, unions, largest=True) if unions else steps + extra
    out = set()
    for s1 in steps:
        for s2 in steps:
            if s1 is s2 or not (s1[1] == s2[0] or s1[0] == s2[1]):
                continue
            if float(s1[3] @ s2[3]) >= cos_dir and 0.7 <= s1[2] / s2[2] <= 1 / 0.7:
                out.add((s1[0], s1[1]))
                break
    # two treads alone (a short flight seen from above: the landing, two treads, the floor):
    # the third face may be any horizontal plane one more rise up or down that comes within a
    # run of them (the landing or floor, support or cut by the border; it does not join the
    # proposal), when both treads are flight-like: wide and shallow
    byl = {p.label: p for p in planes}
    byl.update((k, u) for k, (u, _) in unions.items())
    anchors = [p for p in planes if kind[p.label] == "tread"]
    members: set = set()
    n_steps = len(steps)
    for i, (lo_l, hi_l, dv, direction, k, _run) in enumerate(steps + extra):
        lo, hi = byl[lo_l], byl[hi_l]
        if i == n_steps:
            # a cut top tread only where the lower one is in no counted step: with a row of
            # treads found, the strip the border cuts above its top may be the landing the
            # camera stands on as well as the top tread (dev_st i0001, dev_sr i0020), and
            # its seen part tells them apart by nothing
            members = {x for pr in out for x in pr}
        if i >= n_steps and lo_l in members:
            continue
        if (lo_l, hi_l) in out or k != 1 or kind[lo_l] != "tread":
            continue
        across = cross3(up, direction)
        if any(np.ptp(np.asarray(q.hull3d, float) @ across) < max(min_width, 1.5 * np.ptp(
                np.asarray(q.hull3d, float) @ direction)) for q in (lo, hi)):
            continue
        for a in anchors:
            if a.label in (lo_l, hi_l):
                continue
            face, sign = (hi, 1.0) if a.height > hi.height else (lo, -1.0)
            gap = abs(a.height - face.height)
            if not 0.7 <= gap / dv <= 1 / 0.7 or abs(float(np.asarray(a.normal) @ up)) < cos_tol:
                continue
            off = _anchor_offset(face, a, up)
            dist = float(np.linalg.norm(off))
            if dist > run[1] or (dist >= 0.5 * run[0] and float(off @ direction) * sign < cos_dir * dist):
                continue
            out.add((lo_l, hi_l))
            break
    if two_risers:
        out |= _two_riser_steps(steps, out, byl, planes, kind, up, run, min_width)
    if cut_chain and cut and out:
        lab = getattr(planes, "labels", None)
        # treads cut at a slant only: the landing the camera stands on is cut all along
        slanted = [p for p in planes if p.label in cut and (not want or p.label in want)
                   and _border_share(lab, p) < CUT_CHAIN_BORDER]
        out |= _cut_chain_steps(steps + extra, out, slanted, byl, up, run, min_overlap,
                                max_ratio, cos_tol, tread_axis if tread_axes else None)
    if unions:
        return {pr[:2] for pr in _spread_steps([(lo, hi) for lo, hi in out], unions)}
    return out


#: A two-riser step's ground: a horizontal plane level with the lower riser's foot within this
#: share of the step's rise (:func:`_two_riser_steps`)
TWO_RISER_FOOT = 0.3


def _two_riser_steps(steps, counted, by_label, planes, kind, up, run, min_width: float) -> set:
    """Steps of two risers alone that count: a flight seen level from a low camera.

    A camera 0.3-0.5 m over the floor (a tracked rescue robot, a low service robot) sees an
    ascending flight's risers and its treads edge on: no tread is a plane, and the row of
    three risers that a step needs to count may be two (a two-step flight; the upper risers
    partly hidden behind the treads' noses, too unlike in size to pair).  A step of two
    risers (``steps``' entries ``(lower, higher, rise, direction (3,), span, run)``, one span)
    that is not counted yet counts when

    - both risers are flight-like: their extent across the flight at least ``min_width`` and
      1.5 times their height (a box's face or a cabinet's door is narrower than tall);
    - no horizontal plane lies level with the lower riser's top edge within ``run[1]`` of it:
      the tread between them is not seen (two boxes of two heights seen from above show the
      lower one's top, and stay two proposals, as the issue asks of touching boxes);
    - the lower riser stands on a horizontal plane (the floor, a landing): a plane within
      ``tilt`` of level whose level lies within :data:`TWO_RISER_FOOT` of a rise of the
      riser's lowest hull point, and whose hull comes within ``run[1]`` of the riser's
      centroid horizontally, on the side the flight rises from (a box on a table before a
      wall's skirting has no ground under its face at that level).

    Two boxes, the farther one a step taller, standing a run apart on the floor and seen so
    low that the nearer one's top is no plane, are such a step too: that is the geometry of a
    two-step flight seen so.

    Returns
    -------
    set of (int, int)
        ``(lower, higher)`` label pairs.
    """
    cos_dir = math.cos(math.radians(25.0))
    out: set = set()
    grounds = [p for p in planes if kind.get(p.label) == "tread"
               or getattr(p, "orientation", None) == "horizontal"]
    if not grounds:
        return out
    for lo_l, hi_l, dv, direction, k, _run in steps:
        if k != 1 or (lo_l, hi_l) in counted or kind.get(lo_l) != "riser":
            continue
        lo, hi = by_label[lo_l], by_label[hi_l]
        across = cross3(up, direction)
        if any(np.ptp(np.asarray(q.hull3d, float) @ across) < max(
                min_width, 1.5 * np.ptp(np.asarray(q.hull3d, float) @ up)) for q in (lo, hi)):
            continue
        levels = np.asarray(lo.hull3d, float) @ up
        foot, top = float(levels.min()), float(levels.max())
        if any(abs(float(np.asarray(g.centroid, float) @ up) - top) <= TWO_RISER_FOOT * dv
               and float(np.linalg.norm(_anchor_offset(lo, g, up))) <= run[1]
               for g in grounds if g.label not in (lo_l, hi_l)):
            continue  # the tread between them is seen: a row of three decides, as before
        for g in grounds:
            if g.label in (lo_l, hi_l):
                continue
            if abs(float(np.asarray(g.centroid, float) @ up) - foot) > TWO_RISER_FOOT * dv:
                continue
            off = _anchor_offset(lo, g, up)
            dist = float(np.linalg.norm(off))
            # within a run, and before the riser (against the flight's direction)
            if dist > run[1] or (dist >= 0.5 * run[0] and -float(off @ direction) < cos_dir * dist):
                continue
            out.add((lo_l, hi_l))
            break
    return out


def _spread_steps(steps, unions, largest: bool = False) -> list:
    """``steps`` (tuples beginning ``(lower, higher)``) with each union of tread pieces
    (``unions``, :func:`~planerel.features.tread_pieces.tread_unions`) replaced by its pieces:
    one tuple a piece (two unions: a tuple a pair of pieces), the rest of the tuple kept; with
    ``largest``, by its largest piece only (a step named once, as a whole face's would be)."""
    out = []
    keep = slice(0, 1) if largest else slice(None)
    for s in steps:
        los = unions[s[0]][1][keep] if s[0] in unions else (s[0],)
        his = unions[s[1]][1][keep] if s[1] in unions else (s[1],)
        out.extend((lo, hi) + tuple(s[2:]) for lo in los for hi in his)
    return out


#: A cut tread's step repeats its row's: rise within this share of the row's rise per step,
#: run within :data:`CUT_CHAIN_RUN` of its run (:func:`_cut_chain_steps`)
CUT_CHAIN_RISE = 0.15
CUT_CHAIN_RUN = 0.2
#: ... and the border holds under this share of the long side of the cut tread's pixel box: a
#: tread cut at a slant shows an end or part of its near edge (0.55 in dev_st's flights seen
#: at a yaw), the landing the camera stands on runs out of the image all along (0.94-0.97)
CUT_CHAIN_BORDER = 0.75


def _cut_chain_steps(steps, counted, cut, by_label, up, run, min_overlap: float,
                     max_ratio: float, cos_tol: float, tread_axis) -> set:
    """Steps from a counted row's end tread to a tread the image border cuts along its length
    (``cut``), one step further along the row.

    The border cuts a tread "along its length" when its pixels on the border's rows (or
    columns) reach half its pixel box's long side; a flight seen at a yaw has its treads
    running out of the image's bottom edge at a slant, so whole treads of it are cut so.  Such
    a tread still extends a row of steps already counted (``counted``, ``(lower, higher)``
    pairs of ``steps``' entries ``(lower, higher, rise, direction (3,), span, run)``) when the
    step between it and the row's end tread passes the tests a step of two whole treads passes
    (normals within ``cos_tol``, areas within ``max_ratio``, each at most ``run[1]`` deep,
    extents across overlapping by ``min_overlap``) and repeats the row: its rise within
    :data:`CUT_CHAIN_RISE` of the row's step's rise, its run within :data:`CUT_CHAIN_RUN` of
    that step's run, its direction within 25 degrees.  The caller passes only treads cut at
    a slant (:data:`CUT_CHAIN_BORDER`): the landing the camera stands on is a step's rise
    and, by chance, a run away too, but the border cuts it all along.  Repeated while a tread
    joins (a row runs on through several cut treads).

    Returns
    -------
    set of (int, int)
        ``(lower, higher)`` label pairs.
    """
    cos_dir = math.cos(math.radians(25.0))
    rows = [s for s in steps if (s[0], s[1]) in counted and s[4] == 1]
    members = {x for pr in counted for x in pr}
    left = [c for c in cut if c.label not in members]

    def extends(c, row):
        """The step ``(lower, higher)`` from ``row``'s lower or higher end to the cut tread
        ``c`` that repeats the row and passes the step tests, or None."""
        lo_l, hi_l, dv, direction, _k, dist = row
        for end, sign in ((by_label[hi_l], 1.0), (by_label[lo_l], -1.0)):
            if abs(sign * (c.height - end.height) - dv) > CUT_CHAIN_RISE * dv \
                    or max(c.area, end.area) > max_ratio * min(c.area, end.area) \
                    or abs(float(np.asarray(c.normal, float) @ np.asarray(end.normal, float))) \
                    < cos_tol:
                continue
            lo, hi = (end, c) if sign > 0 else (c, end)
            d2, dir2 = step_offset(lo, hi, "tread", up, tread_axis)
            if (run[0] <= d2 <= run[1] and abs(d2 - dist) <= CUT_CHAIN_RUN * dist
                    and float(dir2 @ direction) >= cos_dir
                    and _step_faces(lo, hi, up, dir2, dir2, run[1], min_overlap)):
                return lo, hi
        return None

    out: set = set()
    grown = True
    while grown and left:
        grown = False
        for c in list(left):
            for row in rows:
                step = extends(c, row)
                if step is not None:
                    lo, hi = step
                    out.add((lo.label, hi.label))
                    rows.append((lo.label, hi.label, row[2], row[3], 1, row[5]))
                    left.remove(c)
                    grown = True
                    break
    return out


def _step_faces(lo, hi, up, direction, depth_axis, limit: float, min_overlap: float) -> bool:
    """The last tests of a step between the faces ``lo`` and ``hi``: each at most ``limit``
    deep along ``depth_axis`` (one step deep or high: not a floor or a landing), and their
    extents across ``direction`` overlapping by at least ``min_overlap`` (interval IoU)."""
    if any(np.ptp(np.asarray(q.hull3d, float) @ depth_axis) > limit for q in (lo, hi)):
        return False
    return _across_overlap(lo, hi, up, direction) >= min_overlap


#: Metres: how far the plan gap between a cut top tread's far edge and the lower tread's near
#: edge may lie off the band the top tread's nosing hides (:func:`_cut_top_steps`)
CUT_TOP_SLACK = 0.05


def _cut_top_steps(lows, tops, up, rise, run, min_overlap: float, max_ratio: float,
                   cos_tol: float, tread_axis) -> list:
    """One-rise steps from a tread the image border cuts along its length (``tops``: the top
    tread of a flight going down from the camera's landing, its near part out of the image) to
    a whole tread (``lows``) one rise lower and one run *farther from the camera*, its riser
    hidden: the top tread's far edge (the nosing) occludes the lower tread's back.

    A pair counts when both treads are long (1.5 times longer than deep) with step directions
    within 25 degrees (the run is measured across them, between their centroids, within
    ``run``: the cut tread's centroid lies nearer its nosing), their extents across the flight
    overlap by ``min_overlap`` (interval IoU), each is at most ``run[1]`` deep as seen, the cut
    tread's seen area is at most ``max_ratio`` times the whole one's (a landing's seen piece is
    larger; no lower bound: the border leaves a strip of the top tread), and the plan gap from
    the top tread's far edge to the lower tread's near edge lies within ``CUT_TOP_SLACK`` of
    the band the nosing hides from the camera (rise times the nosing's distance from the camera
    along the flight over its depth under the camera; the camera at the origin): the two are
    seen edge to edge, no
    floor between them.  The caller asks of these pairs what it asks of two treads alone (wide,
    shallow, a third level one more rise up or down).

    Returns
    -------
    list of tuple
        ``(lower, higher, rise, unit horizontal direction (3,), 1, run)`` as
        :func:`step_chain_pairs` lists its steps (``chain=False``).
    """
    out = []
    cos_dir = math.cos(math.radians(25.0))
    for hi in tops:
        nh = np.asarray(hi.normal, float)
        ch = np.asarray(hi.centroid, float)
        for lo in lows:
            dv = hi.height - lo.height
            if not rise[0] <= dv <= rise[1] or hi.area > max_ratio * lo.area:
                continue
            if abs(float(nh @ np.asarray(lo.normal, float))) < cos_tol:
                continue
            (da, ea), (db, eb) = tread_axis(lo), tread_axis(hi)
            if min(ea, eb) < 1.5 or abs(float(da @ db)) < cos_dir:
                continue
            cl = np.asarray(lo.centroid, float)
            d = ch - cl
            dh = d - (d @ up) * up
            along = float(dh @ da)
            direction = da if along >= 0 else -da  # from the lower tread to the top one
            dist = abs(along)
            if not run[0] <= dist <= run[1]:
                continue
            # the camera (at the origin) stands on the top tread's side: the flight goes down
            # away from it, the lower tread beyond the top one
            if float(ch @ direction) >= 0.0:
                continue
            if any(np.ptp(np.asarray(q.hull3d, float) @ direction) > run[1] for q in (lo, hi)):
                continue
            if _across_overlap(lo, hi, up, direction) < min_overlap:
                continue
            # edge to edge: the plan gap is the band the top tread's nosing hides
            H = np.asarray(hi.hull3d, float)
            t = H @ direction
            nose = H[int(np.argmin(t))]
            below = -float(nose @ up)  # the nosing's depth under the camera
            if below <= 0:
                continue  # the camera is not above the top tread: not seen from the landing
            # the sight line over the nosing drops one rise over this much of the flight
            band = dv * -float(nose @ direction) / below
            gap = float(t.min()) - float((np.asarray(lo.hull3d, float) @ direction).max())
            if abs(gap - band) > CUT_TOP_SLACK:
                continue
            out.append((lo.label, hi.label, dv, direction, 1, dist))
    return out


def _across_overlap(lo, hi, up, direction) -> float:
    """Interval IoU of planes ``lo`` and ``hi`` across the horizontal ``direction`` (their
    hulls' extents along ``up x direction``: one flight's width); -1 when the union is empty."""
    across = cross3(up, direction)
    a0, a1 = _extent(lo, across)
    b0, b1 = _extent(hi, across)
    union = max(a1, b1) - min(a0, b0)
    return (min(a1, b1) - max(a0, b0)) / union if union > 0 else -1.0


def _step_like(pa, pb, min_overlap: float, up=None, riser_max: float | None = None,
               riser_min: float = 0.0) -> bool:
    """A horizontal or inclined plane and a vertical one meeting as tread and riser (or a
    slope and the face at its end): their extents along the shared edge line overlap by at
    least ``min_overlap`` (IoU of the two intervals), and (with ``up`` and ``riser_max``) the
    vertical one is at most ``riser_max`` high or 1.5 times the other's height range: a wall
    seen behind a far tread is no riser, a ramp's end face is as high as its slope.  With
    ``up`` and ``riser_min`` > 0, a vertical plane over a horizontal one lower than
    ``riser_min`` is no riser (a box's face rising a few centimetres over a lower box)."""
    ors = sorted((pa.orientation, pb.orientation))
    if ors not in (["horizontal", "vertical"], ["inclined", "vertical"]):
        return False
    if up is not None and (riser_max is not None or riser_min > 0):
        vert, other = (pa, pb) if pa.orientation == "vertical" else (pb, pa)
        u = np.asarray(up, float)
        high = float(np.ptp(np.asarray(vert.hull3d, float) @ u))  # the riser's height
        if riser_min > 0 and other.orientation == "horizontal" and high < riser_min:
            return False
        if riser_max is not None and high > max(
                riser_max, 1.5 * float(np.ptp(np.asarray(other.hull3d, float) @ u))):
            return False
    return edge_overlap(pa, pb) >= min_overlap
