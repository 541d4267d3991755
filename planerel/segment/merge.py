"""Merging coplanar regions: the last post-processing step after region growing (not in the
paper).

Region growing can stop a region and start a new one on the same surface -- a box top grown
as two halves of 90 points each, a floor cut in three by a line of noisy normals -- and the
leftover search of :mod:`planerel.segment.split` can find a piece beside a region of the same
plane.  A learner counting horizontal planes then sees two box tops.

:func:`merge_coplanar`, with the noise model of :class:`~planerel.segment.split.SplitParams`:

1. **Candidates.**  Pairs of regions with pixels within ``merge_gap`` pixels of each other in
   the image grid whose 3-D points there lie within ``merge_jump * z`` metres (the same surface,
   not a near edge in front of a far one).  With ``hole_bridge`` (off by default) also pairs
   that only a hole in the depth separates (:func:`hole_pairs`).  Candidates and statistics
   come from a regular grid sample of about 160x120 pixels (every pixel at 160x120, every 4th
   row and column at 640x480), as in the split test, so ``merge_gap`` means the same angle at
   every resolution.
2. **Test.**  The normals differ by at most ``merge_angle`` degrees and the least-squares plane
   of the union fits it within the split test's tolerance: RMS residual <= ``tolerance`` x the
   RMS the noise model expects (raised by the sensor's measured noise, as in the split test).
   So a merge never makes a region the split step would cut again.
3. **Greedy.**  The best-fitting pair (smallest RMS ratio) merges first; statistics are updated
   and the remaining pairs re-tested, until no pair passes.  Plane fits use per-region sums
   (count, sum, scatter), so each test is O(1).

The merged region takes the smaller label; labels are renumbered ``0 .. n-1`` in the order of
the regions' smallest original labels, and planes are refitted.

:func:`join_pieces` then joins pieces of a face a sensor bends slightly (Kinect, mOSD), and
:func:`join_wavy` the pieces of faces an active-stereo sensor's wavy depth cuts apart, on
frames whose noise model measures that waviness only.
"""

from __future__ import annotations

import math

import numpy as np

from planerel.errors import InputError
from planerel.segment.absorb import ABSORB_FRACTION, _facets, _touching_pairs
from planerel.segment.result import Segmentation
from planerel.segment.wavy_fit import (
    WAVE_FLAT,
    WAVE_MAX_RMS,
    WAVE_SPAN,
    wavy_model,
    wavy_ratio,
    wavy_sheet_fits,
)

__all__ = ["join_pieces", "join_wavy", "merge_coplanar", "wavy_sheet_fits", "WAVE_JOIN_ANGLE", "WAVE_FLAT",
           "WAVE_SPAN", "WAVE_OWN", "WAVE_MAX_RMS", "WAVE_JOIN_MAX", "WAVE_TILT"]

#: Largest angle between the normals of two pieces of one wavy face (degrees): small pieces of
#: a face whose depth waves by millimetres over centimetres tilt by up to 20 degrees (a carton
#: top of the RealSense palletizer frames, pieces of 400-900 px at 1.5 m: 10-20 degrees).
WAVE_JOIN_ANGLE = 20.0
#: A long union that is no flat sheet (:data:`WAVE_FLAT`) still joins when it fits about as
#: well as the worse of its two sides alone (a face that is
#: wavy itself): RMS at most this factor times the larger of their own RMS.
WAVE_OWN = 1.2
#: Beyond :data:`WAVE_JOIN_ANGLE`, up to this angle (degrees), two pieces may still join when
#: the smaller is small against the waves: the tangent of their angle at most
#: :data:`WAVE_TILT` x the waves' RMS (``wave x sigma(z)``) / its largest in-plane std (a piece
#: of std ``s`` on a face waving by ``w`` tilts by about ``atan(w / s)``).  hidden26's ycb4
#: (RealSense): a box top's and a wall's pieces of 1-2 cm std 20-31 degrees apart need 3.3-9.7;
#: a carton pile's long pieces (std 6-15 cm, the palletizer frames), which a fixed bound of 35
#: degrees joined into a false staircase, 17-40 (frag31, docs/segmentation.md).
WAVE_JOIN_MAX = 30.0
WAVE_TILT = 8.0


def merge_coplanar(cloud, seg: Segmentation, params=None, *,
                   absorb_factor: float | None = None) -> Segmentation:
    """Merge touching regions that lie on one plane.

    Parameters
    ----------
    cloud : Cloud
        The organized ``(H, W, 3)`` cloud ``seg`` was computed from (unorganized clouds are
        returned unchanged).
    seg : Segmentation
        ``labels`` (H, W) int32, -1 unassigned.
    params : SplitParams, optional
        ``merge_angle``, ``merge_gap``, ``merge_jump``, ``tolerance`` and the noise model.
    absorb_factor : float, optional
        Then absorb crease fragments (:func:`planerel.segment.absorb.absorb_fragments` with
        this ``refine_factor``), on this step's sample and touching pairs.

    Returns
    -------
    Segmentation
        ``info`` adds ``merged`` (number of merges) and, with ``absorb_factor``, the absorb
        counts; ``seg`` itself when nothing changed.
    """
    from planerel.segment._post_kernels import merge_stats
    from planerel.segment.split import _TEST_PIXELS, SplitParams, _residual_stats

    p = params if params is not None else SplitParams()
    if not isinstance(p, SplitParams):
        raise InputError(f"merge: params must be SplitParams, got {type(p).__name__}")
    from planerel.segment.absorb import _absorb, absorb_fragments

    info = dict(seg.info, merged=0)
    n = seg.n_planes

    def done(out, Ls=None, Xs=None, pairs=None):
        if absorb_factor is None:
            return out
        if pairs is None:
            return absorb_fragments(cloud, out, refine_factor=absorb_factor, gap=p.merge_gap,
                                    jump=p.merge_jump, params=p)
        return _absorb(cloud, out, Ls, Xs, pairs, absorb_factor, ABSORB_FRACTION, None, p)

    if n < 2 or not cloud.organized or not p.merge:
        return done(Segmentation(seg.labels, seg.planes, seg.method, seg.params, seg.normals,
                                 info))
    labels = seg.labels
    xyz = cloud.xyz
    # tests on a regular grid sample of about 160x120 pixels, as the split test: merge_gap is
    # then the same angle at every resolution, and a 640x480 frame costs what 160x120 does
    h, w = labels.shape
    st = max(1, int(math.sqrt(h * w / _TEST_PIXELS)))
    Ls = np.ascontiguousarray(labels[::st, ::st], dtype=np.int32)
    Xs = np.ascontiguousarray(xyz[::st, ::st], dtype=np.float64)
    pairs = _touching_pairs(Ls, Xs, n, p.merge_gap, p.merge_jump)
    if p.hole_bridge > 0:
        # pieces of one face a hole in the depth cuts apart (srob59): candidates too, for
        # the same test; the absorb step below keeps the pairs that touch
        across = sorted(set(hole_pairs(Ls, Xs, p.hole_bridge)) - set(pairs))
        if across:
            info["hole_pairs"] = len(across)
    else:
        across = []
    if not pairs and not across:
        return done(Segmentation(labels, seg.planes, seg.method, seg.params, seg.normals, info),
                    Ls, Xs, pairs)

    # the sensor's noise relative to the model, as the split test measures it (the split step
    # leaves its median in info; measured here otherwise)
    pn = np.array([pl.normal for pl in seg.planes])
    po = np.array([pl.offset for pl in seg.planes])
    sensor = seg.info.get("noise_scale")
    if sensor is None:
        sensor = 1.0
        if p.local_noise:
            _, exp_rms, local = _residual_stats(Xs, Ls, pn, po, n, p, True)
            scale = np.ones(n)
            ok = np.isfinite(local) & (local > exp_rms) & (exp_rms > 0)
            scale[ok] = local[ok] / exp_rms[ok]
            sensor = float(np.median(scale))

    # per-region sums (count, sum, scatter) and the expected point-to-plane variance summed
    # with the region's own normal (the union's normal differs by at most merge_angle, so
    # this is close), in one pass over the sample
    q = p.disparity_step / (p.focal_px * p.baseline)
    cnt, s1, s2, sv = merge_stats(Xs.reshape(-1, 3), Ls.reshape(-1),
                                  np.ascontiguousarray(pn, dtype=np.float64), n, float(p.noise),
                                  float(q), float(p.depth_unit), float(sensor) ** 2)
    normal = pn.copy()

    parent = np.arange(n)

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    cos_max = math.cos(math.radians(p.merge_angle))
    cos_par = math.cos(math.radians(p.min_split_angle)) if p.min_split_angle > 0 else 2.0
    # the touching pairs of current groups (roots), a < b; a merge renames drop to keep
    edges = set(pairs) | set(across)
    merged = 0
    while True:
        best = _best_pair(edges, normal, cnt, s1, s2, sv, cos_max, p.tolerance, cos_par,
                          p.merge_side, p.merge_side_span)
        if best is None:
            break
        _, ra, rb, nv = best
        keep, drop = min(ra, rb), max(ra, rb)
        parent[drop] = keep
        _rename(edges, keep, drop)
        cnt[keep] += cnt[drop]
        s1[keep] += s1[drop]
        s2[keep] += s2[drop]
        sv[keep] += sv[drop]
        normal[keep] = nv
        merged += 1
    if not merged:
        return done(Segmentation(labels, seg.planes, seg.method, seg.params, seg.normals, info),
                    Ls, Xs, pairs)
    roots = np.array([root(i) for i in range(n)])
    out, planes, new_id = _apply_groups(labels, xyz, seg.planes, roots)
    info["merged"] = merged
    res = Segmentation(out, planes, seg.method, seg.params, seg.normals, info)
    if absorb_factor is None:
        return res
    # the sample and the touching pairs of the merged groups (a group touches what its
    # members touched)
    gid = new_id[roots]
    pairs = sorted({(min(x, y), max(x, y)) for x, y in ((int(gid[a]), int(gid[b]))
                                                      for a, b in pairs) if x != y})
    remap = np.concatenate([[-1], gid]).astype(np.int32)
    return done(res, np.ascontiguousarray(remap[Ls + 1]), Xs, pairs)


def hole_pairs(labels: np.ndarray, xyz: np.ndarray, steps: int) -> list[tuple[int, int]]:
    """Label pairs ``(a, b)``, ``a < b``, whose regions a hole in the depth separates: each
    region grown into the invalid pixels (no depth) beside it, ``steps`` pixels at most
    (4-neighbours, all regions at once), meets the other's pixels or growth there.

    Valid pixels of no region stop the growth: only a gap with no depth at all is bridged
    (a stereo sensor's holes, a speckle's dropouts), never a strip the segmentation left.

    Parameters
    ----------
    labels : ndarray (H, W) int
        Region labels, -1 none.
    xyz : ndarray (H, W, 3)
        Points; a pixel is invalid when its ``z`` is not finite and positive.
    steps : int
        Largest distance grown, pixels of ``labels``' grid.

    Returns
    -------
    list of (int, int)
        Sorted pairs.
    """
    z = xyz[..., 2]
    hole = ~(np.isfinite(z) & (z > 0)) & (labels < 0)
    if steps < 1 or not hole.any():
        return []
    grown = np.asarray(labels, np.int64).copy()
    h, w = grown.shape
    found = set()
    shifts = ((0, 1), (1, 0), (0, -1), (-1, 0))

    def meet_all(grown, new=None):
        # each shift's neighbour label; a hole pixel a region reached meets another region's
        # pixel or growth; with ``new``, the hole pixels a neighbour reaches are taken
        for dy, dx in shifts:
            nb = np.full_like(grown, -1)
            nb[max(-dy, 0):h - max(dy, 0), max(-dx, 0):w - max(dx, 0)] = \
                grown[max(dy, 0):h - max(-dy, 0), max(dx, 0):w - max(-dx, 0)]
            meet = hole & (grown >= 0) & (nb >= 0) & (nb != grown)
            if meet.any():
                a, b = grown[meet], nb[meet]
                found.update(zip(np.minimum(a, b).tolist(), np.maximum(a, b).tolist(),
                                 strict=True))
            if new is not None:
                take = hole & (new < 0) & (nb >= 0)
                new[take] = nb[take]

    for _ in range(int(steps)):
        new = grown.copy()
        meet_all(grown, new)
        if np.array_equal(new, grown):
            break
        grown = new
    # the last growth's meetings
    meet_all(grown)
    return sorted(found)


def _rename(edges: set, keep: int, drop: int) -> None:
    """Rename ``drop`` to ``keep`` in the touching pairs ``edges`` (``(a, b)``, ``a < b``), in
    place: a group that touched either touches the joined one."""
    moved = [e for e in edges if drop in e]
    edges.difference_update(moved)
    for a, b in moved:
        a, b = (keep if a == drop else a), (keep if b == drop else b)
        if a != b:
            edges.add((min(a, b), max(a, b)))


def _apply_groups(labels, xyz, planes, roots):
    """Relabel ``labels`` (H, W) so that every region takes its group's root (``roots`` (n,),
    each group's smallest label) and refit the groups of two or more regions from their
    pixels (in pixel order: the sums of a full refit), in one pass.

    Returns
    -------
    labels : ndarray (H, W) int32
        Renumbered ``0 .. k-1`` in the order of the groups' smallest original labels.
    planes : tuple of SegPlane
        ``planes`` of the regions left alone, refits of the joined groups.
    new_id : ndarray (n,) int32
        The new label of each old label.
    """
    from planerel.segment.split import _relabel_refit

    n = len(roots)
    kept = np.unique(roots)  # ascending = order of the smallest original label of each group
    new_id = np.full(n, -1, dtype=np.int32)
    new_id[kept] = np.arange(len(kept), dtype=np.int32)
    remap = np.concatenate([[-1], new_id[roots]]).astype(np.int32)
    grouped = np.bincount(roots, minlength=n) > 1
    refit = np.flatnonzero(grouped)  # roots of joined groups, ascending = ascending new ids
    sub = np.full(n + 1, -1, dtype=np.int64)
    sub[np.flatnonzero(grouped[roots]) + 1] = np.searchsorted(refit, roots[grouped[roots]])
    out, fits = _relabel_refit(labels.reshape(-1), remap, sub, xyz.reshape(-1, 3), len(refit))
    fit_of = dict(zip(new_id[refit].tolist(), fits, strict=True))
    out_planes = tuple(fit_of[i].with_id(i) if i in fit_of else planes[int(r)].with_id(i)
                       for i, r in enumerate(kept.tolist()))
    return out.reshape(labels.shape), out_planes, new_id


def join_pieces(cloud, seg: Segmentation, params=None) -> Segmentation:
    """Join touching pieces of one bent surface: the last post-processing step.

    A real sensor bends a flat face by a few millimetres (a cardboard box's side on a Kinect
    v1 at 0.6-0.8 m: pieces 3-9 degrees apart, the smaller one's points 2-5 mm RMS off the
    larger one's plane, 1.6-6.6 times its own RMS), so region growing, the split test and
    the merge (which judge the union against the noise) leave it in two or three pieces.
    Downstream these pieces are two planes ``parallel`` and touching, which no sharp
    synthetic face ever is: the varied world's rules for ``other`` read it as two faces of a
    thin slab (docs/results.md, "Faces split in two").

    Two regions touching as the merge finds them (pixels within ``merge_gap``, points within
    ``merge_jump * z``) whose normals differ by more than ``min_split_angle`` and at most
    ``merge_angle`` degrees, and where the smaller one's points lie within ``piece_offset``
    metres RMS of the larger one's plane, are one surface.  Nearly parallel pieces are left
    to the merge, which judges their union against their own noise: a step of a few noise
    widths between them is two surfaces (two blocks' flush tops on the SegComp ABW set, 0.12
    degrees and 0.4 mm apart).  The RMS test keeps apart what is really two surfaces: two
    treads or a tread and the floor differ by a rise, a book lying on a table by its
    thickness, a table's leg by the few centimetres it stands back from the apron, and a
    plane meeting another at an angle lies off the other's plane by its extent times the
    angle's sine (a ramp starting from the floor: centimetres).  A facet of a round surface
    (a region meeting two or more touching regions at 5-40 degrees, as absorbing judges it)
    is not joined: a cylinder's fan of strips stays a fan.  Closest pair first, greedily,
    from the merge step's sample (per-region sums; the joined region's normal from its
    union's sums).

    Parameters
    ----------
    cloud : Cloud
        The organized cloud ``seg`` was computed from (unorganized clouds: unchanged).
    seg : Segmentation
    params : SplitParams, optional
        ``piece_offset`` (metres; 0 = off), ``min_split_angle``, ``merge_angle``,
        ``merge_gap``, ``merge_jump``.

    Returns
    -------
    Segmentation
        ``info`` adds ``joined`` (number of joins); ``seg``'s labels and planes when none.
    """
    from planerel.segment.split import SplitParams

    p = params if params is not None else SplitParams()
    if not isinstance(p, SplitParams):
        raise InputError(f"join_pieces: params must be SplitParams, got {type(p).__name__}")
    info = dict(seg.info, joined=0)
    n = seg.n_planes
    same = Segmentation(seg.labels, seg.planes, seg.method, seg.params, seg.normals, info)
    if p.piece_offset <= 0 or n < 2 or not cloud.organized:
        return same
    labels = seg.labels
    sums = _touching_sums(cloud, seg, p)
    if sums is None:
        return same
    edges, normal, cnt, s1, s2 = sums
    cos_max = math.cos(math.radians(p.merge_angle))
    # pieces within min_split_angle of each other are the merge's: it judges their union
    # against their own noise, and a step of a few noise widths between two such pieces is
    # two surfaces (two blocks' flush tops on the SegComp ABW set: 0.12 degrees, 0.4 mm)
    cos_par = math.cos(math.radians(p.min_split_angle)) if p.min_split_angle > 0 else 2.0
    # a facet of a round surface (meeting two or more regions at 5-40 degrees: a cylinder is a
    # fan of them) is no piece of a flat face, as in absorbing
    facet = _facets(normal, edges, n)
    parent = np.arange(n)
    joined = 0
    while True:
        best = None
        for a, b in sorted(edges):
            c = abs(normal[a] @ normal[b])
            if cnt[a] == 0 or cnt[b] == 0 or facet[a] or facet[b] or not cos_max <= c < cos_par:
                continue
            big, small = (a, b) if cnt[a] >= cnt[b] else (b, a)
            # the smaller piece's RMS distance to the larger one's plane, from the sums: its
            # centroid's offset and its spread along that normal
            nb, cs = normal[big], s1[small] / cnt[small]
            off = nb @ (cs - s1[big] / cnt[big])
            spread = nb @ (s2[small] / cnt[small] - np.outer(cs, cs)) @ nb
            rms = math.sqrt(off * off + max(spread, 0.0))
            if rms <= p.piece_offset and (best is None or rms < best[0]):
                best = (rms, a, b)
        if best is None:
            break
        _, keep, drop = best
        parent[parent == drop] = keep
        _rename(edges, keep, drop)
        cnt[keep] += cnt[drop]
        s1[keep] += s1[drop]
        s2[keep] += s2[drop]
        c = s1[keep] / cnt[keep]
        normal[keep] = np.linalg.eigh(s2[keep] / cnt[keep] - np.outer(c, c))[1][:, 0]
        joined += 1
    if not joined:
        return same
    out, planes, _ = _apply_groups(labels, cloud.xyz, seg.planes, parent)
    info["joined"] = joined
    return Segmentation(out, planes, seg.method, seg.params, seg.normals, info)


def _touching_sums(cloud, seg: Segmentation, p):
    """``(edges, normal, cnt, s1, s2)`` of :func:`join_pieces` and :func:`join_wavy` on the
    merge's sample (every ``st``-th pixel, about ``_TEST_PIXELS`` of them): the touching pairs
    of ``seg``'s regions (``merge_gap``, ``merge_jump`` of SplitParams ``p``), each region's
    unit normal ``(n, 3)``, point count ``(n,)``, sum of points ``(n, 3)`` and of their outer
    products ``(n, 3, 3)``; None when no pair touches."""
    from planerel.segment._post_kernels import merge_stats
    from planerel.segment.split import _TEST_PIXELS

    labels, n = seg.labels, seg.n_planes
    h, w = labels.shape
    st = max(1, int(math.sqrt(h * w / _TEST_PIXELS)))
    Ls = np.ascontiguousarray(labels[::st, ::st], dtype=np.int32)
    Xs = np.ascontiguousarray(cloud.xyz[::st, ::st], dtype=np.float64)
    edges = set(_touching_pairs(Ls, Xs, n, p.merge_gap, p.merge_jump))
    if not edges:
        return None
    normal = np.array([pl.normal for pl in seg.planes], dtype=np.float64)
    cnt, s1, s2, _ = merge_stats(Xs.reshape(-1, 3), Ls.reshape(-1), normal, n, 0.0, 0.0, 0.0,
                                 0.0)
    return edges, normal, cnt, s1, s2


def join_wavy(cloud, seg: Segmentation, params=None) -> Segmentation:
    """Join the pieces of faces that a wavy sensor's depth cuts apart (after :func:`join_pieces`).

    Active-stereo sensors (RealSense D4xx, OAK-D) bend a flat face by millimetres over a few
    centimetres, far more than the noise of small patches, so region growing on normals cuts
    the face into pieces that tilt 5-20 degrees against each other.  The noise model measures
    that waviness from the frame itself (:attr:`planerel.segment.noise.NoiseModel.wave`: the
    plane-fit std over 25 px windows relative to the small-patch ``sigma``; ``info
    ["noise_model"]``).  Only on a wavy frame (``wave >= WAVY_RATIO``; Kinect, laser and
    synthetic frames measure far less and are returned unchanged): two touching regions (the
    merge's test) whose normals lie within :data:`WAVE_JOIN_ANGLE` degrees (up to
    :data:`WAVE_JOIN_MAX` when the smaller piece is small against the waves,
    :data:`WAVE_TILT`) are joined when
    the least-squares plane of their union fits it within ``tolerance x wave x sigma(z) x
    g`` RMS: ``z`` the union's centroid depth, ``sigma`` the small-patch noise model and
    ``g = sqrt(min(WAVE_SPAN, span / window))`` the waves' growth with the union's extent
    (``span`` its largest in-plane std, ``window`` that of a waviness window at ``z``), and
    within :data:`WAVE_MAX_RMS` (8 mm) whatever the waviness (far from the sensor the depth is
    centimetres off: such unions made false ramps).  A union longer than :data:`WAVE_SPAN`
    windows must also be a flat sheet, RMS at most :data:`WAVE_FLAT` x its span, or fit
    about as well as its worse side alone (:data:`WAVE_OWN` x the larger own RMS: a face that
    is wavy itself).  Best-fitting pair first, greedily, from per-region
    sums on the merge's sample (a pair is re-tested only when one side changed).  Two faces
    of a box (90 degrees), a tread and its riser, a ramp and the floor over their extent, or
    a book on a table (a step of its thickness) do not fit within it.

    Parameters
    ----------
    cloud : Cloud
        The organized cloud ``seg`` was computed from (unorganized clouds: unchanged).
    seg : Segmentation
        With ``info["noise_model"]`` as region growing reports it (none: unchanged).
    params : SplitParams, optional
        ``wavy_join`` (False: off), ``tolerance``, ``merge_gap``, ``merge_jump``; with
        ``merge_side`` each side must also lie within ``merge_side x tolerance`` times the
        larger of the union's and the sides' own RMS of the union's plane.

    Returns
    -------
    Segmentation
        ``seg`` itself when the frame is not wavy or nothing was joined; else with ``info``
        adding ``wavy_joined`` (number of joins).
    """
    from planerel.segment.split import SplitParams

    p = params if params is not None else SplitParams()
    if not isinstance(p, SplitParams):
        raise InputError(f"join_wavy: params must be SplitParams, got {type(p).__name__}")
    nm = wavy_model(seg.info)
    n = seg.n_planes
    if not p.wavy_join or nm is None or n < 2 or not cloud.organized:
        return seg
    wave, c0, q = float(nm["wave"]), float(nm["const_m"]), float(nm["quad_per_m"])
    labels = seg.labels
    sums = _touching_sums(cloud, seg, p)
    if sums is None:
        return seg
    edges, normal, cnt, s1, s2 = sums
    cos_max = math.cos(math.radians(WAVE_JOIN_ANGLE))
    sig2 = (c0 * c0, q * q)

    def test(a, b):
        """``(ratio, union normal)`` of a pair passing the tests, else None."""
        if cnt[a] < 3 or cnt[b] < 3:
            return None
        cos_ab = abs(float(normal[a] @ normal[b]))
        if cos_ab < cos_wide:
            return None
        m = cnt[a] + cnt[b]
        c = (s1[a] + s1[b]) / m
        ev, vec = np.linalg.eigh((s2[a] + s2[b]) / m - np.outer(c, c))
        rms = math.sqrt(max(ev[0], 0.0))
        if rms > WAVE_MAX_RMS:
            return None
        z = abs(c[2])
        if cos_ab < cos_max:
            # beyond WAVE_JOIN_ANGLE only pieces small against the waves: a piece of in-plane
            # std s on a face waving by wave x sigma(z) tilts by about atan(that / s)
            tilt = WAVE_TILT * wave * math.sqrt(sig2[0] + sig2[1] * z ** 4) / max(min(ext[a], ext[b]), 1e-12)
            if cos_ab < math.cos(math.atan(tilt)):
                return None
        ratio = wavy_ratio(ev, c, nm, p.tolerance, WAVE_OWN * max(own[a], own[b]))
        if ratio > 1.0:
            return None
        if p.merge_side > 0:
            # each side near the union's plane on its own (the merge's side test): a block's
            # top 2-4 cm over a wavy board joined it, the union's RMS being the board's
            nv = vec[:, 0]
            k = np.array([a, b])
            side = _side_rms(cnt[k], s1[k], s2[k], np.stack([nv, nv]),
                             np.full(2, -float(nv @ c)))
            if side.max() > p.merge_side * p.tolerance * max(rms, own[a], own[b]) and (
                    p.merge_side_span <= 0 or min(ext[a], ext[b]) <= p.merge_side_span):
                return None
        return ratio, vec[:, 0]

    own = {i: float(x) for i, x in enumerate(_rms_of(np.maximum(cnt, 1), s1, s2))}
    ext = {i: float(x) for i, x in enumerate(_span_of(np.maximum(cnt, 1), s1, s2))}
    cos_wide = math.cos(math.radians(max(WAVE_JOIN_ANGLE, WAVE_JOIN_MAX)))
    parent = np.arange(n)
    joined = 0
    tested = {e: test(*e) for e in sorted(edges)}  # pair -> result; redone when a side changes
    while True:
        best = None
        for e in sorted(edges):
            r = tested.get(e, False)
            if r is False:
                r = tested[e] = test(*e)
            if r is not None and (best is None or r[0] < best[0]):
                best = (r[0], e[0], e[1], r[1])
        if best is None:
            break
        _, a, b, nv = best
        keep, drop = min(a, b), max(a, b)
        parent[parent == drop] = keep
        _rename(edges, keep, drop)
        cnt[keep] += cnt[drop]
        s1[keep] += s1[drop]
        s2[keep] += s2[drop]
        normal[keep] = nv
        own[keep] = float(_rms_of(cnt[keep:keep + 1], s1[keep:keep + 1], s2[keep:keep + 1])[0])
        ext[keep] = float(_span_of(cnt[keep:keep + 1], s1[keep:keep + 1], s2[keep:keep + 1])[0])
        tested = {e: r for e, r in tested.items() if keep not in e and drop not in e}
        joined += 1
    if not joined:
        return seg
    out, planes, _ = _apply_groups(labels, cloud.xyz, seg.planes, parent)
    info = dict(seg.info, wavy_joined=joined)
    return Segmentation(out, planes, seg.method, seg.params, seg.normals, info)


def _span_of(m, s1, s2) -> np.ndarray:
    """Largest in-plane std of each group (the square root of its covariance's largest
    eigenvalue) from its sums (k,)."""
    c = s1 / m[:, None]
    cov = s2 / m[:, None, None] - np.einsum("ki,kj->kij", c, c)
    return np.sqrt(np.maximum(np.linalg.eigvalsh(cov)[:, 2], 0.0))


def _rms_of(m, s1, s2) -> np.ndarray:
    """RMS distance to the least-squares plane of each group from its sums (k,)."""
    c = s1 / m[:, None]
    cov = s2 / m[:, None, None] - np.einsum("ki,kj->kij", c, c)
    return np.sqrt(np.maximum(np.linalg.eigvalsh(cov)[:, 0], 0.0))


def _side_rms(m, s1, s2, normal, offset) -> np.ndarray:
    """RMS distance of each group (its sums ``m`` (k,), ``s1`` (k, 3), ``s2`` (k, 3, 3)) to
    the plane ``normal . x + offset = 0`` given per group (``normal`` (k, 3), ``offset``
    (k,)), from the sums alone: ``(n' S2 n + 2 d n.S1 + m d^2) / m``."""
    q = np.einsum("ki,kij,kj->k", normal, s2, normal)
    q += 2.0 * offset * np.einsum("ki,ki->k", normal, s1) + m * offset * offset
    return np.sqrt(np.maximum(q / m, 0.0))


def _best_pair(edges, normal, cnt, s1, s2, sv, cos_max, tolerance, cos_par=2.0, side=0.0,
               side_span=0.0):
    """The pair of current groups (``edges``: a set of touching root pairs ``(a, b)``,
    ``a < b``) that passes the merge test with the smallest RMS ratio (the first in pair order
    on a tie): ``(ratio, root_a, root_b, union normal)``, or None.

    The union's RMS is compared with the RMS the noise model expects; for two groups whose
    normals lie within ``acos(cos_par)`` (``min_split_angle``) of each other, with the larger
    of that and the groups' own RMS: a real sensor's large plane is bent by more than its
    noise (a Kinect floor), and its pieces are still one surface when their union fits about
    as well as each piece alone.

    With ``side`` > 0 each group must also fit the union's plane within ``side x tolerance``
    times that bound on its own: a union's RMS is its larger side's, so a small region on a
    parallel plane centimetres off a large one (a block's top over the board it stands on)
    passed the pooled test (tote67).  With ``side_span`` > 0 only for the pairs whose
    smaller group spans at most that (its largest in-plane std, metres; span91)."""
    if not edges:
        return None
    cand = np.array(sorted(edges), dtype=np.int64)
    A, B = cand[:, 0], cand[:, 1]
    # |cos| of the normals' angle, once (einsum's row values do not depend on the other rows)
    dots = np.abs(np.einsum("ij,ij->i", normal[A], normal[B]))
    ok = dots >= cos_max
    if not ok.any():
        return None
    A, B, dots = A[ok], B[ok], dots[ok]
    m = cnt[A] + cnt[B]
    c = (s1[A] + s1[B]) / m[:, None]
    cov = (s2[A] + s2[B]) / m[:, None, None] - np.einsum("ki,kj->kij", c, c)
    w, v = np.linalg.eigh(cov)
    rms = np.sqrt(np.maximum(w[:, 0], 0.0))
    ref = np.sqrt((sv[A] + sv[B]) / m)
    par = dots >= cos_par
    if par.any():
        # both sides' own RMS in one batch of 3x3 eigenvalue problems
        k = int(par.sum())
        G = np.concatenate([A[par], B[par]])
        own = _rms_of(cnt[G], s1[G], s2[G])
        ref[par] = np.maximum(ref[par], np.maximum(own[:k], own[k:]))
    ratio = rms / np.maximum(ref, 1e-12)
    if side > 0:
        nv = v[:, :, 0]
        off = -np.einsum("ki,ki->k", nv, c)
        worst = np.maximum(_side_rms(cnt[A], s1[A], s2[A], nv, off),
                           _side_rms(cnt[B], s1[B], s2[B], nv, off))
        held = worst > side * tolerance * np.maximum(ref, 1e-12)
        if side_span > 0 and held.any():
            # the spans of the held pairs only (most pairs fit on both sides)
            h = np.flatnonzero(held)
            held[h] = np.minimum(_span_of(cnt[A[h]], s1[A[h]], s2[A[h]]),
                                 _span_of(cnt[B[h]], s1[B[h]], s2[B[h]])) <= side_span
        ratio = np.where(held, np.inf, ratio)
    j = int(np.argmin(ratio))
    if ratio[j] > tolerance:
        return None
    return float(ratio[j]), int(A[j]), int(B[j]), v[j, :, 0]
