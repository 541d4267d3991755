"""Synthetic scenes: geometry, ray casting, sensor model and ground truth (planerel.synth.generator)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.io.cloud import Intrinsics
from planerel.synth import geometry as sg
from planerel.synth.generator import (
    CameraRange,
    SensorModel,
    apply_sensor,
    generate_scene,
    look_at_pose,
    raycast,
    scene_seed,
)

SMALL = dict(size=(640, 480), subsample=4)  # 160x120


def _rays(intr: Intrinsics) -> np.ndarray:
    u = (np.arange(intr.width) - intr.cx) / intr.fx
    v = (np.arange(intr.height) - intr.cy) / intr.fy
    r = np.empty((intr.height, intr.width, 3))
    r[:, :, 0] = u[None, :]
    r[:, :, 1] = v[:, None]
    r[:, :, 2] = 1.0
    return r


def _fit_normal(points: np.ndarray) -> np.ndarray:
    c = points - points.mean(axis=0)
    return np.linalg.svd(c, full_matrices=False)[2][-1]


# ------------------------------------------------------------------ ray casting


def test_raycast_square_depth_extent_and_occlusion():
    intr = Intrinsics(40, 30, 20.0, 20.0, 19.5, 14.5)
    far = np.array([[-1, -1, 3.0], [1, -1, 3.0], [1, 1, 3.0], [-1, 1, 3.0]])
    near = np.array([[0, 0, 2.0], [2, 0, 2.0], [2, 2, 2.0], [0, 2, 2.0]])  # lower-right quadrant
    depth, index = raycast([far, near], intr)
    r = _rays(intr)
    in_far = (np.abs(r[:, :, 0] * 3) <= 1) & (np.abs(r[:, :, 1] * 3) <= 1)
    in_near = (r[:, :, 0] * 2 >= 0) & (r[:, :, 0] * 2 <= 2) & (r[:, :, 1] * 2 >= 0) & (r[:, :, 1] * 2 <= 2)
    np.testing.assert_array_equal(index >= 0, in_far | in_near)
    np.testing.assert_array_equal(index == 1, in_near)
    np.testing.assert_allclose(depth[in_near], 2.0)
    np.testing.assert_allclose(depth[in_far & ~in_near], 3.0)
    assert np.all(np.isnan(depth[~(in_far | in_near)]))


def test_raycast_tilted_polygon_crossing_the_camera_plane():
    """A floor running under and behind the camera: clipped at the near plane, exact depth."""
    intr = Intrinsics(32, 24, 16.0, 16.0, 15.5, 11.5)
    floor = np.array([[-5, 1.0, -5], [5, 1.0, -5], [5, 1.0, 10], [-5, 1.0, 10]])  # y = 1 (below)
    depth, index = raycast([floor], intr)
    r = _rays(intr)
    expected = np.where(r[:, :, 1] > 1 / 10, 1.0 / np.maximum(r[:, :, 1], 1e-12), np.nan)
    hit = np.isfinite(expected) & (np.abs(r[:, :, 0] * expected) <= 5)
    np.testing.assert_array_equal(index == 0, hit)
    np.testing.assert_allclose(depth[hit], expected[hit], rtol=1e-12)


def test_look_at_pose_is_a_rotation_looking_at_target():
    pose = look_at_pose([1.0, -2.0, 1.2], [0.0, 0.0, 0.3], roll_deg=2.0)
    rot = pose[:3, :3]
    np.testing.assert_allclose(rot @ rot.T, np.eye(3), atol=1e-12)
    assert np.linalg.det(rot) == pytest.approx(1.0)
    target = pose @ np.array([0.0, 0.0, 0.3, 1.0])
    assert target[0] == pytest.approx(0, abs=1e-12) and target[1] == pytest.approx(0, abs=1e-12)
    assert target[2] > 0
    up = rot[:, 2]
    assert up[1] < -0.8  # the world's up points roughly to image -y


# ------------------------------------------------------------------ ground truth


@pytest.mark.parametrize("kind", ["box", "stairs", "ramp"])
@pytest.mark.parametrize("seed", [1, 2])
def test_gt_planes_match_the_pixels(kind, seed):
    s = generate_scene(kind, seed, **SMALL)
    assert s.depth_mm.shape == (120, 160) and s.depth_mm.dtype == np.uint16
    assert s.cloud.intrinsics == Intrinsics.kinect(160, 120)
    r = _rays(s.intrinsics)
    xyz = s.cloud.xyz
    valid = s.depth_mm > 0
    np.testing.assert_array_equal(valid, s.gt_labels >= 0)
    np.testing.assert_array_equal(s.gt_objects >= 0, valid)
    seen = 0
    for p in s.planes:
        n = np.array(p.normal)
        assert np.linalg.norm(n) == pytest.approx(1.0, abs=1e-8)
        assert p.offset > 0
        mask = s.gt_labels == p.index
        assert mask.sum() == p.n_pixels
        if not p.n_pixels:
            continue
        seen += 1
        # the noise-free depth lies exactly on the plane
        exact = (r[mask] * s.depth_true[mask][:, None]) @ n + p.offset
        np.testing.assert_allclose(exact, 0.0, atol=1e-9)
        # measured points lie on the plane within the sensor's error bound along the ray
        resid = np.abs(xyz[mask] @ n + p.offset)
        scale = np.abs(r[mask] @ n)
        bound4 = scale * s.sensor.error_bound(s.depth_true[mask], 4.0)
        bound6 = scale * s.sensor.error_bound(s.depth_true[mask], 6.0)
        assert np.all(resid <= bound6)
        assert np.mean(resid <= bound4) >= 0.999
        assert np.all(s.gt_objects[mask] == p.object_index)
    assert seen >= 3
    roles = {p.role for p in s.visible_planes()}
    assert "floor" in roles
    # the floor's normal (towards the camera above it) is the up vector
    floor = next(p for p in s.planes if p.role == "floor")
    np.testing.assert_allclose(floor.normal, s.up, atol=1e-8)
    assert floor.offset == pytest.approx(s.params["camera"]["height"], abs=1e-6)


def test_stairs_treads_are_horizontal_with_the_right_rise():
    rise, steps = 0.17, 4
    s = generate_scene("stairs", 5, **SMALL, steps=steps, rise=rise, tread=0.3, width=1.0,
                       walls=0, sides="open")
    treads = [p for p in s.planes if p.role == "tread"]
    risers = [p for p in s.planes if p.role == "riser"]
    assert len(treads) == steps and len(risers) == steps
    for i, t in enumerate(treads):
        assert t.incline_deg == pytest.approx(0.0, abs=1e-6)
        assert t.height == pytest.approx((i + 1) * rise, abs=1e-9)
        np.testing.assert_allclose(t.normal, s.up, atol=1e-8)
    for r_ in risers:
        assert r_.incline_deg == pytest.approx(90.0, abs=1e-6)
    # measured heights from the noisy cloud: height = camera height + up . x
    cam_h = s.params["camera"]["height"]
    heights = []
    for t in treads:
        mask = s.gt_labels == t.index
        assert mask.sum() >= 10, "every tread should be seen from above"
        heights.append(cam_h + np.median(s.cloud.xyz[mask] @ s.up))
    np.testing.assert_allclose(np.diff(heights), rise, atol=0.01)


@pytest.mark.parametrize("angle,axis", [(8.0, "pitch"), (19.0, "roll"), (30.0, "pitch"), (30.0, "roll")])
def test_ramp_incline_is_the_requested_angle(angle, axis):
    s = generate_scene("ramp", 11, **SMALL, angle_deg=angle, axis=axis, walls=0)
    slope = next(p for p in s.planes if p.role == "slope")
    assert slope.incline_deg == pytest.approx(angle, abs=1e-6)
    mask = s.gt_labels == slope.index
    assert mask.sum() > 100
    n = _fit_normal(s.cloud.xyz[mask])
    measured = math.degrees(math.acos(abs(float(n @ s.up))))
    assert measured == pytest.approx(angle, abs=1.5)
    # pitch ramps rise away from the camera, roll ramps across the view
    fwd = np.array([0.0, 0.0, 1.0])
    horizontal_normal = np.array(slope.normal) - (np.array(slope.normal) @ s.up) * s.up
    horizontal_normal /= np.linalg.norm(horizontal_normal)
    fwd_h = fwd - (fwd @ s.up) * s.up
    fwd_h /= np.linalg.norm(fwd_h)
    along = abs(float(horizontal_normal @ fwd_h))
    if axis == "pitch":
        assert along > math.cos(math.radians(50))
    else:
        assert along < math.sin(math.radians(50))


def test_ramp_platform_and_sides():
    s = generate_scene("ramp", 3, **SMALL, angle_deg=15.0, platform=0.6, side_faces=True)
    roles = [p.role for p in s.planes if p.object_index == 1]
    assert roles == ["slope", "top", "back", "side", "side"]
    top = s.planes[[p.role for p in s.planes].index("top")]
    assert top.incline_deg == pytest.approx(0.0, abs=1e-6)
    run = s.params["run"]
    assert top.height == pytest.approx(run * math.tan(math.radians(15.0)), abs=1e-9)
    bare = generate_scene("ramp", 3, **SMALL, angle_deg=15.0, platform=0.0, side_faces=False)
    assert [p.role for p in bare.planes if p.object_index == 1] == ["slope", "back"]


def test_box_faces_are_vertical_and_perpendicular():
    s = generate_scene("box", 4, **SMALL, length=0.8, width=0.5, height=0.6)
    faces = [p for p in s.planes if p.role == "face"]
    top = next(p for p in s.planes if p.role == "top")
    assert top.height == pytest.approx(0.6) and top.incline_deg == pytest.approx(0.0, abs=1e-6)
    assert len(faces) == 4
    normals = np.array([f.normal for f in faces])
    for f in faces:
        assert f.incline_deg == pytest.approx(90.0, abs=1e-6)
    dots = np.abs(normals @ normals.T)
    # each face is parallel to one other face and perpendicular to two
    np.testing.assert_allclose(np.sort(dots, axis=1), np.tile([0.0, 0.0, 1.0, 1.0], (4, 1)),
                               atol=1e-9)


def test_object_is_seen_and_classes_differ():
    for kind in ("box", "stairs", "ramp"):
        s = generate_scene(kind, 21, **SMALL)
        assert s.klass == kind
        assert (s.gt_objects == 1).mean() >= 0.04 - 0.02  # min fraction, less dropouts
        assert s.objects[1] == {"index": 1, "id": "s0000_o1", "class": kind}
        assert all(p.id == f"s0000_p{p.index:02d}" for p in s.planes)


# ------------------------------------------------------------------ sensor model


def test_ideal_sensor_is_rounded_true_depth():
    s = generate_scene("box", 2, **SMALL, sensor=SensorModel.ideal())
    hit = np.isfinite(s.depth_true) & (s.depth_true <= 4.5) & (s.depth_true >= 0.45)
    np.testing.assert_array_equal(s.depth_mm > 0, hit)
    np.testing.assert_array_equal(s.depth_mm[hit], np.round(s.depth_true[hit] * 1000))


def test_noise_statistics_and_quantisation_on_a_flat_wall():
    z = np.full((200, 200), 2.0)
    cos = np.ones_like(z)
    sensor = SensorModel(dropout=0.0, edge_dropout=0.0, disparity_step=0.0)
    mm = apply_sensor(z, cos, sensor, np.random.default_rng(0)).astype(float)
    err = mm / 1000 - 2.0
    assert np.std(err) == pytest.approx(0.0012 * 4, rel=0.05)
    assert abs(np.mean(err)) < 3e-4
    z21 = np.full((20, 20), 2.37)
    quant = apply_sensor(z21, np.ones_like(z21),
                         dataclasses.replace(sensor, noise=0.0, disparity_step=0.125),
                         np.random.default_rng(0))
    fb = 525.0 * 0.075
    # one exact disparity level, the nearest to fb / 2.37 in steps of 1/8 pixel
    level = round(fb / 2.37 * 8) / 8
    assert np.all(quant == round(fb / level * 1000)) and round(fb / level * 1000) != 2370
    noisy = apply_sensor(z, cos, SensorModel(dropout=0.0, edge_dropout=0.0), np.random.default_rng(0))
    levels = np.unique(fb / (noisy.astype(float) / 1000) * 8)
    # on the 1/8-pixel grid (up to the 1 mm rounding): a handful of levels, not ~20 mm of spread
    np.testing.assert_allclose(levels, np.round(levels), atol=0.05)
    assert 2 <= len(levels) <= 8


def test_sensor_range_dropout_and_grazing():
    z = np.linspace(0.2, 6.0, 100 * 100).reshape(100, 100)
    cos = np.ones_like(z)
    cos[:, :10] = 0.05  # grazing
    sensor = SensorModel(dropout=0.1, edge_dropout=0.0)
    mm = apply_sensor(z, cos, sensor, np.random.default_rng(1))
    assert mm.max() <= 4500 and mm[mm > 0].min() >= 450
    assert np.all(mm[:, :10] == 0)
    inside = (z > 0.6) & (z < 4.2)
    inside[:, :10] = False
    assert (mm[inside] == 0).mean() == pytest.approx(0.1, abs=0.02)


def test_edge_dropout_hits_only_the_far_side_of_jumps():
    z = np.full((50, 50), 3.0)
    z[:, :25] = 1.0
    sensor = SensorModel(noise=0.0, disparity_step=0.0, dropout=0.0, edge_dropout=1.0,
                         grazing_deg=None)
    mm = apply_sensor(z, np.ones_like(z), sensor, np.random.default_rng(0))
    missing = mm == 0
    assert missing[:, 25].all() and missing.sum() == 50


# ------------------------------------------------------------------ determinism and options


def test_same_seed_same_scene_other_seed_other_scene():
    a = generate_scene("stairs", 7, **SMALL)
    b = generate_scene("stairs", 7, **SMALL)
    c = generate_scene("stairs", 8, **SMALL)
    np.testing.assert_array_equal(a.depth_mm, b.depth_mm)
    np.testing.assert_array_equal(a.gt_labels, b.gt_labels)
    assert a.metadata() == b.metadata()
    assert not np.array_equal(a.depth_mm, c.depth_mm)
    assert scene_seed(0, 1) == scene_seed(0, 1) != scene_seed(0, 2)


def test_subsampled_scene_equals_every_kth_pixel_of_full_scene():
    full = generate_scene("ramp", 9, size=(640, 480), subsample=1, sensor=SensorModel.ideal())
    small = generate_scene("ramp", 9, size=(640, 480), subsample=8, sensor=SensorModel.ideal())
    np.testing.assert_allclose(small.depth_true, full.depth_true[::8, ::8], equal_nan=True)
    np.testing.assert_array_equal(small.gt_labels, full.gt_labels[::8, ::8])
    assert small.intrinsics == full.intrinsics.scaled(8)


def test_camera_range_option_changes_the_distance():
    near = CameraRange(distance=(0.6, 0.8))
    far = CameraRange(distance=(2.0, 2.4))
    dn = [generate_scene("box", s, **SMALL, camera=near).params["camera"]["gap"] for s in range(3)]
    df = [generate_scene("box", s, **SMALL, camera=far).params["camera"]["gap"] for s in range(3)]
    assert all(0.6 <= d <= 0.8 for d in dn) and all(2.0 <= d <= 2.4 for d in df)
    s = generate_scene("box", 0, **SMALL, camera=CameraRange(height=(1.9, 2.0)))
    assert s.params["camera"]["height"] >= 1.9


@pytest.mark.parametrize("call,match", [
    (lambda: generate_scene("table", 0), "unknown scene class 'table'"),
    (lambda: generate_scene("box", -1), "seed must be a non-negative integer"),
    (lambda: generate_scene("box", 0, colour="red"), "unknown option.*colour"),
    (lambda: generate_scene("ramp", 0, angle_deg=95), "ramp angle must"),
    (lambda: generate_scene("ramp", 0, axis="yaw"), "ramp axis must be 'pitch' or 'roll'"),
    (lambda: generate_scene("stairs", 0, steps=0), "whole number of steps >= 1"),
    (lambda: generate_scene("stairs", 0, sides="half"), "sides must be 'open' or 'closed'"),
    (lambda: generate_scene("box", 0, length=-0.5), "box length must be a positive"),
    (lambda: generate_scene("box", 0, walls=3), "walls must be 0, 1 or 2"),
    (lambda: generate_scene("box", 0, height="tall"), "box height must be a number, got 'tall'"),
    (lambda: generate_scene("ramp", 0, platform="x"), "ramp platform depth must be a number"),
    (lambda: generate_scene("ramp", 0, side_faces="yes"), "side_faces must be True or False"),
    (lambda: generate_scene("box", 0, yaw_deg="north"), "yaw_deg must be a number"),
    (lambda: generate_scene("box", 0, size=(640,)), r"size must be \(width, height\)"),
    (lambda: generate_scene("box", 0, subsample=0), "subsample must be a positive integer"),
    (lambda: SensorModel(min_range=3.0, max_range=2.0), "max range 2.0 must exceed min range 3.0"),
    (lambda: SensorModel(noise=-1), "sensor noise must be a finite number"),
    (lambda: SensorModel(dropout=1.5), "sensor dropout"),
    (lambda: CameraRange(height=(2.0, 1.0)), "camera height must be a finite"),
    (lambda: generate_scene("box", 0, camera="high"), "camera must be a CameraRange"),
])
def test_bad_parameters_raise_input_error(call, match):
    with pytest.raises(InputError, match=match):
        call()


def test_geometry_builders_validate_and_describe_planes():
    g = sg.stairs_geometry(3, 0.15, 0.3, 1.0, sides="open")
    assert [p.role for p in g.planes] == ["riser", "tread"] * 3 + ["back", "side", "side"]
    # the open side profile is split into one convex piece per step on one plane
    side_pieces = [p for p in g.polygons if g.planes[p.plane].role == "side"]
    assert len(side_pieces) == 6
    for p in g.polygons:
        n = p.normal()
        assert np.allclose((p.vertices - p.vertices[0]) @ n, 0, atol=1e-12)  # planar
    with pytest.raises(InputError, match="unknown plane role"):
        sg.PlaneSpec("roof", 1)
    with pytest.raises(InputError, match="degenerate polygon"):
        sg.Polygon(np.zeros((3, 3)), 0).normal()
