"""The depth-noise model of a sensor, estimated from one organized cloud.

Depth noise decides how far a plane's points scatter, hence how large a normal window, a
region and a merge tolerance must be.  Sensors differ: a Kinect-type structured-light camera
measures disparity, so its noise and its quantisation steps grow as ``z^2``; a laser
triangulation scanner such as SegComp ABW's has uniform depth steps; synthetic data may have
none.  :func:`estimate_noise` measures it from the data itself:

1. **Patches.**  Small ``k x k`` pixel patches on a regular grid (about :data:`MAX_PATCHES` of
   them); only patches whose pixels are all valid are used.
2. **Local plane fits.**  For a pinhole camera a plane is *linear* in inverse depth:
   ``1/z = a + b u + c v``.  Each patch's ``1/z`` is fitted by least squares (one shared hat
   matrix: a single matrix product for all patches) and its residual variance, times ``z^4``,
   is the patch's depth variance (``d(1/z) = -dz / z^2``).
3. **Per depth band.**  Patches are sorted by depth into up to :data:`MAX_BANDS` bands of at
   least :data:`MIN_PER_BAND` patches; a band's noise is a low quantile of its patches' std
   (patches across an edge or a crease have far larger residuals and fall above it), scaled
   to the median of a pure-noise patch.
4. **Model.**  ``sigma(z)^2 = const^2 + (quad z^2)^2`` fitted to the bands by least squares of
   relative errors with both coefficients >= 0.

The model's ``kind`` names the term that dominates at the median depth: ``"z2"``
(disparity-type, Kinect), ``"uniform"`` (constant depth noise or depth steps, laser / ABW) or
``"none"`` (below :data:`NONE_PIXELS` of a pixel's footprint: clean synthetic data).

5. **Waviness** (``NoiseModel.wave``).  Active-stereo sensors (Intel RealSense D4xx, Luxonis
   OAK-D) are smooth pixel to pixel but wavy over a few centimetres: the residual of a plane
   grows with the window it is fitted over, far beyond what the 5 x 5 patches measure.  The
   same fit over :data:`WAVE_WINDOW` x :data:`WAVE_WINDOW` windows (at 640 px width, scaled
   with the image width) on a regular grid, each window's std divided by the model's
   ``sigma`` at its depth; ``wave`` is the :data:`QUANTILE` quantile of these ratios (the
   flatter windows: those across edges fall above it).  White noise gives about 1; the
   Kinect v1 frames 1.5-1.6, mOSD 1.5-2.2, SegComp ABW 1.2-1.4; RealSense and OAK-D frames
   3-4.6 (docs/segmentation.md, "Wavy sensors").  Measured when asked
   (``estimate_noise(cloud, waviness=True)``: region growing asks; the planes' and stair
   fits' callers do not pay for it).  A frame is *wavy* when ``wave`` reaches
   :data:`WAVY_RATIO`; the merge then joins pieces of one face whose union fits a plane
   within ``wave x sigma`` (:func:`planerel.segment.merge.join_wavy`).
"""

from __future__ import annotations

import functools
import math
import weakref
from dataclasses import dataclass, replace

import numpy as np

from planerel.errors import InputError

__all__ = ["NoiseModel", "estimate_noise", "PATCH", "MAX_PATCHES", "MAX_BANDS", "MIN_PER_BAND",
           "NONE_PIXELS", "QUANTILE", "QUANTILE_TO_MEDIAN", "WAVE_WINDOW", "WAVE_MIN_WINDOW",
           "WAVY_RATIO", "WIDE_PATCH", "WIDE_QUANTILE_TO_MEDIAN"]

#: Side of the square patches, pixels.
PATCH = 5
#: Patches sampled at most (the grid's spacing grows with the image).
MAX_PATCHES = 4000
#: Depth bands at most, and fewest patches per band.
MAX_BANDS = 8
MIN_PER_BAND = 60
#: Quantile of the patches' std taken per band (robust to patches across edges) ...
QUANTILE = 0.35
#: ... and the ratio (median / QUANTILE quantile) of the std of pure-noise patches:
#: ``sqrt(chi2.ppf(0.5, 22) / chi2.ppf(0.35, 22))`` for 25-pixel patches (22 degrees of
#: freedom): sqrt(21.337 / 18.940) = 1.0614.
QUANTILE_TO_MEDIAN = 1.0614
#: Noise below this fraction of a pixel's footprint (``z / f``) counts as none.
NONE_PIXELS = 0.02

#: Side of the waviness windows at 640 px image width, pixels (scaled with the width, at least
#: :data:`WAVE_MIN_WINDOW`); windows on a grid of this step (they do not overlap).
WAVE_WINDOW = 25
WAVE_MIN_WINDOW = 7
#: ``wave`` at or above this makes a frame wavy (Kinect-type and laser frames measured 1.2-2.8,
#: most <= 2.2; the active-stereo RealSense / OAK-D frames that lose boxes 3.05-4.6).
WAVY_RATIO = 3.0

#: Patch side of the wide estimate (``RegionGrowParams.wide_noise_window``, off by default) and
#: its median / QUANTILE-quantile ratio of a pure-noise patch's std (222 degrees of freedom:
#: ``sqrt(chi2.ppf(0.5, 222) / chi2.ppf(0.35, 222))``).
WIDE_PATCH = 15
WIDE_QUANTILE_TO_MEDIAN = 1.0186

#: Model kinds.
KINDS = ("z2", "uniform", "none")


@dataclass(frozen=True)
class NoiseModel:
    """Depth noise ``sigma(z) = sqrt(const^2 + (quad z^2)^2)`` metres at depth ``z``.

    Parameters
    ----------
    kind : {"z2", "uniform", "none"}
        The term that dominates at ``z_median`` (see the module docstring).
    const : float
        Constant depth std, metres.
    quad : float
        Coefficient of the ``z^2`` term, 1/metre (Kinect: about 0.0012 plus quantisation).
    z_median, z_min, z_max : float
        Median and range of the patches' depths, metres.
    pixel_angle : float
        Angular size of one pixel, radians (``1 / f``); a pixel spans ``z * pixel_angle`` m.
    n_patches : int
        Patches the model was fitted to (0: too few valid patches; the model is then ``none``
        with zero noise, and ``reliable`` is False).
    bands : tuple of (float, float)
        ``(depth, std)`` of each depth band, metres.
    wave : float
        Waviness: the plane-fit std over ``wave_window`` windows relative to ``sigma`` at
        their depth (the :data:`QUANTILE` quantile over the windows); 0 when not measured
        (fewer than :data:`MIN_PER_BAND` complete windows).
    wave_window : int
        Side of those windows, pixels (0: not measured).
    """

    kind: str
    const: float
    quad: float
    z_median: float
    z_min: float
    z_max: float
    pixel_angle: float
    n_patches: int
    bands: tuple = ()
    wave: float = 0.0
    wave_window: int = 0

    @property
    def wavy(self) -> bool:
        """Whether the depth is wavy (``wave >= WAVY_RATIO``, measured on a reliable model)."""
        return self.reliable and self.kind != "none" and self.wave >= WAVY_RATIO

    @property
    def reliable(self) -> bool:
        """Whether enough patches were measured."""
        return self.n_patches >= MIN_PER_BAND

    def sigma(self, z):
        """Depth std (m) at depth ``z`` (m), any shape."""
        z = np.asarray(z, dtype=np.float64)
        return np.sqrt(self.const ** 2 + (self.quad * z * z) ** 2)

    def pixels(self, z=None) -> float:
        """Noise in pixel footprints, ``sigma(z) / (z * pixel_angle)``, at ``z`` (default the
        median depth)."""
        z = self.z_median if z is None else float(z)
        if not z > 0:
            return 0.0
        return float(self.sigma(z)) / (z * self.pixel_angle)

    def to_dict(self) -> dict:
        """JSON-ready summary (metres; ``sigma_median`` at the median depth)."""
        return {"kind": self.kind, "const_m": round(self.const, 7), "quad_per_m": round(self.quad, 7),
                "sigma_median_m": round(float(self.sigma(self.z_median)), 7),
                "noise_pixels": round(self.pixels(), 4), "z_median_m": round(self.z_median, 4),
                "z_range_m": [round(self.z_min, 4), round(self.z_max, 4)],
                "n_patches": self.n_patches, "wave": round(self.wave, 4),
                "wave_window": self.wave_window, "pixel_angle": float(f"{self.pixel_angle:.6g}")}

    def describe(self) -> str:
        """One line: kind, sigma at the median depth (mm and pixels), coefficients."""
        return (f"{self.kind} (sigma {1000 * float(self.sigma(self.z_median)):.2f} mm = "
                f"{self.pixels():.2f} px at {self.z_median:.2f} m; const {1000 * self.const:.3f} mm, "
                f"quad {self.quad:.5f}/m; {self.n_patches} patches)")


@functools.lru_cache(maxsize=8)
def _slopes(k: int) -> np.ndarray:
    """(2, k*k): the centred pixel coordinates ``u``, ``v`` of a k x k patch, unit length.  With
    the constant, they are an orthogonal basis of the planes ``a + b u + c v``.  Cached per
    ``k`` (read-only)."""
    v, u = np.mgrid[0:k, 0:k]
    q = np.stack([u.ravel() - (k - 1) / 2, v.ravel() - (k - 1) / 2]).astype(np.float64)
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    q.setflags(write=False)
    return q


#: ``{cloud: {(patch, max_patches, waviness): NoiseModel}}``: a cloud's points are read-only
#: and the estimate is a function of them, so a classify (the segmentation's two growings, the
#: planes, the stair fit, the relations each ask) measures it once (eye62)
_MEMO: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def estimate_noise(cloud, *, patch: int = PATCH, max_patches: int = MAX_PATCHES,
                   waviness: bool = False) -> NoiseModel:
    """Estimate the depth-noise model of an organized cloud (measured once a cloud and
    arguments: the model of an earlier call is returned; without ``waviness`` an earlier
    model measured with it, its ``wave`` set to 0, as this call would measure it).

    Parameters
    ----------
    cloud : Cloud
        Organized ``(H, W, 3)`` cloud, metres, NaN invalid.
    patch : int
        Patch side in pixels (>= 3).
    max_patches : int
        Patches sampled at most.
    waviness : bool
        Also measure the waviness (``NoiseModel.wave``; about 1 ms at 640x480).  Region
        growing asks for it; without it ``wave`` is 0 (not measured).

    Returns
    -------
    NoiseModel
        With ``n_patches == 0`` (kind ``"none"``, ``reliable`` False) when fewer than
        :data:`MIN_PER_BAND` complete patches exist.

    Raises
    ------
    InputError
        An unorganized cloud, or a bad ``patch`` / ``max_patches``.
    """
    if not getattr(cloud, "organized", False):
        raise InputError("noise estimate: needs an organized cloud (image-grid neighbours)")
    if isinstance(patch, bool) or not isinstance(patch, (int, np.integer)) or patch < 3:
        raise InputError(f"noise estimate: patch must be an integer >= 3, got {patch!r}")
    if isinstance(max_patches, bool) or not isinstance(max_patches, (int, np.integer)) \
            or max_patches < 1:
        raise InputError(f"noise estimate: max_patches must be a positive integer, got {max_patches!r}")
    try:
        memo = _MEMO.setdefault(cloud, {})
    except TypeError:  # not weakly referenceable: measured every time
        memo = {}
    key = (int(patch), int(max_patches), bool(waviness))
    got = memo.get(key)
    if got is None and not waviness:
        wavy = memo.get((key[0], key[1], True))
        if wavy is not None:
            got = memo[key] = replace(wavy, wave=0.0, wave_window=0)
    if got is None:
        got = memo[key] = _estimate(cloud, int(patch), int(max_patches), bool(waviness))
    return got


def _estimate(cloud, patch: int, max_patches: int, waviness: bool) -> NoiseModel:
    """:func:`estimate_noise`'s measurement (arguments checked)."""
    from planerel.segment.normals import pixel_angle

    xyz = cloud.xyz
    h, w, _ = xyz.shape
    pa = pixel_angle(xyz, cloud.intrinsics)
    empty = NoiseModel("none", 0.0, 0.0, 0.0, 0.0, 0.0, pa, 0)
    if h < patch or w < patch:
        return empty
    step = max(patch, int(math.ceil(math.sqrt((h - patch + 1) * (w - patch + 1) / max_patches))))
    # the patches' plane fits in one compiled pass over the image (no window copies)
    from planerel.segment._noise_kernels import band_quantiles, patch_noise, sorted_median

    zc, sd = patch_noise(xyz[:, :, 2], int(step), int(patch),
                         _slopes(patch))
    n = len(zc)
    if n < MIN_PER_BAND:
        return empty
    order = np.argsort(zc, kind="stable")
    zc, sd = zc[order], sd[order]
    nb = max(1, min(MAX_BANDS, n // MIN_PER_BAND))
    size = n // nb  # equal bands of consecutive depths (the last n % nb patches are left out)
    zc, sd = zc[:nb * size], sd[:nb * size]
    # the bands' medians (np.median of sorted rows)
    bz_a = np.array([sorted_median(zc, b * size, (b + 1) * size) for b in range(nb)])
    const, quad = 1.0, 0.0
    for _ in range(2):
        # each patch's std carried to its band's depth under the current model's shape (the
        # first pass assumes none), so that a band spanning a wide range of depths -- or a gap
        # between two surfaces -- is not biased towards its nearer patches; per band the
        # QUANTILE quantile (np.quantile's, compiled)
        bs_a = band_quantiles(zc, sd, bz_a, nb, size, const ** 2, quad, QUANTILE,
                              QUANTILE_TO_MEDIAN)
        const, quad = _fit(bz_a, bs_a)
        if const == 0 and quad == 0:
            break
    bz, bs = bz_a.tolist(), bs_a.tolist()
    zmed = float(sorted_median(zc, 0, len(zc)))
    model = NoiseModel("none", const, quad, zmed, float(zc[0]), float(zc[-1]), pa, n,
                       tuple(zip(bz, bs, strict=True)))
    if model.pixels() < NONE_PIXELS:
        kind = "none"
    elif (quad * zmed * zmed) ** 2 > const ** 2:
        kind = "z2"
    else:
        kind = "uniform"
    wave, wk = 0.0, 0
    if waviness and kind != "none":
        wave, wk = _waviness(xyz[:, :, 2], w, const, quad)
    return NoiseModel(kind, const, quad, zmed, model.z_min, model.z_max, pa, n, model.bands,
                      wave, wk)


def _waviness(z, width: int, const: float, quad: float) -> tuple[float, int]:
    """``(wave, window)``: the :data:`QUANTILE` quantile over non-overlapping windows of
    :data:`WAVE_WINDOW` px (scaled with ``width`` / 640) of their plane-fit std relative to
    the model ``sqrt(const^2 + (quad z^2)^2)`` at their depth; ``(0.0, 0)`` with fewer than
    :data:`MIN_PER_BAND` complete windows.

    Parameters
    ----------
    z : (H, W) float array
        Depth, metres (NaN invalid).
    width : int
        Image width, pixels.
    const, quad : float
        The fitted small-patch model.
    """
    from planerel.segment._noise_kernels import patch_noise

    h = z.shape[0]
    k = max(WAVE_MIN_WINDOW, int(round(WAVE_WINDOW * width / 640.0)))
    if h < k or width < k:
        return 0.0, 0
    zc, sd = patch_noise(z, int(k), int(k), _slopes(k))
    if len(zc) < MIN_PER_BAND:
        return 0.0, 0
    sig = np.sqrt(const * const + (quad * zc * zc) ** 2)
    ok = sig > 0
    if ok.sum() < MIN_PER_BAND:
        return 0.0, 0
    return float(np.quantile(sd[ok] / sig[ok], QUANTILE)), k


def _fit(z: np.ndarray, s: np.ndarray) -> tuple[float, float]:
    """``(const, quad)`` >= 0 minimising ``sum(((const^2 + quad^2 z^4) / s^2 - 1)^2)``."""
    s2 = np.maximum(s * s, 1e-30)
    a = np.column_stack([1.0 / s2, z ** 4 / s2])
    t = np.ones(len(z))
    best = None
    cands = []
    if len(z) >= 2:
        sol, *_ = np.linalg.lstsq(a, t, rcond=None)
        if sol[0] >= 0 and sol[1] >= 0:
            cands.append((sol[0], sol[1]))
    for col in (0, 1):  # one term alone
        x = a[:, col]
        c = float(x @ t / max(x @ x, 1e-300))
        cands.append((c, 0.0) if col == 0 else (0.0, c))
    for c0, c1 in cands:
        err = float(np.sum((a @ np.array([c0, c1]) - t) ** 2))
        if best is None or err < best[0]:
            best = (err, c0, c1)
    return math.sqrt(max(best[1], 0.0)), math.sqrt(max(best[2], 0.0))
