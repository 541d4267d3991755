"""numba kernels of the plane-attribute and relation stage (compiled at first call, cached on disk).

Import this module only from inside functions: numba itself is a heavy import.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["label_moments", "label_boundary", "touch_pairs", "mask_pixels"]


@njit(cache=True, nogil=True)
def label_moments(xyz, lab, nlab):  # pragma: no cover - compiled
    """Per label: count, reference point, sums and second moments relative to the reference,
    and the sum of pixel rows.

    xyz (H, W, 3) float64, lab (H, W) int32 (-1 skipped) ->
    counts (nlab,) int64, ref (nlab, 3), s1 (nlab, 3), s2 (nlab, 6) [xx, xy, xz, yy, yz, zz],
    rows (nlab,) float64.
    """
    H, W = lab.shape
    counts = np.zeros(nlab, np.int64)
    ref = np.zeros((nlab, 3))
    s1 = np.zeros((nlab, 3))
    s2 = np.zeros((nlab, 6))
    rows = np.zeros(nlab)
    for v in range(H):
        for u in range(W):
            k = lab[v, u]
            if k < 0:
                continue
            x = xyz[v, u, 0]
            y = xyz[v, u, 1]
            z = xyz[v, u, 2]
            if counts[k] == 0:
                ref[k, 0] = x
                ref[k, 1] = y
                ref[k, 2] = z
            dx = x - ref[k, 0]
            dy = y - ref[k, 1]
            dz = z - ref[k, 2]
            counts[k] += 1
            s1[k, 0] += dx
            s1[k, 1] += dy
            s1[k, 2] += dz
            s2[k, 0] += dx * dx
            s2[k, 1] += dx * dy
            s2[k, 2] += dx * dz
            s2[k, 3] += dy * dy
            s2[k, 4] += dy * dz
            s2[k, 5] += dz * dz
            rows[k] += v
    return counts, ref, s1, s2, rows


@njit(cache=True, nogil=True)
def label_boundary(lab):  # pragma: no cover - compiled
    """(H, W) bool: labelled pixels with a 4-neighbour of another label, or on the image border."""
    H, W = lab.shape
    out = np.zeros((H, W), np.bool_)
    for v in range(H):
        for u in range(W):
            k = lab[v, u]
            if k < 0:
                continue
            if v == 0 or u == 0 or v == H - 1 or u == W - 1:
                out[v, u] = True
            elif lab[v - 1, u] != k or lab[v + 1, u] != k or lab[v, u - 1] != k or lab[v, u + 1] != k:
                out[v, u] = True
    return out


@njit(cache=True, nogil=True)
def touch_pairs(xyz, lab, brow, bcol, g, max_dist, rel_dist, known):  # pragma: no cover - compiled
    """(nlab, nlab) bool, symmetric: labels a != b with pixels within ``g`` pixels (Chebyshev)
    whose 3-D points lie within ``max(max_dist, rel_dist * z)`` metres (z = depth of the first
    pixel).  Only boundary pixels (brow, bcol) are visited; ``known`` (nlab,) bool masks the
    labels that count.  ``xyz`` and ``lab`` C-contiguous: read through flat views by unsigned
    offsets, each window row as a clipped column range (no wraparound or per-pixel column
    tests; the same pixels in the same order)."""
    H, W = lab.shape
    nlab = known.shape[0]
    out = np.zeros((nlab, nlab), np.bool_)
    L = lab.ravel()
    X = xyz.ravel()
    for i in range(brow.shape[0]):
        v = brow[i]
        u = bcol[i]
        p = np.uint64(v * W + u)
        a = L[p]
        if a < 0 or a >= nlab or not known[a]:
            continue
        d2max = -1.0  # the pixel's limit, read at its first candidate neighbour
        for dv in range(0, g + 1):
            v2 = v + dv
            if v2 >= H:
                break
            # the window's columns on this row: after the pixel on its own row
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
    return out


@njit(cache=True, nogil=True)
def mask_pixels(mask):  # pragma: no cover - compiled
    """``np.nonzero(mask)`` of a 2-D bool mask: rows and columns ``(N,)`` int64, row-major.
    A branch-free count a row first (a loop the compiler vectorizes), then only the rows
    that hold a pixel are read again, each up to its last pixel."""
    H, W = mask.shape
    per = np.zeros(H, np.int64)
    n = 0
    for r in range(H):
        s = 0
        for c in range(W):
            s += np.uint8(mask[r, c])
        per[r] = s
        n += s
    rows = np.empty(n, np.int64)
    cols = np.empty(n, np.int64)
    k = 0
    for r in range(H):
        left = per[r]
        c = 0
        while left > 0:
            if mask[r, c]:
                rows[k], cols[k] = r, c
                k += 1
                left -= 1
            c += 1
    return rows, cols
