"""Whether a sloping plane's parts slope as the whole does (wave83).

A ramp is one flat slope: any part of it rises as steeply as the whole, in the same direction.
A far floor piece that an active stereo camera's undulating depth tilted (docs/objects.md
"A stereo pair as wavy as a real D4xx"), or two surfaces grown into one plane (a floor strip
and the foot of a wall behind it), slopes only as a compromise of parts that do not: one part
nearly level, another steep or tilted the other way.

:func:`slope_parts` cuts a plane's points into four parts by their medians along its downhill
direction and across it, fits each part's plane and returns each part's slope along the
whole's downhill direction as a share of the whole's (1: the same slope).  The whole's slope is
that of its own fit to the same points.  The decision's ``slope_parts_gate``
(:meth:`planerel.classify.classifier.Classifier._slope_parts`) refuses ``ramp`` when a part of
every measured sloping proof plane is off by more than ``slope_parts_tol``.

Measured with the demo's model (docs/objects.md "A ramp's parts slope alike"): the 96 ramps
it answers on eleven independent sets keep every part within 0.24 of the whole's slope (shares
0.76-1.16), and 9 of the 12 ramps it answers on no ramp (far floor pieces at 2.7-5.4 m under
the wavy stereo sensor, a far wall strip) have a part off by 0.52-2.4.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["SlopeParts", "slope_parts", "PARTS_MIN_POINTS", "PARTS_MAX_POINTS"]

#: Points each part needs for its plane to be fitted (fewer: the plane is not judged).
PARTS_MIN_POINTS = 20
#: At most this many of a plane's points are fitted (every k-th in the image's order beyond:
#: a 200 000-pixel ramp is measured in about 4 ms, not 44, with the same shares to 0.01).
PARTS_MAX_POINTS = 20000


@dataclass(frozen=True)
class SlopeParts:
    """One sloping plane's parts."""

    #: the plane's label
    plane: int
    #: the whole's slope from level, degrees (its own fit to the points)
    slope: float
    #: each part's slope along the whole's downhill direction as a share of the whole's
    #: (tangents; 1: the same slope, 0: level, negative: tilted the other way): the uphill
    #: half's two quarters, then the downhill half's
    shares: tuple

    @property
    def worst(self) -> float:
        """The largest ``|share - 1|`` over the parts."""
        return max(abs(s - 1.0) for s in self.shares)


def _upward_normals(points: np.ndarray, part: np.ndarray, n: int, up: np.ndarray) -> np.ndarray:
    """``(n, 3)``: the unit normals of the least-squares planes of the ``n`` parts of
    ``points`` ``(N, 3)`` (``part`` ``(N,)``: each point's part, 0 .. n - 1), turned up (the
    segmentation's plane fit, :func:`planerel.segment.result.fit_planes`)."""
    from planerel.segment.result import fit_planes

    normals = fit_planes(points, part, n)[0]
    return normals * np.where(normals @ up >= 0, 1.0, -1.0)[:, None]


def slope_parts(plane, up, xyz, labels, min_points: int = PARTS_MIN_POINTS,
                min_slope: float = 1.0) -> SlopeParts | None:
    """The parts of the sloping plane ``plane`` and how they slope.

    Parameters
    ----------
    plane : planerel.features.planes.Plane
        Its ``label`` is read.
    up : array_like, shape (3,)
        Gravity up in the sensor's frame.
    xyz : ndarray, shape (H, W, 3)
        Organized points (NaN where there is no depth).
    labels : ndarray, shape (H, W)
        The label image the plane's label indexes.
    min_points : int
        Points each of the four parts needs.
    min_slope : float
        Degrees: a plane whose own fit slopes less is not judged (its downhill direction is
        noise).

    Returns
    -------
    SlopeParts or None
        None when the plane has too few points, or its fit slopes under ``min_slope``
        degrees or faces sideways (more than 80 degrees from level).
    """
    up = np.asarray(up, dtype=np.float64)
    up = up / np.linalg.norm(up)
    xyz = np.asarray(xyz)
    idx = np.flatnonzero(np.asarray(labels) == plane.label)
    if len(idx) > PARTS_MAX_POINTS:
        idx = idx[::-(-len(idx) // PARTS_MAX_POINTS)]
    pts = xyz.reshape(-1, 3)[idx].astype(np.float64)
    pts = pts[np.isfinite(pts).all(axis=1)]
    if len(pts) < 4 * min_points:
        return None
    n = _upward_normals(pts, np.zeros(len(pts), np.int32), 1, up)[0]
    rise = float(n @ up)
    lean = n - rise * up
    size = float(np.linalg.norm(lean))
    slope = float(np.degrees(np.arctan2(size, rise)))
    if not min_slope <= slope <= 80.0:
        return None
    down = lean / size                      # the whole's downhill direction, level
    across = np.cross(up, down)
    grade = size / rise                     # the whole's tangent along ``down``
    q = pts - pts.mean(axis=0)
    s, t = q @ down, q @ across
    # the quarters: 0, 1 the uphill half's (its two sides), 2, 3 the downhill half's
    part = (2 * (s > np.median(s)) + (t > np.median(t))).astype(np.int32)
    if np.bincount(part, minlength=4).min() < min_points:
        return None
    m = _upward_normals(pts, part, 4, up)
    # an upright part (m . up = 0) slopes without bound: a share of 1e9 or more
    shares = (m @ down) / np.maximum(m @ up, 1e-9) / grade
    return SlopeParts(int(plane.label), slope, tuple(float(v) for v in shares))
