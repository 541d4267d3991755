"""Region-growing planar segmentation: Algorithm 1 of Farid & Sammut, "Region-Growing Planar
Segmentation for Robot Action Planning" (AI 2014), with planerel's documented choices where the
paper is silent (docs/segmentation.md).

Per image:

1. normals (:mod:`planerel.normals`);
2. the 8-neighbour grid graph: an edge between adjacent valid pixels whose points are closer
   than ``delta`` (``"auto"``: ``delta_factor`` x the mean over points of the distance to the
   nearest adjacent neighbour);
3. growing (compiled): seeds in row-major order; a seed must have ``min_neighbour_num``
   delta-neighbours, all with normals within ``theta * angle_mf`` of its own.  A region grows
   breadth-first over delta-edges; a candidate joins when it has at least ``min_neighbour_num``
   delta-neighbours and its normal is within the angle threshold of the region's base normal
   (``theta * angle_mf`` while the region has fewer than ``num_initial_points`` points, ``theta``
   after).  The base normal is the normalised mean of the region's normals, refreshed after each
   of the first ``num_initial_points`` additions and then every ``base_update_step``.  A region
   with fewer than ``min_region_size`` points is dissolved (its points may join later regions
   but never seed one);
4. a least-squares (PCA) plane per kept region;
5. (planerel, optional, on by default) boundary completion, then a final PCA refit.
"""

from __future__ import annotations

import math

import numpy as np

from planerel.errors import InputError
from planerel.segment.params import RegionGrowParams, scaled_min_region_size
from planerel.segment.result import Segmentation, SegPlane, fit_planes

__all__ = ["region_grow", "check_cloud", "resolve_min_region_size"]

#: Depth bands of the automatic delta.
_NBANDS = 24


def check_cloud(cloud) -> None:
    """Raise :class:`InputError` for clouds no plane can be fitted to: fewer than 3 valid points,
    or all valid points on one line (or one point)."""
    name = cloud.source or "cloud"
    cloud.require_points(3)
    h, wd, _ = cloud.xyz.shape
    step = max(1, int(math.sqrt(h * wd / 20000)))
    pts = cloud.xyz[::step, ::step][cloud.valid[::step, ::step]]
    w = _spread(pts)
    if len(pts) < 3 or w[1] <= 1e-10 * w[2]:
        w = _spread(cloud.points())  # the sample may miss the few points off the line
    if w[2] <= 1e-18:
        raise InputError(f"{name}: all valid points are the same point; no plane can be fitted")
    if w[1] <= 1e-10 * w[2]:
        raise InputError(f"{name}: all valid points lie on one line; no plane can be fitted")


def _spread(pts) -> np.ndarray:
    """Eigenvalues (ascending) of the covariance of ``pts`` (n, 3); zeros when n < 2."""
    if len(pts) < 2:
        return np.zeros(3)
    c = pts - pts.mean(axis=0)
    return np.linalg.eigvalsh(c.T @ c / len(c))


def resolve_min_region_size(value, n_pixels: int) -> int:
    """The ``min_region_size`` to use for an image of ``n_pixels`` (``"auto"`` scales the paper's
    90 at 160x120 with the pixel count)."""
    return scaled_min_region_size(n_pixels) if value == "auto" else int(value)


def _build(labels, xyz_flat, n, params, normals, info) -> Segmentation:
    nrm, off, cnt, cen, rms = fit_planes(xyz_flat, labels.reshape(-1), n)
    planes = tuple(
        SegPlane(i, nrm[i], off[i], int(cnt[i]), cen[i], rms[i]) for i in range(n)
    )
    return Segmentation(labels, planes, "regiongrow", params, normals, info)


def region_grow(cloud, params: RegionGrowParams | None = None, *, normals=None) -> Segmentation:
    """Segment a cloud into planes by region growing.

    Parameters
    ----------
    cloud : Cloud
        Organized (grid neighbours) or unorganized (k-NN neighbours).
    params : RegionGrowParams, optional
        Defaults: the paper's.
    normals : ndarray, shape (H, W, 3), optional
        Precomputed normals (NaN = unknown); computed from ``params`` otherwise.

    Returns
    -------
    Segmentation
        Zero planes (and a message saying so) when no region reaches ``min_region_size``.
    """
    from planerel import normals as nmod
    from planerel.segment import _kernels as K

    p = params if params is not None else RegionGrowParams()
    if not isinstance(p, RegionGrowParams):
        raise InputError(f"regiongrow: params must be RegionGrowParams, got {type(p).__name__}")
    check_cloud(cloud)
    xyz = cloud.xyz
    h, w, _ = xyz.shape
    n_pix = h * w
    min_size = resolve_min_region_size(p.min_region_size, n_pix)
    cos_main = math.cos(math.radians(p.theta))
    cos_init = math.cos(math.radians(p.theta * p.angle_mf))
    delta_fixed = -1.0 if p.delta == "auto" else float(p.delta)

    if normals is None:
        if cloud.organized:
            nrm = nmod.organized_normals(
                xyz, smooth=p.normal_smooth, radius=p.normal_radius,
                jump_factor=p.jump_factor, intrinsics=cloud.intrinsics,
            )
        else:
            nrm = nmod.knn_normals(xyz.reshape(-1, 3), k=p.knn).reshape(xyz.shape)
    else:
        nrm = np.asarray(normals, dtype=np.float64)
        if nrm.shape != xyz.shape:
            raise InputError(f"regiongrow: normals shape {nrm.shape} differs from the cloud's {xyz.shape}")
    nrm = np.ascontiguousarray(nrm)
    nflat = nrm.reshape(-1, 3)
    nvalid = np.empty(n_pix, dtype=np.bool_)  # filled by the kernels from the normals
    labels = np.empty(n_pix, dtype=np.int32)
    queue = np.empty(n_pix, dtype=np.int32)
    xyz_flat = xyz.reshape(-1, 3)
    info: dict = {"min_region_size": min_size}

    if cloud.organized:
        mask = np.empty((h, w), dtype=np.uint8)
        table, zmin, zwidth, mean_nn = K.grid_graph(
            xyz, float(p.delta_factor), delta_fixed, p.delta_mode == "depth", _NBANDS,
            max(1, h // 120), mask)
        info.update(delta=float(np.median(table)), delta_min=float(table.min()),
                    delta_max=float(table.max()), mean_neighbour_distance=float(mean_nn))
        mflat = mask.reshape(-1)
        n = K.region_grow_grid(nflat, nvalid, mflat, w, p.min_neighbour_num, cos_init, cos_main,
                               cos_init, p.num_initial_points, p.base_update_step, min_size,
                               labels, queue)
        n = int(n)
        info["grown_points"] = int((labels >= 0).sum())
        if p.refine and n > 0:
            pn, po, _, _, prms = fit_planes(xyz_flat, labels, n)
            planes = np.ascontiguousarray(np.column_stack([pn, po]))
            thr = p.refine_factor * np.maximum(prms, 1e-6)
            rounds = (p.refine_rounds if p.refine_rounds != "auto" else
                      _auto_rounds(p, w))
            added = K.refine_grid(xyz_flat, mflat, w, labels, planes, thr, int(rounds))
            info["refined_points"] = int(added)
        labels[labels < 0] = -1
    else:
        from scipy.spatial import cKDTree

        pts = xyz_flat
        ok = cloud.valid.reshape(-1)
        idx_ok = np.flatnonzero(ok)
        q = pts[idx_ok]
        kk = min(9, len(q))
        dist, idx = cKDTree(q).query(q, k=kk)
        dist, idx = dist[:, 1:], idx[:, 1:]
        mean_nn = float(dist[:, 0].mean()) if dist.shape[1] else 0.0
        delta = delta_fixed if delta_fixed > 0 else p.delta_factor * mean_nn
        nbr_local = np.where(dist < delta, idx_ok[idx], -1).astype(np.int32)
        nbr = np.full((n_pix, nbr_local.shape[1]), -1, dtype=np.int32)
        nbr[idx_ok] = nbr_local
        info.update(delta=float(delta), mean_neighbour_distance=mean_nn)
        n = int(K.region_grow_list(nflat, nvalid, nbr, p.min_neighbour_num, cos_init, cos_main,
                                   cos_init, p.num_initial_points, p.base_update_step, min_size,
                                   labels, queue))
        info["grown_points"] = int((labels >= 0).sum())
        labels[labels < 0] = -1
    return _build(labels.reshape(h, w), xyz_flat, n, p, nrm, info)


def _auto_rounds(p: RegionGrowParams, width: int) -> int:
    from planerel.normals import auto_normal_scale

    s_auto, r_auto = auto_normal_scale(width)
    s = s_auto if p.normal_smooth == "auto" else int(p.normal_smooth)
    r = r_auto if p.normal_radius == "auto" else int(p.normal_radius)
    return s + r + 2
