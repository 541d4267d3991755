"""Merging coplanar regions: the last post-processing step after region growing (not in the
paper).

Region growing can stop a region and start a new one on the same surface -- a box top grown
as two halves of 90 points each, a floor cut in three by a line of noisy normals -- and the
leftover search of :mod:`planerel.segment.split` can find a piece beside a region of the same
plane.  A learner counting horizontal planes then sees two box tops.

:func:`merge_coplanar`, with the noise model of :class:`~planerel.segment.split.SplitParams`:

1. **Candidates.**  Pairs of regions with pixels within ``merge_gap`` pixels of each other in
   the image grid whose 3-D points there lie within ``merge_jump * z`` metres (the same surface,
   not a near edge in front of a far one).  Candidates and statistics come from a regular grid
   sample of about 160x120 pixels (every pixel at 160x120, every 4th row and column at
   640x480), as in the split test, so ``merge_gap`` means the same angle at every resolution.
2. **Test.**  The normals differ by at most ``merge_angle`` degrees and the least-squares plane
   of the union fits it within the split test's tolerance: RMS residual <= ``tolerance`` x the
   RMS the noise model expects (raised by the sensor's measured noise, as in the split test).
   So a merge never makes a region the split step would cut again.
3. **Greedy.**  The best-fitting pair (smallest RMS ratio) merges first; statistics are updated
   and the remaining pairs re-tested, until no pair passes.  Plane fits use per-region sums
   (count, sum, scatter), so each test is O(1).

The merged region takes the smaller label; labels are renumbered ``0 .. n-1`` in the order of
the regions' smallest original labels, and planes are refitted.
"""

from __future__ import annotations

import math

import numpy as np

from planerel.errors import InputError
from planerel.segment.absorb import ABSORB_FRACTION, _touching_pairs
from planerel.segment.result import Segmentation

__all__ = ["merge_coplanar"]


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
    from planerel.segment.split import _TEST_PIXELS, SplitParams, _relabel_refit, _residual_stats

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
    if not pairs:
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
    edges = set(pairs)
    merged = 0
    while True:
        best = _best_pair(edges, normal, cnt, s1, s2, sv, cos_max, p.tolerance, cos_par)
        if best is None:
            break
        _, ra, rb, nv = best
        keep, drop = min(ra, rb), max(ra, rb)
        parent[drop] = keep
        moved = [e for e in edges if drop in e]
        edges.difference_update(moved)
        for a, b in moved:
            a, b = (keep if a == drop else a), (keep if b == drop else b)
            if a != b:
                edges.add((min(a, b), max(a, b)))
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
    kept = np.unique(roots)  # ascending = order of the smallest original label of each group
    new_id = np.full(n, -1, dtype=np.int32)
    new_id[kept] = np.arange(len(kept), dtype=np.int32)
    remap = np.concatenate([[-1], new_id[roots]]).astype(np.int32)
    # refit only the merged groups, from their pixels (in pixel order: the sums of a full
    # refit), in the relabelling's pass
    grouped = np.bincount(roots, minlength=n) > 1
    refit = np.flatnonzero(grouped)  # roots of merged groups, ascending = ascending new ids
    sub = np.full(n + 1, -1, dtype=np.int64)
    sub[np.flatnonzero(grouped[roots]) + 1] = np.searchsorted(refit, roots[grouped[roots]])
    out, fits = _relabel_refit(labels.reshape(-1), remap, sub, xyz.reshape(-1, 3), len(refit))
    fit_of = dict(zip(new_id[refit].tolist(), fits, strict=True))
    planes = tuple(fit_of[i].with_id(i) if i in fit_of else seg.planes[int(r)].with_id(i)
                   for i, r in enumerate(kept.tolist()))
    info["merged"] = merged
    res = Segmentation(out.reshape(labels.shape), planes, seg.method, seg.params, seg.normals, info)
    if absorb_factor is None:
        return res
    # the sample and the touching pairs of the merged groups (a group touches what its
    # members touched)
    gid = new_id[roots]
    pairs = sorted({(min(x, y), max(x, y)) for x, y in ((int(gid[a]), int(gid[b]))
                                                      for a, b in pairs) if x != y})
    return done(res, np.ascontiguousarray(remap[Ls + 1]), Xs, pairs)


def _rms_of(m, s1, s2) -> np.ndarray:
    """RMS distance to the least-squares plane of each group from its sums (k,)."""
    c = s1 / m[:, None]
    cov = s2 / m[:, None, None] - np.einsum("ki,kj->kij", c, c)
    return np.sqrt(np.maximum(np.linalg.eigvalsh(cov)[:, 0], 0.0))


def _best_pair(edges, normal, cnt, s1, s2, sv, cos_max, tolerance, cos_par=2.0):
    """The pair of current groups (``edges``: a set of touching root pairs ``(a, b)``,
    ``a < b``) that passes the merge test with the smallest RMS ratio (the first in pair order
    on a tie): ``(ratio, root_a, root_b, union normal)``, or None.

    The union's RMS is compared with the RMS the noise model expects; for two groups whose
    normals lie within ``acos(cos_par)`` (``min_split_angle``) of each other, with the larger
    of that and the groups' own RMS: a real sensor's large plane is bent by more than its
    noise (a Kinect floor), and its pieces are still one surface when their union fits about
    as well as each piece alone."""
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
    j = int(np.argmin(ratio))
    if ratio[j] > tolerance:
        return None
    return float(ratio[j]), int(A[j]), int(B[j]), v[j, :, 0]
