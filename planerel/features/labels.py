"""A label image in, its check and per-label moments out: the first step of measuring planes,
shared by :mod:`planerel.features.planes` and :mod:`planerel.features.gravity` (its own module
so that those two do not import each other).
"""

from __future__ import annotations

import numpy as np

from planerel.errors import InputError

__all__ = ["check_labels"]


def check_labels(labels, shape: tuple[int, int]) -> np.ndarray:
    """Validate a label image: ``(H, W)`` integer array matching the cloud, values >= -1."""
    lab = np.asarray(labels)
    if lab.shape != tuple(shape):
        raise InputError(f"label image has shape {lab.shape} but the cloud is {tuple(shape)}")
    if not np.issubdtype(lab.dtype, np.integer):
        raise InputError(f"label image must hold integers, got dtype {lab.dtype}")
    if lab.size and lab.min() < -1:
        raise InputError(f"label image holds {int(lab.min())}; labels are >= 0 and -1 = unassigned")
    return lab.astype(np.int32, copy=False)


def _moments(xyz: np.ndarray, lab: np.ndarray, nlab: int):
    """Counts ``(L,)``, centroids ``(L, 3)``, covariances ``(L, 3, 3)`` and mean pixel rows
    ``(L,)`` per label (one compiled pass over the image)."""
    from planerel.segment._label_kernels import label_moments

    counts, ref, s1, s2, rows = label_moments(np.ascontiguousarray(xyz),
                                              np.ascontiguousarray(lab, dtype=np.int32), nlab)
    safe = np.maximum(counts, 1).astype(np.float64)
    m1 = s1 / safe[:, None]
    m2 = s2 / safe[:, None]
    cov = np.empty((nlab, 3, 3))
    for k, (i, j) in enumerate(((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))):
        cov[:, i, j] = cov[:, j, i] = m2[:, k] - m1[:, i] * m1[:, j]
    return counts, ref + m1, cov, rows / safe
