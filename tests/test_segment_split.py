"""Splitting bent regions (planerel.segment.split): floor + ramp becomes two planes, true planes
stay whole, deterministic output, parameter validation."""

import math

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.io.cloud import Intrinsics, depth_to_cloud
from planerel.segment import segment
from planerel.segment._scenes import staircase
from planerel.segment.evaluate import evaluate
from planerel.segment.split import SplitParams, expected_sigma, split_bent_regions
from planerel.synth.generator import SensorModel, apply_sensor, generate_scene


def _correct_gt(seg, gt) -> set:
    return {g for _, g in evaluate(seg.labels, gt).correct_pairs}


def _check_result(seg, shape):
    assert seg.labels.dtype == np.int32 and seg.labels.shape == shape
    present = set(np.unique(seg.labels)) - {-1}
    assert present == set(range(seg.n_planes))
    for i, p in enumerate(seg.planes):
        assert p.id == i
        assert p.n_points == int((seg.labels == i).sum())
        assert p.offset > 0 and p.normal @ p.centroid < 0


@pytest.mark.parametrize("angle", [8, 10, 12])
def test_floor_and_ramp_become_two_planes(angle):
    sc = generate_scene("ramp", 0, size=(640, 480), subsample=4, angle_deg=angle)
    slope = [p.index for p in sc.planes if p.role == "slope" and p.n_pixels > 0]
    floor = [p.index for p in sc.planes if p.role == "floor"]
    assert len(slope) == 1 and len(floor) == 1
    seg = segment(sc.cloud, split=False)
    out = split_bent_regions(sc.cloud, seg)
    _check_result(out, sc.cloud.shape)
    after = _correct_gt(out, sc.gt_labels)
    assert slope[0] in after and floor[0] in after
    assert len(after) >= len(_correct_gt(seg, sc.gt_labels))
    assert out.info["split_regions"] >= 1
    assert out.n_planes == seg.n_planes + out.info["split_new_regions"]
    # the slope's fitted normal is within 2 degrees of the truth
    pair = dict((g, m) for m, g in evaluate(out.labels, sc.gt_labels).correct_pairs)
    n_fit = out.planes[pair[slope[0]]].normal
    n_true = np.array(sc.planes[slope[0]].normal)
    assert math.degrees(math.acos(min(1.0, abs(float(n_fit @ n_true))))) < 2.0


def _plane_scene(normal_world, offset, eye_height, pitch_deg, seed, size=(160, 120)):
    """A single plane seen by a Kinect-like camera (noise, disparity quantisation, dropouts)."""
    w, h = size
    intr = Intrinsics.kinect(w, h)
    u, v = np.meshgrid(np.arange(w), np.arange(h))
    ray = np.stack([(u - intr.cx) / intr.fx, (v - intr.cy) / intr.fy, np.ones((h, w))], axis=2)
    c, s = math.cos(math.radians(pitch_deg)), math.sin(math.radians(pitch_deg))
    rot = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])  # camera pitched down by pitch_deg
    n = rot @ np.asarray(normal_world, dtype=float)
    den = ray @ n
    with np.errstate(divide="ignore", invalid="ignore"):
        t = -offset / den
    z = np.where((t > 0) & np.isfinite(t), t, np.nan)
    z[z > 4.5] = np.nan
    cos_inc = np.abs(den) / np.linalg.norm(ray, axis=2)
    depth_mm = apply_sensor(z, cos_inc, SensorModel(), np.random.default_rng(seed))
    return depth_to_cloud(depth_mm, intr, 1000.0)


@pytest.mark.parametrize("kind,seed", [("floor", 0), ("floor", 1), ("wall", 2), ("wall", 3)])
def test_single_noisy_plane_is_not_split(kind, seed):
    if kind == "floor":  # floor 1.1 m below a camera pitched 25 degrees down, seen to 4.5 m
        cloud = _plane_scene((0, -1, 0), 1.1, 1.1, 25, seed)
    else:  # a wall 2.5 m away, turned 35 degrees
        cloud = _plane_scene((math.sin(math.radians(35)), 0, -math.cos(math.radians(35))), 2.5,
                             0, 0, seed)
    gt = np.where(cloud.valid, 0, -1).astype(np.int32)
    seg = segment(cloud, split=False)
    out = split_bent_regions(cloud, seg)
    assert out.info["split_regions"] == 0
    assert out.n_planes == seg.n_planes
    assert np.array_equal(out.labels, seg.labels)
    assert evaluate(out.labels, gt).correct == evaluate(seg.labels, gt).correct == 1


@pytest.mark.parametrize("seed", [0, 1])
def test_staircase_is_not_split(seed):
    cloud, gt, _, _ = staircase(160, 120, steps=4, seed=seed)
    seg = segment(cloud, split=False)
    out = split_bent_regions(cloud, seg)
    assert out.n_planes == seg.n_planes
    assert evaluate(out.labels, gt).correct == evaluate(seg.labels, gt).correct


def test_true_planes_match_the_noise_model():
    # the residual test's premise: a noisy floor's RMS is close to the model's expectation
    cloud = _plane_scene((0, -1, 0), 1.1, 1.1, 25, 5)
    seg = segment(cloud, split=False)
    big = max(seg.planes, key=lambda p: p.n_points)
    pts = cloud.xyz[seg.labels == big.id]
    exp = math.sqrt(float(np.mean(expected_sigma(pts, big.normal) ** 2)))
    assert 0.7 < big.rms / exp < SplitParams().tolerance


def test_deterministic_and_seed_used():
    sc = generate_scene("ramp", 3, size=(640, 480), subsample=4, angle_deg=10)
    seg = segment(sc.cloud, split=False)
    a = split_bent_regions(sc.cloud, seg)
    b = split_bent_regions(sc.cloud, seg)
    assert np.array_equal(a.labels, b.labels)
    assert [p.to_dict() for p in a.planes] == [p.to_dict() for p in b.planes]
    assert a.info == b.info
    c = split_bent_regions(sc.cloud, seg, params=SplitParams(seed=0))
    assert np.array_equal(a.labels, c.labels)


def test_nothing_to_split_returns_same_labels_and_info():
    cloud, _, _, _ = staircase(160, 120, steps=3, seed=4)
    seg = segment(cloud, split=False)
    out = split_bent_regions(cloud, seg, tolerance=1000.0)
    assert out.info["split_tested"] == 0 and out.info["split_regions"] == 0
    assert np.array_equal(out.labels, seg.labels)
    assert out.method == seg.method and out.params is seg.params


@pytest.mark.parametrize("kw,match", [
    (dict(tolerance=0.5), "tolerance"),
    (dict(tolerance=float("nan")), "tolerance"),
    (dict(inlier_sigmas=5.0, assign_sigmas=4.0), "assign_sigmas"),
    (dict(max_parts=1), "max_parts"),
    (dict(noise=0.0, disparity_step=0.0, depth_unit=0.0), "noise model"),
    (dict(local_noise="yes please"), "local_noise"),
    (dict(min_region_size="big"), "min_region_size"),
    (dict(seed=-1), "seed"),
    (dict(focal_px=0), "focal_px"),
])
def test_bad_parameters(kw, match):
    with pytest.raises(InputError, match=match):
        SplitParams(**kw)


def test_bad_input():
    cloud, _, _, _ = staircase(160, 120, steps=3, seed=0)
    seg = segment(cloud, split=False)
    with pytest.raises(InputError, match="unknown parameter"):
        split_bent_regions(cloud, seg, tolerence=2)
    with pytest.raises(InputError, match="Cloud"):
        split_bent_regions(cloud.xyz, seg)
    with pytest.raises(InputError, match="Segmentation"):
        split_bent_regions(cloud, seg.labels)
    with pytest.raises(InputError, match="not both"):
        split_bent_regions(cloud, seg, params=SplitParams(), tolerance=2)
    small, _, _, _ = staircase(80, 60, steps=3, seed=0)
    with pytest.raises(InputError, match="shape"):
        split_bent_regions(small, seg)
