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


def _solve(sums):
    """``(K, 3)`` solutions of the normal equations from ``disparity_pass`` sums, and
    ``(K,)`` bool: solved (at least 3 pixels, a well-conditioned pixel layout)."""
    K = sums.shape[0]
    M = np.empty((K, 3, 3))
    M[:, 0, 0] = sums[:, 0]
    M[:, 0, 1] = M[:, 1, 0] = sums[:, 1]
    M[:, 0, 2] = M[:, 2, 0] = sums[:, 2]
    M[:, 1, 1] = sums[:, 3]
    M[:, 1, 2] = M[:, 2, 1] = sums[:, 4]
    M[:, 2, 2] = sums[:, 5]
    r = sums[:, 6:9]
    ok = sums[:, 5] >= 3
    # scale-free conditioning test: a strip one pixel high or a line of pixels has a
    # (near-)singular design; PCA keeps those
    tr = np.trace(M, axis1=1, axis2=2)
    ok &= np.linalg.det(M) > 1e-12 * np.maximum(tr, 1e-300) ** 3
    sol = np.zeros((K, 3))
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
        times their label's RMS residual are left out of the next.
    trim : float

    Returns
    -------
    normals : ndarray, shape (K, 3)
        Unit normals, sign arbitrary (zero rows where not fitted).
    fitted : ndarray, shape (K,), bool
        False where the fit is not defined: fewer than 3 pixels, a degenerate pixel layout,
        or a point at ``z <= 0`` (not a camera-frame cloud).
    """
    from planerel.features._disparity_kernels import disparity_gather, disparity_pass, disparity_rms

    labels = np.asarray(labels, np.int64)
    K = labels.size
    if K == 0 or lab.size == 0 or lab.max() < 0:
        return np.zeros((K, 3)), np.zeros(K, bool)
    idx = np.full(int(lab.max()) + 1, -1, np.int64)
    idx[labels] = np.arange(K)
    code, u, v, w, bad = disparity_gather(np.ascontiguousarray(xyz),
                                          np.ascontiguousarray(lab, dtype=np.int32), idx)
    sol = np.zeros((K, 3))
    thr = np.full(K, -1.0)  # the first pass takes every pixel
    ok = np.zeros(K, bool)
    for it in range(max(1, passes)):
        new, ok = _solve(disparity_pass(code, u, v, w, K, sol, thr))
        if it < passes - 1:
            rms = disparity_rms(code, u, v, w, K, sol, thr, new)
            thr = np.where(ok, trim * rms + 1e-12, -1.0)
        sol = new
    norm = np.linalg.norm(sol, axis=1)
    ok &= ~bad & (norm > 0) & np.isfinite(norm)
    out = np.zeros((K, 3))
    out[ok] = sol[ok] / norm[ok, None]
    return out, ok
