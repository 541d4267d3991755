"""numba kernel of :mod:`planerel.features.stairfit` (compiled at first call, cached on disk).

Import this module only from inside functions: numba itself is a heavy import.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, inline="always", error_model="numpy")
def _steps_distance2(d, h, k0, r, t, h0, d0, m11, m12, m22, c1, c2):
    """The least squared distance of the point ``(d, h)`` to treads and risers ``k0 - 1`` ...
    ``k0 + 2`` of the staircase polyline in the metric ``[[m11, m12], [m12, m22]]``.
    ``k0`` is an integer or an integer-valued float (the same value either way)."""
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


@njit(cache=True, nogil=True, error_model="numpy")
def _point_distance2(d, h, r, t, h0, d0, m11, m12, m22, c1, c2):
    """Squared distance of one point to the staircase polyline in its metric
    ``[[m11, m12], [m12, m22]]`` (:func:`planerel.features.stairfit.profile_distance` of one
    point, squared, without the face).  ``c1 = m12 / m11``, ``c2 = m12 / m22``: the nearest
    point of a horizontal tread is at ``ex + c1 ey`` along it, of a vertical riser at
    ``ey + c2 ex`` (both clipped to the face)."""
    k0 = math.floor(((d - d0) / t + (h - h0) / r) / 2.0)
    return _steps_distance2(d, h, k0, r, t, h0, d0, m11, m12, m22, c1, c2)


@njit(cache=True, nogil=True, error_model="numpy")
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


@njit(cache=True, inline="always", error_model="numpy")
def _point_distance2_f(d, h, r, t, h0, d0, m11, m12, m22, c1, c2):
    """:func:`_point_distance2` with the tread index a float (``np.floor``, not
    ``math.floor``'s integer): the same value for ``|u + v| < 2**53`` (an integer-valued
    float converts exactly), and a loop over the points of it compiles to vector
    instructions (no float-integer conversions)."""
    k0 = np.floor(((d - d0) / t + (h - h0) / r) / 2.0)
    return _steps_distance2(d, h, k0, r, t, h0, d0, m11, m12, m22, c1, c2)


@njit(cache=True, nogil=True, error_model="numpy")
def profile_costs_vec(d, h, metric, trunc2, rises, factors, nphase, slope, run_lo, run_hi):
    """:func:`profile_costs` (same parameters, the same array bit for bit when every
    ``|d|``, ``|h|`` is below 1e6 m: what :func:`planerel.features.stairfit.fit_profile`
    checks) about 4 times faster: each profile's truncated squared distances first into a
    buffer by a loop the compiler vectorises (:func:`_point_distance2_f`, the metric's
    columns contiguous), then summed in the points' order as before."""
    n = d.shape[0]
    md = 0.0
    mh = 0.0
    for i in range(n):
        md += d[i]
        mh += h[i]
    md /= n
    mh /= n
    out = np.full((rises.shape[0], factors.shape[0], nphase), np.inf)
    m11 = metric[:, 0].copy()
    m12 = metric[:, 1].copy()
    m22 = metric[:, 2].copy()
    c1 = m12 / m11
    c2 = m12 / m22
    e = np.empty(n)
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
                for i in range(n):
                    v = _point_distance2_f(d[i], h[i], r, t, h0, d0, m11[i], m12[i], m22[i],
                                           c1[i], c2[i])
                    e[i] = trunc2[i] if v > trunc2[i] else v
                acc = 0.0
                for i in range(n):
                    acc += e[i]
                out[a, b, j] = acc / n
    return out


@njit(cache=True, nogil=True, error_model="numpy")
def cluster_slopes(pts, ids, n, e1, e2, up, min_det):
    """The slope of every cluster's least-squares plane ``h = a u + b v + c`` (``u, v, h``
    the points' coordinates along ``e1``, ``e2``, ``up``; ``ids`` each point's cluster in
    ``[0, n)``), from its sums centred on the cluster's mean, and whether that slope is
    reliable: at least 3 points and normal equations with ``det >= min_det`` times the
    product of their diagonal (else the slope is 0 and not reliable).

    Returns
    -------
    (ndarray (n,) float64, ndarray (n,) bool)
        ``hypot(a, b)`` and its reliability.
    """
    N = ids.shape[0]
    cnt = np.zeros(n)
    mu = np.zeros(n)
    mv = np.zeros(n)
    mh = np.zeros(n)
    for i in range(N):
        c = ids[i]
        x, y, z = pts[i, 0], pts[i, 1], pts[i, 2]
        cnt[c] += 1.0
        mu[c] += x * e1[0] + y * e1[1] + z * e1[2]
        mv[c] += x * e2[0] + y * e2[1] + z * e2[2]
        mh[c] += x * up[0] + y * up[1] + z * up[2]
    for c in range(n):
        if cnt[c] > 0:
            mu[c] /= cnt[c]
            mv[c] /= cnt[c]
            mh[c] /= cnt[c]
    suu = np.zeros(n)
    suv = np.zeros(n)
    svv = np.zeros(n)
    suh = np.zeros(n)
    svh = np.zeros(n)
    for i in range(N):
        c = ids[i]
        x, y, z = pts[i, 0], pts[i, 1], pts[i, 2]
        du = x * e1[0] + y * e1[1] + z * e1[2] - mu[c]
        dv = x * e2[0] + y * e2[1] + z * e2[2] - mv[c]
        dh = x * up[0] + y * up[1] + z * up[2] - mh[c]
        suu[c] += du * du
        suv[c] += du * dv
        svv[c] += dv * dv
        suh[c] += du * dh
        svh[c] += dv * dh
    g = np.zeros(n)
    sure = np.zeros(n, np.bool_)
    for c in range(n):
        det = suu[c] * svv[c] - suv[c] * suv[c]
        if cnt[c] >= 3 and det > 0 and det > min_det * suu[c] * svv[c]:
            a = (svv[c] * suh[c] - suv[c] * svh[c]) / det
            b = (suu[c] * svh[c] - suv[c] * suh[c]) / det
            g[c] = math.hypot(a, b)
            sure[c] = True
    return g, sure


@njit(cache=True, nogil=True, error_model="numpy")
def cluster_spans_at(xyz, rows, cols, ids, n, e1, e2):
    """:func:`cluster_spans` of the points ``xyz[rows, cols]`` read in place (no gathered
    copy): the same values in the same order, so the same spans."""
    N = ids.shape[0]
    lo_u = np.full(n, np.inf)
    hi_u = np.full(n, -np.inf)
    lo_v = np.full(n, np.inf)
    hi_v = np.full(n, -np.inf)
    bad = np.zeros(n, np.bool_)
    for i in range(N):
        c = ids[i]
        r, q = rows[i], cols[i]
        x, y, z = xyz[r, q, 0], xyz[r, q, 1], xyz[r, q, 2]
        u = x * e1[0] + y * e1[1] + z * e1[2]
        v = x * e2[0] + y * e2[1] + z * e2[2]
        if not (math.isfinite(u) and math.isfinite(v)):
            bad[c] = True
            continue
        lo_u[c] = min(lo_u[c], u)
        hi_u[c] = max(hi_u[c], u)
        lo_v[c] = min(lo_v[c], v)
        hi_v[c] = max(hi_v[c], v)
    out = np.zeros(n)
    for c in range(n):
        if bad[c]:
            out[c] = np.nan
        elif hi_u[c] >= lo_u[c]:
            out[c] = math.hypot(hi_u[c] - lo_u[c], hi_v[c] - lo_v[c])
    return out


@njit(cache=True, nogil=True, error_model="numpy")
def cluster_spans(pts, ids, n, e1, e2):
    """How far each cluster reaches across the horizontal plane at most: ``hypot`` of the
    ranges of its points' coordinates along ``e1`` and ``e2`` (``ids`` each point's cluster in
    ``[0, n)``; 0 for a cluster without points).  Any horizontal unit direction's range of the
    points is at most this (up to rounding): :func:`planerel.features.stairfit` rules out by
    it the clusters that cannot be ``min_width`` wide before their fit.

    Returns
    -------
    ndarray (n,) float64
    """
    N = ids.shape[0]
    lo_u = np.full(n, np.inf)
    hi_u = np.full(n, -np.inf)
    lo_v = np.full(n, np.inf)
    hi_v = np.full(n, -np.inf)
    bad = np.zeros(n, np.bool_)
    for i in range(N):
        c = ids[i]
        x, y, z = pts[i, 0], pts[i, 1], pts[i, 2]
        u = x * e1[0] + y * e1[1] + z * e1[2]
        v = x * e2[0] + y * e2[1] + z * e2[2]
        if not (math.isfinite(u) and math.isfinite(v)):
            bad[c] = True  # a point not finite: the span is NaN (never rules the cluster out)
            continue
        lo_u[c] = min(lo_u[c], u)
        hi_u[c] = max(hi_u[c], u)
        lo_v[c] = min(lo_v[c], v)
        hi_v[c] = max(hi_v[c], v)
    out = np.zeros(n)
    for c in range(n):
        if bad[c]:
            out[c] = np.nan
        elif hi_u[c] >= lo_u[c]:
            out[c] = math.hypot(hi_u[c] - lo_u[c], hi_v[c] - lo_v[c])
    return out


@njit(cache=True, nogil=True, error_model="numpy")
def width_bound(P, e1, e2, up, min_det):
    """:func:`planerel.features.stairfit._surely_narrow`'s figures in three passes over the
    points ``P`` (N, 3) float64 (no temporary arrays): the least-squares plane ``h = a u + b
    v + c`` (``u, v, h`` along ``e1``, ``e2``, ``up``) from its centred normal equations, the
    points' range across its slope direction (along ``up x f``, ``f = (a e1 + b e2) / g``)
    and their horizontal reach (``hypot`` of the ranges of ``u`` and ``v``).

    Returns
    -------
    (bool, float, float)
        Whether the plane is well conditioned (at least 3 points, ``det >= min_det`` times the
        product of the diagonal, a slope ``g > 0``; else the figures are 0), the range and
        the reach.
    """
    n = P.shape[0]
    if n < 3:
        return False, 0.0, 0.0
    su = 0.0
    sv = 0.0
    sh = 0.0
    lo_u = math.inf
    hi_u = -math.inf
    lo_v = math.inf
    hi_v = -math.inf
    for i in range(n):
        x, y, z = P[i, 0], P[i, 1], P[i, 2]
        u = x * e1[0] + y * e1[1] + z * e1[2]
        v = x * e2[0] + y * e2[1] + z * e2[2]
        su += u
        sv += v
        sh += x * up[0] + y * up[1] + z * up[2]
        lo_u = min(lo_u, u)
        hi_u = max(hi_u, u)
        lo_v = min(lo_v, v)
        hi_v = max(hi_v, v)
    mu, mv, mh = su / n, sv / n, sh / n
    suu = 0.0
    suv = 0.0
    svv = 0.0
    suh = 0.0
    svh = 0.0
    for i in range(n):
        x, y, z = P[i, 0], P[i, 1], P[i, 2]
        du = x * e1[0] + y * e1[1] + z * e1[2] - mu
        dv = x * e2[0] + y * e2[1] + z * e2[2] - mv
        dh = x * up[0] + y * up[1] + z * up[2] - mh
        suu += du * du
        suv += du * dv
        svv += dv * dv
        suh += du * dh
        svh += dv * dh
    det = suu * svv - suv * suv
    if not (det > 0 and det >= min_det * suu * svv):
        return False, 0.0, 0.0
    a = (svv * suh - suv * svh) / det
    b = (suu * svh - suv * suh) / det
    g = math.hypot(a, b)
    if not g > 0:
        return False, 0.0, 0.0
    f0 = (a * e1[0] + b * e2[0]) / g
    f1 = (a * e1[1] + b * e2[1]) / g
    f2 = (a * e1[2] + b * e2[2]) / g
    s0 = up[1] * f2 - up[2] * f1
    s1 = up[2] * f0 - up[0] * f2
    s2 = up[0] * f1 - up[1] * f0
    lo = math.inf
    hi = -math.inf
    for i in range(n):
        t = P[i, 0] * s0 + P[i, 1] * s1 + P[i, 2] * s2
        lo = min(lo, t)
        hi = max(hi, t)
    return True, hi - lo, math.hypot(hi_u - lo_u, hi_v - lo_v)
