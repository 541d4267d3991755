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

__all__ = ["WAVE_FLAT", "WAVE_MAX_RMS", "WAVE_SPAN", "wavy_sheet_fits"]

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


def wavy_sheet_fits(P, noise_model: dict, tolerance: float, max_rms: float = WAVE_MAX_RMS) -> bool:
    """Whether points ``P`` (m, 3) fit one plane within a wavy frame's measured waviness, as
    :func:`planerel.segment.merge.join_wavy` judges the union of two pieces: the RMS to their least-squares plane is
    at most ``tolerance x wave x sigma(z) x g`` (``z`` the centroid's depth, ``sigma`` the
    small-patch noise model, ``g = sqrt(min(WAVE_SPAN, span / window))`` the waves' growth with
    the extent) and at most ``max_rms`` (:data:`WAVE_MAX_RMS`), and, when longer than :data:`WAVE_SPAN`
    waviness windows, a flat sheet (RMS at most :data:`WAVE_FLAT` x its largest in-plane std).

    Parameters
    ----------
    P : ndarray, shape (m, 3)
        The points (metres), all finite.
    noise_model : dict
        ``info["noise_model"]`` of region growing (``wave``, ``const_m``, ``quad_per_m``,
        ``wave_window``, ``pixel_angle``).
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
    rms = math.sqrt(max(ev[0], 0.0))
    if rms > max_rms:
        return False
    wave = float(noise_model["wave"])
    c0, q = float(noise_model["const_m"]), float(noise_model["quad_per_m"])
    win = (float(noise_model.get("wave_window", 0)) * float(noise_model.get("pixel_angle", 0.0))
           / math.sqrt(12.0))
    z = abs(float(c[2]))
    span = math.sqrt(max(ev[2], 0.0))
    if span > WAVE_SPAN * win * z and rms > WAVE_FLAT * span:
        return False
    grow = math.sqrt(min(WAVE_SPAN, max(1.0, span / max(win * z, 1e-12))))
    return rms <= tolerance * wave * math.sqrt(c0 * c0 + q * q * z ** 4) * grow
