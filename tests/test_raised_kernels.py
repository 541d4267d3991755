"""planerel.features._raised_kernels against the kernel it replaced (main 8c18deb: the column
sums column by column, the row sums one row at a time): the same masks and heights, bit for
bit."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from planerel.features._raised_kernels import raised_pixels


@njit(cache=False, nogil=True)
def _raised_pixels_old(xyz, lab, label, r0, c0, H, W, f, n, d0, a, min_rise, k_sigma, r):
    """Raised and weakly raised pixels of one support plane, and each pixel's height above it,
    on the grid of every ``f``-th pixel of the box ``(r0, c0, r0 + H f, c0 + W f)``.

    Parameters
    ----------
    xyz : ndarray (rows, cols, 3) float64
        Organized points.
    lab : ndarray (rows, cols) int
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
    for i in range(H):
        for j in range(W):
            y = r0 + i * f
            x = c0 + j * f
            if lab[y, x] == label and math.isfinite(xyz[y, x, 2]):
                on[i, j] = True
                h[i, j] = xyz[y, x, 0] * n[0] + xyz[y, x, 1] * n[1] + xyz[y, x, 2] * n[2] - d0
    # window sums of h and of the plane's pixels: along rows, then along columns
    rs = np.zeros((H, W), np.float32)
    rc = np.zeros((H, W), np.int32)
    for i in range(H):
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
    raw = np.zeros((H, W), np.bool_)
    weak = np.zeros((H, W), np.bool_)
    for j in range(W):
        s = 0.0
        c = 0
        for i in range(min(r, H)):
            s += rs[i, j]
            c += rc[i, j]
        for i in range(H):
            if i + r < H:
                s += rs[i + r, j]
                c += rc[i + r, j]
            if i - r - 1 >= 0:
                s -= rs[i - r - 1, j]
                c -= rc[i - r - 1, j]
            if not on[i, j] or c <= 0:
                continue
            mean = s / c
            if mean <= 0.5 * min_rise:
                continue
            z = max(abs(xyz[r0 + i * f, c0 + j * f, 2]), 0.1)
            lim = max(min_rise, k_sigma * a * z * z / math.sqrt(c))
            raw[i, j] = mean > lim
            weak[i, j] = mean > 0.5 * lim
    return on, raw, weak, h


def test_raised_pixels_match_the_column_by_column_kernel():
    rng = np.random.default_rng(8)
    raised = 0
    for _ in range(60):
        rows, cols = (int(v) for v in rng.integers(4, 60, 2))
        lab = rng.integers(-1, 3, (rows, cols)).astype(np.int32)
        lab[rng.random((rows, cols)) < 0.6] = 1
        xyz = np.stack(np.meshgrid(np.linspace(-1, 1, cols), np.linspace(-1, 1, rows)), -1)
        z = np.full((rows, cols, 1), 2.0)
        xyz = np.concatenate([xyz, z], -1) + rng.normal(size=(rows, cols, 3)) * 0.002
        bump = rng.random((rows, cols)) < 0.2
        xyz[bump, 1] += rng.uniform(0.005, 0.05)
        xyz[rng.random((rows, cols)) < 0.05] = np.nan
        f = int(rng.integers(1, 3))
        r0, c0 = int(rng.integers(0, 3)), int(rng.integers(0, 3))
        H, W = -(-(rows - r0) // f), -(-(cols - c0) // f)
        n = np.array([0.0, 1.0, 0.0])
        args = (xyz, lab, 1, r0, c0, H, W, f, n, 0.0, float(rng.uniform(0, 0.01)), 0.01, 2.5,
                int(rng.integers(1, 6)))
        got = raised_pixels(*args)
        want = _raised_pixels_old(*args)
        for g, w in zip(got, want, strict=True):
            assert g.dtype == w.dtype and np.array_equal(g, w)
        raised += int(want[1].sum())
    assert raised > 50


def test_raised_pixels_match_on_every_row_count_and_window():
    # the rows are read and summed four at a time, then one at a time, the column pass follows
    # them (a window of 0 too): grids of 1..11 rows (every
    # remainder, fewer rows than a block), windows wider than the grid, narrow grids
    rng = np.random.default_rng(22)
    raised, seen = 0, set()
    for H in range(1, 12):
        for W in (1, 2, 5, 17):
            for r in (0, 1, 2, 4, 7, 12):
                lab = np.where(rng.random((H, W)) < 0.8, 1, 2).astype(np.int32)
                xyz = np.stack(np.meshgrid(np.linspace(-1, 1, W), np.linspace(-1, 1, H)), -1)
                xyz = np.concatenate([xyz, np.full((H, W, 1), 1.5)], -1)
                xyz[..., 1] += rng.normal(size=(H, W)) * 0.002
                xyz[rng.random((H, W)) < 0.3, 1] += 0.03
                xyz[rng.random((H, W)) < 0.05] = np.nan
                n = np.array([0.0, 1.0, 0.0])
                args = (xyz, lab, 1, 0, 0, H, W, 1, n, 0.0, 0.001, 0.01, 2.5, r)
                got = raised_pixels(*args)
                want = _raised_pixels_old(*args)
                for g, w in zip(got, want, strict=True):
                    assert g.shape == (H, W) and g.dtype == w.dtype and np.array_equal(g, w)
                raised += int(want[1].sum())
                seen.add(H % 4)
    assert seen == {0, 1, 2, 3} and raised > 50
