"""An image grid for an unorganized point cloud: a z-buffer projection from one viewpoint.

Much of planerel looks through the image grid: depth-edge normals, the sensor's noise model,
``describe``'s relations that project a plane into the image (a box's ``skirt/2``).  A cloud
with no grid (a PLY, a PCD with ``HEIGHT 1``, an ``(N, 3)`` ``.npy`` that is no exact pinhole
back-projection, which :func:`planerel.io.readers.pinhole_grid` would put back on its pixels)
is projected here onto a pinhole image seen from the camera's origin (x right, y down,
z forward): every pixel holds the nearest point along its ray, pixels no point falls in are
NaN.  The points keep their coordinates (they are not moved onto the pixel rays).

The intrinsics are the user's when given; else chosen from the points: the pixel is the
points' angular spacing measured from their local density (:func:`_spacing`: a depth frame's
points come back on about its own grid), widened by the least of :data:`PIXEL_FACTORS` that
leaves at most :data:`MAX_PINHOLES` one-pixel holes; the image spans the points' angular
extent, and the larger side is capped at ``max_side`` pixels (:data:`MAX_SIDE`).  A cloud that cannot be one view is refused with an
:class:`~planerel.errors.InputError` that says what to do: points at or behind the viewpoint
(``z <= 0``), or a field of view over :data:`MAX_FOV_DEG` degrees (a 360-degree LiDAR sweep).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planerel.errors import InputError
from planerel.io.cloud import Intrinsics

__all__ = ["organize", "Organized", "viewpoint_transform", "MAX_SIDE", "MAX_FOV_DEG",
           "NO_ORGANIZE_HINT"]

#: Largest image side (pixels) of a grid chosen from the points.
MAX_SIDE = 640
#: Largest field of view (degrees, across either image axis) of a cloud seen as one view.
MAX_FOV_DEG = 150.0
#: Pixel sizes tried, in units of the points' spacing: the smallest at which at most
#: :data:`MAX_PINHOLES` of the pixels inside the cloud are one-pixel holes is taken.
PIXEL_FACTORS = (1.0, 1.15, 1.3, 1.5, 1.75, 2.0, 2.5, 3.0)
#: Largest share of one-pixel holes a chosen grid may have (a Kinect frame has 0.04 %; a depth
#: frame's points jittered by 0.5 mm on their own pixel size have 22 %, and on 1.5x it 2.4 %;
#: region growing needs the neighbours).
MAX_PINHOLES = 0.05
#: Points sampled (deterministically) to measure the angular spacing.
_SPACING_SAMPLE = 5000
#: Neighbours a point's local density is measured from.
_SPACING_K = 16

#: What to tell a user whose cloud is refused.
NO_ORGANIZE_HINT = ("give it in the frame of the sensor that saw it (x right, y down, z "
                    "forward), or read it unorganized: --no-organize (organize=False)")


@dataclass(frozen=True)
class Organized:
    """Where :func:`organize` put each point.

    Attributes
    ----------
    rows, cols : ndarray, shape (N,), int64
        Pixel of each input point, -1 for points that hold no pixel (invalid, outside a given
        camera's image, or hidden behind a nearer point in the same pixel).
    intrinsics : Intrinsics
        The grid's camera.
    xyz : ndarray, shape (H, W, 3), float64
        The points on the grid (camera frame, metres), NaN where no point is.
    n_points : int
        Valid input points.
    n_hidden : int
        Valid points that lost their pixel to a nearer one.
    n_outside : int
        Valid points outside a given camera's image.
    chosen : bool
        True when the intrinsics were chosen from the points, False when given.
    """

    rows: np.ndarray
    cols: np.ndarray
    intrinsics: Intrinsics
    xyz: np.ndarray
    n_points: int
    n_hidden: int
    n_outside: int
    chosen: bool

    def place(self, values: np.ndarray, fill) -> np.ndarray:
        """``values`` ``(N, ...)`` of the input points on the grid, ``fill`` where no point is."""
        values = np.asarray(values)
        intr = self.intrinsics
        out = np.full((intr.height, intr.width) + values.shape[1:], fill, dtype=values.dtype)
        ok = self.rows >= 0
        out[self.rows[ok], self.cols[ok]] = values[ok]
        return out

    def note(self, where: str) -> str:
        """One sentence for a :class:`~planerel.errors.PlanerelWarning` / CLI ``note:``."""
        i = self.intrinsics
        how = ("chosen from the points' angular spacing and extent" if self.chosen
               else "as given")
        hidden = (f"; {self.n_hidden:,} points ({100 * self.n_hidden / max(self.n_points, 1):.1f} %) "
                  "hidden behind nearer ones in their pixel")
        outside = f"; {self.n_outside:,} outside the image" if self.n_outside else ""
        fill = int(np.isfinite(self.xyz[:, :, 2]).sum())
        advice = ("give the camera's own with --intrinsics when known" if self.chosen
                  else "")
        tail = f"; {advice}" if advice else ""
        return (f"{where}: an unorganized cloud of {self.n_points:,} points put on a "
                f"{i.width}x{i.height} image grid seen from the sensor's origin (intrinsics "
                f"{how}: fx {i.fx:.1f}, fy {i.fy:.1f}, cx {i.cx:.1f}, cy {i.cy:.1f}; "
                f"{fill:,} pixels hold a point{hidden}{outside}){tail}; --no-organize keeps it "
                "unorganized")


def viewpoint_transform(points: np.ndarray, viewpoint) -> np.ndarray:
    """Points given in a cloud's frame, in the frame of the sensor at ``viewpoint``.

    Parameters
    ----------
    points : ndarray, shape (N, 3)
    viewpoint : 7-sequence
        A PCD ``VIEWPOINT``: the sensor's position ``tx ty tz`` and orientation quaternion
        ``qw qx qy qz`` in the cloud's frame.

    Returns
    -------
    ndarray, shape (N, 3)
        ``R^T (p - t)``.
    """
    tx, ty, tz, qw, qx, qy, qz = (float(v) for v in viewpoint)
    n = np.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    if not np.isfinite(n) or n == 0:
        raise InputError(f"the VIEWPOINT quaternion {qw, qx, qy, qz} is not a rotation")
    qw, qx, qy, qz = qw / n, qx / n, qy / n, qz / n
    r = np.array([
        [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
        [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
        [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)],
    ])
    return (np.asarray(points, dtype=np.float64) - [tx, ty, tz]) @ r


def is_identity_viewpoint(viewpoint) -> bool:
    """Whether a PCD ``VIEWPOINT`` is the identity pose (``0 0 0 1 0 0 0``)."""
    if viewpoint is None:
        return True
    v = np.asarray(viewpoint, dtype=np.float64)
    return v.shape == (7,) and np.allclose(v, [0, 0, 0, 1, 0, 0, 0])


def _sample(a: np.ndarray, b: np.ndarray, n: int) -> np.ndarray:
    """About ``n`` indices of the points, chosen by a hash of their values (so the same
    points whatever their order)."""
    if len(a) <= n:
        return np.arange(len(a))
    h = (a.view(np.uint64) * np.uint64(0x9E3779B97F4A7C15)) ^ (b.view(np.uint64) *
                                                               np.uint64(0xC2B2AE3D27D4EB4F))
    h ^= h >> np.uint64(29)
    h *= np.uint64(0xBF58476D1CE4E5B9)
    h ^= h >> np.uint64(32)
    m = np.uint64(max(1, len(a) // n))
    return np.nonzero(h % m == 0)[0]


def _spacing(a: np.ndarray, b: np.ndarray) -> float:
    """The points' typical angular spacing in ``(x/z, y/z)``: ``1 / sqrt(density)``, the
    density measured from each sampled point's :data:`_SPACING_K` nearest neighbours (a
    least-squares fit of ``k + 1/2 = density * pi * r_k**2``; median over a sample chosen by
    the points' values, so the same whatever their order).  On a depth frame's points it is
    its pixel (1.00-1.01 px on a lattice, jittered by up to half a pixel or not); on a random
    half of them, 1.41 px (one point a pixel).  The median distance to the nearest neighbour
    is not: 0.90 px on learn0 jittered by 0.5 mm (fx 580 for the camera's 525)."""
    from scipy.spatial import cKDTree

    ab = np.stack([a, b], axis=1)
    for attempt in range(2):
        k = min(_SPACING_K, len(ab) - 1)
        if k < 1:
            return 0.0
        tree = cKDTree(ab, balanced_tree=False, compact_nodes=False)
        d, _ = tree.query(ab[_sample(ab[:, 0].copy(), ab[:, 1].copy(), _SPACING_SAMPLE)],
                          k=k + 1)
        if attempt == 0 and np.mean(d[:, 1] == 0) > 0.05:
            # repeated points (a cloud merged with itself, stored twice) add no area: measure
            # on one copy of each
            ab = np.unique(ab, axis=0)
            continue
        break
    area = np.pi * d[:, 1:] ** 2
    kk = np.arange(1, k + 1) + 0.5
    with np.errstate(invalid="ignore", divide="ignore"):
        density = (area * kk).sum(axis=1) / (area * area).sum(axis=1)
    density = density[np.isfinite(density)]
    if not density.size:
        return 0.0
    return float(1.0 / np.sqrt(np.median(density)))


def _pinholes(a: np.ndarray, b: np.ndarray, f: float) -> float:
    """The share of one-pixel holes (an empty pixel with at least 3 of its 4 neighbours
    holding a point) among the pixels that hold a point or are such a hole, on the grid of
    focal length ``f`` spanning the points."""
    u = np.floor((a - a.min()) * f + 0.5).astype(np.int64)
    v = np.floor((b - b.min()) * f + 0.5).astype(np.int64)
    w, h = int(u.max()) + 1, int(v.max()) + 1
    occ = np.zeros((h + 2, w + 2), bool)
    occ[v + 1, u + 1] = True
    nb = (occ[:-2, 1:-1].astype(np.int8) + occ[2:, 1:-1] + occ[1:-1, :-2] + occ[1:-1, 2:])
    filled = occ[1:-1, 1:-1]
    holes = int(((~filled) & (nb >= 3)).sum())
    return holes / max(holes + int(filled.sum()), 1)


def _choose_camera(a: np.ndarray, b: np.ndarray, max_side: int) -> Intrinsics:
    """The grid's camera for points at ``(x/z, y/z) = (a, b)``: square pixels of the points'
    spacing (:func:`_spacing`) times the smallest of :data:`PIXEL_FACTORS` at which at most
    :data:`MAX_PINHOLES` of the pixels inside the cloud are one-pixel holes, the image just
    spanning the points, its larger side at most ``max_side``."""
    extent = float(max(np.ptp(a), np.ptp(b)))
    if not extent > 0:  # every point on one ray: one pixel
        return Intrinsics(1, 1, 1.0, 1.0, round(-float(a[0]), 6), round(-float(b[0]), 6))
    s = _spacing(a, b)
    if not s > 0:
        s = extent / (max_side - 1)
    f = None
    for factor in PIXEL_FACTORS:
        f = 1.0 / (s * factor)
        if extent * f > max_side - 1 or _pinholes(a, b, f) <= MAX_PINHOLES:
            break
    f = min(f, (max_side - 1) / extent)
    cx, cy = -a.min() * f, -b.min() * f
    w = int(np.floor(np.ptp(a) * f + 0.5)) + 1
    h = int(np.floor(np.ptp(b) * f + 0.5)) + 1
    return Intrinsics(w, h, round(f, 6), round(f, 6), round(cx, 6), round(cy, 6))


def _pixel(coord) -> np.ndarray:
    """Image coordinates rounded to whole pixels, int64; a coordinate that is not finite or
    lies far outside any image (a point almost in the sensor's plane, under given intrinsics)
    becomes -1, outside, without numpy's cast warning."""
    with np.errstate(invalid="ignore", over="ignore"):
        p = np.floor(np.asarray(coord, float) + 0.5)
        return np.where(np.isfinite(p) & (np.abs(p) < 2.0**31), p, -1.0).astype(np.int64)


def organize(points, intrinsics=None, *, viewpoint=None, max_side: int = MAX_SIDE,
             where: str = "cloud") -> Organized:
    """Project an unorganized cloud onto a pinhole image grid with a z-buffer.

    Each pixel ``(v, u)`` holds the valid point nearest the camera among those with
    ``u = round(fx x/z + cx)``, ``v = round(fy y/z + cy)``; ties (equal depth) are broken by
    ``x``, then ``y``, so the same points in any order give the same grid.  The points keep
    their coordinates.

    Parameters
    ----------
    points : ndarray, shape (N, 3)
        XYZ in metres (NaN rows and points exactly at the origin, ``0 0 0``: invalid, left
        out).  In the camera frame (x right, y down,
        z forward) unless ``viewpoint`` says where the sensor was.
    intrinsics : Intrinsics, optional
        The grid's camera; points outside its image are left out.  Default: chosen from the
        points (:func:`_choose_camera`: the pixel from their angular spacing, widened against
        one-pixel holes; the image just spans them, its larger side at most ``max_side``
        pixels).
    viewpoint : 7-sequence, optional
        A PCD ``VIEWPOINT`` (``tx ty tz qw qx qy qz``, the sensor's pose in the cloud's
        frame); the points are moved into the sensor's frame first.
    max_side : int
        Largest side of a chosen grid (pixels).
    where : str
        Named in errors.

    Returns
    -------
    Organized
        ``xyz`` ``(H, W, 3)``, the intrinsics, and each input point's pixel.

    Raises
    ------
    InputError
        No valid point; points at or behind the viewpoint (``z <= 0``); a field of view over
        :data:`MAX_FOV_DEG` degrees (a 360-degree sweep is no one view).
    """
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    if viewpoint is not None and not is_identity_viewpoint(viewpoint):
        p = viewpoint_transform(p, viewpoint)
    # NaN rows, and points exactly at the origin: the "no return" that depth cameras' and
    # point-cloud libraries' exports write for an invalid pixel
    valid = np.all(np.isfinite(p), axis=1) & np.any(p != 0.0, axis=1)
    n_valid = int(valid.sum())
    if n_valid == 0:
        raise InputError(f"{where}: the cloud holds no valid point")
    z = p[:, 2]
    behind = valid & (z <= 0)
    if behind.any():
        frac = 100 * behind.sum() / n_valid
        raise InputError(f"{where}: {int(behind.sum()):,} of {n_valid:,} points ({frac:.1f} %) are "
                         "at or behind the sensor (z <= 0): no one view to put on an image "
                         f"grid; {NO_ORGANIZE_HINT}")
    q = p[valid]
    a = q[:, 0] / q[:, 2]
    b = q[:, 1] / q[:, 2]
    chosen = intrinsics is None
    if chosen:
        fov = np.degrees([np.arctan(a.max()) - np.arctan(a.min()),
                          np.arctan(b.max()) - np.arctan(b.min())])
        if fov.max() > MAX_FOV_DEG:
            raise InputError(f"{where}: the points span {fov[0]:.0f} x {fov[1]:.0f} degrees "
                             f"from the sensor, over one view's {MAX_FOV_DEG:.0f} (a 360-degree "
                             f"scan?): no image grid; {NO_ORGANIZE_HINT}")
        intr = _choose_camera(a, b, max_side)
    else:
        intr = intrinsics
    u = _pixel(intr.fx * a + intr.cx)
    v = _pixel(intr.fy * b + intr.cy)
    inside = (u >= 0) & (u < intr.width) & (v >= 0) & (v < intr.height)
    n_outside = int((~inside).sum())
    idx = np.nonzero(valid)[0][inside]
    u, v, q = u[inside], v[inside], q[inside]
    pix = v * intr.width + u
    zq = q[:, 2]
    # the nearest point of each pixel (np.minimum.at); equal depths broken by x, then y, so
    # the same points in any order give the same grid
    zmin = np.full(intr.width * intr.height, np.inf)
    np.minimum.at(zmin, pix, zq)
    cand = np.nonzero(zq == zmin[pix])[0]
    twice = np.bincount(pix[cand], minlength=zmin.size)[pix[cand]] > 1
    if twice.any():
        tied = cand[twice]
        order = np.lexsort((q[tied, 1], q[tied, 0], pix[tied]))
        tied = tied[order]
        first = np.ones(len(tied), bool)
        first[1:] = pix[tied][1:] != pix[tied][:-1]
        cand = np.concatenate([cand[~twice], tied[first]])
    win = cand
    rows = np.full(len(p), -1, np.int64)
    cols = np.full(len(p), -1, np.int64)
    rows[idx[win]], cols[idx[win]] = v[win], u[win]
    xyz = np.full((intr.height, intr.width, 3), np.nan)
    xyz[v[win], u[win]] = q[win]
    return Organized(rows, cols, intr, xyz, n_valid, int(len(pix) - len(win)), n_outside,
                     chosen)
