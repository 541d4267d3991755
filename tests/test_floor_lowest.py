"""Which plane is the floor when the far view is bent (planerel.features.planes, the floor rule;
docs/gravity.md "The floor's level: its own lowest point, not a bent far piece's").

An active-stereo camera (RealSense) in a room bends its far surfaces: real frames show pieces
5-8 m away measured 8-29 degrees inclined whose low ends reach 0.2-0.4 m below the floor, and a
near floor measured a degree or two off level.  The floor rule compared each candidate's
centroid with the lowest hull point of every plane, so such a far piece made the near floor no
floor (aims-lab frames of hunt28: a far piece, or nothing, was the floor).  It now compares
each candidate's own lowest point with the lowest point of the level and vertical planes.

The scenes are rendered noise-free with the camera frame's conventions (x right, y down, z
forward) and true labels, so the test is about the rule alone.
"""

from __future__ import annotations

import math

import numpy as np

from planerel.features.planes import measure_planes
from planerel.io.cloud import Intrinsics, depth_to_cloud
from planerel.synth.generator import raycast

INTR = Intrinsics(640, 480, 525.0, 525.0, 319.5, 239.5)
UP = (0.0, -1.0, 0.0)
#: the camera's height over the near floor, metres
H = 1.2


def _floor(z0: float, z1: float, tilt: float, x0: float = -1.5, x1: float = 1.5) -> np.ndarray:
    """A floor quad from ``z0`` to ``z1`` metres ahead whose far edge is ``tilt`` degrees
    lower than level (a floor the sensor measures off level), level at its middle."""
    zm = 0.5 * (z0 + z1)
    dy = lambda z: (z - zm) * math.tan(math.radians(tilt))  # noqa: E731 (y grows downwards)
    return np.array([[x0, H + dy(z0), z0], [x1, H + dy(z0), z0], [x1, H + dy(z1), z1],
                     [x0, H + dy(z1), z1]])


def _scene(*polys):
    depth, poly = raycast(list(polys), INTR)
    lab = np.where(poly >= 0, poly, -1).astype(np.int32)
    return depth_to_cloud(depth, INTR, 1.0, source="floor-test"), lab


def _bent_far_piece() -> np.ndarray:
    """A piece 5-7 m ahead, to the right, inclined 15 degrees, its far end 0.35 m below the
    floor (what the sensor made of the room's far end)."""
    drop = 2.0 * math.tan(math.radians(15.0))
    return np.array([[0.6, H - 0.2, 5.0], [1.8, H - 0.2, 5.0], [1.8, H - 0.2 + drop, 7.0],
                     [0.6, H - 0.2 + drop, 7.0]])


def test_a_near_floor_a_degree_off_level_is_the_floor_despite_a_bent_far_piece():
    cloud, lab = _scene(_floor(1.0, 3.5, 2.0), _bent_far_piece())
    ps = measure_planes(cloud, lab, up=UP)
    near, far = ps.by_label(0), ps.by_label(1)
    assert near.orientation == "horizontal" and 1.5 < near.incline < 2.5
    assert far.orientation == "inclined" and far.incline > 10
    # the far piece reaches 0.3 m below the floor, farther than floor_tol
    assert float(np.min(np.asarray(far.hull3d) @ np.asarray(UP))) < \
        float(np.asarray(near.centroid) @ np.asarray(UP)) - 0.2
    assert ps.floor == 0 and near.is_floor and abs(near.height) < 1e-9


def test_a_gentle_ramp_larger_than_the_floor_in_view_is_no_floor():
    """A 4.5-degree ramp is ``horizontal`` by the tolerance (``gentle_tol`` 0, the default)
    and reaches the floor with its low end, but its middle is 0.1 m up: the floor (smaller in
    view) is the floor.  With ``gentle_tol`` 3.5 (the plane no floor and larger than
    ``gentle_area``) the ramp is ``inclined``, and the floor the same."""
    from planerel.features.planes import PlaneParams

    rise = 2.5 * math.tan(math.radians(4.5))
    ramp = np.array([[-1.5, H, 3.0], [1.5, H, 3.0], [1.5, H - rise, 5.5], [-1.5, H - rise, 5.5]])
    cloud, lab = _scene(_floor(2.6, 3.0, 0.0), ramp)
    ps = measure_planes(cloud, lab, up=UP)
    assert ps.by_label(1).orientation == "horizontal" and ps.by_label(1).area > ps.by_label(0).area
    assert ps.floor == 0
    ps = measure_planes(cloud, lab, up=UP, params=PlaneParams(gentle_tol=3.5))
    assert ps.by_label(1).orientation == "inclined" and ps.floor == 0


def test_a_level_floor_and_a_table_top_the_floor_is_the_floor():
    """The rule's purpose is kept: a table top (0.75 m up, larger in view) is no floor when the
    floor is in view, and a wall standing on the floor sets the lowest point."""
    table = np.array([[-0.8, H - 0.75, 1.2], [0.8, H - 0.75, 1.2], [0.8, H - 0.75, 2.4],
                      [-0.8, H - 0.75, 2.4]])
    wall = np.array([[-3.0, -1.0, 6.0], [3.0, -1.0, 6.0], [3.0, H, 6.0], [-3.0, H, 6.0]])
    cloud, lab = _scene(table, _floor(2.6, 5.9, 0.0), wall)
    ps = measure_planes(cloud, lab, up=UP)
    assert ps.by_label(0).area > ps.by_label(1).area * 0.3  # the table is a real candidate
    assert ps.floor == 1
    assert abs(ps.by_label(0).height - 0.75) < 0.01


def test_a_table_top_over_a_wall_reaching_lower_is_no_floor():
    """No floor in view, a wall reaching 1.2 m below the table top: the table is not the
    floor by the lowest-point rule (the vertical plane's foot is the scene's lowest point).

    The ground rule is isolated off here (``ground_reach=0``, its riser test at any distance):
    the wall stands 0.6 m beyond the table's far edge, farther than ``ground_reach`` (0.5 m,
    table50), so by default the table is the ground, as a table top filling a close view with
    the room's wall beyond it is; the same wall at the table's edge still keeps it from that."""
    from planerel.features.planes import PlaneParams

    table = np.array([[-0.8, H - 0.75, 1.2], [0.8, H - 0.75, 1.2], [0.8, H - 0.75, 2.4],
                      [-0.8, H - 0.75, 2.4]])
    wall = np.array([[-3.0, -1.0, 3.0], [3.0, -1.0, 3.0], [3.0, H, 3.0], [-3.0, H, 3.0]])
    cloud, lab = _scene(table, wall)
    assert measure_planes(cloud, lab, up=UP, params=PlaneParams(ground_reach=0.0)).floor is None
    assert measure_planes(cloud, lab, up=UP).floor == 0
    near = wall.copy()
    near[:, 2] = 2.45
    cloud, lab = _scene(table, near)
    assert measure_planes(cloud, lab, up=UP).floor is None


def test_a_far_wall_the_sensor_bends_below_the_floor_is_only_as_low_as_its_noise():
    """A structured-light sensor (sigma growing as z^2: 7 cm at 7 m) sees a wall 7 m away
    reaching 12 cm below the floor's level (where nothing in front hides its foot): a plane's
    low point counts only as low as the sensor is sure of (raised by ``floor_noise_sigmas``
    sigma at its far depth), so the floor 2.6-4.3 m away is still the floor (hunt28's dining
    rooms: Kinect walls 6.5-7.6 m away 10-18 cm below the floor).  With ``floor_noise_sigmas``
    0 (no allowance) it is not."""
    from planerel.features.planes import PlaneParams
    from planerel.synth.generator import cos_incidence
    from planerel.synth.sensor import StructuredLight

    sensor = StructuredLight(max_range=8.0, shadows=False)
    floor = _floor(2.6, 4.3, 0.0)
    wall = np.array([[-3.0, -1.0, 7.0], [3.0, -1.0, 7.0], [3.0, H + 0.12, 7.0],
                     [-3.0, H + 0.12, 7.0]])
    depth, poly = raycast([floor, wall], INTR)
    normals = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, -1.0]])
    units, _ = sensor.apply(depth, cos_incidence(normals, poly, INTR), INTR,
                            np.random.default_rng(5), poly)
    cloud = depth_to_cloud(units, INTR, 1.0 / sensor.depth_unit, source="far wall")
    lab = np.where((poly >= 0) & np.isfinite(cloud.xyz[..., 2]), poly, -1).astype(np.int32)
    ps = measure_planes(cloud, lab, up=UP)
    assert ps.by_label(1).orientation == "vertical"
    assert ps.floor == 0
    # the floor rule alone (the ground rule's riser test at any distance, ``ground_reach=0``):
    # with the default the ground rule takes the floor, the wall standing 2.7 m beyond it
    strict = measure_planes(cloud, lab, up=UP, params=PlaneParams(floor_noise_sigmas=0,
                                                                   ground_reach=0.0))
    assert strict.floor is None
    ground = measure_planes(cloud, lab, up=UP, params=PlaneParams(floor_noise_sigmas=0))
    assert ground.floor == 0
