"""numba kernels of :mod:`planerel.features.relations` (compiled at first call, cached on disk).

Import this module only from inside functions: numba itself is a heavy import.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from planerel.segment._intrinsics import prefetch

#: How many boundary pixels ahead the touch test and the edge sums ask for data (speed22y):
#: the label and point of that pixel and of the pixel ``band`` rows below it (the newest row
#: of its neighbourhood).  The boundary pixels are read in row order but far apart, and the
#: hardware's prefetcher does not follow them.  Only when data arrives changes (C-order
#: arrays assumed for the addresses; any other layout only wastes the hint).  Written out in
#: each loop: a jitted helper taking the arrays costs their reference counts at every pixel.
_AHEAD = 64


@njit(cache=True, nogil=True, error_model="numpy")
def edge_sums(lab, xyz, r0, c0, used, band, depth, n):
    """Sums of :func:`planerel.features.proposals.edge_means` in one pass.

    The flow calls :func:`edge_sums_pairs` (the same sums for the asked pairs, windows proved
    empty skipped); this plainer form of every pair is kept as the reference it is tested
    against (tests/test_proved_nothing.py, tests/test_relation_kernels.py).

    For each boundary pixel ``(r0[t], c0[t])`` of a used label ``a`` and each pixel ``k``
    = 1..``band`` steps away to the right, down and along both down diagonals whose label
    ``b`` is used and differs, the pair counts when the two points lie within
    ``depth * max(1, |z|)`` of the boundary pixel's depth ``z``; the pair code is
    ``min(a, b) * n + max(a, b)``.

    Returns
    -------
    (cnt (n*n,) float64, acc_lo (n*n, 3), acc_hi (n*n, 3))
        Pair counts and the summed points of the lower and of the higher label.
    """
    H, W = lab.shape
    cnt = np.zeros(n * n)
    acc_lo = np.zeros((n * n, 3))
    acc_hi = np.zeros((n * n, 3))
    for t in range(r0.shape[0]):
        y0 = r0[t]
        x0 = c0[t]
        a = lab[y0, x0]
        if a < 0 or a >= n or not used[a]:
            continue
        lim2 = -1.0  # the pixel's limit, read at its first candidate neighbour
        for k in range(1, band + 1):
            for d in range(4):
                if d == 0:
                    y, x = y0, x0 + k
                elif d == 1:
                    y, x = y0 + k, x0
                elif d == 2:
                    y, x = y0 + k, x0 + k
                else:
                    y, x = y0 + k, x0 - k
                if y < 0 or y >= H or x < 0 or x >= W:
                    continue
                b = lab[y, x]
                if b == a or b < 0 or b >= n or not used[b]:
                    continue
                if lim2 < 0:
                    lim = depth * max(1.0, abs(xyz[y0, x0, 2]))
                    lim2 = lim * lim
                dx = xyz[y0, x0, 0] - xyz[y, x, 0]
                dy = xyz[y0, x0, 1] - xyz[y, x, 1]
                dz = xyz[y0, x0, 2] - xyz[y, x, 2]
                if not dx * dx + dy * dy + dz * dz <= lim2:
                    continue
                if a < b:
                    code = a * n + b
                    for j in range(3):
                        acc_lo[code, j] += xyz[y0, x0, j]
                        acc_hi[code, j] += xyz[y, x, j]
                else:
                    code = b * n + a
                    for j in range(3):
                        acc_lo[code, j] += xyz[y, x, j]
                        acc_hi[code, j] += xyz[y0, x0, j]
                cnt[code] += 1.0
    return cnt, acc_lo, acc_hi


#: Tiles of ``2**TILE_SHIFT`` pixels a side: :func:`boundary_tiles`' grid.
TILE_SHIFT = 3


@njit(cache=True, inline="always", error_model="numpy")
def _label_bit(k):
    """The bit of label ``k >= 0`` in a tile's mask: bit ``k``, or bit 63 for every label from
    63 on (a bound shared by those labels: never a reason to skip one of them)."""
    return np.uint64(1) << np.uint64(k if k < 63 else 63)


@njit(cache=True, nogil=True, error_model="numpy")
def boundary_tiles(lab, brow, bcol):
    """``(ceil(H / T), ceil(W / T))`` uint64, ``T = 2**TILE_SHIFT``: per tile of the image the
    bits (:func:`_label_bit`) of the labels ``>= 0`` of the pixels ``(brow, bcol)`` in it.

    Given every boundary pixel of ``lab`` (a labelled pixel with a 4-neighbour of another
    label or on the image border, as :func:`planerel.features.planes._boundary_pixels` lists
    them), a tile mask bounds which labels can occur near a pixel: when a pixel ``q`` of label
    ``b`` lies in a box that also holds a pixel ``p`` of another label, a 4-connected path
    from ``q`` to ``p`` inside the box leaves ``b`` at a pixel of ``b`` with a 4-neighbour of
    another label, a boundary pixel of ``b`` in the box.  So a label whose bit is in none of
    the tiles a box meets has no pixel in that box (next to a pixel of another label)."""
    H, W = lab.shape
    out = np.zeros((((H - 1) >> TILE_SHIFT) + 1, ((W - 1) >> TILE_SHIFT) + 1), np.uint64)
    nb = brow.shape[0]
    for i in range(nb):
        if i + _AHEAD < nb:
            prefetch(lab, brow[i + _AHEAD] * W + bcol[i + _AHEAD])
        k = lab[brow[i], bcol[i]]
        if k >= 0:
            out[brow[i] >> TILE_SHIFT, bcol[i] >> TILE_SHIFT] |= _label_bit(k)
    return out


@njit(cache=True, inline="always", error_model="numpy")
def _box_bits(tiles, v0, v1, u0, u1):
    """The union of the tile masks over the pixel box ``[v0, v1] x [u0, u1]`` (inclusive)."""
    m = np.uint64(0)
    for tv in range(v0 >> TILE_SHIFT, (v1 >> TILE_SHIFT) + 1):
        for tu in range(u0 >> TILE_SHIFT, (u1 >> TILE_SHIFT) + 1):
            m |= tiles[tv, tu]
    return m


@njit(cache=True, nogil=True, error_model="numpy")
def touch_pairs_tiled(xyz, lab, brow, bcol, g, max_dist, rel_dist, known):
    """:func:`planerel.segment._label_kernels.touch_pairs` when ``(brow, bcol)`` are every
    boundary pixel of ``lab`` (row-major): the same pixels in the same order, the same answer,
    but a pixel's window (``g`` rows down, ``g`` columns either side) is read only when the
    tiles it meets (:func:`boundary_tiles`) hold a known label other than the pixel's own whose
    pair with it is not found yet: a window with none of those can change nothing (the pairs
    found are skipped in the window too).  About half the boundary pixels of the real frames
    border only unassigned pixels or labels already found touching."""
    return touch_pairs_with_tiles(xyz, lab, brow, bcol, boundary_tiles(lab, brow, bcol), g,
                                  max_dist, rel_dist, known)


@njit(cache=True, nogil=True, error_model="numpy")
def touch_pairs_with_tiles(xyz, lab, brow, bcol, tiles, g, max_dist, rel_dist, known):
    """:func:`touch_pairs_tiled` with the tiles given (``boundary_tiles(lab, brow, bcol)``,
    which :func:`edge_sums_pairs_with_tiles` reads too)."""
    H, W = lab.shape
    nlab = known.shape[0]
    out = np.zeros((nlab, nlab), np.bool_)
    kmask = np.uint64(0)
    for k in range(nlab):
        if known[k]:
            kmask |= _label_bit(k)
    # per label: the bits of the known labels not (yet) found touching it; its own bit off
    # (labels from 63 on share bit 63, which is never taken off)
    open_ = np.empty(nlab, np.uint64)
    for k in range(nlab):
        open_[k] = kmask & ~_label_bit(k) if k < 63 else kmask
    L = lab.ravel()
    X = xyz.ravel()
    nb = brow.shape[0]
    for i in range(nb):
        if i + _AHEAD < nb:
            pa = brow[i + _AHEAD] * W + bcol[i + _AHEAD]
            prefetch(L, pa)
            prefetch(X, 3 * pa)
            if brow[i + _AHEAD] + g < H:
                prefetch(L, pa + g * W)
                prefetch(X, 3 * (pa + g * W))
        v = brow[i]
        u = bcol[i]
        p = np.uint64(v * W + u)
        a = L[p]
        if a < 0 or a >= nlab or not known[a]:
            continue
        if _box_bits(tiles, v, min(v + g, H - 1), max(u - g, 0), min(u + g, W - 1)) \
                & open_[a] == 0:
            continue
        d2max = -1.0  # the pixel's limit, read at its first candidate neighbour
        for dv in range(0, g + 1):
            v2 = v + dv
            if v2 >= H:
                break
            ulo = max(u - g, 0) if dv > 0 else u + 1
            uhi = min(u + g, W - 1)
            row = v2 * W
            for u2 in range(ulo, uhi + 1):
                q = np.uint64(row + u2)
                b = L[q]
                if b == a or b < 0 or b >= nlab or not known[b]:
                    continue
                if out[a, b]:
                    continue
                if d2max < 0:
                    lim = max(max_dist, rel_dist * abs(X[3 * p + 2]))
                    d2max = lim * lim
                ex = X[3 * p] - X[3 * q]
                ey = X[3 * p + 1] - X[3 * q + 1]
                ez = X[3 * p + 2] - X[3 * q + 2]
                if ex * ex + ey * ey + ez * ez <= d2max:
                    out[a, b] = True
                    out[b, a] = True
                    if b < 63:
                        open_[a] &= ~_label_bit(b)
                    if a < 63:
                        open_[b] &= ~_label_bit(a)
    return out


@njit(cache=True, nogil=True, error_model="numpy")
def edge_sums_pairs(lab, xyz, r0, c0, partner, band, depth):
    """:func:`edge_sums` of the pairs ``partner`` ``(n, n)`` bool (symmetric) marks, when
    ``(r0, c0)`` are every boundary pixel of ``lab`` (row-major): the same sums, counts and
    order for those pairs (other pairs' entries stay 0).  A boundary pixel is read only when
    the tiles its band's box meets (:func:`boundary_tiles`: ``band`` rows down, ``band``
    columns either side) hold a partner of its label; the support planes, which
    :func:`planerel.features.proposals.propose_objects` leaves out of its pairs, border most
    objects' outlines."""
    return edge_sums_pairs_with_tiles(lab, xyz, r0, c0, boundary_tiles(lab, r0, c0), partner,
                                      band, depth)


@njit(cache=True, nogil=True, error_model="numpy")
def edge_sums_pairs_with_tiles(lab, xyz, r0, c0, tiles, partner, band, depth):
    """:func:`edge_sums_pairs` with the tiles given (``boundary_tiles(lab, r0, c0)``, which
    :func:`touch_pairs_with_tiles` reads too)."""
    H, W = lab.shape
    n = partner.shape[0]
    cnt = np.zeros(n * n)
    acc_lo = np.zeros((n * n, 3))
    acc_hi = np.zeros((n * n, 3))
    pmask = np.zeros(n, np.uint64)
    used = np.zeros(n, np.bool_)
    for a in range(n):
        for b in range(n):
            if partner[a, b]:
                pmask[a] |= _label_bit(b)
                used[a] = True
    nb = r0.shape[0]
    for t in range(nb):
        if t + _AHEAD < nb:
            pa = r0[t + _AHEAD] * W + c0[t + _AHEAD]
            prefetch(lab, pa)
            prefetch(xyz, 3 * pa)
            if r0[t + _AHEAD] + band < H:
                prefetch(lab, pa + band * W)
                prefetch(xyz, 3 * (pa + band * W))
        y0 = r0[t]
        x0 = c0[t]
        a = lab[y0, x0]
        if a < 0 or a >= n or not used[a]:
            continue
        if _box_bits(tiles, y0, min(y0 + band, H - 1), max(x0 - band, 0),
                     min(x0 + band, W - 1)) & pmask[a] == 0:
            continue
        lim2 = -1.0  # the pixel's limit, read at its first candidate neighbour
        for k in range(1, band + 1):
            for d in range(4):
                if d == 0:
                    y, x = y0, x0 + k
                elif d == 1:
                    y, x = y0 + k, x0
                elif d == 2:
                    y, x = y0 + k, x0 + k
                else:
                    y, x = y0 + k, x0 - k
                if y < 0 or y >= H or x < 0 or x >= W:
                    continue
                b = lab[y, x]
                if b == a or b < 0 or b >= n or not partner[a, b]:
                    continue
                if lim2 < 0:
                    lim = depth * max(1.0, abs(xyz[y0, x0, 2]))
                    lim2 = lim * lim
                dx = xyz[y0, x0, 0] - xyz[y, x, 0]
                dy = xyz[y0, x0, 1] - xyz[y, x, 1]
                dz = xyz[y0, x0, 2] - xyz[y, x, 2]
                if not dx * dx + dy * dy + dz * dz <= lim2:
                    continue
                if a < b:
                    code = a * n + b
                    for j in range(3):
                        acc_lo[code, j] += xyz[y0, x0, j]
                        acc_hi[code, j] += xyz[y, x, j]
                else:
                    code = b * n + a
                    for j in range(3):
                        acc_lo[code, j] += xyz[y, x, j]
                        acc_hi[code, j] += xyz[y0, x0, j]
                cnt[code] += 1.0
    return cnt, acc_lo, acc_hi


@njit(cache=True, nogil=True, error_model="numpy")
def box_points(lab, xyz, label, r0, c0, r1, c1, k):
    """The finite points of ``label`` on every ``k``-th row and column of the pixel box
    ``[r0, r1) x [c0, c1)``, row-major (:func:`planerel.features.solid.face_points`).

    Returns
    -------
    (pts (N, 3) float64, rows (N,) int64, cols (N,) int64)
    """
    nr = max(0, (r1 - r0 + k - 1) // k)
    nc = max(0, (c1 - c0 + k - 1) // k)
    pts = np.empty((nr * nc, 3))
    rows = np.empty(nr * nc, np.int64)
    cols = np.empty(nr * nc, np.int64)
    m = 0
    for r in range(r0, r1, k):
        for c in range(c0, c1, k):
            if lab[r, c] != label:
                continue
            x, y, z = xyz[r, c, 0], xyz[r, c, 1], xyz[r, c, 2]
            if np.isfinite(x) and np.isfinite(y) and np.isfinite(z):
                pts[m, 0], pts[m, 1], pts[m, 2] = x, y, z
                rows[m], cols[m] = r, c
                m += 1
    return pts[:m].copy(), rows[:m].copy(), cols[:m].copy()


@njit(cache=True, inline="always", error_model="numpy")
def _dot3(a0, a1, a2, b0, b1, b2):
    """A 3-vector dot product summed as numpy's ``einsum`` sums it on two-lane SIMD: lanes 0
    and 2 first, then lane 1 (``tests/test_relation_kernels.py`` compares the two)."""
    return (a0 * b0 + a2 * b2) + a1 * b1


@njit(cache=True, inline="always", error_model="numpy")
def _clip01(x):
    if x < 0.0:
        return 0.0
    if x > 1.0:
        return 1.0
    return x


@njit(cache=True, inline="always", error_model="numpy")
def _min(a, b):
    """``np.minimum``: NaN wins."""
    if a != a:
        return a
    if b != b or b < a:
        return b
    return a


@njit(cache=True, nogil=True, error_model="numpy")
def segment_distance(p1, q1, p2, q2):
    """Closest distance between segments ``p1q1`` and ``p2q2`` (3-vectors): the arithmetic of
    :func:`planerel.features.relations._segment_distances` for one pair, step for step."""
    d10, d11, d12 = q1[0] - p1[0], q1[1] - p1[1], q1[2] - p1[2]
    d20, d21, d22 = q2[0] - p2[0], q2[1] - p2[1], q2[2] - p2[2]
    r0, r1, r2 = p1[0] - p2[0], p1[1] - p2[1], p1[2] - p2[2]
    a = _dot3(d10, d11, d12, d10, d11, d12)
    e = _dot3(d20, d21, d22, d20, d21, d22)
    f = _dot3(d20, d21, d22, r0, r1, r2)
    c = _dot3(d10, d11, d12, r0, r1, r2)
    b = _dot3(d10, d11, d12, d20, d21, d22)
    eps = 1e-18
    a_ok = a > eps
    e_ok = e > eps
    safe_a = a if a_ok else 1.0
    safe_e = e if e_ok else 1.0
    denom = a * e - b * b
    ae = a * e
    if denom > eps * (ae if ae > eps or ae != ae else eps):
        s = (b * f - c * e) / (denom if denom > 0 else 1.0)
    else:
        s = 0.0
    s = _clip01(s)
    t = (b * s + f) / safe_e
    low = t < 0
    high = t > 1
    t = _clip01(t)
    if low:
        s = _clip01(-c / safe_a)
    if high:
        s = _clip01((b - c) / safe_a)
    if not a_ok:
        s = 0.0
    if not a_ok and e_ok:
        t = _clip01(f / safe_e)
    if not e_ok:
        t = 0.0
    if not e_ok and a_ok:
        s = _clip01(-c / safe_a)
    x0 = (p1[0] + d10 * s) - (p2[0] + d20 * t)
    x1 = (p1[1] + d11 * s) - (p2[1] + d21 * t)
    x2 = (p1[2] + d12 * s) - (p2[2] + d22 * t)
    return np.sqrt(_dot3(x0, x1, x2, x0, x1, x2))


@njit(cache=True, inline="always", error_model="numpy")
def _inside(poly2, n, u, v):
    """Whether the in-plane point ``(u, v)`` lies inside face ``n``: every edge of the padded
    polygon ``poly2[n]`` (``(M, 2)``, the last vertex repeated) has it on its left, as
    :func:`planerel.features.relations._gap_matrix`'s ``inside``."""
    M = poly2.shape[1]
    for m in range(M):
        m1 = m + 1 if m + 1 < M else 0
        e0 = poly2[n, m1, 0] - poly2[n, m, 0]
        e1 = poly2[n, m1, 1] - poly2[n, m, 1]
        cr = e0 * (v - poly2[n, m, 1]) - e1 * (u - poly2[n, m, 0])
        if not cr >= -1e-12:
            return False
    return True


@njit(cache=True, nogil=True, error_model="numpy")
def gap_matrix(V, vstart, C, N, AX, poly2, isface):
    """``(n, n)`` closest distances between the 3-D convex hulls of ``n`` planes: the values
    of :func:`planerel.features.relations._gap_matrix`'s numpy reference, pair by pair.

    ``V[vstart[k]:vstart[k + 1]]`` are plane ``k``'s hull vertices (its edges join each to
    the next and the last to the first; two vertices make one edge, one vertex a zero-length
    edge); ``C``, ``N``, ``AX`` its centroid, normal and in-plane axes; ``poly2[k]`` its hull
    in its own frame padded to a common length with its last vertex; ``isface[k]`` whether it
    has at least 3 vertices.  A pair's distance is the smallest of the edge-edge distances
    (the edge of the lower plane first), the distances of a vertex to the other's face where
    it projects inside, and 0 when an edge of one pierces the other's face.
    """
    n = C.shape[0]
    # edges: start and end vertex indices, owner
    ne = 0
    for k in range(n):
        cnt = vstart[k + 1] - vstart[k]
        ne += cnt if cnt >= 3 else 1
    ea = np.empty(ne, np.int64)
    eb = np.empty(ne, np.int64)
    eo = np.empty(ne, np.int64)
    estart = np.empty(n + 1, np.int64)
    t = 0
    for k in range(n):
        s0 = vstart[k]
        cnt = vstart[k + 1] - s0
        estart[k] = t
        if cnt == 1:
            ea[t], eb[t], eo[t] = s0, s0, k
            t += 1
        elif cnt == 2:
            ea[t], eb[t], eo[t] = s0, s0 + 1, k
            t += 1
        else:
            for m in range(cnt):
                ea[t], eb[t], eo[t] = s0 + m, s0 + (m + 1) % cnt, k
                t += 1
    estart[n] = t
    # each edge's box: an edge pair whose boxes lie clearly farther apart than the pair's
    # nearest edges so far cannot be nearer (its distance is at least the boxes'): skipped,
    # the minimum is the same value (a margin of 1e-9 relative keeps rounding out of it)
    blo = np.empty((ne, 3))
    bhi = np.empty((ne, 3))
    for e in range(ne):
        for d in range(3):
            a, b = V[ea[e], d], V[eb[e], d]
            blo[e, d] = a if a < b else b
            bhi[e, d] = b if a < b else a
    G = np.full((n, n), np.inf)
    for i in range(n):
        for j in range(i + 1, n):
            best = np.inf
            for u in range(estart[i], estart[i + 1]):
                for w in range(estart[j], estart[j + 1]):
                    g2 = 0.0
                    for d in range(3):
                        g = blo[w, d] - bhi[u, d]
                        if blo[u, d] - bhi[w, d] > g:
                            g = blo[u, d] - bhi[w, d]
                        if g > 0.0:
                            g2 += g * g
                    if np.sqrt(g2) * (1.0 - 1e-9) > best:
                        continue
                    best = _min(best, segment_distance(V[ea[u]], V[eb[u]], V[ea[w]], V[eb[w]]))
            G[i, j] = best
            G[j, i] = best
    # vertices over faces
    for k in range(n):
        for q in range(vstart[k], vstart[k + 1]):
            for f in range(n):
                if f == k or not isface[f]:
                    continue
                r0 = V[q, 0] - C[f, 0]
                r1 = V[q, 1] - C[f, 1]
                r2 = V[q, 2] - C[f, 2]
                u = _dot3(r0, r1, r2, AX[f, 0, 0], AX[f, 0, 1], AX[f, 0, 2])
                v = _dot3(r0, r1, r2, AX[f, 1, 0], AX[f, 1, 1], AX[f, 1, 2])
                if _inside(poly2, f, u, v):
                    h = abs(_dot3(r0, r1, r2, N[f, 0], N[f, 1], N[f, 2]))
                    G[k, f] = _min(G[k, f], h)
                    G[f, k] = _min(G[f, k], h)
    # edges piercing faces
    pierce = np.zeros((n, n), np.bool_)
    for t in range(ne):
        k = eo[t]
        A = V[ea[t]]
        B = V[eb[t]]
        for f in range(n):
            if f == k or not isface[f] or pierce[k, f]:
                continue
            a0, a1, a2 = A[0] - C[f, 0], A[1] - C[f, 1], A[2] - C[f, 2]
            b0, b1, b2 = B[0] - C[f, 0], B[1] - C[f, 1], B[2] - C[f, 2]
            h0 = _dot3(a0, a1, a2, N[f, 0], N[f, 1], N[f, 2])
            h1 = _dot3(b0, b1, b2, N[f, 0], N[f, 1], N[f, 2])
            if not h0 * h1 < 0:
                continue
            tt = h0 / (h0 - h1)
            x0 = a0 + (b0 - a0) * tt
            x1 = a1 + (b1 - a1) * tt
            x2 = a2 + (b2 - a2) * tt
            u = _dot3(x0, x1, x2, AX[f, 0, 0], AX[f, 0, 1], AX[f, 0, 2])
            v = _dot3(x0, x1, x2, AX[f, 1, 0], AX[f, 1, 1], AX[f, 1, 2])
            if _inside(poly2, f, u, v):
                pierce[k, f] = True
    for i in range(n):
        for j in range(n):
            if pierce[i, j] or pierce[j, i]:
                G[i, j] = 0.0
        G[i, i] = 0.0
    return G


@njit(cache=True, nogil=True, error_model="numpy")
def linspace(start, stop, num):
    """``np.linspace(start, stop, num)`` of two floats (numpy 2's arithmetic: ``i * step +
    start`` with ``step = (stop - start) / (num - 1)``, or ``i / (num - 1) * delta + start``
    when the step is 0, and ``stop`` last), without its overhead."""
    out = np.empty(max(num, 0))
    div = num - 1
    delta = stop - start
    if div > 0:
        step = delta / div
        for i in range(num):
            out[i] = (float(i) / div * delta if step == 0 else float(i) * step) + start
        out[num - 1] = stop
    elif num == 1:
        out[0] = 0.0 * delta + start
    return out


@njit(cache=True, nogil=True, error_model="numpy")
def cover_samples(c, along, vert, ca, cu, vu, s, levels, fx, fy, cx, cy, H, W):
    """The sample points of :func:`planerel.features.solid._cover` that project into the
    image, level by level, and their pixels: ``x = (c + (s - ca) along) + ((level - cu) / vu)
    vert`` (``ca = c . along``, ``cu = c . up``, ``vu = vert . up``), pixel ``rint(f x / z +
    c)``, kept when ``z > 0`` and the pixel lies in the ``H x W`` image.

    Returns
    -------
    (X (K, 3) float64, u (K,) int64, v (K,) int64)
    """
    n = levels.shape[0] * s.shape[0]
    X = np.empty((n, 3))
    u = np.empty(n, np.int64)
    v = np.empty(n, np.int64)
    k = 0
    for li in range(levels.shape[0]):
        b = (levels[li] - cu) / vu
        for si in range(s.shape[0]):
            a = s[si] - ca
            x0 = (c[0] + a * along[0]) + b * vert[0]
            x1 = (c[1] + a * along[1]) + b * vert[1]
            x2 = (c[2] + a * along[2]) + b * vert[2]
            uu = np.rint(fx * x0 / x2 + cx)
            vv = np.rint(fy * x1 / x2 + cy)
            if x2 > 0 and uu >= 0 and uu < W and vv >= 0 and vv < H:
                X[k, 0], X[k, 1], X[k, 2] = x0, x1, x2
                u[k] = np.int64(uu)
                v[k] = np.int64(vv)
                k += 1
    return X[:k].copy(), u[:k].copy(), v[:k].copy()


@njit(cache=True, nogil=True, error_model="numpy")
def cover_counts(labels, label, u, v, X, seen, lab, cos, proj, cos_par):
    """``(covered, open)`` of :func:`planerel.features.solid._cover` from its samples: a
    sample is covered when a pixel of ``label`` lies in its 3x3 neighbourhood (clipped to the
    image) or its pixel's plane is parallel to the face (``cos >= cos_par``) with its point on
    the face's plane (``|proj| <= margin``); open when not covered and not hidden (its pixel's
    range finite and not nearer than the sample's by more than ``margin = max(0.03, 0.03
    range)``).  Ranges summed as ``np.linalg.norm`` sums them."""
    H, W = labels.shape
    covered = 0
    open_ = 0
    for t in range(u.shape[0]):
        near = False
        for dv in range(-1, 2):
            for du in range(-1, 2):
                yy = min(max(v[t] + dv, 0), H - 1)
                xx = min(max(u[t] + du, 0), W - 1)
                if labels[yy, xx] == label:
                    near = True
        rs = np.sqrt((seen[t, 0] * seen[t, 0] + seen[t, 1] * seen[t, 1]) + seen[t, 2] * seen[t, 2])
        rf = np.sqrt((X[t, 0] * X[t, 0] + X[t, 1] * X[t, 1]) + X[t, 2] * X[t, 2])
        m = 0.03 * rf
        margin = m if m > 0.03 or m != m else 0.03  # np.maximum: NaN wins
        hidden = not np.isfinite(rs) or rs < rf - margin
        if not near and lab[t] >= 0 and cos[t] >= cos_par and abs(proj[t]) <= margin:
            near = True
        if near:
            covered += 1
        elif not hidden:
            open_ += 1
    return covered, open_


@njit(cache=True, nogil=True, error_model="numpy")
def cover_counts_at(labels, label, u, v, X, xyz, normals, n, c, cos_par):
    """:func:`cover_counts` with its per-sample inputs taken here: ``seen = xyz[v, u]``
    (float64), ``lab = labels[v, u]``, ``cos = |normals[max(lab, 0)] . n|`` and ``proj =
    (seen - c) . n``, the dot products summed in the plain order (numpy's matrix products,
    BLAS, may round the last bit otherwise: ``tests/test_relation_kernels.py`` compares)."""
    m = u.shape[0]
    seen = np.empty((m, 3))
    lab = np.empty(m, np.int64)
    cos = np.empty(m)
    proj = np.empty(m)
    for t in range(m):
        y, x = v[t], u[t]
        s0, s1, s2 = float(xyz[y, x, 0]), float(xyz[y, x, 1]), float(xyz[y, x, 2])
        seen[t, 0], seen[t, 1], seen[t, 2] = s0, s1, s2
        a = labels[y, x]
        lab[t] = a
        k = a if a > 0 else 0
        cos[t] = abs(normals[k, 0] * n[0] + normals[k, 1] * n[1] + normals[k, 2] * n[2])
        proj[t] = (s0 - c[0]) * n[0] + (s1 - c[1]) * n[1] + (s2 - c[2]) * n[2]
    return cover_counts(labels, label, u, v, X, seen, lab, cos, proj, cos_par)


@njit(cache=True, nogil=True, error_model="numpy")
def cover_at(labels, label, xyz, normals, n, c, along, vert, ca, cu, vu, t0, t1, samples,
             levels, fx, fy, cx, cy, cos_par):
    """:func:`linspace` of the top's extent, :func:`cover_samples` and
    :func:`cover_counts_at` in one call (:func:`planerel.features.solid._cover`: the same
    samples and counts, without two calls' boxed arrays between them): ``(samples in the
    image, covered, open)``."""
    H, W = labels.shape
    s = linspace(t0, t1, samples)
    X, u, v = cover_samples(c, along, vert, ca, cu, vu, s, levels, fx, fy, cx, cy, H, W)
    if u.shape[0] == 0:
        return 0, 0, 0
    covered, open_ = cover_counts_at(labels, label, u, v, X, xyz, normals, n, c, cos_par)
    return u.shape[0], covered, open_


@njit(cache=True, nogil=True, error_model="numpy")
def box_label_count(lab, label, r0, c0, r1, c1):
    """Pixels of ``label`` in the pixel box ``[r0, r1) x [c0, c1)``."""
    n = 0
    for r in range(r0, r1):
        for c in range(c0, c1):
            if lab[r, c] == label:
                n += 1
    return n


@njit(cache=True, nogil=True, error_model="numpy")
def box_label_fill(lab, xyz, label, r0, c0, r1, c1, out):
    """``out[:] = xyz[r0:r1, c0:c1][lab[r0:r1, c0:c1] == label]``: the points of ``label`` in
    the box, row-major, finite or not (``out`` sized by :func:`box_label_count`)."""
    k = 0
    for r in range(r0, r1):
        for c in range(c0, c1):
            if lab[r, c] == label:
                out[k, 0] = xyz[r, c, 0]
                out[k, 1] = xyz[r, c, 1]
                out[k, 2] = xyz[r, c, 2]
                k += 1


@njit(cache=True, nogil=True, error_model="numpy")
def _select(a, lo, hi, k):
    """Move the ``k``-th smallest value of ``a[lo:hi]`` (``k`` an index of ``a``) to ``a[k]``,
    with none larger before it and none smaller after it, in place (Hoare's partition around
    a median of three; finite values)."""
    hi -= 1
    while hi > lo:
        mid = (lo + hi) >> 1
        x, y, z = a[lo], a[mid], a[hi]
        if x > y:
            x, y = y, x
        if y > z:
            y = z
        if x > y:
            y = x
        p = y
        i, j = lo, hi
        while i <= j:
            while a[i] < p:
                i += 1
            while a[j] > p:
                j -= 1
            if i <= j:
                a[i], a[j] = a[j], a[i]
                i += 1
                j -= 1
        if k <= j:
            hi = j
        elif k >= i:
            lo = i
        else:
            return


@njit(cache=True, nogil=True, error_model="numpy")
def percentiles_2_98(x):
    """``np.percentile(x, [2, 98])`` (linear method) of a finite 1-D ``x``, ``N >= 1``: the
    same order statistics (two selections in a copy) and the same interpolation arithmetic
    (:func:`planerel.features.solid._percentiles_2_98`; ``tests/test_solid.py`` compares)."""
    return _percentiles_in_place(x.copy())


#: Fewest values for :func:`_tails` (smaller arrays are selected whole).
_TAILS_MIN = 512
#: Size of :func:`_tails`' sample.
_TAILS_SAMPLE = 64


@njit(cache=True, nogil=True, error_model="numpy")
def _tails(a, k_lo, k_hi):
    """The order statistics ``s(k_lo), s(k_lo + 1), s(k_hi), s(k_hi + 1)`` of ``a`` (0-based,
    ``k_lo + 1 < n``, ``k_hi + 1 < n``, ``n >= _TAILS_SAMPLE``), found in its two tails.

    The 5th smallest and 5th largest of a strided sample of 64 values (selected) are the
    pivots; one pass copies the values below the low pivot and those above the high one aside, and the
    wanted values are selected there: when at least ``k_lo + 2`` values lie below the low
    pivot they hold the ``k_lo + 2`` smallest (ties with the pivot stay out, so none is
    missed), and likewise at the top.  About 8 % of the values are copied where the whole
    array was selected twice.

    Returns
    -------
    (float, float, float, float, bool)
        The four values, and False when a tail held too few (nothing is known then; the
        caller selects in the whole array).
    """
    n = a.shape[0]
    m = _TAILS_SAMPLE
    step = n // m
    smp = np.empty(m)
    for i in range(m):
        smp[i] = a[i * step]
    # the sample's 5th smallest and 5th largest (the values its sorted copy holds there), by
    # two selections instead of a sort
    _select(smp, 0, m, 4)
    _select(smp, 5, m, m - 5)
    p_lo, p_hi = smp[4], smp[m - 5]
    low = np.empty(n)
    high = np.empty(n)
    m1 = 0
    m2 = 0
    for i in range(n):
        x = a[i]
        if x < p_lo:
            low[m1] = x
            m1 += 1
        elif x > p_hi:
            high[m2] = x
            m2 += 1
    top = n - 1 - k_hi  # s(k_hi) is the top-th largest (0-based)
    if m1 < k_lo + 2 or top < 1 or m2 < top + 1:
        return 0.0, 0.0, 0.0, 0.0, False
    _select(low, 0, m1, k_lo)
    lo_a, lo_b = low[k_lo], np.inf
    for i in range(k_lo + 1, m1):
        if low[i] < lo_b:
            lo_b = low[i]
    t = m2 - 1 - top
    _select(high, 0, m2, t)
    hi_a, hi_b = high[t], np.inf
    for i in range(t + 1, m2):
        if high[i] < hi_b:
            hi_b = high[i]
    return lo_a, lo_b, hi_a, hi_b, True


@njit(cache=True, nogil=True, error_model="numpy")
def _percentiles_in_place(a):
    """:func:`percentiles_2_98` of ``a``, reordering ``a`` (at least :data:`_TAILS_MIN`
    values: from the tails, :func:`_tails`; the same order statistics)."""
    n = a.shape[0]
    v_lo = (n - 1) * 0.02
    k_lo = min(int(np.floor(v_lo)), n - 1)
    v_hi = (n - 1) * 0.98
    k_hi = min(int(np.floor(v_hi)), n - 1)
    if n >= _TAILS_MIN:
        lo_a, lo_b, hi_a, hi_b, ok = _tails(a, k_lo, k_hi)
        if ok:
            return _interpolate_2_98(v_lo, k_lo, lo_a, lo_b, v_hi, k_hi, hi_a, hi_b)
    # the k_hi-th value and the next one up (the smallest after it)
    _select(a, 0, n, k_hi)
    hi_a = a[k_hi]
    hi_b = hi_a
    if k_hi + 1 <= n - 1:
        hi_b = a[k_hi + 1]
        for i in range(k_hi + 2, n):
            if a[i] < hi_b:
                hi_b = a[i]
    # the k_lo-th value lies before k_hi; the next one up before k_hi or at it
    if k_lo == k_hi:
        lo_a, lo_b = hi_a, hi_b
    else:
        _select(a, 0, k_hi, k_lo)
        lo_a = a[k_lo]
        lo_b = hi_a
        for i in range(k_lo + 1, k_hi):
            if a[i] < lo_b:
                lo_b = a[i]
    return _interpolate_2_98(v_lo, k_lo, lo_a, lo_b, v_hi, k_hi, hi_a, hi_b)


@njit(cache=True, nogil=True, error_model="numpy")
def _interpolate_2_98(v_lo, k_lo, lo_a, lo_b, v_hi, k_hi, hi_a, hi_b):
    """``np.percentile``'s linear interpolation between each pair of order statistics
    (``va = s(k)``, ``vb = s(k + 1)`` at the virtual index ``v``), its arithmetic."""
    out = np.empty(2)
    for i in range(2):
        v, k, va, vb = (v_lo, k_lo, lo_a, lo_b) if i == 0 else (v_hi, k_hi, hi_a, hi_b)
        t = v - k
        d = vb - va
        out[i] = vb - d * (1 - t) if t >= 0.5 else va + d * t
    return out


@njit(cache=True, inline="always", error_model="numpy")
def _prefetch_box_row(lab, xyz, r, r1, c0, c1):
    """Ask for row ``r`` (when ``r < r1``) of a box's labels and points, columns ``c0..c1-1``,
    while the row before it is read: a box's rows are short pieces of the image's rows, and
    the hardware's prefetcher starts each anew.  Only when the data arrives changes (C-order
    arrays assumed for the addresses; any other layout only wastes the hint)."""
    if r >= r1:
        return
    W = lab.shape[1]
    for c in range(c0, c1, 16):
        prefetch(lab, r * W + c)
    for c in range(c0, c1, 2):  # 24-byte points: every 64-byte line
        prefetch(xyz, 3 * (r * W + c))


@njit(cache=True, nogil=True, error_model="numpy")
def box_profile(lab, xyz, label, r0, c0, r1, c1, k, up, along):
    """The 2nd and 98th percentiles of ``up . x`` and of ``along . x`` over the points of
    :func:`box_points` (the same pixels), in one pass without the points: the face profile
    of :func:`planerel.features.solid.face_profile_of`.  The dot products are summed in the
    plain order ``x u0 + y u1 + z u2`` (numpy's matrix product, BLAS, may round the last bit
    otherwise: ``tests/test_relation_kernels.py`` compares within 1e-12).  The box lies in
    the image (``0 <= r0``, ``0 <= c0``, ``r1 <= H``, ``c1 <= W``: clipped as
    :func:`planerel.features.solid._face_box` clips it).

    Returns
    -------
    ndarray (4,) float64
        ``(bottom, top, lo, hi)``; NaN with fewer than 3 points.
    """
    nr = max(0, (r1 - r0 + k - 1) // k)
    nc = max(0, (c1 - c0 + k - 1) // k)
    hu = np.empty(nr * nc)
    ha = np.empty(nr * nc)
    u0, u1, u2 = up[0], up[1], up[2]
    a0, a1, a2 = along[0], along[1], along[2]
    m = 0
    for r in range(r0, r1, k):
        _prefetch_box_row(lab, xyz, r + k, r1, c0, c1)
        for c in range(c0, c1, k):
            # (an unsigned column, >= 0 as the box is: numba wraps a signed one around at
            # every read)
            cu = np.uint64(c)
            if lab[r, cu] != label:
                continue
            x, y, z = xyz[r, cu, 0], xyz[r, cu, 1], xyz[r, cu, 2]
            if np.isfinite(x) and np.isfinite(y) and np.isfinite(z):
                hu[m] = x * u0 + y * u1 + z * u2
                ha[m] = x * a0 + y * a1 + z * a2
                m += 1
    out = np.full(4, np.nan)
    if m >= 3:
        p = _percentiles_in_place(hu[:m])
        q = _percentiles_in_place(ha[:m])
        out[0], out[1], out[2], out[3] = p[0], p[1], q[0], q[1]
    return out


@njit(cache=True, nogil=True, error_model="numpy")
def box_label_heights(lab, xyz, label, r0, c0, r1, c1, up):
    """``xyz[r0:r1, c0:c1][lab[r0:r1, c0:c1] == label] @ up`` (finite or not, row-major) in
    one pass (into a buffer the size of the box, returned trimmed), each dot product summed
    in the plain order ``x u0 + y u1 + z u2`` (numpy's BLAS product may round the last bit
    otherwise: ``tests/test_relation_kernels.py`` compares within 1e-12)."""
    out = np.empty(max(0, r1 - r0) * max(0, c1 - c0))
    u0, u1, u2 = up[0], up[1], up[2]
    k = 0
    for r in range(r0, r1):
        for c in range(c0, c1):
            if lab[r, c] == label:
                out[k] = xyz[r, c, 0] * u0 + xyz[r, c, 1] * u1 + xyz[r, c, 2] * u2
                k += 1
    return out[:k]


@njit(cache=True, nogil=True, error_model="numpy")
def box_label_heights_range(lab, xyz, label, r0, c0, r1, c1, up):
    """``(h, *finite_range(h))`` of ``h = box_label_heights(...)`` in its one pass: the same
    heights, and their finite count, min and max taken as they are computed (the same
    comparisons in the same order as :func:`finite_range`)."""
    out = np.empty(max(0, r1 - r0) * max(0, c1 - c0))
    u0, u1, u2 = up[0], up[1], up[2]
    k = 0
    n = 0
    lo = np.nan
    hi = np.nan
    for r in range(r0, r1):
        for c in range(c0, c1):
            if lab[r, c] == label:
                v = xyz[r, c, 0] * u0 + xyz[r, c, 1] * u1 + xyz[r, c, 2] * u2
                out[k] = v
                k += 1
                if not np.isfinite(v):
                    continue
                if n == 0:
                    lo = v
                    hi = v
                elif v < lo:
                    lo = v
                elif v > hi:
                    hi = v
                n += 1
    return out[:k], n, lo, hi


@njit(cache=True, nogil=True, error_model="numpy")
def finite_range(x):
    """``(count, min, max)`` of the finite values of a 1-D ``x`` in one pass (``np.min`` and
    ``np.max`` of ``x[np.isfinite(x)]``; NaN for both when there is none)."""
    n = 0
    lo = np.nan
    hi = np.nan
    for i in range(x.shape[0]):
        v = x[i]
        if not np.isfinite(v):
            continue
        if n == 0:
            lo = v
            hi = v
        elif v < lo:
            lo = v
        elif v > hi:
            hi = v
        n += 1
    return n, lo, hi


@njit(cache=True, nogil=True, error_model="numpy")
def level_bins(h, lo, bin_size, nb, w, dense):
    """The height histogram of :func:`planerel.features.stepped.stepped_levels` and its
    populated bins: ``counts[k]`` the heights with ``min(int((h - lo) / bin_size), nb - 1)
    == k``; bin ``k`` is populated when it holds at least 3 and at least ``dense`` times the
    fullest bin within ``w`` bins of it (numpy's ``bincount``, zero-padded sliding maximum
    and comparisons: the same integers and the same float products)."""
    counts = np.zeros(nb, np.int64)
    for i in range(h.shape[0]):
        k = int((h[i] - lo) / bin_size)
        counts[min(k, nb - 1)] += 1
    pop = np.zeros(nb, np.bool_)
    for k in range(nb):
        local = 0
        for j in range(max(0, k - w), min(nb, k + w + 1)):
            if counts[j] > local:
                local = counts[j]
        pop[k] = counts[k] >= 3 and counts[k] >= dense * local
    return counts, pop


@njit(cache=True, nogil=True, error_model="numpy")
def median(x):
    """``np.median(x)`` of a 1-D ``x`` (``N >= 1``): the middle value, or the mean
    ``(a + b) / 2`` of the two middle ones, found by selection in a copy (the same order
    statistics, so the same float); NaN when ``x`` holds a NaN, as numpy's."""
    n = x.shape[0]
    a = np.empty(n)
    for i in range(n):
        v = x[i]
        if v != v:
            return np.nan
        a[i] = v
    k = n // 2
    _select(a, 0, n, k)
    if n % 2:
        return a[k]
    lo = a[0]
    for i in range(1, k):
        if a[i] > lo:
            lo = a[i]
    return (lo + a[k]) / 2.0


@njit(cache=True, nogil=True, error_model="numpy")
def _window_outline_pass(lab, r0, c0, r1, c1, a, b, pa, pb):
    """Count (and, where ``pa`` / ``pb`` have room, write) the outline pixels of labels ``a``
    and ``b`` in the window (see :func:`window_outlines`); return the two counts."""
    na = nb = 0
    for v in range(r0, r1):
        for u in range(c0, c1):
            k = lab[v, u]
            if k < 0 or (k != a and k != b):
                continue
            if not (v == r0 or u == c0 or v == r1 - 1 or u == c1 - 1
                    or lab[v - 1, u] != k or lab[v + 1, u] != k
                    or lab[v, u - 1] != k or lab[v, u + 1] != k):
                continue
            if k == a:
                if pa.shape[0] > na:
                    pa[na, 0] = v - r0
                    pa[na, 1] = u - c0
                na += 1
            if k == b:
                if pb.shape[0] > nb:
                    pb[nb, 0] = v - r0
                    pb[nb, 1] = u - c0
                nb += 1
    return na, nb


@njit(cache=True, nogil=True, error_model="numpy")
def window_outlines(lab, r0, c0, r1, c1, a, b):
    """``np.argwhere(edge & (w == a))`` and the same of ``b``, ``w = lab[r0:r1, c0:c1]`` and
    ``edge`` its outline (:func:`planerel.segment._label_kernels.label_boundary` of ``w``: a
    labelled pixel with a 4-neighbour of another label or on the window's border), without
    the window's copy, outline image and label masks; ``(N, 2)`` int64 window coordinates,
    row-major.  The window lies inside the image (``0 <= r0 <= r1 <= H``, the same of
    columns)."""
    none = np.empty((0, 2), np.int64)
    na, nb = _window_outline_pass(lab, r0, c0, r1, c1, a, b, none, none)
    pa = np.empty((na, 2), np.int64)
    pb = np.empty((nb, 2), np.int64)
    if na or nb:
        _window_outline_pass(lab, r0, c0, r1, c1, a, b, pa, pb)
    return pa, pb
