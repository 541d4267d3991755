"""Exact analytic geometry of the synthetic scenes: convex planar polygons in world coordinates.

World frame: metres, ``z`` up, the floor is the plane ``z = 0``.  Objects are built in a local
frame (``x`` forward = the direction stairs climb and pitch ramps rise, ``y`` to the left, ``z``
up, origin at the centre of the object's footprint) and placed with a yaw about ``z``.

Every surface is a list of :class:`Polygon` (convex, planar, vertices in order); a non-convex
face (the side profile of a staircase) is split into convex pieces that share one plane index.
Planes are described by :class:`PlaneSpec` (role, object).  This module draws no random
numbers: the generator in :mod:`planerel.synth.generator` chooses the dimensions and calls the builders.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planerel.errors import InputError

__all__ = [
    "Polygon",
    "PlaneSpec",
    "Geometry",
    "ROLES",
    "box_geometry",
    "stairs_geometry",
    "ramp_geometry",
    "floor_geometry",
    "wall_geometry",
    "place",
    "combine",
    "drop_planes",
    "cuboid_geometry",
    "table_geometry",
    "chair_geometry",
    "cylinder_geometry",
    "laptop_geometry",
    "plate_geometry",
    "shelf_geometry",
    "door_geometry",
    "descent_geometry",
]

#: Every plane role the builders use.
ROLES = ("floor", "wall", "top", "face", "tread", "riser", "side", "back", "slope",
         "ledge", "bottom", "leg", "seat", "lid", "base", "shelf", "door", "curved", "plate",
         "nosing")


@dataclass(frozen=True, eq=False)
class Polygon:
    """A convex planar polygon.

    Parameters
    ----------
    vertices : ndarray, shape (K, 3), float64
        Corners in order (either winding), ``K >= 3``.
    plane : int
        Index of the plane (in the owning :class:`Geometry`) the polygon lies on.
    """

    vertices: np.ndarray
    plane: int

    def __post_init__(self) -> None:
        v = np.array(self.vertices, dtype=np.float64)
        if v.ndim != 2 or v.shape[1] != 3 or v.shape[0] < 3:
            raise InputError(f"a polygon needs (K >= 3, 3) vertices, got shape {v.shape}")
        v.setflags(write=False)
        object.__setattr__(self, "vertices", v)

    def normal(self) -> np.ndarray:
        """Unit normal by Newell's method, ``(3,)`` (direction follows the winding)."""
        v = self.vertices
        w = np.roll(v, -1, axis=0)
        n = np.array([
            np.sum((v[:, 1] - w[:, 1]) * (v[:, 2] + w[:, 2])),
            np.sum((v[:, 2] - w[:, 2]) * (v[:, 0] + w[:, 0])),
            np.sum((v[:, 0] - w[:, 0]) * (v[:, 1] + w[:, 1])),
        ])
        length = float(np.linalg.norm(n))
        if length < 1e-12:
            raise InputError("degenerate polygon (zero area)")
        return n / length


@dataclass(frozen=True)
class PlaneSpec:
    """What a plane is: its role (one of :data:`ROLES`) and the object it belongs to
    (0 = the environment: floor and walls; 1 = the object of the scene)."""

    role: str
    object_index: int

    def __post_init__(self) -> None:
        if self.role not in ROLES:
            raise InputError(f"unknown plane role {self.role!r}; known: {', '.join(ROLES)}")
        if self.object_index < 0:
            raise InputError(f"object index must be >= 0, got {self.object_index}")


@dataclass(frozen=True, eq=False)
class Geometry:
    """Polygons plus the planes they lie on.

    Parameters
    ----------
    polygons : tuple of Polygon
        ``polygon.plane`` indexes ``planes``.
    planes : tuple of PlaneSpec
    """

    polygons: tuple
    planes: tuple

    def __post_init__(self) -> None:
        object.__setattr__(self, "polygons", tuple(self.polygons))
        object.__setattr__(self, "planes", tuple(self.planes))
        for p in self.polygons:
            if not 0 <= p.plane < len(self.planes):
                raise InputError(f"polygon plane index {p.plane} outside 0..{len(self.planes) - 1}")

    def vertices(self, object_index: int | None = None) -> np.ndarray:
        """All polygon corners, ``(N, 3)``; only those of one object when given."""
        rows = [p.vertices for p in self.polygons
                if object_index is None or self.planes[p.plane].object_index == object_index]
        return np.concatenate(rows, axis=0) if rows else np.zeros((0, 3))


class _Builder:
    """Collects polygons and planes; ``add`` puts several convex pieces on one new plane."""

    def __init__(self, object_index: int) -> None:
        self.object_index = object_index
        self.polygons: list[Polygon] = []
        self.planes: list[PlaneSpec] = []

    def add(self, role: str, *pieces) -> None:
        index = len(self.planes)
        self.planes.append(PlaneSpec(role, self.object_index))
        for piece in pieces:
            self.polygons.append(Polygon(np.asarray(piece, dtype=float), index))

    def build(self) -> Geometry:
        return Geometry(tuple(self.polygons), tuple(self.planes))


def _rect_x(x, y0, y1, z0, z1):
    """Rectangle in the plane ``X = x``."""
    return [(x, y0, z0), (x, y1, z0), (x, y1, z1), (x, y0, z1)]


def _rect_y(y, x0, x1, z0, z1):
    """Rectangle in the plane ``Y = y``."""
    return [(x0, y, z0), (x1, y, z0), (x1, y, z1), (x0, y, z1)]


def _rect_z(z, x0, x1, y0, y1):
    """Rectangle in the plane ``Z = z``."""
    return [(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)]


def _float(name: str, value) -> float:
    if isinstance(value, bool):
        raise InputError(f"{name} must be a number, got {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None


def _positive(name: str, value: float) -> float:
    value = _float(name, value)
    if not math.isfinite(value) or value <= 0:
        raise InputError(f"{name} must be a positive number of metres, got {value!r}")
    return value


def box_geometry(length: float, width: float, height: float, object_index: int = 1, *,
                 top: bool = True) -> Geometry:
    """A cuboid standing on the floor, centred on the local origin.

    Planes: ``top`` and four vertical ``face`` planes (the bottom touches the floor and is
    never seen).  An open box has no top but its ``bottom`` inside, 1 cm above the floor (a
    tenth of the height for lower boxes), as a carton's.

    Parameters
    ----------
    length, width, height : float
        Extent along local x, y, z in metres.
    top : bool
        False: an open box (no lid); its faces and its bottom are then seen from inside.
    """
    lx, wy, h = (_positive(n, v) for n, v in (("box length", length), ("box width", width),
                                              ("box height", height)))
    x0, x1, y0, y1 = -lx / 2, lx / 2, -wy / 2, wy / 2
    b = _Builder(object_index)
    if top:
        b.add("top", _rect_z(h, x0, x1, y0, y1))
    else:
        b.add("bottom", _rect_z(min(0.01, h / 10), x0, x1, y0, y1))
    b.add("face", _rect_x(x0, y0, y1, 0, h))
    b.add("face", _rect_x(x1, y0, y1, 0, h))
    b.add("face", _rect_y(y0, x0, x1, 0, h))
    b.add("face", _rect_y(y1, x0, x1, 0, h))
    return b.build()


def stairs_geometry(steps: int, rise: float, tread: float, width: float, *,
                    top_depth: float | None = None, sides: str = "open",
                    rail: float = 0.3, nosing: float = 0.0, nosing_deg: float = 45.0,
                    open_risers: bool = False, thickness: float = 0.04,
                    object_index: int = 1) -> Geometry:
    """A solid flight of stairs climbing along local +x, centred on the local origin.

    Planes (in this order): for each step ``i`` a vertical ``riser``, with ``nosing`` a
    chamfered ``nosing`` strip, then a horizontal ``tread`` at height ``(i + 1) * rise``; the
    vertical ``back`` face; two ``side`` planes.

    With ``open_risers`` an open-riser flight instead (floating treads, nothing between them,
    nothing under the flight): for each step ``i`` a slab ``thickness`` m thick, its top the
    ``tread`` at height ``(i + 1) * rise`` from ``x_i`` to ``x_{i+1}``, its front edge (role
    ``nosing``: a vertical strip ``thickness`` high) and its underside (role ``bottom``);
    ``sides="open"``: each slab's two end faces (``side``); ``"closed"``: two stringers
    (``side``), boards along the flight from the floor at the first step to the top, ``rail``
    metres above the nosings and one rise below them.  No ``back``, no ``nosing`` chamfer.

    Parameters
    ----------
    steps : int
        Number of steps (risers), >= 1.
    rise, tread, width : float
        Step height, step depth and flight width in metres.
    top_depth : float, optional
        Depth of the top tread (a landing); default ``tread``.
    sides : {"open", "closed"}
        ``open``: the staircase profile of the solid flight is seen from the side (split into
        one rectangle per step, all on one plane).  ``closed``: side walls (stringers) follow the
        slope ``rail`` metres above the step nosings and hide the profile.
    rail : float
        Height of closed side walls above the nosings.
    nosing : float
        Width (m, across the edge, along its surface) of a chamfer where each riser meets its
        tread; 0: a sharp edge.  Real treads end in a rounded or chamfered nosing that a
        range sensor segments as a narrow inclined strip (a real stone flight's: 1.2 cm at 21
        degrees, docs/results.md "The proof gate").
    nosing_deg : float
        The chamfer's incline from the horizontal, degrees (0..90, exclusive).
    open_risers : bool
        An open-riser flight (above; riser26).
    thickness : float
        With ``open_risers``: the treads' thickness, metres, less than ``rise``.
    """
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
        raise InputError(f"stairs need a whole number of steps >= 1, got {steps!r}")
    rise = _positive("stairs rise", rise)
    tread = _positive("stairs tread", tread)
    width = _positive("stairs width", width)
    top = tread if top_depth is None else _positive("stairs top depth", top_depth)
    if sides not in ("open", "closed"):
        raise InputError(f"stairs sides must be 'open' or 'closed', got {sides!r}")
    nosing, nosing_deg = _float("stairs nosing", nosing), _float("stairs nosing angle", nosing_deg)
    if not (math.isfinite(nosing_deg) and 0 < nosing_deg < 90):
        raise InputError(f"stairs nosing angle must lie strictly between 0 and 90 degrees, "
                         f"got {nosing_deg!r}")
    # the chamfer's run along the tread and drop down the riser
    run_n = nosing * math.cos(math.radians(nosing_deg))
    drop_n = nosing * math.sin(math.radians(nosing_deg))
    if not math.isfinite(nosing) or nosing < 0 or drop_n >= rise or run_n >= min(tread, top):
        raise InputError(f"stairs nosing must be >= 0 metres and smaller than a step, got "
                         f"{nosing!r}")
    if open_risers:
        return _open_flight(steps, rise, tread, width, top, sides, rail, thickness, object_index)
    xs = [i * tread for i in range(steps)] + [(steps - 1) * tread + top]
    length = xs[-1]
    shift = -length / 2
    xs = [x + shift for x in xs]
    y0, y1 = -width / 2, width / 2
    b = _Builder(object_index)
    for i in range(steps):
        z = (i + 1) * rise
        b.add("riser", _rect_x(xs[i], y0, y1, i * rise, z - drop_n))
        if nosing > 0:
            b.add("nosing", [(xs[i], y0, z - drop_n), (xs[i], y1, z - drop_n),
                             (xs[i] + run_n, y1, z), (xs[i] + run_n, y0, z)])
        b.add("tread", _rect_z(z, xs[i] + run_n, xs[i + 1], y0, y1))
    total = steps * rise
    b.add("back", _rect_x(xs[-1], y0, y1, 0, total))
    for y in (y0, y1):
        if sides == "open" and nosing > 0:   # each step's profile with its corner cut
            pieces = [[(xs[i], y, 0), (xs[i + 1], y, 0), (xs[i + 1], y, (i + 1) * rise),
                       (xs[i] + run_n, y, (i + 1) * rise), (xs[i], y, (i + 1) * rise - drop_n)]
                      for i in range(steps)]
        elif sides == "open":
            pieces = [_rect_y(y, xs[i], xs[i + 1], 0, (i + 1) * rise) for i in range(steps)]
        else:
            rail = _positive("stairs rail height", rail)
            # stringer: from the first nosing to the top, `rail` above the line of nosings
            slope = rise / tread
            z_end = rise + slope * (xs[-1] - xs[0]) + rail
            z_end = min(z_end, total + rail)
            pieces = [[(xs[0], y, 0), (xs[-1], y, 0), (xs[-1], y, z_end), (xs[0], y, rise + rail)]]
        b.add("side", *pieces)
    return b.build()


def _open_flight(steps: int, rise: float, tread: float, width: float, top: float, sides: str,
                 rail: float, thickness, object_index: int) -> Geometry:
    """The open-riser flight of :func:`stairs_geometry` (its arguments checked there but
    ``thickness``)."""
    t = _positive("stairs tread thickness", thickness)
    if t >= rise:
        raise InputError(f"stairs tread thickness must be smaller than the rise {rise!r}, got {thickness!r}")
    xs = [i * tread for i in range(steps)] + [(steps - 1) * tread + top]
    shift = -xs[-1] / 2
    xs = [x + shift for x in xs]
    y0, y1 = -width / 2, width / 2
    b = _Builder(object_index)
    for i in range(steps):
        z = (i + 1) * rise
        b.add("tread", _rect_z(z, xs[i], xs[i + 1], y0, y1))
        b.add("nosing", _rect_x(xs[i], y0, y1, z - t, z))
        b.add("bottom", _rect_z(z - t, xs[i], xs[i + 1], y0, y1))
    total = steps * rise
    for y in (y0, y1):
        if sides == "open":   # the slabs' end faces
            b.add("side", *[_rect_y(y, xs[i], xs[i + 1], (i + 1) * rise - t, (i + 1) * rise)
                            for i in range(steps)])
        else:
            rail = _positive("stairs rail height", rail)
            # a stringer: from the floor under the first nosing to the top, its upper edge
            # `rail` above the line of nosings, its lower edge one rise below it
            slope = rise / tread
            z_top = min(rise + slope * (xs[-1] - xs[0]), total)
            b.add("side", [(xs[0], y, 0.0), (xs[-1], y, z_top - rise), (xs[-1], y, z_top + rail),
                           (xs[0], y, rise + rail)])
    return b.build()


def ramp_geometry(angle_deg: float, run: float, width: float, *, platform: float = 0.0,
                  side_faces: bool = True, object_index: int = 1) -> Geometry:
    """A ramp rising along local +x at ``angle_deg`` from the floor, centred on the origin.

    Planes (in this order): the inclined ``slope``; the horizontal ``top`` platform (when
    ``platform > 0``); the vertical ``back`` face at the high end; two ``side`` faces (when
    ``side_faces``; without them the slope is a plate and the floor shows beneath it).

    Parameters
    ----------
    angle_deg : float
        Incline in degrees, in (0, 90).
    run : float
        Horizontal length of the slope in metres.
    width : float
        Width across the slope in metres.
    platform : float
        Depth of the horizontal top platform (0 = none).
    """
    angle = _float("ramp angle", angle_deg)
    if not math.isfinite(angle) or not 0 < angle < 90:
        raise InputError(f"ramp angle must lie strictly between 0 and 90 degrees, got {angle_deg!r}")
    run = _positive("ramp run", run)
    width = _positive("ramp width", width)
    platform = _float("ramp platform depth", platform)
    if not math.isfinite(platform) or platform < 0:
        raise InputError(f"ramp platform depth must be >= 0 metres, got {platform!r}")
    h = run * math.tan(math.radians(angle))
    length = run + platform
    x0, x1, x2 = -length / 2, -length / 2 + run, length / 2
    y0, y1 = -width / 2, width / 2
    b = _Builder(object_index)
    b.add("slope", [(x0, y0, 0), (x1, y0, h), (x1, y1, h), (x0, y1, 0)])
    if platform > 0:
        b.add("top", _rect_z(h, x1, x2, y0, y1))
    b.add("back", _rect_x(x2, y0, y1, 0, h))
    if side_faces:
        for y in (y0, y1):
            if platform > 0:
                b.add("side", [(x0, y, 0), (x2, y, 0), (x2, y, h), (x1, y, h)])
            else:
                b.add("side", [(x0, y, 0), (x1, y, 0), (x1, y, h)])
    return b.build()


def floor_geometry(half_size: float = 8.0, object_index: int = 0) -> Geometry:
    """The floor: a square of side ``2 * half_size`` in the plane ``z = 0`` centred on the origin."""
    s = _positive("floor half size", half_size)
    b = _Builder(object_index)
    b.add("floor", _rect_z(0.0, -s, s, -s, s))
    return b.build()


def wall_geometry(centre, direction_deg: float, length: float, height: float,
                  object_index: int = 0) -> Geometry:
    """A vertical wall rectangle standing on the floor.

    Parameters
    ----------
    centre : 2-sequence
        World ``(x, y)`` of the middle of the wall's foot.
    direction_deg : float
        Direction of the wall's long side in the floor plane, degrees from world +x.
    length, height : float
    """
    cx, cy = (_float("wall centre", c) for c in centre)
    length = _positive("wall length", length)
    height = _positive("wall height", height)
    a = math.radians(_float("wall direction", direction_deg))
    dx, dy = math.cos(a) * length / 2, math.sin(a) * length / 2
    b = _Builder(object_index)
    b.add("wall", [(cx - dx, cy - dy, 0), (cx + dx, cy + dy, 0),
                   (cx + dx, cy + dy, height), (cx - dx, cy - dy, height)])
    return b.build()


def place(geometry: Geometry, yaw_deg: float, position=(0.0, 0.0), z: float = 0.0) -> Geometry:
    """Rotate ``geometry`` by ``yaw_deg`` about world z, then move it by ``(x, y)`` and up by
    ``z``."""
    a = math.radians(_float("yaw", yaw_deg))
    rot = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1.0]])
    t = np.array([float(position[0]), float(position[1]), float(z)])
    polys = tuple(Polygon(p.vertices @ rot.T + t, p.plane) for p in geometry.polygons)
    return Geometry(polys, geometry.planes)


def tilt(geometry: Geometry, tilt_deg: float, azimuth_deg: float) -> Geometry:
    """Tip ``geometry`` by ``tilt_deg`` about the horizontal axis through the local origin at
    ``azimuth_deg`` from x, then lift it so that its lowest corner is where it was: an object
    resting on one edge, its top no longer level (a carton's bulging lid, a box on an uneven
    floor)."""
    a, t = math.radians(_float("azimuth", azimuth_deg)), math.radians(_float("tilt", tilt_deg))
    ux, uy = math.cos(a), math.sin(a)
    c, s = math.cos(t), math.sin(t)
    # Rodrigues' rotation about the unit axis (ux, uy, 0)
    rot = np.array([[c + ux * ux * (1 - c), ux * uy * (1 - c), uy * s],
                    [ux * uy * (1 - c), c + uy * uy * (1 - c), -ux * s],
                    [-uy * s, ux * s, c]])
    low = min(float(p.vertices[:, 2].min()) for p in geometry.polygons)
    polys = [p.vertices @ rot.T for p in geometry.polygons]
    lift = low - min(float(v[:, 2].min()) for v in polys)
    return Geometry(tuple(Polygon(v + [0.0, 0.0, lift], p.plane)
                          for v, p in zip(polys, geometry.polygons, strict=True)),
                    geometry.planes)


def combine(*parts: Geometry) -> Geometry:
    """One geometry from several; plane indices are renumbered in order of the parts."""
    polys, planes = [], []
    for g in parts:
        base = len(planes)
        planes.extend(g.planes)
        polys.extend(Polygon(p.vertices, p.plane + base) for p in g.polygons)
    return Geometry(tuple(polys), tuple(planes))


def drop_planes(geometry: Geometry, roles_or_indices) -> Geometry:
    """The geometry without the planes whose index (int) or role (str) is listed; the other
    planes are renumbered in order."""
    drop = set(roles_or_indices)
    keep = [k for k, spec in enumerate(geometry.planes) if k not in drop and spec.role not in drop]
    new_index = {k: i for i, k in enumerate(keep)}
    polys = tuple(Polygon(p.vertices, new_index[p.plane]) for p in geometry.polygons
                  if p.plane in new_index)
    return Geometry(polys, tuple(geometry.planes[k] for k in keep))


# ----------------------------------------------------------------------- clutter ("other")


def _cuboid(b: _Builder, x0, x1, y0, y1, z0, z1, *, top="top", side="face",
            bottom=None) -> None:
    """Add the faces of an axis-aligned cuboid (roles None = face left out)."""
    if top:
        b.add(top, _rect_z(z1, x0, x1, y0, y1))
    if bottom:
        b.add(bottom, _rect_z(z0, x0, x1, y0, y1))
    if side:
        b.add(side, _rect_x(x0, y0, y1, z0, z1))
        b.add(side, _rect_x(x1, y0, y1, z0, z1))
        b.add(side, _rect_y(y0, x0, x1, z0, z1))
        b.add(side, _rect_y(y1, x0, x1, z0, z1))


def cuboid_geometry(length: float, width: float, height: float, z0: float = 0.0, *,
                    top: str | None = "top", side: str | None = "face", bottom: str | None = None,
                    object_index: int = 1) -> Geometry:
    """A cuboid from ``z0`` to ``z0 + height`` centred on the local z axis (roles per face
    kind; None leaves the faces out)."""
    lx, wy, h = (_positive(n, v) for n, v in (("length", length), ("width", width),
                                              ("height", height)))
    b = _Builder(object_index)
    _cuboid(b, -lx / 2, lx / 2, -wy / 2, wy / 2, z0, z0 + h, top=top, side=side, bottom=bottom)
    return b.build()


def table_geometry(length: float, width: float, height: float, *, thickness: float = 0.04,
                   leg: float = 0.05, object_index: int = 1) -> Geometry:
    """A table: a top slab (``top``, edge ``face`` planes, ``bottom`` underside) on four square
    ``leg`` posts inset 3 cm from the corners."""
    lx, wy, h = (_positive(n, v) for n, v in (("table length", length), ("table width", width),
                                              ("table height", height)))
    b = _Builder(object_index)
    _cuboid(b, -lx / 2, lx / 2, -wy / 2, wy / 2, h - thickness, h, bottom="bottom")
    for sx in (-1, 1):
        for sy in (-1, 1):
            cx, cy = sx * (lx / 2 - 0.03 - leg / 2), sy * (wy / 2 - 0.03 - leg / 2)
            _cuboid(b, cx - leg / 2, cx + leg / 2, cy - leg / 2, cy + leg / 2, 0, h - thickness,
                    top=None, side="leg")
    return b.build()


def chair_geometry(seat: float = 0.42, seat_height: float = 0.45, back_height: float = 0.45, *,
                   thickness: float = 0.04, leg: float = 0.035, object_index: int = 1) -> Geometry:
    """A chair: square ``seat`` slab on four legs, a vertical ``back`` rest at local -x."""
    s, h, bh = (_positive(n, v) for n, v in (("chair seat", seat), ("chair seat height", seat_height),
                                             ("chair back height", back_height)))
    b = _Builder(object_index)
    _cuboid(b, -s / 2, s / 2, -s / 2, s / 2, h - thickness, h, top="seat", bottom="bottom")
    for sx in (-1, 1):
        for sy in (-1, 1):
            cx, cy = sx * (s / 2 - leg / 2), sy * (s / 2 - leg / 2)
            _cuboid(b, cx - leg / 2, cx + leg / 2, cy - leg / 2, cy + leg / 2, 0, h - thickness,
                    top=None, side="leg")
    _cuboid(b, -s / 2, -s / 2 + thickness, -s / 2, s / 2, h, h + bh, side="back")
    return b.build()


def cylinder_geometry(radius: float, height: float, *, facets: int = 16,
                      object_index: int = 1) -> Geometry:
    """An upright cylinder (bin, pillar) as a prism of ``facets`` vertical ``curved`` planes
    and a ``top`` disc."""
    r, h = _positive("cylinder radius", radius), _positive("cylinder height", height)
    ang = np.linspace(0.0, 2 * math.pi, facets, endpoint=False)
    pts = np.stack([r * np.cos(ang), r * np.sin(ang)], axis=1)
    b = _Builder(object_index)
    b.add("top", [(x, y, h) for x, y in pts])
    for i in range(facets):
        (xa, ya), (xb, yb) = pts[i], pts[(i + 1) % facets]
        b.add("curved", [(xa, ya, 0), (xb, yb, 0), (xb, yb, h), (xa, ya, h)])
    return b.build()


def laptop_geometry(width: float = 0.33, depth: float = 0.23, lid_deg: float = 110.0, *,
                    thickness: float = 0.02, object_index: int = 1) -> Geometry:
    """A laptop: a thin ``base`` slab and a ``lid`` plate hinged at its back edge (local -x),
    opened ``lid_deg`` degrees from the closed position (90 = upright)."""
    w, d = _positive("laptop width", width), _positive("laptop depth", depth)
    a = math.radians(_float("laptop lid angle", lid_deg))
    b = _Builder(object_index)
    _cuboid(b, -d / 2, d / 2, -w / 2, w / 2, 0, thickness, top="base")
    hx, hz = -d / 2, thickness
    ex, ez = hx + d * math.cos(a), hz + d * math.sin(a)
    b.add("lid", [(hx, -w / 2, hz), (hx, w / 2, hz), (ex, w / 2, ez), (ex, -w / 2, ez)])
    return b.build()


def plate_geometry(length: float, width: float, tilt_deg: float, *,
                   object_index: int = 1) -> Geometry:
    """A thin board leaning at ``tilt_deg`` from the floor, its low edge on the floor at local
    ``x = -length * cos(tilt) / 2`` (a small tilted plane: a ``plate``)."""
    length, w = _positive("plate length", length), _positive("plate width", width)
    t = math.radians(_float("plate tilt", tilt_deg))
    run, rise = length * math.cos(t), length * math.sin(t)
    b = _Builder(object_index)
    b.add("plate", [(-run / 2, -w / 2, 0), (-run / 2, w / 2, 0), (run / 2, w / 2, rise),
                    (run / 2, -w / 2, rise)])
    return b.build()


def sofa_geometry(width: float, depth: float, seat_height: float, back_height: float,
                  back_deg: float, seat_tilt_deg: float = 0.0, arm_height: float = 0.6, *,
                  arm: float = 0.15, object_index: int = 1) -> Geometry:
    """A sofa (or an armchair, when narrow): a ``face`` under the seat (local +x), the
    ``seat`` sloping ``seat_tilt_deg`` down towards the back, the ``back`` rest leaning
    ``back_deg`` from horizontal, two arms (``side`` faces outside and in, a front ``face``,
    a ``top``) and a vertical rear ``face``.  The back is a large inclined plane next to level
    and vertical ones: too steep to walk on, no ramp."""
    w, d, sh, bh = (_positive(n, v) for n, v in (("sofa width", width), ("sofa depth", depth),
                                                 ("sofa seat height", seat_height),
                                                 ("sofa back height", back_height)))
    ah, a = _positive("sofa arm height", arm_height), _positive("sofa arm", arm)
    bd = math.radians(_float("sofa back angle", back_deg))
    tilt = math.radians(_float("sofa seat tilt", seat_tilt_deg))
    if not (0 < bd < math.pi / 2) or not (0 <= tilt < math.radians(30)) or w <= 2 * a:
        raise InputError(f"sofa back angle must lie in (0, 90) degrees, its seat tilt in "
                         f"[0, 30) and its width above {2 * a} m, got {back_deg!r}, "
                         f"{seat_tilt_deg!r}, {width!r}")
    xb = -d / 2 + bh * math.cos(bd)  # where the back meets the seat
    if xb >= d / 2:
        raise InputError(f"sofa depth {depth!r} is too small for its back ({back_height!r} m "
                         f"at {back_deg!r} degrees)")
    zb = sh - (d / 2 - xb) * math.tan(tilt)
    zt = zb + bh * math.sin(bd)
    y0, y1 = -w / 2 + a, w / 2 - a
    b = _Builder(object_index)
    b.add("face", _rect_x(d / 2, y0, y1, 0, sh))
    b.add("seat", [(xb, y0, zb), (xb, y1, zb), (d / 2, y1, sh), (d / 2, y0, sh)])
    b.add("back", [(-d / 2, y0, zt), (-d / 2, y1, zt), (xb, y1, zb), (xb, y0, zb)])
    b.add("face", _rect_x(-d / 2, -w / 2, w / 2, 0, zt))
    for side in (-1, 1):
        yo, yi = side * w / 2, side * (w / 2 - a)
        b.add("side", _rect_y(yo, -d / 2, d / 2, 0, ah))
        b.add("side", _rect_y(yi, -d / 2, d / 2, sh, ah))
        b.add("side", _rect_x(d / 2, min(yo, yi), max(yo, yi), 0, ah))
        b.add("top", _rect_z(ah, -d / 2, d / 2, min(yo, yi), max(yo, yi)))
    return b.build()


def shelf_geometry(width: float, depth: float, height: float, boards: int, *,
                   object_index: int = 1) -> Geometry:
    """An open shelf: a ``back`` panel (local -x), two ``side`` panels and ``boards``
    horizontal ``shelf`` boards evenly spaced up to the top (thin plates)."""
    w, d, h = (_positive(n, v) for n, v in (("shelf width", width), ("shelf depth", depth),
                                            ("shelf height", height)))
    b = _Builder(object_index)
    b.add("back", _rect_x(-d / 2, -w / 2, w / 2, 0, h))
    for y in (-w / 2, w / 2):
        b.add("side", _rect_y(y, -d / 2, d / 2, 0, h))
    for k in range(1, int(boards) + 1):
        b.add("shelf", _rect_z(h * k / boards, -d / 2, d / 2, -w / 2, w / 2))
    return b.build()


def door_geometry(width: float = 0.85, height: float = 2.0, thickness: float = 0.04, *,
                  object_index: int = 1) -> Geometry:
    """A door leaf standing on the floor: two large ``door`` faces, narrow ``face`` edges and a
    ``top``."""
    w, h, t = (_positive(n, v) for n, v in (("door width", width), ("door height", height),
                                            ("door thickness", thickness)))
    b = _Builder(object_index)
    b.add("top", _rect_z(h, -t / 2, t / 2, -w / 2, w / 2))
    b.add("door", _rect_x(-t / 2, -w / 2, w / 2, 0, h))
    b.add("door", _rect_x(t / 2, -w / 2, w / 2, 0, h))
    b.add("face", _rect_y(-w / 2, -t / 2, t / 2, 0, h))
    b.add("face", _rect_y(w / 2, -t / 2, t / 2, 0, h))
    return b.build()


def descent_geometry(steps: int, rise: float, tread: float, width: float, *,
                     sides: str = "open", rail: float = 0.3, nosing: float = 0.0,
                     nosing_deg: float = 45.0, object_index: int = 1,
                     extent: float = 8.0) -> tuple:
    """A staircase going down from the floor the camera stands on.

    Local frame: the drop edge is the line ``x = 0``; the floor (``z = 0``) lies at ``x < 0``,
    the flight descends along +x to a lower floor at ``z = -steps * rise``.  Beside the flight
    the upper floor ends in a vertical ``ledge``.

    Returns
    -------
    environment : Geometry
        Upper ``floor``, ``ledge`` (both sides of the flight, one plane), lower ``floor``
        (object index 0).
    stairs : Geometry
        ``steps`` risers and ``steps - 1`` treads below floor level, then the ``side`` planes
        (the top step is the upper floor itself).  With ``nosing`` (:func:`stairs_geometry`)
        every step's edge is chamfered, the drop edge's too (the upper floor stops short of
        it across the flight).
    """
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 2:
        raise InputError(f"descending stairs need a whole number of steps >= 2, got {steps!r}")
    total = steps * rise
    up = stairs_geometry(steps, rise, tread, width, top_depth=tread, sides=sides, rail=rail,
                         nosing=nosing, nosing_deg=nosing_deg, object_index=object_index)
    treads = [k for k, p in enumerate(up.planes) if p.role == "tread"]
    up = drop_planes(up, [treads[-1], "back"])
    run_n = float(nosing) * math.cos(math.radians(float(nosing_deg)))
    # climbing along +x with its top riser at local x = (steps - 1) * tread - length / 2;
    # turn it round (climbing along -x) and put that riser's top edge on the drop edge x = 0
    length = steps * tread
    top_riser_x = (steps - 1) * tread - length / 2
    flight = place(up, 180.0, (top_riser_x, 0.0), -total)
    w2, e = width / 2, extent
    b = _Builder(0)
    if run_n > 0:   # the top step's chamfer replaces the floor's edge across the flight
        b.add("floor", _rect_z(0.0, -e, -run_n, -e, e), _rect_z(0.0, -run_n, 0.0, -e, -w2),
              _rect_z(0.0, -run_n, 0.0, w2, e))
    else:
        b.add("floor", _rect_z(0.0, -e, 0.0, -e, e))
    b.add("ledge", _rect_x(0.0, -e, -w2, -total, 0.0), _rect_x(0.0, w2, e, -total, 0.0))
    b.add("floor", _rect_z(-total, 0.0, 2 * e, -e, e))
    return b.build(), flight
