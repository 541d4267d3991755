"""The floor of a scene whose floor measures off level at range (planerel.features.planes,
``PlaneParams.floor_noise_sigmas``; docs/gravity.md "A floor the sensor tilts").

The real PCL office cloud (``../shared/data/kinect/office1.pcd``) shows its floor only as a strip
3.1-3.9 m away at the image's bottom; the up the walls give makes it 6.2 degrees off level
(structured-light depth error growing with range), so it was no floor and the ramp rule fired
on it.  :func:`office_like_scene` reproduces that: a level camera 1.3 m up, a wall 5 m away and
one on the right dominating the up estimate, a 1 m wide floor strip 3.1-3.9 m away, and a depth
error that grows across the image columns (``distortion``: depth times ``1 + k (u - cx) / f``)
which tilts the strip sideways.  Ramps are rendered with the same structured-light sensor, with
no horizontal floor in view (the case the fallback decides), close up and at range.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from planerel.features.planes import PlaneParams, measure_planes
from planerel.io.cloud import Intrinsics, depth_to_cloud
from planerel.synth.generator import camera_planes, cast_world, cos_incidence, look_at_pose, raycast
from planerel.synth.geometry import ramp_geometry
from planerel.synth.sensor import StructuredLight

INTR = Intrinsics(640, 480, 525.0, 525.0, 319.5, 239.5)
#: The Kinect-like sensor of the varied world, seeing to 6 m (the office wall is 5 m away).
SENSOR = StructuredLight(max_range=6.0, shadows=False)


def _measured(depth_true, normals, plane, seed: int, distortion: float = 0.0):
    """Depth (metres) -> the structured-light sensor's organized cloud, with an optional depth
    error growing across the columns (``depth * (1 + distortion * (u - cx) / fx)``)."""
    u = (np.arange(INTR.width) - INTR.cx) / INTR.fx
    z = depth_true * (1.0 + distortion * u[None, :])
    cos = cos_incidence(normals, plane, INTR)
    units, _fly = SENSOR.apply(z, cos, INTR, np.random.default_rng(seed), plane)
    return units


def office_like_scene(distortion: float = 0.28, seed: int = 0):
    """``(cloud, strip_mask)``: the office situation in the camera frame (x right, y down,
    z forward; the camera level, 1.3 m above the floor)."""
    h = 1.3
    polys = [
        np.array([[-2.6, -1.7, 5.0], [1.5, -1.7, 5.0], [1.5, h, 5.0], [-2.6, h, 5.0]]),  # far wall
        np.array([[1.5, -1.7, 2.0], [1.5, -1.7, 5.0], [1.5, h, 5.0], [1.5, h, 2.0]]),  # right wall
        np.array([[-2.6, 0.55, 3.9], [1.5, 0.55, 3.9], [1.5, h, 3.9],
                  [-2.6, h, 3.9]]),  # a desk front hiding the floor beyond 3.9 m
        np.array([[-0.45, h, 3.1], [0.55, h, 3.1], [0.55, h, 3.9], [-0.45, h, 3.9]]),  # floor strip
    ]
    normals = np.array([[0, 0, -1.0], [-1.0, 0, 0], [0, 0, -1.0], [0, -1.0, 0]])
    depth, poly = raycast(polys, INTR)
    units = _measured(depth, normals, poly, seed, distortion)
    cloud = depth_to_cloud(units, INTR, 1.0 / SENSOR.depth_unit, source="office-like")
    return cloud, poly == 3, poly


def ramp_scene(angle: float, distance: float, seed: int = 0):
    """``(cloud, up, slope_mask)``: a ramp of ``angle`` degrees (3 m run, 2 m wide) whose slope
    fills the lower view, no floor in the world; the camera 1.2 m above the ramp's low end,
    ``distance`` metres before it, looking at the slope's middle."""
    world = ramp_geometry(angle, 3.0, 2.0, side_faces=False)
    mid_h = 1.5 * math.tan(math.radians(angle)) / 2
    pose = look_at_pose((-1.5 - distance, 0.0, 1.2), (0.0, 0.0, mid_h))
    depth, _poly, plane, _obj = cast_world(world, pose, INTR)
    normals, _off, _first = camera_planes(world, pose)
    units = _measured(depth, normals, plane, seed)
    cloud = depth_to_cloud(units, INTR, 1.0 / SENSOR.depth_unit, source="ramp")
    return cloud, pose[:3, 2].copy(), plane == 0


def _labels(*masks) -> np.ndarray:
    lab = np.full(masks[0].shape, -1, dtype=np.int32)
    for k, m in enumerate(masks):
        lab[m] = k
    return lab


def _plane_on(planes, mask):
    lab = np.asarray(planes.labels)
    k = np.bincount(lab[mask & (lab >= 0)]).argmax()
    return planes.by_label(int(k))


def test_office_like_floor_strip_is_the_floor_not_an_inclined_plane():
    cloud, strip, poly = office_like_scene()
    lab = _labels(*(poly == k for k in range(4)))
    before = measure_planes(cloud, lab, params=PlaneParams(floor_noise_sigmas=0))
    p = _plane_on(before, strip)
    # the situation of the real office: the up follows the walls, the strip measures 6 degrees
    assert before.up_source == "estimated"
    assert 5.5 < p.incline < 7.5, p.incline
    assert p.orientation == "inclined" and before.floor is None and p.area > 0.5
    after = measure_planes(cloud, lab)
    q = _plane_on(after, strip)
    assert after.floor == q.label and q.is_floor and q.orientation == "horizontal"
    assert q.incline == pytest.approx(p.incline)  # the measurement is kept
    assert np.allclose(after.up, before.up)
    assert abs(q.height) < 1e-9
    # heights now from the strip: the desk front stands on it
    desk = _plane_on(after, poly == 2)
    assert desk.height == pytest.approx(0.375, abs=0.08)


def test_office_like_floor_strip_is_support_and_in_no_proposal():
    from planerel.features.facts import describe_scene

    cloud, strip, poly = office_like_scene()
    lab = _labels(*(poly == k for k in range(4)))
    desc = describe_scene(cloud, lab, scene_id="t")
    floor = desc.planes.floor
    assert floor is not None and floor == _plane_on(desc.planes, strip).label
    assert all(floor not in o.planes for o in desc.objects)


def test_without_the_distortion_the_strip_is_a_level_floor_anyway():
    cloud, strip, poly = office_like_scene(distortion=0.0)
    lab = _labels(*(poly == k for k in range(4)))
    ps = measure_planes(cloud, lab)
    p = _plane_on(ps, strip)
    assert p.incline < 2 and p.orientation == "horizontal" and ps.floor == p.label


def test_a_noise_free_cloud_gets_no_allowance():
    """Ideal depth: no noise is measured, so a tilted strip stays inclined (the fallback only
    forgives what the sensor can err)."""
    cloud, strip, poly = office_like_scene()
    u = (np.arange(INTR.width) - INTR.cx) / INTR.fx
    depth, _ = raycast([np.array([[-0.45, 1.3, 3.1], [0.55, 1.3, 3.1], [0.55, 1.3, 3.9],
                                  [-0.45, 1.3, 3.9]])], INTR)
    clean = depth_to_cloud(depth * (1.0 + 0.28 * u[None, :]), INTR, 1.0, source="clean")
    ps = measure_planes(clean, np.where(np.isfinite(depth), 0, -1).astype(np.int32),
                        up=(0.0, -1.0, 0.0))
    assert ps.planes[0].incline > 5.5 and ps.floor is None
    assert ps.planes[0].orientation == "inclined"


@pytest.mark.parametrize("angle,distance", [(7.0, 0.3), (9.0, 0.3), (9.0, 2.0), (12.0, 2.0)])
def test_ramps_without_a_floor_in_view_stay_inclined(angle, distance):
    """A ramp whose slope fills the lower view (no horizontal plane anywhere), seen close up
    (slope 0.5-3.5 m away) and at range (2-5 m): the slope's tilt is beyond what the sensor can
    err over its width there, so it is no floor and stays ``inclined``."""
    cloud, up, slope = ramp_scene(angle, distance)
    lab = np.where(slope, 0, -1).astype(np.int32)
    ps = measure_planes(cloud, lab, up=up)
    p = ps.planes[0]
    assert p.incline == pytest.approx(angle, abs=1.5)
    assert p.orientation == "inclined" and ps.floor is None and not p.is_floor


def test_the_allowance_is_bounded_by_horizontal_tol():
    """A plane tilted by more than twice ``horizontal_tol`` is never the floor, however narrow
    and far (the allowance is at most ``horizontal_tol``)."""
    cloud, strip, poly = office_like_scene(distortion=0.7)
    lab = _labels(*(poly == k for k in range(4)))
    ps = measure_planes(cloud, lab, params=PlaneParams(horizontal_tol=3.0))
    p = _plane_on(ps, strip)
    assert p.incline > 6.0 and ps.floor is None and p.orientation == "inclined"


def test_floor_noise_sigmas_is_checked():
    from planerel.errors import InputError

    with pytest.raises(InputError):
        PlaneParams(floor_noise_sigmas=-1)
    assert dataclasses.replace(PlaneParams(), floor_noise_sigmas=0).floor_noise_sigmas == 0
