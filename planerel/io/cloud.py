"""Camera intrinsics and the organized point cloud every stage works on.

Camera frame (OpenCV / ROS optical): x to the right, y down, z forward along the optical axis,
metres.  A pixel ``(row v, column u)`` with depth ``z`` back-projects to
``x = (u - cx) * z / fx``, ``y = (v - cy) * z / fy``.  A level camera has up = ``(0, -1, 0)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from planerel.errors import InputError

__all__ = [
    "Intrinsics",
    "Cloud",
    "KINECT",
    "DEFAULT_DEPTH_SCALE",
    "depth_to_cloud",
    "subsample",
]

#: Raw Kinect/OpenNI 16-bit depth is in millimetres: 1000 units per metre.
DEFAULT_DEPTH_SCALE = 1000.0


#: The focal lengths (pixels) an :class:`Intrinsics` takes: far beyond any camera's (a
#: fisheye's tens of pixels, a telephoto's tens of thousands) on both sides, and inside what
#: the projections' arithmetic holds in float64.
FOCAL_MIN = 1e-6
FOCAL_MAX = 1e12


@dataclass(frozen=True)
class Intrinsics:
    """Pinhole intrinsics of a depth camera.

    Parameters
    ----------
    width, height : int
        Image size in pixels.
    fx, fy : float
        Focal lengths in pixels (> 0).
    cx, cy : float
        Principal point in pixels.
    """

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float

    def __post_init__(self) -> None:
        for name in ("width", "height"):
            value = getattr(self, name)
            # JSON writers often store sizes as 160.0: a whole float is that integer
            if isinstance(value, (float, np.floating)) and math.isfinite(value) and value == int(value):
                value = int(value)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
                raise InputError(f"intrinsics {name} must be a positive integer, got {value!r}")
            object.__setattr__(self, name, int(value))
        for name in ("fx", "fy", "cx", "cy"):
            value = getattr(self, name)
            try:
                value = float(value)
            except (TypeError, ValueError):
                raise InputError(f"intrinsics {name} must be a number, got {value!r}") from None
            if not math.isfinite(value):
                raise InputError(f"intrinsics {name} must be finite, got {value!r}")
            object.__setattr__(self, name, value)
        if self.fx <= 0 or self.fy <= 0:
            raise InputError(f"focal lengths must be positive, got fx={self.fx}, fy={self.fy}")
        if not (FOCAL_MIN <= self.fx <= FOCAL_MAX and FOCAL_MIN <= self.fy <= FOCAL_MAX):
            # (products and quotients of such values under- or overflow: user103)
            raise InputError(f"focal lengths are pixels, between {FOCAL_MIN:g} and "
                             f"{FOCAL_MAX:g}; got fx={self.fx:g}, fy={self.fy:g}")

    def field_of_view(self) -> tuple[float, float]:
        """The horizontal and vertical fields of view (degrees) across the image."""
        return (math.degrees(2.0 * math.atan2(self.width / 2.0, self.fx)),
                math.degrees(2.0 * math.atan2(self.height / 2.0, self.fy)))

    @classmethod
    def kinect(cls, width: int = 640, height: int = 480) -> Intrinsics:
        """Kinect / PrimeSense preset (fx = fy = 525, cx = 319.5, cy = 239.5 at 640x480),
        scaled to ``width x height`` when that is a whole-number subsampling of 640x480."""
        base = cls(640, 480, 525.0, 525.0, 319.5, 239.5)
        if (width, height) == (640, 480):
            return base
        k = 640 // width if width else 0
        if k < 1 or 640 % width or 480 % height or 480 // height != k:
            raise InputError(
                f"no Kinect preset for {width}x{height}: give the intrinsics explicitly "
                "(640x480 divided by a whole number is supported)"
            )
        return base.scaled(k)

    @classmethod
    def from_matrix(cls, K, width: int, height: int) -> Intrinsics:
        """Build from a 3x3 camera matrix ``K``."""
        K = np.asarray(K, dtype=float)
        if K.shape != (3, 3):
            raise InputError(f"camera matrix K must be 3x3, got shape {K.shape}")
        return cls(width, height, K[0, 0], K[1, 1], K[0, 2], K[1, 2])

    @classmethod
    def from_any(cls, value) -> Intrinsics:
        """Accept an ``Intrinsics``, a mapping with the six fields, or a 6-sequence
        ``(width, height, fx, fy, cx, cy)``."""
        if isinstance(value, Intrinsics):
            return value
        if isinstance(value, dict):
            try:
                return cls(**{k: value[k] for k in ("width", "height", "fx", "fy", "cx", "cy")})
            except KeyError as exc:
                raise InputError(f"intrinsics mapping lacks {exc.args[0]!r}") from None
        try:
            seq = list(value)
        except TypeError:
            raise InputError(f"cannot read intrinsics from {value!r}") from None
        if len(seq) != 6:
            raise InputError(f"intrinsics need 6 values (width, height, fx, fy, cx, cy), got {len(seq)}")
        w, h = seq[0], seq[1]
        if isinstance(w, float) and w.is_integer():
            w = int(w)
        if isinstance(h, float) and h.is_integer():
            h = int(h)
        return cls(w, h, *seq[2:])

    def scaled(self, k: int) -> Intrinsics:
        """Intrinsics after keeping every ``k``-th row and column starting at 0."""
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 1:
            raise InputError(f"subsampling factor must be a positive integer, got {k!r}")
        return Intrinsics(
            -(-self.width // k), -(-self.height // k),
            self.fx / k, self.fy / k, self.cx / k, self.cy / k,
        )

    def matrix(self) -> np.ndarray:
        """The 3x3 camera matrix ``K``."""
        return np.array([[self.fx, 0, self.cx], [0, self.fy, self.cy], [0, 0, 1.0]])

    def to_dict(self) -> dict:
        return {"width": self.width, "height": self.height, "fx": self.fx,
                "fy": self.fy, "cx": self.cx, "cy": self.cy}


KINECT = Intrinsics(640, 480, 525.0, 525.0, 319.5, 239.5)


def unit_up(v, what: str = "up vector") -> np.ndarray:
    """``v`` as a unit ``(3,)`` float64 vector; :class:`InputError` naming ``what`` otherwise."""
    try:
        a = np.asarray(v, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"{what} must be 3 finite numbers, got {v!r}") from None
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise InputError(f"{what} must be 3 finite numbers, got {v!r}")
    n = float(np.linalg.norm(a))
    if n == 0:
        raise InputError(f"{what} must not be the zero vector")
    return a / n


def _unit_up(up) -> np.ndarray | None:
    if up is None:
        return None
    try:
        v = np.asarray(up, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"up vector must be 3 numbers, got {up!r}") from None
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise InputError(f"up vector must be 3 finite numbers, got {up!r}")
    n = float(np.linalg.norm(v))
    if n == 0:
        raise InputError("up vector must not be zero")
    return v / n


@dataclass(frozen=True, eq=False)
class Cloud:
    """A point cloud, organized as an image.

    Parameters
    ----------
    xyz : ndarray, shape (H, W, 3), float64
        Points in the camera frame, metres; NaN rows are invalid points.  Unorganized clouds are
        stored as ``(1, N, 3)`` with ``organized=False``.
    intrinsics : Intrinsics or None
        The camera that made an organized cloud, when known.
    up : ndarray, shape (3,), or None
        Unit gravity-up vector in the camera frame, when known.
    source : str or None
        The file the cloud came from.
    organized : bool
        Whether neighbouring pixels are neighbouring samples (image-grid neighbours are valid).
    """

    xyz: np.ndarray
    intrinsics: Intrinsics | None = None
    up: np.ndarray | None = None
    source: str | None = None
    organized: bool = True
    _valid: np.ndarray = field(init=False, repr=False)
    _n_valid: int = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        name = self.source or "cloud"
        xyz = self.xyz
        if not isinstance(xyz, np.ndarray):
            try:
                xyz = np.asarray(xyz)
            except (TypeError, ValueError):
                raise InputError(f"{name}: xyz must be an array, got {type(self.xyz).__name__}") from None
        if xyz.ndim != 3 or xyz.shape[2] != 3:
            raise InputError(f"{name}: xyz must have shape (H, W, 3), got {xyz.shape}")
        if xyz.shape[0] == 0 or xyz.shape[1] == 0:
            raise InputError(f"{name}: the cloud is empty (shape {xyz.shape})")
        if not (np.issubdtype(xyz.dtype, np.floating) or np.issubdtype(xyz.dtype, np.integer)):
            raise InputError(f"{name}: xyz must be numeric, got dtype {xyz.dtype}")
        xyz = np.array(xyz, dtype=np.float64, order="C", copy=True)
        bad = ~np.all(np.isfinite(xyz), axis=2)
        xyz[bad] = np.nan
        xyz.setflags(write=False)
        valid = ~bad
        valid.setflags(write=False)
        object.__setattr__(self, "xyz", xyz)
        object.__setattr__(self, "_valid", valid)
        # counted once: segmentation asks for it on every call (a full-image sum, ~0.1 ms)
        object.__setattr__(self, "_n_valid", int(np.count_nonzero(valid)))
        object.__setattr__(self, "up", _unit_up(self.up))
        if self.intrinsics is not None:
            intr = Intrinsics.from_any(self.intrinsics)
            if self.organized and (intr.width, intr.height) != (xyz.shape[1], xyz.shape[0]):
                raise InputError(
                    f"{name}: intrinsics are for {intr.width}x{intr.height} but the cloud is "
                    f"{xyz.shape[1]}x{xyz.shape[0]}"
                )
            object.__setattr__(self, "intrinsics", intr)

    @property
    def shape(self) -> tuple[int, int]:
        """``(H, W)``."""
        return self.xyz.shape[:2]

    def __repr__(self) -> str:
        # the dataclass repr printed the whole (H, W, 3) array: pages of NaN at a prompt
        h, w = self.shape
        up = None if self.up is None else [round(float(v), 3) for v in self.up]
        return (f"Cloud({h}x{w}{'' if self.organized else ' unorganized'}, {self.n_valid} valid "
                f"points, source={self.source!r}, intrinsics={self.intrinsics!r}, up={up})")

    @property
    def valid(self) -> np.ndarray:
        """``(H, W)`` bool mask of valid points."""
        return self._valid

    @property
    def n_valid(self) -> int:
        """Number of valid points."""
        return self._n_valid

    @property
    def depth(self) -> np.ndarray:
        """``(H, W)`` z in metres, NaN where invalid."""
        return self.xyz[:, :, 2]

    def points(self) -> np.ndarray:
        """``(N, 3)`` valid points in row-major pixel order."""
        return self.xyz[self._valid]

    def with_up(self, up) -> Cloud:
        """A copy with another up vector."""
        return Cloud(self.xyz, self.intrinsics, up, self.source, self.organized)

    def require_points(self, minimum: int = 1) -> None:
        """Raise :class:`InputError` unless the cloud has at least ``minimum`` valid points."""
        n = self.n_valid
        if n < minimum:
            what = "no valid point" if n == 0 else f"only {n} valid point{'s' if n > 1 else ''}"
            raise InputError(f"{self.source or 'cloud'}: has {what} (need at least {minimum})")


#: The no-data value of 16-bit depth images (the type's largest): invalid, as 0 is.
NO_DATA_16 = 65535


def depth_to_cloud(
    depth,
    intrinsics,
    depth_scale: float = DEFAULT_DEPTH_SCALE,
    *,
    up=None,
    source: str | None = None,
    max_range: float | None = None,
) -> Cloud:
    """Back-project a depth image into an organized cloud.

    Parameters
    ----------
    depth : array_like, shape (H, W)
        Raw depth values; ``depth / depth_scale`` is metres.  0 and NaN are invalid, and so
        is 65535 in a 16-bit image: the no-data (or saturated) value some drivers and
        exporters write (a RealSense D435i's frames read 65.5 m there at 1000 units per metre,
        hunt45), never a measured depth.
    intrinsics : Intrinsics or 6-sequence or dict
        Camera of the image; its size must be ``W x H``.
    depth_scale : float
        Units per metre (Kinect/OpenNI raw 1000, TUM RGB-D 5000, float metres 1).
    max_range : float, optional
        Depths beyond this many metres become invalid.

    Returns
    -------
    Cloud
    """
    name = source or "depth image"
    try:
        scale = float(depth_scale)
    except (TypeError, ValueError):
        raise InputError(f"{name}: depth scale must be a number, got {depth_scale!r}") from None
    if not math.isfinite(scale) or scale <= 0:
        raise InputError(f"{name}: depth scale must be positive and finite, got {depth_scale!r}")
    d = np.asarray(depth)
    if d.ndim != 2:
        raise InputError(f"{name}: a depth image must be 2-D (H, W), got shape {d.shape}")
    if not (np.issubdtype(d.dtype, np.floating) or np.issubdtype(d.dtype, np.integer)):
        raise InputError(f"{name}: depth must be numeric, got dtype {d.dtype}")
    intr = Intrinsics.from_any(intrinsics)
    if (intr.width, intr.height) != (d.shape[1], d.shape[0]):
        raise InputError(
            f"{name}: intrinsics are for {intr.width}x{intr.height} but the image is "
            f"{d.shape[1]}x{d.shape[0]}"
        )
    z = d.astype(np.float64) / scale
    with np.errstate(invalid="ignore"):
        invalid = ~np.isfinite(z) | (z <= 0)
        if d.dtype == np.uint16:
            invalid |= d == NO_DATA_16
        if max_range is not None:
            invalid |= z > max_range
    z[invalid] = np.nan
    if invalid.all():
        raise InputError(f"{name}: every pixel is invalid (0, NaN, 65535 or out of range)")
    h, w = d.shape
    u = np.arange(w, dtype=np.float64)[None, :]
    v = np.arange(h, dtype=np.float64)[:, None]
    xyz = np.empty((h, w, 3))
    xyz[:, :, 0] = (u - intr.cx) * z / intr.fx
    xyz[:, :, 1] = (v - intr.cy) * z / intr.fy
    xyz[:, :, 2] = z
    return Cloud(xyz, intr, up, source)


def subsample(cloud: Cloud, k: int) -> Cloud:
    """Keep every ``k``-th row and column (the paper's 640x480 -> 160x120 is ``k = 4``).

    The intrinsics are divided by ``k`` so back-projection stays exact.
    """
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 1:
        raise InputError(f"subsampling factor must be a positive integer, got {k!r}")
    if k == 1:
        return cloud
    if not cloud.organized:
        raise InputError(f"{cloud.source or 'cloud'}: cannot subsample an unorganized cloud on a grid")
    intr = cloud.intrinsics.scaled(k) if cloud.intrinsics is not None else None
    return Cloud(cloud.xyz[::k, ::k], intr, cloud.up, cloud.source, True)


def as_path(path) -> Path:
    """``Path`` of a user-given path, with a clear error for anything else."""
    try:
        return Path(path)
    except TypeError:
        raise InputError(f"expected a file path, got {path!r}") from None
