"""``benchmarks/noise_scales.py`` (noise58, docs/segmentation.md "Correlated depth noise"):
the 5 px estimate measures white noise but not noise correlated over a few pixels; the 15 px
estimate sees the correlated part.  Synthetic planes made here (a measuring tool's check, no
evidence about real frames)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
import noise_scales as ns  # noqa: E402

from planerel.io.cloud import depth_to_cloud  # noqa: E402
from planerel.segment.noise import QUANTILE_TO_MEDIAN  # noqa: E402

W, H, F = 320, 240, 300.0


def _plane(noise_mm: float, sigma_px: float, seed: int = 0):
    v, u = np.mgrid[0:H, 0:W].astype(float)
    z = 1.5 + 0.0005 * (u - W / 2) + 0.0003 * (v - H / 2)
    n = ns._smooth(np.random.default_rng(seed).standard_normal(z.shape), sigma_px)
    return depth_to_cloud(z + noise_mm / 1000 * n, (W, H, F, F, W / 2, H / 2), depth_scale=1.0)


def test_quantile_factor_matches_the_segmentations():
    assert ns._qtm(5) == pytest.approx(QUANTILE_TO_MEDIAN, abs=1e-3)
    assert 1.0 < ns._qtm(15) < ns._qtm(11) < ns._qtm(5)


def test_white_noise_is_measured_at_every_scale():
    r = ns.measure_cloud(_plane(3.0, 0.0))
    for k in (5, 11, 15):
        assert r[f"s{k}"] == pytest.approx(3.0, rel=0.1)
    assert r["corr"] < 1.0


def test_correlated_noise_is_missed_at_5_px_and_seen_at_15():
    r = ns.measure_cloud(_plane(3.0, 2.0))
    assert r["s5"] < 1.0  # the 5 px plane fit absorbs most of it
    assert r["s15"] > 2.0 * r["s5"]
    assert r["corr"] > 1.5


def test_perturbed_adds_the_named_noise():
    c = _plane(0.0, 0.0)
    p = ns.perturbed(c, 0.002, 0.0, 0)
    d = np.asarray(p.depth, float) - np.asarray(c.depth, float)
    assert np.nanstd(d) == pytest.approx(0.002 * 1.5 ** 2, rel=0.05)
