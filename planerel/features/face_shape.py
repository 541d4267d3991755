"""An upright face's height against its width (fbox59).

A box is a compact solid: each upright face of it is a rectangle about as tall as it is wide,
or a few times taller (a product box's narrowest side: 5.6 times on the real development
frames).  A face many times taller than it is wide is a post's, a door jamb's, a wall's end,
a furniture side seen edge-on or a board's edge.

:func:`face_extent` measures one upright plane from its points: its height along ``up`` and
its width along its own horizontal axis (``normal x up``), each the 2nd-98th percentile
spread, and whether its pixels reach the image's left or right column (its width is then a
lower bound, and its height over its width an upper bound: not judged).  A face cut by the
image's top or bottom row is at least as tall as measured, so its ratio is a lower bound and
is judged.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["FaceExtent", "face_extent"]


@dataclass(frozen=True)
class FaceExtent:
    """One upright plane's height and width."""

    #: the plane's label
    face: int
    #: metres along ``up`` (2nd-98th percentile of its points' levels)
    height: float
    #: metres along its horizontal axis (2nd-98th percentile)
    width: float
    #: its pixels reach the image's left or right column (its width is a lower bound)
    cut: bool

    @property
    def ratio(self) -> float:
        """Height over width (the width at least 1 mm)."""
        return self.height / max(self.width, 1e-3)


def face_extent(plane, up, xyz, labels, min_points: int = 10) -> FaceExtent | None:
    """How tall and how wide the upright plane ``plane`` is.

    Parameters
    ----------
    plane : planerel.features.planes.Plane
        An upright plane (``label``, ``normal``).
    up : array_like, shape (3,)
        Unit up vector, camera frame.
    xyz : ndarray, shape (H, W, 3)
        The scan's organized points (NaN where none).
    labels : ndarray, shape (H, W)
        The plane label of each pixel.
    min_points : int
        Fewer valid points than this: None.

    Returns
    -------
    FaceExtent or None
    """
    lab = np.asarray(labels)
    rows, cols = np.nonzero(lab == plane.label)
    if rows.size < min_points:
        return None
    pts = np.asarray(xyz)[rows, cols]
    pts = pts[np.isfinite(pts).all(axis=1)]
    if len(pts) < min_points:
        return None
    u = np.asarray(up, float)
    u = u / np.linalg.norm(u)
    axis = np.cross(np.asarray(plane.normal, float), u)
    norm = np.linalg.norm(axis)
    if norm < 1e-6:   # not upright
        return None
    axis /= norm
    h, a = pts @ u, pts @ axis
    height = float(np.percentile(h, 98) - np.percentile(h, 2))
    width = float(np.percentile(a, 98) - np.percentile(a, 2))
    cut = bool(cols.min() == 0 or cols.max() == lab.shape[1] - 1)
    return FaceExtent(int(plane.label), height, width, cut)
