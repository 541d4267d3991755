"""Tiny analytic scenes for the feature tests: rectangles ray-cast into an organized grid.

World frame: z up, floor at z = 0.  The camera sits at ``(0, 0, cam_height)`` looking along
world +y, pitched down by ``pitch`` degrees and rolled by ``roll`` degrees.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planerel.io.cloud import Cloud, Intrinsics


@dataclass(frozen=True)
class Rect:
    center: tuple
    e1: tuple
    e2: tuple
    a: float  # half size along e1
    b: float  # half size along e2
    obj: int = -1  # object id (-1 = support)


def camera_rotation(pitch: float, roll: float) -> np.ndarray:
    """Columns = camera x, y, z axes in world coordinates."""
    x = np.array([1.0, 0, 0])
    y = np.array([0, 0, -1.0])
    z = np.array([0, 1.0, 0])
    R = np.stack([x, y, z], axis=1)
    p = math.radians(pitch)
    # pitch down: rotate about camera x so that z tilts towards world -z
    Rp = np.array([[1, 0, 0], [0, math.cos(p), math.sin(p)], [0, -math.sin(p), math.cos(p)]])
    r = math.radians(roll)
    Rr = np.array([[math.cos(r), -math.sin(r), 0], [math.sin(r), math.cos(r), 0], [0, 0, 1]])
    return R @ Rp @ Rr


def render(rects, *, pitch=20.0, roll=0.0, cam_height=1.2, width=160, height=120,
           noise=0.0, seed=0, with_up=True):
    """Ray-cast rectangles; return (Cloud, labels (H,W) int32, up_true (3,), object_of_label)."""
    intr = Intrinsics.kinect(width, height)
    R = camera_rotation(pitch, roll)
    t = np.array([0.0, 0.0, cam_height])
    u = np.arange(width, dtype=float)
    v = np.arange(height, dtype=float)
    U, V = np.meshgrid(u, v)
    d = np.stack([(U - intr.cx) / intr.fx, (V - intr.cy) / intr.fy, np.ones_like(U)], axis=-1)
    best = np.full((height, width), np.inf)
    labels = np.full((height, width), -1, np.int32)
    for k, r in enumerate(rects):
        c = R.T @ (np.asarray(r.center, float) - t)
        e1 = R.T @ np.asarray(r.e1, float)
        e2 = R.T @ np.asarray(r.e2, float)
        n = np.cross(e1, e2)
        denom = d @ n
        with np.errstate(divide="ignore", invalid="ignore"):
            tt = (c @ n) / denom
        p = tt[..., None] * d - c
        inside = (np.abs(p @ e1) <= r.a) & (np.abs(p @ e2) <= r.b) & (tt > 0) & (tt < best)
        best[inside] = tt[inside]
        labels[inside] = k
    z = np.where(np.isfinite(best), best, np.nan)
    if noise:
        rng = np.random.default_rng(seed)
        z = z + rng.normal(0, noise, z.shape) * z * z
    xyz = d * z[..., None]
    up = R.T @ np.array([0.0, 0.0, 1.0])
    cloud = Cloud(xyz, intr, up if with_up else None, "analytic")
    return cloud, labels, up, [r.obj for r in rects]


def floor(size=6.0, y=3.0):
    return Rect((0, y, 0), (1, 0, 0), (0, 1, 0), size / 2, size / 2)


def wall(y=5.5, w=6.0, h=2.5):
    return Rect((0, y, h / 2), (1, 0, 0), (0, 0, 1), w / 2, h / 2)


def box(cx, cy, sx, sy, sz, obj=1):
    """Top and the four sides of an axis-aligned box standing on the floor."""
    return [
        Rect((cx, cy, sz), (1, 0, 0), (0, 1, 0), sx / 2, sy / 2, obj),
        Rect((cx, cy - sy / 2, sz / 2), (1, 0, 0), (0, 0, 1), sx / 2, sz / 2, obj),
        Rect((cx - sx / 2, cy, sz / 2), (0, 1, 0), (0, 0, 1), sy / 2, sz / 2, obj),
        Rect((cx + sx / 2, cy, sz / 2), (0, 1, 0), (0, 0, 1), sy / 2, sz / 2, obj),
        Rect((cx, cy + sy / 2, sz / 2), (1, 0, 0), (0, 0, 1), sx / 2, sz / 2, obj),
    ]


def stairs(cx, y0, n=3, rise=0.17, run=0.28, width=1.0, obj=1):
    """Risers facing the camera (-y) and treads; step k's riser at y0 + k * run."""
    out = []
    for k in range(n):
        y = y0 + k * run
        out.append(Rect((cx, y, (k + 0.5) * rise), (1, 0, 0), (0, 0, 1), width / 2, rise / 2, obj))
        out.append(Rect((cx, y + run / 2, (k + 1) * rise), (1, 0, 0), (0, 1, 0), width / 2, run / 2, obj))
    return out


def ramp(cx, y0, angle=15.0, length=1.5, width=1.0, obj=1):
    """An inclined rectangle rising away from the camera, starting on the floor at y0."""
    a = math.radians(angle)
    e2 = (0.0, math.cos(a), math.sin(a))
    c = (cx, y0 + math.cos(a) * length / 2, math.sin(a) * length / 2)
    return [Rect(c, (1, 0, 0), e2, width / 2, length / 2, obj)]
