"""Sensor-realistic depth profiles for the synthetic scenes: structured light and time of flight.

Two models turn the exact ray-cast depth of a scene into what a real range camera writes.  Both
work on the image as written (any subsampling of the physical sensor); the noise is that of the
physical sensor's pixels.  The sources of every number are in ``docs/synthetic-world.md``.

:class:`StructuredLight` (Kinect v1 / PrimeSense / Xtion)
    Depth comes from the disparity ``d = f b / z`` between the camera and a projector ``b`` metres
    to its side (Khoshelham & Elberink 2012).  The disparity gets Gaussian noise of
    ``disparity_noise`` pixels and is quantised to ``disparity_step`` (1/8) pixel (Konolige &
    Mihelich, ROS ``kinect_calibration``), so the depth error grows with ``z**2``:
    ``sigma_z = z**2 / (f b) * sqrt(disparity_noise**2 + disparity_step**2 / 12)`` (the default
    0.043 px gives ``1.43e-3 z**2`` m, Khoshelham & Elberink's figure).  Missing depth: in the
    projector's shadow (surfaces the camera sees but the projector does not light, found exactly
    along each image row: the rows are the epipolar lines), on the far side of depth edges, at
    grazing incidence, out of range, and a few at random.  Flying pixels: at occluding edges some
    pixels take a depth between the near and the far surface.

:class:`TimeOfFlight` (Kinect v2; :meth:`TimeOfFlight.laser` for a laser scanner)
    Depth is measured along each pixel's ray with an axial noise
    ``sigma_z = a0 + a1 z + a2 z**2 + a3 z**1.5 theta**2 / (pi/2 - theta)**2`` (Fankhauser et al.
    2015; ``theta`` the incidence angle), no quantisation beyond the depth unit, no projector
    shadow (the illumination is next to the lens).  Mixed ("flying") pixels at occluding edges are
    common; missing depth at grazing incidence, out of range, and a few at random.

Both return the measured depth in depth units and a mask of the flying pixels (valid depth that
lies on no surface: the ground truth labels them -1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planerel.errors import InputError
from planerel.synth.generator import _number as _num  # one checker for the generator's parameters

__all__ = [
    "StructuredLight",
    "TimeOfFlight",
    "PROFILES",
    "sensor_profile",
    "projector_shadow",
    "edge_neighbours",
    "window_average",
]


def _check_common(s) -> None:
    _num("sensor depth unit", s.depth_unit, 0.0, 0.1, lo_strict=True)
    _num("sensor min range", s.min_range, 0.0)
    _num("sensor max range", s.max_range, 0.0, lo_strict=True)
    if s.max_range <= s.min_range:
        raise InputError(f"sensor max range {s.max_range} must exceed min range {s.min_range}")
    if s.max_range / s.depth_unit > 65534:
        raise InputError(f"sensor max range {s.max_range} m does not fit 16 bits at a depth unit "
                         f"of {s.depth_unit} m")
    for name in ("dropout", "edge_dropout", "flying"):
        _num(f"sensor {name.replace('_', ' ')}", getattr(s, name), 0.0, 1.0)
    _num("sensor edge jump", s.edge_jump, 0.0, lo_strict=True)
    if s.grazing_deg is not None:
        _num("sensor grazing angle", s.grazing_deg, 0.0, 90.0, lo_strict=True)


def edge_neighbours(z: np.ndarray, jump: float, surface: np.ndarray | None = None):
    """For every pixel, the 4-neighbour depth that differs most from its own, when the difference
    exceeds ``jump`` (and, with ``surface``, the neighbour lies on another surface: a steep
    plane seen at grazing angle is then no edge however fast its depth changes).

    Parameters
    ----------
    z : ndarray, shape (H, W)
        Depth in metres; NaN or inf = nothing hit (never an edge partner).
    jump : float
    surface : ndarray, shape (H, W), int, optional
        Surface (plane) index per pixel.

    Returns
    -------
    other : ndarray, shape (H, W), float64
        The neighbour's depth (NaN where no neighbour jumps).
    far_side : ndarray, shape (H, W), bool
        The pixel lies behind some neighbour by more than ``jump`` (the occluded side).
    """
    zz = np.where(np.isfinite(z), z, np.nan)
    h, w = zz.shape
    pad = np.full((h + 2, w + 2), np.nan)
    pad[1:-1, 1:-1] = zz
    best = np.zeros((h, w))
    other = np.full((h, w), np.nan)
    far_side = np.zeros((h, w), dtype=bool)
    if surface is not None:
        spad = np.full((h + 2, w + 2), -2, dtype=np.int64)
        spad[1:-1, 1:-1] = surface
    for dv, du in ((-1, 0), (1, 0), (0, -1), (0, 1)):
        nb = pad[1 + dv:h + 1 + dv, 1 + du:w + 1 + du]
        with np.errstate(invalid="ignore"):
            diff = np.abs(nb - zz)
            other_surface = (True if surface is None
                             else spad[1 + dv:h + 1 + dv, 1 + du:w + 1 + du] != surface)
            take = (diff > np.maximum(best, jump)) & other_surface
            far_side |= ((zz - nb) > jump) & other_surface
        take &= np.isfinite(diff)
        best = np.where(take, diff, best)
        other = np.where(take, nb, other)
    return other, far_side



def _box_weights(width: float) -> np.ndarray:
    """1-D weights of a box ``width`` pixels wide centred on pixel 0: the overlap of each pixel
    ``[i - 1/2, i + 1/2]`` with ``[-width/2, width/2]`` (a fractional width gives partial end
    weights), offsets ``-r..r``."""
    half = width / 2.0
    r = max(0, math.ceil(half - 0.5))
    i = np.arange(-r, r + 1, dtype=np.float64)
    return np.clip(np.minimum(i + 0.5, half) - np.maximum(i - 0.5, -half), 0.0, None)


def window_average(z: np.ndarray, width: float, jump: float) -> np.ndarray:
    """Depth after averaging the disparity ``1/z`` over a ``width`` x ``width`` pixel window
    (pixels of the image as given, fractional widths allowed) on continuous surfaces: a
    neighbour ``k`` pixels away (Chebyshev) takes part when its depth differs from the centre's by
    at most ``k * jump`` (so never across an occluding edge).

    This is what a block-matching (structured-light or stereo) sensor measures: the disparity
    of a plane is linear in the image coordinates, so a plane stays exactly the same plane,
    while a crease (a box's edge) is rounded over half a window on each side.

    Parameters
    ----------
    z : ndarray, shape (H, W)
        Depth in metres; NaN or inf = nothing hit (takes no part, stays as it is).
    width : float
        Window width in pixels; <= 1 returns ``z`` unchanged.
    jump : float
        Metres per pixel of offset.

    Returns
    -------
    ndarray, shape (H, W), float64
    """
    z = np.asarray(z, dtype=np.float64)
    if width <= 1.0:
        return z
    wt = _box_weights(float(width))
    r = (len(wt) - 1) // 2
    h, w = z.shape
    hit = np.isfinite(z) & (z > 0)
    zz = np.where(hit, z, np.nan)
    pad = np.full((h + 2 * r, w + 2 * r), np.nan)
    pad[r:r + h, r:r + w] = zz
    num = np.zeros((h, w))
    den = np.zeros((h, w))
    with np.errstate(invalid="ignore", divide="ignore"):
        for dv in range(-r, r + 1):
            for du in range(-r, r + 1):
                nb = pad[r + dv:r + dv + h, r + du:r + du + w]
                ok = np.abs(nb - zz) <= jump * max(1, abs(dv), abs(du))  # False at NaN
                wk = wt[dv + r] * wt[du + r]
                num += np.where(ok, wk / nb, 0.0)
                den += np.where(ok, wk, 0.0)
        out = np.where(hit & (num > 0), den / num, z)
    return out


def _draws(depth_true, rng: np.random.Generator):
    """The random draws both sensor models take, in one fixed order (so a seed gives the same
    frame): ``z`` (H, W) float64, standard normal ``noise`` and uniform ``drop``, ``edge``,
    ``mix`` draws (H, W), ``hit`` (H, W) bool where a surface was hit, ``zt`` = z with 1.0 at
    misses (safe to divide by)."""
    z = np.asarray(depth_true, dtype=np.float64)
    noise = rng.standard_normal(z.shape)
    drop_draw = rng.random(z.shape)
    edge_draw = rng.random(z.shape)
    mix_draw = rng.random(z.shape)
    hit = np.isfinite(z)
    return z, noise, drop_draw, edge_draw, mix_draw, hit, np.where(hit, z, 1.0)

def _flying_edges(z, zt, hit, edge_draw, mix_draw, edge_jump: float, flying: float, surface):
    """Flying pixels at depth edges, shared by both sensor models: ``(zt, fly, far_side)``
    with ``zt`` moved a uniform share of the way to the other side of the edge where ``fly``
    (``edge_draw`` is that share; flying pixels never use it for dropping)."""
    other, far_side = edge_neighbours(z, edge_jump, surface)
    edge = np.isfinite(other)
    fly = hit & edge & (mix_draw < flying)
    t = np.where(fly, edge_draw, 0.0)
    zt = np.where(fly, zt + t * (np.where(edge, other, zt) - zt), zt)
    return zt, fly, far_side


def _kept(sensor, units, hit, cos, far_side, fly, edge_draw, drop_draw, shadow=None):
    """The frame as written, shared by both sensor models: ``units`` where the sensor
    returns a depth (in range, not grazing, not in ``shadow``, not dropped at the far side
    of an edge or at random), 0 elsewhere; ``(uint16 (H, W), flying valid pixels (H, W))``."""
    zq = units * sensor.depth_unit
    ok = hit & (zq >= sensor.min_range) & (zq <= sensor.max_range)
    if sensor.grazing_deg is not None:
        ok &= np.asarray(cos, dtype=float) >= math.cos(math.radians(sensor.grazing_deg))
    if shadow is not None:
        ok &= ~shadow
    ok &= ~(far_side & ~fly & (edge_draw < sensor.edge_dropout))
    ok &= drop_draw >= sensor.dropout
    return np.where(ok, units, 0).astype(np.uint16), fly & ok


def _as_dict(sensor) -> dict:
    """``{"profile": ..., field: value ...}`` of a sensor model (tuples as lists)."""
    d = {"profile": sensor.profile}
    d.update({f: (list(v) if isinstance(v := getattr(sensor, f), tuple) else v)
              for f in sensor.__dataclass_fields__})
    return d


def projector_shadow(z: np.ndarray, fx: float, baseline: float) -> np.ndarray:
    """Pixels the camera sees but a projector ``baseline`` metres to its right (along the image
    +x axis; negative = to its left) does not light.

    Camera and projector are rectified (same orientation, offset along x), so each image row is
    an epipolar line: the point seen at column ``u`` with depth ``z`` appears in the projector at
    ``u - fx * baseline / z``.  Two points of a row swap their order in the projector exactly
    when the nearer one hides the farther from it, so (projector to the right) pixel ``u`` is in
    shadow when some pixel to its right has a smaller projector column.  Only surfaces the camera
    sees can cast a shadow.

    Parameters
    ----------
    z : ndarray, shape (H, W)
        True depth in metres, NaN = nothing hit.
    fx : float
        Focal length of the image as written, pixels.
    baseline : float
        Camera-to-projector offset, metres.

    Returns
    -------
    ndarray, shape (H, W), bool
    """
    h, w = z.shape
    u = np.arange(w, dtype=np.float64)[None, :]
    hit = np.isfinite(z)
    with np.errstate(divide="ignore", invalid="ignore"):
        up = np.where(hit, u - fx * baseline / np.where(hit, z, 1.0), np.nan)
    if baseline < 0:  # mirror: the same sweep from the other side
        return projector_shadow(z[:, ::-1], fx, -baseline)[:, ::-1]
    # minimum projector column of everything to the right of each pixel
    filled = np.where(hit, up, np.inf)
    right_min = np.minimum.accumulate(filled[:, ::-1], axis=1)[:, ::-1]
    after = np.full((h, w), np.inf)
    after[:, :-1] = right_min[:, 1:]
    eps = 1e-9 * max(1.0, fx)
    return hit & (up > after + eps)


@dataclass(frozen=True)
class StructuredLight:
    """Structured-light depth sensor (Kinect v1 / PrimeSense), see the module docstring.

    Parameters
    ----------
    focal_px : float
        Focal length of the physical sensor's pixels (525 px at 640x480).
    baseline : float
        Camera-projector baseline, metres (Kinect: 0.075); the projector is to the camera's
        right (image +x) when positive, to its left when negative.  Default -0.075: the shadows
        then fall right of near objects, as in the real Kinect frames of ``../shared/data``
        (116 of 161 gaps at depth edges in the three TIFF frames lie right of the nearer side).
    disparity_step : float
        Disparity quantisation, pixels (Kinect: 1/8); 0 = none.
    disparity_noise : float
        Standard deviation of the Gaussian disparity error, pixels.
    depth_unit : float
        Depth resolution of the written image, metres.
    min_range, max_range : float
        Metres.
    dropout : float
        Probability that a pixel is missing at random.
    edge_dropout : float
        Probability that a pixel on the far side of a depth edge is missing.
    edge_jump : float
        A 4-neighbour depth difference above this (metres) is a depth edge.
    flying : float
        Probability that a pixel next to a depth edge (either side, not already missing) becomes a
        flying pixel, its depth uniform between its own and its neighbour's.
    grazing_deg : float or None
        Missing beyond this incidence angle (degrees from the surface normal).
    shadows : bool
        Missing depth in the projector's shadow.
    window : float
        Width, in pixels of the physical sensor (``focal_px``), of the square block-matching
        window over which the disparity is averaged on continuous surfaces before the noise
        (:func:`window_average`): planes stay planes, a box's edges are rounded.  0 = off (the
        behaviour before sensor40).  Kinect v1: 9 (Konolige & Mihelich's 9x9 correlation
        window); 13 matches the rounded box edges of real Kinect frames (mOSD) at 640x480:
        docs/synthetic-world.md, "Block-matching window".
    """

    focal_px: float = 525.0
    baseline: float = -0.075
    disparity_step: float = 0.125
    disparity_noise: float = 0.043
    depth_unit: float = 0.001
    min_range: float = 0.45
    max_range: float = 4.5
    dropout: float = 0.005
    edge_dropout: float = 0.5
    edge_jump: float = 0.05
    flying: float = 0.2
    grazing_deg: float | None = 80.0
    shadows: bool = True
    window: float = 0.0

    profile = "structured-light"

    def __post_init__(self) -> None:
        _num("sensor focal length", self.focal_px, 0.0, lo_strict=True)
        _num("sensor baseline", self.baseline, -1.0, 1.0)
        if self.baseline == 0:
            raise InputError("sensor baseline must not be 0 for a structured-light sensor")
        _num("sensor disparity step", self.disparity_step, 0.0, 1.0)
        _num("sensor disparity noise", self.disparity_noise, 0.0, 5.0)
        _num("sensor window", self.window, 0.0, 64.0)
        _check_common(self)
        if not isinstance(self.shadows, (bool, np.bool_)):
            raise InputError(f"sensor shadows must be True or False, got {self.shadows!r}")

    def axial_sigma(self, z, cos_incidence=None) -> np.ndarray:
        """Standard deviation of the depth error at true depth ``z`` (metres), quantisation
        included (first order: ``z**2 / (f b) * sigma_disparity``)."""
        z = np.asarray(z, dtype=float)
        sd = math.sqrt(self.disparity_noise ** 2 + self.disparity_step ** 2 / 12.0)
        return z * z / (self.focal_px * abs(self.baseline)) * sd

    def apply(self, depth_true, cos_incidence, intrinsics, rng: np.random.Generator,
              surface=None):
        """Measured depth of a scene.

        Parameters
        ----------
        depth_true : ndarray, shape (H, W)
            True depth in metres, NaN where nothing is hit.
        cos_incidence : ndarray, shape (H, W)
            ``|cos|`` of the angle between each ray and the surface normal.
        intrinsics : Intrinsics
            Camera of the image as written (its ``fx`` places the projector shadow).
        rng : numpy.random.Generator
            Draws four ``(H, W)`` arrays, always in the same order.
        surface : ndarray, shape (H, W), int, optional
            Surface index per pixel: depth edges are only between different surfaces.

        Returns
        -------
        units : ndarray, shape (H, W), uint16
            Depth in ``depth_unit``, 0 = missing.
        flying : ndarray, shape (H, W), bool
            Valid pixels whose depth lies on no surface.
        """
        z, noise, drop_draw, edge_draw, mix_draw, hit, zt = _draws(depth_true, rng)
        fb = self.focal_px * abs(self.baseline)
        if self.window > 0:  # the matching window, in pixels of the image as written
            zw = window_average(z, self.window * intrinsics.fx / self.focal_px, self.edge_jump)
            zt = np.where(hit, zw, zt)
        # flying pixels: a depth between the two sides of the edge
        zt, fly, far_side = _flying_edges(z, zt, hit, edge_draw, mix_draw, self.edge_jump,
                                          self.flying, surface)
        disp = fb / zt + self.disparity_noise * noise
        if self.disparity_step > 0:
            disp = np.round(disp / self.disparity_step) * self.disparity_step
            disp = np.maximum(disp, self.disparity_step)
        disp = np.maximum(disp, 1e-6)
        units = np.round(fb / disp / self.depth_unit)
        shadow = projector_shadow(z, intrinsics.fx, self.baseline) if self.shadows else None
        return _kept(self, units, hit, cos_incidence, far_side, fly, edge_draw, drop_draw,
                     shadow)

    def to_dict(self) -> dict:
        return _as_dict(self)


@dataclass(frozen=True)
class TimeOfFlight:
    """Time-of-flight depth sensor (Kinect v2 by default), see the module docstring.

    Parameters
    ----------
    sigma_coeffs : (a0, a1, a2, a3)
        Axial noise ``a0 + a1 z + a2 z**2 + a3 z**1.5 theta**2 / (pi/2 - theta)**2`` metres
        (Fankhauser et al. 2015: 1.5e-3, -0.5e-3, 0.3e-3, 0.1e-3), at least ``min_sigma``.
    min_sigma : float
        Floor of the noise std, metres.
    depth_unit, min_range, max_range, dropout, edge_dropout, edge_jump, flying, grazing_deg
        As for :class:`StructuredLight`.
    """

    sigma_coeffs: tuple = (0.0015, -0.0005, 0.0003, 0.0001)
    min_sigma: float = 0.0005
    depth_unit: float = 0.001
    min_range: float = 0.5
    max_range: float = 4.5
    dropout: float = 0.002
    edge_dropout: float = 0.1
    edge_jump: float = 0.05
    flying: float = 0.5
    grazing_deg: float | None = 82.0

    profile = "time-of-flight"

    def __post_init__(self) -> None:
        try:
            coeffs = tuple(float(c) for c in self.sigma_coeffs)
        except (TypeError, ValueError):
            raise InputError(f"sensor sigma_coeffs must be 4 numbers, got {self.sigma_coeffs!r}") from None
        if len(coeffs) != 4 or not all(math.isfinite(c) for c in coeffs):
            raise InputError(f"sensor sigma_coeffs must be 4 finite numbers, got {self.sigma_coeffs!r}")
        object.__setattr__(self, "sigma_coeffs", coeffs)
        _num("sensor min sigma", self.min_sigma, 0.0, 1.0)
        _check_common(self)

    @classmethod
    def laser(cls) -> TimeOfFlight:
        """A tilting 2-D laser scanner (Hokuyo UTM-30LX class): 10 mm constant noise, 0.1-30 m,
        mixed pixels at edges, no angle dependence."""
        return cls(sigma_coeffs=(0.01, 0.0, 0.0, 0.0), min_sigma=0.0, min_range=0.1,
                   max_range=30.0, dropout=0.001, edge_dropout=0.0, flying=0.5, grazing_deg=85.0)

    def axial_sigma(self, z, cos_incidence=None) -> np.ndarray:
        """Standard deviation of the depth error (metres) at depth ``z`` and incidence
        ``acos(cos_incidence)`` (default head-on)."""
        z = np.asarray(z, dtype=float)
        a0, a1, a2, a3 = self.sigma_coeffs
        s = a0 + a1 * z + a2 * z * z
        if cos_incidence is not None and a3:
            theta = np.arccos(np.clip(np.asarray(cos_incidence, dtype=float), 0.0, 1.0))
            theta = np.minimum(theta, math.radians(89.0))
            s = s + a3 * z ** 1.5 * theta ** 2 / (math.pi / 2 - theta) ** 2
        return np.maximum(s, self.min_sigma)

    def apply(self, depth_true, cos_incidence, intrinsics, rng: np.random.Generator,
              surface=None):
        """Measured depth of a scene; same arguments and results as :meth:`StructuredLight.apply`
        (``intrinsics`` is unused).  The noise std is that of z (the model was measured on z)."""
        z, noise, drop_draw, edge_draw, mix_draw, hit, zt = _draws(depth_true, rng)
        zt, fly, far_side = _flying_edges(z, zt, hit, edge_draw, mix_draw, self.edge_jump,
                                          self.flying, surface)
        cos = np.asarray(cos_incidence, dtype=float)
        zn = zt + self.axial_sigma(zt, cos) * noise
        units = np.round(np.maximum(zn, 1e-3) / self.depth_unit)
        return _kept(self, units, hit, cos, far_side, fly, edge_draw, drop_draw)

    def to_dict(self) -> dict:
        return _as_dict(self)


#: Sensor profiles by name (``planerel dataset synth --sensor``); ``basic`` is the original
#: :class:`planerel.synth.generator.SensorModel` of the paper-sized set.
PROFILES = ("basic", "structured-light", "tof", "laser")


def sensor_profile(name: str):
    """The sensor of a profile name (one of :data:`PROFILES`)."""
    if name == "basic":
        from planerel.synth.generator import SensorModel

        return SensorModel()
    if name == "structured-light":
        return StructuredLight()
    if name == "tof":
        return TimeOfFlight()
    if name == "laser":
        return TimeOfFlight.laser()
    raise InputError(f"unknown sensor profile {name!r}; choose one of {', '.join(PROFILES)}")
