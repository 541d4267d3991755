"""Plane normals fitted in disparity space: the fit a structured-light sensor's noise calls for.

A structured-light (or stereo) sensor measures disparity, proportional to inverse depth
``w = 1/z``; its error is about the same everywhere in disparity and lies along the viewing ray
in 3-D.  A least-squares (PCA) fit in 3-D treats that error as isotropic, and on a surface seen
at a grazing angle, whose extent across the view is small (a far stair tread: a strip a few
pixels high), the error along the ray tilts the fitted normal towards the ray: measured on
Kinect-like scenes (structured-light model, 1/8 px disparity steps), treads 2-3.5 m away
came out 5-26 degrees from horizontal instead of 0-2.

In the camera frame a plane ``n . X = d`` satisfies ``1/z = (n_x x/z + n_y y/z + n_z) / d``:
inverse depth is *linear* in the normalized image coordinates ``(x/z, y/z)``.  Fitting
``w = a u + b v + c`` by least squares (errors in ``w`` only, as the sensor makes them) gives
the normal ``(a, b, c) / |(a, b, c)|`` without that bias; a few trimming passes drop flying
pixels at the plane's edges.  (For a time-of-flight sensor, whose error is roughly constant in
depth, the same fit weights far points less than it could; it is still unbiased.)
"""

from __future__ import annotations

import numpy as np

__all__ = ["disparity_normals"]


def _solve(code, n, u, v, w, keep):
    """Per-label normal equations of ``w ~ a u + b v + c`` over the kept pixels: ``(n, 3)``
    solutions and ``(n,)`` bool (solved: at least 3 pixels, well conditioned)."""
    k = code[keep]
    uk, vk, wk = u[keep], v[keep], w[keep]
    s = lambda x: np.bincount(k, weights=x, minlength=n)  # noqa: E731
    one = np.bincount(k, minlength=n).astype(np.float64)
    su, sv = s(uk), s(vk)
    M = np.empty((n, 3, 3))
    M[:, 0, 0] = s(uk * uk)
    M[:, 0, 1] = M[:, 1, 0] = s(uk * vk)
    M[:, 0, 2] = M[:, 2, 0] = su
    M[:, 1, 1] = s(vk * vk)
    M[:, 1, 2] = M[:, 2, 1] = sv
    M[:, 2, 2] = one
    r = np.stack([s(uk * wk), s(vk * wk), s(wk)], 1)
    ok = one >= 3
    # scale-free conditioning test: a strip one pixel high or a line of pixels has a
    # (near-)singular design; PCA keeps those
    tr = np.trace(M, axis1=1, axis2=2)
    det = np.linalg.det(M)
    ok &= det > 1e-12 * np.maximum(tr, 1e-300) ** 3
    sol = np.zeros((n, 3))
    if ok.any():
        sol[ok] = np.linalg.solve(M[ok], r[ok][:, :, None])[:, :, 0]
    return sol, ok


def disparity_normals(xyz: np.ndarray, lab: np.ndarray, labels, passes: int = 3,
                      trim: float = 2.5) -> tuple[np.ndarray, np.ndarray]:
    """Unit normals of the labelled planes from a fit in inverse depth.

    Parameters
    ----------
    xyz : ndarray, shape (H, W, 3)
        Organized points in the camera frame (z forward), NaN invalid.
    lab : ndarray, shape (H, W), int
        Plane labels, -1 unassigned.
    labels : ndarray, shape (K,), int
        The labels to fit.
    passes : int
        Fits; after each but the last, pixels whose inverse-depth residual exceeds ``trim``
        times their label's RMS residual are left out.
    trim : float

    Returns
    -------
    normals : ndarray, shape (K, 3)
        Unit normals, sign arbitrary (zero rows where not fitted).
    fitted : ndarray, shape (K,), bool
        False where the fit is not defined: fewer than 3 pixels, a degenerate pixel layout,
        or a point at ``z <= 0`` (not a camera-frame cloud).
    """
    labels = np.asarray(labels, np.int64)
    K = labels.size
    if K == 0:
        return np.zeros((0, 3)), np.zeros(0, bool)
    n = int(lab.max()) + 1
    idx = np.full(n, -1, np.int64)
    idx[labels] = np.arange(K)
    flat = lab.reshape(-1)
    pts = xyz.reshape(-1, 3)
    sel = np.flatnonzero(flat >= 0)
    code = idx[flat[sel]]
    m = code >= 0
    sel, code = sel[m], code[m]
    P = pts[sel].astype(np.float64)
    finite = np.isfinite(P).all(1)
    sel, code, P = sel[finite], code[finite], P[finite]
    bad = np.zeros(K, bool)
    neg = P[:, 2] <= 0
    if neg.any():
        bad[np.unique(code[neg])] = True
        keep_pos = ~neg
        code, P = code[keep_pos], P[keep_pos]
    z = P[:, 2]
    u, v, w = P[:, 0] / z, P[:, 1] / z, 1.0 / z
    keep = np.ones(z.size, bool)
    sol = np.zeros((K, 3))
    ok = np.zeros(K, bool)
    for it in range(max(1, passes)):
        sol, ok = _solve(code, K, u, v, w, keep)
        if it == passes - 1:
            break
        res = sol[code, 0] * u + sol[code, 1] * v + sol[code, 2] - w
        cnt = np.maximum(np.bincount(code[keep], minlength=K), 1)
        rms = np.sqrt(np.bincount(code[keep], weights=res[keep] ** 2, minlength=K) / cnt)
        keep = np.abs(res) <= trim * rms[code] + 1e-12
    norm = np.linalg.norm(sol, axis=1)
    ok &= ~bad & (norm > 0) & np.isfinite(norm)
    out = np.zeros((K, 3))
    out[ok] = sol[ok] / norm[ok, None]
    return out, ok
