"""Shape measures of a region of the label image, shared by the segmentation's passes and the
relations (which come after it and import it, never the other way round)."""

from __future__ import annotations

import numpy as np

__all__ = ["mask_solidity", "row_spans"]


def mask_solidity(mask) -> float:
    """The share of the convex hull, in the image, of the pixels of ``mask`` (2-D bool) that
    they fill: their count over the area of the hull of their squares (a filled rectangle 1.0,
    half a ring about 0.55, an L of one-pixel arms 0.32).

    Returns
    -------
    float
        In (0, 1]; 1.0 for fewer than 3 pixels or pixels on one line (no area to fill).
    """
    from scipy.spatial import ConvexHull, QhullError

    m = np.asarray(mask, bool)
    n = int(m.sum())
    if n < 3:
        return 1.0
    # the hull of the pixels' squares is the hull of each row's outermost squares' corners
    rows, first, last = row_spans(m)
    pts = np.concatenate([np.stack([rows + dr, col + dc], 1)
                          for dr in (0, 1) for col, dc in ((first, 0), (last, 1))])
    try:
        hull = ConvexHull(pts.astype(float))
    except QhullError:
        return 1.0
    return float(min(1.0, n / hull.volume)) if hull.volume > 0 else 1.0


def row_spans(m):
    """``(rows, first, last)``: the rows of the 2-D bool mask ``m`` holding a pixel and, per
    such row, its first and last pixel's column."""
    rows = np.flatnonzero(m.any(axis=1))
    sub = m[rows]
    return rows, sub.argmax(axis=1), sub.shape[1] - 1 - sub[:, ::-1].argmax(axis=1)
