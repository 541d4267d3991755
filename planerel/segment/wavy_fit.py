"""One plane's fit within a wavy frame's measured waviness.

Active-stereo sensors (RealSense D4xx and the like) measure flat surfaces with waves of
millimetres over centimetres (docs/segmentation.md "Wavy frames").  The test that a set of
points is one such wavy sheet serves both the join of a face's pieces
(:func:`planerel.segment.merge.join_wavy`) and the leftover planes kept on wavy frames
(:func:`planerel.segment.split` ``wavy_leftover``); it lives here, apart from both, so that
neither stage imports the other.
"""

from __future__ import annotations

import math

import numpy as np

from planerel.segment.noise import WAVY_RATIO

__all__ = ["WAVE_FLAT", "WAVE_MAX_RMS", "WAVE_SPAN", "wavy_model", "wavy_ratio", "wavy_sheet_fits"]

#: Largest RMS of a wavy join's union relative to its largest in-plane std, for a union
#: longer than :data:`WAVE_SPAN` waviness windows: a large union must be a flat sheet, whatever
#: the sensor's waviness far away (two planes of similar size meeting at 10 degrees measure
#: about 0.07; a carton top's wavy pieces 0.01-0.03).  Pieces within a few windows tilt by
#: the waves themselves and are judged by the waviness alone.
WAVE_FLAT = 0.04
WAVE_SPAN = 2.0
#: Largest RMS of a wavy join's union, metres, whatever the waviness: far from an active-stereo
#: sensor its depth is centimetres off (unions of 16 and 104 mm at 3.9 and 5.6 m made false
#: ramps), while the pieces of a face joined at 0.4-2 m fit within 2-7 mm.
WAVE_MAX_RMS = 0.008


def wavy_model(info) -> dict | None:
    """``info["noise_model"]`` (region growing's) when it measures a wavy frame (``wave`` at
    least :data:`planerel.segment.noise.WAVY_RATIO`, from measured patches), else None."""
    nm = info.get("noise_model") if isinstance(info, dict) else None
    if (not nm or nm.get("kind") == "none" or nm.get("n_patches", 0) <= 0
            or nm.get("wave", 0.0) < WAVY_RATIO):
        return None
    return nm


def wavy_ratio(ev, centroid, noise_model: dict, tolerance: float, own: float = 0.0,
               max_rms: float = WAVE_MAX_RMS) -> float:
    """How well a least-squares plane fits within a wavy frame's measured waviness: its RMS over
    ``tolerance x wave x sigma(z) x g`` (``z`` the centroid's depth, ``sigma`` the small-patch
    noise model, ``g = sqrt(min(WAVE_SPAN, span / window))`` the waves' growth with the extent);
    ``inf`` when the RMS exceeds ``max_rms`` or, longer than :data:`WAVE_SPAN` waviness windows,
    it is no flat sheet (RMS over :data:`WAVE_FLAT` x its largest in-plane std) and fits worse
    than ``own`` (m; 0: no allowance).

    Parameters
    ----------
    ev : array_like, shape (3,)
        The points' covariance eigenvalues, ascending (m^2).
    centroid : array_like, shape (3,)
        Their centroid (m, camera frame).
    noise_model : dict
        ``info["noise_model"]`` of region growing (``wave``, ``const_m``, ``quad_per_m``,
        ``wave_window``, ``pixel_angle``).
    tolerance : float
        ``SplitParams.tolerance``.
    own : float
        A long union that is no flat sheet still passes when its RMS is at most ``own`` (the
        caller's allowance: :data:`planerel.segment.merge.WAVE_OWN` x its sides' RMS).
    max_rms : float
        The largest RMS (m) accepted whatever the waviness.

    Returns
    -------
    float
        The ratio (at most 1: fits), or ``inf``.
    """
    rms = math.sqrt(max(float(ev[0]), 0.0))
    if rms > max_rms:
        return math.inf
    wave = float(noise_model["wave"])
    c0, q = float(noise_model["const_m"]), float(noise_model["quad_per_m"])
    # a waviness window's std along one side per metre of depth (its side: wave_window pixels)
    win = (float(noise_model.get("wave_window", 0)) * float(noise_model.get("pixel_angle", 0.0))
           / math.sqrt(12.0))
    z = abs(float(centroid[2]))
    span = math.sqrt(max(float(ev[2]), 0.0))
    if span > WAVE_SPAN * win * z and rms > WAVE_FLAT * span and rms > own:
        return math.inf
    # the waves' RMS grows with the extent beyond the window's (as measured on the RealSense
    # frames: x1.2-1.6 from 25 to 50 px), up to WAVE_SPAN windows
    grow = math.sqrt(min(WAVE_SPAN, max(1.0, span / max(win * z, 1e-12))))
    allowed = tolerance * wave * math.sqrt(c0 * c0 + q * q * z ** 4) * grow
    return rms / max(allowed, 1e-12)


def wavy_sheet_fits(P, noise_model: dict, tolerance: float, max_rms: float = WAVE_MAX_RMS) -> bool:
    """Whether points ``P`` fit one plane within a wavy frame's measured waviness
    (:func:`wavy_ratio` at most 1, as :func:`planerel.segment.merge.join_wavy` judges the
    union of two pieces, with no allowance for pieces that are wavy themselves).

    Parameters
    ----------
    P : ndarray, shape (m, 3)
        The points (metres), all finite.
    noise_model : dict
        ``info["noise_model"]`` of region growing.
    tolerance : float
        ``SplitParams.tolerance``.
    max_rms : float
        The largest RMS (m) accepted whatever the waviness.

    Returns
    -------
    bool
        False for fewer than 3 points.
    """
    P = np.asarray(P, dtype=np.float64)
    if len(P) < 3:
        return False
    c = P.mean(axis=0)
    D = P - c
    ev = np.linalg.eigvalsh(D.T @ D / len(P))
    return wavy_ratio(ev, c, noise_model, tolerance, 0.0, max_rms) <= 1.0
