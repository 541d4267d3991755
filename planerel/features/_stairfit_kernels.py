"""numba kernel of :mod:`planerel.features.stairfit` (compiled at first call, cached on disk).

Import this module only from inside functions: numba itself is a heavy import.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def _point_distance2(d, h, r, t, h0, d0):
    """Squared distance of one point to the staircase polyline (:func:`profile_distance` of one
    point, squared, without the face)."""
    u = (d - d0) / t
    v = (h - h0) / r
    k0 = math.floor((u + v) / 2.0)
    best = math.inf
    for dk in range(-1, 3):
        k = k0 + dk
        a = d0 + k * t
        # tread k
        dd = min(max(d, a), a + t)
        x = d - dd
        y = h - (h0 + k * r)
        e = x * x + y * y
        if e < best:
            best = e
        # riser k
        top = h0 + k * r
        hh = min(max(h, top - r), top)
        x = d - a
        y = h - hh
        e = x * x + y * y
        if e < best:
            best = e
    return best


@njit(cache=True, nogil=True)
def profile_costs(d, h, tol, rises, factors, nphase, slope, run_lo, run_hi):
    """Mean truncated squared distance of the points to each profile of the grid.

    Parameters
    ----------
    d, h, tol : ndarray (N,) float64
        The points (along the flight, height) and each one's truncation, metres.
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
    tol2 = tol * tol
    out = np.full((rises.shape[0], factors.shape[0], nphase), np.inf)
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
                    e = _point_distance2(d[i], h[i], r, t, h0, d0)
                    if e > tol2[i]:
                        e = tol2[i]
                    acc += e
                out[a, b, j] = acc / n
    return out
