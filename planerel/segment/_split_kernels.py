"""numba kernel of the post-processing's residual test (compiled once, cached on disk; import
only from inside functions)."""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["residual_stats_grid"]


@njit(cache=True, nogil=True, error_model="numpy")
def residual_stats_grid(X, L, pn, po, n, noise, q, depth_unit, organized):  # pragma: no cover
    """Per region: RMS residual, RMS expected by the noise model, high-frequency noise.

    ``X`` (h, w, 3) points and ``L`` (h, w) int32 labels (-1 none) of a grid sample, ``pn``
    (n, 3) / ``po`` (n,) the regions' planes; depth variance ``(noise z^2)^2 + (q z^2)^2 / 12
    + depth_unit^2 / 12`` (see :meth:`planerel.segment.split.SplitParams.depth_sigma2`).  The
    noise is ``sqrt(mean(dd^2) / 6)`` over the second differences ``dd`` of the residual along
    rows and columns within one region (``organized`` only; NaN without any).  Sums run in
    row-major order, as numpy's ``bincount`` of the former implementation did.
    Returns (rms, exp_rms, local), each (n,).
    """
    h = L.shape[0]
    w = L.shape[1]
    cnt = np.zeros(n)
    s_d = np.zeros(n)
    s_e = np.zeros(n)
    D = np.zeros((h, w))
    for v in range(h):
        for u in range(w):
            lab = L[v, u]
            if lab < 0:
                continue
            x = X[v, u, 0]
            y = X[v, u, 1]
            z = X[v, u, 2]
            dn = x * pn[lab, 0] + y * pn[lab, 1] + z * pn[lab, 2]
            d = dn + po[lab]
            D[v, u] = d
            z2 = z * z
            a = noise * z2
            b = q * z2
            sig = np.sqrt(a * a + b * b / 12.0 + depth_unit * depth_unit / 12.0) * (abs(dn) / z)
            cnt[lab] += 1.0
            s_d[lab] += d * d
            s_e[lab] += sig * sig
    rms = np.empty(n)
    exp_rms = np.empty(n)
    for i in range(n):
        c = max(cnt[i], 1.0)
        rms[i] = np.sqrt(s_d[i] / c)
        exp_rms[i] = np.sqrt(s_e[i] / c)
    local = np.full(n, np.nan)
    if organized:
        ssum = np.zeros(n)
        scnt = np.zeros(n)
        csum = np.zeros(n)
        # row and column sums apart, added at the end (the former implementation's order)
        for v in range(h):
            for u in range(1, w - 1):
                lb = L[v, u]
                if lb >= 0 and L[v, u - 1] == lb and L[v, u + 1] == lb:
                    dd = D[v, u - 1] - 2.0 * D[v, u] + D[v, u + 1]
                    ssum[lb] += dd * dd
                    scnt[lb] += 1.0
        for v in range(1, h - 1):
            for u in range(w):
                lb = L[v, u]
                if lb >= 0 and L[v - 1, u] == lb and L[v + 1, u] == lb:
                    dd = D[v - 1, u] - 2.0 * D[v, u] + D[v + 1, u]
                    csum[lb] += dd * dd
                    scnt[lb] += 1.0
        for i in range(n):
            local[i] = np.sqrt((ssum[i] + csum[i]) / scnt[i] / 6.0)
    return rms, exp_rms, local
