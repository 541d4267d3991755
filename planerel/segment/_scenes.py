"""Small analytic scenes with exact ground truth, for segmentation tests and the benchmark.

The project's scene generator is :mod:`planerel.synth.generator`; this private module only ray-casts a few
axis-aligned boxes with numpy so segmentation can be tested on its own.
"""

from __future__ import annotations

import numpy as np

from planerel.io.cloud import Cloud, Intrinsics

__all__ = ["staircase", "look_at"]


def look_at(eye, target) -> np.ndarray:
    """Rotation ``R`` (3, 3) taking camera-frame vectors (x right, y down, z forward) to a world
    frame with Y up, for a camera at ``eye`` looking at ``target`` with no roll."""
    eye = np.asarray(eye, float)
    f = np.asarray(target, float) - eye
    f /= np.linalg.norm(f)
    up = np.array([0.0, 1.0, 0.0])
    x = np.cross(up, f)  # right-handed: x = up x forward points to the camera's right
    x /= np.linalg.norm(x)
    y = np.cross(f, x)  # camera down = forward x right
    return np.column_stack([x, y, f])


def _raycast_boxes(origin, dirs, boxes):
    """Nearest hit of rays with axis-aligned boxes.

    Returns t (N,), box index (N,), face (N,) as axis * 2 + (1 if the + face else 0).
    """
    n = len(dirs)
    best_t = np.full(n, np.inf)
    best_box = np.full(n, -1)
    best_face = np.full(n, -1)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / dirs
    for b, (lo, hi) in enumerate(boxes):
        t1 = (np.asarray(lo) - origin) * inv
        t2 = (np.asarray(hi) - origin) * inv
        tmin = np.minimum(t1, t2)
        tmax = np.maximum(t1, t2)
        t_enter = tmin.max(axis=1)
        axis = tmin.argmax(axis=1)
        t_exit = tmax.min(axis=1)
        hit = (t_enter <= t_exit) & (t_enter > 1e-6) & (t_enter < best_t)
        plus = dirs[np.arange(n), axis] < 0  # entering through the + face
        best_t[hit] = t_enter[hit]
        best_box[hit] = b
        best_face[hit] = axis[hit] * 2 + plus[hit]
    return best_t, best_box, best_face


def staircase(
    width: int = 160,
    height: int = 120,
    *,
    steps: int = 4,
    seed: int = 0,
    noise: float = 0.0012,
    rise: float = 0.18,
    run: float = 0.28,
    stair_width: float = 1.0,
    start: float = 1.6,
    eye=(1.0, 1.35, 0.0),
):
    """A staircase in front of a wall, on a floor, seen from above and to the right.

    Parameters
    ----------
    width, height : int
        Image size (a whole-number subsampling of 640x480; Kinect intrinsics).
    steps : int
        Number of steps: planes are floor, wall, the right side face, ``steps`` risers and
        ``steps`` treads (11 for 4 steps).
    seed : int
        Seed of the depth noise.
    noise : float
        Kinect-like noise: depth std ``noise * z**2`` metres along each ray (0 = none).

    Returns
    -------
    cloud : Cloud
    labels : ndarray, shape (H, W), int32
        Ground-truth plane per pixel, -1 = nothing hit.
    normals : ndarray, shape (K, 3)
        Ground-truth unit normals (camera frame, towards the sensor) of plane ids 0..K-1.
    offsets : ndarray, shape (K,)
    """
    intr = Intrinsics.kinect(width, height)
    eye = np.asarray(eye, float)
    z_wall = start + steps * run
    R = look_at(eye, (0.0, 0.35, start + 0.5 * steps * run))
    v, u = np.mgrid[0:height, 0:width].astype(float)
    d_cam = np.stack([(u - intr.cx) / intr.fx, (v - intr.cy) / intr.fy, np.ones_like(u)], -1)
    d_cam = d_cam.reshape(-1, 3)
    dirs = d_cam @ R.T
    hw = stair_width / 2
    boxes = [((-6.0, -1.0, -6.0), (6.0, 0.0, z_wall)),          # floor
             ((-6.0, -1.0, z_wall), (6.0, 4.0, z_wall + 1.0))]  # wall
    for i in range(1, steps + 1):
        boxes.append(((-hw, 0.0, start + (i - 1) * run), (hw, i * rise, z_wall)))
    t, box, face = _raycast_boxes(eye, dirs, boxes)
    # plane ids: floor 0, wall 1, side (+X) 2, side (-X) 3, riser i 4+2(i-1), tread i 5+2(i-1)
    lab = np.full(len(t), -1, dtype=np.int64)
    lab[(box == 0) & (face == 3)] = 0
    lab[(box == 1) & (face == 4)] = 1
    st = box >= 2
    lab[st & (face == 1)] = 2
    lab[st & (face == 0)] = 3
    lab[st & (face == 4)] = 4 + 2 * (box[st & (face == 4)] - 2)
    lab[st & (face == 3)] = 5 + 2 * (box[st & (face == 3)] - 2)
    world_n, world_p = [], []
    world_n += [(0, 1, 0), (0, 0, -1), (1, 0, 0), (-1, 0, 0)]
    world_p += [(0, 0, 0), (0, 0, z_wall), (hw, 0, 0), (-hw, 0, 0)]
    for i in range(1, steps + 1):
        world_n += [(0, 0, -1), (0, 1, 0)]
        world_p += [(0, 0, start + (i - 1) * run), (0, i * rise, 0)]
    wn = np.array(world_n, float)
    wp = np.array(world_p, float)
    cam_n = wn @ R  # R^T n
    cam_p = (wp - eye) @ R
    off = -np.einsum("ij,ij->i", cam_n, cam_p)
    flip = off < 0
    cam_n[flip] *= -1
    off[flip] *= -1
    pts_cam = d_cam * t[:, None]
    ok = np.isfinite(t) & (lab >= 0)
    pts_cam[~ok] = np.nan
    if noise > 0:
        rng = np.random.default_rng(seed)
        z = pts_cam[:, 2]
        e = rng.standard_normal(len(z)) * noise * z ** 2
        with np.errstate(invalid="ignore"):
            pts_cam *= ((z + e) / z)[:, None]
    # renumber to the planes present
    lab[~ok] = -1
    present = np.unique(lab[lab >= 0])
    remap = np.full(len(wn), -1)
    remap[present] = np.arange(len(present))
    lab = np.where(lab >= 0, remap[np.maximum(lab, 0)], -1).astype(np.int32)
    cloud = Cloud(pts_cam.reshape(height, width, 3), intr, R[1].copy(), f"staircase-{steps}-s{seed}")
    return cloud, lab.reshape(height, width), cam_n[present], off[present]
