"""Synthetic box / stairs / ramp depth scenes with exact ground truth.

A scene is one object (box, stairs or ramp) on a floor, with 0-2 walls, seen by a Kinect-like
depth camera.  The geometry is exact (convex planar polygons, :mod:`planerel.synth.geometry`);
the depth image is ray-cast analytically and vectorised over pixels, then passed through a
sensor model (:class:`SensorModel`).  Everything random comes from one seed.

Resolution: the ray casting runs directly at the written resolution with the intrinsics of the
full-size camera divided by ``subsample`` (:meth:`planerel.io.cloud.Intrinsics.scaled`).  Pixel
``(v, u)`` of the small image is exactly pixel ``(k v, k u)`` of the full image, so this equals
ray-casting at full size and keeping every k-th row and column; the sensor noise is then applied
to the pixels written.  Disparity quantisation always uses the physical sensor's focal length
(``SensorModel.focal_px``, 525 px), whatever the written resolution.

Ground truth per pixel: the plane index (``gt_labels``, -1 = no valid depth) and the object
index (``gt_objects``: 0 = environment (floor, walls), 1 = the object, -1 = none).  Per plane:
its normal and offset in the camera frame (``normal . x + offset = 0``, normal towards the
sensor, offset > 0), its role and object.  The camera pose is the 4x4 world-to-camera matrix;
the world is z-up with the floor at z = 0, so ``up`` (camera frame) is the pose's third column.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from planerel.errors import InputError
from planerel.io.cloud import Cloud, Intrinsics, depth_to_cloud
from planerel.progress import progress_bar

__all__ = [
    "CLASSES",
    "SensorModel",
    "CameraRange",
    "GTPlane",
    "Scene",
    "look_at_pose",
    "raycast",
    "apply_sensor",
    "measure",
    "generate_scene",
    "render_scene",
    "generate_dataset",
    "scene_seed",
    "OPTIONS",
]

#: Scene classes, in data-set order.
CLASSES = ("box", "stairs", "ramp")

#: The scene options :func:`generate_scene` accepts per class (besides the common ones).
OPTIONS = {
    "box": ("length", "width", "height", "yaw_deg"),
    "stairs": ("steps", "rise", "tread", "width", "top_depth", "sides", "rail", "yaw_deg"),
    "ramp": ("angle_deg", "axis", "run", "width", "platform", "side_faces", "yaw_deg"),
}
_COMMON = ("walls",)


def _pair(name: str, value, lo: float = 0.0, *, strict: bool = True) -> tuple[float, float]:
    try:
        a, b = (float(v) for v in value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a (min, max) pair of numbers, got {value!r}") from None
    if not (math.isfinite(a) and math.isfinite(b)) or a > b or (a <= lo if strict else a < lo):
        bound = f"> {lo}" if strict else f">= {lo}"
        raise InputError(f"{name} must be a finite (min, max) pair with min <= max and min {bound}, "
                         f"got {value!r}")
    return (a, b)


def _number(name: str, value, lo: float | None = None, hi: float | None = None,
            *, lo_strict: bool = False) -> float:
    if isinstance(value, bool):  # float(True) is 1.0: a flag given where a number belongs
        raise InputError(f"{name} must be a number, got {value!r}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(x) or (lo is not None and (x <= lo if lo_strict else x < lo)) or (
            hi is not None and x > hi):
        if hi is None:  # no upper bound: "in [0.0, None]" would read as a bug
            rng = f"{'>' if lo_strict else '>='} {lo}" if lo is not None else ""
        elif lo is None:
            rng = f"<= {hi}"
        else:
            rng = f"in {'(' if lo_strict else '['}{lo}, {hi}]"
        raise InputError(f"{name} must be a finite number{' ' + rng if rng else ''}, "
                         f"got {value!r}")
    return x


@dataclass(frozen=True)
class SensorModel:
    """Kinect-like depth sensor model, applied per pixel at the written resolution.

    Order: Gaussian depth noise (std ``noise * z**2`` m) -> disparity quantisation (disparity
    ``focal_px * baseline / z`` rounded to ``disparity_step`` pixels) -> rounding to
    ``depth_unit`` -> range limits -> missing depth at grazing incidence -> missing depth next to
    depth jumps (``edge_dropout``) -> random dropouts.

    Parameters
    ----------
    noise : float
        Depth noise coefficient: std = ``noise * z**2`` metres (Khoshelham & Elberink: 0.0012...
        0.0019 for the Kinect).
    disparity_step : float
        Disparity quantisation in pixels (Kinect: 1/8); 0 turns quantisation off.
    baseline, focal_px : float
        Projector-camera baseline (m) and focal length (px) of the physical sensor.
    depth_unit : float
        Depth resolution of the written image in metres (1 mm).
    min_range, max_range : float
        Depths outside ``[min_range, max_range]`` metres are missing.
    dropout : float
        Probability that a pixel is missing at random.
    edge_dropout : float
        Probability that a pixel next to a depth jump of more than ``edge_jump`` metres (on its
        far side) is missing.
    grazing_deg : float or None
        Pixels whose ray meets the surface at more than this angle from its normal are missing.
    """

    noise: float = 0.0012
    disparity_step: float = 0.125
    baseline: float = 0.075
    focal_px: float = 525.0
    depth_unit: float = 0.001
    min_range: float = 0.45
    max_range: float = 4.5
    dropout: float = 0.01
    edge_dropout: float = 0.3
    edge_jump: float = 0.05
    grazing_deg: float | None = 84.0

    def __post_init__(self) -> None:
        _number("sensor noise", self.noise, 0.0)
        _number("sensor disparity step", self.disparity_step, 0.0)
        _number("sensor baseline", self.baseline, 0.0, lo_strict=True)
        _number("sensor focal length", self.focal_px, 0.0, lo_strict=True)
        _number("sensor depth unit", self.depth_unit, 0.0, 0.1, lo_strict=True)
        _number("sensor min range", self.min_range, 0.0)
        _number("sensor max range", self.max_range, 0.0, 65.0, lo_strict=True)
        if self.max_range <= self.min_range:
            raise InputError(f"sensor max range {self.max_range} must exceed min range {self.min_range}")
        if self.max_range / self.depth_unit > 65534:
            raise InputError(f"sensor max range {self.max_range} m does not fit 16 bits at a depth "
                             f"unit of {self.depth_unit} m")
        _number("sensor dropout", self.dropout, 0.0, 1.0)
        _number("sensor edge dropout", self.edge_dropout, 0.0, 1.0)
        _number("sensor edge jump", self.edge_jump, 0.0, lo_strict=True)
        if self.grazing_deg is not None:
            _number("sensor grazing angle", self.grazing_deg, 0.0, 90.0, lo_strict=True)

    @classmethod
    def ideal(cls, max_range: float = 4.5) -> SensorModel:
        """No noise, no quantisation beyond the depth unit, no dropouts."""
        return cls(noise=0.0, disparity_step=0.0, dropout=0.0, edge_dropout=0.0,
                   grazing_deg=None, max_range=max_range)

    def error_bound(self, z, k: float = 4.0) -> np.ndarray:
        """Bound on ``|measured - true|`` depth (m) at true depth ``z``: ``k`` noise sigmas plus
        half a disparity step plus half a depth unit (with a 5 % margin)."""
        z = np.asarray(z, dtype=float)
        zz = z + k * self.noise * z * z
        quant = 0.5 * self.disparity_step * zz * zz / (self.focal_px * self.baseline)
        return 1.05 * (k * self.noise * z * z + quant) + 0.5 * self.depth_unit + 1e-9

    def to_dict(self) -> dict:
        return {f: getattr(self, f) for f in self.__dataclass_fields__}


@dataclass(frozen=True)
class CameraRange:
    """Ranges the camera placement is drawn from (uniformly).

    Parameters
    ----------
    height : (float, float)
        Camera height above the floor, metres.
    distance : (float, float)
        Horizontal distance from the camera to the object's nearest point, metres.
    roll_deg : float
        Roll about the optical axis is drawn from ``[-roll_deg, roll_deg]``.
    aim_jitter : float
        The camera looks at the object's centre plus up to this many metres in x, y and z.
    min_clearance : float
        The camera is raised to at least this many metres above the object's highest point
        (so that the treads of tall stairs and the tops of boxes are seen); negative allows
        cameras below the top.
    """

    height: tuple = (0.5, 1.5)
    distance: tuple = (0.7, 1.8)
    roll_deg: float = 3.0
    aim_jitter: float = 0.15
    min_clearance: float = 0.25

    def __post_init__(self) -> None:
        object.__setattr__(self, "height", _pair("camera height", self.height))
        object.__setattr__(self, "distance", _pair("camera distance", self.distance))
        _number("camera roll", self.roll_deg, 0.0, 45.0)
        _number("camera aim jitter", self.aim_jitter, 0.0, 2.0)
        _number("camera min clearance", self.min_clearance, -10.0, 10.0)

    def to_dict(self) -> dict:
        return {"height": list(self.height), "distance": list(self.distance),
                "roll_deg": self.roll_deg, "aim_jitter": self.aim_jitter,
                "min_clearance": self.min_clearance}


@dataclass(frozen=True)
class GTPlane:
    """Ground truth of one plane of a synthetic scene.

    Parameters
    ----------
    index : int
        Label value in ``gt_labels``.
    id : str
        ``s0007_p03``.
    normal : tuple of 3 float
        Unit normal in the camera frame, towards the sensor.
    offset : float
        ``normal . x + offset = 0``; > 0 (distance of the camera centre to the plane).
    role : str
        ``floor``, ``wall``, ``top``, ``face``, ``tread``, ``riser``, ``side``, ``back``, ``slope``.
    object_index : int
        0 = environment, 1 = the object.
    object_id : str
        ``s0007_o1``.
    n_pixels : int
        Pixels labelled with this plane (valid depth only); 0 when the plane is not seen.
    incline_deg : float
        Angle between the plane's normal and up, degrees (0 = horizontal, 90 = vertical).
    height : float
        For horizontal planes the height above the floor in metres, else NaN -> stored as None.
    """

    index: int
    id: str
    normal: tuple
    offset: float
    role: str
    object_index: int
    object_id: str
    n_pixels: int
    incline_deg: float
    height: float | None = None

    def to_dict(self) -> dict:
        return {"index": self.index, "id": self.id, "normal": list(self.normal),
                "offset": self.offset, "role": self.role, "object_index": self.object_index,
                "object": self.object_id, "n_pixels": self.n_pixels,
                "incline_deg": self.incline_deg, "height": self.height}


@dataclass(frozen=True, eq=False)
class Scene:
    """A synthetic depth scene and its ground truth.

    Attributes
    ----------
    scene_id : str
        ``s0007``.
    klass : str
        ``box``, ``stairs`` or ``ramp``.
    seed : int
        The seed that regenerates the scene with :func:`generate_scene`.
    depth_mm : ndarray, shape (H, W), uint16
        Measured depth in ``depth_unit`` (mm); 0 = missing.
    depth_true : ndarray, shape (H, W), float64
        Noise-free ray-cast depth (m), NaN where the ray hits nothing within the floor / walls.
    cloud : Cloud
        ``depth_mm`` back-projected, with ``intrinsics`` and ``up``.
    intrinsics : Intrinsics
        Camera at the written resolution.
    gt_labels : ndarray, shape (H, W), int32
        Plane index per pixel, -1 where the depth is missing or a flying pixel (valid depth on
        no surface, :mod:`planerel.synth.sensor`).
    gt_objects : ndarray, shape (H, W), int32
        Object index per pixel (0 environment, 1 object), -1 where the depth is missing.
    planes : tuple of GTPlane
        Every plane of the geometry, in index order (also the unseen ones, ``n_pixels == 0``).
    pose : ndarray, shape (4, 4)
        World-to-camera transform: ``x_cam = R x_world + t``.
    up : ndarray, shape (3,)
        Unit gravity-up vector in the camera frame.
    params : dict
        The drawn scene parameters (object dimensions, walls, camera placement).
    sensor : SensorModel, StructuredLight or TimeOfFlight
    depth_scale : float
        Depth units per metre (``1 / sensor.depth_unit``).
    """

    scene_id: str
    klass: str
    seed: int
    depth_mm: np.ndarray
    depth_true: np.ndarray
    cloud: Cloud
    intrinsics: Intrinsics
    gt_labels: np.ndarray
    gt_objects: np.ndarray
    planes: tuple
    pose: np.ndarray
    up: np.ndarray
    params: dict = field(default_factory=dict)
    sensor: object = field(default_factory=SensorModel)
    depth_scale: float = 1000.0
    object_list: tuple = ()
    world: str = "paper"

    @property
    def objects(self) -> tuple:
        """One dict per object, in index order: ``{"index": 0, "id": ..., "class":
        "environment"}``, then the objects (paper world: ``{"index": 1, ..., "class": klass}``;
        varied world: every object with its class -- ``box``, ``stairs``, ``ramp`` or ``other``
        -- its ``kind``, ``params`` and ``n_pixels``)."""
        if self.object_list:
            return self.object_list
        return ({"index": 0, "id": f"{self.scene_id}_o0", "class": "environment"},
                {"index": 1, "id": f"{self.scene_id}_o1", "class": self.klass})

    def visible_planes(self, min_pixels: int = 1) -> tuple:
        """Planes with at least ``min_pixels`` labelled pixels."""
        return tuple(p for p in self.planes if p.n_pixels >= min_pixels)

    def metadata(self) -> dict:
        """The JSON sidecar content (see ``docs/formats.md``)."""
        return {
            "format": "planerel-synth-scene",
            "version": 1,
            "scene_id": self.scene_id,
            "class": self.klass,
            "seed": self.seed,
            "intrinsics": self.intrinsics.to_dict(),
            "depth_scale": self.depth_scale,
            "up": [_r(v) for v in self.up],
            "pose": {"world_to_camera": [[_r(v) for v in row] for row in self.pose],
                     "world": "z up, floor at z = 0, metres"},
            **({"world": self.world} if self.world != "paper" else {}),
            "objects": list(self.objects),
            "planes": [p.to_dict() for p in self.planes],
            "params": self.params,
            "sensor": self.sensor.to_dict(),
        }


def _r(x: float) -> float:
    """A plain float for JSON (full precision; -0.0 -> 0.0)."""
    v = float(x)
    return 0.0 if v == 0 else v


# ----------------------------------------------------------------------- camera and raycast


def look_at_pose(eye, target, roll_deg: float = 0.0) -> np.ndarray:
    """World-to-camera 4x4 matrix of a camera at ``eye`` looking at ``target`` (world z up).

    Camera axes: x right, y down, z forward; ``roll_deg`` turns the image about the optical axis.
    """
    eye = np.asarray(eye, dtype=float)
    f = np.asarray(target, dtype=float) - eye
    norm = np.linalg.norm(f)
    if norm < 1e-9:
        raise InputError("camera target coincides with the camera position")
    f /= norm
    right = np.cross(f, [0.0, 0.0, 1.0])
    if np.linalg.norm(right) < 1e-6:
        raise InputError("camera looks straight up or down; the image x axis is undefined")
    right /= np.linalg.norm(right)
    down = np.cross(f, right)
    a = math.radians(roll_deg)
    x = math.cos(a) * right + math.sin(a) * down
    y = -math.sin(a) * right + math.cos(a) * down
    rot = np.stack([x, y, f])
    pose = np.eye(4)
    pose[:3, :3] = rot
    pose[:3, 3] = -rot @ eye
    return pose


def _clip_near(vertices: np.ndarray, near: float) -> np.ndarray:
    """Sutherland-Hodgman clip of a convex polygon (camera frame) to ``z >= near``."""
    z = vertices[:, 2]
    if np.all(z >= near):
        return vertices
    if np.all(z < near):
        return vertices[:0]
    out = []
    k = len(vertices)
    for i in range(k):
        a, b = vertices[i], vertices[(i + 1) % k]
        ina, inb = a[2] >= near, b[2] >= near
        if ina:
            out.append(a)
        if ina != inb:
            t = (near - a[2]) / (b[2] - a[2])
            out.append(a + t * (b - a))
    return np.array(out)


def raycast(polygons, intrinsics: Intrinsics, near: float = 0.05):
    """Ray-cast convex planar polygons given in the camera frame.

    Each pixel ``(v, u)`` casts the ray ``r = ((u - cx) / fx, (v - cy) / fy, 1)``; a ray lies
    in a convex polygon's viewing cone when it is on the inner side of every plane through the
    camera centre and an edge, which is a linear test in ``u`` and ``v``.  Each polygon is
    tested only inside the image bounding box of its projection (after clipping at ``near``).

    Parameters
    ----------
    polygons : sequence of ndarray, shape (K_i, 3)
        Convex planar polygons (either winding), camera frame, metres.
    intrinsics : Intrinsics

    Returns
    -------
    depth : ndarray, shape (H, W), float64
        z of the nearest hit, NaN where nothing is hit.
    index : ndarray, shape (H, W), int32
        Index of the polygon hit, -1 where nothing is hit.
    """
    intr = intrinsics
    h, w = intr.height, intr.width
    xn_all = (np.arange(w, dtype=np.float64) - intr.cx) / intr.fx
    yn_all = (np.arange(h, dtype=np.float64) - intr.cy) / intr.fy
    zbuf = np.full((h, w), np.inf)
    index = np.full((h, w), -1, dtype=np.int32)
    for i, verts in enumerate(polygons):
        v = _clip_near(np.asarray(verts, dtype=np.float64), near)
        if len(v) < 3:
            continue
        # plane through the polygon, oriented so that offset > 0
        centre = v.mean(axis=0)
        n = np.cross(v[1] - v[0], v[2] - v[0])
        for j in range(3, len(v)):
            if np.linalg.norm(n) > 1e-12:
                break
            n = np.cross(v[1] - v[0], v[j] - v[0])
        nn = np.linalg.norm(n)
        if nn < 1e-12:
            continue
        n = n / nn
        d = -float(n @ centre)
        if abs(d) < 1e-9:
            continue  # the camera lies in the polygon's plane: seen edge-on
        if d < 0:
            n, d = -n, -d
        # image bounding box of the projection
        u = intr.fx * v[:, 0] / v[:, 2] + intr.cx
        vv = intr.fy * v[:, 1] / v[:, 2] + intr.cy
        u0, u1 = max(int(math.floor(u.min())), 0), min(int(math.ceil(u.max())), w - 1)
        v0, v1 = max(int(math.floor(vv.min())), 0), min(int(math.ceil(vv.max())), h - 1)
        if u0 > u1 or v0 > v1:
            continue
        xn = xn_all[None, u0:u1 + 1]
        yn = yn_all[v0:v1 + 1, None]
        edges = np.cross(v, np.roll(v, -1, axis=0))  # normals of the planes camera-edge
        sign = 1.0 if float(edges[0] @ centre) >= 0 else -1.0
        edges *= sign
        inside = None
        for e in edges:
            test = (e[0] * xn + e[1] * yn) >= -e[2]
            inside = test if inside is None else inside & test
        denom = n[0] * xn + n[1] * yn + n[2]
        with np.errstate(divide="ignore", invalid="ignore"):
            z = -d / denom
        win = (slice(v0, v1 + 1), slice(u0, u1 + 1))
        better = inside & (denom < 0) & (z < zbuf[win])
        if not better.any():
            continue
        zbuf[win] = np.where(better, z, zbuf[win])
        index[win] = np.where(better, i, index[win])
    depth = np.where(np.isfinite(zbuf), zbuf, np.nan)
    return depth, index


def apply_sensor(depth_true, cos_incidence, sensor: SensorModel, rng: np.random.Generator):
    """Turn noise-free depth into a measured depth image.

    Parameters
    ----------
    depth_true : ndarray, shape (H, W)
        True z in metres, NaN where nothing is hit.
    cos_incidence : ndarray, shape (H, W)
        ``|cos|`` of the angle between each ray and the surface normal it hits.
    sensor : SensorModel
    rng : numpy.random.Generator
        Always draws three ``(H, W)`` arrays in the same order, so the result depends only on
        the generator's state.

    Returns
    -------
    ndarray, shape (H, W), uint16
        Depth in ``sensor.depth_unit``; 0 = missing.
    """
    z = np.asarray(depth_true, dtype=np.float64)
    noise = rng.standard_normal(z.shape)
    drop_draw = rng.random(z.shape)
    edge_draw = rng.random(z.shape)
    hit = np.isfinite(z)
    zt = np.where(hit, z, 1.0)
    zn = zt + sensor.noise * zt * zt * noise
    zn = np.maximum(zn, 1e-3)
    if sensor.disparity_step > 0:
        fb = sensor.focal_px * sensor.baseline
        disp = np.round(fb / zn / sensor.disparity_step) * sensor.disparity_step
        disp = np.maximum(disp, sensor.disparity_step)
        zn = fb / disp
    units = np.round(zn / sensor.depth_unit)
    zq = units * sensor.depth_unit
    ok = hit & (zq >= sensor.min_range) & (zq <= sensor.max_range)
    if sensor.grazing_deg is not None:
        ok &= np.asarray(cos_incidence) >= math.cos(math.radians(sensor.grazing_deg))
    if sensor.edge_dropout > 0:
        far = np.where(hit, z, np.inf)
        jump = np.zeros(z.shape, dtype=bool)
        # a pixel is on the far side of a jump when a 4-neighbour is nearer by > edge_jump
        with np.errstate(invalid="ignore"):
            jump[1:, :] |= far[1:, :] - far[:-1, :] > sensor.edge_jump
            jump[:-1, :] |= far[:-1, :] - far[1:, :] > sensor.edge_jump
            jump[:, 1:] |= far[:, 1:] - far[:, :-1] > sensor.edge_jump
            jump[:, :-1] |= far[:, :-1] - far[:, 1:] > sensor.edge_jump
        ok &= ~(jump & (edge_draw < sensor.edge_dropout))
    if sensor.dropout > 0:
        ok &= drop_draw >= sensor.dropout
    return np.where(ok, units, 0).astype(np.uint16)


def _check_sensor(sensor) -> None:
    from planerel.synth.sensor import StructuredLight, TimeOfFlight

    if not isinstance(sensor, (SensorModel, StructuredLight, TimeOfFlight)):
        raise InputError(f"sensor must be a SensorModel, StructuredLight or TimeOfFlight, got "
                         f"{type(sensor).__name__}")


def measure(depth_true, cos_incidence, sensor, intrinsics: Intrinsics, rng: np.random.Generator,
            surface=None):
    """Measured depth of a ray-cast image with any sensor model (``surface``: the plane index
    per pixel, for the realistic models' depth edges).

    Returns
    -------
    units : ndarray, shape (H, W), uint16
        Depth in ``sensor.depth_unit``, 0 = missing.
    flying : ndarray, shape (H, W), bool
        Valid pixels whose depth lies on no surface (always False for :class:`SensorModel`).
    """
    if isinstance(sensor, SensorModel):
        units = apply_sensor(depth_true, cos_incidence, sensor, rng)
        return units, np.zeros(units.shape, dtype=bool)
    return sensor.apply(depth_true, cos_incidence, intrinsics, rng, surface)


# ----------------------------------------------------------------------- scene generation


def scene_seed(seed: int, index: int) -> int:
    """The seed of scene ``index`` of a data set generated with ``seed`` (a 32-bit integer)."""
    return int(np.random.SeedSequence([int(seed), int(index)]).generate_state(1)[0])


def _check_seed(seed) -> int:
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"seed must be a non-negative integer, got {seed!r}")
    return int(seed)


def _check_size(size) -> tuple[int, int]:
    try:
        w, h = size
    except (TypeError, ValueError):
        raise InputError(f"size must be (width, height), got {size!r}") from None
    for name, v in (("width", w), ("height", h)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 8:
            raise InputError(f"image {name} must be an integer >= 8, got {v!r}")
    return int(w), int(h)


def _scene_setup(kind: str, seed, size, subsample) -> tuple[int, int, int, Intrinsics]:
    """Check the arguments every world's scene generator takes; return ``(seed, width,
    height, intrinsics)``: the Kinect preset scaled to ``size`` when it divides 640x480, else
    fx = fy = 525 * width / 640 with a centred principal point, then subsampled."""
    if kind not in CLASSES:
        raise InputError(f"unknown scene class {kind!r}; choose one of {', '.join(CLASSES)}")
    seed = _check_seed(seed)
    w, h = _check_size(size)
    if isinstance(subsample, bool) or not isinstance(subsample, (int, np.integer)) or subsample < 1:
        raise InputError(f"subsample must be a positive integer, got {subsample!r}")
    if (w, h) == (640, 480) or (640 % w == 0 and 480 % h == 0 and 640 // w == 480 // h):
        full = Intrinsics.kinect(w, h)
    else:
        f = 525.0 * w / 640.0
        full = Intrinsics(w, h, f, f, (w - 1) / 2, (h - 1) / 2)
    intr = full.scaled(int(subsample))
    if intr.width < 8 or intr.height < 8:  # the size check's bound, after subsampling
        raise InputError(f"size {w}x{h} subsampled by {int(subsample)} gives {intr.width}x"
                         f"{intr.height} images; both sides must stay >= 8 pixels (a larger "
                         f"size or a smaller subsample)")
    return seed, w, h, intr


def primary_seen(obj, depth_true, sensor):
    """``(H, W)`` bool: the pixels that see the scene's primary object (object 1, ``obj`` of
    :func:`cast_world`) within ``sensor``'s range."""
    return (obj == 1) & (depth_true <= sensor.max_range) & (depth_true >= sensor.min_range)


def cast_world(world, pose, intr: Intrinsics):
    """Ray-cast a world seen from ``pose``: ``(depth_true, poly_index, plane, obj)``, the last
    two ``(H, W)`` images of the plane and the object each pixel sees (-1: nothing)."""
    rot, t = pose[:3, :3], pose[:3, 3]
    depth_true, poly_index = raycast([p.vertices @ rot.T + t for p in world.polygons], intr)
    plane_of_poly = np.array([p.plane for p in world.polygons], dtype=np.int32)
    obj_of_plane = np.array([sp.object_index for sp in world.planes], dtype=np.int32)
    plane = np.where(poly_index >= 0, plane_of_poly[np.maximum(poly_index, 0)], -1)
    obj = np.where(plane >= 0, obj_of_plane[np.maximum(plane, 0)], -1)
    return depth_true, poly_index, plane, obj


def _draw_object(kind: str, rng: np.random.Generator, opts: dict):
    """Draw the object's dimensions; ``opts`` overrides any of them. Returns (geometry, params,
    facing), where facing is the preferred camera azimuth relative to the object's yaw
    (None = any)."""
    from planerel.synth import geometry as sg

    def pick(name, draw):
        value = draw()  # always draw, so overriding one option does not shift the others
        return opts[name] if name in opts else value

    if kind == "box":
        p = {"length": pick("length", lambda: float(rng.uniform(0.3, 1.2))),
             "width": pick("width", lambda: float(rng.uniform(0.3, 1.0))),
             "height": pick("height", lambda: float(rng.uniform(0.2, 0.9)))}
        geom = sg.box_geometry(p["length"], p["width"], p["height"])
        facing = None
    elif kind == "stairs":
        p = {"steps": pick("steps", lambda: int(rng.integers(2, 7))),
             "rise": pick("rise", lambda: float(rng.uniform(0.12, 0.22))),
             "tread": pick("tread", lambda: float(rng.uniform(0.22, 0.36))),
             "width": pick("width", lambda: float(rng.uniform(0.6, 1.4)))}
        land = float(rng.uniform(1.0, 2.5))
        p["top_depth"] = pick("top_depth", lambda: None)
        if p["top_depth"] is None:
            p["top_depth"] = p["tread"] * (land if rng.random() < 0.4 else 1.0)
        else:
            rng.random()
        p["sides"] = pick("sides", lambda: "open" if rng.random() < 0.5 else "closed")
        p["rail"] = pick("rail", lambda: float(rng.uniform(0.1, 0.5)))
        geom = sg.stairs_geometry(p["steps"], p["rise"], p["tread"], p["width"],
                                  top_depth=p["top_depth"], sides=p["sides"], rail=p["rail"])
        facing = 180.0
    elif kind == "ramp":
        p = {"angle_deg": pick("angle_deg", lambda: float(rng.uniform(8.0, 30.0))),
             "axis": pick("axis", lambda: "pitch" if rng.random() < 0.5 else "roll"),
             "width": pick("width", lambda: float(rng.uniform(0.6, 1.4)))}
        if p["axis"] not in ("pitch", "roll"):
            raise InputError(f"ramp axis must be 'pitch' or 'roll', got {p['axis']!r}")
        # the slope rises 0.15 .. 0.6 m, within a run of 0.6 .. 2.2 m
        rise = float(rng.uniform(0.15, 0.6))
        run_default = min(max(rise / math.tan(math.radians(_number("ramp angle", p["angle_deg"], 0, 89.9,
                                                                   lo_strict=True))), 0.6), 2.2)
        p["run"] = pick("run", lambda: run_default)
        p["platform"] = pick("platform", lambda: float(rng.uniform(0.3, 1.0)) if rng.random() < 0.5 else 0.0)
        p["side_faces"] = pick("side_faces", lambda: bool(rng.random() < 0.6))
        if not isinstance(p["side_faces"], (bool, np.bool_)):
            raise InputError(f"ramp side_faces must be True or False, got {p['side_faces']!r}")
        geom = sg.ramp_geometry(p["angle_deg"], p["run"], p["width"], platform=p["platform"],
                                side_faces=bool(p["side_faces"]))
        facing = 180.0 if p["axis"] == "pitch" else (90.0 if rng.random() < 0.5 else -90.0)
    else:  # pragma: no cover - checked by the caller
        raise InputError(f"unknown scene class {kind!r}")
    return geom, p, facing


def _build(kind: str, rng: np.random.Generator, opts: dict, camera: CameraRange, intr: Intrinsics):
    """Draw one candidate scene: geometry (world), pose, parameters."""
    from planerel.synth import geometry as sg

    geom, params, facing = _draw_object(kind, rng, opts)
    yaw = float(rng.uniform(-180.0, 180.0))
    if "yaw_deg" in opts:
        yaw = _number("yaw_deg", opts["yaw_deg"], -360.0, 360.0)
    params["yaw_deg"] = yaw
    obj = sg.place(geom, yaw)
    verts = obj.vertices()
    top = float(verts[:, 2].max())
    # camera azimuth (direction from the object to the camera), relative to the object's yaw
    jitter = float(rng.uniform(-35.0, 35.0))
    rel = float(rng.uniform(-180.0, 180.0)) if facing is None else facing + jitter
    az = math.radians(yaw + rel)
    height = max(float(rng.uniform(*camera.height)), top + camera.min_clearance)
    gap = float(rng.uniform(*camera.distance))
    # horizontal distance from the object's centre to its nearest point towards the camera
    direction = np.array([math.cos(az), math.sin(az)])
    reach = float(np.max(verts[:, :2] @ direction))
    dist = reach + gap
    eye = np.array([direction[0] * dist, direction[1] * dist, height])
    aim = np.array([0.0, 0.0, 0.5 * top]) + rng.uniform(-camera.aim_jitter, camera.aim_jitter, 3)
    roll = float(rng.uniform(-camera.roll_deg, camera.roll_deg))
    pose = look_at_pose(eye, aim, roll)
    # walls behind the object (as seen from the camera) and to one side
    n_walls = int(rng.integers(0, 3))
    if "walls" in opts:
        n_walls = opts["walls"]
        if isinstance(n_walls, bool) or not isinstance(n_walls, (int, np.integer)) or not 0 <= n_walls <= 2:
            raise InputError(f"walls must be 0, 1 or 2, got {n_walls!r}")
        n_walls = int(n_walls)
    back_gap = float(rng.uniform(0.3, 1.5))
    side_gap = float(rng.uniform(0.3, 1.5))
    wall_turn = float(rng.uniform(-20.0, 20.0))
    side_sign = 1.0 if rng.random() < 0.5 else -1.0
    wall_h = float(rng.uniform(1.8, 2.8))
    parts = [sg.floor_geometry()]
    back_dir = az + math.pi + math.radians(wall_turn)  # from the object away from the camera
    bd = np.array([math.cos(back_dir), math.sin(back_dir)])
    sd = np.array([-bd[1], bd[0]]) * side_sign
    wall_dist = float(np.max(verts[:, :2] @ bd)) + back_gap
    side_dist = float(np.max(verts[:, :2] @ sd)) + side_gap
    if n_walls >= 1:
        parts.append(sg.wall_geometry(bd * wall_dist, math.degrees(back_dir) + 90.0, 10.0, wall_h))
    if n_walls >= 2:
        # from the back wall towards the camera, along the side
        centre = bd * wall_dist + sd * side_dist - bd * 4.0
        parts.append(sg.wall_geometry(centre, math.degrees(back_dir), 8.0, wall_h))
    world = sg.combine(*parts, obj)
    params.update({
        "walls": n_walls,
        "camera": {"height": height, "gap": gap, "distance": dist, "azimuth_deg": math.degrees(az),
                   "relative_azimuth_deg": rel, "roll_deg": roll,
                   "eye": eye.tolist(), "aim": aim.tolist()},
    })
    if n_walls:
        params["wall"] = {"back_gap": back_gap, "side_gap": side_gap, "height": wall_h,
                          "turn_deg": wall_turn, "side": "left" if side_sign > 0 else "right"}
    return world, pose, params


def generate_scene(kind: str, seed: int = 0, size=(640, 480), subsample: int = 1, *,
                   scene_id: str = "s0000", sensor: SensorModel | None = None,
                   camera: CameraRange | None = None, min_object_fraction: float = 0.04,
                   **options) -> Scene:
    """Generate one synthetic scene with ground truth.

    Parameters
    ----------
    kind : {"box", "stairs", "ramp"}
    seed : int
        Everything random (dimensions, camera, noise) comes from this seed.
    size : (int, int)
        Full sensor size ``(width, height)``; the Kinect preset intrinsics are scaled to it when
        it divides 640x480, else fx = fy = 525 * width / 640 with a centred principal point.
    subsample : int
        Keep every k-th row and column: the image written is ``ceil(W / k) x ceil(H / k)``.
    scene_id : str
        Prefix of the plane and object ids.
    sensor : SensorModel, StructuredLight or TimeOfFlight, optional
        Default :class:`SensorModel()`; ``SensorModel.ideal()`` for noise-free depth; the
        realistic profiles are in :mod:`planerel.synth.sensor`.
    camera : CameraRange, optional
        Default :class:`CameraRange()`.
    min_object_fraction : float
        A drawn camera is rejected (and drawn again) unless the object covers at least this
        fraction of the image with valid depth and no more than a little of it leaves the image.
    **options
        Fix drawn parameters. box: ``length, width, height``; stairs: ``steps, rise, tread,
        width, top_depth, sides ('open'|'closed'), rail``; ramp: ``angle_deg, axis
        ('pitch'|'roll'), run, width, platform, side_faces``; all: ``yaw_deg``, ``walls`` (0-2).

    Returns
    -------
    Scene

    Raises
    ------
    InputError
        Unknown class or option, or a bad value.
    """
    seed, w, h, intr = _scene_setup(kind, seed, size, subsample)
    unknown = sorted(set(options) - set(OPTIONS[kind]) - set(_COMMON))
    if unknown:
        raise InputError(f"unknown option(s) for a {kind} scene: {', '.join(unknown)}; known: "
                         f"{', '.join(OPTIONS[kind] + _COMMON)}")
    sensor = SensorModel() if sensor is None else sensor
    camera = CameraRange() if camera is None else camera
    _check_sensor(sensor)
    if not isinstance(camera, CameraRange):
        raise InputError(f"camera must be a CameraRange, got {type(camera).__name__}")
    _number("min_object_fraction", min_object_fraction, 0.0, 0.9)
    rng = np.random.default_rng(seed)
    margin = 0.03
    for _attempt in range(200):
        world, pose, params = _build(kind, rng, options, camera, intr)
        rot, t = pose[:3, :3], pose[:3, 3]
        # the object must (nearly) fit in the image
        obj_v = world.vertices(1) @ rot.T + t
        if np.any(obj_v[:, 2] < 0.3):
            continue
        pu = (intr.fx * obj_v[:, 0] / obj_v[:, 2] + intr.cx) / intr.width
        pv = (intr.fy * obj_v[:, 1] / obj_v[:, 2] + intr.cy) / intr.height
        inside = (pu > -margin) & (pu < 1 + margin) & (pv > -margin) & (pv < 1 + margin)
        if inside.mean() < 0.85:
            continue
        depth_true, poly_index, _plane, obj = cast_world(world, pose, intr)
        obj_px = (obj == 1) & (depth_true <= sensor.max_range)
        if obj_px.mean() >= min_object_fraction:
            break
    else:
        raise InputError(f"could not place the camera so that the {kind} is seen (seed {seed}); "
                         "widen the camera ranges or lower min_object_fraction")
    params = _jsonable_params(params)
    params.update({"size": [w, h], "subsample": int(subsample)})
    return render_scene(world, pose, intr, sensor, rng, scene_id=scene_id, klass=kind, seed=seed,
                        params=params, depth_true=depth_true, poly_index=poly_index)


def camera_planes(world, pose):
    """Every plane of ``world`` in the camera frame: ``(normals (P, 3), offsets (P,),
    {plane: first polygon})``, normals towards the camera (offset > 0)."""
    rot, t = pose[:3, :3], pose[:3, 3]
    normals_c, offsets_c = [], []
    first_poly = {}
    for p in world.polygons:
        first_poly.setdefault(p.plane, p)
    for k in range(len(world.planes)):
        poly = first_poly[k]
        n_w = poly.normal()
        d_w = -float(n_w @ poly.vertices[0])
        n_c = rot @ n_w
        d_c = d_w - float(n_c @ t)
        if d_c < 0:
            n_c, d_c = -n_c, -d_c
        normals_c.append(n_c)
        offsets_c.append(d_c)
    return np.array(normals_c), offsets_c, first_poly


def cos_incidence(normals_c, plane_index, intr: Intrinsics) -> np.ndarray:
    """``|cos|`` of the angle between each pixel's ray and the normal of the plane it hits,
    ``(H, W)`` (pixels that hit nothing get the first plane's value; mask them)."""
    xn = (np.arange(intr.width) - intr.cx) / intr.fx
    yn = (np.arange(intr.height) - intr.cy) / intr.fy
    nrm = normals_c[np.maximum(plane_index, 0)]
    dot = nrm[:, :, 0] * xn[None, :] + nrm[:, :, 1] * yn[:, None] + nrm[:, :, 2]
    return np.abs(dot) / np.sqrt(xn[None, :] ** 2 + yn[:, None] ** 2 + 1.0)


def render_scene(world, pose, intr: Intrinsics, sensor, rng: np.random.Generator, *,
                 scene_id: str, klass: str, seed: int, params: dict, depth_true=None,
                 poly_index=None, object_list: tuple = (), world_name: str = "paper") -> Scene:
    """Ray-cast (unless ``depth_true`` and ``poly_index`` are given), measure and label one
    scene: the common tail of every world's generator.

    Parameters
    ----------
    world : planerel.synth.geometry.Geometry
        Everything in world coordinates (z up, floor z = 0).
    pose : ndarray, shape (4, 4)
        World-to-camera transform.
    object_list : tuple of dict
        ``{"index", "id", "class", ...}`` per object (default: environment + one ``klass``).
    """
    rot = pose[:3, :3]
    if depth_true is None:
        depth_true, poly_index, ideal_planes, _obj = cast_world(world, pose, intr)
    else:
        plane_of_poly = np.array([p.plane for p in world.polygons], dtype=np.int32)
        ideal_planes = np.where(poly_index >= 0, plane_of_poly[np.maximum(poly_index, 0)], -1)
    obj_of_plane = np.array([sp.object_index for sp in world.planes], dtype=np.int32)
    up = rot[:, 2].copy()
    normals_c, offsets_c, first_poly = camera_planes(world, pose)
    cos_inc = cos_incidence(normals_c, ideal_planes, intr)
    depth_mm, flying = measure(depth_true, cos_inc, sensor, intr, rng, ideal_planes)
    valid = depth_mm > 0
    gt_labels = np.where(valid & ~flying, ideal_planes, -1).astype(np.int32)
    gt_objects = np.where(gt_labels >= 0, obj_of_plane[np.maximum(gt_labels, 0)], -1).astype(np.int32)
    counts = np.bincount(gt_labels[gt_labels >= 0], minlength=len(world.planes))
    planes = []
    for k, spec in enumerate(world.planes):
        n_c = normals_c[k]
        incline = math.degrees(math.atan2(float(np.linalg.norm(np.cross(n_c, up))),
                                          abs(float(n_c @ up))))
        height = None
        if incline < 1e-6:
            height = _r(first_poly[k].vertices[0, 2])
        planes.append(GTPlane(
            index=k, id=f"{scene_id}_p{k:02d}", normal=tuple(_r(c) for c in n_c),
            offset=_r(offsets_c[k]), role=spec.role, object_index=spec.object_index,
            object_id=f"{scene_id}_o{spec.object_index}", n_pixels=int(counts[k]),
            incline_deg=_r(incline), height=height,
        ))
    if object_list:
        per_object = np.bincount(gt_objects[gt_objects >= 0], minlength=len(object_list))
        object_list = tuple({**o, "n_pixels": int(per_object[o["index"]])} for o in object_list)
    cloud = depth_to_cloud(depth_mm, intr, 1.0 / sensor.depth_unit, up=up, source=scene_id)
    for arr in (depth_mm, depth_true, gt_labels, gt_objects):
        arr.setflags(write=False)
    pose.setflags(write=False)
    up.setflags(write=False)
    return Scene(scene_id=scene_id, klass=klass, seed=seed, depth_mm=depth_mm,
                 depth_true=depth_true, cloud=cloud, intrinsics=intr, gt_labels=gt_labels,
                 gt_objects=gt_objects, planes=tuple(planes), pose=pose, up=up, params=params,
                 sensor=sensor, depth_scale=1.0 / sensor.depth_unit, object_list=object_list,
                 world=world_name)


def _jsonable_params(obj):
    if isinstance(obj, dict):
        return {k: _jsonable_params(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable_params(v) for v in obj]
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        return _r(obj)
    return obj


def generate_dataset(out_dir, n_box: int = 12, n_stairs: int = 15, n_ramp: int = 18,
                     seed: int = 0, size=(640, 480), subsample: int = 4, *,
                     sensor=None, camera: CameraRange | None = None,
                     progress: bool = False, world: str = "paper", ranges=None) -> Path:
    """Generate and write a synthetic data set (format: ``docs/formats.md``).

    Scenes ``s0000 ..`` are the boxes, then the stairs, then the ramps; scene ``i`` uses the seed
    :func:`scene_seed` ``(seed, i)``, so any scene can be regenerated alone.

    ``world="paper"`` (default): one object per scene (:func:`generate_scene`, ``camera``
    ranges); ``world="varied"``: the counts are scenes whose *primary* object has that class,
    with more objects and clutter around it (:func:`planerel.synth.world.generate_world_scene`,
    ``ranges`` a :class:`planerel.synth.world.WorldRange`; default sensor: structured light).

    Returns
    -------
    Path
        ``out_dir``.
    """
    from planerel.atomic import atomic_dir
    from planerel.features.dataset import write_dataset_info, write_manifest, write_scene

    counts = {"box": n_box, "stairs": n_stairs, "ramp": n_ramp}
    for name, n in counts.items():
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
            raise InputError(f"number of {name} scenes must be a non-negative integer, got {n!r}")
    if sum(counts.values()) == 0:
        raise InputError("a data set needs at least one scene (all counts are 0)")
    if sum(counts.values()) > 9999:
        raise InputError(f"at most 9999 scenes, got {sum(counts.values())}")
    seed = _check_seed(seed)
    from planerel.synth.world import WORLDS, WorldRange, generate_world_scene

    if world not in WORLDS:
        raise InputError(f"unknown world {world!r}; choose one of {', '.join(WORLDS)}")
    if world == "paper":
        sensor = SensorModel() if sensor is None else sensor
    else:
        from planerel.synth.sensor import StructuredLight

        sensor = StructuredLight() if sensor is None else sensor
        ranges = WorldRange() if ranges is None else ranges
    _check_sensor(sensor)
    camera = CameraRange() if camera is None else camera
    out = Path(out_dir)
    jobs = [(kind, None) for kind in CLASSES for _ in range(counts[kind])]
    rows = []
    it = progress_bar(range(len(jobs)), desc="scenes", enabled=bool(progress), leave=True)
    # built aside and swapped in whole: a killed run leaves the previous set or none, never a mix
    with atomic_dir(out, markers=("manifest.csv", "dataset.json")) as tmp:
        for i in it:
            kind = jobs[i][0]
            if world == "paper":
                scene = generate_scene(kind, scene_seed(seed, i), size, subsample,
                                       scene_id=f"s{i:04d}", sensor=sensor, camera=camera)
            else:
                scene = generate_world_scene(kind, scene_seed(seed, i), size, subsample,
                                             scene_id=f"s{i:04d}", sensor=sensor, ranges=ranges)
            rows.append(write_scene(tmp, scene))
        write_manifest(tmp, rows)
        info = {
            "format": "planerel-synth-dataset", "version": 1, "seed": seed,
            "counts": counts, "size": list(_check_size(size)), "subsample": int(subsample),
            "sensor": sensor.to_dict(),
        }
        if world == "paper":
            info["camera"] = camera.to_dict()
        else:
            info["world"] = world
            info["world_ranges"] = ranges.to_dict()
        write_dataset_info(tmp, info)
    return out
