"""Surface normals for organized clouds (image-grid neighbours) and unorganized clouds (k-NN PCA).

Organized clouds
----------------
:func:`organized_normals` works on the ``(H, W, 3)`` grid in three O(1)-per-pixel passes
(compiled with numba, cached on disk):

1. **Depth-jump map.**  Two adjacent pixels are *connected* when both are valid and their depths
   differ by at most ``jump_factor * z / f`` (``z / f`` is the size of one pixel at depth ``z``;
   ``f`` the focal length in pixels, from the intrinsics or estimated from the points).  NaN holes
   and depth discontinuities therefore both cut the grid.
2. **Depth-aware box smoothing.**  Each pixel's point is replaced by the mean of a
   ``(2 * smooth + 1)`` box, separably (rows, then columns); a box never extends past a cut, so
   points on the two sides of a step edge are never averaged together.  Prefix sums over the
   connected runs of each row and column make this O(1) per pixel.
3. **Central differences** of the smoothed points ``radius`` pixels to each side, clipped to the
   connected run (one-sided at a cut); ``n = t_v x t_u`` normalised and turned towards the sensor
   (``n . p < 0``).  A pixel with no connected neighbour along a row or a column gets NaN.

Unorganized clouds
------------------
:func:`knn_normals`: PCA of the ``k`` nearest neighbours (scipy ``cKDTree``), smallest-eigenvalue
eigenvector, oriented towards the sensor at the origin.
"""

from __future__ import annotations

import math

import numpy as np

from planerel.errors import InputError

__all__ = [
    "estimate_normals",
    "organized_normals",
    "knn_normals",
    "pixel_angle",
    "auto_normal_scale",
    "normal_kernel_args",
]

#: Default ``(smooth, radius)`` in pixels at 160x120; larger images scale them with their width.
_BASE_SMOOTH = 1
_BASE_RADIUS = 1
#: Default depth-jump factor: neighbours whose depths differ by more than this many pixel sizes
#: (z / f) are on different surfaces.
DEFAULT_JUMP_FACTOR = 12.0
#: Depth (m) at which the normal window has its nominal size.
DEFAULT_REFERENCE_DEPTH = 2.0


def auto_normal_scale(width: int) -> tuple[int, int]:
    """Default ``(smooth, radius)`` in pixels for an image ``width`` pixels wide.

    1 and 1 at 160x120 (and below); proportional to ``sqrt(width / 160)`` above, so that a
    640x480 image gets 2 and 2: noise per pixel is the same at every resolution while pixels are
    4x closer, so a wider support is needed at full resolution, but growing it linearly with
    the width would blur stair edges.
    """
    f = math.sqrt(max(width, 1) / 160.0)
    return max(_BASE_SMOOTH, int(round(_BASE_SMOOTH * f))), max(_BASE_RADIUS, int(round(_BASE_RADIUS * f)))


def _check_int(name: str, value, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InputError(f"normals: {name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def _check_pos(name: str, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"normals: {name} must be a number, got {value!r}") from None
    if not math.isfinite(v) or v <= 0:
        raise InputError(f"normals: {name} must be positive and finite, got {value!r}")
    return v


def pixel_angle(xyz: np.ndarray, intrinsics=None) -> float:
    """Angular size of one pixel (``1 / f`` in radians) of an organized cloud.

    From ``intrinsics`` (``1 / sqrt(fx * fy)``) when given, otherwise estimated as the median of
    ``|x(u+1) - x(u)| / z`` over horizontally adjacent valid pixels.
    """
    if intrinsics is not None:
        return 1.0 / math.sqrt(intrinsics.fx * intrinsics.fy)
    h, w, _ = xyz.shape
    step = max(1, h // 64)
    rows = xyz[::step]
    dx = np.abs(rows[:, 1:, 0] - rows[:, :-1, 0])
    z = 0.5 * (rows[:, 1:, 2] + rows[:, :-1, 2])
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = dx / z
    ratio = ratio[np.isfinite(ratio) & (ratio > 0)]
    if ratio.size == 0:
        dy = np.abs(xyz[1:, :, 1] - xyz[:-1, :, 1])
        zz = 0.5 * (xyz[1:, :, 2] + xyz[:-1, :, 2])
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = dy / zz
        ratio = ratio[np.isfinite(ratio) & (ratio > 0)]
    if ratio.size == 0:
        return 1.0 / 525.0
    return float(np.median(ratio))


def organized_normals(
    xyz,
    *,
    smooth: int | str = "auto",
    radius: int | str = "auto",
    jump_factor: float = DEFAULT_JUMP_FACTOR,
    reference_depth: float | None = DEFAULT_REFERENCE_DEPTH,
    intrinsics=None,
) -> np.ndarray:
    """Per-pixel normals of an organized cloud.

    Parameters
    ----------
    xyz : ndarray, shape (H, W, 3), float64
        Points in the camera frame, NaN for invalid.
    smooth : int or "auto"
        Half-size of the depth-aware box filter (0 = no smoothing).
    radius : int or "auto"
        Pixel distance of the central differences (>= 1).
    jump_factor : float
        Adjacent pixels whose depths differ by more than ``jump_factor * z / f`` are not
        connected (a depth discontinuity).
    reference_depth : float or None
        ``smooth`` and ``radius`` hold at this depth (metres) and grow in proportion to the
        depth elsewhere (``round(smooth * z / reference_depth)``, at least 1, at most 4x), since
        sensor noise grows faster than the pixel footprint; None = the same everywhere.
    intrinsics : Intrinsics, optional
        Gives ``f``; estimated from the points otherwise.

    Returns
    -------
    ndarray, shape (H, W, 3), float64
        Unit normals towards the sensor; NaN where the point is invalid or has no connected
        neighbour along a row or a column.
    """
    a = np.ascontiguousarray(np.asarray(xyz, dtype=np.float64))
    args = normal_kernel_args(a, smooth=smooth, radius=radius, jump_factor=jump_factor,
                              reference_depth=reference_depth, intrinsics=intrinsics)
    from planerel.segment._normal_kernels import no_graph, normals_stream
    from planerel.segment._workspace import _workspace, normal_rings

    out = np.empty(a.shape, dtype=np.float32)
    ws = _workspace(a.shape[0], a.shape[1])  # reused scratch (see planerel.segment._workspace)
    normals_stream(a, *args, out, *normal_rings(ws, args[3], args[4]), ws.mom, no_graph())
    return out.astype(np.float64)


def normal_kernel_args(
    xyz: np.ndarray,
    *,
    smooth: int | str = "auto",
    radius: int | str = "auto",
    jump_factor: float = DEFAULT_JUMP_FACTOR,
    reference_depth: float | None = DEFAULT_REFERENCE_DEPTH,
    intrinsics=None,
) -> tuple[float, float, float, int, int, float]:
    """Validated arguments ``(smooth, radius, zref, smax, rmax, jump_per_z)`` of the compiled
    normal kernels for the ``(H, W, 3)`` array ``xyz`` (see :func:`organized_normals`)."""
    a = xyz
    if a.ndim != 3 or a.shape[2] != 3:
        raise InputError(f"normals: xyz must have shape (H, W, 3), got {a.shape}")
    s_auto, r_auto = auto_normal_scale(a.shape[1])
    s = s_auto if smooth == "auto" else _check_int("smooth", smooth, 0)
    r = r_auto if radius == "auto" else _check_int("radius", radius, 1)
    jf = _check_pos("jump_factor", jump_factor)
    if reference_depth is None:
        zref, smax, rmax = 0.0, s, r  # zref 0: the same window at every depth
    else:
        zref = _check_pos("reference_depth", reference_depth)
        smax, rmax = 4 * s, 4 * r
    if a.shape[0] >= 32768 or a.shape[1] >= 32768:
        raise InputError(f"normals: image too large ({a.shape[1]}x{a.shape[0]}); at most 32767 a side")
    pa = pixel_angle(a, intrinsics)
    return float(s), float(r), float(zref), int(smax), int(rmax), float(jf * pa)


def knn_normals(points, k: int = 16) -> np.ndarray:
    """k-nearest-neighbour PCA normals of an unorganized cloud.

    Parameters
    ----------
    points : ndarray, shape (N, 3)
        Points; rows with NaN are skipped (their normal is NaN).
    k : int
        Neighbours per point, including the point itself (>= 3).

    Returns
    -------
    ndarray, shape (N, 3)
        Unit normals oriented towards the origin (the sensor).
    """
    from scipy.spatial import cKDTree

    p = np.asarray(points, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 3:
        raise InputError(f"normals: points must have shape (N, 3), got {p.shape}")
    k = _check_int("k", k, 3)
    out = np.full(p.shape, np.nan)
    ok = np.all(np.isfinite(p), axis=1)
    q = p[ok]
    if len(q) < 3:
        return out
    kk = min(k, len(q))
    _, idx = cKDTree(q).query(q, k=kk)
    nb = q[idx]  # (M, k, 3)
    c = nb - nb.mean(axis=1, keepdims=True)
    cov = np.einsum("mki,mkj->mij", c, c)
    _, vec = np.linalg.eigh(cov)
    n = vec[:, :, 0]
    flip = np.einsum("mi,mi->m", n, q) > 0
    n[flip] *= -1.0
    out[ok] = n
    return out


def estimate_normals(cloud, **params) -> np.ndarray:
    """Normals of a :class:`~planerel.io.cloud.Cloud`.

    Organized clouds use :func:`organized_normals` (``params``: ``smooth``, ``radius``,
    ``jump_factor``); unorganized ones :func:`knn_normals` (``params``: ``k``).

    Returns
    -------
    ndarray, shape (H, W, 3)
        Same layout as ``cloud.xyz``; NaN where unknown.
    """
    if cloud.organized:
        allowed = {"smooth", "radius", "jump_factor", "reference_depth"}
        bad = set(params) - allowed
        if bad:
            raise InputError(f"normals: unknown parameter(s) {sorted(bad)} for an organized cloud")
        return organized_normals(cloud.xyz, intrinsics=cloud.intrinsics, **params)
    bad = set(params) - {"k"}
    if bad:
        raise InputError(f"normals: unknown parameter(s) {sorted(bad)} for an unorganized cloud")
    n = knn_normals(cloud.xyz.reshape(-1, 3), **params)
    return n.reshape(cloud.xyz.shape)
