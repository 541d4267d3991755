"""RANSAC baselines SP and SNP: planes found, seeded determinism, sparse planes vs region growing."""

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.evaluate import evaluate
from planerel.segment import segment
from planerel.segment._scenes import staircase
from planerel.segment.ransac import SNP_THRESHOLDS, SP_THRESHOLDS


@pytest.fixture(scope="module")
def stairs():
    return staircase(160, 120, steps=4, seed=0)


def test_paper_thresholds():
    assert SP_THRESHOLDS == (0.005, 0.01, 0.03, 0.05)
    assert SNP_THRESHOLDS == (0.01, 0.03, 0.05)


def test_sp_finds_the_big_planes(stairs):
    cloud, gt, gn, _ = stairs
    seg = segment(cloud, "sp", threshold=0.01, seed=1)
    assert seg.method == "sp"
    assert seg.n_planes >= 3
    s = evaluate(seg.labels, gt, pred_normals=[p.normal for p in seg.planes], gt_normals=gn)
    assert s.correct >= 2  # at least floor and wall
    for p in seg.planes:
        assert p.offset > 0 and p.normal @ p.centroid < 0
        assert p.n_points >= seg.info["min_region_size"]


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
