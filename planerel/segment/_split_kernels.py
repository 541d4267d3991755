"""numba kernels of the post-processing's residual test and of the search for planar parts in a
bent region (compiled once, cached on disk; import only from inside functions).

The part-search kernels replace the numpy statements of ``split._split_one`` with the same
operations in the same order (the point-to-plane products ``P @ n`` stay numpy's, they are
passed in), so the results are bit for bit those of the statements they replace
(``tests/test_segment_split_kernels.py``)."""

from __future__ import annotations

import numpy as np
from numba import njit

from planerel.segment._kernels import plane_from_scatter

__all__ = ["residual_stats_grid", "inliers_fit", "assign_refit", "part_centroids", "sample_normals",
           "group_pixels"]


@njit(cache=True, nogil=True)
def group_pixels(lab, sel):  # pragma: no cover
    """The pixels of the selected regions, grouped by region: a counting sort.

    ``lab`` (N,) int labels (-1 none), ``sel`` (n + 1,) bool, ``sel[l + 1]`` for region ``l``.
    Returns ``(idx, starts)``: ``idx`` the flat indices of the pixels whose region is selected,
    by region and ascending within one (what ``idx[np.argsort(lab[idx], kind="stable")]`` of
    ``idx = np.flatnonzero(sel[lab + 1])`` gives), and ``starts`` (n + 2,) int64 with region
    ``l``'s pixels at ``idx[starts[l + 1]:starts[l + 2]]``.  Two passes over the image instead
    of a sort.
    """
    m = sel.shape[0]
    counts = np.zeros(m, np.int64)
    for i in range(lab.shape[0]):
        k = lab[i] + 1
        if sel[k]:
            counts[k] += 1
    starts = np.zeros(m + 1, np.int64)
    for k in range(m):
        starts[k + 1] = starts[k] + counts[k]
    pos = starts[:m].copy()
    idx = np.empty(starts[m], np.int64)
    for i in range(lab.shape[0]):
        k = lab[i] + 1
        if sel[k]:
            idx[pos[k]] = i
            pos[k] += 1
    return idx, starts


@njit(cache=True, nogil=True, error_model="numpy")
def residual_stats_grid(X, L, pn, po, n, noise, q, depth_unit, organized):  # pragma: no cover
    """Per region: RMS residual, RMS expected by the noise model, high-frequency noise.

    ``X`` (h, w, 3) points and ``L`` (h, w) int32 labels (-1 none) of a grid sample, ``pn``
    (n, 3) / ``po`` (n,) the regions' planes; depth variance ``(noise z^2)^2 + (q z^2)^2 / 12
    + depth_unit^2 / 12`` (see :meth:`planerel.segment.split.SplitParams.depth_sigma2`).  The
    noise is ``sqrt(mean(dd^2) / 6)`` over the second differences ``dd`` of the residual along
    rows and columns within one region (``organized`` only; NaN without any).  Sums run in
    row-major order, as numpy's ``bincount`` of the former implementation did.
    Returns (rms, exp_rms, local), each (n,).
    """
    h = L.shape[0]
    w = L.shape[1]
    cnt = np.zeros(n)
    s_d = np.zeros(n)
    s_e = np.zeros(n)
    D = np.zeros((h, w))
    for v in range(h):
        for u in range(w):
            lab = L[v, u]
            if lab < 0:
                continue
            x = X[v, u, 0]
            y = X[v, u, 1]
            z = X[v, u, 2]
            dn = x * pn[lab, 0] + y * pn[lab, 1] + z * pn[lab, 2]
            d = dn + po[lab]
            D[v, u] = d
            z2 = z * z
            a = noise * z2
            b = q * z2
            sig = np.sqrt(a * a + b * b / 12.0 + depth_unit * depth_unit / 12.0) * (abs(dn) / z)
            cnt[lab] += 1.0
            s_d[lab] += d * d
            s_e[lab] += sig * sig
    rms = np.empty(n)
    exp_rms = np.empty(n)
    for i in range(n):
        c = max(cnt[i], 1.0)
        rms[i] = np.sqrt(s_d[i] / c)
        exp_rms[i] = np.sqrt(s_e[i] / c)
    local = np.full(n, np.nan)
    if organized:
        ssum = np.zeros(n)
        scnt = np.zeros(n)
        csum = np.zeros(n)
        # row and column sums apart, added at the end (the former implementation's order)
        for v in range(h):
            for u in range(1, w - 1):
                lb = L[v, u]
                if lb >= 0 and L[v, u - 1] == lb and L[v, u + 1] == lb:
                    dd = D[v, u - 1] - 2.0 * D[v, u] + D[v, u + 1]
                    ssum[lb] += dd * dd
                    scnt[lb] += 1.0
        for v in range(1, h - 1):
            for u in range(w):
                lb = L[v, u]
                if lb >= 0 and L[v - 1, u] == lb and L[v + 1, u] == lb:
                    dd = D[v - 1, u] - 2.0 * D[v, u] + D[v + 1, u]
                    csum[lb] += dd * dd
                    scnt[lb] += 1.0
        for i in range(n):
            local[i] = np.sqrt((ssum[i] + csum[i]) / scnt[i] / 6.0)
    return rms, exp_rms, local


@njit(cache=True, nogil=True, error_model="numpy")
def _fit_selected(P, sel, m):  # pragma: no cover - compiled
    """:func:`planerel.segment._post_kernels.plane_fit` of the ``m`` rows of ``P`` (M, 3) with
    ``sel`` (M,) true, in row order: (unit normal (3,), offset)."""
    cx = cy = cz = 0.0
    for i in range(P.shape[0]):
        if sel[i]:
            cx += P[i, 0]
            cy += P[i, 1]
            cz += P[i, 2]
    cx /= m
    cy /= m
    cz /= m
    sxx = sxy = sxz = syy = syz = szz = 0.0
    for i in range(P.shape[0]):
        if sel[i]:
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


@njit(cache=True, nogil=True, error_model="numpy")
def inliers_fit(P, dn, zs, off, sigmas):  # pragma: no cover - compiled
    """One least-squares refinement of a part's plane: the inliers of the plane with products
    ``dn`` (m,) = ``P @ normal`` and ``off`` (normalised distance ``|dn + off| * zs /
    max(|dn|, 1e-12)`` <= ``sigmas``), and the plane fitted to them.
    Returns (inlier mask (m,) bool, inlier count, normal (3,), offset); the plane is zeros when
    fewer than 3 points are inliers."""
    m = P.shape[0]
    inl = np.empty(m, dtype=np.bool_)
    cnt = 0
    for i in range(m):
        d = dn[i]
        ok = abs(d + off) * zs[i] / max(abs(d), 1e-12) <= sigmas
        inl[i] = ok
        if ok:
            cnt += 1
    if cnt < 3:
        return inl, cnt, np.zeros(3), 0.0
    n, o = _fit_selected(P, inl, cnt)
    return inl, cnt, n, o


@njit(cache=True, nogil=True, error_model="numpy")
def assign_refit(P, DN, zs, offs, assign_sigmas, cut):  # pragma: no cover - compiled
    """One assign / refit round of the sample: each point ``P`` (m, 3) goes to the part of
    smallest normalised distance (the first of equal ones; ``DN`` (k, m) the products ``P @
    normal_j``, ``offs`` (k,)), -1 beyond ``assign_sigmas`` when ``cut``; then each part with
    at least 3 points is refitted.  Returns (part (m,) int64, planes (k, 4) normal and offset,
    refitted (k,) bool)."""
    m = P.shape[0]
    k = DN.shape[0]
    part = np.empty(m, dtype=np.int64)
    cnt = np.zeros(k, dtype=np.int64)
    for i in range(m):
        bj = 0
        best = 0.0
        for j in range(k):
            d = DN[j, i]
            c = abs(d + offs[j]) * zs[i] / max(abs(d), 1e-12)
            if j == 0 or c < best:
                best = c
                bj = j
        if cut and best > assign_sigmas:
            bj = -1
        else:
            cnt[bj] += 1
        part[i] = bj
    planes = np.zeros((k, 4))
    done = np.zeros(k, dtype=np.bool_)
    if not cut:
        return part, planes, done
    # every part's plane_fit at once: the same sums per part in the same (row) order
    c = np.zeros((k, 3))
    for i in range(m):
        j = part[i]
        if j >= 0:
            c[j, 0] += P[i, 0]
            c[j, 1] += P[i, 1]
            c[j, 2] += P[i, 2]
    for j in range(k):
        if cnt[j] >= 3:
            c[j, 0] /= cnt[j]
            c[j, 1] /= cnt[j]
            c[j, 2] /= cnt[j]
    sc = np.zeros((k, 6))
    for i in range(m):
        j = part[i]
        if j >= 0:
            x = P[i, 0] - c[j, 0]
            y = P[i, 1] - c[j, 1]
            z = P[i, 2] - c[j, 2]
            sc[j, 0] += x * x
            sc[j, 1] += x * y
            sc[j, 2] += x * z
            sc[j, 3] += y * y
            sc[j, 4] += y * z
            sc[j, 5] += z * z
    cov = np.empty((3, 3))
    for j in range(k):
        if cnt[j] < 3:
            continue
        cov[0, 0] = sc[j, 0]
        cov[0, 1] = cov[1, 0] = sc[j, 1]
        cov[0, 2] = cov[2, 0] = sc[j, 2]
        cov[1, 1] = sc[j, 3]
        cov[1, 2] = cov[2, 1] = sc[j, 4]
        cov[2, 2] = sc[j, 5]
        _, vec = np.linalg.eigh(cov)
        planes[j, 0] = vec[0, 0]
        planes[j, 1] = vec[1, 0]
        planes[j, 2] = vec[2, 0]
        planes[j, 3] = -(vec[0, 0] * c[j, 0] + vec[1, 0] * c[j, 1] + vec[2, 0] * c[j, 2])
        done[j] = True
    return part, planes, done


@njit(cache=True, nogil=True)
def sample_normals(N, pix, step):  # pragma: no cover - compiled
    """The normals ``N[pix[::step]]`` as float64 (m, 3) (``N`` (H*W, 3) flat normals, any
    float type) and per row whether all three are finite (m,) bool."""
    m = (pix.shape[0] + step - 1) // step
    out = np.empty((m, 3))
    fin = np.empty(m, dtype=np.bool_)
    for t in range(m):
        q = pix[t * step]
        a = np.float64(N[q, 0])
        b = np.float64(N[q, 1])
        c = np.float64(N[q, 2])
        out[t, 0] = a
        out[t, 1] = b
        out[t, 2] = c
        fin[t] = np.isfinite(a) and np.isfinite(b) and np.isfinite(c)
    return out, fin


@njit(cache=True, nogil=True, error_model="numpy")
def part_centroids(P, part, k):  # pragma: no cover - compiled
    """Mean of the points ``P`` (m, 3) of each part ``0 .. k-1`` of ``part`` (m,), summed in
    row order (numpy's ``P[part == j].mean(axis=0)``), and the count (k,)."""
    s = np.zeros((k, 3))
    c = np.zeros(k, dtype=np.int64)
    for i in range(P.shape[0]):
        j = part[i]
        if j >= 0:
            s[j, 0] += P[i, 0]
            s[j, 1] += P[i, 1]
            s[j, 2] += P[i, 2]
            c[j] += 1
    for j in range(k):
        if c[j] > 0:
            s[j, 0] /= c[j]
            s[j, 1] /= c[j]
            s[j, 2] /= c[j]
    return s, c
