"""numba kernel of :mod:`planerel.features.raised` (compiled at first call, cached on disk).

Import this module only from inside functions: numba itself is a heavy import.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
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
    on = np.zeros((H, W), np.bool_)
    h = np.zeros((H, W), np.float32)
    # the grid read through flat views by unsigned offsets (C-contiguous inputs)
    L = lab.ravel()
    X = xyz.ravel()
    cols = lab.shape[1]
    n0, n1, n2 = n[0], n[1], n[2]
    for i in range(H):
        base = (r0 + i * f) * cols + c0
        for j in range(W):
            q = np.uint64(base + j * f)
            if L[q] == label and math.isfinite(X[3 * q + 2]):
                on[i, j] = True
                h[i, j] = X[3 * q] * n0 + X[3 * q + 1] * n1 + X[3 * q + 2] * n2 - d0
    # window sums of h and of the plane's pixels: along rows, then along columns. Along rows
    # four rows at a time, each with its own running sum (four independent chains of adds
    # instead of one; each row's sum takes the same values in the same order: the same floats)
    rs = np.zeros((H, W), np.float32)
    rc = np.zeros((H, W), np.int32)
    i = 0
    while i + 4 <= H:
        s0 = 0.0
        s1 = 0.0
        s2 = 0.0
        s3 = 0.0
        k0 = 0
        k1 = 0
        k2 = 0
        k3 = 0
        for j in range(min(r, W)):
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
                s0 += h[i, j + r]
                s1 += h[i + 1, j + r]
                s2 += h[i + 2, j + r]
                s3 += h[i + 3, j + r]
                k0 += on[i, j + r]
                k1 += on[i + 1, j + r]
                k2 += on[i + 2, j + r]
                k3 += on[i + 3, j + r]
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
        i += 4
    while i < H:
        s = 0.0
        c = 0
        for j in range(min(r, W)):
            s += h[i, j]
            c += on[i, j]
        for j in range(W):
            if j + r < W:
                s += h[i, j + r]
                c += on[i, j + r]
            if j - r - 1 >= 0:
                s -= h[i, j - r - 1]
                c -= on[i, j - r - 1]
            rs[i, j] = s
            rc[i, j] = c
        i += 1
    raw = np.zeros((H, W), np.bool_)
    weak = np.zeros((H, W), np.bool_)
    # the columns' running sums kept side by side, row by row (each column's sum takes the
    # same values in the same order as a column-by-column pass: the same floats)
    cs = np.zeros(W)
    cc = np.zeros(W, np.int64)
    for i in range(min(r, H)):
        for j in range(W):
            cs[j] += rs[i, j]
            cc[j] += rc[i, j]
    for i in range(H):
        for j in range(W):
            if i + r < H:
                cs[j] += rs[i + r, j]
                cc[j] += rc[i + r, j]
            if i - r - 1 >= 0:
                cs[j] -= rs[i - r - 1, j]
                cc[j] -= rc[i - r - 1, j]
        for j in range(W):
            c = cc[j]
            if not on[i, j] or c <= 0:
                continue
            mean = cs[j] / c
            if mean <= 0.5 * min_rise:
                continue
            z = max(abs(xyz[r0 + i * f, c0 + j * f, 2]), 0.1)
            lim = max(min_rise, k_sigma * a * z * z / math.sqrt(c))
            raw[i, j] = mean > lim
            weak[i, j] = mean > 0.5 * lim
    return on, raw, weak, h


@njit(cache=True, nogil=True)
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
