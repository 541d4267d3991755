"""The varied synthetic world: several objects per scene, clutter, real dimensions, any camera.

A scene has one *primary* object of the class asked for (box, stairs or ramp: the scene's class
in the manifest), 0-3 more objects (boxes, stairs, ramps, or clutter of class ``other``: tables,
chairs, cylinders, laptops, small tilted plates, shelves, doors), a floor and 0-2 walls, seen by a
camera 0.3-2 m high pitched 0-75 degrees down and rolled.  Every object keeps its own index, so
the per-pixel object image is exact ground truth for object proposals.  The ranges are
:class:`WorldRange`; ``docs/synthetic-world.md`` lists them with their sources.

Construction (all random numbers from the scene's seed, redrawn until the primary object covers
enough of the image):

1. Camera at ``(0, 0, height)`` looking along world +x, pitched down and rolled.
2. The primary object is placed where the ray through a random pixel of the image's centre
   region meets the floor (0.6-4 m away): boxes at any yaw (sometimes open, sometimes on a table,
   sometimes touching a second box); ascending stairs and pitch ramps rise away from the camera
   (+-35 degrees), roll ramps across the view; descending stairs start at a drop edge in front of
   a camera standing on the upper floor.
3. Extra objects at other floor points seen by the camera, footprints not overlapping.
4. Walls behind and beside everything, sometimes touching the farthest object.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planerel.errors import InputError
from planerel.io.cloud import Intrinsics
from planerel.synth import geometry as sg

__all__ = [
    "WORLDS",
    "OTHER",
    "CLUTTER",
    "WorldRange",
    "generate_world_scene",
]

#: World names for ``planerel dataset synth --world``.
WORLDS = ("paper", "varied")
#: The class of objects that are none of the learned classes.
OTHER = "other"
#: Clutter kinds (class ``other``).
CLUTTER = ("table", "chair", "cylinder", "laptop", "plate", "shelf", "door")


def _pair(name, value, lo=0.0):
    try:
        a, b = (float(v) for v in value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a (min, max) pair of numbers, got {value!r}") from None
    if not (math.isfinite(a) and math.isfinite(b)) or a > b or a < lo:
        raise InputError(f"{name} must be a finite (min, max) pair with {lo} <= min <= max, "
                         f"got {value!r}")
    return (a, b)


@dataclass(frozen=True)
class WorldRange:
    """Ranges the varied world is drawn from (uniformly unless said otherwise).

    Parameters
    ----------
    camera_height : (float, float)
        Metres above the floor the camera stands on.
    camera_pitch_deg : (float, float)
        Optical axis below the horizontal, degrees.
    camera_roll_deg : float
        Roll about the optical axis from ``[-r, r]`` degrees.
    object_range : (float, float)
        Distance (3-D, metres) from the camera to the point the primary object stands on.
    extra_objects : (int, int)
        Number of further objects.
    box_size, box_height : (float, float)
        Box footprint sides and height, metres.
    box_tilt_deg : (float, float)
        A box's tilt from level, degrees (about a horizontal axis at any azimuth; drawn only
        when the upper bound is above 0).  Real table-top boxes' tops measure 1-4 degrees
        from the table they stand on (the shared mOSD frames, docs/results.md "The varied
        recipe on real frames"); a world of exactly level boxes teaches rules that ask for a
        top within a degree of level.
    clutter_tilt_deg : (float, float)
        The same for the further clutter objects (tables, chairs, shelves, ...; not a table
        under a box): with boxes alone tipped, a tipped top is a box's cue (measured).
    stairs_tilt_deg : (float, float)
        The same for ascending staircases (a descending flight is cut into the floor and stays
        level): with boxes and clutter tipped, level treads would be a staircase's cue.
    level_share : float
        With any of the tilt ranges on, the share of those objects that stand level all the
        same (one more draw per object, only when above 0): with every such object tipped,
        level planes belong to the floor, a table under a box and descending flights only,
        and rules learn that (measured, docs/results.md "Every object tipped").
    plate_share : float
        The share of the further clutter objects that are plates (small tilted planes), drawn
        before the uniform pick of a kind (one more draw per clutter object, only when above
        0).  A plate 0.5-0.7 m wide tilted under 20 degrees is a short ramp by every measure
        but its length, and the uniform pick makes few of them; a training world with more
        of them gives the learner negatives to tell a plate seen whole from a ramp cut by
        the view (docs/results.md, "Plates against short ramps").
    panel_share : float
        The share of the further clutter objects that are panels or sofas (a sofa three times
        in four), drawn before the plates' draw (two more draws per such object, only when
        above 0): a panel is a board 0.8-2 m long and 0.5-1.2 m wide leaning 30-80 degrees
        from the floor (a board or a mattress against a wall, a drafting table's top), a sofa
        1.2-2.4 m wide has its back (0.5-0.8 m with its cushions) leaning 60-78 degrees over a
        level seat between its arms.  Large and inclined like a ramp, but too
        steep to walk on: negatives that teach the ramp rules a ramp's slope (real rooms'
        far upholstered furniture measured 27-75 degrees, docs/objects.md "A flight's steps as
        a relation (`stair_step/2`); steep planes are no ramps").
    steps : (int, int)
        Number of steps (risers).
    rise, run, stairs_width : (float, float)
        Step rise, step run (tread depth) and flight width, metres.
    descending : float
        Share of staircases seen from the top (going down).
    nosing : (float, float)
        Width of the chamfer where each riser meets its tread, metres (drawn, with its angle
        from 20-60 degrees, only when the upper bound is above 0; :func:`~planerel.synth.
        geometry.stairs_geometry`).  Real treads end in a rounded or chamfered nosing, a
        narrow inclined strip to a range sensor; a world of sharp steps teaches rules that a
        short inclined plane is never part of a staircase (docs/results.md, "The proof gate").
    ramp_angle_deg, ramp_length, ramp_width : (float, float)
        Incline, length along the slope, width.
    open_share : float
        Share of the ascending staircases that are open-riser flights (floating treads
        ``open_thickness`` thick, no risers: :func:`~planerel.synth.geometry.stairs_geometry`'s
        ``open_risers``); drawn (one more draw per flight, and the thickness) only when above
        0, so that other worlds keep their scenes (riser26).
    open_thickness : (float, float)
        Metres: an open-riser tread's thickness.
    roll_share : float
        Share of the ramps drawn as roll ramps (placed across the view, so that the camera
        sees a side; the rest are pitch ramps rising away from it).
    side_share : float
        Share of the ramps closed by their two triangular side faces (the rest are a plate
        over the floor).  A camera lower than a roll ramp's top sees the side face and not
        the slope (ramp77's ramp-side part).
    side_view : bool
        A ramp or a flight counts as seen when one of its side faces shows, its slope or its
        steps out of view or not, and a flight stands across the view as a roll ramp does
        (the side-view part; otherwise a ramp's slope or two steps must show:
        :func:`_characteristic`).
    """

    camera_height: tuple = (0.3, 2.0)
    camera_pitch_deg: tuple = (0.0, 75.0)
    camera_roll_deg: float = 20.0
    object_range: tuple = (0.8, 3.8)
    extra_objects: tuple = (0, 3)
    box_size: tuple = (0.12, 1.2)
    box_height: tuple = (0.1, 1.0)
    box_tilt_deg: tuple = (0.0, 0.0)
    clutter_tilt_deg: tuple = (0.0, 0.0)
    stairs_tilt_deg: tuple = (0.0, 0.0)
    level_share: float = 0.0
    plate_share: float = 0.0
    panel_share: float = 0.0
    steps: tuple = (2, 10)
    rise: tuple = (0.14, 0.21)
    run: tuple = (0.22, 0.35)
    stairs_width: tuple = (0.6, 1.6)
    descending: float = 0.35
    nosing: tuple = (0.0, 0.0)
    ramp_angle_deg: tuple = (4.0, 20.0)
    ramp_length: tuple = (1.0, 4.0)
    ramp_width: tuple = (0.6, 1.6)
    open_share: float = 0.0
    open_thickness: tuple = (0.03, 0.06)
    roll_share: float = 0.5
    side_share: float = 0.6
    side_view: bool = False

    def __post_init__(self) -> None:
        for name in ("camera_height", "object_range", "box_size", "box_height", "rise", "run",
                     "stairs_width", "ramp_length", "ramp_width"):
            object.__setattr__(self, name, _pair(name.replace("_", " "), getattr(self, name)))
            if getattr(self, name)[0] <= 0:
                raise InputError(f"{name.replace('_', ' ')} must be positive, got "
                                 f"{getattr(self, name)!r}")
        pitch = _pair("camera pitch", self.camera_pitch_deg)
        if pitch[1] > 85:
            raise InputError(f"camera pitch must lie in 0..85 degrees, got {self.camera_pitch_deg!r}")
        object.__setattr__(self, "camera_pitch_deg", pitch)
        for name in ("box_tilt_deg", "clutter_tilt_deg", "stairs_tilt_deg"):
            what = name[:-9].replace("_", " ") + " tilt"
            tilt = _pair(what, getattr(self, name))
            if tilt[1] > 10:
                raise InputError(f"{what} must lie in 0..10 degrees, got {getattr(self, name)!r}")
            object.__setattr__(self, name, tilt)
        ang = _pair("ramp angle", self.ramp_angle_deg)
        if ang[0] <= 0 or ang[1] >= 60:
            raise InputError(f"ramp angle must lie in (0, 60) degrees, got {self.ramp_angle_deg!r}")
        object.__setattr__(self, "ramp_angle_deg", ang)
        for name, lo in (("steps", 2), ("extra_objects", 0)):
            v = getattr(self, name)
            try:
                a, b = (int(x) for x in v)
            except (TypeError, ValueError):
                raise InputError(f"{name} must be a (min, max) pair of integers, got {v!r}") from None
            if a < lo or a > b:
                raise InputError(f"{name} must be integers with {lo} <= min <= max, got {v!r}")
            object.__setattr__(self, name, (a, b))
        # one number each (``--range descending=0,0`` is a pair: refused with the same message)
        for name, what, hi in (("camera_roll_deg", "camera roll", 45.0),
                               ("level_share", "level share", 1.0),
                               ("plate_share", "plate share", 1.0),
                               ("panel_share", "panel share", 1.0),
                               ("descending", "descending share", 1.0),
                               ("open_share", "open-riser share", 1.0),
                               ("roll_share", "roll share", 1.0),
                               ("side_share", "side-face share", 1.0)):
            v = getattr(self, name)
            try:
                x = math.nan if isinstance(v, bool) else float(v)
            except (TypeError, ValueError):
                x = math.nan
            if not 0 <= x <= hi:
                unit = " degrees" if name == "camera_roll_deg" else ""
                raise InputError(f"{what} must be one number in 0..{hi:g}{unit}, got {v!r}")
            object.__setattr__(self, name, x)
        if not isinstance(self.side_view, bool):  # --range side_view=1 gives a number
            if not isinstance(self.side_view, (int, float)) or self.side_view not in (0, 1):
                raise InputError(f"side view must be true or false (1 or 0), got "
                                 f"{self.side_view!r}")
            object.__setattr__(self, "side_view", bool(self.side_view))
        nosing = _pair("nosing", self.nosing)
        if nosing[1] > 0.06:
            raise InputError(f"nosing must lie in 0..0.06 metres, got {self.nosing!r}")
        object.__setattr__(self, "nosing", nosing)
        thick = _pair("open thickness", self.open_thickness)
        if thick[0] <= 0 or thick[1] >= self.rise[0]:
            raise InputError(f"open thickness must lie in (0, {self.rise[0]:g}) metres (under the "
                             f"least rise), got {self.open_thickness!r}")
        object.__setattr__(self, "open_thickness", thick)

    def to_dict(self) -> dict:
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in self.__dict__.items()}


# ----------------------------------------------------------------------- placement helpers


class _Layout:
    """Objects placed so far: geometries (world), footprints (2-D convex polygons), info."""

    def __init__(self) -> None:
        self.env: list = []
        self.objects: list = []  # (geometry, info dict)
        self.footprints: list = []  # (object position in list or -1, (K, 2) array)
        self.keep_side = None  # (point, direction): footprints must lie behind this line

    def free(self, poly: np.ndarray, margin: float = 0.05, ignore=()) -> bool:
        if self.keep_side is not None:
            p0, d = self.keep_side
            if np.max((poly - p0) @ d) > -margin:
                return False
        return all(k in ignore or not _overlap(poly, other, margin) for k, other in self.footprints)

    def add(self, geom, info: dict, footprint=None) -> int:
        k = len(self.objects)
        self.objects.append((geom, info))
        if footprint is not None:
            self.footprints.append((k, footprint))
        return k


def _overlap(a: np.ndarray, b: np.ndarray, margin: float) -> bool:
    """Separating-axis test of two convex polygons ``(K, 2)``, grown by ``margin``."""
    for poly in (a, b):
        edges = np.roll(poly, -1, axis=0) - poly
        for e in edges:
            n = np.array([-e[1], e[0]])
            norm = np.linalg.norm(n)
            if norm < 1e-12:
                continue
            n /= norm
            pa, pb = a @ n, b @ n
            if pa.max() + margin <= pb.min() or pb.max() + margin <= pa.min():
                return False
    return True


#: Floor around the camera that no object may cover.
_CAMERA_SPOT = np.array([[-0.4, -0.4], [0.4, -0.4], [0.4, 0.4], [-0.4, 0.4]])


def _footprint(geom) -> np.ndarray:
    """The 2-D bounding rectangle of a local geometry, ``(4, 2)``."""
    v = geom.vertices()
    (x0, y0), (x1, y1) = v[:, :2].min(axis=0), v[:, :2].max(axis=0)
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]])


def _place_fp(fp: np.ndarray, yaw_deg: float, pos) -> np.ndarray:
    a = math.radians(yaw_deg)
    rot = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
    return fp @ rot.T + np.asarray(pos, dtype=float)[:2]


def _camera_pose(height: float, pitch_deg: float, roll_deg: float) -> np.ndarray:
    from planerel.synth.generator import look_at_pose

    p = math.radians(pitch_deg)
    eye = np.array([0.0, 0.0, height])
    return look_at_pose(eye, eye + np.array([math.cos(p), 0.0, -math.sin(p)]), roll_deg)


def _floor_point(rng, pose, intr: Intrinsics, lo: float, hi: float, region=(0.2, 0.8, 0.3, 0.9),
                 floor_z: float = 0.0):
    """Where the ray through a random pixel of ``region`` (fractions u0, u1, v0, v1 of the image)
    meets the plane ``z = floor_z``, when its distance lies in ``[lo, hi]``; else None."""
    u = rng.uniform(region[0], region[1]) * intr.width
    v = rng.uniform(region[2], region[3]) * intr.height
    rot, t = pose[:3, :3], pose[:3, 3]
    eye = -rot.T @ t
    d = rot.T @ np.array([(u - intr.cx) / intr.fx, (v - intr.cy) / intr.fy, 1.0])
    if d[2] > -1e-6:
        return None
    s = (floor_z - eye[2]) / d[2]
    p = eye + s * d
    dist = float(np.linalg.norm(p - eye))
    if not lo <= dist <= hi:
        return None
    return p


def _view_azimuth(point) -> float:
    return math.degrees(math.atan2(point[1], point[0]))


# ----------------------------------------------------------------------- object drawers


def _draw_box(rng, r: WorldRange, index: int, *, max_side=None, open_ok=True):
    lo, hi = r.box_size
    if max_side is not None:
        hi = max(lo, min(hi, max_side))
    # sizes spread evenly on a log scale: as many small boxes as large ones
    length = float(math.exp(rng.uniform(math.log(lo), math.log(hi))))
    width = float(math.exp(rng.uniform(math.log(lo), math.log(hi))))
    height = float(math.exp(rng.uniform(*np.log(r.box_height))))
    has_top = not (open_ok and rng.random() < 0.2)
    geom = sg.box_geometry(length, width, height, index, top=has_top)
    params = {"length": length, "width": width, "height": height, "top": has_top}
    geom = _tipped(rng, geom, params, r.box_tilt_deg, r.level_share)
    return geom, {"class": "box", "kind": "box" if has_top else "open box", "params": params}


def _tipped(rng, geom, params: dict, tilt_range, level_share: float = 0.0):
    """``geom`` tipped by a tilt drawn from ``tilt_range`` (recorded in ``params``); no draw at
    all when its upper bound is 0, so that level worlds keep their scenes.  With ``level_share``
    above 0 that share of the objects stays level (``tip_deg`` 0; one draw more)."""
    if tilt_range[1] <= 0:
        return geom
    if level_share > 0 and rng.random() < level_share:
        params["tip_deg"] = 0.0
        return geom
    params["tip_deg"] = float(rng.uniform(*tilt_range))
    params["tip_azimuth_deg"] = float(rng.uniform(0.0, 360.0))
    return sg.tilt(geom, params["tip_deg"], params["tip_azimuth_deg"])


def _flight(rng, r: WorldRange) -> dict:
    """A flight's steps, rise, run and width (drawn in this order)."""
    return {"steps": int(rng.integers(r.steps[0], r.steps[1] + 1)),
            "rise": float(rng.uniform(*r.rise)), "run": float(rng.uniform(*r.run)),
            "width": float(rng.uniform(*r.stairs_width))}


def _flight_sides(rng, r: WorldRange) -> dict:
    """Open or closed sides, the side walls' height above the nosings, and the nosings'
    chamfer (drawn only when ``r.nosing`` is on, so that other worlds keep their scenes)."""
    out = {"sides": "open" if rng.random() < 0.5 else "closed",
           "rail": float(rng.uniform(0.1, 0.9))}
    if r.nosing[1] > 0:
        out["nosing"] = float(rng.uniform(*r.nosing))
        out["nosing_deg"] = float(rng.uniform(20.0, 60.0))
    return out


def _draw_stairs_up(rng, r: WorldRange, index: int):
    p = _flight(rng, r)
    landing = rng.random() < 0.4
    p["top_depth"] = p["run"] * float(rng.uniform(1.5, 4.0)) if landing else p["run"]
    p.update(landing=bool(landing), **_flight_sides(rng, r), direction="up")
    if r.open_share > 0 and rng.random() < r.open_share:
        # an open-riser flight: floating treads (riser26)
        p.update(open_risers=True, thickness=float(rng.uniform(*r.open_thickness)))
        p.pop("nosing", None)
        p.pop("nosing_deg", None)
    geom = sg.stairs_geometry(p["steps"], p["rise"], p["run"], p["width"],
                              top_depth=p["top_depth"], sides=p["sides"], rail=p["rail"],
                              nosing=p.get("nosing", 0.0),
                              nosing_deg=p.get("nosing_deg", 45.0),
                              open_risers=p.get("open_risers", False),
                              thickness=p.get("thickness", 0.04), object_index=index)
    geom = _tipped(rng, geom, p, r.stairs_tilt_deg, r.level_share)
    return geom, {"class": "stairs", "kind": "stairs up", "params": p}


def _draw_ramp(rng, r: WorldRange, index: int):
    angle = float(rng.uniform(*r.ramp_angle_deg))
    length = float(rng.uniform(*r.ramp_length))
    width = float(rng.uniform(*r.ramp_width))
    run = length * math.cos(math.radians(angle))
    platform = float(rng.uniform(0.3, 1.2)) if rng.random() < 0.4 else 0.0
    side_faces = bool(rng.random() < r.side_share)
    axis = "pitch" if rng.random() < 1.0 - r.roll_share else "roll"
    geom = sg.ramp_geometry(angle, run, width, platform=platform, side_faces=side_faces,
                            object_index=index)
    return geom, {"class": "ramp", "kind": f"{axis} ramp",
                  "params": {"angle_deg": angle, "length": length, "run": run, "width": width,
                             "platform": platform, "side_faces": side_faces, "axis": axis}}


#: What ``WorldRange.panel_share`` draws, uniformly: a sofa three times in four (with one in
#: two the demo's second ramp clause, "an inclined plane of 0.5 m^2 next to another plane",
#: bounded no slope: too few multi-plane negatives reached it; docs/objects.md "A flight's
#: steps as a relation; steep planes are no ramps").
_PANEL_KINDS = ("panel", "sofa", "sofa", "sofa")

#: Clutter kinds: the geometry builder and its parameters, drawn in this order (uniform
#: ``(lo, hi)``; integers from ``range(lo, hi)`` when both are int).
_CLUTTER_DRAWS = {
    "table": (sg.table_geometry, (("length", 0.6, 1.8), ("width", 0.5, 1.0),
                                  ("height", 0.45, 0.8))),
    "chair": (sg.chair_geometry, (("seat", 0.38, 0.5), ("seat_height", 0.4, 0.5),
                                  ("back_height", 0.3, 0.55))),
    "cylinder": (sg.cylinder_geometry, (("radius", 0.08, 0.35), ("height", 0.25, 1.2))),
    "laptop": (sg.laptop_geometry, (("width", 0.28, 0.4), ("depth", 0.2, 0.28),
                                    ("lid_deg", 90.0, 135.0))),
    "plate": (sg.plate_geometry, (("length", 0.2, 0.7), ("width", 0.2, 0.7),
                                  ("tilt_deg", 8.0, 70.0))),
    # drawn only by ``WorldRange.panel_share`` (not in CLUTTER's uniform pick)
    "panel": (sg.plate_geometry, (("length", 0.8, 2.0), ("width", 0.5, 1.2),
                                  ("tilt_deg", 30.0, 80.0))),
    # drawn only by ``WorldRange.panel_share`` too: a sofa's back leans 60-78 degrees
    "sofa": (sg.sofa_geometry, (("width", 1.2, 2.4), ("depth", 0.8, 1.0),
                                ("seat_height", 0.38, 0.48), ("back_height", 0.5, 0.8),
                                ("back_deg", 60.0, 78.0), ("seat_tilt_deg", 0.0, 5.0),
                                ("arm_height", 0.55, 0.7))),
    "shelf": (sg.shelf_geometry, (("width", 0.5, 1.2), ("depth", 0.25, 0.45),
                                  ("height", 0.6, 2.0), ("boards", 2, 6))),
    "door": (sg.door_geometry, (("width", 0.7, 0.95), ("height", 1.9, 2.1))),
}


def _draw_clutter(rng, kind: str, index: int):
    if kind not in _CLUTTER_DRAWS:  # pragma: no cover - callers pass CLUTTER names
        raise InputError(f"unknown clutter kind {kind!r}")
    build, draws = _CLUTTER_DRAWS[kind]
    p = {name: (int(rng.integers(lo, hi)) if isinstance(lo, int) and isinstance(hi, int)
                else float(rng.uniform(lo, hi))) for name, lo, hi in draws}
    return build(**p, object_index=index), {"class": OTHER, "kind": kind, "params": p}


# ----------------------------------------------------------------------- the primary object


def _put(lay: _Layout, geom, info: dict, yaw: float, pos) -> bool:
    """Add ``geom`` turned by ``yaw`` at floor point ``pos`` with its footprint, unless the
    footprint covers the camera's spot (then False)."""
    fp = _place_fp(_footprint(geom), yaw, pos)
    if _overlap(fp, _CAMERA_SPOT, 0.0):
        return False
    lay.add(sg.place(geom, yaw, np.asarray(pos, dtype=float)[:2]), info, fp)
    return True


def _place_primary(kind, rng, r: WorldRange, pose, intr, lay: _Layout):
    """Place the primary object (index 1, plus helpers: a table under a box, a touching box).
    Returns False when no floor point was found."""
    anchor = None
    for _ in range(8):
        anchor = _floor_point(rng, pose, intr, *r.object_range)
        if anchor is not None:
            break
    if anchor is None:
        return False
    az = _view_azimuth(anchor)
    if kind == "box":
        variant = rng.random()
        if variant < 0.2:  # on a table
            tgeom, tinfo = _draw_clutter(rng, "table", 0)
            tp = tinfo["params"]
            ty = float(rng.uniform(-180, 180))
            geom, info = _draw_box(rng, r, 1, max_side=0.9 * min(tp["length"], tp["width"]))
            info["params"]["on"] = "table"
            yaw = ty + float(rng.uniform(-30, 30))
            tfp = _place_fp(_footprint(tgeom), ty, anchor)
            if _overlap(tfp, _CAMERA_SPOT, 0.0):
                return False
            lay.add(sg.place(geom, yaw, anchor[:2], tp["height"]), info, None)
            lay.add(sg.place(tgeom, ty, anchor[:2]), tinfo, tfp)
            return True
        geom, info = _draw_box(rng, r, 1)
        yaw = float(rng.uniform(-180, 180))
        if not _put(lay, geom, info, yaw, anchor):
            return False
        if variant < 0.5:  # a second box touching it (face to face, other height)
            g2, i2 = _draw_box(rng, r, 0, open_ok=False)
            p1, p2 = info["params"], i2["params"]
            side = 1.0 if rng.random() < 0.5 else -1.0
            shift = float(rng.uniform(-0.4, 0.4)) * min(p1["width"], p2["width"])
            local = np.array([side * (p1["length"] + p2["length"]) / 2, shift])
            a = math.radians(yaw)
            off = np.array([math.cos(a) * local[0] - math.sin(a) * local[1],
                            math.sin(a) * local[0] + math.cos(a) * local[1]])
            if _put(lay, g2, i2, yaw, anchor[:2] + off):
                i2["params"]["touching"] = "box"
                info["params"]["touching"] = "box"
        return True
    if kind == "stairs" and rng.random() < r.descending:
        p = _flight(rng, r)  # WorldRange keeps steps >= 2
        p.update(**_flight_sides(rng, r), direction="down")
        env, flight = sg.descent_geometry(p["steps"], p["rise"], p["run"], p["width"],
                                          sides=p["sides"], rail=p["rail"],
                                          nosing=p.get("nosing", 0.0),
                                          nosing_deg=p.get("nosing_deg", 45.0), object_index=1)
        yaw = az + float(rng.uniform(-30, 30))
        lay.env.append(sg.place(env, yaw, anchor[:2]))
        info = {"class": "stairs", "kind": "stairs down", "params": p}
        fp = _place_fp(_footprint(flight), yaw, anchor)
        lay.add(sg.place(flight, yaw, anchor[:2]), info, fp)
        a = math.radians(yaw)
        lay.keep_side = (anchor[:2].copy(), np.array([math.cos(a), math.sin(a)]))
        lay.drop = p["steps"] * p["rise"]
        return True
    if kind == "stairs":
        geom, info = _draw_stairs_up(rng, r, 1)
        if r.side_view:  # across the view, as a roll ramp (the side-view part, ramp77)
            yaw = az + (90.0 if rng.random() < 0.5 else -90.0) + float(rng.uniform(-25, 25))
        else:
            yaw = az + float(rng.uniform(-35, 35))
    else:
        geom, info = _draw_ramp(rng, r, 1)
        if info["params"]["axis"] == "pitch":
            yaw = az + float(rng.uniform(-35, 35))
        else:
            yaw = az + (90.0 if rng.random() < 0.5 else -90.0) + float(rng.uniform(-25, 25))
    fp_local = _footprint(geom)
    # the low end (local -x) at the anchor for stairs and pitch ramps; roll ramps centred
    front = 0.0 if kind == "ramp" and info["params"]["axis"] == "roll" else -fp_local[0, 0]
    a = math.radians(yaw)
    return _put(lay, geom, info, yaw, anchor[:2] + front * np.array([math.cos(a), math.sin(a)]))


def _place_extra(rng, r: WorldRange, pose, intr, lay: _Layout, index: int) -> None:
    u = rng.random()
    if u < 0.25:
        geom, info = _draw_box(rng, r, index)
    elif u < 0.32:
        geom, info = _draw_ramp(rng, r, index)
    elif u < 0.38:
        geom, info = _draw_stairs_up(rng, r, index)
    else:
        if r.panel_share > 0 and rng.random() < r.panel_share:
            kind = _PANEL_KINDS[int(rng.integers(len(_PANEL_KINDS)))]
        elif r.plate_share > 0 and rng.random() < r.plate_share:
            kind = "plate"
        else:
            kind = CLUTTER[int(rng.integers(len(CLUTTER)))]
        geom, info = _draw_clutter(rng, kind, index)
        geom = _tipped(rng, geom, info["params"], r.clutter_tilt_deg, r.level_share)
    fp_local = _footprint(geom)
    for _ in range(10):
        p = _floor_point(rng, pose, intr, 0.6, 4.2, region=(0.0, 1.0, 0.2, 1.0))
        yaw = float(rng.uniform(-180, 180))
        if p is None:
            continue
        if info["kind"] == "shelf":
            # shelves stand with their open side to the room (the camera), +-60 degrees: from
            # behind, a shelf is a closed box (back panel, sides, top board)
            yaw = math.degrees(math.atan2(-p[1], -p[0])) + yaw / 3.0
        fp = _place_fp(fp_local, yaw, p)
        if lay.free(fp) and not _overlap(fp, _CAMERA_SPOT, 0.0):
            lay.add(sg.place(geom, yaw, p[:2]), info, fp)
            return
    # no free spot: the object is left out (the draws above keep the scene deterministic)


def _walls(rng, lay: _Layout) -> list:
    """0-2 walls behind and beside the objects; the back wall touches the farthest object a
    quarter of the time."""
    n = int(rng.integers(0, 3))
    gap = 0.0 if rng.random() < 0.25 else float(rng.uniform(0.2, 1.5))
    side_gap = 0.0 if rng.random() < 0.25 else float(rng.uniform(0.2, 1.5))
    turn = float(rng.uniform(-20, 20))
    side = 1.0 if rng.random() < 0.5 else -1.0
    height = float(rng.uniform(2.0, 2.8))
    if n == 0 or not lay.footprints:
        return []
    pts = np.concatenate([fp for _, fp in lay.footprints])
    az = math.degrees(math.atan2(pts[:, 1].mean(), pts[:, 0].mean())) + turn
    bd = np.array([math.cos(math.radians(az)), math.sin(math.radians(az))])
    sd = side * np.array([-bd[1], bd[0]])
    z0 = -getattr(lay, "drop", 0.0)
    back = float(np.max(pts @ bd)) + gap
    out = [_wall(bd * back, az + 90.0, 14.0, z0, height)]
    if n == 2:
        reach = float(np.max(pts @ sd)) + side_gap
        out.append(_wall(sd * reach + bd * (back - 5.0), az, 10.0, z0, height))
    return out


def _wall(centre, direction_deg, length, z0, height):
    a = math.radians(direction_deg)
    dx, dy = math.cos(a) * length / 2, math.sin(a) * length / 2
    cx, cy = float(centre[0]), float(centre[1])
    b = sg._Builder(0)
    b.add("wall", [(cx - dx, cy - dy, z0), (cx + dx, cy + dy, z0), (cx + dx, cy + dy, height),
                   (cx - dx, cy - dy, height)])
    return b.build()


def _with_index(geom, index: int):
    """A copy of ``geom`` whose planes all belong to object ``index``."""
    planes = tuple(sg.PlaneSpec(p.role, index) for p in geom.planes)
    return sg.Geometry(geom.polygons, planes)


def _add_objects(parts: list, infos: list, lay, scene_id: str) -> None:
    """Append the layout's objects (index 1, 2, ...) to the world ``parts`` and their records
    to ``infos`` (index 0, the environment, is already there)."""
    for k, (geom, info) in enumerate(lay.objects, start=1):
        parts.append(_with_index(geom, k))
        infos.append({"index": k, "id": f"{scene_id}_o{k}", "class": info["class"],
                      "kind": info["kind"], "params": info["params"]})


def _render_seen(world, pose, intr: Intrinsics, sensor, rng, infos: list, params: dict, *,
                 scene_id: str, klass: str, seed: int, depth_true, poly_index, seen,
                 min_object_fraction: float):
    """Render a drawn room through ``sensor`` with each object's unoccluded pixel count
    (``n_pixels_full``), or None when the sensor model (projector shadows, flying pixels of
    nearer clutter) leaves the primary object on less than half the required share of the
    image: the caller then draws the scene again."""
    from planerel.synth.generator import _jsonable_params, render_scene

    full_px = _pixels_alone(world, pose, intr, sensor, len(infos))
    infos = [{**i, "n_pixels_full": int(full_px[i["index"]])} if i["index"] >= 1 else i
             for i in infos]
    scene = render_scene(world, pose, intr, sensor, rng, scene_id=scene_id, klass=klass,
                         seed=seed, params=_jsonable_params(params), depth_true=depth_true,
                         poly_index=poly_index,
                         object_list=tuple(_jsonable_params(i) for i in infos),
                         world_name="varied")
    if scene.objects[1]["n_pixels"] >= 0.5 * min_object_fraction * seen.size:
        return scene
    return None


def render_box_scene(world, pose, intr: Intrinsics, sensor, rng, infos: list, params: dict, *,
                     scene_id: str, seed: int, min_object_fraction: float):
    """Ray-cast a drawn box scene (its primary object, object 1, a box) and render it through
    ``sensor`` (:func:`_render_seen`), or None when the primary object covers less than
    ``min_object_fraction`` of the image within the sensor's range, or the sensor model leaves
    it less than half of that: the caller then draws the scene again (the round, flat, product
    and pile parts of the training world)."""
    from planerel.synth.generator import cast_world, primary_seen

    depth_true, poly_index, _plane, obj = cast_world(world, pose, intr)
    seen = primary_seen(obj, depth_true, sensor)
    if seen.mean() < min_object_fraction:
        return None
    return _render_seen(world, pose, intr, sensor, rng, infos, params, scene_id=scene_id,
                        klass="box", seed=seed, depth_true=depth_true, poly_index=poly_index,
                        seen=seen, min_object_fraction=min_object_fraction)


def _characteristic(world, plane: np.ndarray, seen: np.ndarray, side_view: bool = False) -> bool:
    """The primary object shows what makes its class: two steps (treads or risers) of a
    staircase, the slope of a ramp, or with ``side_view`` those or a side face (each on at
    least 0.5 % of the image)."""
    counts = np.bincount(plane[seen], minlength=len(world.planes))
    least = 0.005 * plane.size
    roles = [sp.role for sp in world.planes]
    steps = sum(1 for k, r in enumerate(roles) if r in ("tread", "riser")
                and world.planes[k].object_index == 1 and counts[k] >= least)
    shown = ("slope", "side") if side_view else ("slope",)
    slope = any(r in shown and world.planes[k].object_index == 1 and counts[k] >= least
                for k, r in enumerate(roles))
    kinds = {r for k, r in enumerate(roles) if world.planes[k].object_index == 1}
    if "tread" in kinds:
        return steps >= 2 or (side_view and any(
            r == "side" and world.planes[k].object_index == 1 and counts[k] >= least
            for k, r in enumerate(roles)))
    if "slope" in kinds:
        return slope
    return True


def _pixels_alone(world, pose, intr: Intrinsics, sensor, n_objects: int) -> np.ndarray:
    """Pixels each object would cover alone, with nothing in front of it and an image three
    times as wide and high (the same camera): what it shows when neither occluded nor cut by
    the image border, in range and not at grazing incidence. ``(n_objects,)``; index 0 (the
    environment) is 0."""
    from planerel.synth.generator import camera_planes, cos_incidence, raycast

    rot, t = pose[:3, :3], pose[:3, 3]
    big = Intrinsics(3 * intr.width, 3 * intr.height, intr.fx, intr.fy,
                     intr.cx + intr.width, intr.cy + intr.height)
    normals_c = camera_planes(world, pose)[0]
    out = np.zeros(n_objects, dtype=np.int64)
    for k in range(1, n_objects):
        polys = [p for p in world.polygons if world.planes[p.plane].object_index == k]
        if not polys:
            continue
        depth, idx = raycast([p.vertices @ rot.T + t for p in polys], big)
        hit = idx >= 0
        plane = np.where(hit, np.array([p.plane for p in polys])[np.maximum(idx, 0)], 0)
        ok = hit & (depth >= sensor.min_range) & (depth <= sensor.max_range)
        if sensor.grazing_deg is not None:
            ok &= cos_incidence(normals_c, plane, big) >= math.cos(math.radians(sensor.grazing_deg))
        out[k] = int(ok.sum())
    return out


# ----------------------------------------------------------------------- the scene


def generate_world_scene(kind: str, seed: int = 0, size=(640, 480), subsample: int = 4, *,
                         scene_id: str = "s0000", sensor=None, ranges: WorldRange | None = None,
                         min_object_fraction: float = 0.03):
    """One scene of the varied world with ``kind`` (box, stairs, ramp) as its primary object.

    The scene is drawn again until the primary object is seen on ``min_object_fraction`` of
    the image (in range, not at grazing incidence) and shows two steps (stairs) or its slope
    (ramps), each on 0.5 % of the image, and until the sensor model keeps half of that share.

    Parameters
    ----------
    kind : {"box", "stairs", "ramp"}
    seed : int
    size, subsample
        As for :func:`planerel.synth.generator.generate_scene`.
    sensor : optional
        Default :class:`planerel.synth.sensor.StructuredLight`.
    ranges : WorldRange, optional
    min_object_fraction : float
        The scene is drawn again until the primary object covers this fraction of the image
        with valid depth.

    Returns
    -------
    planerel.synth.generator.Scene
        ``objects`` lists every object with its class (``other`` for clutter), kind, drawn
        parameters, pixel count ``n_pixels`` and ``n_pixels_full`` (pixels it would cover
        alone in an unbounded view); ``gt_objects`` is the per-pixel object index.
    """
    from planerel.synth.generator import (
        _check_sensor,
        _scene_setup,
        camera_planes,
        cast_world,
        cos_incidence,
        primary_seen,
    )
    from planerel.synth.sensor import StructuredLight

    seed, w, h, intr = _scene_setup(kind, seed, size, subsample)
    sensor = StructuredLight() if sensor is None else sensor
    _check_sensor(sensor)
    ranges = WorldRange() if ranges is None else ranges
    if not isinstance(ranges, WorldRange):
        raise InputError(f"ranges must be a WorldRange, got {type(ranges).__name__}")
    rng = np.random.default_rng(seed)
    for _attempt in range(300):
        cam_h = float(rng.uniform(*ranges.camera_height))
        pitch = float(rng.uniform(*ranges.camera_pitch_deg))
        roll = float(rng.uniform(-ranges.camera_roll_deg, ranges.camera_roll_deg))
        pose = _camera_pose(cam_h, pitch, roll)
        lay = _Layout()
        if not _place_primary(kind, rng, ranges, pose, intr, lay):
            continue
        n_extra = int(rng.integers(ranges.extra_objects[0], ranges.extra_objects[1] + 1))
        for _ in range(n_extra):
            _place_extra(rng, ranges, pose, intr, lay, 0)
        walls = _walls(rng, lay)
        env = lay.env if lay.env else [sg.floor_geometry(10.0)]
        parts, infos = list(env) + walls, [{"index": 0, "id": f"{scene_id}_o0",
                                            "class": "environment", "kind": "floor and walls"}]
        _add_objects(parts, infos, lay, scene_id)
        world = sg.combine(*parts)
        depth_true, poly_index, plane, obj = cast_world(world, pose, intr)
        seen = primary_seen(obj, depth_true, sensor)
        if sensor.grazing_deg is not None:
            cos = cos_incidence(camera_planes(world, pose)[0], plane, intr)
            seen &= cos >= math.cos(math.radians(sensor.grazing_deg))
        if not (seen.mean() >= min_object_fraction and _characteristic(world, plane, seen,
                                                                      ranges.side_view)):
            continue
        params = {
            "world": "varied",
            "camera": {"height": cam_h, "pitch_deg": pitch, "roll_deg": roll},
            "walls": len(walls),
            "size": [w, h], "subsample": int(subsample),
        }
        scene = _render_seen(world, pose, intr, sensor, rng, infos, params, scene_id=scene_id,
                             klass=kind, seed=seed, depth_true=depth_true,
                             poly_index=poly_index, seen=seen,
                             min_object_fraction=min_object_fraction)
        if scene is not None:
            return scene
    raise InputError(f"could not make a varied {kind} scene in which the {kind} is seen "
                     f"(seed {seed}); widen the world ranges")
