"""numba kernels of :mod:`planerel.features.disparity_fit` (compiled at first call, cached on disk).

Import this module only from inside functions: numba itself is a heavy import.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def _takes_part(sol_prev, thr_prev, k, u, v, w) -> bool:
    """A pixel of label index ``k`` takes part in a pass when its label's threshold is < 0
    (the first pass) or its residual under ``sol_prev`` is within it."""
    if thr_prev[k] < 0.0:
        return True
    return abs(sol_prev[k, 0] * u + sol_prev[k, 1] * v + sol_prev[k, 2] - w) <= thr_prev[k]


@njit(cache=True, nogil=True)
def disparity_pass(code, u, v, w, K, sol_prev, thr_prev):
    """One least-squares pass of ``w ~ a u + b v + c`` per label.

    Parameters
    ----------
    code : ndarray (N,) int64
        Fitted-label index (0..K-1) of each pixel.
    u, v, w : ndarray (N,) float64
        ``x/z``, ``y/z``, ``1/z`` of each pixel.
    K : int
    sol_prev : ndarray (K, 3)
    thr_prev : ndarray (K,)
        A pixel takes part when ``thr_prev`` of its label is < 0 or its residual under
        ``sol_prev`` is within it.

    Returns
    -------
    sums : ndarray (K, 9)
        uu, uv, u, vv, v, 1, uw, vw, w over the pixels taking part.
    """
    s = np.zeros((K, 9))
    for i in range(code.shape[0]):
        k = code[i]
        if not _takes_part(sol_prev, thr_prev, k, u[i], v[i], w[i]):
            continue
        s[k, 0] += u[i] * u[i]
        s[k, 1] += u[i] * v[i]
        s[k, 2] += u[i]
        s[k, 3] += v[i] * v[i]
        s[k, 4] += v[i]
        s[k, 5] += 1.0
        s[k, 6] += u[i] * w[i]
        s[k, 7] += v[i] * w[i]
        s[k, 8] += w[i]
    return s


@njit(cache=True, nogil=True)
def disparity_rms(code, u, v, w, K, sol_prev, thr_prev, sol):
    """``(K,)`` RMS residual under ``sol`` of the pixels that took part in the pass of
    ``(sol_prev, thr_prev)`` (the pixels ``sol`` was fitted to)."""
    ss = np.zeros(K)
    n = np.zeros(K)
    for i in range(code.shape[0]):
        k = code[i]
        if not _takes_part(sol_prev, thr_prev, k, u[i], v[i], w[i]):
            continue
        r = sol[k, 0] * u[i] + sol[k, 1] * v[i] + sol[k, 2] - w[i]
        ss[k] += r * r
        n[k] += 1.0
    out = np.zeros(K)
    for k in range(K):
        if n[k] > 0:
            out[k] = math.sqrt(ss[k] / n[k])
    return out


@njit(cache=True, nogil=True)
def disparity_gather(xyz, lab, idx):
    """The pixels of the fitted labels: ``code`` (N,) label index, ``u, v, w`` (N,) = ``x/z,
    y/z, 1/z`` of the finite points in front of the camera, and ``(K,)`` bool: the label has
    a finite point at ``z <= 0``.  ``idx`` maps a label to its index (-1: not fitted)."""
    H, W = lab.shape
    K = 0
    for t in range(idx.shape[0]):
        if idx[t] >= 0:
            K += 1
    n = 0
    for i in range(H):
        for j in range(W):
            lb = lab[i, j]
            if lb >= 0 and lb < idx.shape[0] and idx[lb] >= 0:
                n += 1
    code = np.empty(n, np.int64)
    u = np.empty(n)
    v = np.empty(n)
    w = np.empty(n)
    bad = np.zeros(K, np.bool_)
    m = 0
    for i in range(H):
        for j in range(W):
            lb = lab[i, j]
            if lb < 0 or lb >= idx.shape[0]:
                continue
            k = idx[lb]
            if k < 0:
                continue
            x = float(xyz[i, j, 0])
            y = float(xyz[i, j, 1])
            z = float(xyz[i, j, 2])
            if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z)):
                continue
            if z <= 0.0:
                bad[k] = True
                continue
            code[m] = k
            w[m] = 1.0 / z
            u[m] = x * w[m]
            v[m] = y * w[m]
            m += 1
    return code[:m], u[:m], v[:m], w[:m], bad
