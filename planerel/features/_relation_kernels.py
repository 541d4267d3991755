"""numba kernels of :mod:`planerel.features.relations` (compiled at first call, cached on disk).

Import this module only from inside functions: numba itself is a heavy import.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def edge_sums(lab, xyz, r0, c0, used, band, depth, n):
    """Sums of :func:`planerel.features.relations.edge_means` in one pass.

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
        lim = depth * max(1.0, abs(xyz[y0, x0, 2]))
        lim2 = lim * lim
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
                if b < 0 or b == a or b >= n or not used[b]:
                    continue
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


@njit(cache=True, nogil=True)
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
