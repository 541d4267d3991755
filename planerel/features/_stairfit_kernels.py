"""numba kernel of :mod:`planerel.features.stairfit` (compiled at first call, cached on disk).

Import this module only from inside functions: numba itself is a heavy import.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def _point_distance2(d, h, r, t, h0, d0, m11, m12, m22, c1, c2):
    """Squared distance of one point to the staircase polyline in its metric
    ``[[m11, m12], [m12, m22]]`` (:func:`planerel.features.stairfit.profile_distance` of one
    point, squared, without the face).  ``c1 = m12 / m11``, ``c2 = m12 / m22``: the nearest
    point of a horizontal tread is at ``ex + c1 ey`` along it, of a vertical riser at
    ``ey + c2 ex`` (both clipped to the face)."""
    u = (d - d0) / t
    v = (h - h0) / r
    k0 = math.floor((u + v) / 2.0)
    best = math.inf
    for dk in range(-1, 3):
        k = k0 + dk
        a = d0 + k * t
        top = h0 + k * r
        ex = d - a
        # tread k: from (a, top) to (a + t, top)
        ey = h - top
        s = min(max(ex + c1 * ey, 0.0), t)
        wx = ex - s
        e = wx * wx * m11 + 2.0 * wx * ey * m12 + ey * ey * m22
        if e < best:
            best = e
        # riser k: from (a, top - r) to (a, top)
        ey = h - (top - r)
        s = min(max(ey + c2 * ex, 0.0), r)
        wy = ey - s
        e = ex * ex * m11 + 2.0 * ex * wy * m12 + wy * wy * m22
        if e < best:
            best = e
    return best


@njit(cache=True, nogil=True)
def profile_costs(d, h, metric, trunc2, rises, factors, nphase, slope, run_lo, run_hi):
    """Mean truncated squared distance of the points to each profile of the grid.

    Parameters
    ----------
    d, h : ndarray (N,) float64
        The points (along the flight, height), metres.
    metric : ndarray (N, 3) float64
        Each point's metric ``(m11, m12, m22)`` (the inverse of its noise covariance in
        ``(d, h)``; ``(1, 0, 1)``: metres).
    trunc2 : ndarray (N,) float64
        Each point's truncation of the squared distance (in its metric).
    rises, factors : ndarray float64
        The grid's rises and slope factors (slope ``slope * factor``, run ``rise / slope``).
    nphase : int
        Phases of the tread levels: ``h0 = (j / nphase) rise``.
    run_lo, run_hi : float
        Profiles with a run outside this range get an infinite cost.

    Returns
    -------
    ndarray (len(rises), len(factors), nphase) float64
        The costs; the profile's midline (half a rise below the nosings) passes through the
        points' centroid.
    """
    n = d.shape[0]
    md = 0.0
    mh = 0.0
    for i in range(n):
        md += d[i]
        mh += h[i]
    md /= n
    mh /= n
    out = np.full((rises.shape[0], factors.shape[0], nphase), np.inf)
    c1 = metric[:, 1] / metric[:, 0]
    c2 = metric[:, 1] / metric[:, 2]
    for a in range(rises.shape[0]):
        r = rises[a]
        for b in range(factors.shape[0]):
            s = slope * factors[b]
            t = r / s
            if t < run_lo or t > run_hi:
                continue
            c = mh - s * md
            for j in range(nphase):
                h0 = (j / nphase) * r
                d0 = (h0 - r / 2.0 - c) / s
                acc = 0.0
                for i in range(n):
                    e = _point_distance2(d[i], h[i], r, t, h0, d0, metric[i, 0],
                                         metric[i, 1], metric[i, 2], c1[i], c2[i])
                    if e > trunc2[i]:
                        e = trunc2[i]
                    acc += e
                out[a, b, j] = acc / n
    return out
