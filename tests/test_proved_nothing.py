"""Work skipped where a cheap bound proves it can find nothing (speed22u, issue 22): each fast
path against the form it replaced, which the tests keep as the reference, on random cases and
on real frames; the answers must be the same, bit for bit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

_DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def _same(a, b) -> bool:
    """The same values, bit for bit."""
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def _boundary_list(lab):
    """Every boundary pixel of ``lab`` (``label_boundary``), row-major."""
    from planerel.segment._label_kernels import label_boundary, mask_pixels

    return mask_pixels(label_boundary(np.ascontiguousarray(lab, dtype=np.int32)))


def _blobs(rng, H, W, nlab):
    """A label image of rectangles (labels ``0..nlab-1``, drawn over one another) on unassigned
    pixels, with holes: planes with long outlines, touching and apart."""
    lab = np.full((H, W), -1, np.int32)
    for k in range(nlab):
        r0, c0 = int(rng.integers(0, H)), int(rng.integers(0, W))
        r1, c1 = r0 + int(rng.integers(1, max(2, H // 2))), c0 + int(rng.integers(1, max(2, W // 2)))
        lab[r0:r1, c0:c1] = k
    lab[rng.random((H, W)) < 0.05] = -1
    return lab


def _cloud(rng, H, W, lab):
    """Points on a few depth levels (one per label, so some neighbours touch in 3-D and some
    do not), noise, and invalid pixels."""
    z = 1.0 + 0.02 * (np.maximum(lab, 0) % 3) + rng.normal(size=(H, W)) * 0.01
    u, v = np.meshgrid(np.arange(W), np.arange(H))
    xyz = np.stack([(u - W / 2) * z / 500, (v - H / 2) * z / 500, z], -1)
    xyz[rng.random((H, W)) < 0.05] = np.nan
    return np.ascontiguousarray(xyz)


# ---- the touch test: windows that meet no tile of an untested label are not read

def test_boundary_tiles_hold_every_boundary_label_of_each_tile():
    from planerel.features._relation_kernels import TILE_SHIFT, boundary_tiles

    rng = np.random.default_rng(2201)
    for _ in range(40):
        H, W = (int(v) for v in rng.integers(1, 60, 2))
        lab = _blobs(rng, H, W, int(rng.integers(1, 80)))
        rows, cols = _boundary_list(lab)
        tiles = boundary_tiles(lab, rows, cols)
        T = 1 << TILE_SHIFT
        assert tiles.shape == (-(-H // T), -(-W // T))
        want = np.zeros(tiles.shape, np.uint64)
        for r, c in zip(rows.tolist(), cols.tolist(), strict=True):
            want[r // T, c // T] |= np.uint64(1) << np.uint64(min(int(lab[r, c]), 63))
        assert _same(tiles, want)


def test_touch_pairs_tiled_is_touch_pairs_on_random_label_images():
    from planerel.features._relation_kernels import touch_pairs_tiled
    from planerel.segment._label_kernels import touch_pairs

    rng = np.random.default_rng(2202)
    found = skipped_labels = 0
    for t in range(150):
        H, W = (int(v) for v in rng.integers(2, 70, 2))
        # up to 90 labels: labels from 63 on share one bit of the tiles
        nlab = int(rng.integers(1, 12 if t % 3 else 90))
        lab = _blobs(rng, H, W, nlab)
        xyz = _cloud(rng, H, W, lab)
        known = rng.random(max(int(lab.max()) + 1, 1)) < 0.85
        skipped_labels += int((~known).sum())
        rows, cols = _boundary_list(lab)
        g = int(rng.integers(1, 5))
        rel = float(rng.choice([0.0, 0.02, 0.05]))
        want = touch_pairs(xyz, lab, rows, cols, g, 0.015, rel, known)
        got = touch_pairs_tiled(xyz, lab, rows, cols, g, 0.015, rel, known)
        found += int(want.sum())
        assert _same(got, want), (t, H, W, nlab, g)
    assert found > 500 and skipped_labels > 20


@pytest.mark.skipif(not (_DATA / "mosd").is_dir(), reason="needs ../shared/data")
def test_touch_pairs_tiled_on_real_frames():
    from planerel.features._relation_kernels import touch_pairs_tiled
    from planerel.features.planes import _boundary_pixels, label_max
    from planerel.features.relations import RelationParams, _touching
    from planerel.io.readers import read
    from planerel.segment import segment
    from planerel.segment._label_kernels import touch_pairs

    files = sorted((_DATA / "kinect").glob("*_depth.tiff"))[:2] + sorted((_DATA / "mosd").glob("*.pcd"))[:3]
    from planerel.features.planes import measure_planes

    pairs = 0
    for f in files:
        cloud = read(f)
        planes = measure_planes(cloud, segment(cloud).labels)
        lab = np.ascontiguousarray(planes.labels, dtype=np.int32)
        xyz = np.ascontiguousarray(cloud.xyz)
        known = np.zeros(label_max(planes.labels) + 1, bool)
        known[[p.label for p in planes]] = True
        rows, cols = _boundary_pixels(planes.labels)
        for g in (1, 2, 3):
            want = touch_pairs(xyz, lab, rows, cols, g, 0.05, 0.05, known)
            assert _same(touch_pairs_tiled(xyz, lab, rows, cols, g, 0.05, 0.05, known), want)
            pairs += int(want.sum()) // 2
        # relate's own call
        got = _touching(planes, RelationParams(), cloud.xyz)
        want = touch_pairs(xyz, lab, rows, cols, 2, 0.05, 0.05, known)
        a, b = np.nonzero(want)
        assert got == {(x, y) for x, y in zip(a.tolist(), b.tolist(), strict=True) if x < y}
    assert pairs > 30


# ---- the edge sums: only the wanted pairs, pixels whose band meets none of them not read

def _edge_sums_of(lab, xyz, rows, cols, want, band, depth):
    """``edge_sums`` (every pair of labels of a wanted pair) and ``edge_sums_pairs`` (the
    wanted pairs alone), ``n`` the label count."""
    from planerel.features._relation_kernels import edge_sums, edge_sums_pairs

    n = max(int(lab.max()) + 1, 1)
    used = np.zeros(n, bool)
    partner = np.zeros((n, n), bool)
    for a, b in want:
        used[a] = used[b] = True
        partner[a, b] = partner[b, a] = True
    return (edge_sums(lab, xyz, rows, cols, used, band, depth, n),
            edge_sums_pairs(lab, xyz, rows, cols, partner, band, depth), n)


def _check_wanted(old, new, n, want) -> int:
    """The wanted pairs' count and sums bit for bit; every other pair's entries 0."""
    codes = {min(a, b) * n + max(a, b) for a, b in want}
    for c in codes:
        for o, w in zip(old, new, strict=True):
            assert _same(o[c], w[c])
    rest = np.ones(n * n, bool)
    rest[list(codes)] = False
    for w in new:
        assert not np.any(w[rest])
    return int(sum(old[0][c] for c in codes))


def test_edge_sums_pairs_are_edge_sums_of_the_wanted_pairs():
    rng = np.random.default_rng(2203)
    counted = 0
    for t in range(150):
        H, W = (int(v) for v in rng.integers(2, 70, 2))
        lab = _blobs(rng, H, W, int(rng.integers(2, 12 if t % 3 else 80)))
        xyz = _cloud(rng, H, W, lab)
        n = int(lab.max()) + 1
        labels = np.unique(lab[lab >= 0])
        want = {(int(a), int(b)) for a in labels for b in labels
                if a < b and rng.random() < (0.3 if t % 2 else 0.9)}
        rows, cols = _boundary_list(lab)
        band = int(rng.integers(1, 5))
        old, new, n = _edge_sums_of(lab, xyz, rows, cols, want, band, 0.03)
        counted += _check_wanted(old, new, n, want)
    assert counted > 1000


@pytest.mark.skipif(not (_DATA / "mosd").is_dir(), reason="needs ../shared/data")
def test_edge_means_on_real_frames_are_the_old_sums():
    from planerel.features.facts import describe_scene
    from planerel.features.planes import _boundary_pixels
    from planerel.features.relations import edge_means
    from planerel.io.readers import read
    from planerel.segment import segment

    files = sorted((_DATA / "kinect").glob("*_depth.tiff"))[:1] + sorted((_DATA / "mosd").glob("*.pcd"))[:3]
    counted = 0
    for f in files:
        cloud = read(f)
        d = describe_scene(cloud, segment(cloud).labels)
        lab = np.ascontiguousarray(d.planes.labels)
        xyz = np.ascontiguousarray(cloud.xyz, dtype=np.float64)
        rows, cols = _boundary_pixels(d.planes.labels)
        drop = set(d.support)
        want = {(r.a, r.b) for r in d.relations
                if r.adjacent and r.a < r.b and r.a not in drop and r.b not in drop}
        assert want
        old, new, n = _edge_sums_of(lab, xyz, rows, cols, want, 3, 0.03)
        counted += _check_wanted(old, new, n, want)
        # edge_means itself gives the old sums' means
        got = edge_means(d.planes.labels, cloud.xyz, want, 3, 0.03)
        for a, b in want:
            c = old[0][a * n + b]
            if c > 0:
                assert _same(got[(a, b)][0], old[1][a * n + b] / c)
                assert _same(got[(a, b)][1], old[2][a * n + b] / c) and got[(a, b)][2] == int(c)
            else:
                assert (a, b) not in got
    assert counted > 200


# ---- step chains: a pair whose height difference is no rise of any span is not measured

def test_step_chains_skip_only_pairs_no_span_can_take(monkeypatch):
    from scenes_analytic import floor, render, stairs

    import planerel.features.step_chains as R
    from planerel.features.facts import describe_scene

    view = dict(pitch=30, cam_height=1.6, width=320, height=240, noise=0.001)
    checked = 0
    for rise, n, drop in ((0.17, 4, ()), (0.17, 5, (3, 4)), (0.09, 5, (5, 6)), (0.28, 3, ()),
                          (0.15, 6, (4,))):
        rects = [floor()] + stairs(0.0, 2.0, n=n, rise=rise, run=0.28, obj=1)
        cloud, lab, _up, _objs = render(rects, **view)
        planes = describe_scene(cloud, lab).planes
        some = [p.label for p in planes if p.label not in drop]
        for kw in ({}, {"skip_missing": True}, {"tread_axes": True}, {"skip": False}):
            got = R.step_chain_pairs(planes, some, **kw)
            with monkeypatch.context() as m:
                m.setattr(R, "_some_rise", lambda *a: True)  # the form before: every pair measured
                want = R.step_chain_pairs(planes, some, **kw)
            assert got == want
            checked += len(want)
    assert checked > 20


def test_some_rise_is_the_rise_half_of_the_step_test():
    from planerel.features.relations import _some_rise

    rise = (0.08, 0.30)
    assert _some_rise(0.17, rise, (1, 2)) and _some_rise(0.5, rise, (1, 2))
    assert not _some_rise(0.5, rise, (1,)) and not _some_rise(0.61, rise, (1, 2))
    assert not _some_rise(0.05, rise, (1, 2)) and _some_rise(0.16, rise, (2,))
    assert not _some_rise(float("nan"), rise, (1, 2))


# ---- the floor as a tread: a floor wider than a step's run across every direction

def _random_hull(rng):
    """``(hull3d (K, 3), up)``: the convex hull of random points (round, long, thin, tiny or
    few), in a plane tilted up to 15 degrees from the horizontal, the up vector random."""
    import shapely

    n = int(rng.integers(3, 40))
    pts = rng.normal(size=(n, 2)) * [rng.uniform(0.01, 3.0), rng.uniform(0.001, 3.0)]
    if rng.random() < 0.2:
        pts = pts.round(1)  # repeated and collinear vertices
    geom = shapely.convex_hull(shapely.multipoints(pts))
    if geom.geom_type != "Polygon":
        return None, None
    v = np.asarray(shapely.geometry.polygon.orient(geom, 1.0).exterior.coords)[:-1]
    up = rng.normal(size=3)
    up /= np.linalg.norm(up)
    tilt = np.radians(rng.uniform(0, 15))
    a = np.cross(up, rng.normal(size=3))
    a /= np.linalg.norm(a)
    b = np.cross(up, a)
    # the plane's axes: b tilted towards up
    u = a
    w = np.cos(tilt) * b + np.sin(tilt) * up
    c = rng.normal(size=3)
    return c + v[:, :1] * u + v[:, 1:] * w, up


def test_surely_deep_never_says_deep_where_the_calipers_measure_a_step():
    from types import SimpleNamespace

    from planerel.features.relations import _surely_deep, _tread_depth_axis

    rng = np.random.default_rng(2205)
    said = tested = 0
    for _ in range(3000):
        H, up = _random_hull(rng)
        if H is None:
            continue
        p = SimpleNamespace(hull3d=H)
        f_dir, _ = _tread_depth_axis(p, up)
        width = float(np.ptp(H @ f_dir))  # what _floor_is_tread compares with the run
        for limit in (width * rng.uniform(0.3, 1.0), width, width * rng.uniform(1.0, 1.5)):
            deep = _surely_deep(p, up, float(limit))
            tested += 1
            said += deep
            assert not (deep and width <= limit), (width, limit)
    assert tested > 6000 and said > 1000  # the bound takes a good part of the floors


def test_surely_deep_on_small_and_degenerate_hulls():
    from types import SimpleNamespace

    from planerel.features.relations import _surely_deep

    up = np.array([0.0, 0.0, 1.0])
    square = np.array([[0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0.0]])
    assert _surely_deep(SimpleNamespace(hull3d=square), up, 0.6)  # 2 x 2 m: A/D = 1.41
    assert not _surely_deep(SimpleNamespace(hull3d=square), up, 1.5)
    strip = np.array([[0, 0, 0], [5, 0, 0], [5, 0.5, 0], [0, 0.5, 0.0]])
    assert not _surely_deep(SimpleNamespace(hull3d=strip), up, 0.6)  # 0.5 m deep: a run
    for H in (square[:2], square[:0], np.zeros((4, 3)), np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0.0]])):
        assert not _surely_deep(SimpleNamespace(hull3d=H), up, 0.0)
    # a wall (vertical): its projection has no area
    wall = np.array([[0, 0, 0], [3, 0, 0], [3, 0, 2], [0, 0, 2.0]])
    assert not _surely_deep(SimpleNamespace(hull3d=wall), up, 0.01)


@pytest.mark.skipif(not (_DATA / "mosd").is_dir(), reason="needs ../shared/data")
def test_surely_deep_on_real_floors():
    from planerel.features.facts import describe_scene
    from planerel.features.relations import (
        ProposalParams,
        _floor_is_tread,
        _surely_deep,
        _tread_depth_axis,
    )
    from planerel.io.readers import read
    from planerel.segment import segment

    files = sorted((_DATA / "kinect").glob("*_depth.tiff"))[:1] + sorted((_DATA / "mosd").glob("*.pcd"))
    deep = 0
    pp = ProposalParams()
    for f in files:
        cloud = read(f)
        d = describe_scene(cloud, segment(cloud).labels)
        up = np.asarray(d.planes.up, float)
        for p in d.planes:
            if p.orientation != "horizontal":
                continue
            f_dir, _ = _tread_depth_axis(p, up)
            width = float(np.ptp(np.asarray(p.hull3d, float) @ f_dir))
            for limit in (pp.step_run_max, 0.5 * width, width):
                if _surely_deep(p, up, limit):
                    assert width > limit
                    deep += p.is_floor
        floor = next(p for p in d.planes if p.is_floor)
        assert not _floor_is_tread(d.planes, floor, d.relations, pp)
    assert deep >= len(files)  # every real floor is proved deeper than a run
