"""The structured-light sensor's block-matching window (``StructuredLight.window``, sensor40):
planes stay planes, occluding edges stay sharp, a box's convex edge is rounded by the amount the
model predicts, which opens the measured corner beyond 90 degrees as on real Kinect frames."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.io.cloud import Intrinsics
from planerel.synth.sensor import StructuredLight, _box_weights, window_average

F = 525.0
INTR = Intrinsics(320, 240, F, F, 160.0, 119.5)  # a column on the edge (x = 0)


def _rays(intr: Intrinsics):
    u, v = np.meshgrid(np.arange(intr.width, dtype=float), np.arange(intr.height, dtype=float))
    return (u - intr.cx) / intr.fx, (v - intr.cy) / intr.fy


def _corner(z0: float, intr: Intrinsics = INTR) -> np.ndarray:
    """Depth of a vertical convex 90-degree edge pointing at the camera at depth ``z0``: the
    faces ``z = z0 + |x|`` (each at 45 degrees to the view axis)."""
    xn, _ = _rays(intr)
    return z0 / (1.0 - np.abs(xn))


def _fit(p: np.ndarray):
    c = p.mean(0)
    n = np.linalg.svd(p - c, full_matrices=False)[2][2]
    return c, (n if n @ c < 0 else -n)


def _interior(z: np.ndarray, band: float, intr: Intrinsics = INTR) -> float:
    """Interior angle (degrees) of the corner from plane fits of each face's points between
    ``band`` and 4 cm from the edge (lateral |x| in metres)."""
    xn, yn = _rays(intr)
    p = np.stack([xn * z, yn * z, z], -1).reshape(-1, 3)
    x = p[:, 0]
    na = _fit(p[(x > band) & (x < 0.04)])[1]
    nb = _fit(p[(x < -band) & (x > -0.04)])[1]
    return 180.0 - float(np.degrees(np.arccos(np.clip(na @ nb, -1, 1))))


def test_box_weights_sum_to_the_width():
    for w in (1.0, 2.25, 3.0, 9.0, 12.5):
        wt = _box_weights(w)
        assert wt.sum() == pytest.approx(w)
        assert len(wt) % 2 == 1 and np.allclose(wt, wt[::-1])
    assert np.allclose(_box_weights(2.25), [0.625, 1.0, 0.625])


def test_window_keeps_a_plane_exactly():
    # any plane n.p = d: its disparity 1/z is linear in the image coordinates
    xn, yn = _rays(INTR)
    n, d = np.array([0.3, -0.5, 0.81]), 1.0
    z = d / (n[0] * xn + n[1] * yn + n[2])
    out = window_average(z, 9.0, 0.05)
    assert np.max(np.abs(out - z)[5:-5, 5:-5]) < 1e-9
    assert window_average(z, 1.0, 0.05) is not None and np.array_equal(window_average(z, 0.5, 0.05), z)


def test_window_does_not_cross_an_occluding_edge():
    z = np.full((60, 80), 2.0)
    z[:, 40:] = 1.5  # a 0.5 m step
    z[10, 10] = np.nan  # nothing hit: stays NaN, takes no part
    out = window_average(z, 9.0, 0.05)
    assert np.allclose(out[:, :40][np.isfinite(z[:, :40])], 2.0)
    assert np.allclose(out[:, 40:], 1.5)
    assert np.isnan(out[10, 10])


@pytest.mark.parametrize("z0", [0.6, 1.2])
def test_window_rounds_a_convex_edge_by_a_quarter_window(z0):
    z = _corner(z0)
    out = window_average(z, 9.0, 0.05)
    xn, _ = _rays(INTR)
    edge = np.argmin(np.abs(xn[120]))
    # the faces' disparity (1 - |x_n|) / z0 is linear in |x_n|, whose mean over a window W = 9 px
    # (9 z0 / f metres) wide is W / 4: the edge moves back by z0 W / (4 f)
    w_m = 9.0 * z0 / F
    assert out[120, edge] - z[120, edge] == pytest.approx(w_m / 4, rel=0.03)
    # half a window from the edge the faces are untouched
    far = np.abs(xn[120] * z0) > w_m / 2 + 2 * z0 / F
    far[:5] = far[-5:] = False  # the window is cut at the image's border
    assert np.max(np.abs(out[120, far] - z[120, far])) < 1e-9
    # the corner measured on whole faces opens beyond 90 degrees; beyond the band it is exact
    assert _interior(z, 0.0) == pytest.approx(90.0, abs=0.02)
    opened = _interior(out, 0.0)
    assert 90.5 < opened < 93.0  # 90.63 at 0.6 m, 92.48 at 1.2 m (faces fitted within 4 cm)
    assert _interior(out, w_m / 2 + 0.001) == pytest.approx(90.0, abs=0.02)


def test_sensor_window_zero_is_the_old_sensor_and_window_is_in_physical_pixels():
    z = _corner(0.7)
    cos = np.ones_like(z)
    old = StructuredLight(dropout=0.0)
    a, _ = old.apply(z, cos, INTR, np.random.default_rng(3))
    b, _ = dataclasses.replace(old, window=0.0).apply(z, cos, INTR, np.random.default_rng(3))
    assert np.array_equal(a, b)
    quiet = StructuredLight(dropout=0.0, disparity_noise=0.0, disparity_step=0.0, depth_unit=2e-5, max_range=1.3,
                            shadows=False, grazing_deg=None, edge_dropout=0.0, flying=0.0)
    w9, _ = dataclasses.replace(quiet, window=9.0).apply(z, cos, INTR, np.random.default_rng(3))
    assert np.allclose(w9 * 2e-5, window_average(z, 9.0, 0.05), atol=2e-5)
    # the same window on an image subsampled by 4 (fx / 4) is 9 / 4 of its pixels wide
    sub = Intrinsics(80, 60, F / 4, F / 4, 39.5, 29.5)
    z4 = _corner(0.7, sub)
    w4, _ = dataclasses.replace(quiet, window=9.0).apply(z4, np.ones_like(z4), sub,
                                                         np.random.default_rng(3))
    assert np.allclose(w4 * 2e-5, window_average(z4, 2.25, 0.05), atol=2e-5)


def test_bad_window_raises():
    with pytest.raises(InputError, match="window"):
        StructuredLight(window=-1.0)
