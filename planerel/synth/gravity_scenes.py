"""Synthetic scenes at a chosen camera pitch and roll, for measuring the gravity estimate.

:func:`posed_scene` builds one object (box, stairs, ramp) on a floor with 0-2 walls, like
:mod:`planerel.synth.generator`, but the camera's *pitch* (angle of the optical axis below the horizon)
and *roll* (about the optical axis) are chosen by the caller instead of drawn, from looking
straight ahead (pitch 0) to looking steeply down (pitch 85).  The object is placed where the
optical axis meets the floor (clamped to 0.4-2.5 m beyond the camera), so it is in view at
every pitch.  Geometry, ray casting and the sensor model are those of :mod:`planerel.synth.generator`;
the true up vector is returned and *not* stored in the cloud, so the cloud must be estimated.

``kind="stairs_from_above"`` is the case of issue 15: a staircase of 4-6 steps seen from a
camera 1.5-1.9 m above its top landing, looking down the flight (treads and the floor below
seen, risers hidden).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planerel.errors import InputError

__all__ = ["PosedScene", "posed_scene", "KINDS"]

#: Scene kinds :func:`posed_scene` builds.
KINDS = ("box", "stairs", "ramp", "stairs_from_above")


@dataclass(frozen=True, eq=False)
class PosedScene:
    """A synthetic scene seen at a known pose.

    Attributes
    ----------
    cloud : Cloud
        ``(H, W, 3)``, metres, ``up`` not set.
    gt_labels : ndarray, shape (H, W), int32
        Plane index per pixel, -1 where the depth is missing.
    roles : tuple of str
        Role of each plane index (``floor``, ``wall``, ``tread``, ...).
    up : ndarray, shape (3,)
        True unit up vector in the camera frame.
    pitch_deg, roll_deg : float
        The camera pose.
    kind : str
    params : dict
        Drawn dimensions and placement.
    """

    cloud: object
    gt_labels: np.ndarray
    roles: tuple
    up: np.ndarray
    pitch_deg: float
    roll_deg: float
    kind: str
    params: dict


def _object(kind: str, rng: np.random.Generator):
    from planerel.synth import geometry as sg

    if kind == "box":
        dims = (float(rng.uniform(0.3, 1.0)), float(rng.uniform(0.3, 0.8)), float(rng.uniform(0.2, 0.7)))
        return sg.box_geometry(*dims), {"size": dims}
    if kind == "stairs":
        steps = int(rng.integers(3, 6))
        rise, tread, width = (float(rng.uniform(0.14, 0.2)), float(rng.uniform(0.25, 0.33)),
                              float(rng.uniform(0.8, 1.3)))
        return (sg.stairs_geometry(steps, rise, tread, width, sides="open"),
                {"steps": steps, "rise": rise, "tread": tread, "width": width})
    if kind == "ramp":
        angle, run, width = (float(rng.uniform(10.0, 25.0)), float(rng.uniform(1.0, 1.8)),
                             float(rng.uniform(0.8, 1.3)))
        return (sg.ramp_geometry(angle, run, width, platform=0.4, side_faces=True),
                {"angle_deg": angle, "run": run, "width": width})
    raise InputError(f"unknown posed scene kind {kind!r}; choose one of {', '.join(KINDS)}")


def posed_scene(kind: str, pitch_deg: float, roll_deg: float = 0.0, seed: int = 0, *,
                subsample: int = 4, sensor=None, walls: int | None = None) -> PosedScene:
    """One synthetic scene seen with the camera at ``pitch_deg`` below the horizon and rolled
    by ``roll_deg``.

    Parameters
    ----------
    kind : {"box", "stairs", "ramp", "stairs_from_above"}
    pitch_deg : float
        In [-10, 85].
    roll_deg : float
        In [-45, 45].
    seed : int
        Dimensions, camera height and azimuth, walls and sensor noise.
    subsample : int
        Of the 640x480 Kinect image (4 gives 160x120).
    sensor : SensorModel, StructuredLight or TimeOfFlight, optional
        Default ``SensorModel()`` (Kinect-like noise and quantisation);
        :class:`planerel.synth.sensor.StructuredLight` adds the projector's shadows, flying
        pixels at depth edges and grazing dropout (flying pixels are labelled -1).
    walls : int, optional
        0, 1 or 2 walls; default drawn.

    Returns
    -------
    PosedScene
    """
    from planerel.io.cloud import Intrinsics, depth_to_cloud
    from planerel.synth import geometry as sg
    from planerel.synth.generator import SensorModel, _check_sensor, look_at_pose, measure, raycast

    if kind not in KINDS:
        raise InputError(f"unknown posed scene kind {kind!r}; choose one of {', '.join(KINDS)}")
    p = float(pitch_deg)
    r = float(roll_deg)
    if not -10.0 <= p <= 85.0:
        raise InputError(f"pitch must be in [-10, 85] degrees, got {pitch_deg!r}")
    if not -45.0 <= r <= 45.0:
        raise InputError(f"roll must be in [-45, 45] degrees, got {roll_deg!r}")
    sensor = SensorModel() if sensor is None else sensor
    _check_sensor(sensor)
    rng = np.random.default_rng(seed)
    intr = Intrinsics.kinect().scaled(int(subsample))
    az = float(rng.uniform(-180.0, 180.0))
    yaw_jitter = float(rng.uniform(-30.0, 30.0))
    height = float(rng.uniform(0.7, 1.7))
    n_walls = int(rng.integers(0, 3)) if walls is None else int(walls)
    back_gap, side_gap = float(rng.uniform(0.5, 2.0)), float(rng.uniform(0.4, 1.5))
    side_sign = 1.0 if rng.random() < 0.5 else -1.0
    wall_turn = float(rng.uniform(-20.0, 20.0))
    direction = np.array([math.cos(math.radians(az)), math.sin(math.radians(az))])
    params: dict = {"azimuth_deg": az, "walls": n_walls}
    if kind == "stairs_from_above":
        steps = int(rng.integers(4, 7))
        rise, tread, width = (float(rng.uniform(0.15, 0.19)), float(rng.uniform(0.26, 0.32)),
                              float(rng.uniform(0.9, 1.3)))
        geom = sg.stairs_geometry(steps, rise, tread, width, top_depth=1.5, sides="closed", rail=0.9)
        # stairs climb along local +x; the camera stands on the landing looking down (-x)
        obj = sg.place(geom, az + 180.0)
        verts = obj.vertices()
        height = steps * rise + float(rng.uniform(1.5, 1.9))  # eye height above the landing
        # camera above the landing, 0.3 m back from the top nosing
        nosing = (steps - 1) * tread - 0.5 * ((steps - 1) * tread + 1.5)
        cam_xy = -direction * (nosing + 0.3)
        params.update({"steps": steps, "rise": rise, "tread": tread, "width": width})
    else:
        geom, dims = _object(kind, rng)
        params.update(dims)
        facing = 0.0  # local +x away from the camera: stairs and ramps rise away from it
        obj_probe = sg.place(geom, az + facing + yaw_jitter)
        verts = obj_probe.vertices()
        top = float(verts[:, 2].max())
        reach = float(np.max(verts[:, :2] @ -direction))
        aim_h = 0.5 * top
        dist = (height - aim_h) / math.tan(math.radians(p)) if p > 1.0 else 2.5
        dist = min(max(dist, reach + 0.4), reach + 2.5)
        obj = sg.place(geom, az + facing + yaw_jitter, position=tuple(direction * dist))
        verts = obj.vertices()
        cam_xy = np.zeros(2)
    parts = [sg.floor_geometry(12.0), obj]
    back_dir = math.radians(az + wall_turn)
    bd = np.array([math.cos(back_dir), math.sin(back_dir)])
    sd = np.array([-bd[1], bd[0]]) * side_sign
    wall_dist = float(np.max((verts[:, :2] - cam_xy) @ bd)) + back_gap
    side_dist = float(np.max(np.abs((verts[:, :2] - cam_xy) @ sd))) + side_gap
    if n_walls >= 1:
        parts.append(sg.wall_geometry(cam_xy + bd * wall_dist, math.degrees(back_dir) + 90.0, 14.0, 2.8))
    if n_walls >= 2:
        parts.append(sg.wall_geometry(cam_xy + sd * side_dist + bd * (wall_dist - 5.0),
                                      math.degrees(back_dir), 10.0, 2.8))
    world = sg.combine(*parts)
    eye = np.array([cam_xy[0], cam_xy[1], height])
    look = np.array([direction[0] * math.cos(math.radians(p)),
                     direction[1] * math.cos(math.radians(p)), -math.sin(math.radians(p))])
    pose = look_at_pose(eye, eye + look, r)
    rot, t = pose[:3, :3], pose[:3, 3]
    polys = [pg.vertices @ rot.T + t for pg in world.polygons]
    depth_true, poly_index = raycast(polys, intr)
    plane_of = np.array([pg.plane for pg in world.polygons], dtype=np.int32)
    planes = np.where(poly_index >= 0, plane_of[np.maximum(poly_index, 0)], -1)
    # incidence for the sensor's grazing dropout
    normals = []
    for k in range(len(world.planes)):
        pg = next(q for q in world.polygons if q.plane == k)
        normals.append(rot @ pg.normal())
    normals = np.array(normals)
    xn = (np.arange(intr.width) - intr.cx) / intr.fx
    yn = (np.arange(intr.height) - intr.cy) / intr.fy
    nrm = normals[np.maximum(planes, 0)]
    dot = nrm[:, :, 0] * xn[None, :] + nrm[:, :, 1] * yn[:, None] + nrm[:, :, 2]
    cos_inc = np.abs(dot) / np.sqrt(xn[None, :] ** 2 + yn[:, None] ** 2 + 1.0)
    depth_mm, flying = measure(depth_true, cos_inc, sensor, intr, rng, surface=planes)
    labels = np.where((depth_mm > 0) & ~flying, planes, -1).astype(np.int32)
    cloud = depth_to_cloud(depth_mm, intr, 1.0 / sensor.depth_unit, source=f"{kind}-p{p:g}-r{r:g}")
    up = rot[:, 2].copy()
    params.update({"height": height, "pitch_deg": p, "roll_deg": r})
    return PosedScene(cloud, labels, tuple(s.role for s in world.planes), up, p, r, kind, params)
