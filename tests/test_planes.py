"""Plane attributes and up-vector estimation against analytic and synthetic ground truth."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scenes_analytic import box, floor, ramp, render, stairs, wall

from planerel.errors import InputError
from planerel.features.planes import PlaneParams, estimate_up, measure_planes, resolve_up
from planerel.io.cloud import Cloud


def _deg(a, b) -> float:
    return math.degrees(math.acos(min(1.0, abs(float(np.dot(a, b))))))


def test_box_attributes_match_geometry():
    rects = [floor(), wall()] + box(0.3, 2.5, 0.6, 0.4, 0.5)
    cloud, lab, up, _ = render(rects, pitch=30, roll=0, noise=0.0, width=640, height=480)
    ps = measure_planes(cloud, lab)
    assert ps.up_source == "file"
    assert ps.floor == 0
    top = ps.by_label(2)
    assert top.orientation == "horizontal"
    assert top.height == pytest.approx(0.5, abs=0.005)
    assert top.area == pytest.approx(0.6 * 0.4, rel=0.1)  # pixel centres: a little smaller
    assert top.length == pytest.approx(0.6, abs=0.02)
    assert top.width == pytest.approx(0.4, abs=0.03)  # ~1 pixel footprint at grazing view
    front = ps.by_label(3)
    assert front.orientation == "vertical"
    assert front.height == pytest.approx(0.25, abs=0.02)  # point centroid, perspective-weighted
    for p in ps:
        assert p.offset > 0
        assert float(p.normal @ p.centroid) < 0  # towards the sensor
        assert p.rms < 1e-6
        assert p.distance == pytest.approx(float(np.linalg.norm(p.centroid)))
        assert np.allclose((p.hull3d - p.centroid) @ p.normal, 0, atol=1e-9)


def test_table_rows_equal_attributes():
    cloud, lab, _, _ = render([floor()] + box(0.0, 2.5, 0.5, 0.5, 0.4))
    ps = measure_planes(cloud, lab)
    t = ps.table()
    assert set(t) >= {"label", "area", "incline", "orientation", "normal_x", "centroid_z"}
    assert all(len(v) == len(ps) for v in t.values())
    for k, p in enumerate(ps):
        assert t["area"][k] == p.area and t["orientation"][k] == p.orientation
        assert t["normal_y"][k] == p.normal[1]


@pytest.mark.parametrize("angle", [8.0, 15.0, 25.0])
def test_ramp_incline_within_two_degrees(angle):
    cloud, lab, _, _ = render([floor(), *ramp(0.0, 2.0, angle)], pitch=25, noise=0.0012)
    ps = measure_planes(cloud, lab)
    slope = ps.by_label(1)
    assert slope.incline == pytest.approx(angle, abs=2.0)
    assert slope.orientation == ("inclined" if angle > 5 else "horizontal")  # horizontal_tol 5


def test_synthetic_ground_truth_planes():
    from planerel.synth.generator import generate_scene

    for kind, seed in (("stairs", 1), ("ramp", 1), ("box", 2)):
        sc = generate_scene(kind, seed, subsample=4)
        ps = measure_planes(sc.cloud, sc.gt_labels)
        for p in ps:
            gt = sc.planes[p.label]
            if p.n_points < 30:
                continue
            assert _deg(p.normal, gt.normal) < 3.0, (kind, gt.role)
            assert p.incline == pytest.approx(gt.incline_deg, abs=2.0)
            if gt.role in ("tread", "top", "floor"):
                assert p.orientation == "horizontal"
                assert p.height == pytest.approx(gt.height, abs=0.02)
            if gt.role in ("riser", "wall", "face"):
                assert p.orientation == "vertical"
            if gt.role == "slope":
                assert p.orientation == "inclined"


@pytest.mark.parametrize("pitch,roll", [(0, 0), (20, 5), (35, -8), (45, 10)])
def test_up_estimate_pitched_and_rolled(pitch, roll):
    rects = [floor(), wall()] + stairs(0.2, 2.0, 3) + box(-1.2, 2.6, 0.5, 0.5, 0.4, obj=2)
    cloud, lab, up, _ = render(rects, pitch=pitch, roll=roll, noise=0.0012, with_up=False)
    assert cloud.up is None
    assert _deg(estimate_up(cloud), up) < 3.0
    assert _deg(estimate_up(cloud, lab), up) < 3.0
    est = resolve_up(cloud, lab)
    assert est.source == "estimated" and float(est.vector @ up) > 0
    ps = measure_planes(cloud, lab)
    assert ps.up_source == "estimated" and ps.up_confidence == pytest.approx(est.confidence)


def test_up_sources():
    cloud, lab, up, _ = render([floor()], with_up=True)
    assert resolve_up(cloud, lab).source == "file"
    est = resolve_up(cloud, lab, up=(0, 0, 2))
    assert est.source == "given" and np.allclose(est.vector, (0, 0, 1))
    with pytest.raises(InputError, match="up vector"):
        resolve_up(cloud, lab, up=(0, 0, 0))


def _tiny_cloud(points: dict[tuple[int, int], tuple[float, float, float]], shape=(6, 6)):
    xyz = np.full(shape + (3,), np.nan)
    lab = np.full(shape, -1, np.int32)
    for (v, u), p in points.items():
        xyz[v, u] = p
        lab[v, u] = 0
    return Cloud(xyz, up=(0, -1, 0)), lab


def test_three_points_and_collinear_points():
    cloud, lab = _tiny_cloud({(1, 1): (0, 0, 1.0), (1, 2): (0.1, 0, 1.0), (2, 1): (0, 0, 1.1)})
    (p,) = measure_planes(cloud, lab)
    assert p.n_points == 3 and p.area == pytest.approx(0.005)
    assert p.hull.shape == (3, 2) and not p.degenerate
    cloud, lab = _tiny_cloud({(1, k): (0.1 * k, 0, 1.0) for k in range(4)})
    (p,) = measure_planes(cloud, lab)
    assert p.degenerate and p.area == 0.0 and p.width == 0.0
    assert p.length == pytest.approx(0.3)
    cloud, lab = _tiny_cloud({(1, 1): (0, 0, 1.0), (1, 2): (0.1, 0, 1.0)})
    ps = measure_planes(cloud, lab)
    assert len(ps) == 0 and ps.skipped == (0,)


def test_no_planes_and_no_floor():
    cloud, lab, _, _ = render([floor()])
    empty = measure_planes(cloud, np.full(lab.shape, -1, np.int32))
    assert len(empty) == 0 and empty.table()["area"].shape == (0,)
    # a box floating in view with no floor: heights from its lowest hull point
    cloud, lab, _, _ = render(box(0.0, 2.0, 0.5, 0.5, 0.4))
    ps = measure_planes(cloud, lab)
    assert ps.floor is None
    assert min(float((p.hull3d @ ps.up).min()) - ps.floor_level for p in ps) == pytest.approx(0.0)


def test_bad_input():
    cloud, lab, _, _ = render([floor()])
    with pytest.raises(InputError, match="shape"):
        measure_planes(cloud, lab[:-1])
    with pytest.raises(InputError, match="integers"):
        measure_planes(cloud, lab.astype(float))
    with pytest.raises(InputError, match="-1 = unassigned"):
        measure_planes(cloud, lab - 5)
    with pytest.raises(InputError, match="min_points"):
        PlaneParams(min_points=2)
    with pytest.raises(InputError, match="horizontal_tol"):
        PlaneParams(horizontal_tol=50)
    with pytest.raises(InputError, match="planerel Cloud"):
        measure_planes(np.zeros((4, 4, 3)), lab)


@pytest.mark.parametrize("case", ["random", "collinear", "duplicates", "grid", "two"])
def test_hull_geometry_equals_the_hull_of_the_points(case):
    """The hull is taken of a line string through the points (cheap to build); it must be the
    multipoint hull exactly: same vertices in the same order, same measures."""
    import shapely

    from planerel.features.planes import _hull_geometry

    rng = np.random.default_rng(3)
    pts = {
        "random": rng.normal(size=(500, 2)),
        "collinear": np.c_[np.linspace(0, 1, 50), 2 * np.linspace(0, 1, 50)],
        "duplicates": np.repeat(rng.normal(size=(30, 2)), 4, axis=0),
        "grid": np.stack(np.meshgrid(np.arange(20.0), np.arange(7.0)), -1).reshape(-1, 2),
        "two": np.array([[0.0, 0.0], [1.0, 0.5]]),
    }[case]
    verts, simp, area, length, width = _hull_geometry(pts, 0.01)
    ref = shapely.convex_hull(shapely.multipoints(pts))
    if ref.geom_type == "Polygon":
        from shapely.geometry.polygon import orient

        ref = orient(ref, 1.0)
        np.testing.assert_array_equal(verts, np.asarray(ref.exterior.coords)[:-1])
        assert area == ref.area
    else:
        np.testing.assert_array_equal(verts, np.asarray(ref.coords))
        assert area == 0.0


def test_label_max_and_boundary_pixels_remembered_for_the_planes_labels():
    """``label_max`` and ``_boundary_pixels`` of a PlaneSet's labels: what ``lab.max()`` and
    ``np.nonzero(label_boundary(lab))`` give, remembered by ``measure_planes`` (the relations
    and proposals ask again); a writable image is never remembered (it may change)."""
    from planerel.features import planes as P
    from planerel.segment._label_kernels import label_boundary

    rects = [floor(), wall()] + box(0.3, 2.5, 0.6, 0.4, 0.5)
    cloud, lab, _, _ = render(rects, pitch=30, roll=0, noise=0.0, width=160, height=120)
    ps = measure_planes(cloud, lab)
    own = ps.labels
    entry = P._remembered(own)
    assert entry is not None and entry[3] == int(own.max())
    rows, cols = np.nonzero(label_boundary(np.ascontiguousarray(own, dtype=np.int32)))
    got = P._boundary_pixels(own)
    assert got is entry[2]
    for a, b in zip(got, (rows, cols), strict=True):
        assert a.dtype == np.int64 and not a.flags.writeable
        assert np.array_equal(a, b)
    assert P.label_max(own) == int(own.max())
    # a writable copy: computed each time, not remembered
    mine = own.copy()
    assert P.label_max(mine) == int(own.max())
    mine[mine == int(own.max())] = -1
    assert P.label_max(mine) == int(mine.max()) < int(own.max())
    assert P._remembered(mine) is None
    assert P.label_max(np.full((3, 4), -1, np.int32)) == -1
    assert P.label_max(np.zeros((0, 4), np.int32)) == -1
    # a read-only image of its own: remembered once asked
    fixed = np.array([[0, 2], [5, -1]], np.int32)
    fixed.setflags(write=False)
    assert P.label_max(fixed) == 5 and P._remembered(fixed)[3] == 5
