"""``benchmarks/plane_share.py`` (srob59, docs/segmentation.md "Staircases under correlated
noise and holes"): the share of valid pixels in a plane, narrow and wide.  Synthetic planes made
here (a measuring tool's check, no evidence about real frames)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
import plane_share as ps  # noqa: E402
import stairs_robust as sr  # noqa: E402

from planerel.io.cloud import depth_to_cloud  # noqa: E402

W, H, F = 320, 240, 300.0


def _slope(k: float, sigma_px: float = 2.0):
    v, _u = np.mgrid[0:H, 0:W].astype(float)
    z = 2.0 + 0.002 * (v - H / 2)
    if k:
        z = z + k * z ** 2 * sr._smooth(np.random.default_rng(0).standard_normal(z.shape),
                                        sigma_px)
    z[:10, :10] = 0.0  # no depth: not counted
    return depth_to_cloud(z, (W, H, F, F, W / 2, H / 2), depth_scale=1.0)


def test_a_clean_plane_is_all_assigned_and_not_redone():
    r = ps.frame_row("clean", _slope(0.0))
    assert r["narrow"] > 0.95 and "wide" not in r
    assert r["kind"] in ("z2", "uniform", "none")


def test_correlated_noise_narrow_fails_wide_recovers():
    r = ps.frame_row("noisy", _slope(0.005))
    assert r["narrow"] < 0.5 and r["wide"] > 0.9
    assert r["s15_mm"] > r["s5_mm"]  # the 15 px patches see the correlated part
    every = ps.frame_row("clean", _slope(0.0), below=1.01)
    assert "wide" in every
