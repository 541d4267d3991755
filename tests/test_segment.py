"""Region growing: quality on staircases, plane conventions, determinism, bad input."""

import numpy as np
import pytest

from planerel.errors import InputError, PlanerelError
from planerel.io.cloud import Cloud, Intrinsics
from planerel.segment import RegionGrowParams, make_params, segment
from planerel.segment._scenes import staircase
from planerel.segment.evaluate import evaluate


@pytest.fixture(scope="module")
def stairs160():
    return staircase(160, 120, steps=4, seed=0)


def _score(seg, gt, gn):
    return evaluate(seg.labels, gt, pred_normals=[p.normal for p in seg.planes], gt_normals=gn)


def test_staircase_160x120_default_parameters(stairs160):
    cloud, gt, gn, _ = stairs160
    assert len(gn) == 11  # floor, wall, side, 4 risers, 4 treads
    seg = segment(cloud)
    s = _score(seg, gt, gn)
    assert s.correct >= 10
    assert s.sparse == 0
    assert s.mean_angle_error < 1.0


@pytest.mark.parametrize("steps", [3, 5])
def test_staircase_other_step_counts(steps):
    cloud, gt, gn, _ = staircase(160, 120, steps=steps, seed=2)
    s = _score(segment(cloud), gt, gn)
    assert s.correct >= len(gn) - 1
    assert s.sparse == 0


def test_staircase_640x480_default_parameters():
    cloud, gt, gn, _ = staircase(640, 480, steps=4, seed=1)
    seg = segment(cloud)
    s = _score(seg, gt, gn)
    assert s.correct >= 10
    assert s.sparse == 0
    # the minimum region: 20 noise stds a side at the median depth, in pixels (20 p)^2 with p
    # the noise in pixel footprints, at least the resolution floor (360 px at 640x480); the
    # fixed defaults: 90 px at 160x120 scaled with the pixel count
    from planerel.segment.noise import estimate_noise

    p = estimate_noise(cloud).pixels()
    assert seg.info["min_region_size"] == max(360, round((20 * p) ** 2))
    assert segment(cloud, preset="kinect").info["min_region_size"] == 1440


def test_plane_conventions_and_labels(stairs160):
    cloud, gt, gn, go = stairs160
    seg = segment(cloud)
    assert seg.labels.dtype == np.int32 and seg.labels.shape == cloud.shape
    assert set(np.unique(seg.labels)) == set(range(-1, seg.n_planes)) - (
        set() if (seg.labels == -1).any() else {-1})
    assert not (seg.labels[~cloud.valid] >= 0).any()
    for p in seg.planes:
        assert abs(np.linalg.norm(p.normal) - 1) < 1e-9
        assert p.offset > 0
        assert p.normal @ p.centroid < 0
        assert p.n_points == int((seg.labels == p.id).sum())
        pts = cloud.xyz[seg.labels == p.id]
        assert np.sqrt(np.mean((pts @ p.normal + p.offset) ** 2)) == pytest.approx(p.rms, rel=1e-6)
    # each correct plane matches its true offset within 2 cm
    s = _score(seg, gt, gn)
    for pi, gi in s.correct_pairs:
        assert abs(seg.planes[pi].offset - go[gi]) < 0.02


def test_deterministic(stairs160):
    cloud = stairs160[0]
    a = segment(cloud)
    b = segment(cloud)
    assert np.array_equal(a.labels, b.labels)
    assert [p.to_dict() for p in a.planes] == [p.to_dict() for p in b.planes]


def test_paper_defaults_and_auto_scaling():
    p = RegionGrowParams()
    assert (p.theta, p.min_neighbour_num, p.base_update_step, p.num_initial_points) == (15.0, 4, 8, 16)
    assert p.angle_mf < 1 and p.delta == "auto" and p.min_region_size == "auto"
    cloud = staircase(80, 60, seed=0)[0]
    seg = segment(cloud, adapt=False)
    assert seg.info["min_region_size"] == 22  # 90 * (80*60) / (160*120)
    assert seg.info["delta"] > 0


def test_parameters_change_the_result(stairs160):
    cloud = stairs160[0]
    big = segment(cloud, min_region_size=5000)
    assert all(p.n_points >= 5000 for p in big.planes)
    assert 1 <= big.n_planes <= 2
    fixed = segment(cloud, delta=0.05, refine=False)
    assert fixed.info["delta"] == pytest.approx(0.05)
    assert "refined_points" not in fixed.info


def test_no_plane_large_enough_is_not_an_error():
    cloud = staircase(80, 60, seed=0)[0]
    seg = segment(cloud, min_region_size=10**6)
    assert seg.n_planes == 0
    assert (seg.labels == -1).all()
    assert "no plane" in seg.message


def test_unorganized_cloud(stairs160):
    cloud, gt, gn, _ = stairs160
    ok = cloud.valid
    u = Cloud(cloud.xyz[ok][None], organized=False)
    seg = segment(u, min_region_size=200)
    assert seg.labels.shape == (1, int(ok.sum()))
    lab = np.full(gt.shape, -1, np.int32)
    lab[ok] = seg.labels[0]
    s = evaluate(lab, gt, tolerance=0.8)
    assert s.correct >= 4  # floor, wall and the larger step faces
    assert s.sparse == 0


def test_unorganized_cloud_with_repeated_points(stairs160):
    # a map that stores each point several times (a terrain map, one copy per layer: the ANYmal
    # stair cloud of hunt28 repeats 107 772 points over 18 323 places): the same planes as the
    # distinct points give, each copy labelled as its point; before, the nearest neighbour of
    # every point was its own copy at distance 0, the linking distance was 0 and no plane grew
    cloud, gt, _gn, _ = stairs160
    ok = cloud.valid
    pts = cloud.xyz[ok]
    once = segment(Cloud(pts[None], organized=False), min_region_size=200)
    order = np.random.default_rng(3).permutation(3 * len(pts))
    many = np.concatenate([pts, pts, pts])[order]
    nan_row = np.full((1, 3), np.nan)
    seg = segment(Cloud(np.concatenate([many, nan_row])[None], organized=False),
                  min_region_size=200)
    assert seg.labels.shape == (1, len(many) + 1) and seg.labels[0, -1] == -1
    assert seg.info["repeated_points"] == 2 * len(pts)
    assert seg.n_planes == once.n_planes >= 4
    # every copy of a point has the same label and normal
    lab = seg.labels[0, :-1]
    back = np.empty_like(lab)
    back[order] = lab
    per_copy = back.reshape(3, -1)
    assert (per_copy == per_copy[0]).all()
    assert seg.normals.shape == (1, len(many) + 1, 3)
    # the planes found are the distinct points' planes (up to numbering and a few points at
    # their borders: the distinct points are grown in the order they first occur)
    base = once.labels[0]
    for k in range(seg.n_planes):
        mine = base[per_copy[0] == k]
        top = np.bincount(mine[mine >= 0]).max()
        assert top >= 0.97 * len(mine)
    # deterministic
    again = segment(Cloud(np.concatenate([many, nan_row])[None], organized=False),
                    min_region_size=200)
    np.testing.assert_array_equal(again.labels, seg.labels)
    # fifty copies of one point are one point: a clear error, not a plane
    with pytest.raises(InputError, match="50 valid points but only 1 distinct"):
        segment(Cloud(np.ones((1, 50, 3)), organized=False, source="same"))


def _cloud_from_points(points, shape=(10, 10)):
    xyz = np.full(shape + (3,), np.nan)
    flat = xyz.reshape(-1, 3)
    flat[: len(points)] = points
    return Cloud(xyz, None, source="test-cloud")


def test_bad_clouds_raise_clear_errors():
    with pytest.raises(InputError, match="no valid point"):
        segment(Cloud(np.full((5, 5, 3), np.nan), source="empty"))
    with pytest.raises(InputError, match="only 1 valid point"):
        segment(_cloud_from_points([[0, 0, 1.0]]))
    line = np.column_stack([np.linspace(0, 1, 50), np.zeros(50), np.full(50, 2.0)])
    with pytest.raises(InputError, match="line"):
        segment(_cloud_from_points(line))
    with pytest.raises(InputError, match="same point"):
        segment(_cloud_from_points(np.tile([[0.1, 0.2, 1.0]], (20, 1))))
    with pytest.raises(InputError, match="Cloud"):
        segment(np.zeros((4, 4, 3)))


def test_points_off_a_line_outside_the_check_sample_are_not_an_error():
    """The normals pass checks degeneracy on every 4th row and column; a cloud whose sampled
    points lie on one line but whose other points do not is valid (the exact check decides)."""
    xyz = np.full((30, 40, 3), np.nan)
    u = np.arange(40, dtype=float)
    xyz[0, :] = np.column_stack([u * 0.01, np.zeros(40), np.full(40, 2.0)])  # row 0: a line
    xyz[1, 1] = [0.01, 0.02, 2.0]  # off the line, row 1 and column 1: outside the sample
    xyz[2, 5] = [0.05, 0.04, 2.1]
    seg = segment(Cloud(xyz, None, source="sparse-check"))
    assert seg.labels.shape == (30, 40)
    xyz[1, 1] = xyz[2, 5] = np.nan
    with pytest.raises(InputError, match="line"):
        segment(Cloud(xyz, None, source="sparse-check"))


@pytest.mark.parametrize("bad, match", [
    (dict(theta=0), "theta"), (dict(theta=90), "theta"), (dict(theta=-3), "theta"),
    (dict(theta=float("nan")), "theta.*finite"), (dict(delta=float("nan")), "delta"),
    (dict(min_region_size=0), "min_region_size"), (dict(angle_mf=1.5), "angle_mf"),
    (dict(min_neighbour_num=9), "min_neighbour_num"), (dict(delta="big"), "delta"),
    (dict(bogus=1), "unknown parameter"), (dict(delta_factor="nan"), "delta_factor"),
])
def test_bad_parameters(stairs160, bad, match):
    with pytest.raises(InputError, match=match):
        segment(stairs160[0], **bad)


def test_bad_method_and_params_object(stairs160):
    with pytest.raises(PlanerelError, match="unknown segmentation method"):
        segment(stairs160[0], method="watershed")
    p = make_params("regiongrow", theta="12", refine="false")
    assert p.theta == 12.0 and p.refine is False
    seg = segment(stairs160[0], params=p)
    assert seg.params is p
    with pytest.raises(InputError, match="not both"):
        segment(stairs160[0], params=p, theta=10)


def test_synthetic_stairs_scene_from_the_generator():
    synth = pytest.importorskip("planerel.synth.generator")
    sc = synth.generate_scene("stairs", seed=1, subsample=4)
    seg = segment(sc.cloud)
    s = evaluate(seg.labels, sc.gt_labels)
    big = [p for p in sc.planes if p.n_pixels >= 200]
    assert s.correct >= len(big) - 1
    assert s.sparse == 0
    assert s.under == 0


def test_intrinsics_do_not_change_the_result_much():
    # same scene without intrinsics: f is estimated from the points
    cloud = staircase(160, 120, seed=0)[0]
    bare = Cloud(cloud.xyz)
    a = segment(cloud)
    b = segment(bare)
    # every plane found with the intrinsics is found without them (80 % overlap both ways),
    # and at most 1 % of the pixels change label
    s = evaluate(b.labels, a.labels)
    assert s.correct == s.n_gt == a.n_planes == b.n_planes
    assert (a.labels != b.labels).mean() <= 0.01
    # the intrinsics the scene was made with: Kinect's 640x480 camera subsampled by 4
    # (every 4th pixel from 0: f / 4 and c / 4)
    k = Intrinsics.kinect(160, 120)
    assert (k.fx, k.fy, k.cx, k.cy) == (525 / 4, 525 / 4, 319.5 / 4, 239.5 / 4)
    assert cloud.intrinsics == k


def _visible_gt(scene, min_size):
    """The generator's GT labels without planes smaller than ``min_size`` pixels (SegComp
    practice: regions below the minimum region size are not counted)."""
    gt = scene.gt_labels.copy()
    for p in scene.planes:
        if p.n_pixels < min_size:
            gt[gt == p.index] = -1
    return gt


@pytest.mark.parametrize("steps", [3, 4, 5])
def test_closed_staircases_from_the_generator_160x120(steps):
    synth = pytest.importorskip("planerel.synth.generator")
    sc = synth.generate_scene("stairs", 0, size=(640, 480), subsample=4, steps=steps,
                              sides="closed", walls=1)
    seg = segment(sc.cloud)
    gt = _visible_gt(sc, seg.info["min_region_size"])
    s = evaluate(seg.labels, gt)
    assert s.n_gt >= 2 * steps + 2  # floor, wall, risers, treads, sides
    assert s.correct >= s.n_gt - 1
    assert s.sparse == 0 and s.under == 0


def test_closed_staircase_from_the_generator_640x480():
    synth = pytest.importorskip("planerel.synth.generator")
    sc = synth.generate_scene("stairs", 1, size=(640, 480), subsample=1, steps=4,
                              sides="closed", walls=1)
    seg = segment(sc.cloud)
    s = evaluate(seg.labels, _visible_gt(sc, seg.info["min_region_size"]))
    assert s.n_gt >= 11
    assert s.correct >= s.n_gt - 1
    assert s.sparse == 0 and s.under == 0


def test_presets(stairs160):
    from planerel.segment.params import PRESETS, scaled_min_region_size

    p = make_params("regiongrow", preset="structured-light")
    assert p.reference_depth is None and p.normal_smooth == 3 and p.min_region_scale == 0.25
    assert make_params("regiongrow", preset="abw") == p
    assert make_params("regiongrow", preset="kinect") == RegionGrowParams(adapt=False)
    assert p.adapt is False
    q = make_params("regiongrow", preset="abw", normal_smooth=2, reference_depth="none")
    assert q.normal_smooth == 2 and q.normal_radius == 3 and q.reference_depth is None
    assert set(PRESETS) >= {"kinect", "structured-light", "abw"}
    seg = segment(stairs160[0], preset="structured-light")
    assert seg.info["min_region_size"] == scaled_min_region_size(160 * 120, 0.25)
    with pytest.raises(InputError, match="unknown preset 'laser'"):
        make_params("regiongrow", preset="laser")
    with pytest.raises(InputError, match="min_region_scale"):
        segment(stairs160[0], min_region_scale=0)
    with pytest.raises(InputError, match="leftover_planes"):
        segment(stairs160[0], leftover_planes=3)


def test_leftover_planes_only_add_planar_patches(stairs160):
    cloud = stairs160[0]
    a = segment(cloud, leftover_planes=False)
    b = segment(cloud)
    assert "leftover_planes" not in a.info
    k = b.info["leftover_planes"]
    assert b.n_planes == a.n_planes + k
    # the grown and completed regions are the same; leftover regions only take unassigned pixels
    assert np.array_equal(b.labels[a.labels >= 0], a.labels[a.labels >= 0])
    med = np.median([p.rms for p in a.planes])
    for p in b.planes[a.n_planes:]:
        assert p.rms <= 3 * med * 1.0001


ABW = __import__("pathlib").Path(__file__).resolve().parents[2] / "shared" / "data" / "abw"


@pytest.mark.skipif(not (ABW / "abw.test.0.range").exists(), reason="SegComp ABW data not present")
def test_abw_image_with_the_structured_light_preset():
    from planerel.io.readers import read_abw, read_abw_gt

    cloud = read_abw(ABW / "abw.test.0.range")
    gt = read_abw_gt(ABW / "abw.test.0.gt-seg")
    seg = segment(cloud)
    s_default = evaluate(seg.labels, gt)
    s_kinect = evaluate(segment(cloud, preset="kinect").labels, gt)
    s_preset = evaluate(segment(cloud, preset="structured-light").labels, gt)
    assert s_preset.n_gt == 27
    assert s_preset.correct >= 13 and s_preset.correct > s_kinect.correct
    assert s_preset.sparse == 0 and s_preset.under == 0
    # the default measures uniform depth steps and chooses structured-light-like settings itself
    assert seg.info["noise_model"]["kind"] == "uniform"
    assert seg.info["settings"]["reference_depth"] is None
    assert seg.info["settings"]["normal_smooth"] == 3
    assert s_default.correct >= s_preset.correct - 1 and s_default.correct > s_kinect.correct
    assert s_default.sparse == 0 and s_default.under == 0


def test_results_stay_valid_when_the_next_frame_is_segmented(stairs160):
    # the organized pipeline reuses its buffers; a result still held must never change
    cloud = stairs160[0]
    first = segment(cloud)
    labels, normals = first.labels.copy(), first.normals.copy()
    other = staircase(160, 120, steps=3, seed=5)[0]
    second = segment(other)
    assert np.array_equal(first.labels, labels)
    assert np.array_equal(first.normals, normals, equal_nan=True)
    assert not np.shares_memory(first.labels, second.labels)
    del first
    third = segment(cloud)  # buffers of a dropped result may be reused
    assert np.array_equal(third.labels, labels)
    assert not np.shares_memory(third.labels, second.labels)


def test_precomputed_normals_give_the_same_segmentation():
    """Organized cloud with normals given: the graph is built in its own pass (not in the
    normals' pass) and the result is the same, also for a cloud whose array is a strided view."""
    from planerel.segment import segment
    from planerel.synth.generator import generate_scene

    cloud = generate_scene("stairs", seed=1, subsample=4).cloud
    ref = segment(cloud, refine=False, split=False)
    given = segment(cloud, refine=False, split=False, normals=np.asarray(ref.normals))
    np.testing.assert_array_equal(given.labels, ref.labels)
    assert given.info["delta"] == ref.info["delta"]
    wide = np.full((cloud.xyz.shape[0], cloud.xyz.shape[1] * 2, 3), np.nan)
    wide[:, ::2] = cloud.xyz
    view = Cloud(wide[:, ::2], intrinsics=cloud.intrinsics)
    strided = segment(view, refine=False, split=False, normals=np.asarray(ref.normals))
    np.testing.assert_array_equal(strided.labels, ref.labels)
