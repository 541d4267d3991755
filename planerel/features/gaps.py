"""What the image shows between two planes that do not touch in it.

Two parallel planes whose hulls come within a few centimetres but whose pixels neither touch
nor share an edge are either pieces of one surface with something in front of it between them
(a shelf's back panel seen above and below a board, a face behind a table leg) or two
surfaces with a gap between them (two boxes in a row: the floor seen between them, or a face
of one of them).  The pixels on the short image lines between the two planes tell which: an
occluder lies in front of both planes; a gap shows what is behind them or beside them.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["gap_behind", "gap_in_front", "occluded_piece_pairs", "plane_between"]


def gap_in_front(labels, xyz, a: int, b: int, margin: float = 0.05, lines: int = 5,
                 max_outline: int = 200, window=None, fast: bool = False) -> float | None:
    """Fraction of the valid pixels between planes ``a`` and ``b`` that lie in front of both.

    Parameters
    ----------
    labels, xyz : ndarray, shapes (H, W) int and (H, W, 3) float
        The plane label image and the organized points (NaN where invalid).
    a, b : int
        The two labels.
    margin : float
        Metres at 1 m (scaled by the range): a pixel is in front when its range is below the
        smaller of the two end pixels' ranges by more than ``margin * max(1, range)``.
    lines : int
        The image lines looked at: between the ``lines`` closest pairs of outline pixels (one
        of each plane; every second outline pixel kept until at most ``max_outline`` are).
    max_outline : int
        Outline pixels per plane compared at most.
    window : (row0, col0, row1, col1), optional
        Pixel box holding both planes (their ``bbox`` joined): only it is looked at.
    fast : bool
        Select the ``lines`` closest pairs with a partial sort, ties broken by the pairs' order
        (a full sort of up to ``max_outline``^2 distances took most of a call's 1-2 ms at
        640x480; the full sort's order among tied distances is its own, so the default keeps
        it for the rules measured with it).

    Returns
    -------
    float or None
        In front / valid pixels on those lines (end pixels and pixels of ``a`` or ``b`` not
        counted); None when there are none (the planes touch, or only invalid pixels lie
        between them: nothing is known).
    """
    n_valid = n_front = 0
    for r, near, _far in _between(labels, xyz, a, b, lines, max_outline, window, fast):
        n_valid += r.size
        n_front += int((r < near - margin * max(1.0, near)).sum())
    return n_front / n_valid if n_valid else None


def gap_behind(labels, xyz, a: int, b: int, margin: float = 0.05, lines: int = 5,
               max_outline: int = 200, window=None) -> float | None:
    """Fraction of the valid pixels between planes ``a`` and ``b`` that lie behind both: what is
    seen through a gap between them (the floor or a wall behind two boxes in a row), where an
    occluder or a thin part of the object between two pieces of one surface (a shelf's board
    seen nearly edge-on) lies at their depth or in front.

    Parameters as for :func:`gap_in_front`; a pixel is behind when its range exceeds the larger
    of the two end pixels' ranges by more than ``margin * max(1, range)``.

    Returns
    -------
    float or None
        Behind / valid pixels on those lines; None when there are none.
    """
    n_valid = n_behind = 0
    for r, _near, far in _between(labels, xyz, a, b, lines, max_outline, window):
        n_valid += r.size
        n_behind += int((r > far + margin * max(1.0, far)).sum())
    return n_behind / n_valid if n_valid else None


def plane_between(labels, xyz, a, b, normal, point, margin: float = 0.01, lines: int = 9,
                  max_outline: int = 100, window=None, skip_ends: bool = True) -> tuple[float, float] | None:
    """Where the pixels between planes ``a`` and ``b`` lie against one plane through both.

    The valid pixels on the image lines between the ``lines`` closest pairs of outline pixels
    of ``a`` and ``b`` (as :func:`gap_in_front`, closest pairs by the partial sort) are
    compared with the point where their ray meets the plane through ``point`` with normal
    ``normal``: a pixel is *in front* when its range is below that point's by more than
    ``margin * max(1, range)``, *behind* when above it by more.  Where one surface runs on
    behind something lying or standing on it (a bar across a box's top), every pixel between
    its two pieces is in front of the surface's plane (or not seen: its shadow); where the
    planes are two objects' faces at one height, the table or a lower face seen between them
    lies behind it.  Unlike :func:`gap_in_front`, whose reference is the nearer end pixel's
    range, this measures against the surface itself, so a thin occluder (2-3 cm over a top
    seen at 0.7 m) counts as in front.

    Returns
    -------
    (float, float) or None
        ``(in front, behind)`` as fractions of those valid pixels; None when there are none.
    """
    lab, pts, found = _line_pixels(labels, xyz, a, b, lines, max_outline, window, True)
    # the pixels next to either piece are left out: an occluder lying on the surface meets it
    # there (its base lies on the plane; on the real frames it is the sensor's shadow)
    edge = max(1, round(np.asarray(labels).shape[1] / 160)) if skip_ends else 0
    found = [f for f in found if f[4].size > 2 * edge]
    if not found:
        return None
    rr = np.concatenate([f[4][edge:f[4].size - edge] for f in found])
    cc = np.concatenate([f[5][edge:f[5].size - edge] for f in found])
    X = np.asarray(pts[rr, cc], float).reshape(-1, 3)
    X = X[np.isfinite(X).all(axis=1)]
    n = np.asarray(normal, float)
    rng = np.linalg.norm(X, axis=1)
    ok = rng > 0
    X, rng = X[ok], rng[ok]
    cosang = (X @ n) / rng
    ok = np.abs(cosang) > 1e-6
    if not ok.any():
        return None
    rng, cosang = rng[ok], cosang[ok]
    hit = float(n @ np.asarray(point, float)) / cosang  # range of the ray's point on the plane
    tol = margin * np.maximum(1.0, rng)
    return float((rng < hit - tol).mean()), float((rng > hit + tol).mean())


def _between(labels, xyz, a, b, lines, max_outline, window, fast: bool = False) -> list:
    """``(ranges, near, far)`` per image line between the ``lines`` closest pairs of outline
    pixels of ``a`` and ``b``: the finite ranges of the pixels on it (end pixels and pixels of
    ``a`` or ``b`` left out) and the smaller and larger range of its two end pixels (lines with
    a non-finite end or under two steps long left out).  ``fast``: the closest pairs by a
    partial sort, ties in the pairs' order (see :func:`gap_in_front`)."""
    lab, xyz, found = _line_pixels(labels, xyz, a, b, lines, max_outline, window, fast)

    def rng(r, c):
        return np.linalg.norm(np.asarray(xyz[r, c], float), axis=-1)

    out = []
    for r0, c0, r1, c1, rr, cc in found:
        ends = (_range_at(xyz, r0, c0), _range_at(xyz, r1, c1))
        near = min(ends)
        if not np.isfinite(near):
            continue
        r = rng(rr, cc)
        r = r[np.isfinite(r)]
        out.append((r, near, max(ends)))
    return out


def _line_pixels(labels, xyz, a, b, lines, max_outline, window, fast: bool = False):
    """``(lab, xyz, found)``: the label image and points cut to ``window`` and, per image line
    between the ``lines`` closest pairs of outline pixels of ``a`` and ``b`` (under two steps
    long left out), ``(r0, c0, r1, c1, rows, cols)``: its end pixels and the pixels on it that
    belong to neither plane, in the window's coordinates (see :func:`_between`)."""
    from planerel.features._relation_kernels import window_outlines
    from planerel.features.planes import _boundary

    lab = np.asarray(labels)
    xyz = np.asarray(xyz)
    H, W = lab.shape
    if window is not None:
        r0, c0, r1, c1 = (int(v) for v in window)
        rs, cs = slice(r0, r1).indices(H), slice(c0, c1).indices(W)
        lab, xyz = lab[r0:r1, c0:c1], xyz[r0:r1, c0:c1]
    else:
        rs, cs = (0, H, 1), (0, W, 1)
    if lab.dtype == np.int32 and lab.size:
        # the window's outline pixels of a and b in one compiled pass over the image's window
        # (the same pixels, in the same order, as the outline of the window's copy)
        full = np.asarray(labels)
        pa, pb = window_outlines(full if full.flags.c_contiguous else np.ascontiguousarray(full),
                                 rs[0], cs[0], max(rs[0], rs[1]), max(cs[0], cs[1]),
                                 int(a), int(b))
    else:
        edge = _boundary(lab)
        pa, pb = np.argwhere(edge & (lab == a)), np.argwhere(edge & (lab == b))
    if len(pa) == 0 or len(pb) == 0:
        return lab, xyz, []
    while len(pa) > max_outline:
        pa = pa[::2]
    while len(pb) > max_outline:
        pb = pb[::2]
    # squared pixel distances of every pair (integers: the same values whatever the order)
    dr = pa[:, 0][:, None] - pb[:, 0][None, :]
    dc = pa[:, 1][:, None] - pb[:, 1][None, :]
    d2 = dr * dr + dc * dc
    if fast and d2.size > lines:
        flat = d2.ravel()
        part = np.argpartition(flat, lines - 1)[:lines]
        order = part[np.lexsort((part, flat[part]))]
    else:
        order = np.argsort(d2, axis=None)[:lines]
    found = []
    for k in order:
        i, j = divmod(int(k), d2.shape[1])  # np.unravel_index's (row, column) of C order
        (r0, c0), (r1, c1) = pa[i], pb[j]
        steps = int(max(abs(r1 - r0), abs(c1 - c0)))
        if steps < 2:
            continue
        t = np.arange(1, steps) / steps
        rr = np.rint(r0 + t * (r1 - r0)).astype(int)
        cc = np.rint(c0 + t * (c1 - c0)).astype(int)
        keep = (lab[rr, cc] != a) & (lab[rr, cc] != b)
        found.append((r0, c0, r1, c1, rr[keep], cc[keep]))
    return lab, xyz, found


def _range_at(xyz, r, c) -> float:
    """``float(np.linalg.norm(np.asarray(xyz[r, c], float), axis=-1))`` of one pixel without
    numpy's calls: its arithmetic, ``sqrt((x x + y y) + z z)`` (``tests/test_relation_kernels.py``
    compares)."""
    x, y, z = (float(v) for v in xyz[r, c].tolist())
    return math.sqrt(x * x + y * y + z * z)


def _gap_pair(relations, a: int, b: int, min_gap: float, max_gap: float) -> bool:
    """True when the relation of ``a`` and ``b`` (either order, as a missing one: False) is
    not touching and its hulls' gap lies in ``(min_gap, max_gap]``: the relation tests of
    :func:`occluded_piece_pairs`."""
    a, b = (a, b) if a < b else (b, a)
    try:
        r = relations.get(a, b)
    except KeyError:
        return False
    return not r.touching and min_gap < r.gap <= max_gap


def occluded_piece_pairs(planes, relations, labels, xyz, skip=(), angle_tol: float = 10.0,
                         coplanar_depth: float = 0.03, min_gap: float = 0.05,
                         max_gap: float = 0.25, min_front: float = 0.5, together=None,
                         flat: bool = False, near: bool = False, flat_depth: float = 0.02,
                         max_behind: float = 0.02, min_covered: float = 0.95,
                         exclude=None) -> set:
    """Pieces of one surface seen on both sides of something in front of it.

    A shelf's back panel seen from above comes out in pieces between its boards: each board's
    front edge hides a band of the panel, so the pieces neither touch in the image nor come
    within the relations' ``adjacency_gap`` in 3-D.  Two vertical planes are joined as one
    surface when their normals are within ``angle_tol``, each lies within ``coplanar_depth *
    max(1, z)`` of the other's plane, their hulls lie more than ``min_gap`` and at most
    ``max_gap`` metres apart (closer pairs are the relations' adjacent ones) and at least
    ``min_front`` of the valid pixels on the image lines between them lie in front of both
    (:func:`gap_in_front`; no valid pixel: not joined).  Two coplanar faces of two objects
    with a gap between them show what is behind or beside them there (the floor, a wall),
    not an occluder.

    With ``flat`` the same holds for horizontal and inclined planes (a box's top seen on both
    sides of a bar lying across it, of a plate standing in front of it, of a box on it), and
    with ``near`` for pairs whose hulls come within ``min_gap`` too (the relations call them
    adjacent; those the proposals did not join: hulls 2-5 cm apart across a plate).  Such a
    pair (any pair but two vertical planes more than ``min_gap`` apart) must pass a stricter
    test, since the tops of two objects of one height with a third between them in the image
    are common on a crowded table: each within ``flat_depth * max(1, z)`` of the other's
    plane, neither ``exclude``-d, and on the lines between them (:func:`plane_between`, the
    pixels next to either piece left out) at most ``max_behind`` of the valid pixels behind
    the plane through both (the table or a lower face seen between two tops lies behind their
    plane) and either at least ``min_covered`` in front of it, or :func:`gap_in_front` at
    least ``min_front`` (what lies between clearly nearer than both pieces).

    Parameters
    ----------
    planes : PlaneSet or sequence of Plane
    relations : Relations
        The scene's pair relations (their ``gap``: the hulls' distance).
    labels, xyz : ndarray
        The plane label image and the organized points.
    skip : iterable of int
        Labels left out (the support planes).
    together : callable, optional
        ``together(a, b)`` True when the two are in one proposal already: not looked at.
    flat, near : bool
        Also non-vertical planes; also hulls within ``min_gap`` (not touching in the image).
    flat_depth, max_behind, min_covered : float
        The stricter test's coplanarity (metres at 1 m), largest fraction behind and the
        fraction in front that suffices alone.
    exclude : callable, optional
        ``exclude(label)`` True for a plane that is no piece under the stricter test (the
        proposals pass the support's skin pieces).

    Returns
    -------
    set of (int, int)
        The joined pairs ``(a, b)``, ``a < b``.
    """
    skip = set(skip)
    kinds = ("vertical", "horizontal", "inclined") if flat else ("vertical",)
    cand = [p for p in planes if p.label not in skip and p.orientation in kinds]
    out: set = set()
    if len(cand) < 2:
        return out
    low = -1.0 if near else min_gap
    # the relations' tests first (cheap) when only vertical planes far apart are looked at:
    # with no pair of candidates whose hulls lie in the gap range and that do not touch,
    # nothing is joined (the same answer as the tests below)
    if not (flat or near) and not any(_gap_pair(relations, pa.label, pb.label, low, max_gap)
                                      for k, pa in enumerate(cand) for pb in cand[k + 1:]):
        return out
    cos_tol = math.cos(math.radians(angle_tol))
    # (the same values as np.asarray(p.normal, float) row by row, in one conversion)
    nrm = np.array([p.normal for p in cand], float)
    cen = np.array([p.centroid for p in cand], float)
    # parallel, and each within coplanar_depth * max(1, z) of the other's plane (one matrix
    # product for all pairs; the pairs left are few)
    par = np.abs(nrm @ nrm.T) >= cos_tol
    off = np.abs(np.einsum("ik,ijk->ij", nrm, cen[None, :, :] - cen[:, None, :]))
    z = np.maximum(1.0, 0.5 * np.abs(cen[:, 2][:, None] + cen[:, 2][None, :]))
    off = np.maximum(off, off.T)
    ok = par & (off <= coplanar_depth * z)
    # the pairs above the diagonal, row by row (np.triu's order, without its masks)
    for i, j in zip(*(x.tolist() for x in np.nonzero(ok)), strict=True):
        if j <= i:
            continue
        pa, pb = cand[i], cand[j]
        a, b = sorted((pa.label, pb.label))
        try:
            r = relations.get(a, b)
        except KeyError:
            continue
        if r.touching or not low < r.gap <= max_gap:
            continue
        old = pa.orientation == "vertical" and pb.orientation == "vertical" and r.gap > min_gap
        if not old and off[i, j] > flat_depth * z[i, j]:
            continue
        if (together is not None and together(a, b)) or (
                not old and exclude is not None and (exclude(a) or exclude(b))):
            continue
        ba, bb = pa.bbox, pb.bbox
        box = (min(ba[0], bb[0]), min(ba[1], bb[1]), max(ba[2], bb[2]), max(ba[3], bb[3]))
        if old:
            f = gap_in_front(labels, xyz, a, b, max_outline=100, window=box, fast=True)
            if f is not None and f >= min_front:
                out.add((a, b))
            continue
        na, nb = nrm[i], nrm[j]
        n = na + nb if float(na @ nb) >= 0 else na - nb
        fb = plane_between(labels, xyz, a, b, n / np.linalg.norm(n), 0.5 * (cen[i] + cen[j]),
                           window=box)
        if fb is None or fb[1] > max_behind:
            continue
        if fb[0] >= min_covered:
            out.add((a, b))
            continue
        f = gap_in_front(labels, xyz, a, b, max_outline=100, window=box, fast=True)
        if f is not None and f >= min_front:
            out.add((a, b))
    return out
