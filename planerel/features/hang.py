"""An upright face that hangs: its lower edge stands on nothing (false57).

A box rests on what carries it: the floor, a table, a shelf or the box under it.  Its upright
faces end at that support, so what the camera sees just beneath a face's lower edge is the
support's surface at the edge's level (farther or nearer), or something nearer that hides the
edge.  Furniture and fixtures of a box's shape often hang instead: a sofa's seat front over
the gap between its legs, a desk's apron over the knee space, a panel radiator on its
brackets, a monitor on its stand.  Beneath such a face's lower edge the camera looks past it,
down into the space under it: the points there are farther along the ray *and* lower than the
edge (the floor under the sofa, the wall under the radiator).

:func:`face_hang` measures one upright plane: for each image line across the face along the
image's "down" (gravity's ``-up`` as the image shows it at its centre), the face's lowest
pixel on that line when it lies on the face's lower edge (within 5 cm of its level: a thin
face seen slanted has lines whose lowest pixel is high on the face), and the first few valid
pixels of other planes (or none) 3-25 pixels further down.  A line is

* ``near`` when they are nearer than the edge (something in front hides the edge or carries
  the face there),
* ``level`` when they lie at the edge's height (a support seen beyond or before it),
* ``hang`` when they are farther by more than ``drop`` and lower by more than ``level``,
* unseen when no valid pixel lies there (the image's border, a shadow).

:func:`supported` asks whether a horizontal plane of the scan lies at the face's lower edge
(within ``level``) and reaches within ``reach`` of it across the floor: a box standing back
on a box below it, or overhanging it, hangs by the first test and stands by this one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["FaceHang", "face_hang", "supported"]


@dataclass(frozen=True)
class FaceHang:
    """What lies beneath one upright plane's lower edge."""

    #: the plane's label
    face: int
    #: image lines across the face with a sample beneath its edge
    seen: int
    #: lines with none (the image's border, invalid depth)
    unseen: int
    #: lines whose sample is farther and lower than the edge
    hang: int
    #: lines whose sample is nearer than the edge
    near: int
    #: lines whose sample lies at the edge's height
    level: int
    #: the lower edge's height over the floor (metres: the median over the lines of each
    #: line's lowest pixel)
    bottom: float

    @property
    def share(self) -> float:
        """The hanging lines' share of the lines with a sample (0 when none)."""
        return self.hang / self.seen if self.seen else 0.0


def _down_step(up):
    """The image step ``(dcol, drow)`` of gravity's down at the image's centre, or None when
    the camera looks nearly along gravity (no image direction is down)."""
    d = -np.asarray(up, dtype=np.float64)[:2]
    n = float(np.linalg.norm(d))
    return None if n < 0.3 else d / n


def _valid(xyz, rows, cols):
    """The points of pixels ``rows, cols`` of ``xyz`` as float64 ``(n, 3)``, their ranges
    ``(n,)`` and whether each is a measured point (finite, not at the origin)."""
    p = xyz[rows, cols].astype(np.float64)
    ok = np.isfinite(p).all(-1)
    rng = np.linalg.norm(np.where(ok[:, None], p, 0.0), axis=-1)
    return p, rng, ok & (rng > 0)


def face_hang(face: int, up, floor_level: float, xyz, labels, drop: float = 0.12,
              level: float = 0.04, near: float = 0.03, first: int = 3, last: int = 25,
              samples: int = 6, edge: float = 0.05):
    """Measure upright plane ``face`` of an organized scan (``xyz`` shape (H, W, 3),
    ``labels`` shape (H, W)): a :class:`FaceHang`, or None when no image direction is down
    or the face has no valid pixel.  Only the lines whose lowest pixel lies within ``edge``
    (metres) of the face's lower edge (the 10th percentile of the lines' lowest pixels'
    heights) are judged."""
    step = _down_step(up)
    if step is None:
        return None
    up = np.asarray(up, dtype=np.float64)
    lab = np.asarray(labels)
    xyz = np.asarray(xyz)
    h, w = lab.shape
    # only the face's pixels and the samples beneath it are read (no pass over the image)
    rows, cols = np.nonzero(lab == face)
    fpts, frng, ok = _valid(xyz, rows, cols)
    rows, cols, fpts, frng = rows[ok], cols[ok], fpts[ok], frng[ok]
    if rows.size == 0:
        return None
    hgt = fpts @ up - floor_level
    perp = np.array([-step[1], step[0]])
    line = np.round(cols * perp[0] + rows * perp[1]).astype(np.int64)
    order = np.lexsort((hgt, line))           # by line, lowest first
    first_of = np.ones(order.size, dtype=bool)
    first_of[1:] = line[order][1:] != line[order][:-1]
    seen = unseen = n_hang = n_near = n_level = 0
    offs = np.arange(first, last + 1, dtype=np.float64)
    low = order[first_of]
    # the lower edge: the lines whose lowest pixel lies within ``edge`` of the face's lowest
    # level (a box's lower edge is level; a thin face seen slanted, or one whose foot a nearer
    # thing hides, has lines whose lowest pixel is no point of that edge)
    ref = float(np.percentile(hgt[low], 10))
    low = low[hgt[low] <= ref + edge]
    bottom = float(np.median(hgt[low]))
    for i in low:
        r0, c0, hb = int(rows[i]), int(cols[i]), float(hgt[i])
        rb = float(frng[i])
        rr = np.round(r0 + offs * step[1]).astype(np.int64)
        cc = np.round(c0 + offs * step[0]).astype(np.int64)
        inside = (rr >= 0) & (rr < h) & (cc >= 0) & (cc < w)
        rr, cc = rr[inside], cc[inside]
        spts, srng, ok = _valid(xyz, rr, cc)
        ok &= lab[rr, cc] != face
        spts, srng = spts[ok][:samples], srng[ok][:samples]
        if srng.size == 0:
            unseen += 1
            continue
        seen += 1
        dr = float(np.median(srng)) - rb
        dh = float(np.median(spts @ up - floor_level)) - hb
        if dr < -near:
            n_near += 1
        elif abs(dh) <= level:
            n_level += 1
        elif dr > drop and dh < -level:
            n_hang += 1
    return FaceHang(int(face), seen, unseen, n_hang, n_near, n_level, bottom)


def supported(planes, hang: FaceHang, xyz, labels, level: float = 0.04,
              reach: float = 0.3) -> bool:
    """Whether a horizontal plane of ``planes`` (a :class:`~planerel.features.planes.PlaneSet`)
    other than the face lies at ``hang``'s lower edge (its points' median height within
    ``level``) with a point within ``reach`` of the edge's points across the floor."""
    up = np.asarray(planes.up, dtype=np.float64)
    fl = float(planes.floor_level)
    lab = np.asarray(labels)
    pts = np.asarray(xyz, dtype=np.float64)
    fm = lab == hang.face
    fp = pts[fm]
    fp = fp[np.isfinite(fp).all(-1)]
    if fp.size == 0:
        return False
    fh = fp @ up - fl
    edge = fp[fh <= hang.bottom + level]
    if edge.size == 0:
        return False
    edge = edge - np.outer(edge @ up, up)
    for p in planes.planes:
        if p.label == hang.face or p.orientation != "horizontal":
            continue
        q = pts[lab == p.label]
        q = q[np.isfinite(q).all(-1)]
        if q.shape[0] < 10:
            continue
        qh = q @ up - fl
        if abs(float(np.median(qh)) - hang.bottom) > level:
            continue
        q = q - np.outer(q @ up, up)
        if q.shape[0] > 2000:
            q = q[:: q.shape[0] // 2000 + 1]
        e = edge if edge.shape[0] <= 500 else edge[:: edge.shape[0] // 500 + 1]
        d2 = ((e[:, None, :] - q[None, :, :]) ** 2).sum(-1)
        if float(d2.min()) <= reach * reach:
            return True
    return False
