"""numba kernel of :mod:`planerel.features.raised` (compiled at first call, cached on disk).

Import this module only from inside functions: numba itself is a heavy import.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from planerel.features._relation_kernels import median


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
    same masks: ``tests/test_shared_work.py`` compares), 0 when there is none."""
    on, h, rs, rc, vals = _raised_rows(xyz, lab, label, r0, c0, H, W, f, n, d0, r, step)
    a = 1.4826 * median(vals) if vals.shape[0] else 0.0
    raw, weak = _raised_tests(xyz, r0, c0, f, on, rs, rc, a, min_rise, k_sigma, r)
    return on, raw, weak, h


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
