"""Kernels of planerel.features.raised against their numpy reference."""

from __future__ import annotations

import numpy as np
import pytest


def test_noise_values_kernel_is_numpys_within_rounding():
    """_raised_on's noise values in one compiled pass (plain-order dot products) against the
    numpy slicing, masking and matrix product, boxes reaching past the image included."""
    from planerel.features.raised import _noise_values

    rng = np.random.default_rng(23)
    for _ in range(60):
        H, W = (int(v) for v in rng.integers(1, 60, 2))
        lab = rng.integers(-1, 3, (H, W)).astype(np.int32)
        xyz = rng.normal(size=(H, W, 3)) * rng.choice([0.05, 1.0, 4.0])
        xyz[rng.random((H, W)) < 0.1, 2] = np.nan
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        bbox = (int(rng.integers(0, H)), int(rng.integers(0, W)), int(rng.integers(0, H + 5)),
                int(rng.integers(0, W + 5)))
        step = int(rng.integers(1, 11))
        d0 = float(rng.normal())
        got = _noise_values(xyz, lab, 1, bbox, step, n, d0)
        r0, c0, r1, c1 = bbox
        ps = xyz[r0:r1:step, c0:c1:step][lab[r0:r1:step, c0:c1:step] == 1]
        ps = ps[np.isfinite(ps[:, 2])]
        want = np.abs(ps @ n - d0) / np.maximum(np.abs(ps[:, 2]), 0.1) ** 2
        assert got.shape == want.shape
        assert np.allclose(got, want, rtol=1e-12, atol=1e-15)
        if want.size:
            assert np.median(got) == pytest.approx(np.median(want), rel=1e-12)
