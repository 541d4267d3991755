"""Small calls of the description made cheaper (speed22w, issue 22): each replacement against
the numpy call or kernel it replaced, which the tests keep as the reference, on random cases
and on real frames; the results must be the same values, bit for bit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

_DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def _same(a, b) -> bool:
    """The same values, bit for bit (signed zeros and NaN payloads too)."""
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def _vectors(rng, n):
    """3-vectors at scales 1e-9-1e9, unit ones, zeros, signed zeros, NaN and infinities."""
    out = [rng.normal(size=3) * 10.0 ** rng.integers(-9, 10) for _ in range(n)]
    out += [v / np.linalg.norm(v) for v in out[:200]]
    out += [np.zeros(3), np.array([-0.0, 0.0, -0.0]), np.array([np.nan, 1.0, 2.0]),
            np.array([np.inf, 1.0, 0.0]), np.array([-np.inf, np.inf, 0.0]),
            np.array([1e-300, 1e-300, 0.0]), np.array([1e300, 1e300, 1e300])]
    return out


def test_vec_norm_is_numpys_norm_bit_for_bit():
    from planerel.features.vectors import vec_norm

    rng = np.random.default_rng(2222)
    for v in _vectors(rng, 4000):
        want = float(np.linalg.norm(v))
        got = vec_norm(v)
        assert isinstance(got, float)
        assert _same(np.float64(got), np.float64(want)), (v, got, want)
    # a strided view (numpy's norm ravels it first) and longer vectors
    base = rng.normal(size=(50, 3))
    for v in (base[:, 1], base[::3, 0], base.ravel()[:7], rng.normal(size=40)):
        assert _same(np.float64(vec_norm(v)), np.linalg.norm(v))


def test_lo_hi_is_numpys_min_and_max():
    from planerel.features.vectors import lo_hi

    rng = np.random.default_rng(2223)
    cases = [rng.normal(size=int(rng.integers(1, 30))) * 10.0 ** rng.integers(-6, 7)
             for _ in range(3000)]
    cases += [np.array([0.0, -0.0, 1.0]), np.array([-0.0, 0.0]), np.array([1.0, -0.0, 2.0]),
              np.array([np.nan, 1.0]), np.array([1.0, np.nan, -1.0]), np.array([np.inf, 1.0]),
              np.array([-np.inf, np.inf]), np.array([np.inf, np.inf]), np.array([5.0]),
              np.array([2.0, 2.0, 2.0]), np.array([1e308, 1e308, -1.0])]
    for a in cases:
        lo, hi = lo_hi(a)
        assert isinstance(lo, float) and isinstance(hi, float)
        assert _same(np.float64(lo), np.float64(a.min())), (a, lo)
        assert _same(np.float64(hi), np.float64(a.max())), (a, hi)
    with pytest.raises(ValueError):
        lo_hi(np.zeros(0))


def test_pitch_diffs_both_is_pitch_diffs_of_each_axis():
    from planerel.features._curved_kernels import pitch_diffs, pitch_diffs_both

    rng = np.random.default_rng(2224)
    for _ in range(200):
        H, W = (int(v) for v in rng.integers(1, 40, 2))
        xyz = rng.normal(size=(H, W, 3))
        xyz[..., 2] = rng.uniform(0.3, 5.0, (H, W))
        xyz[rng.random((H, W)) < 0.15] = np.nan
        xyz[rng.random((H, W)) < 0.03, 2] = 0.0  # a division by zero: inf, left out
        n = int(rng.integers(0, H * W + 1))
        flat = np.sort(rng.choice(H * W, n, replace=False)).astype(np.int64)
        rows, cols = flat // W, flat % W
        d1, d0 = pitch_diffs_both(xyz, rows, cols)
        assert _same(d1, pitch_diffs(xyz, rows, cols, 1))
        assert _same(d0, pitch_diffs(xyz, rows, cols, 0))


def _pitch_at(xyz, r, c, axis):
    """The pitch along one axis as the curved stage measured it before ``_pitches_at``: the
    median of ``pitch_diffs``, the whole image's (``_pitch``) when there is none."""
    from planerel.features._curved_kernels import pitch_diffs
    from planerel.features._relation_kernels import median
    from planerel.features.curved import _pitch

    d = pitch_diffs(np.asarray(xyz, dtype=np.float64), np.asarray(r, dtype=np.int64),
                    np.asarray(c, dtype=np.int64), int(axis))
    return float(median(d)) if d.size else _pitch(xyz, axis)


def test_pitches_at_is_pitch_at_of_each_axis():
    from planerel.features.curved import _pitches_at

    rng = np.random.default_rng(2225)
    xyz = rng.normal(size=(30, 40, 3))
    xyz[..., 2] = rng.uniform(0.5, 3.0, (30, 40))
    for rows, cols in ((np.array([3, 3, 7]), np.array([5, 6, 39])),
                       (np.array([29]), np.array([39])),  # no neighbour: the whole image's
                       (np.arange(30), np.full(30, 12))):
        got = _pitches_at(xyz, rows, cols)
        assert got == (_pitch_at(xyz, rows, cols, 1), _pitch_at(xyz, rows, cols, 0))
    # a strided window (the raised groups' grid)
    bx = xyz[1:29:2, 0:40:2]
    rows, cols = np.array([0, 2, 5]), np.array([1, 1, 3])
    assert _pitches_at(bx, rows, cols) == (_pitch_at(bx, rows, cols, 1), _pitch_at(bx, rows, cols, 0))


def test_mask_values_is_boolean_indexing():
    from planerel.features._curved_kernels import mask_values

    rng = np.random.default_rng(2226)
    for dtype in (np.int32, np.int64):
        for _ in range(100):
            H, W = (int(v) for v in rng.integers(1, 50, 2))
            lab = rng.integers(-1, 20, (H, W)).astype(dtype)
            m = np.zeros((H, W), bool)
            for _ in range(int(rng.integers(0, 4))):  # a few blobs on a few rows
                r0, c0 = int(rng.integers(0, H)), int(rng.integers(0, W))
                m[r0:r0 + int(rng.integers(1, 6)), c0:c0 + int(rng.integers(1, 9))] = True
            got = mask_values(m, lab)
            assert _same(got, lab[m])
            assert _same(np.unique(got), np.unique(lab[m]))


def test_label_bound_only_where_the_planes_labels_are_the_labels():
    from planerel.features.facts import _label_bound
    from planerel.features.planes import label_max, measure_planes
    from planerel.synth.generator import generate_scene

    sc = generate_scene("box", seed=3, subsample=4)
    lab = np.asarray(sc.gt_labels)
    planes = measure_planes(sc.cloud, lab)
    assert _label_bound(lab.astype(np.int32), planes, False) == label_max(planes.labels) + 1
    assert _label_bound(lab.astype(np.int16), planes, False) == label_max(planes.labels) + 1
    valid = sc.cloud.valid
    assert label_max(planes.labels) == int(lab[valid].max())
    # labels int32 cannot hold, or planes split again: the curved stage takes the image's own
    assert _label_bound(lab.astype(np.int64), planes, False) is None
    assert _label_bound(lab.astype(np.uint32), planes, False) is None
    assert _label_bound(lab.astype(np.int32), planes, True) is None


def _curved_both_ways(cloud, labels):
    """``describe_scene``'s objects with the label bound, and ``curved_objects`` asked again
    without it (the image's own largest label) on the same inputs."""
    from planerel.features import curved as C
    from planerel.features.facts import describe_scene

    seen = []
    orig = C.curved_objects

    def spy(*args, **kw):
        out = orig(*args, **kw)
        seen.append((args, kw, out))
        return out

    C.curved_objects = spy
    try:
        describe_scene(cloud, labels)
    finally:
        C.curved_objects = orig
    (args, kw, out), = seen
    return args, kw, out, orig(*args[:-1], None, **kw)


def _same_objects(a, b) -> bool:
    return len(a) == len(b) and all(
        x.planes == y.planes and x.planar_fraction == y.planar_fraction and x.curved == y.curved
        and x.n_points == y.n_points
        and ((x.mask is None and y.mask is None) or _same(x.mask, y.mask)) for x, y in zip(a, b, strict=True))


@pytest.mark.skipif(not (_DATA / "kinect").is_dir(), reason="needs ../shared/data")
def test_curved_objects_with_the_label_bound_on_real_frames():
    from planerel.io.readers import read
    from planerel.segment import segment

    clustered = 0
    for f in sorted((_DATA / "kinect").glob("*_depth.tiff")):
        cloud = read(f)
        labels = segment(cloud).labels
        args, _kw, with_bound, without = _curved_both_ways(cloud, labels)
        assert args[-1] is not None  # the bound was given
        assert _same_objects(with_bound, without)
        clustered += sum(o.mask is not None for o in with_bound)
    assert clustered >= 3  # the Kinect frames' clusters were counted both ways


def test_open_pixels_of_a_mask_list_is_open_mask():
    """The raw pixels opened from their list (open_pixels with nothing dropped, as
    raised_clusters asks open_pixel_list) are open_mask's pixels, row-major."""
    from planerel.features._curved_kernels import open_mask, open_pixels
    from planerel.features.raised import _NO_DROP
    from planerel.segment._label_kernels import mask_pixels

    rng = np.random.default_rng(2227)
    kept = 0
    for _ in range(300):
        H, W = (int(v) for v in rng.integers(1, 60, 2))
        mask = rng.random((H, W)) < rng.uniform(0.0, 0.3)
        for _ in range(int(rng.integers(0, 4))):  # blocks that survive an opening
            r0, c0 = int(rng.integers(0, H)), int(rng.integers(0, W))
            mask[r0:r0 + int(rng.integers(1, 12)), c0:c0 + int(rng.integers(1, 12))] = True
        rows, cols = mask_pixels(mask)
        for r in (0, 1, 2, 3):
            want = open_mask(mask, r)
            _, ro, co = open_pixels(rows, cols, mask.view(np.uint8), _NO_DROP, H, W, r)
            wr, wc = np.nonzero(want)
            assert _same(ro, wr.astype(np.int64)) and _same(co, wc.astype(np.int64))
            kept += len(ro) > 0
    assert kept > 300


def _raised_clusters_with_open_mask(cloud, labels, planes, support):
    """raised_clusters as it was (open_mask over the grid), patched in for the comparison."""
    import planerel.features._curved_kernels as K
    import planerel.features.raised as R

    keep = K.open_pixel_list

    def old_open(rows, cols, raw8, drop, H, W, r):
        # the mask alone, at the default radius (not the arguments the new code passes)
        m = K.open_mask(raw8.view(np.bool_), R.RaisedParams().open_px)
        rr, cc = np.nonzero(m)
        return rr.astype(np.int64), cc.astype(np.int64)

    K.open_pixel_list = old_open
    try:
        return R.raised_clusters(cloud, labels, planes, support)
    finally:
        K.open_pixel_list = keep


def test_raised_clusters_as_with_open_mask():
    from scenes_analytic import camera_rotation, floor, render

    from planerel.features.facts import describe_scene
    from planerel.features.raised import RaisedParams, raised_clusters
    from planerel.io.cloud import Cloud

    cloud, lab, up, _objs = render([floor()], noise=0.001, pitch=45, cam_height=1.2, width=320,
                                   height=240)
    d = describe_scene(cloud, lab)
    xyz = np.array(cloud.xyz)
    world = xyz @ camera_rotation(45, 0).T + np.array([0.0, 0.0, 1.2])
    found = 0
    sensitive = 0
    shapes = [(r2 < rad ** 2) for r2, rad in
              (((world[..., 0] - cx) ** 2 + (world[..., 1] - cy) ** 2, rad)
               for cx, cy, rad in ((0.2, 1.6, 0.15), (-0.3, 1.3, 0.1), (0.0, 2.0, 0.3),
                                   (0.4, 1.2, 0.03)))]
    # thin strips 40 cm long: whether they survive the opening depends on its radius
    shapes += [(np.abs(world[..., 0] - 0.1) < w / 2) & (np.abs(world[..., 1] - 1.5) < 0.2)
               for w in (0.02, 0.03, 0.04, 0.05, 0.06)]
    for k, where in enumerate(shapes):
        hgt = (0.008, 0.012, 0.02, 0.01)[k % 4]
        step = Cloud(xyz + np.where(where, hgt, 0.0)[..., None] * up, cloud.intrinsics, up,
                     "analytic")
        got = raised_clusters(step, lab, d.planes, d.support)
        want = _raised_clusters_with_open_mask(step, lab, d.planes, d.support)
        assert len(got) == len(want) and all(_same(a, b) for a, b in zip(got, want, strict=True))
        found += len(got)
        for r in (1, 3):
            other = raised_clusters(step, lab, d.planes, d.support, RaisedParams(open_px=r))
            sensitive += len(other) != len(got) or not all(_same(a, b) for a, b in zip(got, other, strict=True))
    assert found >= 2
    assert sensitive >= 1  # the scenes tell the opening's radius apart


def test_box_label_heights_range_is_heights_then_finite_range():
    from planerel.features._relation_kernels import (
        box_label_heights,
        box_label_heights_range,
        finite_range,
    )

    rng = np.random.default_rng(2228)
    for _ in range(200):
        H, W = (int(v) for v in rng.integers(1, 40, 2))
        lab = rng.integers(-1, 4, (H, W)).astype(np.int32)
        xyz = rng.normal(size=(H, W, 3)) * rng.uniform(0.01, 3.0)
        xyz[rng.random((H, W)) < 0.1] = np.nan
        xyz[rng.random((H, W)) < 0.02, 0] = np.inf
        up = rng.normal(size=3)
        up /= np.linalg.norm(up)
        r0, c0 = int(rng.integers(0, H)), int(rng.integers(0, W))
        r1, c1 = int(rng.integers(r0, H + 1)), int(rng.integers(c0, W + 1))
        label = int(rng.integers(-1, 4))
        h, n, lo, hi = box_label_heights_range(lab, xyz, label, r0, c0, r1, c1, up)
        want = box_label_heights(lab, xyz, label, r0, c0, r1, c1, up)
        assert _same(h, want)
        n0, lo0, hi0 = finite_range(want)
        assert n == n0 and _same(np.float64(lo), np.float64(lo0)) and _same(np.float64(hi), np.float64(hi0))


def test_split_stepped_as_with_stepped_levels():
    """split_stepped takes the heights' range from their own pass: the same split as
    stepped_levels of the heights (on rendered flights seen from above, split or not)."""
    from planerel.features import stepped as S
    from planerel.features.planes import measure_planes
    from planerel.synth.generator import generate_scene

    def old(xyz, labels, planes, rise=(0.08, 0.30), margin=0.02):
        up = np.asarray(planes.up, float)
        out, parent, nxt = None, {}, None
        lab = np.asarray(labels)
        for p in planes:
            if p.orientation != "inclined" or p.is_floor:
                continue
            box = (slice(p.bbox[0], p.bbox[2]), slice(p.bbox[1], p.bbox[3]))
            h = S._box_heights(lab, xyz, p.label, box, up)
            levels = S.stepped_levels(h, rise, margin=margin)
            if not levels:
                continue
            m = lab[box] == p.label
            if out is None:
                out = lab.astype(np.int32, copy=True)
                nxt = int(lab.max()) + 1
            new = np.full(h.shape, -1, np.int32)
            for k, (a, b) in enumerate(levels):
                new[(h >= a - margin) & (h <= b + margin)] = p.label if k == 0 else nxt
                if k > 0:
                    parent[nxt] = p.label
                    nxt += 1
            out[box][m] = new
        return None if out is None else (out, parent)

    split = 0
    for kind, seed in (("stairs", 1), ("stairs", 2), ("stairs", 3), ("ramp", 1), ("box", 2)):
        sc = generate_scene(kind, seed=seed, subsample=2)
        lab = np.asarray(sc.gt_labels)
        # the treads of a flight joined into one label: a "plane" that lies on levels
        if kind == "stairs":
            planes0 = measure_planes(sc.cloud, lab)
            treads = [p.label for p in planes0 if p.orientation == "horizontal" and not p.is_floor]
            lab = lab.copy()
            for t in treads[1:]:
                lab[lab == t] = treads[0]
        planes = measure_planes(sc.cloud, lab)
        got, want = S.split_stepped(sc.cloud.xyz, planes.labels, planes), old(
            sc.cloud.xyz, planes.labels, planes)
        assert (got is None) == (want is None)
        if got is not None:
            assert _same(got[0], want[0]) and got[1] == want[1]
            split += 1
    assert split >= 1


def test_cluster_spans_at_is_cluster_spans_of_the_gathered_points():
    from planerel.features._stairfit_kernels import cluster_spans, cluster_spans_at
    from planerel.features.stairfit import _gather, _narrow_clusters, _narrow_clusters_at

    rng = np.random.default_rng(2229)
    for _ in range(150):
        H, W = (int(v) for v in rng.integers(1, 40, 2))
        xyz = rng.normal(size=(H, W, 3)) * rng.uniform(0.05, 3.0)
        xyz[rng.random((H, W)) < 0.05] = np.nan
        N = int(rng.integers(0, H * W + 1))
        flat = np.sort(rng.choice(H * W, N, replace=False)).astype(np.int64)
        rows, cols = flat // W, flat % W
        n = int(rng.integers(1, 8))
        ids = rng.integers(0, n, N).astype(np.int64)
        e1 = rng.normal(size=3)
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(e1, [0.0, 0.0, 1.0])
        pts = _gather(xyz, rows, cols)
        assert _same(cluster_spans_at(xyz, rows, cols, ids, n, e1, e2),
                     cluster_spans(pts, ids, n, e1, e2))
        w = float(rng.uniform(0.1, 3.0))
        assert _same(_narrow_clusters_at(xyz, rows, cols, ids, n, e1, e2, w),
                     _narrow_clusters(pts, ids, n, e1, e2, w))


def test_open_pixel_list_is_open_pixels():
    """The opening from each row's runs (no image) against open_pixels (and so open_mask):
    random masks of blocks and noise, labels dropped, radii 0-3, the image's borders."""
    from planerel.features._curved_kernels import open_mask, open_pixel_list, open_pixels
    from planerel.segment._label_kernels import mask_pixels

    rng = np.random.default_rng(2230)
    kept = 0
    for _ in range(400):
        H, W = (int(v) for v in rng.integers(1, 70, 2))
        mask = rng.random((H, W)) < rng.uniform(0.0, 0.5)
        for _ in range(int(rng.integers(0, 6))):
            r0, c0 = int(rng.integers(0, H)), int(rng.integers(0, W))
            mask[r0:r0 + int(rng.integers(1, 15)), c0:c0 + int(rng.integers(1, 15))] = True
        lab = rng.integers(-1, 6, (H, W)).astype(np.int32)
        drop = rng.random(int(rng.integers(0, 7))) < 0.3
        rows, cols = mask_pixels(mask)
        for r in (0, 1, 2, 3):
            _, wr, wc = open_pixels(rows, cols, lab, drop, H, W, r)
            gr, gc = open_pixel_list(rows, cols, lab, drop, H, W, r)
            assert _same(gr, wr) and _same(gc, wc), (H, W, r)
            kept += len(gr) > 0
        # nothing dropped: open_mask of the mask itself
        for r in (1, 2):
            want = np.nonzero(open_mask(mask, r))
            got = open_pixel_list(rows, cols, lab, np.zeros(0, np.bool_), H, W, r)
            assert _same(got[0], want[0].astype(np.int64)) and _same(got[1], want[1].astype(np.int64))
    assert kept > 400


def test_list_components_spans_is_list_components_then_cluster_spans():
    from planerel.features._curved_kernels import list_components, list_components_spans
    from planerel.features._stairfit_kernels import cluster_spans
    from planerel.features.stairfit import _gather

    rng = np.random.default_rng(2231)
    multi = 0
    for _ in range(200):
        H, W = (int(v) for v in rng.integers(1, 50, 2))
        xyz = np.stack(np.meshgrid(np.linspace(-1, 1, W), np.linspace(-1, 1, H)), -1)
        xyz = np.concatenate([xyz, np.full((H, W, 1), 1.5)], -1)
        xyz[..., 2] += 0.3 * (rng.random((H, W)) < 0.15)  # jumps that cut components
        xyz[rng.random((H, W)) < 0.03] = np.nan
        xyz[rng.random((H, W)) < 0.01, 0] = np.inf
        mask = rng.random((H, W)) < rng.uniform(0.1, 0.9)
        rr, cc = np.nonzero(mask)
        rows, cols = rr.astype(np.int64), cc.astype(np.int64)
        e1 = rng.normal(size=3)
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(e1, [0.0, 0.0, 1.0])
        for edge in (0.02, 0.1):
            ids, k = list_components(rows, cols, xyz, edge, H)
            ids2, k2, span = list_components_spans(rows, cols, xyz, edge, H, e1, e2)
            assert k2 == k and _same(ids2, ids)
            assert _same(span, cluster_spans(_gather(xyz, rows, cols), ids, k, e1, e2))
            multi += k > 3
    assert multi > 100


def test_list_components_pitch_is_list_components_and_pitch_diffs_both():
    from planerel.features._curved_kernels import (
        list_areas,
        list_areas_depths,
        list_components,
        list_components_pitch,
        pitch_diffs_both,
    )

    rng = np.random.default_rng(2232)
    for _ in range(200):
        H, W = (int(v) for v in rng.integers(1, 50, 2))
        xyz = np.stack(np.meshgrid(np.linspace(-1, 1, W), np.linspace(-1, 1, H)), -1)
        xyz = np.concatenate([xyz, rng.uniform(0.3, 4.0, (H, W, 1))], -1)
        xyz[..., 2] += 0.3 * (rng.random((H, W)) < 0.15)
        xyz[rng.random((H, W)) < 0.05] = np.nan
        xyz[rng.random((H, W)) < 0.02, 2] = 0.0
        mask = rng.random((H, W)) < rng.uniform(0.05, 0.9)
        rr, cc = np.nonzero(mask)
        rows, cols = rr.astype(np.int64), cc.astype(np.int64)
        for edge in (0.02, 0.1):
            ids, k, d1, d0 = list_components_pitch(rows, cols, xyz, edge, H)
            want_ids, want_k = list_components(rows, cols, xyz, edge, H)
            w1, w0 = pitch_diffs_both(xyz, rows, cols)
            assert k == want_k and _same(ids, want_ids) and _same(d1, w1) and _same(d0, w0)
            area, zs, cnt = list_areas_depths(xyz, rows, cols, ids, 0.0017, 0.0019, k)
            assert _same(area, list_areas(xyz, rows, cols, ids, 0.0017, 0.0019, k))
            assert _same(zs, np.bincount(ids, weights=xyz[rows, cols, 2], minlength=k))
            assert _same(cnt, np.bincount(ids, minlength=k).astype(np.int64))


def _raised_tests_reference():
    """_raised_tests as it was (every plane pixel's mean divided out), compiled here."""
    import math

    from numba import njit

    @njit(cache=False)
    def ref(xyz, r0, c0, f, on, rs, rc, a, min_rise, k_sigma, r):
        H, W = on.shape
        raw = np.zeros((H, W), np.bool_)
        weak = np.zeros((H, W), np.bool_)
        cs = np.zeros(W)
        cc = np.zeros(W, np.int64)
        for k in range(min(r, H)):
            for j in range(W):
                cs[j] += rs[k, j]
                cc[j] += rc[k, j]
        for o in range(H):
            if o + r < H:
                for j in range(W):
                    cs[j] += rs[o + r, j]
                    cc[j] += rc[o + r, j]
            if o - r - 1 >= 0:
                for j in range(W):
                    cs[j] -= rs[o - r - 1, j]
                    cc[j] -= rc[o - r - 1, j]
            for j in range(W):
                c = cc[j]
                if not on[o, j] or c <= 0:
                    continue
                mean = cs[j] / c
                if mean <= 0.5 * min_rise:
                    continue
                z = max(abs(xyz[r0 + o * f, c0 + j * f, 2]), 0.1)
                lim = max(min_rise, k_sigma * a * z * z / math.sqrt(c))
                raw[o, j] = mean > lim
                weak[o, j] = mean > 0.5 * lim
        return raw, weak

    return ref


def test_raised_tests_reject_by_a_product_as_by_the_mean():
    """The window test's product bound rejects only what the division rejects, and the
    branch-free flags of each row (speed22y) let through what the branchy tests did: random
    windows, sums within a few ulps of half the rise times the count, non-finite sums."""
    from planerel.features._raised_kernels import _raised_tests

    ref = _raised_tests_reference()
    rng = np.random.default_rng(2233)
    near = odd = hits = 0
    for _ in range(300):
        H, W = (int(v) for v in rng.integers(1, 30, 2))
        r = int(rng.integers(0, 6))  # windows taller than the grid too
        min_rise = float(rng.choice([0.006, 0.01, 1e-3]))
        on = rng.random((H, W)) < 0.8
        rc = rng.integers(0, 2 * r + 2, (H, W)).astype(np.int32)
        rs = (rng.normal(size=(H, W)) * 0.004 + 0.003).astype(np.float32)
        if rng.random() < 0.5:
            # row sums that put many window sums at about half the rise times their count
            rs = (rc * np.float32(0.5 * min_rise)).astype(np.float32)
            rs = np.nextafter(rs, np.float32(rng.choice([-1.0, 1.0])) * np.inf) if rng.random() < 0.5 else rs
            near += 1
        if rng.random() < 0.3:
            # non-finite row sums (the flag lets a NaN window through to the division, as
            # the branchy test did; infinities either way)
            rs[rng.random((H, W)) < 0.05] = rng.choice([np.nan, np.inf, -np.inf])
            odd += 1
        xyz = rng.uniform(0.3, 4.0, (H, W, 3))
        a = float(rng.uniform(0.0, 0.01))
        got = _raised_tests(xyz, 0, 0, 1, on, rs, rc, a, min_rise, 4.0, r)
        want = ref(xyz, 0, 0, 1, on, rs, rc, a, min_rise, 4.0, r)
        assert _same(got[0], want[0]) and _same(got[1], want[1])
        hits += int(want[0].sum()) + int(want[1].sum())
    assert near > 50 and odd > 50 and hits > 100


def test_boundary_tiles_remembered_with_the_label_image():
    """The touch test and the edge sums read one set of boundary tiles, remembered with a
    PlaneSet's labels: the kernels' own tiles, and the same pairs and sums."""
    from planerel.features._relation_kernels import (
        boundary_tiles,
        edge_sums_pairs,
        edge_sums_pairs_with_tiles,
        touch_pairs_tiled,
        touch_pairs_with_tiles,
    )
    from planerel.features.planes import _boundary_pixels, _boundary_tiles, measure_planes
    from planerel.synth.generator import generate_scene

    for kind, seed in (("box", 1), ("stairs", 2)):
        sc = generate_scene(kind, seed=seed, subsample=2)
        planes = measure_planes(sc.cloud, np.asarray(sc.gt_labels))
        lab = planes.labels
        brow, bcol = _boundary_pixels(lab)
        tiles = _boundary_tiles(lab)
        assert _same(tiles, boundary_tiles(lab, brow, bcol))
        assert _boundary_tiles(lab) is tiles and not tiles.flags.writeable  # remembered
        other = np.array(lab)  # writeable: measured, not remembered
        assert _same(_boundary_tiles(other), tiles) and _boundary_tiles(lab) is tiles
        xyz = np.ascontiguousarray(sc.cloud.xyz)
        known = np.ones(int(lab.max()) + 1, bool)
        assert _same(touch_pairs_with_tiles(xyz, lab, brow, bcol, tiles, 2, 0.02, 0.05, known),
                     touch_pairs_tiled(xyz, lab, brow, bcol, 2, 0.02, 0.05, known))
        partner = np.ones((len(known), len(known)), bool)
        for got, want in zip(edge_sums_pairs_with_tiles(lab, xyz, brow, bcol, tiles, partner, 2, 0.02),
                             edge_sums_pairs(lab, xyz, brow, bcol, partner, 2, 0.02), strict=True):
            assert _same(got, want)
