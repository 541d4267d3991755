"""A region's own depth noise, measured on small patches of it (tof72).

The far pass (:func:`planerel.segment._far_planes`) keeps a candidate plane when it fits within
``far_rms`` times the frame's measured noise.  A time-of-flight camera's dark surfaces (a
stairwell's risers, hunt71) are five times as noisy as the rest of the frame, with the noise
correlated over several pixels, so they fit at 7-18 times the frame's noise however flat they
are.  :func:`patch_noise` measures the region's own noise instead: the median RMS of plane fits
to square patches of it.  A region that is flat at its own scale as at the patches' (its whole
fit within a small factor of that) is a plane seen through noise; a curved or folded surface
fits its patches far better than its whole.
"""

from __future__ import annotations

import numpy as np

__all__ = ["patch_noise", "patch_size"]

#: Patch side (px) at 960 px wide (hunt71's Kinect v2 frames: 12 px patches measure the risers'
#: 10-11 mm and the treads' 1.6-2.4 mm); scaled with the width, 6 at least
PATCH_960 = 12
#: A patch is measured when this share of its pixels lies in the region
PATCH_FILL = 0.6
#: Patches needed for a measure
PATCH_MIN = 3


def patch_size(width: int) -> int:
    """The patch side (px) for an image ``width`` px wide."""
    return max(6, int(round(PATCH_960 * width / 960)))


def patch_noise(xyz: np.ndarray, mask: np.ndarray, size: int) -> float | None:
    """The median RMS (m) of least-squares plane fits to the ``size`` x ``size`` patches of a
    grid tiling ``mask``'s bounding box that lie for :data:`PATCH_FILL` or more in ``mask``.

    Parameters
    ----------
    xyz : ndarray, shape (H, W, 3)
        The organized cloud (metres; NaN where invalid: never in ``mask``).
    mask : ndarray, shape (H, W), bool
        The region's pixels.
    size : int
        The patch side (px), >= 2.

    Returns
    -------
    float or None
        None when fewer than :data:`PATCH_MIN` patches are measured.
    """
    from planerel.segment._kernels import planes_from_sums, region_sums_into

    rows = np.flatnonzero(mask.any(axis=1))
    cols = np.flatnonzero(mask.any(axis=0))
    if rows.size == 0:
        return None
    r0, r1, c0, c1 = int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1
    # each pixel of the region labelled by its patch of the grid over the bounding box; the
    # patches' plane fits from their moments, as the region growing fits its regions
    nr, nc = -(-(r1 - r0) // size), -(-(c1 - c0) // size)
    rr, cc = np.mgrid[0:r1 - r0, 0:c1 - c0]
    tile = ((rr // size) * nc + cc // size).astype(np.int32)
    tile[~mask[r0:r1, c0:c1]] = -1
    pts = np.ascontiguousarray(xyz[r0:r1, c0:c1], dtype=np.float64).reshape(-1, 3)
    n = nr * nc
    sums, ref = np.zeros((n, 10)), np.zeros((n, 3))
    region_sums_into(pts, tile.reshape(-1), n, sums, ref, True)
    full = sums[:, 0] >= PATCH_FILL * size * size
    if int(full.sum()) < PATCH_MIN:
        return None
    rms = planes_from_sums(sums, ref, n)[4]
    return float(np.median(rms[full]))
