"""Region-growing planar segmentation: Algorithm 1 of Farid & Sammut, "Region-Growing Planar
Segmentation for Robot Action Planning" (AI 2014), with planerel's documented choices where the
paper is silent (docs/segmentation.md).

Per image:

1. normals (:mod:`planerel.segment.normals`);
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
import statistics

import numpy as np

from planerel.errors import InputError
from planerel.segment._workspace import _output, _padded_labels, _workspace, normal_rings
from planerel.segment.adapt import adapt_params
from planerel.segment.params import RegionGrowParams, scaled_min_region_size
from planerel.segment.result import Segmentation, SegPlane, fit_planes

__all__ = ["region_grow", "check_cloud", "resolve_min_region_size"]

#: Depth bands of the automatic delta.
_NBANDS = 24
#: ``cos_seed`` of the growing kernels that turns the seed test off.
_NO_SEED_TEST = -2.0


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


def resolve_min_region_size(value, n_pixels: int, scale: float = 1.0) -> int:
    """The ``min_region_size`` to use for an image of ``n_pixels`` (``"auto"`` scales the paper's
    90 at 160x120 with the pixel count, times ``scale``)."""
    return scaled_min_region_size(n_pixels, scale) if value == "auto" else int(value)


def _check_moments(mom, cloud) -> None:
    """The degeneracy check of :func:`check_cloud` from the moments of the regular sample the
    normals pass gathered; when the sample looks degenerate (it may miss the few points off a
    line) the exact check on every point decides."""
    from planerel.segment._kernels import spread_of_moments

    w = spread_of_moments(mom)
    if mom[0] < 3 or w[2] <= 1e-18 or w[1] <= 1e-10 * w[2]:
        check_cloud(cloud)


def _build(labels, xyz_flat, n, params, normals, info, fits=None) -> Segmentation:
    if fits is None:
        fits = fit_planes(xyz_flat, labels.reshape(-1), n)
    planes = SegPlane.from_fits(*fits)
    return Segmentation(labels, planes, "regiongrow", params, normals, info)


def region_grow(cloud, params: RegionGrowParams | None = None, *, normals=None,
                split: bool = False, same_window=None) -> Segmentation:
    """Segment a cloud into planes by region growing.

    Parameters
    ----------
    cloud : Cloud
        Organized (grid neighbours) or unorganized (k-NN neighbours).
    params : RegionGrowParams, optional
        Defaults: the paper's.
    normals : ndarray, shape (H, W, 3), optional
        Precomputed normals (NaN = unknown); computed from ``params`` otherwise.
    split : bool
        Whether the caller post-processes the result (only resolves ``angle_order`` /
        ``seed_test`` ``"auto"``: see :meth:`RegionGrowParams.growing_variant`).
    same_window : Segmentation, optional
        An earlier growing of this organized cloud with the same normal window (the same
        parameters but the angles): its normals (float32) are used as this growing would
        compute them, and only the neighbour graph is built again (the far planes' second
        growing, :func:`planerel.segment._far_planes`).

    Returns
    -------
    Segmentation
        Zero planes (and a message saying so) when no region reaches ``min_region_size``.
    """
    from planerel.segment import _kernels as K
    from planerel.segment import normals as nmod
    from planerel.segment._graph_kernels import graph_table, grid_graph
    from planerel.segment._normal_kernels import normals_stream, with_graph

    p = params if params is not None else RegionGrowParams()
    if not isinstance(p, RegionGrowParams):
        raise InputError(f"regiongrow: params must be RegionGrowParams, got {type(p).__name__}")
    xyz = cloud.xyz
    h, w, _ = xyz.shape
    n_pix = h * w
    model = wide = None
    if cloud.organized and p.adapt:
        from planerel.segment.noise import WIDE_PATCH, estimate_noise

        cloud.require_points(3)
        model = estimate_noise(cloud, waviness=True)
        if p.wide_noise_window:
            wide = estimate_noise(cloud, patch=WIDE_PATCH)
    given = p  # the Segmentation keeps the parameters as given; info["settings"] the used ones
    p, chosen = adapt_params(p, model, (h, w), wide=wide)
    min_size = resolve_min_region_size(p.min_region_size, n_pix, p.min_region_scale)
    order, seed_test = p.growing_variant(split)
    cos_theta = math.cos(math.radians(p.theta))
    cos_strict = math.cos(math.radians(p.theta * p.angle_mf))
    # the angle threshold while the region has fewer than num_initial_points points, and after
    if order == "paper":
        cos_init, cos_main = cos_theta, cos_strict  # Algorithm 1, lines 16-21
    else:
        cos_init, cos_main = cos_strict, cos_theta
    cos_seed = cos_strict if seed_test else _NO_SEED_TEST
    delta_fixed = -1.0 if p.delta == "auto" else float(p.delta)
    xyz_flat = xyz.reshape(-1, 3)
    info: dict = {"min_region_size": min_size, "noise_model": _model_info(model),
                  "settings": _settings(chosen, p, w, min_size), "angle_order": order,
                  "seed_test": seed_test}
    if cloud.organized:
        graph_args = (float(p.delta_factor), delta_fixed, p.delta_mode == "depth", _NBANDS,
                      max(1, h // 120))
    reuse = same_window is not None and cloud.organized and normals is None
    if cloud.organized and normals is None and not reuse:
        cloud.require_points(3)
        ws = _workspace(h, w)
        a = np.ascontiguousarray(xyz, dtype=np.float64)
        s, r, zref, smax, rmax, jump = nmod.normal_kernel_args(
            a, smooth=p.normal_smooth, radius=p.normal_radius, jump_factor=p.jump_factor,
            reference_depth=p.reference_depth, intrinsics=cloud.intrinsics)
        nrm = _output(ws, "out_normals", (h, w, 3), np.float32)
        # the neighbour graph's delta table from a sample of rows, then its rows in the normals'
        # pass (the cloud is read once)
        table, tab2, zmin, zwidth, mean_nn = graph_table(a, *graph_args)
        normals_stream(a, s, r, zref, smax, rmax, jump, nrm, *normal_rings(ws, smax, rmax), ws.mom,
                       with_graph(tab2, zmin, zwidth, ws.mask, ws.graph))
        _check_moments(ws.mom, cloud)
    else:
        check_cloud(cloud)
        if reuse:
            nrm = np.asarray(same_window.normals)
            if nrm.shape != xyz.shape or nrm.dtype != np.float32:
                raise InputError("regiongrow: same_window's normals are not this cloud's")
        elif normals is None:
            nrm = nmod.knn_normals(xyz.reshape(-1, 3), k=p.knn).reshape(xyz.shape)
        else:
            nrm = np.asarray(normals, dtype=np.float64)
            if nrm.shape != xyz.shape:
                raise InputError(f"regiongrow: normals shape {nrm.shape} differs from the cloud's "
                                 f"{xyz.shape}")
        nrm = np.ascontiguousarray(nrm)
    nflat = nrm.reshape(-1, 3)
    if cloud.organized:
        padded, labels = _padded_labels(_workspace(h, w), h, w)
    else:
        labels = np.empty(n_pix, dtype=np.int32)

    fits = None
    if cloud.organized:
        ws = _workspace(h, w)
        pts = np.ascontiguousarray(xyz_flat, dtype=np.float64)
        mask = ws.mask
        if normals is not None or reuse:  # the graph was not made in the normals' pass
            table, zmin, zwidth, mean_nn = grid_graph(pts.reshape(h, w, 3), *graph_args, mask)
        tl = sorted(table.tolist())
        info.update(delta=statistics.median(tl), delta_min=tl[0], delta_max=tl[-1],
                    mean_neighbour_distance=float(mean_nn))
        mflat = mask.reshape(-1)
        # moments of every region, kept up to date by the kernels (regions hold >= min_size
        # pixels each, so at most n_pix // min_size of them)
        maxreg = n_pix // max(min_size, 1) + 2
        sums = np.zeros((maxreg, 10))
        ref = np.zeros((maxreg, 3))
        n = int(K.region_grow_grid_ws(nflat, ws.nvalid, mflat, w, p.min_neighbour_num,
                                      cos_init, cos_main, cos_seed, p.num_initial_points,
                                      p.base_update_step, min_size, padded, ws.queue,
                                      ws.seedable))
        K.region_sums_into(pts, labels, n, sums, ref, True)  # and -2 ("cannot join") -> -1
        info["grown_points"] = int(sums[:n, 0].sum())  # the kept regions' pixel counts
        if p.refine and n > 0:
            pn, po, _, _, prms = K.planes_from_sums(sums, ref, n)
            planes = np.ascontiguousarray(np.column_stack([pn, po]))
            thr = p.refine_factor * np.maximum(prms, 1e-6)
            rounds = (p.refine_rounds if p.refine_rounds != "auto" else
                      _auto_rounds(p, w))
            added, ws.entries = K.refine_grid_ws(pts, mflat, w, labels, planes, thr,
                                                 min(int(rounds), 254), ws.depth, ws.qlev,
                                                 ws.entries, sums, ref)
            info["refined_points"] = int(added)
            if p.leftover_planes:
                n = _leftover_planes(K, pts, mflat, w, labels, n, min_size,
                                     p.refine_factor * float(np.median(prms)), ws, info,
                                     sums, ref)
        fits = K.planes_from_sums(sums, ref, n)
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
        nvalid = np.empty(n_pix, dtype=np.bool_)
        queue = np.empty(n_pix, dtype=np.int32)
        n = int(K.region_grow_list(nflat, nvalid, nbr, p.min_neighbour_num, cos_init, cos_main,
                                   cos_seed, p.num_initial_points, p.base_update_step, min_size,
                                   labels, queue))
        info["grown_points"] = int((labels >= 0).sum())
        labels[labels < 0] = -1
    return _build(labels.reshape(h, w), xyz_flat, n, given, nrm, info, fits)


def _model_info(model) -> dict | None:
    """The noise model as reported in ``Segmentation.info`` (None when not measured)."""
    return None if model is None else model.to_dict()


def _settings(chosen: dict, p: RegionGrowParams, width: int, min_size: int) -> dict:
    """The settings chosen for this cloud (``info["settings"]``): whether they were adapted to
    the measured noise, the normal window and reference depth, the minimum region size."""
    from planerel.segment.normals import auto_normal_scale

    s_auto, r_auto = auto_normal_scale(width)
    out = dict(chosen)
    out["normal_smooth"] = s_auto if p.normal_smooth == "auto" else int(p.normal_smooth)
    out["normal_radius"] = r_auto if p.normal_radius == "auto" else int(p.normal_radius)
    out["reference_depth"] = p.reference_depth
    out["min_region_size"] = min_size
    return out


def _leftover_planes(K, pts, mflat, w, labels, n, min_size, tol, ws, info, sums, ref) -> int:
    """planerel's leftover step: each connected patch (over delta edges) of pixels still
    unassigned after completion, of at least ``min_size`` pixels, whose least-squares plane fits
    within ``tol`` (RMS, metres) becomes a region (its moments go to ``sums`` / ``ref`` rows
    n, n + 1, ...).  Returns the new region count."""
    comp = ws.comp
    m = int(K.leftover_components(mflat, labels, w, min_size, comp, ws.queue))
    added = 0
    if m:
        csums, cref = K.region_sums(pts, comp, m)
        rms = K.planes_from_sums(csums, cref, m)[4]
        ok = rms <= tol
        if ok.any():
            k = int(ok.sum())
            new_id = np.full(m + 1, -1, dtype=np.int32)
            new_id[:m][ok] = n + np.arange(k, dtype=np.int32)
            take = comp >= 0
            labels[take] = np.maximum(labels[take], new_id[comp[take]])
            sums[n:n + k] = csums[ok]
            ref[n:n + k] = cref[ok]
            added = k
    info["leftover_planes"] = added
    return n + added


def _auto_rounds(p: RegionGrowParams, width: int) -> int:
    from planerel.segment.normals import auto_normal_scale

    s_auto, r_auto = auto_normal_scale(width)
    s = s_auto if p.normal_smooth == "auto" else int(p.normal_smooth)
    r = r_auto if p.normal_radius == "auto" else int(p.normal_radius)
    return s + r + 2
