"""Realistic sensor profiles (planerel.synth.sensor): the generated noise, quantisation, shadows,
flying pixels and dropouts follow the documented models."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.io.cloud import Intrinsics
from planerel.synth.generator import generate_scene
from planerel.synth.sensor import (
    StructuredLight,
    TimeOfFlight,
    edge_neighbours,
    projector_shadow,
    sensor_profile,
)

INTR = Intrinsics(300, 300, 525.0, 525.0, 149.5, 149.5)
# only the noise: no dropouts, edges, shadows, grazing; a fine depth unit so that the 1 mm
# rounding does not blur the disparity grid
QUIET_SL = StructuredLight(dropout=0.0, edge_dropout=0.0, flying=0.0, grazing_deg=None,
                           shadows=False, depth_unit=1e-4)
QUIET_TOF = TimeOfFlight(dropout=0.0, edge_dropout=0.0, flying=0.0, grazing_deg=None,
                         depth_unit=1e-4)


def _band(z0: float, half: float = 0.05, n: int = 300) -> np.ndarray:
    """A smooth depth image spanning z0 +- half (many disparity steps, so the true disparities
    fall uniformly between the quantisation levels)."""
    return np.tile(np.linspace(z0 - half, z0 + half, n), (n, 1)).T.copy()


@pytest.mark.parametrize("z0", [1.0, 2.0, 3.0, 4.0])
def test_structured_light_disparity_noise_and_quantisation(z0):
    z = _band(z0)
    units, fly = QUIET_SL.apply(z, np.ones_like(z), INTR, np.random.default_rng(1))
    assert not fly.any() and (units > 0).all()
    zm = units * 1e-4
    fb = 525.0 * 0.075
    d_true, d_meas = fb / z, fb / zm
    # every measurement lies on the 1/8-pixel disparity grid (up to the 0.1 mm depth rounding)
    grid_err = np.abs(d_meas * 8 - np.round(d_meas * 8))
    assert np.max(grid_err) <= 8 * fb * 0.5e-4 / np.min(zm) ** 2 * 1.01
    # disparity error: Gaussian (0.043 px) plus uniform rounding of 1/8 px, unbiased
    err = d_meas - d_true
    expected = math.sqrt(0.043 ** 2 + 0.125 ** 2 / 12)
    assert np.std(err) == pytest.approx(expected, rel=0.03)
    assert abs(np.mean(err)) < 0.003
    # depth error grows with z^2 as documented: z^2 / (f b) * sigma_d
    zerr = (zm - z) / z ** 2
    assert np.std(zerr) == pytest.approx(expected / fb, rel=0.04)
    assert float(QUIET_SL.axial_sigma(z0)) == pytest.approx(z0 ** 2 / fb * expected, rel=1e-12)


def test_structured_light_without_quantisation_is_gaussian_in_disparity():
    sensor = dataclasses.replace(QUIET_SL, disparity_step=0.0, disparity_noise=0.1)
    z = np.full((300, 300), 2.5)
    units, _ = sensor.apply(z, np.ones_like(z), INTR, np.random.default_rng(2))
    err = 525.0 * 0.075 / (units * 1e-4) - 525.0 * 0.075 / 2.5
    assert np.std(err) == pytest.approx(0.1, rel=0.03)
    # Gaussian: 68.3 % within one sigma, 95.4 % within two
    assert np.mean(np.abs(err) < 0.1) == pytest.approx(0.683, abs=0.01)
    assert np.mean(np.abs(err) < 0.2) == pytest.approx(0.954, abs=0.01)


@pytest.mark.parametrize("z0,theta_deg", [(1.0, 0.0), (2.5, 0.0), (4.0, 0.0), (2.0, 60.0)])
def test_time_of_flight_axial_noise_matches_the_model(z0, theta_deg):
    z = np.full((300, 300), z0)
    cos = np.full_like(z, math.cos(math.radians(theta_deg)))
    units, fly = QUIET_TOF.apply(z, cos, INTR, np.random.default_rng(3))
    assert not fly.any()
    err = units * 1e-4 - z0
    th = math.radians(theta_deg)
    # Fankhauser et al. 2015, in metres
    sigma = 0.0015 - 0.0005 * z0 + 0.0003 * z0 ** 2 + 0.0001 * z0 ** 1.5 * th ** 2 / (math.pi / 2 - th) ** 2
    assert np.std(err) == pytest.approx(sigma, rel=0.03)
    assert abs(np.mean(err)) < 3 * sigma / 300


def test_laser_profile_has_constant_noise():
    laser = dataclasses.replace(TimeOfFlight.laser(), dropout=0.0, flying=0.0, grazing_deg=None,
                                depth_unit=1e-4, max_range=6.0)
    for z0 in (1.0, 5.0):
        z = np.full((200, 200), z0)
        units, _ = laser.apply(z, np.ones_like(z), INTR, np.random.default_rng(4))
        assert np.std(units * 1e-4 - z0) == pytest.approx(0.01, rel=0.04)


def _plate(z_near=1.0, z_far=2.0, cols=(120, 180)):
    z = np.full((20, 300), z_far)
    z[:, cols[0]:cols[1]] = z_near
    return z


@pytest.mark.parametrize("baseline", [0.075, -0.075])
def test_projector_shadow_has_the_width_of_the_disparity_jump(baseline):
    fx, (a, b) = 100.0, (120, 180)
    z = _plate(cols=(a, b))
    shadow = projector_shadow(z, fx, baseline)
    width = fx * abs(baseline) * (1 / 1.0 - 1 / 2.0)  # 3.75 px
    u = np.arange(300)
    if baseline > 0:  # projector to the right: the shadow falls left of the plate
        expected = (u < a) & (u > a - width)
    else:
        expected = (u >= b) & (u < b - 1 + width)
    np.testing.assert_array_equal(shadow, np.tile(expected, (20, 1)))
    assert expected.sum() == 3


def test_projector_shadow_needs_an_occluder_and_ignores_empty_pixels():
    z = np.tile(np.linspace(1.0, 3.0, 300), (10, 1))  # a slanted wall: lit everywhere
    assert not projector_shadow(z, 525.0, 0.075).any()
    z[:, 100:110] = np.nan
    assert not projector_shadow(z, 525.0, 0.075).any()


def test_structured_light_scene_shadow_is_missing_depth():
    sensor = dataclasses.replace(StructuredLight(), dropout=0.0, edge_dropout=0.0, flying=0.0)
    z = _plate()
    units, _ = sensor.apply(z, np.ones_like(z), INTR, np.random.default_rng(0))
    width = 525.0 * 0.075 * 0.5  # 19.7 px right of the plate (projector to the left)
    u = np.arange(300)
    expected = (u >= 180) & (u < 179 + width)
    np.testing.assert_array_equal(units == 0, np.tile(expected, (20, 1)))


@pytest.mark.parametrize("cls", [StructuredLight, TimeOfFlight])
def test_flying_pixels_lie_between_the_two_sides_of_an_edge(cls):
    sensor = cls(dropout=0.0, edge_dropout=0.0, flying=0.3, grazing_deg=None, depth_unit=1e-4,
                 **({"disparity_noise": 0.0, "disparity_step": 0.0, "shadows": False}
                    if cls is StructuredLight else {"sigma_coeffs": (0, 0, 0, 0), "min_sigma": 0}))
    z = np.full((2000, 40), 3.0)
    z[:, :20] = 1.0
    units, fly = sensor.apply(z, np.ones_like(z), INTR, np.random.default_rng(5))
    edge = np.zeros_like(fly)
    edge[:, 19:21] = True
    assert not (fly & ~edge).any()
    assert fly[edge].mean() == pytest.approx(0.3, abs=0.03)
    depth = units[fly] * 1e-4
    assert np.all((depth >= 1.0 - 1e-4) & (depth <= 3.0 + 1e-4))
    # uniform between the sides: mean at the middle, a quarter in each quarter
    assert depth.mean() == pytest.approx(2.0, abs=0.06)
    assert np.mean(depth < 1.5) == pytest.approx(0.25, abs=0.05)
    np.testing.assert_allclose(units[~fly & ~edge] * 1e-4, z[~fly & ~edge], atol=1e-4)


def test_edge_dropout_is_on_the_far_side_only_and_needs_two_surfaces():
    z = np.full((50, 50), 3.0)
    z[:, :25] = 1.0
    other, far = edge_neighbours(z, 0.05)
    assert far[:, 25].all() and far.sum() == 50
    np.testing.assert_array_equal(np.isfinite(other), np.isin(np.arange(50), [24, 25])[None, :]
                                  .repeat(50, axis=0))
    # a steep plane (depth changing 0.1 m per pixel) is one surface: no edge
    ramp = np.tile(np.arange(50) * 0.1 + 1.0, (50, 1))
    assert np.isfinite(edge_neighbours(ramp, 0.05)[0]).all()
    assert not np.isfinite(edge_neighbours(ramp, 0.05, np.zeros((50, 50), int))[0]).any()
    sensor = StructuredLight(dropout=0.0, edge_dropout=1.0, flying=0.0, grazing_deg=None,
                             shadows=False)
    units, _ = sensor.apply(z, np.ones_like(z), INTR, np.random.default_rng(0))
    np.testing.assert_array_equal(units == 0, far)


def test_random_dropout_and_grazing_and_range():
    sensor = TimeOfFlight(dropout=0.1, flying=0.0, edge_dropout=0.0, grazing_deg=80.0)
    z = np.full((200, 200), 2.0)
    z[:, :10] = 0.3  # closer than the minimum range
    cos = np.ones_like(z)
    cos[:, 190:] = math.cos(math.radians(85))
    units, _ = sensor.apply(z, cos, INTR, np.random.default_rng(6))
    assert (units[:, :10] == 0).all() and (units[:, 190:] == 0).all()
    assert (units[:, 10:190] == 0).mean() == pytest.approx(0.1, abs=0.01)


@pytest.mark.parametrize("name", ["structured-light", "tof", "laser"])
def test_generated_scene_with_a_profile(name):
    sensor = sensor_profile(name)
    s = generate_scene("box", 3, subsample=4, sensor=sensor)
    again = generate_scene("box", 3, subsample=4, sensor=sensor)
    np.testing.assert_array_equal(s.depth_mm, again.depth_mm)
    valid = s.depth_mm > 0
    assert valid.mean() > 0.5
    # flying pixels (valid depth, no plane) sit at object edges only, and are labelled -1
    flying = valid & (s.gt_labels < 0)
    if sensor.flying > 0:
        other, _ = edge_neighbours(s.depth_true, sensor.edge_jump)
        assert np.all(np.isfinite(other[flying]))
    # measured points of each plane lie on it within 6 sigma of the model (plus the depth unit)
    r = np.stack(np.meshgrid((np.arange(160) - s.intrinsics.cx) / s.intrinsics.fx,
                             (np.arange(120) - s.intrinsics.cy) / s.intrinsics.fy), axis=-1)
    for p in s.visible_planes():
        m = s.gt_labels == p.index
        zt = s.depth_true[m]
        err = np.abs(s.depth_mm[m] * sensor.depth_unit - zt)
        bound = 6 * sensor.axial_sigma(zt, np.full(zt.shape, 0.2)) + sensor.depth_unit
        if isinstance(sensor, StructuredLight):
            bound = bound + 0.5 * sensor.disparity_step * zt ** 2 / (sensor.focal_px * sensor.baseline) * 1.2
        assert np.all(err <= bound)
    assert s.metadata()["sensor"]["profile"] == sensor.profile
    assert r.shape == (120, 160, 2)


@pytest.mark.parametrize("call,match", [
    (lambda: StructuredLight(baseline=0.0), "baseline must not be 0"),
    (lambda: StructuredLight(disparity_noise=-1), "disparity noise"),
    (lambda: StructuredLight(shadows="yes"), "shadows must be True or False"),
    (lambda: TimeOfFlight(sigma_coeffs=(1, 2)), "sigma_coeffs must be 4"),
    (lambda: TimeOfFlight(flying=2.0), "sensor flying"),
    (lambda: TimeOfFlight(min_range=5.0, max_range=4.0), "must exceed min range"),
    (lambda: sensor_profile("sonar"), "unknown sensor profile 'sonar'"),
    (lambda: generate_scene("box", 0, sensor="kinect"), "sensor must be a SensorModel"),
])
def test_bad_sensor_parameters_raise_input_error(call, match):
    with pytest.raises(InputError, match=match):
        call()
