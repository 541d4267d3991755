"""Region-growing settings derived from the sensor's measured depth noise (``adapt=True``, the
default).

:func:`adapt_params` turns the :class:`~planerel.segment.noise.NoiseModel` of one cloud into
concrete values for the parameters left at ``"auto"``:

- **Minimum region size** in physical units: a region must be at least
  :data:`MIN_SIDE_SIGMAS` depth-noise stds on a side at the scene's median depth, i.e. an area
  of ``(20 sigma(z))^2`` m^2; in pixels ``(20 p)^2`` with ``p = sigma(z) / (z / f)`` the noise
  in pixel footprints.  A resolution floor (:data:`FLOOR_SCALE` x the paper's 90 px at 160x120
  scaled with the pixel count: 360 px at 640x480) keeps regions large enough for their normals
  to be trusted.  Then times ``min_region_scale``.
- **Normal window.**  Disparity-type noise (kind ``"z2"``) grows faster than the pixel
  footprint, so the window grows with depth beyond ``reference_depth`` (2 m), as before.  With
  uniform depth noise or depth steps (kind ``"uniform"``: laser triangulation, SegComp ABW) the
  window is the same at every depth and spans a depth step's terrace: a step of
  ``sqrt(12) sigma`` on a 45-degree face is ``sqrt(12) p`` pixels wide, so
  ``smooth = radius = max(nominal, round(sqrt(12) p))``.
- Kind ``"none"`` (clean data) or too few measurable patches: the fixed defaults.

With ``wide_noise_window`` (off by default; noise58) the same rule is also applied, for every
kind, to the noise measured over :data:`~planerel.segment.noise.WIDE_PATCH` px patches (noise
correlated over a few pixels, which the 5 px patches miss), and the larger window is used.

Values given explicitly are never changed.  Presets (``kinect``, ``structured-light``) turn the
adaptation off.
"""

from __future__ import annotations

import dataclasses
import math

from planerel.segment.params import RegionGrowParams, scaled_min_region_size

__all__ = ["adapt_params", "MIN_SIDE_SIGMAS", "FLOOR_SCALE", "MAX_WINDOW", "FIXED_REFERENCE_DEPTH"]

#: A region's side in depth-noise stds at least (the minimum area is this squared, in sigma^2).
MIN_SIDE_SIGMAS = 20.0
#: The resolution floor of the minimum region size, as a factor of the paper's size scaled with
#: the pixel count.
FLOOR_SCALE = 0.25
#: Largest adapted normal window (smooth and radius), pixels.
MAX_WINDOW = 8
#: ``reference_depth`` of the fixed (non-adapted) defaults and of kind ``"z2"``, metres.
FIXED_REFERENCE_DEPTH = 2.0


def adapt_params(p: RegionGrowParams, model, shape, wide=None) -> tuple[RegionGrowParams, dict]:
    """Concrete parameters for one cloud.

    Parameters
    ----------
    p : RegionGrowParams
        Parameters as given; only ``"auto"`` values are set here.
    model : NoiseModel or None
        The cloud's estimated noise (None: unorganized cloud, nothing measured).
    shape : (int, int)
        ``(H, W)`` of the cloud.
    wide : NoiseModel or None
        The noise measured over ``WIDE_PATCH`` px patches; used only with
        ``p.wide_noise_window``.

    Returns
    -------
    (RegionGrowParams, dict)
        The parameters to run with (``reference_depth`` resolved, ``min_region_size`` and the
        normal window set when adapted) and what was chosen (for ``Segmentation.info``).
    """
    from planerel.segment.normals import auto_normal_scale

    h, w = shape
    n_pix = h * w
    changes: dict = {}
    chosen: dict = {"adapted": False}
    zref = p.reference_depth
    use = bool(p.adapt) and model is not None and model.reliable and model.kind != "none"
    if use:
        chosen["adapted"] = True
        px = model.pixels()
        if p.min_region_size == "auto":
            floor = scaled_min_region_size(n_pix, FLOOR_SCALE)
            phys = (MIN_SIDE_SIGMAS * px) ** 2
            size = max(3, int(round(max(floor, phys) * p.min_region_scale)))
            changes["min_region_size"] = size
            foot = model.z_median * model.pixel_angle
            chosen.update(min_region_size=size, min_region_floor=floor,
                          min_region_area_m2=round(size * foot * foot, 7),
                          min_region_depth_m=round(model.z_median, 4))
        if model.kind == "uniform":
            s_nom, r_nom = auto_normal_scale(w)
            win = max(s_nom, r_nom, min(MAX_WINDOW, int(round(math.sqrt(12.0) * px))))
            if p.normal_smooth == "auto":
                changes["normal_smooth"] = win
            if p.normal_radius == "auto":
                changes["normal_radius"] = win
            if zref == "auto":
                zref = None
        if p.wide_noise_window and wide is not None and wide.reliable:
            from planerel.segment.noise import QUANTILE_TO_MEDIAN, WIDE_QUANTILE_TO_MEDIAN

            foot = model.z_median * model.pixel_angle
            pw = float(wide.sigma(model.z_median)) * WIDE_QUANTILE_TO_MEDIAN / QUANTILE_TO_MEDIAN
            pw /= foot
            win = min(MAX_WINDOW, int(round(math.sqrt(12.0) * pw)))
            chosen["wide_noise_pixels"] = round(pw, 3)
            for i, name in enumerate(("normal_smooth", "normal_radius")):
                cur = changes.get(name, getattr(p, name))
                if cur == "auto":
                    cur = auto_normal_scale(w)[i]
                if getattr(p, name) == "auto" and win > cur:
                    changes[name] = win
    if zref == "auto":
        zref = FIXED_REFERENCE_DEPTH
    changes["reference_depth"] = zref
    out = dataclasses.replace(p, **changes)
    chosen.update(normal_smooth=out.normal_smooth, normal_radius=out.normal_radius,
                  reference_depth=out.reference_depth)
    return out, chosen
