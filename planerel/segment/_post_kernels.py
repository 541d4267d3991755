"""numba kernels of the planar post-processing (:mod:`planerel.segment.split` and
:mod:`planerel.segment.merge`): label checks and counts, connected patches, part assignment,
connected pieces.  Compiled once, cached on disk; import only from inside functions.

Each kernel replaces a few numpy / scipy calls over whole images or whole regions; they compute
the same values in the same order (sums sequentially over points in pixel order, components
numbered by their first pixel in row-major order), so results match the numpy statements they
replace (tests in ``tests/test_segment_post_kernels.py``).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from planerel.segment._kernels import (
    NO_MOMENTS,
    moments_add,
    moments_enter,
    moments_store,
    plane_from_scatter,
)

__all__ = ["label_counts", "free_patches", "depth_scales", "assign_parts", "part_pieces",
           "absorb_small", "merge_stats", "ransac_hypotheses", "absorb_relabel", "fit_counts",
           "relabel_moments", "relabel", "group_moments"]


@njit(cache=True, nogil=True)
def label_counts(labels, valid, n):  # pragma: no cover - compiled
    """Pixels per label ``0 .. n-1`` of ``labels`` (N,) int32, and a status: 0 when every
    label lies in ``-1 .. n-1`` and every labelled pixel is ``valid`` (N,) bool; 1 when a label
    is out of range; 2 when a labelled pixel is invalid."""
    cnt = np.zeros(n, dtype=np.int64)
    status = 0
    for p in range(labels.shape[0]):
        lab = labels[p]
        if lab < 0:
            if lab < -1:
                return cnt, 1
            continue
        if lab >= n:
            return cnt, 1
        if not valid[p]:
            status = 2
        cnt[lab] += 1
    return cnt, status


@njit(cache=True, nogil=True, error_model="numpy")
def depth_scales(z, scale, noise, q, unit):  # pragma: no cover - compiled
    """``z / (scale * sigma_z(z))`` per point (:meth:`SplitParams.depth_sigma2`, the same
    operations in the same order)."""
    out = np.empty(z.shape[0])
    u2 = unit ** 2 / 12.0
    for i in range(z.shape[0]):
        z2 = z[i] * z[i]
        a = noise * z2
        b = q * z2
        out[i] = z[i] / (scale * np.sqrt(a * a + b * b / 12.0 + u2))
    return out


@njit(cache=True, nogil=True, error_model="numpy")
def assign_parts(P, zs, planes, assign_sigmas):  # pragma: no cover - compiled
    """Normalised distances ``cost`` (m, k) of points ``P`` (m, 3) to the planes (k, 4: normal,
    offset), ``|n . p + off| * zs / max(|n . p|, 1e-12)``, and per point the nearest part
    (the first of equal ones), -1 beyond ``assign_sigmas``."""
    m = P.shape[0]
    k = planes.shape[0]
    cost = np.empty((m, k))
    part = np.empty(m, dtype=np.int64)
    for i in range(m):
        best = np.inf
        bj = 0
        for j in range(k):
            dn = P[i, 0] * planes[j, 0] + P[i, 1] * planes[j, 1] + P[i, 2] * planes[j, 2]
            c = abs(dn + planes[j, 3]) * zs[i] / max(abs(dn), 1e-12)
            cost[i, j] = c
            if c < best:
                best = c
                bj = j
        part[i] = bj if best <= assign_sigmas else -1
    return cost, part


@njit(cache=True, nogil=True, error_model="numpy")
def ransac_hypotheses(Q, tri, N, pick):  # pragma: no cover - compiled
    """The hypothesis planes of :func:`planerel.segment.split._ransac`: one through each
    point triple ``Q[tri[t]]`` (``tri`` (t, 3)), then one through each point ``Q[pick[t]]``
    with its normal ``N[pick[t]]`` (``N`` (m, 3) float64, may be empty with ``pick``); a
    triple on a line or a zero normal gives none.  Returns the unit normals (h, 3) and offsets
    (h,) with the numpy statements' roundings: cross products as ``u1 v2 - u2 v1`` ...,
    lengths ``sqrt(x^2 + y^2 + z^2)`` (``np.linalg.norm(axis=1)``), offsets ``-((n0 p0 + n2 p2)
    + n1 p1)`` (``np.einsum("ij,ij->i")``'s order for three columns)."""
    k = tri.shape[0] + pick.shape[0]
    Hn = np.empty((k, 3))
    P = np.empty((k, 3))
    h = 0
    for t in range(tri.shape[0]):
        i0 = tri[t, 0]
        i1 = tri[t, 1]
        i2 = tri[t, 2]
        ax = Q[i0, 0]
        ay = Q[i0, 1]
        az = Q[i0, 2]
        ux = Q[i1, 0] - ax
        uy = Q[i1, 1] - ay
        uz = Q[i1, 2] - az
        vx = Q[i2, 0] - ax
        vy = Q[i2, 1] - ay
        vz = Q[i2, 2] - az
        c0 = uy * vz - uz * vy
        c1 = uz * vx - ux * vz
        c2 = ux * vy - uy * vx
        ln = np.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
        if ln > 1e-12:
            Hn[h, 0] = c0 / ln
            Hn[h, 1] = c1 / ln
            Hn[h, 2] = c2 / ln
            P[h, 0] = ax
            P[h, 1] = ay
            P[h, 2] = az
            h += 1
    for t in range(pick.shape[0]):
        j = pick[t]
        a = N[j, 0]
        b = N[j, 1]
        c = N[j, 2]
        ln = np.sqrt(a * a + b * b + c * c)
        if ln > 1e-12:
            Hn[h, 0] = a / ln
            Hn[h, 1] = b / ln
            Hn[h, 2] = c / ln
            P[h, 0] = Q[j, 0]
            P[h, 1] = Q[j, 1]
            P[h, 2] = Q[j, 2]
            h += 1
    Ho = np.empty(h)
    for t in range(h):
        Ho[t] = -((Hn[t, 0] * P[t, 0] + Hn[t, 2] * P[t, 2]) + Hn[t, 1] * P[t, 1])
    return Hn[:h], Ho


@njit(cache=True, nogil=True, error_model="numpy")
def ransac_scores(S, Sz, Hn, Ho, sigmas):  # pragma: no cover - compiled
    """Inlier count of each hypothesis plane (``Hn`` (H, 3) normals, ``Ho`` (H,) offsets) on
    the sample ``S`` (s, 3): points with ``|n . p + o| * zs <= sigmas * |n . p|``."""
    score = np.zeros(Hn.shape[0], dtype=np.int64)
    for j in range(Hn.shape[0]):
        a = Hn[j, 0]
        b = Hn[j, 1]
        c = Hn[j, 2]
        o = Ho[j]
        cnt = 0
        for i in range(S.shape[0]):
            dn = S[i, 0] * a + S[i, 1] * b + S[i, 2] * c
            cnt += abs(dn + o) * Sz[i] <= sigmas * abs(dn)
        score[j] = cnt
    return score


@njit(cache=True, nogil=True, error_model="numpy")
def plane_fit(P):  # pragma: no cover - compiled
    """Least-squares plane of points ``P`` (m, 3), m >= 3: (unit normal (3,), offset), the
    smallest-eigenvalue eigenvector of the scatter about the mean."""
    m = P.shape[0]
    cx = cy = cz = 0.0
    for i in range(m):
        cx += P[i, 0]
        cy += P[i, 1]
        cz += P[i, 2]
    cx /= m
    cy /= m
    cz /= m
    sxx = sxy = sxz = syy = syz = szz = 0.0
    for i in range(m):
        x = P[i, 0] - cx
        y = P[i, 1] - cy
        z = P[i, 2] - cz
        sxx += x * x
        sxy += x * y
        sxz += x * z
        syy += y * y
        syz += y * z
        szz += z * z
    return plane_from_scatter(sxx, sxy, sxz, syy, syz, szz, cx, cy, cz)


@njit(cache=True, nogil=True)
def _columns(pix, W):  # pragma: no cover - compiled
    """Image column of each of the ascending flat pixels ``pix`` (rows advance monotonically:
    no integer division per pixel)."""
    m = pix.shape[0]
    col = np.empty(m, dtype=np.int64)
    row0 = 0
    for i in range(m):
        while pix[i] >= row0 + W:
            row0 += W
        col[i] = pix[i] - row0
    return col


@njit(cache=True, nogil=True)
def _root(parent, r):  # pragma: no cover - compiled
    while parent[r] != r:
        parent[r] = parent[parent[r]]
        r = parent[r]
    return r


@njit(cache=True, nogil=True)
def _point_components(pix, W, member, comp):  # pragma: no cover - compiled
    """8-connected components (in the image grid ``W`` wide) of the points ``i`` of a region
    (flat pixels ``pix`` (m,), ascending) with ``member[i] >= 0``, joining only points with
    equal ``member`` values: ``comp`` (m,) receives 0, 1, ... numbered by first pixel (-1 for
    non-members).  Returns the component sizes.

    Run-length labelling: the points form horizontal runs of equal ``member``; a run joins the
    runs of the row above that it touches (column ranges overlapping once widened by one),
    by union-find over runs with the earlier run as root, so the roots in order number the
    components by first pixel.  Work grows with the runs, not the pixels."""
    m = pix.shape[0]
    col = _columns(pix, W)
    # runs: first point, last point, row start pixel (pix - col), first and last column
    r_first = np.empty(m, dtype=np.int64)
    r_last = np.empty(m, dtype=np.int64)
    nr = 0
    i = 0
    while i < m:
        g = member[i]
        if g < 0:
            comp[i] = -1
            i += 1
            continue
        j = i
        while (j + 1 < m and member[j + 1] == g and pix[j + 1] == pix[j] + 1
               and col[j + 1] == col[j] + 1):
            j += 1
        r_first[nr] = i
        r_last[nr] = j
        nr += 1
        i = j + 1
    parent = np.arange(nr)
    # [a, b): the runs of the row above the current run's row (empty when that row has
    # none); a only moves right, past runs that end left of the current run
    a = 0
    b = 0
    cur_row = -1
    for r in range(nr):
        f = r_first[r]
        row = pix[f] - col[f]  # flat index of the row's first pixel
        if row != cur_row:
            if r > 0 and cur_row == row - W:
                b = r
                a = r - 1
                while a > 0 and pix[r_first[a - 1]] - col[r_first[a - 1]] == cur_row:
                    a -= 1
            else:
                a = r
                b = r
            cur_row = row
        u0 = col[f]
        u1 = col[r_last[r]]
        g = member[f]
        while a < b and col[r_last[a]] < u0 - 1:
            a += 1
        for q in range(a, b):
            qf = r_first[q]
            if col[qf] > u1 + 1:
                break
            if member[qf] == g:
                ra = _root(parent, r)
                rb = _root(parent, q)
                if ra != rb:  # the earlier run stays the root
                    if ra < rb:
                        parent[rb] = ra
                    else:
                        parent[ra] = rb
    sizes = np.zeros(max(nr, 1), dtype=np.int64)
    cid = np.empty(nr, dtype=np.int64)
    nc = 0
    for r in range(nr):
        root = _root(parent, r)
        if root == r:
            cid[r] = nc
            nc += 1
        else:
            cid[r] = cid[root]
        c = cid[r]
        sizes[c] += r_last[r] - r_first[r] + 1
        for k in range(r_first[r], r_last[r] + 1):
            comp[k] = c
    return sizes[:nc]


@njit(cache=True, nogil=True)
def free_patches(labels, valid, W, min_size):  # pragma: no cover - compiled
    """8-connected patches of valid unassigned pixels (``labels`` (N,) < 0, ``valid`` (N,))
    with at least ``min_size`` pixels: (flat pixel indices (K,) grouped by patch, ascending
    within one; starts (P + 1,)), patches ordered by their first pixel (row-major)."""
    N = labels.shape[0]
    m = 0
    for p in range(N):
        if valid[p] and labels[p] < 0:
            m += 1
    pix = np.empty(m, dtype=np.int64)
    k = 0
    for p in range(N):
        if valid[p] and labels[p] < 0:
            pix[k] = p
            k += 1
    comp = np.empty(m, dtype=np.int64)
    sizes = _point_components(pix, W, np.zeros(m, dtype=np.int64), comp)
    nc = sizes.shape[0]
    first = np.full(nc, -1, dtype=np.int64)  # write position of each kept patch
    npk = 0
    total = 0
    for c in range(nc):
        if sizes[c] >= min_size:
            first[c] = total
            total += sizes[c]
            npk += 1
    starts = np.empty(npk + 1, dtype=np.int64)
    k = 0
    for c in range(nc):
        if first[c] >= 0:
            starts[k] = first[c]
            k += 1
    starts[npk] = total
    out = np.empty(total, dtype=np.int64)
    for i in range(m):  # points in pixel order: ascending within each patch
        c = comp[i]
        if first[c] >= 0:
            out[first[c]] = pix[i]
            first[c] += 1
    return out, starts


@njit(cache=True, nogil=True)
def part_pieces(pix, W, part, k, min_size):  # pragma: no cover - compiled
    """Connected pieces of the parts of one region (see ``split._pieces``): per point the kept
    piece (0.. ordered by part, then by first pixel), -2 in a piece of fewer than
    ``min_size`` points, -1 unassigned; and each kept piece's part."""
    m = pix.shape[0]
    comp = np.empty(m, dtype=np.int64)
    sizes = _point_components(pix, W, part, comp)
    nc = sizes.shape[0]
    cpart = np.empty(nc, dtype=np.int64)
    for i in range(m):
        if comp[i] >= 0:
            cpart[comp[i]] = part[i]
    lut = np.full(nc, -2, dtype=np.int64)
    plane_of = np.empty(nc, dtype=np.int64)
    kept = 0
    for j in range(k):
        for c in range(nc):
            if cpart[c] == j and sizes[c] >= min_size:
                lut[c] = kept
                plane_of[kept] = j
                kept += 1
    piece = np.empty(m, dtype=np.int64)
    for i in range(m):
        piece[i] = -1 if comp[i] < 0 else lut[comp[i]]
    return piece, plane_of[:kept].copy()


@njit(cache=True, nogil=True)
def absorb_small(pix, W, piece, piece_plane, cost, assign_sigmas, cellmap):  # pragma: no cover
    """Points of too-small pieces (-2) join the adjacent kept piece (8-connected to their small
    component) whose plane is nearest in ``cost`` (the first of equal ones), within
    ``assign_sigmas``; else they become unassigned (-1) (see ``split._absorb``).  ``cellmap``
    (N,) int32 scratch, all -1 (restored): here the kept piece at each of the region's pixels.
    Works on the small points only, apart from one pass writing and one clearing the map."""
    m = pix.shape[0]
    N = cellmap.shape[0]
    kept = piece_plane.shape[0]
    out = piece.copy()
    ns = 0
    for i in range(m):
        if piece[i] == -2:
            ns += 1
    if ns == 0:
        return out
    sidx = np.empty(ns, dtype=np.int64)
    k = 0
    for i in range(m):
        if piece[i] == -2:
            sidx[k] = i
            k += 1
    spix = np.empty(ns, dtype=np.int64)
    for k in range(ns):
        spix[k] = pix[sidx[k]]
    comp = np.empty(ns, dtype=np.int64)
    sizes = _point_components(spix, W, np.zeros(ns, dtype=np.int64), comp)
    adj = np.zeros((sizes.shape[0], kept), dtype=np.bool_)
    for i in range(m):
        if piece[i] >= 0:
            cellmap[pix[i]] = piece[i]
    col = _columns(spix, W)
    for k in range(ns):
        c = spix[k]
        u = col[k]
        for dv in range(-1, 2):
            for du in range(-1, 2):
                uu = u + du
                q = c + dv * W + du
                if (dv == 0 and du == 0) or uu < 0 or uu >= W or q < 0 or q >= N:
                    continue
                t = cellmap[q]
                if t >= 0:
                    adj[comp[k], t] = True
    for i in range(m):
        if piece[i] >= 0:
            cellmap[pix[i]] = -1
    for k in range(ns):
        i = sidx[k]
        best = np.inf
        bj = 0
        for t in range(kept):
            c = cost[i, piece_plane[t]] if adj[comp[k], t] else np.inf
            if c < best:
                best = c
                bj = t
        out[i] = bj if best <= assign_sigmas else -1
    return out


@njit(cache=True, nogil=True, error_model="numpy")
def merge_stats(X, L, pn, n, noise, q, unit, sensor2):  # pragma: no cover - compiled
    """Per region, over the labelled points of ``X`` (M, 3) with labels ``L`` (M,) (-1 =
    none), in point order: count (n,), sums (n, 3), scatter sums (n, 3, 3) and the sum of the
    expected point-to-plane variance with the region's normal ``pn`` (n, 3), times
    ``sensor2`` (:meth:`SplitParams.depth_sigma2` projected on the normal)."""
    cnt = np.zeros(n)
    s1 = np.zeros((n, 3))
    s2 = np.zeros((n, 3, 3))
    sv = np.zeros(n)
    u2 = unit ** 2 / 12.0
    for i in range(L.shape[0]):
        lab = L[i]
        if lab < 0:
            continue
        x = X[i, 0]
        y = X[i, 1]
        z = X[i, 2]
        cnt[lab] += 1.0
        s1[lab, 0] += x
        s1[lab, 1] += y
        s1[lab, 2] += z
        s2[lab, 0, 0] += x * x
        s2[lab, 0, 1] += x * y
        s2[lab, 0, 2] += x * z
        s2[lab, 1, 1] += y * y
        s2[lab, 1, 2] += y * z
        s2[lab, 2, 2] += z * z
        z2 = z * z
        a = noise * z2
        b = q * z2
        proj = abs(x * pn[lab, 0] + y * pn[lab, 1] + z * pn[lab, 2]) / z
        sv[lab] += (a * a + b * b / 12.0 + u2) * proj * proj * sensor2
    for r in range(n):
        s2[r, 1, 0] = s2[r, 0, 1]
        s2[r, 2, 0] = s2[r, 0, 2]
        s2[r, 2, 1] = s2[r, 1, 2]
    return cnt, s1, s2, sv


@njit(cache=True, nogil=True, error_model="numpy")
def absorb_relabel(pts, labels, gone, keep_rest, cand_ptr, cand_idx, planes, thr, new_id,
                   rec_row, sums, ref):  # pragma: no cover - compiled
    """One pass of :func:`planerel.segment.absorb.absorb_fragments` over the image.

    ``pts`` (N, 3), ``labels`` (N,) int32 (-1 none, ids 0..n-1); ``gone`` (n,) bool: the
    fragments, ``keep_rest`` (n,) bool: fragments that keep the pixels fitting no neighbour
    (the others leave them unassigned); ``cand_idx[cand_ptr[r]:cand_ptr[r + 1]]`` the neighbours a fragment ``r`` may
    join; ``planes`` (n, 4) ``nx, ny, nz, offset``; ``thr`` (n,) fit distance per plane (m);
    ``new_id`` (n,) int32 final id of each kept region; ``rec_row`` (n,) int: row of ``sums`` /
    ``ref`` collecting the moments of a receiving region (-1: none), ``ref`` preset to a point
    of it.  A fragment's pixel joins the neighbour with the smallest ``distance / thr`` when that
    is <= 1, else stays (``keep_rest``) or becomes unassigned.  Returns the final labels (N,) int32, the number of
    fragment pixels left unassigned and the pixels each ``sums`` row received."""
    N = labels.shape[0]
    out = np.empty(N, dtype=np.int32)
    nrow = sums.shape[0]
    got = np.zeros(nrow, dtype=np.int64)
    for i in range(nrow):
        for k in range(10):
            sums[i, k] = 0.0
    lost = 0
    # the current row's totals stay in registers until the row changes (the same additions in
    # the same order, as in planerel.segment._kernels.add_region_moments)
    cur = -1
    m = NO_MOMENTS
    rx = ry = rz = 0.0
    for p in range(N):
        t = labels[p]
        if t < 0:
            out[p] = -1
            continue
        x = pts[p, 0]
        y = pts[p, 1]
        z = pts[p, 2]
        if gone[t]:
            best = -1
            bd = 0.0
            for k in range(cand_ptr[t], cand_ptr[t + 1]):
                c = cand_idx[k]
                d = abs(planes[c, 0] * x + planes[c, 1] * y + planes[c, 2] * z + planes[c, 3]) / thr[c]
                if d <= 1.0 and (best < 0 or d < bd):
                    bd = d
                    best = c
            if best >= 0:
                t = best
            elif not keep_rest[t]:
                out[p] = -1
                lost += 1
                continue
        out[p] = new_id[t]
        r = rec_row[t]
        if r >= 0:
            if r != cur:
                m, rx, ry, rz = moments_enter(sums, ref, cur, m, r, pts, p, False)
                cur = r
            m = moments_add(m, x - rx, y - ry, z - rz)
            if labels[p] != t:
                got[r] += 1
    if cur >= 0:
        moments_store(sums, cur, m)
    return out, lost, got


@njit(cache=True, nogil=True, error_model="numpy")
def fit_counts(X, L, n, active, cand_ptr, cand_idx, planes, thr):  # pragma: no cover - compiled
    """Per region of the sample ``X`` (M, 3), ``L`` (M,) int32: its points, and those within
    ``thr[c]`` of the plane ``planes[c]`` (``nx, ny, nz, offset``) of at least one of its
    candidates ``c`` in ``cand_idx[cand_ptr[r]:cand_ptr[r + 1]]`` with ``active[c]``.
    Returns two (n,) int64 arrays (see :func:`planerel.segment.absorb.absorb_fragments`)."""
    tot = np.zeros(n, dtype=np.int64)
    fit = np.zeros(n, dtype=np.int64)
    for p in range(L.shape[0]):
        r = L[p]
        if r < 0:
            continue
        tot[r] += 1
        x = X[p, 0]
        y = X[p, 1]
        z = X[p, 2]
        for k in range(cand_ptr[r], cand_ptr[r + 1]):
            c = cand_idx[k]
            if not active[c]:
                continue
            if abs(planes[c, 0] * x + planes[c, 1] * y + planes[c, 2] * z + planes[c, 3]) <= thr[c]:
                fit[r] += 1
                break
    return tot, fit


@njit(cache=True, nogil=True, error_model="numpy")
def relabel_moments(labels, remap, row, pts, nrow):  # pragma: no cover - compiled
    """New labels and the moments of the regions to refit, in one pass over the image.

    ``labels`` (N,) int32 (-1 none), ``remap`` (n + 1,) int32: the new label of old label
    ``l`` at ``remap[l + 1]``; ``row`` (n + 1,) int: the moments row of old label ``l`` at
    ``row[l + 1]`` (-1: not refitted); ``pts`` (N, 3).  Returns the new labels (N,) int32 and
    ``(sums (nrow, 10), ref (nrow, 3))`` as :func:`planerel.segment._kernels.region_sums` gives
    them for the points of each row in pixel order (about each row's first point): so
    ``planes_from_sums`` of them equals ``fit_planes`` of those points."""
    N = labels.shape[0]
    out = np.empty(N, dtype=np.int32)
    sums = np.zeros((nrow, 10))
    ref = np.zeros((nrow, 3))
    # the current row's totals stay in registers until the row changes (the same additions in
    # the same order, as in planerel.segment._kernels.add_region_moments)
    cur = -1
    m = NO_MOMENTS
    rx = ry = rz = 0.0
    for p in range(N):
        lab = labels[p] + 1
        out[p] = remap[lab]
        r = row[lab]
        if r < 0:
            continue
        if r != cur:  # the row's first point is its reference
            m, rx, ry, rz = moments_enter(sums, ref, cur, m, r, pts, p, True)
            cur = r
        m = moments_add(m, pts[p, 0] - rx, pts[p, 1] - ry, pts[p, 2] - rz)
    if cur >= 0:
        moments_store(sums, cur, m)
    return out, sums, ref


@njit(cache=True, nogil=True)
def relabel(labels, remap):  # pragma: no cover - compiled
    """``remap[labels + 1]`` (N,) int32 of ``labels`` (N,) int32 (-1 none)."""
    N = labels.shape[0]
    out = np.empty(N, dtype=np.int32)
    for p in range(N):
        out[p] = remap[labels[p] + 1]
    return out


@njit(cache=True, nogil=True, error_model="numpy")
def group_moments(pts, pix, labels, row, owner, g, sums, ref):  # pragma: no cover - compiled
    """Add to ``sums`` / ``ref`` the moments of the pixels ``pix`` (ascending) whose label
    ``l`` belongs to group ``g`` (``owner[l + 1] == g``), to row ``row[l + 1]``; a row whose
    count is still 0 takes its first point as its reference.  When every pixel of those rows
    lies in ``pix`` this is what :func:`relabel_moments` sums for them."""
    cur = -1
    m = NO_MOMENTS
    rx = ry = rz = 0.0
    for t in range(pix.shape[0]):
        p = pix[t]
        lab = labels[p] + 1
        if owner[lab] != g:
            continue
        r = row[lab]
        if r < 0:
            continue
        if r != cur:
            m, rx, ry, rz = moments_enter(sums, ref, cur, m, r, pts, p, True)
            cur = r
        m = moments_add(m, pts[p, 0] - rx, pts[p, 1] - ry, pts[p, 2] - rz)
    if cur >= 0:
        moments_store(sums, cur, m)
