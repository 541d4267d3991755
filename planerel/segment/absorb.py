"""Absorbing fragments: regions whose points lie on a neighbouring larger region's plane (a
post-processing step after the merge; not in the paper).

Normals are averaged over a window, so along a crease between two surfaces (two walls, a
wall and a pillar, the floor and a laptop's edge) they blend from one surface's normal to the
other's.  Where the blend stays within ``theta`` of itself for a few hundred pixels, region
growing makes a thin *fragment* there: its own plane is tilted between the two surfaces, so
the merge (which compares normals) keeps it apart, yet its **points** lie on the surfaces'
planes.  The adaptive minimum region size (a quarter of the fixed one on a Kinect at
640x480, so that a 3-5 cm face counts) keeps such fragments: 6-12 per real Kinect frame.

:func:`absorb_fragments`, with the completion's test of region growing (a point fits a
region's plane when its distance is within ``refine_factor`` x the region's RMS residual):

1. **Neighbours.**  Touching regions, as the merge finds them (pixels within ``merge_gap``,
   points within ``merge_jump * z``), on the merge's regular grid sample.
2. **Test.**  From the largest region down, a region is a fragment when at least
   ``absorb_fraction`` of its sample points fit the plane of a touching region that is larger
   and not itself a fragment.  A true face fits its neighbours only along the shared edge
   (a box side on the floor: the few rows within a few millimetres of the floor; 0-8 % on the
   real Kinect frames), a crease fragment mostly (57-100 %).
   A region meeting two or more touching regions at 5-40 degrees (a facet of a round
   surface: a cylinder is a fan of them, :mod:`planerel.features.curved`) is never a fragment.
3. **Reassignment.**  Each pixel of a fragment joins the fitting neighbour plane it lies
   nearest to (relative to the threshold); a pixel that fits none becomes unassigned.

Labels are renumbered ``0 .. n-1`` in their order; the planes of the regions that received
pixels are refitted (the others keep theirs).
"""

from __future__ import annotations

import math

import numpy as np

from planerel.segment.result import Segmentation, SegPlane

__all__ = ["absorb_fragments", "ABSORB_FRACTION", "RMS_FLOOR"]

#: Fraction of a region's points that must fit a larger neighbour's plane for the region to be
#: absorbed (the real Kinect frames: true faces 0-8 %, crease fragments 57-100 %).
ABSORB_FRACTION = 0.5
#: Smallest RMS (m) a neighbour's fit threshold is based on (a tiny region fitted exactly).
RMS_FLOOR = 1e-4

#: Degrees: two adjacent planes at an angle in this range are neighbouring facets of a round
#: surface (the defaults of :class:`planerel.features.curved.CurvedParams`, defined here because
#: segmentation comes before the features stage).
FACET_MIN_ANGLE = 5.0
FACET_MAX_ANGLE = 50.0


def absorb_fragments(cloud, seg: Segmentation, *, refine_factor: float = 3.0,
                     fraction: float = ABSORB_FRACTION, min_size: int | None = None, gap: int = 2,
                     jump: float = 0.05, params=None) -> Segmentation:
    """Dissolve regions whose points lie on a touching larger region's plane.

    Parameters
    ----------
    cloud : Cloud
        The organized ``(H, W, 3)`` cloud ``seg`` was computed from (unorganized clouds are
        returned unchanged).
    seg : Segmentation
        ``labels`` (H, W) int32, -1 unassigned.
    refine_factor : float
        A point fits a plane within ``refine_factor`` x the plane's RMS residual.
    fraction : float
        Share of a region's sample points that must fit for it to be absorbed.
    min_size : int, optional
        A fragment whose points that fit no neighbour would still make a region of this many
        pixels (estimated from the sample) keeps them; default ``seg.info["min_region_size"]``.
    gap, jump : int, float
        The merge's touching test (pixels; fraction of depth).
    params : SplitParams, optional
        The noise model and ``tolerance`` bounding a curved neighbour's band (see below).

    Returns
    -------
    Segmentation
        ``info`` adds ``absorbed`` (regions dissolved), ``absorbed_shrunk`` (fragments that
        kept their other pixels) and ``absorbed_unassigned`` (pixels of dissolved regions that
        fit no neighbour); ``seg`` itself (with those counts) when none was.
    """
    from planerel.segment.split import _TEST_PIXELS

    n = seg.n_planes
    if n < 2 or not cloud.organized:
        return _absorb(cloud, seg, None, None, (), refine_factor, fraction, min_size)
    h, w = seg.labels.shape
    st = max(1, int(math.sqrt(h * w / _TEST_PIXELS)))
    Ls = np.ascontiguousarray(seg.labels[::st, ::st], dtype=np.int32)
    Xs = np.ascontiguousarray(cloud.xyz[::st, ::st], dtype=np.float64)
    pairs = _touching_pairs(Ls, Xs, n, gap, jump)
    return _absorb(cloud, seg, Ls, Xs, pairs, refine_factor, fraction, min_size, params)


def _absorb(cloud, seg, Ls, Xs, pairs, refine_factor, fraction, min_size,
            params=None) -> Segmentation:
    """:func:`absorb_fragments` given the merge step's regular grid sample of the labels ``Ls``
    and points ``Xs`` and the touching pairs ``(a, b)`` of ``seg``'s regions on it (the merge
    step passes its own when it ran: :func:`planerel.segment.merge.merge_coplanar`)."""
    from planerel.segment._post_kernels import fit_counts

    info = dict(seg.info, absorbed=0, absorbed_shrunk=0, absorbed_unassigned=0)
    n = seg.n_planes
    same = Segmentation(seg.labels, seg.planes, seg.method, seg.params, seg.normals, info)
    if n < 2 or not cloud.organized or not pairs:
        return same
    labels = seg.labels
    h, w = labels.shape
    sizes = [p.n_points for p in seg.planes]  # Python ints: compared pair by pair below
    size = np.array(sizes, dtype=np.int64)
    nbrs: list[list[int]] = [[] for _ in range(n)]
    for a, b in pairs:
        nbrs[a].append(b)
        nbrs[b].append(a)
    normal = np.array([p.normal for p in seg.planes], dtype=np.float64)
    offset = np.array([p.offset for p in seg.planes], dtype=np.float64)
    # a neighbour's fit band: refine_factor x its RMS, but a curved neighbour (RMS over the
    # split test's tolerance x the RMS the noise model expects: a cylinder's facet) counts
    # with that bound, so that a round surface's facets are not absorbed into each other
    from planerel.segment._post_kernels import merge_stats
    from planerel.segment.split import SplitParams

    sp = SplitParams() if params is None else params
    q = sp.disparity_step / (sp.focal_px * sp.baseline)
    cnt, _, _, sv = merge_stats(Xs.reshape(-1, 3), Ls.reshape(-1), normal, n, float(sp.noise),
                                float(q), float(sp.depth_unit),
                                float(seg.info.get("noise_scale", 1.0)) ** 2)
    rms = np.array([p.rms for p in seg.planes])
    bound = np.where(cnt > 0, sp.tolerance * np.sqrt(sv / np.maximum(cnt, 1)), np.inf)
    thr = refine_factor * np.maximum(np.minimum(rms, bound), RMS_FLOOR)
    planes4 = np.ascontiguousarray(np.column_stack([normal, offset]))
    # candidates of a region: its touching neighbours that are larger (CSR, ascending)
    cands = [sorted(j for j in nbrs[r] if sizes[j] > sizes[r]) for r in range(n)]
    ptr = np.cumsum([0] + [len(c) for c in cands]).astype(np.int64)
    idx = np.array([j for c in cands for j in c], dtype=np.int64)
    if len(idx) == 0:
        return same
    if min_size is None:
        min_size = int(seg.info.get("min_region_size", 1))
    active = np.ones(n, dtype=bool)  # candidates not dissolved themselves
    xs, ls = Xs.reshape(-1, 3), Ls.reshape(-1)
    tot, fit = fit_counts(xs, ls, n, active, ptr, idx, planes4, thr)
    facet = _facets(normal, pairs, n)
    gone = np.zeros(n, dtype=bool)
    rest = np.zeros(n, dtype=bool)
    for r in sorted(range(n), key=lambda i: (-sizes[i], i)):  # largest first
        c = cands[r]
        if not c or tot[r] == 0 or facet[r]:
            continue
        if not active[c].all():  # a candidate was dissolved: count against the others
            if not active[c].any():
                continue
            tot, fit = fit_counts(xs, ls, n, active, ptr, idx, planes4, thr)
        share = fit[r] / tot[r]
        if share >= fraction:
            gone[r] = True
            # the rest is still a region (a bent face half lying on its neighbour's plane)
            rest[r] = (1.0 - share) * size[r] >= min_size
            active[r] = False
    if not gone.any():
        return same
    from planerel.segment._kernels import planes_from_sums
    from planerel.segment._post_kernels import absorb_relabel

    # a fragment's pixels may join its candidates that were not dissolved
    into = {r: [j for j in cands[r] if not gone[j]] for r in np.flatnonzero(gone).tolist()}
    ptr = np.cumsum([0] + [len(into.get(r, ())) for r in range(n)]).astype(np.int64)
    idx = np.array([j for r in range(n) for j in into.get(r, ())], dtype=np.int64)
    keep = np.flatnonzero(~gone | rest)
    new_id = np.full(n, -1, dtype=np.int32)
    new_id[keep] = np.arange(len(keep), dtype=np.int32)
    recv = np.array(sorted({j for c in into.values() for j in c} | set(np.flatnonzero(rest).tolist())),
                    dtype=np.int64)
    rec_row = np.full(n, -1, dtype=np.int64)
    rec_row[recv] = np.arange(len(recv))
    sums = np.zeros((len(recv), 10))
    ref = np.array([seg.planes[j].centroid for j in recv], dtype=np.float64).reshape(-1, 3)
    out, lost, got = absorb_relabel(
        np.ascontiguousarray(cloud.xyz.reshape(-1, 3)),  # float32 or float64, not copied
        np.ascontiguousarray(labels.reshape(-1), dtype=np.int32), gone, rest, ptr, idx,
        planes4, thr, new_id, rec_row, sums, ref)
    planes = [seg.planes[i] for i in keep]
    # the receivers' planes refitted from their moments; the other planes are unchanged
    fits = SegPlane.from_fits(*planes_from_sums(sums, ref, len(recv)))
    for j, f, g in zip(recv.tolist(), fits, got.tolist(), strict=True):
        if g or rest[j]:
            planes[int(new_id[j])] = f
    planes = [p.with_id(i) for i, p in enumerate(planes)]
    info.update(absorbed=int((gone & ~rest).sum()), absorbed_shrunk=int(rest.sum()),
                absorbed_unassigned=int(lost))
    return Segmentation(out.reshape(h, w), tuple(planes), seg.method, seg.params, seg.normals,
                        info)


def _facets(normal, pairs, n) -> np.ndarray:
    """(n,) bool: regions meeting two or more touching regions at a shallow angle (the facet
    angles of :class:`planerel.features.curved.CurvedParams`, 5-40 degrees): strips of a round surface
    (a cylinder comes out as a fan of them), kept apart.  A crease fragment between two planes
    meets at most one of them at so shallow an angle (between two walls at 90 degrees: 25 and
    65, or 45 and 45)."""
    lo, hi = math.cos(math.radians(FACET_MIN_ANGLE)), math.cos(math.radians(FACET_MAX_ANGLE))
    shallow = np.zeros(n, dtype=np.int64)
    for a, b in pairs:
        c = abs(float(normal[a] @ normal[b]))
        if hi <= c <= lo:
            shallow[a] += 1
            shallow[b] += 1
    return shallow >= 2


def _touching_pairs(labels, xyz, n: int, gap: int, jump: float) -> list[tuple[int, int]]:
    """Sorted label pairs ``(a, b)``, ``a < b``, with pixels at most ``gap`` apart (Chebyshev
    distance in the grid) whose points lie within ``jump * z`` metres of each other: the
    relations' touching test (:func:`planerel.features.relations._touching`), run on the boundary pixels."""
    from planerel.segment._label_kernels import label_boundary, touch_pairs

    brow, bcol = np.nonzero(label_boundary(np.ascontiguousarray(labels, dtype=np.int32)))
    m = touch_pairs(np.ascontiguousarray(xyz), np.ascontiguousarray(labels), brow.astype(np.int64),
                    bcol.astype(np.int64), int(gap), 0.0,
                    float(jump), np.ones(n, dtype=bool))
    a, b = np.nonzero(np.triu(m, 1))
    return list(zip(a.tolist(), b.tolist(), strict=True))
