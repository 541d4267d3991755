"""Stage 2, planar segmentation: region growing (the paper's Algorithm 1, default) and the RANSAC
baselines SP (plane) and SNP (plane with normals).

In: a :class:`~planerel.io.cloud.Cloud`.  Out: a :class:`Segmentation` (``(H, W)`` int32 plane
labels and the fitted planes).  Also here: :mod:`~planerel.segment.normals` (per-pixel normals),
:mod:`~planerel.segment.evaluate` (SegComp scoring of labels against ground truth) and the
per-label kernels the later stages share (:mod:`~planerel.segment._label_kernels`).

>>> from planerel.segment import segment
>>> seg = segment(cloud)                                  # doctest: +SKIP
>>> seg.labels            # (H, W) int32, -1 = unassigned  # doctest: +SKIP
>>> seg.planes[0].normal, seg.planes[0].offset            # doctest: +SKIP

See docs/segmentation.md for the algorithm, every parameter and the measured quality and speed.
"""

from __future__ import annotations

import functools

from planerel.errors import InputError
from planerel.segment.params import RansacParams, RegionGrowParams, coerce_params
from planerel.segment.result import Segmentation, SegPlane, fit_planes

__all__ = [
    "segment",
    "planar_share",
    "METHODS",
    "Segmentation",
    "SegPlane",
    "RegionGrowParams",
    "RansacParams",
    "fit_planes",
    "make_params",
    "split_fields",
    "SPLIT_PREFIX",
]

#: Method names :func:`segment` accepts.
METHODS = ("regiongrow", "sp", "snp")
#: A segmentation parameter named ``split.NAME`` sets field NAME of the post-processing's
#: :class:`~planerel.segment.split.SplitParams` (``--param split.small_faces=150``).
SPLIT_PREFIX = "split."


def split_fields(params: dict):
    """Separate the post-processing's ``split.NAME`` parameters from the method's.

    Parameters
    ----------
    params : dict
        Segmentation parameters as a user gives them (``{"theta": 12, "split.small_faces": 150}``).

    Returns
    -------
    (dict, SplitParams or None)
        The other parameters (a new dict), and the :class:`~planerel.segment.split.SplitParams`
        built from the ``split.NAME`` ones (strings converted as for ``--param``), or None when
        there are none.

    Raises
    ------
    InputError
        An unknown field or a bad value (the dataclass's message).
    """
    rest, given = {}, {}
    for key, value in params.items():
        if isinstance(key, str) and key.startswith(SPLIT_PREFIX):
            given[key[len(SPLIT_PREFIX):]] = value
        else:
            rest[key] = value
    if not given:
        return rest, None
    from planerel.segment.split import SplitParams

    return rest, coerce_params(SplitParams, given)


def make_params(method: str = "regiongrow", **params):
    """The parameter dataclass of ``method`` built from keyword values (strings from the command
    line are converted); unknown names raise :class:`InputError`.  Region growing also takes
    ``preset`` (``"kinect"`` = the defaults, ``"structured-light"`` / ``"abw"``, ``"paper"``:
    see :data:`planerel.segment.params.PRESETS`); explicit values override the preset's."""
    if method not in METHODS:
        raise InputError(f"unknown segmentation method {method!r}; choose one of {', '.join(METHODS)}")
    try:
        # the value's type is part of the key: 1, 1.0 and True are equal but validate differently
        key = (method, tuple(sorted((k, type(v), v) for k, v in params.items())))
        hash(key)
    except TypeError:  # an unhashable value: build (and validate) without the cache
        return _make_params(method, params)
    return _cached_params(key)


@functools.lru_cache(maxsize=64)
def _cached_params(key):
    # the dataclasses are frozen, so one validated instance per distinct set of values is shared
    # (validation is ~40 us, a twentieth of a 160x120 segmentation)
    method, items = key
    return _make_params(method, {k: v for k, _, v in items})


def _make_params(method: str, params: dict):
    if method == "regiongrow":
        preset = params.pop("preset", None)
        if preset is not None:
            from planerel.segment.params import preset_values

            params = {**preset_values(preset), **params}
        return coerce_params(RegionGrowParams, params)
    return coerce_params(RansacParams, params)


def segment(cloud, method: str = "regiongrow", *, normals=None, split=None, split_params=None,
            up=None, **params) -> Segmentation:
    """Segment a cloud into planes.

    Parameters
    ----------
    cloud : Cloud
        Organized ``(H, W, 3)`` or unorganized ``(1, N, 3)`` cloud (metres, NaN invalid).
    method : {"regiongrow", "sp", "snp"}
        Region growing (the paper's Algorithm 1), RANSAC plane (SP) or RANSAC plane with
        normals (SNP).
    normals : ndarray, shape (H, W, 3), optional
        Precomputed normals (regiongrow, snp).
    split : bool or str, optional
        planerel's planar post-processing: split regions that do not fit one plane (a floor and
        a shallow ramp grown together) into planar parts and find planes in unassigned patches
        (:func:`planerel.segment.split.split_bent_regions`), then merge touching regions of one
        plane (:func:`planerel.segment.merge.merge_coplanar`) and, with ``adapt`` (the
        default), dissolve fragments whose points lie on a touching larger region's plane
        (:func:`planerel.segment.absorb.absorb_fragments`).  Default: on for
        regiongrow, off for the RANSAC baselines (they stay as the paper ran them).  Strings
        ``"true"/"false"/"1"/"0"`` are accepted (``--param split=false``).  With
        ``refine=False`` as well, region growing follows the paper's Algorithm 1 (see
        :meth:`RegionGrowParams.growing_variant`).
    split_params : SplitParams, optional
        Parameters of the split step (default :class:`SplitParams`); or give single fields as
        ``**{"split.small_faces": 150}`` among ``params`` (not both).
    up : 3 numbers or callable, optional
        Gravity up in the camera frame, or a function of the segmentation so far returning it
        (:func:`planerel.features.facts.view_up`: the given, the file's or the estimated up).
        Read only by the small pass with ``small_pitch`` (regiongrow), which runs when the
        camera looks down at least that steeply; without ``up`` it does not run then.
    **params
        Fields of :class:`RegionGrowParams` (regiongrow) or :class:`RansacParams` (sp, snp);
        or ``params=<dataclass instance>``; regiongrow also ``preset="structured-light"`` or
        ``preset="paper"`` (Algorithm 1 as the paper writes it, post-processing off).

    Returns
    -------
    Segmentation
        ``labels`` (H, W) int32 with -1 unassigned and ``planes`` (normal towards the sensor,
        ``offset > 0``, ``n_points``, ``centroid``, ``rms``).

    Raises
    ------
    InputError
        No / one valid point, all points on a line, bad or unknown parameters.
    """
    from planerel.io.cloud import Cloud

    if not isinstance(cloud, Cloud):
        raise InputError(f"segment: expected a planerel Cloud, got {type(cloud).__name__}")
    if not cloud.organized:
        dup = _unique_points(cloud, normals)
        if dup is not None:
            # a map's repeated points (a terrain map stores each cell once per layer): they
            # would be each other's nearest neighbours at distance 0, and the neighbour
            # distance that links points (``delta``) would be 0 too
            sub, sub_normals, where, inverse = dup
            seg = segment(sub, method, normals=sub_normals, split=split,
                          split_params=split_params, up=up, **params)
            return _spread_labels(seg, cloud, where, inverse)
    params, split_given = split_fields(params)
    if split_given is not None:
        if split_params is not None:
            raise InputError("segment: give either split_params=<SplitParams> or split.NAME "
                             "parameters, not both")
        split_params = split_given
    given = params.pop("params", None)
    if given is not None:
        if params:
            raise InputError("segment: give either params=<dataclass> or keyword parameters, not both")
        p = given
    else:
        p = make_params(method, **params)
    # Algorithm 1 as written (the paper's order without planerel's completion, as preset=paper
    # sets them) runs alone: no post-processing unless asked for
    paper = (method == "regiongrow" and isinstance(p, RegionGrowParams)
             and p.angle_order == "paper" and not p.refine)
    do_split = _as_bool(split, default=(method == "regiongrow" and not paper))
    if method == "regiongrow":
        from planerel.segment.regiongrow import region_grow

        seg = region_grow(cloud, p, normals=normals, split=do_split)
    elif method in METHODS:
        from planerel.segment.ransac import ransac_segment

        seg = ransac_segment(cloud, p, normals=normals if method == "snp" else None,
                             use_normals=(method == "snp"))
    else:
        raise InputError(f"unknown segmentation method {method!r}; choose one of {', '.join(METHODS)}")
    if not do_split:
        return seg
    seg = _post_process(cloud, seg, p, normals, split_params)
    if (method == "regiongrow" and cloud.organized and p.adapt and p.wide_fallback > 0
            and not p.wide_noise_window and normals is None):
        # most of the frame in no plane: correlated depth noise (srob59); the wide window
        import dataclasses

        from planerel.segment.adapt import MAX_WINDOW

        share = planar_share(cloud, seg.labels)
        if share is not None and share < p.wide_fallback:
            wp = dataclasses.replace(p, wide_noise_window=True)
            wide = region_grow(cloud, wp, split=True)
            auto = {n: MAX_WINDOW for n in ("normal_smooth", "normal_radius")
                    if getattr(p, n) == "auto"}   # a window the caller set stays theirs
            if auto and _window(wide) <= _window(seg):
                # no wider window from the 15 px estimate (an R200's speckled depth has no
                # 15 x 15 px patch to measure): the widest adaptive window (up66)
                wp = dataclasses.replace(p, **auto)
                wide = region_grow(cloud, wp, split=True)
            wide = _post_process(cloud, wide, wp, None, split_params)
            wshare = planar_share(cloud, wide.labels)
            if wshare > share:
                seg = wide
            seg.info["wide_fallback"] = (round(share, 3), round(wshare, 3))
    if (method == "regiongrow" and cloud.organized and p.adapt
            and (p.far_theta > 0 or p.far_wide) and normals is None):
        # (without adapt no noise model measures a far plane's fit: nothing to add)
        seg = _far_planes(cloud, seg, p, split_params)
    if (method == "regiongrow" and cloud.organized and p.adapt and p.near_wide > 0
            and normals is None):
        seg = _near_planes(cloud, seg, p, split_params)
    if (method == "regiongrow" and cloud.organized and p.adapt and p.small_scale > 0
            and normals is None):
        u = _view_up(seg, up) if (p.small_pitch > 0 or p.raised_min > 0) else None
        if _steep_enough(seg, p, u):
            seg = _small_planes(cloud, seg, p, split_params)
            if p.raised_min > 0 and u is not None:
                seg = _raised_tops(cloud, seg, p, split_params, u)
    if (method == "regiongrow" and cloud.organized and p.adapt and p.noisy_wide > 0
            and normals is None):
        seg = _noisy_planes(cloud, seg, p, split_params)
    return seg


def _view_up(seg, up):
    """``up`` (3 numbers, a function of ``seg`` returning them, or None) read once: ``(3,)``
    or None."""
    import numpy as np

    u = up(seg) if callable(up) else up
    return None if u is None else np.asarray(u, float)


def _steep_enough(seg, p, up) -> bool:
    """Whether the small pass runs: always without ``small_pitch``; with it, when the camera
    looks down at least ``small_pitch`` degrees by ``up`` (3,) (:func:`_view_up`'s; None:
    unknown, no pass).  ``seg.info["view_pitch"]``: the pitch read."""
    if p.small_pitch <= 0:
        return True
    if up is None:
        seg.info["view_pitch"] = None
        return False
    pitch = view_pitch(up)
    seg.info["view_pitch"] = round(pitch, 2)
    return pitch >= p.small_pitch


def view_pitch(up) -> float:
    """Degrees the optical axis (camera +z) looks under the horizon for the gravity ``up``
    (shape (3,), camera frame; any length): 0 level, 90 straight down, negative looking up.
    :class:`InputError` for anything but 3 finite numbers, not all zero."""
    import numpy as np

    from planerel.io.cloud import unit_up

    u = unit_up(up, "up vector")
    return float(np.degrees(np.arcsin(np.clip(-u[2], -1.0, 1.0))))


def planar_share(cloud, labels) -> float | None:
    """The share of ``cloud``'s valid points that ``labels`` (H, W) put in a plane (label
    >= 0); None when the cloud has no valid point."""
    import numpy as np

    valid = np.asarray(cloud.valid)
    return float((np.asarray(labels)[valid] >= 0).mean()) if valid.any() else None


def _window(seg) -> int:
    """The normal window (the larger of smooth and radius, px) a growing ran with (0 when
    its info does not say)."""
    st = seg.info.get("settings") or {}
    vals = [v for v in (st.get("normal_smooth"), st.get("normal_radius")) if isinstance(v, int)]
    return max(vals) if vals else 0


def _second_growing(cloud, seg, wp, split_params):
    """The cloud grown again with ``wp`` (and post-processed), on the first growing's float32
    normals when its window is this one's (the angles or sizes alone differ)."""
    import numpy as np

    from planerel.segment.regiongrow import region_grow

    same = (seg if seg.normals is not None and seg.normals.dtype == np.float32
            and getattr(seg.params, "wide_noise_window", None) == wp.wide_noise_window else None)
    return _post_process(cloud, region_grow(cloud, wp, split=True, same_window=same), wp, None,
                         split_params)


def _noise_sigma(seg, fallback=None):
    """The depth noise (m) at a depth ``z`` (m) as a function of ``z``: the measured noise model
    of ``seg``'s growing, or, when the frame measured none, ``fallback``'s (a SplitParams:
    :meth:`~planerel.segment.split.SplitParams.depth_sigma2`, the Kinect model by default;
    without it 0, so no candidate fits).  ``z`` may be an array (the noise of each depth)."""
    import numpy as np

    nm = seg.info.get("noise_model") or {}
    c, q = float(nm.get("const_m") or 0.0), float(nm.get("quad_per_m") or 0.0)
    if (c > 0 or q > 0) or fallback is None:
        return lambda z: np.hypot(c, q * np.square(z))
    return lambda z: np.sqrt(fallback.depth_sigma2(np.asarray(z, float)))


def _free_regions(cloud, seg, wl, free, min_size, rms_max, share, sigma=None, local=0.0,
                  within=True):
    """The regions of a second growing's labels ``wl`` (H, W) lying for at least ``share`` of
    their pixels, and ``min_size`` pixels or more, in ``free`` (H, W) bool, whose
    least-squares plane's RMS is at most ``rms_max`` times the depth noise at its centroid's
    depth (``sigma``, a function of the depth; default the measured noise,
    :func:`_noise_sigma`): ``(labels with them added as planes n, n + 1, ..., the number added,
    every candidate's RMS over the noise)``.  With ``local`` (``far_local``), a candidate
    failing ``rms_max`` is kept when its RMS is at most ``local`` times its own patch noise
    (:func:`~planerel.segment.patch_noise.patch_noise`), itself above ``rms_max`` times the
    frame's noise (a frame that measured none keeps nothing this way) and at most
    :data:`~planerel.segment.params.FAR_LOCAL_NOISE` per metre of its depth; ``seg.info
    ["far_local"]`` counts them.  Without ``within`` (the noisy pass) a candidate within
    ``rms_max`` is not kept: only the ``local`` test keeps one."""
    import numpy as np
    from scipy.ndimage import find_objects

    lab = seg.labels
    grown = wl >= 0
    total = np.bincount(wl[grown])
    inside = np.bincount(wl[free & grown], minlength=len(total))
    out = lab.copy()
    n = len(seg.planes)
    added = 0
    sigma = sigma if sigma is not None else _noise_sigma(seg)
    fit = []
    xyz = np.asarray(cloud.xyz)
    # each region's bounding box (region r is object r + 1 of wl + 1): a candidate's pixels are
    # read in its box, in the frame's row-major order
    boxes = find_objects(wl + 1, max_label=len(total))
    for r in np.flatnonzero(total).tolist():
        k, t = int(inside[r]), int(total[r])
        if k >= share * t and k >= max(min_size, 1):
            box = boxes[r]
            m = (wl[box] == r) & free[box]
            pts = np.asarray(xyz[box][m], float)
            cen = pts.mean(0)
            # the plane's RMS against the sensor's noise at its depth
            rms = float(np.linalg.svd(pts - cen, compute_uv=False)[-1] / np.sqrt(len(pts)))
            sig = float(sigma(float(cen[2])))
            ratio = rms / sig if sig > 0 else float("inf")
            fit.append(round(ratio, 2))
            if ratio > rms_max:
                if not (local > 0 and sig > 0
                        and _locally_flat(xyz[box], m, xyz.shape[1], rms, cen, local,
                                          rms_max * sig)):
                    continue
                if within:
                    seg.info["far_local"] = seg.info.get("far_local", 0) + 1
            elif not within:
                continue
            out[box][m] = n + added
            added += 1
    return out, added, fit


def _locally_flat(xyz, mask, width, rms, cen, local, floor) -> bool:
    """``far_local``'s test: the region ``mask`` (h, w) of the points ``xyz`` (h, w, 3) (a
    window of a frame ``width`` px wide holding the region: the patches tile the region's
    bounding box, so the window gives the frame's answer), whose plane fits at ``rms`` (m) with
    its centroid ``cen`` (3,), fits within ``local`` times its own patch noise, which is above
    ``floor`` (m: the frame's bound, so the region is noisier than the frame, not folded) and at
    most :data:`~planerel.segment.params.FAR_LOCAL_NOISE` per metre of depth."""
    from planerel.segment.params import FAR_LOCAL_NOISE
    from planerel.segment.patch_noise import patch_noise, patch_size

    own = patch_noise(xyz, mask, patch_size(width))
    if own is None or own <= floor or own > FAR_LOCAL_NOISE * float(cen[2]):
        return False
    return rms <= local * own


def _near_free(cloud, seg, far_depth):
    """``(H, W)`` bool: valid depth nearer than ``far_depth`` that ``seg`` left in no plane
    (where the near and small passes may add planes)."""
    import numpy as np

    z = np.asarray(cloud.xyz[..., 2], float)
    return np.asarray(cloud.valid) & (seg.labels < 0) & (np.nan_to_num(z) <= far_depth)


def _with_added(cloud, seg, out, added):
    """``seg`` rebuilt from the labels ``out`` (H, W) that hold its planes and ``added`` more
    (labelled ``len(seg.planes)`` on), its normals and info kept."""
    import numpy as np

    from planerel.segment.regiongrow import _build

    xyz_flat = np.asarray(cloud.xyz, float).reshape(-1, 3)
    return _build(out.astype(np.int32), xyz_flat, len(seg.planes) + added, seg.params,
                  seg.normals, seg.info)


def _near_rms_max(seg, p, sigma=None) -> float:
    """The fit bound (RMS over the noise ``sigma``, default :func:`_noise_sigma`) of a plane
    the near and small passes add: ``far_rms``, or :data:`~planerel.segment.params.NEAR_RMS`
    times the median fit of the first growing's planes nearer than ``far_depth`` when that is
    looser (a rippled sensor's planes fit at several times the 5 px noise estimate: a
    RealSense board at 1 m at 5-15, hunt67)."""
    import numpy as np

    from planerel.segment.params import NEAR_RMS

    sigma = sigma if sigma is not None else _noise_sigma(seg)
    ratios = [pl.rms / s for pl in seg.planes
              if pl.centroid[2] <= p.far_depth and (s := float(sigma(float(pl.centroid[2])))) > 0]
    return max(p.far_rms, NEAR_RMS * float(np.median(ratios))) if ratios else p.far_rms


def _near_planes(cloud, seg, p, split_params):
    """``near_wide``: planes where the first growing left depth nearer than ``far_depth`` in no
    plane, from a second growing whose normal window is ``near_wide`` times the first's (its
    regions of the first's minimum size lying for :data:`~planerel.segment.params.FAR_SHARE` or
    more in that depth, fitting a plane within ``far_rms`` times the noise, or within
    :data:`~planerel.segment.params.NEAR_RMS` times the median fit of the first growing's near
    planes when that is looser); nothing already in a plane changes.  ``info["near_planes"]``:
    the planes added; ``info["near_fit"]``: every candidate's RMS over the noise;
    ``info["near_rms_max"]``: the bound used; ``info["near_window"]``: the window."""
    import dataclasses

    from planerel.segment.params import FAR_SHARE
    from planerel.segment.regiongrow import region_grow

    free = _near_free(cloud, seg, p.far_depth)
    min_size = int(seg.info.get("min_region_size", 0) or 0)
    if int(free.sum()) < max(min_size, 1):
        seg.info["near_planes"] = 0
        return seg
    # the first growing's window (as adapted), widened
    win = _widened(seg, p, p.near_wide)
    wp = dataclasses.replace(p, normal_smooth=win[0], normal_radius=win[1],
                             min_region_size=max(min_size, 1), far_theta=0.0, far_wide=False,
                             small_scale=0.0, near_wide=0.0)
    wl = _post_process(cloud, region_grow(cloud, wp, split=True), wp, None, split_params).labels
    rms_max = _near_rms_max(seg, p)
    out, added, fit = _free_regions(cloud, seg, wl, free, min_size, rms_max, FAR_SHARE)
    seg.info["near_planes"] = added
    seg.info["near_rms_max"] = round(rms_max, 2)
    seg.info["near_fit"] = fit
    seg.info["near_window"] = tuple(win)
    return _with_added(cloud, seg, out, added) if added else seg


def _widened(seg, p, factor):
    """``[smooth, radius]``: the first growing's normal window (as adapted) times ``factor``,
    at least one pixel more (the near and noisy passes)."""
    from planerel.segment.normals import auto_normal_scale

    settings = seg.info.get("settings") or {}
    nominal = auto_normal_scale(seg.labels.shape[1])
    win = []
    for i, name in enumerate(("normal_smooth", "normal_radius")):
        v = settings.get(name, getattr(p, name))
        v = nominal[i] if not isinstance(v, int) else v
        win.append(max(v + 1, int(round(factor * v))))
    return win


def _noisy_planes(cloud, seg, p, split_params):
    """``noisy_wide``: planes of faces noisier than the rest of the frame where the first
    growing left depth in no plane, at any range (:class:`~planerel.segment.params.
    RegionGrowParams`); nothing already in a plane changes.  ``info["noisy_planes"]``: the
    planes added."""
    import dataclasses

    import numpy as np

    from planerel.segment.params import FAR_SHARE, NOISY_LOCAL, NOISY_SIZE, NOISY_THETA
    from planerel.segment.regiongrow import region_grow

    seg.info["noisy_planes"] = 0
    free = np.asarray(cloud.valid) & (seg.labels < 0)
    least = max(int(seg.info.get("min_region_size", 0) or 0), 1)
    size = int(round(NOISY_SIZE * least))
    sigma = _noise_sigma(seg)
    if int(free.sum()) < size or float(sigma(1.0)) <= 0:
        return seg  # (a frame that measured no noise has nothing noisier than it)
    win = _widened(seg, p, p.noisy_wide)
    wp = dataclasses.replace(p, normal_smooth=win[0], normal_radius=win[1], theta=NOISY_THETA,
                             min_region_size=least, far_theta=0.0, far_wide=False,
                             small_scale=0.0, near_wide=0.0, noisy_wide=0.0)
    wl = _post_process(cloud, region_grow(cloud, wp, split=True), wp, None, split_params).labels
    out, added, _fit = _free_regions(cloud, seg, wl, free, size, _near_rms_max(seg, p, sigma),
                                     FAR_SHARE, sigma, local=NOISY_LOCAL, within=False)
    seg.info["noisy_planes"] = added
    return _with_added(cloud, seg, out, added) if added else seg


def _small_planes(cloud, seg, p, split_params):
    """``small_scale``: planes too small for the first growing where it left depth nearer than
    ``far_depth`` in no plane, from a second growing whose minimum region size is
    ``small_scale`` times the first's (its regions lying for
    :data:`~planerel.segment.params.SMALL_SHARE` or more in that depth, fitting a plane within
    the near pass's bound, :func:`_near_rms_max`, and standing parallel over another plane,
    or with ``small_corners`` meeting one at a corner: :func:`_small_kept`); nothing already
    in a plane changes.

    The second growing merges with the side test (``merge_side`` at least
    :data:`~planerel.segment.params.SMALL_SIDE`): the pooled merge test joins a block's 2 cm
    top to the board under it, whose pixels are not free (hunt67).  ``info["small_planes"]``:
    the planes added; ``info["small_fit"]``: every candidate's RMS over the noise."""
    from planerel.segment.params import SMALL_SHARE

    free = _near_free(cloud, seg, p.far_depth)
    size = max(1, round(p.small_scale * int(seg.info.get("min_region_size", 0) or 0)))
    if int(free.sum()) < size:
        seg.info["small_planes"] = 0
        return seg
    wl, sigma = _small_growing(cloud, seg, p, split_params, size)
    out, added, fit = _free_regions(cloud, seg, wl, free, size, _near_rms_max(seg, p, sigma),
                                    SMALL_SHARE, sigma)
    if added:
        out, added = _small_kept(cloud, seg, out, added, corners=p.small_corners)
    seg.info["small_planes"] = added
    seg.info["small_fit"] = fit
    return _with_added(cloud, seg, out, added) if added else seg


def _small_growing(cloud, seg, p, split_params, size):
    """The small pass's second growing: ``(labels (H, W), sigma)``, its regions of ``size``
    pixels or more and the depth noise (m) as a function of depth its candidates are judged
    by (:func:`_small_planes`; ``benchmarks/no_plane_why.py --small-pass`` follows a box
    through the same steps)."""
    import dataclasses

    from planerel.segment.params import SMALL_SIDE
    from planerel.segment.split import SplitParams

    wp = dataclasses.replace(p, min_region_size=size, far_theta=0.0, far_wide=False,
                             small_scale=0.0, near_wide=0.0)
    sp = split_params if split_params is not None else SplitParams()
    sp = dataclasses.replace(sp, merge_side=max(sp.merge_side, SMALL_SIDE), merge_side_span=0.0)
    # a frame with no measured noise (a Kinect's quantised depth, hunt67) is judged by the
    # split test's sensor model
    return _second_growing(cloud, seg, wp, sp).labels, _noise_sigma(seg, sp)


def _small_kept(cloud, seg, out, added, *, corners=True):
    """Of the ``added`` planes labelled ``n, n + 1, ...`` in ``out`` (H, W) (``n`` the planes of
    ``seg``), those meeting another plane at a corner (with ``corners``): touching (within 2
    px) a plane whose normal lies 60-120 degrees off theirs (a small box's top and side, or a
    side and the table); or standing over one: near it (within the normal window and 2 px:
    the edge between them is in no plane), parallel within
    :data:`~planerel.segment.params.SMALL_PARALLEL` degrees and offset along its normal by
    :data:`~planerel.segment.params.SMALL_RAISE` times the RMS of the looser of the two or
    more (a block's top seen from straight above, its sides hidden, hunt67).  A lone small patch, or one meeting its neighbours at a shallow angle (the
    strips of a curved surface, a crumpled bag's facets), is left unassigned, and so is one
    whose pixels fill under :data:`~planerel.segment.params.SMALL_SOLID` of their convex hull
    in the image (:func:`planerel.segment.shape.mask_solidity`: a strip's, a ring's or a
    crescent's patch, no face of a box).
    Returns ``(labels with the kept planes renumbered n, n + 1, ..., the number kept)``."""
    import math

    import numpy as np
    from scipy.ndimage import binary_dilation, find_objects

    from planerel.segment.params import SMALL_PARALLEL, SMALL_RAISE, SMALL_SOLID
    from planerel.segment.shape import mask_solidity

    n = len(seg.planes)
    xyz = np.asarray(cloud.xyz)
    fits = {p.id: (np.asarray(p.normal, float), np.asarray(p.centroid, float), float(p.rms))
            for p in seg.planes}
    # each added plane's bounding box (label j is object j + 1 of out + 1): the per-plane work
    # reads that box, not the frame (the points in the same row-major order)
    boxes = find_objects(out + 1, max_label=n + added)[n:]
    for j, (rs, cs) in zip(range(n, n + added), boxes, strict=True):
        pts = np.asarray(xyz[rs, cs][out[rs, cs] == j], float)
        cen = pts.mean(0)
        sv, vt = np.linalg.svd(pts - cen, full_matrices=False)[1:]
        fits[j] = (vt[-1], cen, float(sv[-1] / math.sqrt(len(pts))))
    cos_par = math.cos(math.radians(SMALL_PARALLEL))
    reach = 2 + _window(seg)
    h, w = out.shape
    keep = []
    for j, (rs, cs) in zip(range(n, n + added), boxes, strict=True):
        r0, r1 = max(rs.start - reach, 0), min(rs.stop + reach, h)
        c0, c1 = max(cs.start - reach, 0), min(cs.stop + reach, w)
        win = out[r0:r1, c0:c1]
        own = win == j
        if mask_solidity(own) < SMALL_SOLID:
            continue
        ring = binary_dilation(own, iterations=2) & ~own & (win >= 0)
        nj, cj, rj = fits[j]
        if corners and any(abs(float(nj @ fits[k][0])) < 0.5
                           for k in np.unique(win[ring]).tolist()):
            keep.append(j)
            continue
        ring = binary_dilation(own, iterations=reach) & ~own & (win >= 0)
        for k in np.unique(win[ring]).tolist():
            nk, ck, rk = fits[k]
            if (abs(float(nj @ nk)) >= cos_par
                    and abs(float(nk @ (cj - ck))) >= SMALL_RAISE * max(rj, rk)):
                keep.append(j)
                break
    if len(keep) == added:
        return out, added
    remap = np.arange(-1, n + added, dtype=np.int32)  # remap[label + 1]
    remap[n + 1:] = -1
    for i, j in enumerate(keep):
        remap[j + 1] = n + i
    return remap[out + 1], len(keep)


def _raised_tops(cloud, seg, p, split_params, up):
    """``raised_min``: the tops of things standing on the largest level plane (the support,
    within :data:`~planerel.segment.params.RAISED_LEVEL` degrees of ``up`` (3,)), from the
    height over it of the depth the growings left in no plane nearer than ``far_depth``.
    Each 8-connected component of pixels standing ``raised_min`` or more over the support (and
    :data:`~planerel.segment.params.RAISED_SIGMAS` noise sigmas, at most
    :data:`~planerel.segment.params.RAISED_MAX`), of
    :data:`~planerel.segment.params.RAISED_SIZE` times the first growing's least region size
    or more, gives its top band: the pixels within
    :data:`~planerel.segment.params.RAISED_BAND` (or 4 sigmas) of its 90th percentile height,
    their largest 4-connected piece.  The band becomes a plane when it holds
    :data:`~planerel.segment.params.RAISED_SHARE` of the component or more (a box seen from
    above is mostly its top; a bottle's or a fruit's upper band is a narrow cap), its plane
    fits within :data:`~planerel.segment.params.RAISED_RMS` (or 3 sigmas), lies parallel
    to the support within :data:`~planerel.segment.params.RAISED_PARALLEL` degrees, and it is
    a top of its own that ends in a drop (:func:`_own_top`).  A frame the wide fallback grew
    (speckle: the first growing planed little of it) gets no raised top.

    A block's top that the sensor smoothed into a dome (its rim 3-9 mm under its centre over
    5-10 px, session 101) turns its normals through the rim, so no growing keeps it whole; its
    height over the board is 2-12 cm and sharp.  Nothing already in a plane changes.
    ``info["raised_planes"]``: the planes added."""
    import math

    import numpy as np
    from scipy.ndimage import find_objects
    from scipy.ndimage import label as components

    from planerel.segment import params as P
    from planerel.segment.split import SplitParams

    seg.info["raised_planes"] = 0
    if "wide_fallback" in seg.info:
        return seg   # speckle (an R200): the first growing planed under wide_fallback of it
    u = np.asarray(up, float)
    u = u / np.linalg.norm(u)
    cos_level = math.cos(math.radians(P.RAISED_LEVEL))
    level = [pl for pl in seg.planes if abs(float(np.asarray(pl.normal, float) @ u)) >= cos_level]
    if not level:
        return seg
    support = max(level, key=lambda pl: (pl.n_points, -pl.id))
    nrm = np.asarray(support.normal, float)      # towards the sensor: heights over it > 0
    free = _near_free(cloud, seg, p.far_depth)
    if not free.any():
        return seg
    xyz = np.asarray(cloud.xyz, float)
    valid = np.asarray(cloud.valid)
    sigma = _noise_sigma(seg, split_params if split_params is not None else SplitParams())
    pts = xyz[free]
    h = np.full(free.shape, -np.inf)
    h[free] = (pts - np.asarray(support.centroid, float)) @ nrm
    hmin = np.full(free.shape, np.inf)
    hmin[free] = np.maximum(p.raised_min, P.RAISED_SIGMAS * sigma(pts[:, 2]))
    raised = free & (h >= hmin) & (h <= P.RAISED_MAX)
    comp, _ = components(raised, structure=np.ones((3, 3), bool))
    size = max(1, round(P.RAISED_SIZE * int(seg.info.get("min_region_size", 0) or 0)))
    cos_par = math.cos(math.radians(P.RAISED_PARALLEL))
    out = seg.labels.copy()
    n = len(seg.planes)
    added = 0
    for i, box in enumerate(find_objects(comp), start=1):
        if box is None:
            continue
        m = comp[box] == i
        k = int(m.sum())
        if k < size:
            continue
        hb = h[box]
        top = float(np.percentile(hb[m], 90))
        sig = float(sigma(float(np.median(xyz[box][m][:, 2]))))
        depth = max(P.RAISED_BAND, 4.0 * sig)
        band, nb = components(m & (hb >= top - depth))
        if nb == 0:
            continue
        count = np.bincount(band.ravel())
        count[0] = 0
        keep = band == int(np.argmax(count))
        kk = int(keep.sum())
        if kk < size or kk < P.RAISED_SHARE * k:
            continue
        q = xyz[box][keep]
        cen = q.mean(0)
        sv, vt = np.linalg.svd(q - cen, full_matrices=False)[1:]
        rms = float(sv[-1] / math.sqrt(kk))
        if abs(float(vt[-1] @ nrm)) < cos_par or rms > max(P.RAISED_RMS, 3.0 * sig):
            continue
        if not _own_top(xyz, valid, seg.labels, box, keep, support, nrm, top, depth):
            continue
        out[box][keep] = n + added
        added += 1
    seg.info["raised_planes"] = added
    return _with_added(cloud, seg, out, added) if added else seg


def _own_top(xyz, valid, labels, box, keep, support, nrm, top, depth) -> bool:
    """Whether the top band ``keep`` (a mask over the frame's slice ``box``) is a top of its
    own that ends in a drop (:func:`_raised_tops`).  Heights are taken over the ``support``
    plane along its normal ``nrm`` (3,); ``top`` (m) is the band's 90th percentile height and
    ``depth`` (m) how far under it the band reaches.

    - **A drop:** the valid depth :data:`~planerel.segment.params.RAISED_RING` px outside the
      band lies, by its median, :data:`~planerel.segment.params.RAISED_DROP` of ``top`` or more
      under the band's edge.  A box's top ends at its edge (the sensor's smoothing bends it
      over a few pixels: hunt67/90's cubes drop 0.51-1.0 of their height there); a sphere's
      upper band runs on into its slope (a 3 cm cap 1 m away: 0.33, a hemisphere less).
    - **Its own:** under a quarter of the band's 2 px outline lies in a plane (not the
      support) at the band's level: a band around a plane's pixels is that top's rim.
    - **Whole:** the band encloses under :data:`~planerel.segment.params.RAISED_HOLES` of its
      own pixels (a cup's or a bowl's rim goes round its inside: 0.056 on a real LineMOD
      frame; hunt67/90's cube tops 0.025 or less, noise)."""
    import numpy as np
    from scipy.ndimage import binary_dilation, binary_erosion, binary_fill_holes

    from planerel.segment.params import RAISED_DROP, RAISED_HOLES, RAISED_RING

    lo, hi = RAISED_RING
    h, w = valid.shape
    r0, r1 = max(box[0].start - hi, 0), min(box[0].stop + hi, h)
    c0, c1 = max(box[1].start - hi, 0), min(box[1].stop + hi, w)
    band = np.zeros((r1 - r0, c1 - c0), bool)
    band[box[0].start - r0:box[0].stop - r0, box[1].start - c0:box[1].stop - c0] = keep
    ok = valid[r0:r1, c0:c1]
    height = (np.nan_to_num(xyz[r0:r1, c0:c1]) - np.asarray(support.centroid, float)) @ nrm
    near = binary_dilation(band, iterations=2) & ~band & ok
    lab = labels[r0:r1, c0:c1]
    level = near & (lab >= 0) & (lab != support.id) & (np.abs(height - top) <= depth)
    if int(level.sum()) >= 0.25 * int(near.sum()):
        return False
    if int((binary_fill_holes(band) & ~band).sum()) >= RAISED_HOLES * int(band.sum()):
        return False
    ring = binary_dilation(band, iterations=hi) & ~binary_dilation(band, iterations=lo) & ok
    edge = band & ~binary_erosion(band, iterations=2)
    if not ring.any() or not edge.any():
        return False
    return float(np.median(height[edge]) - np.median(height[ring])) >= RAISED_DROP * top


def _far_planes(cloud, seg, p, split_params):
    """``far_theta``: planes where the first growing left depth beyond ``far_depth`` in no
    plane, from a second growing with the wider angle (its regions lying for
    :data:`~planerel.segment.params.FAR_SHARE` or more in that depth); nothing already in a
    plane changes.  ``info["far_planes"]``: the planes added."""
    import dataclasses

    import numpy as np

    from planerel.segment.params import FAR_SHARE

    lab = seg.labels
    z = np.asarray(cloud.xyz[..., 2], float)
    free = np.asarray(cloud.valid) & (lab < 0) & (np.nan_to_num(z) > p.far_depth)
    min_size = int(seg.info.get("min_region_size", 0) or 0)
    if int(free.sum()) < max(min_size, 1):
        seg.info["far_planes"] = 0
        seg.info["far_labels"] = []
        return seg
    wp = dataclasses.replace(p, theta=p.far_theta or p.theta, far_theta=0.0, far_wide=False,
                             far_local=0.0,
                             wide_noise_window=p.wide_noise_window or p.far_wide, small_scale=0.0,
                             near_wide=0.0)
    wl = _second_growing(cloud, seg, wp, split_params).labels
    out, added, fit = _free_regions(cloud, seg, wl, free, min_size, p.far_rms, FAR_SHARE,
                                    local=p.far_local)
    n = len(seg.planes)
    seg.info["far_planes"] = added
    seg.info["far_fit"] = fit
    #: the labels of the planes this growing added (the far gate's provenance)
    seg.info["far_labels"] = list(range(n, n + added))
    return _with_added(cloud, seg, out, added) if added else seg


def _post_process(cloud, seg, p, normals, split_params):
    """The planar post-processing of :func:`segment` (split, merge, absorb, joins)."""
    from planerel.segment.merge import join_pieces, join_wavy, merge_coplanar
    from planerel.segment.split import split_bent_regions

    seg = split_bent_regions(cloud, seg, normals=normals, params=split_params)
    # then crease fragments whose points lie on a neighbour's plane (planerel.segment.absorb)
    absorb = (isinstance(p, RegionGrowParams) and p.adapt
              and (split_params is None or split_params.absorb))
    seg = merge_coplanar(cloud, seg, split_params,
                         absorb_factor=p.refine_factor if absorb else None)
    seg = join_pieces(cloud, seg, split_params)  # itself off at piece_offset 0
    # pieces of faces cut by a wavy sensor's depth (only where the noise model measures it)
    return join_wavy(cloud, seg, split_params)


def _as_bool(value, *, default: bool) -> bool:
    """``None`` -> default; bools as they are; ``"true"/"false"/"1"/"0"/"yes"/"no"``."""
    if value is None:
        return default
    if isinstance(value, bool):
        return value
    text = str(value).strip().lower()
    if text in ("1", "true", "yes", "on"):
        return True
    if text in ("0", "false", "no", "off"):
        return False
    raise InputError(f"split must be true or false, got {value!r}")


def _unique_points(cloud, normals):
    """For an unorganized ``cloud`` with repeated points: ``(cloud of its distinct valid
    points (1, U, 3), their normals or None, indices (V,) of its valid points, inverse (V,)
    into the distinct points)``; None when every valid point is distinct."""
    import numpy as np

    from planerel.io.cloud import Cloud

    flat = np.asarray(cloud.xyz, dtype=np.float64).reshape(-1, 3)
    where = np.flatnonzero(np.isfinite(flat).all(axis=1))
    if len(where) < 2:
        return None
    uniq, first, inverse = np.unique(flat[where], axis=0, return_index=True,
                                     return_inverse=True)
    if len(uniq) == len(where):
        return None
    if len(uniq) < 3:
        raise InputError(f"{cloud.source or 'cloud'}: has {len(where)} valid points but only "
                         f"{len(uniq)} distinct (need at least 3)")
    # the distinct points in the order they first occur (region growing seeds in point order)
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    uniq, first, inverse = uniq[order], first[order], rank[inverse.reshape(-1)]
    sub_normals = None
    if normals is not None:
        sub_normals = np.asarray(normals).reshape(-1, 3)[where[first]][None]
    sub = Cloud(uniq[None], None, cloud.up, cloud.source, organized=False)
    return sub, sub_normals, where, inverse.reshape(-1)


def _spread_labels(seg, cloud, where, inverse):
    """``seg`` (of a cloud's distinct points) on ``cloud``'s own points: each repeated point
    gets its distinct point's label and normal (``info["repeated_points"]`` counts them)."""
    import dataclasses

    import numpy as np

    n = cloud.xyz.shape[0] * cloud.xyz.shape[1]
    labels = np.full(n, -1, dtype=np.int32)
    labels[where] = np.asarray(seg.labels).reshape(-1)[inverse]
    normals = None
    if seg.normals is not None:
        sn = np.asarray(seg.normals).reshape(-1, 3)
        normals = np.full((n, 3), np.nan, dtype=sn.dtype)
        normals[where] = sn[inverse]
        normals = normals.reshape(cloud.xyz.shape)
    info = {**seg.info, "repeated_points": int(len(where) - int(inverse.max()) - 1)}
    return dataclasses.replace(seg, labels=labels.reshape(cloud.xyz.shape[:2]),
                               normals=normals, info=info)
