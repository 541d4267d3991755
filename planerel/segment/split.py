"""Splitting bent regions: a post-processing step after region growing (not in the paper).

Region growing accepts a neighbour whose normal is within ``theta`` (15 degrees) of the region's
base normal, so two surfaces meeting at a shallow crease -- a floor and a ramp of 8-15 degrees,
or faces whose crease normals blend gradually -- grow into one region.  Such a region does not
fit one plane: its least-squares residual is far above the sensor noise expected at its depth.

:func:`split_bent_regions`, per region:

1. **Residual test.**  Expected point-to-plane noise per point (Kinect-like model, see
   :class:`SplitParams`): depth std ``sigma_z(z)^2 = (noise z^2)^2 + (q z^2)^2 / 12 +
   unit^2 / 12`` with ``q = disparity_step / (focal_px * baseline)``, projected on the plane
   normal (``sigma_z * |n . (x/z, y/z, 1)|``).  With ``local_noise`` the model is raised to the
   region's own high-frequency noise (second differences of the residual along rows and
   columns), so a sensor noisier than the model does not look bent.  The region is a candidate
   when its RMS residual exceeds ``tolerance`` times the expected RMS.
2. **Planar parts.**  Sequential seeded RANSAC over the region's points: hypotheses from three
   points and from one point with its normal, scored on a regular sample by the number of
   points within ``inlier_sigmas`` expected sigmas; the best is refined by least squares on its
   inliers; its inliers are removed and the next part is sought in the rest, while at least
   ``min_region_size`` points remain and agree (at most ``max_parts``).
3. **Assignment.**  Every point goes to the part with the smallest normalised distance
   ``|d| / sigma`` (none if it exceeds ``assign_sigmas``); planes are refitted and points
   reassigned (``iterations`` times).
4. **Pieces.**  The 8-connected image-grid components of each part; a component of at least
   ``min_region_size`` points is a new region; smaller ones give their points to the adjacent
   kept piece whose plane they fit (within ``assign_sigmas``) or become unassigned.  The split is
   kept only when it yields two or more pieces; otherwise the region is left as it was.

Labels are renumbered deterministically: regions in their original order, the pieces of a split
region in its place, ordered by their first pixel (row-major).  Planes are refitted by PCA.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass

import numpy as np

from planerel.errors import InputError
from planerel.segment.params import _bool, _int, _num, coerce_params, scaled_min_region_size
from planerel.segment.result import Segmentation, SegPlane
from planerel.segment.wavy_fit import wavy_model, wavy_sheet_fits

__all__ = ["SplitParams", "split_bent_regions", "expected_sigma"]

#: A small leftover piece is "on" a found surface only when their planes are within this
#: angle (degrees) of each other (see :func:`_drop_small_on_found`; faces22).
FOUND_PARALLEL_DEG = 30.0

#: Per thread: a flat int32 pixel map, all -1 between calls (see :func:`_cellmap`).
_CELLMAPS = threading.local()


@dataclass(frozen=True)
class SplitParams:
    """Parameters of :func:`split_bent_regions`.

    Parameters
    ----------
    tolerance : float
        A region is tested for a split when its RMS point-to-plane residual exceeds
        ``tolerance`` times the RMS residual the noise model expects for its points: 1.5 (true
        planes of the synthetic Kinect data measure 0.95-1.1; a 8-degree floor + ramp measures
        above 4).  Must be >= 1.
    noise : float
        Depth noise coefficient: std ``noise * z^2`` metres (Kinect: 0.0012).
    disparity_step : float
        Disparity quantisation in pixels (Kinect: 1/8); 0 = none.
    baseline, focal_px : float
        Baseline (m) and focal length (px, at the sensor's native 640x480) of the disparity
        sensor: depth step ``disparity_step * z^2 / (focal_px * baseline)``.
    depth_unit : float
        Depth resolution in metres (1 mm).
    local_noise : bool
        Raise the model noise of each region to its measured high-frequency noise (see the
        module docstring), so that a noisier sensor than the model does not split true planes.
    inlier_sigmas : float
        Half-width of a part's inlier band, in expected sigmas (3).
    assign_sigmas : float
        A point farther than this many sigmas from every part's plane becomes unassigned (4).
        Must be >= ``inlier_sigmas``.
    max_parts : int
        Planar parts sought per region at most (6).
    hypotheses : int
        RANSAC hypotheses per part (64): half from three points, half from one point and its
        normal (all from three points without normals).
    sample : int
        Hypotheses are scored on a regular sample of about this many points (1000).
    iterations : int
        Assign / refit rounds after the parts are found (2).
    min_region_size : int or "auto"
        Smallest piece kept; ``"auto"``: the segmentation's own (``seg.info["min_region_size"]``,
        else 90 at 160x120 scaled with the pixel count).
    seed : int
        Seed of the random hypotheses: same input, same seed, same output.
    leftover : bool
        Also search the connected patches of still unassigned valid pixels (organized clouds,
        at least ``min_region_size`` points) for planar pieces, as for a bent region but
        keeping a single piece too (True).  Small faces far from the sensor -- the top risers
        and treads of a staircase, 3-8 pixels high at 160x120 -- have normals too blended and
        noisy for region growing to seed them, yet their points fit planes within the noise.
    leftover_scale : float
        Patches smaller than ``min_region_size`` but at least ``leftover_scale`` x it are
        searched too, for one piece of their own size; such a piece is dropped when half of
        its points lie within ``parallel_gap`` x depth of the plane of a region of at least
        ``min_region_size`` points (a surface already found).  1 (the default): off.  0.5
        finds small far box faces of the judge set (docs/objects.md, ninth pass) but changes
        what ``make demo`` learns (a box rule that also fires on a non-box of the real Kinect
        frames), so it is not the default.
    small_faces : int
        Patches smaller than ``min_region_size`` but at least ``max(small_faces, floor)``
        points are searched as ``leftover_scale`` describes, where ``floor`` is the adapted
        segmentation's resolution floor (``info["settings"]["min_region_floor"]``: a quarter of
        the paper's 90 px at 160x120 scaled with the pixel count, 360 at 640x480).  The noise
        term of the adapted minimum region, ``(20 sigma / footprint)^2`` pixels at the scene's
        median depth, rejects whole box faces of 150-850 px on a noisy sensor (the table-top
        judge set: 460-1070 px); a leftover piece must pass the planarity test against the noise
        model itself, so it may be smaller, down to the size at which region growing's normals
        are trusted (the floor).  Where the floor already sets the minimum region (the real
        Kinect and mOSD frames) nothing changes; ``small_faces`` = 150 keeps the search off
        where the minimum region is under 150 points (the 160x120 training world: 71-96 px).
        0 (the default): off, today's output.  150 finds 10 more box faces in 40 table-top
        scenes but moves the judge sets' found / false figures only within their noise (false
        proposals +0.02-0.05 a frame on three of five sets: real table legs, a bowl's flat
        bottom), so it is not the default (docs/objects.md, "Small box faces (faces22)").
        Segmentations not adapted to the noise have no floor: off too.
    merge : bool
        Merge touching regions of one plane afterwards (True; :mod:`planerel.segment.merge`).
    absorb : bool
        Then dissolve fragments whose points lie on a touching larger region's plane (True;
        :mod:`planerel.segment.absorb`); :func:`planerel.segment.segment` runs it when region
        growing adapts to the sensor (``adapt=True``, the default).
    merge_angle : float
        Largest angle in degrees between the normals of two regions that may merge (10).
    merge_gap : int
        Regions touch when pixels of both lie within this many pixels (2) ...
    merge_jump : float
        ... and their points within ``merge_jump * z`` metres (0.05).
    merge_side : float
        With ``merge_side`` > 0 (3, the default since span91), each of the two must also
        fit the union's plane within ``merge_side`` times the union test's bound on its own;
        0: the pooled test only.  The union's RMS is mostly its larger side's, so with the
        pooled test alone a block's top 2-4 cm over the board it stands on merges into the
        board (tote67, docs/segmentation.md "A small top over a large plane").
    merge_side_span : float
        With ``merge_side`` > 0, the side test holds for a pair whose smaller region's
        largest in-plane standard deviation is at most this (metres; a square top of side
        ``s`` has ``0.29 s``): 0.02 (the default) keeps a block's top of up to about 7 cm
        off the board, while a laptop's base or a book 2 cm over a table still merges by the
        pooled test (for every pair, 0, the rules re-learned lose the lying clause's bound:
        the laptops' bases split off as flat tops; span91).
    min_split_angle, parallel_gap : float
        Planar parts of a region whose planes differ by less than ``min_split_angle`` degrees
        (3) and lie within ``parallel_gap`` x depth (0.02: 2 cm at 1 m) of each other's points
        are one surface: real depth sensors bend large planes slightly (a Kinect floor by a
        few millimetres over a metre), so such a floor fails the residual test and RANSAC cuts
        it into parallel slabs 0.1-0.5 degrees apart; a floor and an 8-degree ramp differ by 8
        degrees, a stair tread and the floor by a riser.  The merge step compares nearly
        parallel regions' union with their own RMS as well (:mod:`planerel.segment.merge`).
        ``min_split_angle`` 0 turns both off.
    piece_offset : float
        Last, touching regions whose normals lie more than ``min_split_angle`` and at most
        ``merge_angle`` degrees apart are joined when the smaller one's points lie within
        ``piece_offset`` metres RMS of the larger one's plane (0.005): pieces of one face a
        real sensor bends by more than its noise (:func:`planerel.segment.merge.join_pieces`).
        0 turns it off.
    wavy_join : bool
        Then, on a frame whose noise model measures wavy depth (an active-stereo sensor's:
        :attr:`planerel.segment.noise.NoiseModel.wavy`), join touching pieces of one face
        whose union fits a plane within that waviness (True;
        :func:`planerel.segment.merge.join_wavy`).  Frames that are not wavy are unchanged.
    wavy_leftover : bool
        On a wavy frame, a plane found in an unassigned patch (the ``leftover`` step) that
        fails the planarity test against the noise model is still kept when it fits within the
        measured waviness as :func:`planerel.segment.merge.join_wavy` judges a union
        (:func:`planerel.segment.wavy_fit.wavy_sheet_fits`: ``tolerance x wave x sigma(z)`` grown
        with the extent, at most ``WAVE_LEFTOVER_MAX_RMS`` = 8 mm, a flat sheet when long;
        ``info["leftover_wavy"]`` counts them).  True; frames that are not wavy are unchanged.
    hole_bridge : int
        The merge also tests regions that a hole in the depth (pixels with no depth, no valid
        unassigned pixel between) separates by at most ``2 x hole_bridge`` pixels of its
        160x120 sample grid (:func:`planerel.segment.merge.hole_pairs`): a riser or tread a
        stereo sensor's holes cut into pieces (srob59, docs/segmentation.md).  The same
        union test decides.  0 (the default): off.
    """

    tolerance: float = 1.5
    noise: float = 0.0012
    disparity_step: float = 0.125
    baseline: float = 0.075
    focal_px: float = 525.0
    depth_unit: float = 0.001
    local_noise: bool = True
    inlier_sigmas: float = 3.0
    assign_sigmas: float = 4.0
    max_parts: int = 6
    hypotheses: int = 64
    sample: int = 1000
    iterations: int = 2
    min_region_size: int | str = "auto"
    seed: int = 0
    leftover: bool = True
    leftover_scale: float = 1.0
    small_faces: int = 0
    merge: bool = True
    absorb: bool = True
    merge_angle: float = 10.0
    merge_gap: int = 2
    merge_jump: float = 0.05
    merge_side: float = 3.0
    merge_side_span: float = 0.02
    min_split_angle: float = 3.0
    parallel_gap: float = 0.02
    piece_offset: float = 0.005
    wavy_join: bool = True
    wavy_leftover: bool = True
    hole_bridge: int = 0

    def __post_init__(self) -> None:
        o = "split"
        s = object.__setattr__
        s(self, "tolerance", _num(o, "tolerance", self.tolerance, lo=1.0))
        s(self, "noise", _num(o, "noise", self.noise, lo=0.0))
        s(self, "disparity_step", _num(o, "disparity_step", self.disparity_step, lo=0.0))
        s(self, "baseline", _num(o, "baseline", self.baseline, lo=0.0, lo_open=True))
        s(self, "focal_px", _num(o, "focal_px", self.focal_px, lo=0.0, lo_open=True))
        s(self, "depth_unit", _num(o, "depth_unit", self.depth_unit, lo=0.0))
        if self.noise == 0 and self.disparity_step == 0 and self.depth_unit == 0:
            raise InputError(f"{o}: the noise model is zero (noise, disparity_step and depth_unit "
                             "are all 0); give at least one of them a positive value")
        s(self, "local_noise", _bool(o, "local_noise", self.local_noise))
        s(self, "inlier_sigmas", _num(o, "inlier_sigmas", self.inlier_sigmas, lo=0.0, lo_open=True))
        s(self, "assign_sigmas", _num(o, "assign_sigmas", self.assign_sigmas, lo=0.0, lo_open=True))
        if self.assign_sigmas < self.inlier_sigmas:
            raise InputError(f"{o}: assign_sigmas ({self.assign_sigmas}) must be >= inlier_sigmas "
                             f"({self.inlier_sigmas})")
        s(self, "max_parts", _int(o, "max_parts", self.max_parts, 2))
        s(self, "hypotheses", _int(o, "hypotheses", self.hypotheses, 1))
        s(self, "sample", _int(o, "sample", self.sample, 3))
        s(self, "iterations", _int(o, "iterations", self.iterations, 0))
        if isinstance(self.min_region_size, str):
            if self.min_region_size != "auto":
                raise InputError(f"{o}: min_region_size must be 'auto' or an integer, "
                                 f"got {self.min_region_size!r}")
        else:
            s(self, "min_region_size", _int(o, "min_region_size", self.min_region_size, 3))
        s(self, "seed", _int(o, "seed", self.seed, 0))
        s(self, "leftover", _bool(o, "leftover", self.leftover))
        s(self, "leftover_scale", _num(o, "leftover_scale", self.leftover_scale, lo=0.0, hi=1.0,
                                       lo_open=True))
        s(self, "small_faces", _int(o, "small_faces", self.small_faces, 0))
        s(self, "merge", _bool(o, "merge", self.merge))
        s(self, "absorb", _bool(o, "absorb", self.absorb))
        s(self, "merge_angle", _num(o, "merge_angle", self.merge_angle, lo=0.0, hi=90.0))
        s(self, "merge_gap", _int(o, "merge_gap", self.merge_gap, 1))
        s(self, "merge_jump", _num(o, "merge_jump", self.merge_jump, lo=0.0, lo_open=True))
        s(self, "merge_side", _num(o, "merge_side", self.merge_side, lo=0.0))
        s(self, "merge_side_span", _num(o, "merge_side_span", self.merge_side_span, lo=0.0))
        s(self, "piece_offset", _num(o, "piece_offset", self.piece_offset, lo=0.0))
        s(self, "wavy_join", _bool(o, "wavy_join", self.wavy_join))
        s(self, "wavy_leftover", _bool(o, "wavy_leftover", self.wavy_leftover))
        s(self, "hole_bridge", _int(o, "hole_bridge", self.hole_bridge, 0))
        s(self, "min_split_angle", _num(o, "min_split_angle", self.min_split_angle, lo=0.0,
                                        hi=90.0))
        s(self, "parallel_gap", _num(o, "parallel_gap", self.parallel_gap, lo=0.0))

    def depth_sigma2(self, z: np.ndarray) -> np.ndarray:
        """Variance (m^2) of a depth measurement at depth ``z`` (m), any shape."""
        z2 = z * z
        q = self.disparity_step / (self.focal_px * self.baseline)
        return (self.noise * z2) ** 2 + (q * z2) ** 2 / 12.0 + self.depth_unit ** 2 / 12.0


def expected_sigma(xyz, normal, params: SplitParams | None = None) -> np.ndarray:
    """Expected std (m) of the point-to-plane distance of each point under the noise model.

    Parameters
    ----------
    xyz : ndarray, shape (N, 3)
        Points (z > 0).
    normal : ndarray, shape (3,) or (N, 3)
        Unit plane normal (per point or shared).
    params : SplitParams, optional

    Returns
    -------
    ndarray, shape (N,)
        ``sigma_z(z) * |n . (x/z, y/z, 1)|``: depth noise moves a point along its ray.
    """
    p = params if params is not None else SplitParams()
    xyz = np.asarray(xyz, dtype=np.float64)
    z = xyz[:, 2]
    nrm = np.asarray(normal, dtype=np.float64)
    # z <= 0 only in a cloud that is not in its camera's frame (read warns of it): no noise
    # model holds there, and the NaN it gives is no user's error to print
    with np.errstate(divide="ignore", invalid="ignore"):
        proj = np.abs(xyz @ nrm if nrm.ndim == 1 else np.einsum("ij,ij->i", xyz, nrm)) / z
    return np.sqrt(p.depth_sigma2(z)) * proj


def _make_params(params, kw) -> SplitParams:
    if params is not None:
        if kw:
            raise InputError("split: give either params=<SplitParams> or keyword parameters, not both")
        if not isinstance(params, SplitParams):
            raise InputError(f"split: params must be SplitParams, got {type(params).__name__}")
        return params
    return coerce_params(SplitParams, kw)


def split_bent_regions(cloud, seg: Segmentation, *, normals=None, params: SplitParams | None = None,
                       **kw) -> Segmentation:
    """Split regions that do not fit one plane into planar, connected parts.

    Parameters
    ----------
    cloud : Cloud
        The cloud ``seg`` was computed from, ``(H, W, 3)``.
    seg : Segmentation
        Any method's result; ``labels`` (H, W) int32.
    normals : ndarray, shape (H, W, 3), optional
        Per-pixel normals (NaN = unknown) for the one-point hypotheses; default ``seg.normals``
        (three-point hypotheses only when neither is given).
    params : SplitParams, optional
        Or the fields of :class:`SplitParams` as keywords.

    Returns
    -------
    Segmentation
        Same method, params and normals as ``seg``; labels renumbered ``0 .. n-1`` (see the module
        docstring), planes refitted; ``info`` adds ``split_tested`` (regions over the residual
        tolerance), ``split_regions`` (regions split), ``split_new_regions`` (regions added),
        ``split_unassigned`` (points left unassigned by splits), ``leftover_patches`` /
        ``leftover_regions`` (unassigned patches searched, planes found in them; on a wavy frame
        ``leftover_wavy``, those kept by the waviness test) and
        ``noise_scale`` (median ratio of the measured to the modelled noise of the regions).
        Planes found in unassigned patches are numbered after all others.  ``seg`` itself
        when nothing changed, with the same ``info`` additions.

    Raises
    ------
    InputError
        Not a Cloud / Segmentation, shapes that disagree, bad parameters.
    """
    from planerel.io.cloud import Cloud
    from planerel.segment._post_kernels import label_counts

    p = _make_params(params, kw)
    if not isinstance(cloud, Cloud):
        raise InputError(f"split: expected a planerel Cloud, got {type(cloud).__name__}")
    if not isinstance(seg, Segmentation):
        raise InputError(f"split: expected a Segmentation, got {type(seg).__name__}")
    h, w, _ = cloud.xyz.shape
    if seg.labels.shape != (h, w):
        raise InputError(f"split: labels shape {seg.labels.shape} differs from the cloud's {(h, w)}")
    nrm = normals if normals is not None else seg.normals
    if nrm is not None:
        nrm = np.asarray(nrm)  # float64 only for the points a split looks at
        if nrm.shape != (h, w, 3):
            raise InputError(f"split: normals shape {nrm.shape} differs from the cloud's {(h, w, 3)}")
    if p.min_region_size == "auto":
        min_size = int(seg.info.get("min_region_size", scaled_min_region_size(h * w)))
    else:
        min_size = int(p.min_region_size)

    n = seg.n_planes
    labels = seg.labels
    info = dict(seg.info)
    info.update(split_tested=0, split_regions=0, split_new_regions=0, split_unassigned=0,
                split_parallel=0, leftover_patches=0, leftover_regions=0)
    xyz = cloud.xyz
    lab = labels.reshape(-1)
    xyz_flat = xyz.reshape(-1, 3)
    cnt, status = label_counts(np.ascontiguousarray(lab, dtype=np.int32),
                               cloud.valid.reshape(-1), n)
    if status == 1:
        raise InputError(f"split: labels must lie in -1..{n - 1} (the segmentation has {n} planes)")
    if status == 2:
        raise InputError("split: some labelled pixels have no valid point")

    def normals_of(pix):
        # the flat normals (float32); _split_one converts only the sample it uses
        return None if nrm is None else nrm.reshape(-1, 3)

    new_lab = None
    extra: dict[int, list] = {}
    # the pixels whose labels changed, per split region or leftover patch, and the labels
    # each group's pixels now carry (its refitted regions: none has a pixel outside it)
    changed: list[np.ndarray] = []
    owned: list[list[int]] = []
    next_id = n
    n_unassigned = 0
    sensor_scale = 1.0
    if n:
        pn = np.array([pl.normal for pl in seg.planes])
        po = np.array([pl.offset for pl in seg.planes])
        rms, exp_rms, local = _residual_stats(xyz, labels, pn, po, n, p, cloud.organized)
        scale = np.ones(n)
        if p.local_noise:
            ok = np.isfinite(local) & (local > exp_rms) & (exp_rms > 0)
            scale[ok] = local[ok] / exp_rms[ok]
            sensor_scale = float(np.median(scale))
        info["noise_scale"] = sensor_scale
        with np.errstate(invalid="ignore"):
            bent = np.flatnonzero((rms > p.tolerance * exp_rms * scale) & (cnt >= 2 * min_size))
        info["split_tested"] = int(len(bent))
        # the pixels of every tested region, grouped by a counting sort (ascending per region)
        from planerel.segment._split_kernels import group_pixels

        sel = np.zeros(n + 1, dtype=bool)
        sel[bent + 1] = True
        idx, starts = group_pixels(lab, sel)
        for r in bent:
            pix = idx[starts[r + 1]:starts[r + 2]]
            piece = _split_one(pix, xyz_flat, normals_of(pix), scale[r],
                               min_size, p, w, cloud.organized,
                               np.random.default_rng([p.seed, int(r)]), stats=info)
            if piece is None:
                continue
            if new_lab is None:
                new_lab = lab.copy()
            # pieces ordered by their first pixel (pix is ascending): the first keeps the id r
            k = int(piece.max()) + 1
            first = np.array([int(np.argmax(piece == q)) for q in range(k)])
            rank = np.argsort(first, kind="stable")
            ids = np.empty(k, dtype=np.int64)
            ids[rank[0]] = r
            ids[rank[1:]] = next_id + np.arange(k - 1)
            extra[int(r)] = list(range(next_id, next_id + k - 1))
            changed.append(pix)
            owned.append([int(r), *extra[int(r)]])
            next_id += k - 1
            new_lab[pix] = np.where(piece >= 0, ids[np.maximum(piece, 0)], -1)
            n_unassigned += int((piece < 0).sum())
            info["split_regions"] += 1
            info["split_new_regions"] += k - 1
    info["split_unassigned"] = n_unassigned

    leftover_ids: list[int] = []
    if p.leftover and cloud.organized:
        # the measured waviness (None: not a wavy frame, or off), for the planarity test
        wavy = wavy_model(seg.info) if p.wavy_leftover else None
        if wavy is not None:  # (frames that are not wavy: info as before)
            info["leftover_wavy"] = 0
        cur = lab if new_lab is None else new_lab
        lo_size = max(3, int(round(min_size * p.leftover_scale)))
        floor = (seg.info.get("settings") or {}).get("min_region_floor")
        if p.small_faces > 0 and floor is not None and seg.info["settings"].get("adapted"):
            lo_size = min(lo_size, max(p.small_faces, int(floor)))
        # planes of the regions of at least the minimum size (surfaces already found), needed
        # only when patches under that size are searched
        big_planes = ([(np.asarray(q.normal, dtype=np.float64), float(q.offset))
                       for q in seg.planes if q.n_points >= min_size] if lo_size < min_size else [])
        for t, pix in enumerate(_free_patches(cur.reshape(h, w), cloud.valid, lo_size)):
            info["leftover_patches"] += 1
            # a patch of at least the minimum size is searched for pieces of that size, as
            # before; a smaller one (down to lo_size) for one piece of its own size
            part_min = min_size if len(pix) >= min_size else lo_size
            piece = _split_one(pix, xyz_flat, normals_of(pix),
                               sensor_scale, part_min, p, w, True,
                               np.random.default_rng([p.seed, n + t]), min_parts=1)
            if piece is not None:
                P = xyz_flat.take(pix, axis=0)
                piece = _keep_planar(piece, P, sensor_scale, p, wavy, info)
                if piece is not None and lo_size < min_size:
                    piece = _drop_small_on_found(piece, P, min_size, big_planes, p)
            if piece is None:
                continue
            if new_lab is None:
                new_lab = lab.copy()
            k = int(piece.max()) + 1
            new_lab[pix] = np.where(piece >= 0, next_id + piece, -1)
            leftover_ids.extend(range(next_id, next_id + k))
            changed.append(pix)
            owned.append(list(range(next_id, next_id + k)))
            next_id += k
            info["leftover_regions"] += k
    if new_lab is None:
        return Segmentation(labels, seg.planes, seg.method, seg.params, seg.normals, info)
    # deterministic renumbering: original order, new pieces right after their region,
    # planes from unassigned patches last
    final_order = []
    for r in range(n):
        final_order.append(r)
        final_order.extend(extra.get(r, []))
    final_order.extend(leftover_ids)
    remap = np.full(next_id + 1, -1, dtype=np.int32)
    remap[np.array(final_order, dtype=np.int64) + 1] = np.arange(next_id, dtype=np.int32)
    # refit only the regions whose pixels changed (split regions and leftover patches), from
    # all their pixels in pixel order (the sums of a full refit), visiting only those pixels
    refit = [new for new, old in enumerate(final_order) if old >= n or old in extra]
    sub = np.full(next_id + 1, -1, dtype=np.int64)
    sub[np.array(refit, dtype=np.int64) + 1] = np.arange(len(refit))
    out, fits = _relabel_refit_changed(new_lab, remap, sub[remap + 1], xyz_flat, len(refit),
                                       changed, owned)
    fit_of = dict(zip(refit, fits, strict=True))
    planes = tuple(fit_of[new].with_id(new) if new in fit_of else seg.planes[old].with_id(new)
                   for new, old in enumerate(final_order))
    return Segmentation(out.reshape(h, w), planes, seg.method, seg.params, seg.normals, info)


def _relabel_refit(labels, remap, row, xyz_flat, nrow):
    """``remap[labels + 1]`` (N,) int32 and the planes (:meth:`SegPlane.from_fits`) of the
    ``nrow`` regions to refit, old label ``l`` feeding row ``row[l + 1]`` (-1: none), fitted
    to their pixels in pixel order, in one pass (what ``fit_planes`` of those pixels gives)."""
    from planerel.segment._kernels import planes_from_sums
    from planerel.segment._post_kernels import relabel_moments

    out, sums, ref = relabel_moments(np.ascontiguousarray(labels, dtype=np.int32),
                                     np.ascontiguousarray(remap, dtype=np.int32),
                                     np.ascontiguousarray(row, dtype=np.int64),
                                     np.ascontiguousarray(xyz_flat), int(nrow))
    return out, SegPlane.from_fits(*planes_from_sums(sums, ref, int(nrow)))


def _relabel_refit_changed(labels, remap, row, xyz_flat, nrow, changed, owned):
    """:func:`_relabel_refit` when the regions to refit lie in known pixel groups: ``changed``
    (ascending flat pixels per group) and ``owned`` (the labels, before ``remap``, of each
    group's regions; no pixel of them lies outside the group).  Each row's points are summed
    in pixel order from its group's pixels alone (the same additions as the whole image's
    pass), and the image is only relabelled."""
    from planerel.segment._kernels import planes_from_sums
    from planerel.segment._post_kernels import group_moments, relabel

    labels = np.ascontiguousarray(labels, dtype=np.int32)
    out = relabel(labels, np.ascontiguousarray(remap, dtype=np.int32))
    owner = np.full(len(remap), -1, dtype=np.int64)
    for g, ids in enumerate(owned):
        owner[np.array(ids, dtype=np.int64) + 1] = g
    row = np.ascontiguousarray(row, dtype=np.int64)
    sums = np.zeros((int(nrow), 10))
    ref = np.zeros((int(nrow), 3))
    pts = np.ascontiguousarray(xyz_flat)
    for g, pix in enumerate(changed):
        group_moments(pts, pix, labels, row, owner, g, sums, ref)
    return out, SegPlane.from_fits(*planes_from_sums(sums, ref, int(nrow)))


def _surfaces(planes, Q, part, p: SplitParams) -> np.ndarray:
    """Group index per planar part: parts whose planes lie within ``min_split_angle`` of each
    other and within ``parallel_gap`` x depth of each other's centroid (of their sample points
    ``Q[part == j]``) are one surface, bent by the sensor (parts with no sample point stay
    alone).  Groups are numbered by their first part."""
    k = len(planes)
    parent = list(range(k))
    if p.min_split_angle <= 0 or k < 2:
        return np.arange(k)
    from planerel.segment._split_kernels import part_centroids

    cos_min = math.cos(math.radians(p.min_split_angle))
    mean, count = part_centroids(np.ascontiguousarray(Q, dtype=np.float64),
                                 np.ascontiguousarray(part, dtype=np.int64), k)
    cen = [mean[j] if count[j] else None for j in range(k)]

    def root(i):
        while parent[i] != i:
            i = parent[i]
        return i

    for a in range(k):
        for b in range(a + 1, k):
            if cen[a] is None or cen[b] is None:
                continue
            (na, oa), (nb, ob) = planes[a], planes[b]
            if abs(float(na @ nb)) < cos_min:
                continue
            if (abs(float(na @ cen[b]) + oa) <= p.parallel_gap * cen[b][2]
                    and abs(float(nb @ cen[a]) + ob) <= p.parallel_gap * cen[a][2]):
                ra, rb = root(a), root(b)
                parent[max(ra, rb)] = min(ra, rb)
    roots = [root(i) for i in range(k)]
    first = sorted(set(roots))
    return np.array([first.index(r) for r in roots], dtype=np.int64)


#: The largest RMS (m) of a plane kept from an unassigned patch of a wavy frame by the waviness
#: test (``wavy_leftover``), whatever the waviness.
WAVE_LEFTOVER_MAX_RMS = 0.008


def _keep_planar(piece, P, scale, p: SplitParams, wavy: dict | None = None, stats=None):
    """Pieces found in an unassigned patch that pass the split test themselves (RMS residual
    within ``tolerance`` x the expected RMS), renumbered ``0..``; None when none does.  Far
    from the sensor a plane through the nosings of several thin stair steps can hold enough
    points within the noise band to win RANSAC, but its points spread over the whole band.
    ``wavy``: the noise model of a wavy frame; a piece failing that test is still kept when it
    fits within the measured waviness (:func:`planerel.segment.wavy_fit.wavy_sheet_fits`; counted
    in ``stats["leftover_wavy"]``)."""
    k = int(piece.max()) + 1
    new = np.full(k, -1, dtype=np.int64)
    kept = 0
    for q in range(k):
        Q = P[piece == q]
        nr, off = _fit(Q)
        rms = math.sqrt(float(np.mean((Q @ nr + off) ** 2)))
        exp = scale * math.sqrt(float(np.mean(expected_sigma(Q, nr, p) ** 2)))
        ok = rms <= p.tolerance * exp
        if not ok and wavy is not None and wavy_sheet_fits(Q, wavy, p.tolerance,
                                                           WAVE_LEFTOVER_MAX_RMS):
            ok = True
            if stats is not None:
                stats["leftover_wavy"] = stats.get("leftover_wavy", 0) + 1
        if ok:
            new[q] = kept
            kept += 1
    if kept == 0:
        return None
    return np.where(piece >= 0, new[np.maximum(piece, 0)], -1)


def _drop_small_on_found(piece, P, min_size, big_planes, p: SplitParams):
    """Pieces of a leftover patch under ``min_size`` points (kept down to ``leftover_scale``
    x it) whose points lie on a surface already found are dropped: a piece is dropped when at
    least half of its points lie within ``parallel_gap`` x depth of the plane of a region of
    at least ``min_size`` points and the two planes lie within :data:`FOUND_PARALLEL_DEG` of
    each other (a real floor's bent corner, 7 mm off the table's plane on mOSD; a small box
    face stands off every larger plane, and a box's side face standing on the table is not
    parallel to it, although half of a 4-cm face lies within 2 cm of the table's plane).
    Renumbered ``0..``; None when none is left."""
    k = int(piece.max()) + 1
    new = np.full(k, -1, dtype=np.int64)
    kept = 0
    cos_par = math.cos(math.radians(FOUND_PARALLEL_DEG))
    for q in range(k):
        Q = P[piece == q]
        on = False
        if len(Q) < min_size:
            band = p.parallel_gap * np.abs(Q[:, 2])
            nq, _ = _fit(Q)
            for nr, off in big_planes:
                if abs(float(nq @ nr)) < cos_par:
                    continue  # a face standing on the surface, not a piece of it
                if np.mean(np.abs(Q @ nr + off) <= band) >= 0.5:
                    on = True
                    break
        if not on:
            new[q] = kept
            kept += 1
    if kept == 0:
        return None
    return np.where(piece >= 0, new[np.maximum(piece, 0)], -1)


def _free_patches(labels, valid, min_size):
    """Flat pixel indices (ascending) of each 8-connected patch of valid unassigned pixels
    with at least ``min_size`` pixels, patches ordered by their first pixel (row-major)."""
    from planerel.segment._post_kernels import free_patches

    h, w = labels.shape
    order, starts = free_patches(np.ascontiguousarray(labels, dtype=np.int32).reshape(-1),
                                 np.ascontiguousarray(valid).reshape(-1), w, int(min_size))
    return [order[starts[i]:starts[i + 1]] for i in range(len(starts) - 1)]


#: Points per region used to find the planar parts (a regular sample of larger regions).
_DISCOVERY_POINTS = 4000
#: Pixels of the regular grid sample used for the residual test.
_TEST_PIXELS = 160 * 120


def _residual_stats(xyz, labels, pn, po, n, p: SplitParams, organized):
    """Per region, on a regular grid sample of about ``_TEST_PIXELS`` pixels: RMS residual to
    the region's plane, RMS expected by the noise model, and the high-frequency noise (std of
    the second differences of the residual along rows and columns, ``sqrt(mean(dd^2) / 6)``;
    NaN for unorganized clouds or without three aligned samples).  Arrays of shape (n,)."""
    from planerel.segment._split_kernels import residual_stats_grid

    h, w = labels.shape
    s = max(1, int(math.sqrt(h * w / _TEST_PIXELS)))
    if not organized:
        s = 1
    q = p.disparity_step / (p.focal_px * p.baseline)
    return residual_stats_grid(xyz[::s, ::s], np.asarray(labels[::s, ::s], dtype=np.int32),
                               np.ascontiguousarray(pn, dtype=np.float64),
                               np.ascontiguousarray(po, dtype=np.float64), int(n),
                               float(p.noise), float(q), float(p.depth_unit), bool(organized))


def _fit(P) -> tuple[np.ndarray, float]:
    """Least-squares plane (unit normal, offset) of points ``P`` (m, 3), m >= 3."""
    from planerel.segment._post_kernels import plane_fit

    nr, off = plane_fit(np.ascontiguousarray(P, dtype=np.float64))
    return nr, float(off)


def _products(P, planes) -> np.ndarray:
    """``(k, m)``: ``P @ n`` of each plane ``(n, offset)`` of ``planes`` (numpy's products: a
    point's normalised distance to a plane is ``|n . p + off| * zs / max(|n . p|, 1e-12)``,
    ``zs`` = z / (depth std), so that ``sigma = |n . p| / zs``)."""
    return np.stack([P @ nr for nr, _ in planes])


def _split_one(pix, X, N, scale, min_size, p: SplitParams, w, organized, rng, min_parts=2,
               stats=None):
    """Pieces of one region: ``(len(pix),)`` kept-piece index per point (-1 = unassigned), or
    None when fewer than ``min_parts`` pieces are found (the region stays as it was).  ``pix``
    (m,) ascending flat pixel indices, ``X`` (H*W, 3) the image's flat points (the region's
    are gathered only when it splits: most tested regions do not), ``N`` (H*W, 3) the
    image's flat normals or None; the point-to-plane sigma of a plane ``n`` is ``scale *
    sigma_z(z) * |n . p| / z``."""
    from planerel.segment._post_kernels import absorb_small, assign_parts, depth_scales, part_pieces
    from planerel.segment._split_kernels import assign_refit, inliers_fit, sample_normals

    m = len(pix)
    q = p.disparity_step / (p.focal_px * p.baseline)
    st = max(1, m // _DISCOVERY_POINTS)
    # (take: a row gather several times faster than fancy indexing, the same values)
    Q = X.take(pix[::st], axis=0)  # the points P[::st] of the region's points P = X[pix]
    zs = depth_scales(np.ascontiguousarray(Q[:, 2]), float(scale), float(p.noise), float(q),
                      float(p.depth_unit))
    # N: the image's flat normals (all pixels); only the sample's are read, with whether they
    # are known (the one-point hypotheses' candidates)
    NQ, fin = (None, None) if N is None else sample_normals(N, pix, st)
    mq = len(Q)
    min_q = max(3, int(math.ceil(min_size * mq / m)))
    rem = np.arange(mq)
    planes = []
    for _ in range(p.max_parts):
        if len(rem) < min_q:
            break
        Qr, zr = Q.take(rem, axis=0), zs[rem]
        best = _ransac(Qr, zr, None if NQ is None else NQ.take(rem, axis=0), p, rng,
                       None if fin is None else fin[rem])
        if best is None:
            break
        nr, off = best
        cnt = -1
        for _it in range(3):  # least-squares refinement on the inliers
            inl, cnt, nr2, off2 = inliers_fit(Qr, Qr @ nr, zr, off, float(p.inlier_sigmas))
            if cnt < 3:
                break
            nr, off = nr2, float(off2)
        if cnt < min_q:
            break
        planes.append((nr, off))
        rem = rem[~inl]
    if len(planes) < min_parts:
        return None
    part = None
    for _it in range(p.iterations):  # assign the sample to the nearest part, refit
        part, fits, done = assign_refit(Q, _products(Q, planes), zs,
                                        np.array([off for _, off in planes]),
                                        float(p.assign_sigmas), True)
        for j in np.flatnonzero(done).tolist():
            planes[j] = (fits[j, :3].copy(), float(fits[j, 3]))
    if part is None:  # no refinement rounds: the sample's nearest parts
        part = assign_refit(Q, _products(Q, planes), zs, np.array([off for _, off in planes]),
                            float(p.assign_sigmas), False)[0]
    group = _surfaces(planes, Q, part, p)
    ng = int(group.max()) + 1
    if ng < min_parts:
        if stats is not None:
            stats["split_parallel"] = stats.get("split_parallel", 0) + 1
        return None
    pl = np.array([[*nr, off] for nr, off in planes], dtype=np.float64)
    P = X.take(pix, axis=0)
    zs_all = depth_scales(np.ascontiguousarray(P[:, 2]), float(scale), float(p.noise), float(q),
                          float(p.depth_unit))
    cost, part = assign_parts(np.ascontiguousarray(P, dtype=np.float64), zs_all, pl,
                              float(p.assign_sigmas))
    if ng < len(planes):  # parts of one surface: a point goes to its nearest part's surface
        part = np.where(part >= 0, group[np.maximum(part, 0)], -1)
        cost = np.stack([cost[:, group == g].min(axis=1) for g in range(ng)], axis=1)
        planes = [None] * ng
    if not organized:
        pieces = _pieces(part, len(planes), min_size, min_parts)
        if pieces is None:
            return None
        piece, piece_plane = pieces
        if (piece == -2).any():
            piece = _absorb(piece, piece_plane, cost, p.assign_sigmas)
        return piece
    piece, piece_plane = part_pieces(pix, w, part, len(planes), int(min_size))
    if len(piece_plane) < min_parts:
        return None
    if (piece == -2).any():
        piece = absorb_small(pix, w, piece, piece_plane, cost, float(p.assign_sigmas),
                             _cellmap(pix))
    return piece


def _cellmap(pix):
    """Scratch of the region's image: (N,) int32 all -1 (the kernels restore it), kept per
    thread (``pix`` ascending flat pixels: its last one bounds N from below)."""
    n_min = int(pix[-1]) + 1 if len(pix) else 0
    cm = getattr(_CELLMAPS, "arr", None)
    if cm is None or len(cm) < n_min:
        cm = np.full(max(n_min, 1), -1, dtype=np.int32)
        _CELLMAPS.arr = cm
    return cm


#: No normal hypotheses (:func:`_ransac`).
_NO_PICK = np.zeros(0, dtype=np.int64)
_NO_NORMALS = np.zeros((0, 3))


def _ransac(Q, zs, N, p: SplitParams, rng, finite=None):
    """Best plane (normal, offset) of points ``Q`` (m, 3) by seeded RANSAC: three-point and
    point-with-normal hypotheses scored on a regular sample by their inlier count.  ``finite``
    (m,) bool: the rows of ``N`` that are all finite, when the caller has them."""
    from planerel.segment._post_kernels import ransac_hypotheses, ransac_scores

    m = len(Q)
    step = max(1, m // p.sample)
    S = Q[::step]
    Sz = zs[::step]
    n3 = p.hypotheses if N is None else (p.hypotheses + 1) // 2
    tri = rng.integers(0, m, size=(n3, 3))
    pick, NN = _NO_PICK, _NO_NORMALS
    if N is not None and p.hypotheses > n3:
        good = np.flatnonzero(np.all(np.isfinite(N), axis=1) if finite is None else finite)
        if len(good):
            pick = good[rng.integers(0, len(good), size=p.hypotheses - n3)]
            NN = np.ascontiguousarray(N, dtype=np.float64)
    # the planes through the triples (cross products) and through the picked points with
    # their normals, compiled in the numpy statements' operations
    Hn, Ho = ransac_hypotheses(np.ascontiguousarray(Q, dtype=np.float64), tri, NN, pick)
    if len(Hn) == 0:
        return None
    score = ransac_scores(np.ascontiguousarray(S), np.ascontiguousarray(Sz), Hn, Ho,
                          float(p.inlier_sigmas))
    j = int(np.argmax(score))
    if score[j] < 3:
        return None
    return Hn[j], float(Ho[j])


def _pieces(part, k, min_size, min_pieces=2):
    """Pieces of the parts of an unorganized cloud's region (a part is one piece; organized
    clouds use :func:`planerel.segment._post_kernels.part_pieces`, connected pieces).  Returns
    ``(piece, piece_plane)``: per point the kept piece index (0..), -2 for a point in a
    too-small piece, -1 unassigned; and the part index of each kept piece.  None when fewer
    than ``min_pieces`` pieces are kept."""
    piece = np.full(len(part), -1, dtype=np.int64)
    piece_plane = []
    for j in range(k):
        mj = part == j
        if mj.sum() >= min_size:
            piece[mj] = len(piece_plane)
            piece_plane.append(j)
        else:
            piece[mj] = -2
    if len(piece_plane) < min_pieces:
        return None
    return piece, np.array(piece_plane, dtype=np.int64)


def _absorb(piece, piece_plane, cost, assign_sigmas):
    """Points of too-small pieces (-2) of an unorganized cloud's region join the kept piece
    whose plane is nearest in sigmas, within ``assign_sigmas``; else they become unassigned
    (-1) (organized clouds: :func:`planerel.segment._post_kernels.absorb_small`, adjacent
    pieces only).  ``cost`` (m, k): normalised distance of every point to every part's plane."""
    piece = piece.copy()
    small = np.flatnonzero(piece == -2)
    cs = cost[small][:, piece_plane]                 # (ns, kept pieces)
    best = np.argmin(cs, axis=1)
    cb = cs[np.arange(len(small)), best]
    piece[small] = np.where(cb <= assign_sigmas, best, -1)
    return piece
