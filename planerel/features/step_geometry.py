"""Geometry of step faces shared by the proposal steps: a horizontal basis, a tread's depth
axis, and whether the image border cuts a plane along its length.

Used by :mod:`planerel.features.relations` (the step chains, :func:`~planerel.features.step_chains.step_chain_pairs`)
and :mod:`planerel.features.open_treads` (an open-riser flight's treads); moved here from
``relations`` (riser26) so that ``open_treads`` needs no import of ``relations``, which imports
it.  ``relations`` imports these names, so ``relations._tread_depth_axis`` etc. still work.
"""

from __future__ import annotations

import numpy as np

from planerel.features.vectors import cross3, vec_norm

__all__: list[str] = []


def _cut_lengthwise(planes, along_long_side: bool = True, labels=None) -> set:
    """Labels of planes the image border cuts along their length: as many of their pixels lie on
    the border as half the long side of their pixel box (the floor or landing the camera stands
    on, seen to the image's bottom edge), so how deep they are is not seen.  A tread cut at its
    ends by the left or right border keeps its depth.  With ``along_long_side`` only the
    border pixels on the image sides parallel to the box's long side count (the top and bottom
    rows for a box wider than high, else the left and right columns): a tread of a flight seen
    with the camera rolled, a strip the bottom edge cuts across its narrow side, is cut at its
    end and keeps its depth (seed 33 ``s0030``).  ``labels``: the label image when ``planes``
    is a list of planes (default: ``planes.labels``)."""
    lab = getattr(planes, "labels", None) if labels is None else labels
    if lab is None or lab.size == 0:
        return set()
    return {p.label for p in planes if _border_share(lab, p, along_long_side) >= 0.5}


def _border_share(lab, p, along_long_side: bool = True) -> float:
    """Pixels of the plane ``p`` on the image border over the long side of its pixel box
    (:func:`_cut_lengthwise`'s measure; with ``along_long_side`` only the border sides
    parallel to that long side count); 0 with no label image."""
    if lab is None or lab.size == 0:
        return 0.0
    r0, c0, r1, c1 = p.bbox
    sides = ("rows" if c1 - c0 >= r1 - r0 else "cols") if along_long_side else "all"
    return _border_pixels(lab, p.label, p.bbox, sides) / max(1, max(r1 - r0, c1 - c0))


def _border_pixels(lab, label: int, bbox, sides: str = "all") -> int:
    """Pixels of ``label`` on the image border, counted as ``np.concatenate([lab[0], lab[-1],
    lab[1:-1, 0], lab[1:-1, -1]])`` holds them (a one-row or one-column image counts its
    row or column twice), read only where the label's pixel box ``bbox`` meets the border
    (a plane's box holds all its pixels; a full column is a cache miss a pixel).
    ``sides="rows"``: on the top and bottom rows only; ``"cols"``: on the left and right
    columns only, corners included."""
    H, W = lab.shape
    r0, c0, r1, c1 = (int(v) for v in bbox)
    n = 0
    if sides == "cols":
        if c0 <= 0:
            n += int(np.count_nonzero(lab[max(r0, 0):r1, 0] == label))
        if c1 >= W:
            n += int(np.count_nonzero(lab[max(r0, 0):r1, W - 1] == label))
        return n
    if r0 <= 0:
        n += int(np.count_nonzero(lab[0, max(c0, 0):c1] == label))
    if r1 >= H:
        n += int(np.count_nonzero(lab[H - 1, max(c0, 0):c1] == label))
    if sides == "rows":
        return n
    lo, hi = max(r0, 1), min(r1, H - 1)
    if hi > lo:
        if c0 <= 0:
            n += int(np.count_nonzero(lab[lo:hi, 0] == label))
        if c1 >= W:
            n += int(np.count_nonzero(lab[lo:hi, W - 1] == label))
    return n


def _extent(p, axis) -> tuple[float, float]:
    """``(lowest, highest)`` of the plane ``p``'s hull vertices along ``axis`` (3,)."""
    t = np.asarray(p.hull3d, float) @ axis
    return float(t.min()), float(t.max())


#: The last ``up``'s horizontal basis, ``(up bytes, (e1, e2))`` (:func:`_horizontal_basis`:
#: a scene's steps ask for the same up two to six times).
_LAST_BASIS: list = [None]


def _horizontal_basis(up) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors ``(3,)`` spanning the horizontal plane (perpendicular to ``up``),
    read-only (remembered for the last ``up``).  The cross products in Python floats
    (:func:`~planerel.features.vectors.cross3`: the floats ``np.cross`` gives, without its
    15-40 us a call)."""
    up = np.asarray(up, float)
    key = up.tobytes()
    last = _LAST_BASIS[0]
    if last is not None and last[0] == key:
        return last[1]
    e1 = cross3(up, (1.0, 0.0, 0.0))
    if vec_norm(e1) < 0.1:
        e1 = cross3(up, (0.0, 1.0, 0.0))
    e1 /= vec_norm(e1)
    e2 = cross3(up, e1)
    for e in (e1, e2):
        e.setflags(write=False)
    _LAST_BASIS[0] = (key, (e1, e2))
    return e1, e2


def _tread_depth_axis(p, up) -> tuple[np.ndarray, float]:
    """A tread's step direction: the horizontal unit vector ``(3,)`` across its shortest
    extent (rotating calipers over the horizontal projection of ``hull3d``), and its
    elongation (extent along the edge / extent across it; 0 for a degenerate hull).

    (The arrays are filled in place rather than stacked and rolled: 45 against 100 us a
    call, the same products and differences, so the same floats.)"""
    H = np.asarray(p.hull3d, float)
    e1, e2 = _horizontal_basis(up)
    m = len(H)
    if m < 3:
        return e1, 0.0
    P = np.empty((m, 2))
    P[:, 0] = H @ e1
    P[:, 1] = H @ e2
    t = np.empty_like(P)  # each edge: the next vertex minus this one
    np.subtract(P[1:], P[:-1], out=t[:-1])
    np.subtract(P[0], P[-1], out=t[-1])
    length = np.hypot(t[:, 0], t[:, 1])
    keep = length > 1e-9
    if not keep.all():
        t, length = t[keep], length[keep]
        if not len(t):
            return e1, 0.0
    t /= length[:, None]
    n = np.empty_like(t)
    np.negative(t[:, 1], out=n[:, 0])
    n[:, 1] = t[:, 0]
    across = P @ n.T
    deep = across.max(0) - across.min(0)  # the extent across each edge direction
    k = int(np.argmin(deep))
    if deep[k] <= 0:
        return e1, 0.0
    a = P @ t[k]
    along = float(a.max() - a.min())
    return n[k, 0] * e1 + n[k, 1] * e2, along / float(deep[k])
