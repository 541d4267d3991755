"""numba kernel of :mod:`planerel.features.raised` (compiled at first call, cached on disk).

Import this module only from inside functions: numba itself is a heavy import.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from planerel.features._relation_kernels import median


@njit(cache=True, nogil=True, inline="always", error_model="numpy")
def _on_plane(L, X, q, label, n0, n1, n2, d0):
    """``(on, height)`` of flat pixel ``q``: whether it is the plane's (its label, a finite
    depth) and its height over the plane ``n . x - d0`` rounded to float32 as ``h`` stores it
    (0 when it is not the plane's).  Inlined: the four rows' reads stay in registers.  The
    point's offsets unsigned (``3 * q`` with a signed 3 is int64, and numba wraps every
    signed index around: two more instructions a read)."""
    p = np.uint64(3) * q
    if L[q] == label and math.isfinite(X[p + np.uint64(2)]):
        return True, np.float32(X[p] * n0 + X[p + np.uint64(1)] * n1 + X[p + np.uint64(2)] * n2
                                - d0)
    return False, np.float32(0.0)


@njit(cache=True, nogil=True, error_model="numpy")
def raised_pixels(xyz, lab, label, r0, c0, H, W, f, n, d0, a, min_rise, k_sigma, r):
    """Raised and weakly raised pixels of one support plane, and each pixel's height above it,
    on the grid of every ``f``-th pixel of the box ``(r0, c0, r0 + H f, c0 + W f)``.

    Parameters
    ----------
    xyz : ndarray (rows, cols, 3) float64, C-contiguous
        Organized points.
    lab : ndarray (rows, cols) int, C-contiguous
        Plane labels; the plane's pixels are those of ``label`` with a finite depth.
    r0, c0, H, W, f : int
        The grid: pixel ``(i, j)`` of the outputs is ``(r0 + i f, c0 + j f)``.
    n : ndarray (3,) float64
        The plane's unit normal, turned up; ``d0``: ``n . centroid``.
    a : float
        Noise scale of the height: ``a z^2`` per pixel.
    min_rise, k_sigma : float
        A pixel is raised when the mean height over its ``(2r+1)^2`` window of the grid (the
        plane's pixels only) exceeds ``max(min_rise, k_sigma a z^2 / sqrt(count))``, weakly
        raised when it exceeds half of that.
    r : int

    Returns
    -------
    (on (H, W) bool, raw (H, W) bool, weak (H, W) bool, h (H, W) float32)
    """
    on, h, rs, rc, _ = _raised_rows(xyz, lab, label, r0, c0, H, W, f, n, d0, r, 0)
    raw, weak = _raised_tests(xyz, r0, c0, f, on, rs, rc, a, min_rise, k_sigma, r)
    return on, raw, weak, h


@njit(cache=True, nogil=True, error_model="numpy")
def raised_noise_pixels(xyz, lab, label, r0, c0, H, W, f, n, d0, min_rise, k_sigma, r, step):
    """:func:`raised_pixels` with its noise scale ``a`` measured in the same pass over the
    grid: ``1.4826`` times the median of :func:`noise_values` on every ``step``-th pixel of
    every ``step``-th row of the grid (:func:`planerel.features.raised._raised_on`'s, which
    read them in a pass of their own before; the same values, so the same median and the
    same masks: ``tests/test_shared_work.py`` compares), 0 when there is none.

    The tests' column sums are taken in the pass over the grid, a few rows behind it (the row
    sums kept for the ``2r + 6`` rows they need, not for the whole grid; each column's sum
    takes the same values in the same order as :func:`_raised_tests`' pass: the same floats),
    and the windows the product test cannot reject are kept with their sums; only those are
    divided out and tested against the limits, once the noise scale is known
    (``tests/test_fewer_passes.py`` compares with :func:`raised_pixels`)."""
    on, h, vals, co, cj, csum, ccnt, m = _raised_rows_flagged(xyz, lab, label, r0, c0, H, W, f,
                                                              n, d0, r, step, min_rise)
    a = 1.4826 * median(vals) if vals.shape[0] else 0.0
    raw = np.zeros((H, W), np.bool_)
    weak = np.zeros((H, W), np.bool_)
    for t in range(m):
        o, j, c = co[t], cj[t], ccnt[t]
        mean = csum[t] / c
        if mean <= 0.5 * min_rise:
            continue
        z = max(abs(xyz[r0 + o * f, c0 + j * f, 2]), 0.1)
        lim = max(min_rise, k_sigma * a * z * z / math.sqrt(c))
        raw[o, j] = mean > lim
        weak[o, j] = mean > 0.5 * lim
    return on, raw, weak, h


@njit(cache=True, nogil=True, error_model="numpy")
def _raised_rows_flagged(xyz, lab, label, r0, c0, H, W, f, n, d0, r, step, min_rise):
    """:func:`_raised_rows` with :func:`_raised_tests`' column sums and product test taken a
    few rows behind it (:func:`raised_noise_pixels`): ``(on, h, vals, rows, cols, sums,
    counts, m)``, the first ``m`` entries of the four lists the windows not rejected by the
    product test.  The row sums live in ``R = 2r + 6`` rows (row ``k`` at ``k % R``): a row
    is read last for column row ``k + r + 1``, at most ``r + 4`` rows after the block that
    wrote it, before ``R`` more rows are written."""
    on = np.empty((H, W), np.bool_)
    h = np.empty((H, W), np.float32)
    L = lab.ravel()
    X = xyz.ravel()
    cols = lab.shape[1]
    n0, n1, n2 = n[0], n[1], n[2]
    R = 2 * r + 6
    rs = np.empty((R, W), np.float32)
    rc = np.empty((R, W), np.int32)
    nv = -(-H // step) * -(-W // step) if step > 0 else 0
    vals = np.empty(nv)
    k = 0
    # the windows kept (a few in a thousand; the lists grown when a row could overfill them:
    # lists the size of the grid, allocated and freed each call, cost more than the pass saves)
    cap = 8 * W + 64
    co = np.empty(cap, np.int32)
    cj = np.empty(cap, np.int32)
    csum = np.empty(cap)
    ccnt = np.empty(cap, np.int64)
    m = 0
    cs = np.zeros(W)
    # the windows' pixel counts as floats (whole numbers, exact): the product test's
    # half * cc * shrink without a conversion of int64 (AVX2 has none for a vector of them)
    cc = np.zeros(W)
    flag = np.zeros(W, np.uint8)
    half = 0.5 * min_rise
    shrink = 1.0 - 1e-12
    started = False  # the column sums' first r rows added
    o = 0  # the next row of column sums
    rr = min(r, W)
    i = 0
    while i < H:
        m4 = 4 if i + 4 <= H else 1
        for t in range(m4):
            base = (r0 + (i + t) * f) * cols + c0
            for j in range(rr):
                on[i + t, j], h[i + t, j] = _on_plane(L, X, np.uint64(base + j * f), label,
                                                      n0, n1, n2, d0)
        if m4 == 4:
            s0 = 0.0
            s1 = 0.0
            s2 = 0.0
            s3 = 0.0
            k0 = 0
            k1 = 0
            k2 = 0
            k3 = 0
            for j in range(rr):
                s0 += h[i, j]
                s1 += h[i + 1, j]
                s2 += h[i + 2, j]
                s3 += h[i + 3, j]
                k0 += on[i, j]
                k1 += on[i + 1, j]
                k2 += on[i + 2, j]
                k3 += on[i + 3, j]
            g0 = i % R
            g1 = (i + 1) % R
            g2 = (i + 2) % R
            g3 = (i + 3) % R
            # the four rows' first flat indices (each row's pixel jr at + jr f)
            b0 = (r0 + i * f) * cols + c0
            b1 = b0 + f * cols
            b2 = b1 + f * cols
            b3 = b2 + f * cols
            # (the columns as unsigned indices: no wraparound of each read and write)
            for j in range(W):
                ju = np.uint64(j)
                if j + r < W:
                    jr = np.uint64(j + r)
                    # each pixel's flag and height kept in locals for the row sums (the
                    # height rounded to float32 as its store rounds it: the same values
                    # summed in the same order as read back from h)
                    o0, v0 = _on_plane(L, X, np.uint64(b0 + (j + r) * f), label, n0, n1, n2, d0)
                    o1, v1 = _on_plane(L, X, np.uint64(b1 + (j + r) * f), label, n0, n1, n2, d0)
                    o2, v2 = _on_plane(L, X, np.uint64(b2 + (j + r) * f), label, n0, n1, n2, d0)
                    o3, v3 = _on_plane(L, X, np.uint64(b3 + (j + r) * f), label, n0, n1, n2, d0)
                    on[i, jr] = o0
                    on[i + 1, jr] = o1
                    on[i + 2, jr] = o2
                    on[i + 3, jr] = o3
                    h[i, jr] = v0
                    h[i + 1, jr] = v1
                    h[i + 2, jr] = v2
                    h[i + 3, jr] = v3
                    s0 += v0
                    s1 += v1
                    s2 += v2
                    s3 += v3
                    k0 += o0
                    k1 += o1
                    k2 += o2
                    k3 += o3
                if j - r - 1 >= 0:
                    jl = np.uint64(j - r - 1)
                    s0 -= h[i, jl]
                    s1 -= h[i + 1, jl]
                    s2 -= h[i + 2, jl]
                    s3 -= h[i + 3, jl]
                    k0 -= on[i, jl]
                    k1 -= on[i + 1, jl]
                    k2 -= on[i + 2, jl]
                    k3 -= on[i + 3, jl]
                rs[g0, ju] = s0
                rs[g1, ju] = s1
                rs[g2, ju] = s2
                rs[g3, ju] = s3
                rc[g0, ju] = k0
                rc[g1, ju] = k1
                rc[g2, ju] = k2
                rc[g3, ju] = k3
        else:
            s = 0.0
            c = 0
            for j in range(rr):
                s += h[i, j]
                c += on[i, j]
            g = i % R
            base = (r0 + i * f) * cols + c0
            for j in range(W):
                if j + r < W:
                    jr = j + r
                    on[i, jr], h[i, jr] = _on_plane(L, X, np.uint64(base + jr * f), label,
                                                    n0, n1, n2, d0)
                    s += h[i, jr]
                    c += on[i, jr]
                if j - r - 1 >= 0:
                    s -= h[i, j - r - 1]
                    c -= on[i, j - r - 1]
                rs[g, j] = s
                rc[g, j] = c
        if step > 0:
            for t in range(m4):
                if (i + t) % step:
                    continue
                y = r0 + (i + t) * f
                for j in range(0, W, step):
                    if on[i + t, j]:
                        x = c0 + j * f
                        z = xyz[y, x, 2]
                        zs = max(abs(z), 0.1)
                        hh = xyz[y, x, 0] * n0 + xyz[y, x, 1] * n1 + z * n2
                        vals[k] = abs(hh - d0) / (zs * zs)
                        k += 1
        i += m4
        # the column sums of every row whose window's rows are all summed now
        if not started and i >= min(r, H):
            for g in range(min(r, H)):
                for j in range(W):
                    cs[j] += rs[g % R, j]
                    cc[j] += rc[g % R, j]
            started = True
        while started and o < H and i >= min(o + r + 1, H):
            if m + W > co.shape[0]:
                cap = max(2 * co.shape[0], m + W)
                co2 = np.empty(cap, np.int32)
                cj2 = np.empty(cap, np.int32)
                csum2 = np.empty(cap)
                ccnt2 = np.empty(cap, np.int64)
                co2[:m] = co[:m]
                cj2[:m] = cj[:m]
                csum2[:m] = csum[:m]
                ccnt2[:m] = ccnt[:m]
                co, cj, csum, ccnt = co2, cj2, csum2, ccnt2
            # row o of _raised_tests' column sums: the row below added and the row above
            # taken off as there (written out here: a jitted helper taking the arrays was
            # slower), then the windows that pass the plane, count and product tests flagged
            # without a branch (a loop the compiler vectorizes; a few in a thousand pass) and
            # those alone kept
            if o + r < H and o - r - 1 >= 0:
                ga = (o + r) % R
                gb = (o - r - 1) % R
                for j in range(W):
                    cs[j] = (cs[j] + rs[ga, j]) - rs[gb, j]
                    cc[j] = (cc[j] + rc[ga, j]) - rc[gb, j]
            elif o + r < H:
                ga = (o + r) % R
                for j in range(W):
                    cs[j] += rs[ga, j]
                    cc[j] += rc[ga, j]
            elif o - r - 1 >= 0:
                gb = (o - r - 1) % R
                for j in range(W):
                    cs[j] -= rs[gb, j]
                    cc[j] -= rc[gb, j]
            nf = 0
            for j in range(W):
                g = (np.uint8(on[o, j]) & np.uint8(cc[j] > 0)
                     & np.uint8(not (cs[j] <= half * cc[j] * shrink)))
                flag[j] = g
                nf += g
            # (read up to the row's last flagged window only)
            j = 0
            while nf:
                if flag[j]:
                    co[m] = o
                    cj[m] = j
                    csum[m] = cs[j]
                    ccnt[m] = np.int64(cc[j])
                    m += 1
                    nf -= 1
                j += 1
            o += 1
    return on, h, vals[:k], co, cj, csum, ccnt, m


@njit(cache=True, nogil=True, error_model="numpy")
def _raised_rows(xyz, lab, label, r0, c0, H, W, f, n, d0, r, step):
    """:func:`raised_pixels`' pass over the grid: the plane's pixels ``on``, their heights
    ``h``, each row's window sums of the heights ``rs`` and of the plane's pixels ``rc``
    (``2r + 1`` columns), and with ``step > 0`` the noise values (:func:`noise_values`) of
    every ``step``-th pixel of every ``step``-th row, read while the block's rows are in
    the cache."""
    # every grid pixel of on, h, rs and rc is written below (off the plane: False and 0):
    # no zeroing of the four (H, W) arrays first
    on = np.empty((H, W), np.bool_)
    h = np.empty((H, W), np.float32)
    # each block of four rows is read (the plane's pixels and their heights, column j + r
    # just before the row sums need it) and summed along the rows with four running sums
    # (four independent chains of adds; each row's sum takes the same values in the same
    # order as a row-by-row pass: the same floats)
    L = lab.ravel()
    X = xyz.ravel()
    cols = lab.shape[1]
    n0, n1, n2 = n[0], n[1], n[2]
    rs = np.empty((H, W), np.float32)
    rc = np.empty((H, W), np.int32)
    # the noise sample: every step-th pixel of every step-th row of the grid
    nv = -(-H // step) * -(-W // step) if step > 0 else 0
    vals = np.empty(nv)
    k = 0
    rr = min(r, W)
    i = 0
    while i < H:
        m = 4 if i + 4 <= H else 1
        for t in range(m):
            base = (r0 + (i + t) * f) * cols + c0
            for j in range(rr):
                q = np.uint64(base + j * f)
                if L[q] == label and math.isfinite(X[3 * q + 2]):
                    on[i + t, j] = True
                    h[i + t, j] = X[3 * q] * n0 + X[3 * q + 1] * n1 + X[3 * q + 2] * n2 - d0
                else:
                    on[i + t, j] = False
                    h[i + t, j] = 0.0
        if m == 4:
            s0 = 0.0
            s1 = 0.0
            s2 = 0.0
            s3 = 0.0
            k0 = 0
            k1 = 0
            k2 = 0
            k3 = 0
            for j in range(rr):
                s0 += h[i, j]
                s1 += h[i + 1, j]
                s2 += h[i + 2, j]
                s3 += h[i + 3, j]
                k0 += on[i, j]
                k1 += on[i + 1, j]
                k2 += on[i + 2, j]
                k3 += on[i + 3, j]
            for j in range(W):
                if j + r < W:
                    jr = j + r
                    for t in range(4):
                        q = np.uint64((r0 + (i + t) * f) * cols + c0 + jr * f)
                        if L[q] == label and math.isfinite(X[3 * q + 2]):
                            on[i + t, jr] = True
                            h[i + t, jr] = (X[3 * q] * n0 + X[3 * q + 1] * n1
                                            + X[3 * q + 2] * n2 - d0)
                        else:
                            on[i + t, jr] = False
                            h[i + t, jr] = 0.0
                    s0 += h[i, jr]
                    s1 += h[i + 1, jr]
                    s2 += h[i + 2, jr]
                    s3 += h[i + 3, jr]
                    k0 += on[i, jr]
                    k1 += on[i + 1, jr]
                    k2 += on[i + 2, jr]
                    k3 += on[i + 3, jr]
                if j - r - 1 >= 0:
                    s0 -= h[i, j - r - 1]
                    s1 -= h[i + 1, j - r - 1]
                    s2 -= h[i + 2, j - r - 1]
                    s3 -= h[i + 3, j - r - 1]
                    k0 -= on[i, j - r - 1]
                    k1 -= on[i + 1, j - r - 1]
                    k2 -= on[i + 2, j - r - 1]
                    k3 -= on[i + 3, j - r - 1]
                rs[i, j] = s0
                rs[i + 1, j] = s1
                rs[i + 2, j] = s2
                rs[i + 3, j] = s3
                rc[i, j] = k0
                rc[i + 1, j] = k1
                rc[i + 2, j] = k2
                rc[i + 3, j] = k3
        else:
            s = 0.0
            c = 0
            for j in range(rr):
                s += h[i, j]
                c += on[i, j]
            base = (r0 + i * f) * cols + c0
            for j in range(W):
                if j + r < W:
                    jr = j + r
                    q = np.uint64(base + jr * f)
                    if L[q] == label and math.isfinite(X[3 * q + 2]):
                        on[i, jr] = True
                        h[i, jr] = X[3 * q] * n0 + X[3 * q + 1] * n1 + X[3 * q + 2] * n2 - d0
                    else:
                        on[i, jr] = False
                        h[i, jr] = 0.0
                    s += h[i, jr]
                    c += on[i, jr]
                if j - r - 1 >= 0:
                    s -= h[i, j - r - 1]
                    c -= on[i, j - r - 1]
                rs[i, j] = s
                rc[i, j] = c
        if step > 0:
            for t in range(m):
                if (i + t) % step:
                    continue
                y = r0 + (i + t) * f
                for j in range(0, W, step):
                    if on[i + t, j]:
                        x = c0 + j * f
                        z = xyz[y, x, 2]
                        zs = max(abs(z), 0.1)
                        hh = xyz[y, x, 0] * n0 + xyz[y, x, 1] * n1 + z * n2
                        vals[k] = abs(hh - d0) / (zs * zs)
                        k += 1
        i += m
    return on, h, rs, rc, vals[:k]


@njit(cache=True, nogil=True, error_model="numpy")
def _raised_tests(xyz, r0, c0, f, on, rs, rc, a, min_rise, k_sigma, r):
    """:func:`raised_pixels`' tests: the columns' running sums of the row sums kept side by
    side, row by row (each column's sum takes the same values in the same order as a
    column-by-column pass: the same floats), and each plane pixel's window mean against
    the limits."""
    H, W = on.shape
    raw = np.zeros((H, W), np.bool_)
    weak = np.zeros((H, W), np.bool_)
    cs = np.zeros(W)
    cc = np.zeros(W, np.int64)
    # a window whose sum is at most half_rise * count * (1 - 1e-12) has a mean (cs / c, as
    # the test below divides) at most half_rise: rejected by a product before the division
    # (the bound's own two roundings, at most a relative 2.3e-16, stay far inside the
    # 1e-12; a NaN sum fails this test and takes the division as before)
    half = 0.5 * min_rise
    shrink = 1.0 - 1e-12
    # each row's windows that pass the plane, count and product tests, flagged without a
    # branch (a loop the compiler vectorizes; a few in a thousand pass), then those alone
    # divided out and tested against the limits
    flag = np.zeros(W, np.uint8)
    for k in range(min(r, H)):
        for j in range(W):
            cs[j] += rs[k, j]
            cc[j] += rc[k, j]
    for o in range(H):
        if o + r < H and o - r - 1 >= 0:
            # the row below added and the row above taken off in one loop: the same two
            # roundings in the same order
            for j in range(W):
                cs[j] = (cs[j] + rs[o + r, j]) - rs[o - r - 1, j]
                cc[j] = (cc[j] + rc[o + r, j]) - rc[o - r - 1, j]
        elif o + r < H:
            for j in range(W):
                cs[j] += rs[o + r, j]
                cc[j] += rc[o + r, j]
        elif o - r - 1 >= 0:
            for j in range(W):
                cs[j] -= rs[o - r - 1, j]
                cc[j] -= rc[o - r - 1, j]
        n = 0
        for j in range(W):
            g = (np.uint8(on[o, j]) & np.uint8(cc[j] > 0)
                 & np.uint8(not (cs[j] <= half * cc[j] * shrink)))
            flag[j] = g
            n += g
        if n == 0:
            continue
        for j in range(W):
            if not flag[j]:
                continue
            c = cc[j]
            mean = cs[j] / c
            if mean <= 0.5 * min_rise:
                continue
            z = max(abs(xyz[r0 + o * f, c0 + j * f, 2]), 0.1)
            lim = max(min_rise, k_sigma * a * z * z / math.sqrt(c))
            raw[o, j] = mean > lim
            weak[o, j] = mean > 0.5 * lim
    return raw, weak


@njit(cache=True, nogil=True, error_model="numpy")
def noise_values(xyz, lab, label, r0, c0, r1, c1, step, n, d0):
    """``|p . n - d0| / max(|z|, 0.1)^2`` of the points ``p`` of ``label`` with a finite depth
    ``z`` on every ``step``-th row and column of the box ``[r0, r1) x [c0, c1)`` (row-major;
    :func:`planerel.features.raised._raised_on`'s noise scale), the dot products summed in
    the plain order (numpy's BLAS product may round the last bit otherwise:
    ``tests/test_raised.py`` compares within 1e-12)."""
    nr = max(0, (r1 - r0 + step - 1) // step)
    nc = max(0, (c1 - c0 + step - 1) // step)
    out = np.empty(nr * nc)
    m = 0
    for r in range(r0, r1, step):
        for c in range(c0, c1, step):
            if lab[r, c] != label:
                continue
            z = xyz[r, c, 2]
            if not math.isfinite(z):
                continue
            zs = max(abs(z), 0.1)
            h = xyz[r, c, 0] * n[0] + xyz[r, c, 1] * n[1] + z * n[2]
            out[m] = abs(h - d0) / (zs * zs)
            m += 1
    return out[:m]
