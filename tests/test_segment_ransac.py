"""RANSAC baselines SP and SNP: planes found, seeded determinism, sparse planes vs region growing."""

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.io.cloud import Cloud
from planerel.segment import segment
from planerel.segment._scenes import staircase
from planerel.segment.evaluate import evaluate


@pytest.fixture(scope="module")
def stairs():
    return staircase(160, 120, steps=4, seed=0)


def test_sp_finds_the_big_planes_at_3cm_and_splits_the_wall_at_1cm(stairs):
    """Floor (7467 px) and wall (8588 px) hold 84 % of the image, so SP extracts them first.
    The scene's depth noise has std 0.0012 z^2 along each ray (staircase's default): ~9.5 mm
    on the wall (median z 2.8 m, seen nearly head-on), so a +-1 cm band holds about
    erf(10 / (9.5 sqrt 2)) ~ 71 % of its points, below the 80 % overlap a correct detection
    needs, while +-3 cm (3.2 sigma) holds nearly all of it."""
    cloud, gt, gn, _ = stairs
    assert np.bincount(gt[gt >= 0]).argsort()[-2:].tolist() == [0, 1]
    wall = gt == 1
    z_wall = float(np.median(cloud.xyz[wall][:, 2]))
    assert 0.0012 * z_wall ** 2 == pytest.approx(0.0095, abs=0.0005)
    loose = segment(cloud, "sp", threshold=0.03, seed=1)
    s3 = evaluate(loose.labels, gt, pred_normals=[p.normal for p in loose.planes], gt_normals=gn)
    assert {0, 1} <= {g for _, g in s3.correct_pairs}
    tight = segment(cloud, "sp", threshold=0.01, seed=1)
    s1 = evaluate(tight.labels, gt, pred_normals=[p.normal for p in tight.planes], gt_normals=gn)
    assert 1 not in {g for _, g in s1.correct_pairs}
    assert tight.n_planes > loose.n_planes  # the tight band cuts noisy surfaces into pieces
    for seg in (loose, tight):
        for p in seg.planes:
            assert p.offset > 0 and p.normal @ p.centroid < 0
            assert p.n_points >= seg.info["min_region_size"]


def test_snp_distance_is_weighted_angle_plus_distance():
    """SNP's point-plane distance w * angle + (1 - w) * |d| (PCL SACMODEL_NORMAL_PLANE with
    normal distance weight w), values by hand."""
    from planerel.segment.ransac import _distances

    plane = np.array([[0.0, 0.0, -1.0, 1.9]])  # z = 1.9, normal towards the sensor
    P = np.array([[0.3, -0.2, 2.0], [0.0, 0.0, 1.8], [1.0, 1.0, 1.9]])
    c, s60 = 0.5, np.sqrt(3) / 2
    N = np.array([[0.0, s60, -c],      # 60 degrees from the plane normal
                  [0.0, 0.0, 1.0],     # anti-parallel: angle 0 (either orientation)
                  [1.0, 0.0, 0.0]])    # perpendicular: pi / 2
    w = 0.1
    got = _distances(P, N, plane, w, True)[:, 0]
    want = [w * np.pi / 3 + (1 - w) * 0.1, (1 - w) * 0.1, w * np.pi / 2]
    np.testing.assert_allclose(got, want, rtol=1e-12)
    np.testing.assert_allclose(_distances(P, N, plane, w, False)[:, 0], [0.1, 0.1, 0.0],
                               atol=1e-12)
    np.testing.assert_allclose(_distances(P, N, plane, 1.0, True)[:, 0],
                               [np.pi / 3, 0.0, np.pi / 2], atol=1e-12)


def _flat_patch():
    """A 30x40 grid on the plane z = 2 (1 cm spacing, no noise: every hypothesis is that
    plane), normals (0, 0, -1), except columns 30-39 whose normals are tilted 30 degrees."""
    v, u = np.mgrid[0:30, 0:40].astype(float)
    xyz = np.stack([(u - 20) * 0.01, (v - 15) * 0.01, np.full(u.shape, 2.0)], axis=-1)
    nrm = np.zeros_like(xyz)
    nrm[..., 2] = -1.0
    t = np.radians(30)
    nrm[:, 30:] = [np.sin(t), 0.0, -np.cos(t)]
    return Cloud(xyz), nrm


@pytest.mark.parametrize("threshold, weight, tilted_in", [
    # the tilted points lie on the plane: distance w * pi/6 (0.05236 for w = 0.1)
    (0.052, 0.1, False), (0.053, 0.1, True), (0.10, 0.2, False), (0.11, 0.2, True),
    (0.001, 0.0, True),
])
def test_snp_inliers_follow_the_weighted_distance(threshold, weight, tilted_in):
    cloud, nrm = _flat_patch()
    seg = segment(cloud, "snp", threshold=threshold, normal_weight=weight, min_region_size=100,
                  seed=0, normals=nrm)
    lab = seg.labels
    assert seg.n_planes == 1
    assert (lab[:, :30] == 0).all()  # on the plane, normal along its normal: distance 0
    assert (lab[:, 30:] == (0 if tilted_in else -1)).all()
    # SP ignores the normals: the tilted columns are always inliers
    sp = segment(cloud, "sp", threshold=threshold, min_region_size=100, seed=0)
    assert (sp.labels == 0).all()


def test_seeded_and_deterministic(stairs):
    cloud = stairs[0]
    a = segment(cloud, "snp", threshold=0.03, seed=7, max_iterations=200)
    b = segment(cloud, "snp", threshold=0.03, seed=7, max_iterations=200)
    assert np.array_equal(a.labels, b.labels)


def test_loose_sp_threshold_makes_sparse_planes_and_region_growing_does_not(stairs):
    cloud, gt, _, _ = stairs
    sp = evaluate(segment(cloud, "sp", threshold=0.05, seed=0).labels, gt)
    rg = evaluate(segment(cloud).labels, gt)
    assert sp.sparse >= 1
    assert rg.sparse == 0
    assert rg.correct > sp.correct


def test_snp_uses_normals(stairs):
    cloud, gt, _, _ = stairs
    snp = segment(cloud, "snp", threshold=0.05, seed=0)
    sp = segment(cloud, "sp", threshold=0.05, seed=0)
    assert snp.normals is not None and sp.normals is None
    assert evaluate(snp.labels, gt).correct > evaluate(sp.labels, gt).correct


def test_extraction_stops_at_min_region_size(stairs):
    cloud = stairs[0]
    seg = segment(cloud, "sp", threshold=0.01, min_region_size=5000)
    assert 1 <= seg.n_planes <= 2
    assert all(p.n_points >= 5000 for p in seg.planes)


@pytest.mark.parametrize("bad, match", [
    (dict(threshold=0), "threshold"), (dict(threshold=float("nan")), "threshold"),
    (dict(normal_weight=2), "normal_weight"), (dict(min_region_size=0), "min_region_size"),
    (dict(probability=1.0), "probability"), (dict(theta=10), "unknown parameter"),
])
def test_bad_ransac_parameters(stairs, bad, match):
    with pytest.raises(InputError, match=match):
        segment(stairs[0], "sp", **bad)
