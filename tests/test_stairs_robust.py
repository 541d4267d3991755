"""``benchmarks/stairs_robust.py`` (srob58, docs/objects.md "Staircases under perturbed
depth"): each perturbation does to the depth image and camera what its name says, and an
unperturbed frame re-projects to the cloud it was read as."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
import stairs_robust as sr  # noqa: E402

from planerel.io.cloud import depth_to_cloud  # noqa: E402

K = (200.0, 210.0, 80.0, 60.0)


@pytest.fixture
def z():
    rng = np.random.default_rng(3)
    return 1.0 + 0.5 * rng.random((120, 160))


def _p(name):
    return dict(sr.perturbations())[name]


def test_the_names_are_the_briefs_perturbations():
    names = [n for n, _ in sr.perturbations()]
    assert names[0] == "none" and len(names) == len(set(names)) == 17
    for n in ("f x0.85", "f x1.15", "cx+20", "res /4", "noise 0.005", "quant 0.01",
              "holes 0.3", "z x0.97"):
        assert n in names


def test_none_reprojects_to_the_same_cloud(z):
    c = depth_to_cloud(z, (160, 120, *K), depth_scale=1.0)
    assert sr.camera(c) == pytest.approx(K)
    z2, k2, step = _p("none")(np.asarray(c.depth), sr.camera(c), np.random.default_rng(0))
    c2 = depth_to_cloud(z2, (160, 120, *k2), depth_scale=1.0)
    assert step == 1 and np.allclose(c2.xyz, c.xyz)


def test_camera_is_fitted_to_a_cloud_without_intrinsics(z):
    c = depth_to_cloud(z, (160, 120, *K), depth_scale=1.0)
    bare = type(c)(np.asarray(c.xyz), intrinsics=None)
    assert sr.camera(bare) == pytest.approx(K, abs=1e-3)


def test_focal_and_resolution_and_depth_scale(z):
    rng = np.random.default_rng(0)
    z2, k2, _ = _p("f x1.1")(z, K, rng)
    assert np.array_equal(z2, z) and k2 == pytest.approx((220.0, 231.0, 80.0, 60.0))
    z2, k2, step = _p("res /4")(z, K, rng)
    assert z2.shape == (30, 40) and step == 4 and k2 == pytest.approx((50, 52.5, 20, 15))
    assert np.array_equal(z2, z[::4, ::4])
    z2, _, _ = _p("z x1.03")(z, K, rng)
    assert np.allclose(z2, 1.03 * z)
    z2, _, _ = _p("quant 0.01")(z, K, rng)
    assert np.allclose(z2 * 100, np.round(z2 * 100)) and np.abs(z2 - z).max() <= 0.005 + 1e-12


def test_noise_grows_with_range_squared_and_holes_cover_their_share():
    z = np.full((120, 160), 2.0)
    z2, _, _ = _p("noise 0.005")(z, K, np.random.default_rng(0))
    assert np.std(z2 - z) == pytest.approx(0.005 * 4, rel=0.05)
    z2, _, _ = _p("holes 0.3")(z, K, np.random.default_rng(0))
    assert np.isnan(z2).mean() == pytest.approx(0.3, abs=0.01)
