"""Compiled patch fits of the noise estimate (:func:`planerel.segment.noise.estimate_noise`).

Compiled once, cached on disk; import only from inside functions.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, nogil=True, error_model="numpy")
def patch_noise(z, step, patch, q):  # pragma: no cover - compiled
    """Depth and depth-noise std of the complete ``patch`` x ``patch`` patches of a depth image.

    ``z`` (H, W) depth (NaN or <= 0 invalid); patches start every ``step`` pixels along rows
    and columns (row-major order, as ``sliding_window_view(z, (patch, patch))[::step, ::step]``);
    ``q`` (2, patch*patch) the unit centred pixel coordinates (:func:`noise._slopes`).  A patch
    with an invalid pixel is left out.  For each kept patch the plane ``a + b u + c v`` is
    fitted to the inverse depths; returns ``(zc, sd)`` (n,): ``1 / mean(1 / z)`` and the std of
    the residual (``patch^2 - 3`` degrees of freedom) carried to depth (times ``zc^2``)."""
    h, w = z.shape
    k = patch * patch
    ni = (h - patch) // step + 1
    nj = (w - patch) // step + 1
    zc = np.empty(ni * nj)
    sd = np.empty(ni * nj)
    r = np.empty(k)
    n = 0
    dof = k - 3
    for bi in range(ni):
        i0 = bi * step
        for bj in range(nj):
            j0 = bj * step
            ok = True
            s = 0.0
            for a in range(patch):
                for b in range(patch):
                    v = z[i0 + a, j0 + b]
                    if not v > 0:
                        ok = False
                        break
                    r[a * patch + b] = 1.0 / v
                    s += r[a * patch + b]
                if not ok:
                    break
            if not ok:
                continue
            m = s / k
            c0 = 0.0
            c1 = 0.0
            for t in range(k):
                r[t] -= m
                c0 += r[t] * q[0, t]
                c1 += r[t] * q[1, t]
            ss = 0.0
            for t in range(k):
                e = r[t] - c0 * q[0, t] - c1 * q[1, t]
                ss += e * e
            zm = 1.0 / m
            zc[n] = zm
            sd[n] = np.sqrt(ss / dof) * zm * zm
            n += 1
    return zc[:n], sd[:n]


@njit(cache=True, nogil=True, error_model="numpy")
def sorted_median(v, lo, hi):  # pragma: no cover - compiled
    """``np.median(v[lo:hi])`` of an ascending ``v``: the middle value, or the mean of the two
    middle values computed as numpy does (``(a + b) / 2``)."""
    n = hi - lo
    k = lo + n // 2
    if n % 2 == 1:
        return v[k]
    return (v[k - 1] + v[k]) / 2.0


@njit(cache=True, nogil=True, error_model="numpy")
def band_quantiles(zc, sd, bz, nb, size, c2, quad, q, factor):  # pragma: no cover - compiled
    """Per depth band ``b`` (the patches ``b * size .. (b + 1) * size - 1`` of ``zc``, ``sd``):
    the ``q`` quantile (numpy's default ``"linear"`` method) of the patches' std carried to the
    band's depth ``bz[b]`` under the model ``sqrt(c2 + (quad z^2)^2)``, times ``factor``.  The
    statements of :func:`planerel.segment.noise.estimate_noise` (``np.quantile`` of ``sd *
    shape``) in the same operations, without numpy's per-call overhead."""
    out = np.empty(nb)
    vals = np.empty(size)
    vi = (size - 1) * q
    lo = int(np.floor(vi))
    g = vi - lo
    for b in range(nb):
        t = quad * (bz[b] * bz[b])
        num = np.sqrt(c2 + t * t)
        for i in range(size):
            k = b * size + i
            u = quad * zc[k] * zc[k]
            vals[i] = sd[k] * (num / np.sqrt(c2 + u * u))
        # the order statistics lo and lo + 1 (numpy partitions for them too)
        part = np.partition(vals, lo)
        a = part[lo]
        c = part[lo + 1]
        for i in range(lo + 2, size):
            if part[i] < c:
                c = part[i]
        d = c - a
        if g >= 0.5:
            r = c - d * (1 - g)
        else:
            r = a + d * g
        out[b] = r * factor
    return out
