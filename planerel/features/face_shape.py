"""An upright face's height against its width (fbox59).

A box is a compact solid: each upright face of it is a rectangle about as tall as it is wide,
or a few times taller (a product box's narrowest side: 5.6 times on the real development
frames).  A face many times taller than it is wide is a post's, a door jamb's, a wall's end,
a furniture side seen edge-on or a board's edge.

:func:`face_extent` measures one upright plane from its points: its height along ``up`` and
its width along its own horizontal axis (``normal x up``), each the 2nd-98th percentile
spread, and whether its width is a lower bound: its pixels reach the image's left or right
column, or on at least half of its rows something nearer than the face hides it just beyond
its left or right end (a tall box partly behind a nearer one).  Its height over its width is
then an upper bound: not judged.  Beyond a face's end the camera sees the solid's other face
or what lies behind (farther), or an occluder (nearer).  A face cut by the image's top or
bottom row is at least as tall as measured, so its ratio is a lower bound and is judged.
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
    #: its pixels reach the image's left or right column, or a nearer surface hides one of
    #: its ends (its width is a lower bound)
    cut: bool

    @property
    def ratio(self) -> float:
        """Height over width (the width at least 1 mm)."""
        return self.height / max(self.width, 1e-3)


def _hidden_end(xyz, lab, rows, cols, label, nearer: float, reach: int, share: float) -> bool:
    """Whether on at least ``share`` of the face's rows the first valid pixel of another label
    within ``reach`` pixels beyond its leftmost (or rightmost) pixel is nearer to the camera
    than that pixel by more than ``nearer`` metres, on either side."""
    W = lab.shape[1]
    rng = np.linalg.norm(xyz, axis=-1)
    order = np.argsort(rows, kind="stable")
    r_sorted, c_sorted = rows[order], cols[order]
    uniq, start = np.unique(r_sorted, return_index=True)
    end = np.r_[start[1:], len(r_sorted)]
    for step in (-1, 1):
        hidden = seen = 0
        for r, a, b in zip(uniq, start, end, strict=True):
            c0 = int(c_sorted[a:b].min() if step < 0 else c_sorted[a:b].max())
            r0 = rng[r, c0]
            if not np.isfinite(r0):
                continue
            for k in range(1, reach + 1):
                c = c0 + step * k
                if c < 0 or c >= W:
                    break
                if lab[r, c] == label or not np.isfinite(rng[r, c]):
                    continue
                seen += 1
                hidden += rng[r, c] < r0 - nearer
                break
        if seen and hidden >= share * len(uniq):
            return True
    return False


def face_extent(plane, up, xyz, labels, min_points: int = 10, nearer: float = 0.05,
                reach: int = 4, share: float = 0.5) -> FaceExtent | None:
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
    nearer, reach, share : float, int, float
        An end of the face is hidden when, on at least ``share`` of its rows, the first valid
        pixel of another plane within ``reach`` pixels beyond it is nearer than the face's
        end pixel by more than ``nearer`` metres.

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
    cut = bool(cols.min() == 0 or cols.max() == lab.shape[1] - 1) or _hidden_end(
        np.asarray(xyz), lab, rows, cols, plane.label, nearer, reach, share)
    return FaceExtent(int(plane.label), height, width, cut)
