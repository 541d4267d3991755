"""Independent table-top judge scenes (mOSD-like), made WITHOUT planerel's generators (tabletop22).

A table top with 2-12 objects on it, seen by a Kinect-like sensor from 0.6-1.5 m, 30-65 degrees
down: boxes 4-35 cm in any yaw (alone, stacked two high, touching side by side or face to face,
flush), upright cylinders (cans), mugs, bowls (hemispherical shells) and lying cylinders.  The
geometry is built here as trimesh meshes (world z up, metres), ray cast by the vectorised
Moller-Trumbore routine of ``benchmarks/independent_scenes.py`` (``cast``; each mesh only for the
rays inside its projected bounding box) and written with that script's writers; nothing of
``planerel.synth`` is used.  Sensor model (this file's own, structured-light-like, :func:`sense`):

- a projector 7.5 cm to the camera's right: points the projector does not see (its shadow beside
  each object's edge) have no depth;
- axial noise ``sigma = 1.2 mm + 1.9 mm (z - 0.4)^2`` plus a term growing at grazing incidence
  (the Kinect model of Nguyen, Izadi and Lovell 2012), drawn in depth, then the depth quantised in
  disparity: 1/8 pixel of a 580 px x 7.5 cm disparity (2.9 mm at 1 m, 6.5 mm at 1.5 m);
- no depth nearer than 0.5 m, beyond 4.5 m or at incidence under 8 degrees; 1 % random dropouts;
  at depth jumps over 2.5 % of the depth, each pixel on either side dropped with probability 0.5.

``--sensor mosd`` (tabsensor22; the default ``tabletop22`` is the model above, unchanged) is
fitted to the shared real mOSD frames (learn0-5: residuals of the table and of large box faces
against their plane fits, docs/objects.md "(tabsensor22)"): axial noise ``2.0 mm z^2``
correlated between neighbours (white noise averaged over 8x8 pixels at 640x480, scaled back to
unit variance: the real frames' residuals 0.9-1.0 mm at 0.55-0.70 m, 1.2-1.5 mm at 0.76-0.84 m,
neighbour correlation 0.63-0.85) plus a white grazing term ``0.25 mm / sqrt(z) theta^2 / (pi/2 -
theta)^2`` in quadrature (real faces at 59-65 degrees: 1.1-2.0 mm); the same 1/8-pixel disparity
levels, then whole millimetres (the PCDs' depths are integer mm, levels 1 mm apart at 0.6 m, 2 mm
at 0.8 m, 3 mm at 1.0 m); no random dropouts (none inside the real tables); the same projector
shadow; at depth jumps over 2.5 % of the depth, 60 % of the far side's jump pixels start a band of
1-5 dropped pixels (the real frames' gaps on the side away from the shadow: median 2 px, none in
31 %).

mOSD-like cropping: everything lower than 1 cm under the table top (the floor, the legs, the
table's edge, a wall's lower part) is cut away (NaN) in 80 % of the scenes, as in the shared mOSD
frames (no valid point there lies more than 1.1-2.2 cm under the table's plane); the rest keep
the floor (harder than mOSD: the table is then no support but an object of the room, whose
proposal counts as a false one).  30 % of the scenes have a wall 5-35 cm behind the table, kept
above the crop (harder than mOSD, which crops the far background).  No gravity ``up`` in the sidecar (an mOSD PCD has none; planerel estimates it, as on
the real frames); the true one is ``params.true_up``.

Files per scene (``tNNNN``), read by :func:`planerel.io.readers.read` as they are:

``tNNNN.npy``          ``(H, W, 3)`` float32 XYZ in the camera frame (x right, y down, z forward), NaN = missing
``tNNNN.json``         sidecar: ``intrinsics``, ``objects`` [{index, class, kind}], ``params``
``tNNNN.objects.npy``  ``(H, W)`` int32 truth (mOSD style): ``k >= 1`` object k, 0 table / wall / floor, -1 missing

Classes: boxes ``box``, the rest ``other``.  Kinds: ``box`` (alone), ``stacked box`` (lower or
upper box of a stack), ``touching box`` (two boxes sharing part of a face), ``flush box`` (two
boxes side by side whose front faces are one plane), ``cylinder``, ``mug``, ``bowl``,
``lying cylinder``.

Usage::

    python benchmarks/tabletop_scenes.py make OUT_DIR [--n 40] [--seed 11] [--size 640x480] [--sensor tabletop22|mosd]
    python benchmarks/tabletop_scenes.py score OUT_DIR MODEL_DIR [--json FILE] [--min-pixels 150]

``score`` classifies every scene with the model (:class:`planerel.classify.classifier.Classifier`,
as ``independent_scenes.py score``), scores its proposals against the truth with
:func:`planerel.features.object_eval.score_objects` (IoU >= 0.5) and prints issue 22's lines:
found rate, false proposals a frame, merged / split, per kind found and classes, boxes ``box``,
round objects called ``stairs`` / ``ramp``, and why each missed object is missed
(:func:`planerel.features.object_eval.miss_kind`).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np
import trimesh

sys.path.insert(0, str(Path(__file__).resolve().parent))
from independent_scenes import _box, _write_json, _write_npy, cast  # noqa: E402

BOX_KINDS = ("box", "stacked box", "touching box", "flush box")
ROUND_KINDS = ("cylinder", "mug", "bowl", "lying cylinder")
KINDS = BOX_KINDS + ROUND_KINDS

# ----------------------------------------------------------------------------- objects (at the origin, base z = 0)


def _dims(rng):
    """Box extents 4-35 cm, log-uniform."""
    return np.exp(rng.uniform(np.log(0.04), np.log(0.35), 3))


def can(rng):
    r, h = rng.uniform(0.03, 0.06), rng.uniform(0.06, 0.2)
    m = trimesh.creation.cylinder(radius=r, height=h, sections=32)
    m.apply_translation([0, 0, h / 2])
    return m, r


def mug(rng):
    r, h, t = rng.uniform(0.035, 0.05), rng.uniform(0.08, 0.11), 0.005
    wall = trimesh.creation.annulus(r_min=r - t, r_max=r, height=h, sections=32)
    wall.apply_translation([0, 0, h / 2])
    bottom = trimesh.creation.cylinder(radius=r - t, height=t, sections=32)
    bottom.apply_translation([0, 0, t / 2])
    hs = 0.6 * h  # handle: three bars out of the wall
    parts = [wall, bottom,
             _box((0.025, 0.012, 0.01), (r + 0.01, 0, h / 2 + hs / 2 - 0.005)),
             _box((0.025, 0.012, 0.01), (r + 0.01, 0, h / 2 - hs / 2 + 0.005)),
             _box((0.01, 0.012, hs), (r + 0.02, 0, h / 2))]
    return trimesh.util.concatenate(parts), r + 0.025


def bowl(rng):
    """A hemispherical shell (flattened to 50-90 % of its radius) on a small flat foot."""
    R, t = rng.uniform(0.06, 0.12), 0.005
    h = R * rng.uniform(0.5, 0.9)
    a = np.linspace(0.35, np.pi / 2, 10)  # from the foot's edge up to the rim
    outer = np.stack([R * np.sin(a), h * (1 - np.cos(a))], 1)
    outer[:, 1] -= outer[0, 1]
    inner = np.stack([(R - t) * np.sin(a[::-1]), t + (h - t) * (1 - np.cos(a[::-1]))], 1)
    inner[:, 1] -= inner[-1, 1] - t
    prof = np.vstack([[0, 0], outer, inner, [0, t]])
    prof[:, 1] = np.clip(prof[:, 1], 0, None)
    m = trimesh.creation.revolve(prof, sections=32)
    return m, R


def lying(rng):
    r, L = rng.uniform(0.03, 0.07), rng.uniform(0.1, 0.3)
    m = trimesh.creation.cylinder(radius=r, height=L, sections=32)
    m.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 1, 0]))
    m.apply_translation([0, 0, r])
    return m, L / 2


# ----------------------------------------------------------------------------- placement


def _rect(ex, ey, x, y, yaw):
    c, s = np.cos(yaw), np.sin(yaw)
    p = np.array([[-ex, -ey], [ex, -ey], [ex, ey], [-ex, ey]]) / 2
    return p @ np.array([[c, s], [-s, c]]) + [x, y]


def _circle(r, x, y, n=16):
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.stack([x + r * np.cos(a), y + r * np.sin(a)], 1)


def _apart(p, q, gap):
    """Convex polygons ``p``, ``q`` (n, 2) at least ``gap`` apart along one of their edge normals."""
    for poly in (p, q):
        e = np.roll(poly, -1, 0) - poly
        nrm = np.stack([-e[:, 1], e[:, 0]], 1)
        nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
        a, b = poly @ nrm.T, q @ nrm.T if poly is p else p @ nrm.T
        if np.any((b.min(0) - a.max(0) >= gap) | (a.min(0) - b.max(0) >= gap)):
            return True
    return False


def _unit(rng, kind):
    """One placement unit at the origin: ``(list of (mesh, class, kind)), footprint (n, 2))``."""
    if kind == "box":
        e = _dims(rng)
        return [(_box(e, (0, 0, e[2] / 2)), "box", "box")], _rect(e[0], e[1], 0, 0, 0)
    if kind == "stacked":
        e = _dims(rng)
        e[:2] = np.maximum(e[:2], 0.08)
        e[2] = min(e[2], 0.25)
        f = _dims(rng)
        f[:2] = np.minimum(f[:2], e[:2] * 1.1)
        f[2] = min(f[2], 0.25)
        yaw2 = 0.0 if rng.random() < 0.5 else rng.uniform(-np.pi, np.pi)
        dx, dy = rng.uniform(-0.3, 0.3, 2) * e[:2] * 0.5
        lower = _box(e, (0, 0, e[2] / 2))
        upper = _box(f, (0, 0, f[2] / 2), yaw2)
        upper.apply_translation([dx, dy, e[2]])
        return ([(lower, "box", "stacked box"), (upper, "box", "stacked box")],
                _rect(e[0], e[1], 0, 0, 0))
    if kind in ("touching", "flush"):
        e, f = _dims(rng), _dims(rng)
        e[0], f[0] = max(e[0], 0.06), max(f[0], 0.06)
        if kind == "flush":  # same depth (y), fronts (y = -depth/2) in one plane
            f[1] = e[1]
            dy = 0.0
        else:  # side faces overlapping by part of the shorter one
            dy = rng.uniform(-0.4, 0.4) * min(e[1], f[1])
        a = _box(e, (-e[0] / 2, 0, e[2] / 2))
        b = _box(f, (f[0] / 2, dy, f[2] / 2))
        sub = "flush box" if kind == "flush" else "touching box"
        fp = np.vstack([_rect(e[0], e[1], -e[0] / 2, 0, 0), _rect(f[0], f[1], f[0] / 2, dy, 0)])
        from scipy.spatial import ConvexHull

        fp = fp[ConvexHull(fp).vertices]
        return [(a, "box", sub), (b, "box", sub)], fp
    m, r = {"cylinder": can, "mug": mug, "bowl": bowl, "lying cylinder": lying}[kind](rng)
    if kind == "lying cylinder":
        b = m.bounds
        fp = _rect(b[1, 0] - b[0, 0], b[1, 1] - b[0, 1], 0, 0, 0)
    else:
        fp = _circle(r, 0, 0)
    return [(m, "other", kind)], fp


UNITS = ("box", "stacked", "touching", "flush", "cylinder", "mug", "bowl", "lying cylinder")
UNIT_P = (0.22, 0.14, 0.12, 0.07, 0.12, 0.11, 0.11, 0.11)


def build_scene(rng):
    """Meshes of one table-top scene.

    Returns
    -------
    meshes : list of (trimesh.Trimesh, int)
        Each mesh with its object index (0 = environment: table, wall, floor).
    objects : list of dict
        ``{index, class, kind}`` for index 1, 2, ...
    info : dict
        The table's size and height, which environment is kept, the units.
    """
    L, W, H = rng.uniform(0.9, 1.6), rng.uniform(0.6, 1.0), rng.uniform(0.70, 0.78)
    t = 0.03
    meshes = [(_box((30, 30, 0.02), (0, 0, -0.01)), 0), (_box((L, W, t), (0, 0, H - t / 2)), 0)]
    for sx in (-1, 1):
        for sy in (-1, 1):
            meshes.append((_box((0.05, 0.05, H - t), (sx * (L / 2 - 0.05), sy * (W / 2 - 0.05), (H - t) / 2)), 0))
    wall = bool(rng.random() < 0.3)
    if wall:  # behind the table's far side (+y), 0-30 cm away
        wy = W / 2 + rng.uniform(0.0, 0.3) + 0.05
        meshes.append((_box((4.0, 0.1, 2.5), (0, wy, 1.25)), 0))
    objects = []
    n_target = int(rng.integers(2, 13))
    placed = []  # footprints (world)
    units = []
    # objects spread over the middle of the table (mOSD: in front of the camera)
    hx, hy = min(L / 2 - 0.05, 0.45), min(W / 2 - 0.05, 0.35)
    tries = 0
    while len(objects) < n_target and tries < 60:
        tries += 1
        kind = UNITS[int(rng.choice(len(UNITS), p=UNIT_P))]
        if kind in ("stacked", "touching", "flush") and n_target - len(objects) < 2:
            kind = "box"
        parts, fp = _unit(rng, kind)
        yaw = rng.uniform(-np.pi, np.pi)
        c, s = np.cos(yaw), np.sin(yaw)
        for _ in range(30):
            x, y = rng.uniform(-hx, hx), rng.uniform(-hy, hy)
            wfp = fp @ np.array([[c, s], [-s, c]]) + [x, y]
            inside = np.all(np.abs(wfp[:, 0]) < L / 2 - 0.01) and np.all(np.abs(wfp[:, 1]) < W / 2 - 0.01)
            gap = 0.0 if rng.random() < 0.25 else 0.02  # some units next to each other
            if inside and all(_apart(wfp, q, gap) for q in placed):
                break
        else:
            continue
        placed.append(wfp)
        T = trimesh.transformations.rotation_matrix(yaw, [0, 0, 1])
        T[:3, 3] = [x, y, H]
        idx = []
        for m, klass, sub in parts:
            m.apply_transform(T)
            objects.append({"index": len(objects) + 1, "class": klass, "kind": sub})
            meshes.append((m, len(objects)))
            idx.append(len(objects))
        units.append({"unit": kind, "objects": idx, "x": round(x, 3), "y": round(y, 3),
                      "yaw_deg": round(float(np.degrees(yaw)), 1)})
    info = {"table": [round(L, 3), round(W, 3), round(H, 3)], "wall": wall, "units": units}
    return meshes, objects, info


# ----------------------------------------------------------------------------- camera + sensor


def camera_pose(rng, H):
    """Eye and axes (rows of R: right, down, forward; x_cam = R (p - eye)): 0.6-1.5 m from a point
    near the table's centre, 30-65 degrees down, from the table's near side (-y) +-35 degrees."""
    target = np.array([rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1), H + 0.03])
    D, pitch = rng.uniform(0.6, 1.5), np.radians(rng.uniform(30, 65))
    look = np.pi / 2 + np.radians(rng.uniform(-35, 35))  # horizontal direction looked along
    f = np.array([np.cos(pitch) * np.cos(look), np.cos(pitch) * np.sin(look), -np.sin(pitch)])
    eye = target - D * f
    r = np.array([np.sin(look), -np.cos(look), 0.0])
    d = np.cross(f, r)
    roll = np.radians(rng.uniform(-4, 4))
    r2 = np.cos(roll) * r + np.sin(roll) * d
    R = np.stack([r2, np.cross(f, r2), f])
    return eye, R, {"distance": round(D, 3), "pitch_deg": round(float(np.degrees(pitch)), 2),
                    "look_deg": round(float(np.degrees(look)), 2), "roll_deg": round(float(np.degrees(roll)), 2)}


def raycast(meshes, eye, R, intr):
    """Range ``t`` along unit rays, hit face normal and owner per pixel; each mesh is tested only
    against the rays inside its projected bounding box (all rays when part of it is behind the eye)."""
    W, H, fx, fy, cx, cy = intr
    uu, vv = np.meshgrid(np.arange(W), np.arange(H))
    rays_cam = np.stack([(uu - cx) / fx, (vv - cy) / fy, np.ones_like(uu, float)], -1)
    dirs = (rays_cam.reshape(-1, 3) @ R)
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    t_best = np.full(W * H, np.inf)
    nrm = np.zeros((W * H, 3))
    owner = np.full(W * H, -1, np.int64)
    for m, k in meshes:
        pc = (m.vertices - eye) @ R.T
        if np.all(pc[:, 2] > 0.05):
            u, v = fx * pc[:, 0] / pc[:, 2] + cx, fy * pc[:, 1] / pc[:, 2] + cy
            u0, u1 = max(int(np.floor(u.min())), 0), min(int(np.ceil(u.max())), W - 1)
            v0, v1 = max(int(np.floor(v.min())), 0), min(int(np.ceil(v.max())), H - 1)
            if u0 > u1 or v0 > v1:
                continue
            idx = (np.arange(v0, v1 + 1)[:, None] * W + np.arange(u0, u1 + 1)[None, :]).ravel()
        elif np.all(pc[:, 2] <= 0):
            continue
        else:
            idx = np.arange(W * H)
        t, face = cast(m.triangles, eye, dirs[idx])
        better = t < t_best[idx]
        j = idx[better]
        t_best[j] = t[better]
        nrm[j] = m.face_normals[face[better]]
        owner[j] = k
    return t_best, nrm, owner, rays_cam, dirs


SENSORS = ("tabletop22", "mosd")

# ``mosd`` sensor (tabsensor22): fitted to the shared real mOSD frames (learn0-5; docs/objects.md
# "(tabsensor22)").  Axial noise MOSD_NOISE * z^2, correlated over MOSD_WINDOW-pixel squares at
# 640x480 (scaled with the width), plus a white grazing-incidence term MOSD_GRAZE / sqrt(z) *
# theta^2 / (pi/2 - theta)^2 added in quadrature; depth on the 1/8-pixel disparity levels (580 px
# x 7.5 cm, as ``tabletop22``), then rounded to whole millimetres (the PCDs' depths are integer
# mm); no random dropouts; at a depth jump, a band of 1-MOSD_BAND_MAX pixels on the far side
# dropped at MOSD_BAND_P of the jump's pixels.
MOSD_NOISE = 0.0020
MOSD_WINDOW = 8
MOSD_GRAZE = 0.00025
MOSD_BAND_P = 0.6
MOSD_BAND_MAX = 5


def _far_band(z, rel, width, p, rng):
    """Pixels to drop beside depth jumps over ``rel`` of the depth: the farther pixel of each jump
    and, with it, ``width[pixel] - 1`` pixels behind it along the jump's axis, at ``p`` of the
    jump pixels (``width`` an ``(H, W)`` integer array >= 1)."""
    H, W = z.shape
    zp = np.nan_to_num(z, nan=1e3)
    lim = rel * np.nan_to_num(z, nan=1.0)
    coin = (rng.random((H, W)) < p) & np.isfinite(z)
    band = np.zeros((H, W), bool)
    dx = np.diff(zp, axis=1)
    dy = np.diff(zp, axis=0)
    limx = np.minimum(lim[:, 1:], lim[:, :-1])
    limy = np.minimum(lim[1:, :], lim[:-1, :])
    for k in range(int(width.max()) if width.size else 0):
        ok = width > k
        right = np.zeros((H, W), bool)  # the right pixel is farther: band to the right
        right[:, 1 + k:] = (dx > limx)[:, :W - 1 - k] & coin[:, 1:W - k] & ok[:, 1:W - k]
        left = np.zeros((H, W), bool)
        left[:, :W - 1 - k] = (-dx > limx)[:, k:] & coin[:, k:W - 1] & ok[:, k:W - 1]
        down = np.zeros((H, W), bool)
        down[1 + k:, :] = (dy > limy)[:H - 1 - k, :] & coin[1:H - k, :] & ok[1:H - k, :]
        up = np.zeros((H, W), bool)
        up[:H - 1 - k, :] = (-dy > limy)[k:, :] & coin[k:H - 1, :] & ok[k:H - 1, :]
        band |= right | left | down | up
    return band & np.isfinite(z)


def sense(t, nrm, owner, rays_cam, dirs, intr, rng, *, baseline=0.075, f_sensor=580.0, sensor="tabletop22"):
    """The structured-light-like sensor (module docstring; ``sensor`` ``"tabletop22"`` or
    ``"mosd"``, the fit to the real mOSD frames): depth ``(H, W)`` (NaN missing) and the
    per-pixel owner (-1 missing)."""
    if sensor not in SENSORS:
        raise ValueError(f"sensor {sensor!r}: one of {SENSORS}")
    W, H, fx, fy, cx, cy = intr
    z = t / np.linalg.norm(rays_cam.reshape(-1, 3), axis=1)
    valid = np.isfinite(z)
    cosi = np.abs(np.einsum("ij,ij->i", nrm, dirs))
    valid &= (z > 0.5) & (z < 4.5) & (cosi > np.sin(np.radians(8)))
    if sensor == "tabletop22":
        valid &= rng.random(z.size) > 0.01
    zz = np.where(valid, z, 1.0)
    theta = np.arccos(np.clip(cosi, 0, 1))
    theta = np.minimum(theta, np.radians(82))
    fb8 = 8 * f_sensor * baseline  # disparity in 1/8 sensor pixels
    if sensor == "mosd":
        from independent_scenes import _correlated_noise

        k = max(1, round(MOSD_WINDOW * W / 640))
        graze = MOSD_GRAZE / np.sqrt(zz) * theta ** 2 / (np.pi / 2 - theta) ** 2
        zn = zz + _correlated_noise(rng, H, W, k) * MOSD_NOISE * zz ** 2 + rng.normal(0, 1, zz.size) * graze
        zn = fb8 / np.maximum(np.round(fb8 / np.maximum(zn, 0.3)), 1)
        zn = np.round(zn * 1000) / 1000
    else:
        sig = 0.0012 + 0.0019 * (zz - 0.4) ** 2 + 0.0001 / np.sqrt(zz) * theta ** 2 / (np.pi / 2 - theta) ** 2
        zn = zz + rng.normal(0, 1, zz.size) * sig
        zn = fb8 / np.maximum(np.round(fb8 / np.maximum(zn, 0.3)), 1)
    z = np.where(valid, zn, np.nan).reshape(H, W)
    own = np.where(valid, owner, -1).reshape(H, W)
    # projector shadow: a point is dark when a nearer point lies on its line to the projector
    # (baseline along +x: the same image row; projector column u - f b / z, z-buffered per row)
    zt = np.where(np.isfinite(z), z, np.inf)
    fin = np.isfinite(zt)
    up_ = np.arange(W)[None, :] - fx * baseline / np.where(fin, zt, 1.0)
    off = int(np.ceil(fx * baseline / 0.5)) + 2
    col = np.clip(np.round(up_).astype(np.int64) + off, 0, W + off)
    Wp = W + off + 1
    zbuf = np.full(H * Wp, np.inf)
    key = (np.arange(H)[:, None] * Wp + col)
    np.minimum.at(zbuf, key[fin], zt[fin])
    near = np.minimum(zbuf, np.minimum(np.roll(zbuf, 1), np.roll(zbuf, -1)))  # fill 1-column holes
    shadow = fin & (near[key] < zt * 0.97)
    z[shadow] = np.nan
    own[shadow] = -1
    if sensor == "mosd":
        width = rng.integers(1, MOSD_BAND_MAX + 1, (H, W))
        drop = _far_band(z, 0.025, width, MOSD_BAND_P, rng)
        z[drop] = np.nan
        own[drop] = -1
        return z, own
    # dropouts at depth edges
    zp = np.nan_to_num(z, nan=1e3)
    lim = 0.025 * np.nan_to_num(z, nan=1.0)
    jump = np.zeros((H, W), bool)
    dx = np.abs(np.diff(zp, axis=1)) > np.minimum(lim[:, 1:], lim[:, :-1])
    dy = np.abs(np.diff(zp, axis=0)) > np.minimum(lim[1:, :], lim[:-1, :])
    jump[:, 1:] |= dx
    jump[:, :-1] |= dx
    jump[1:, :] |= dy
    jump[:-1, :] |= dy
    drop = jump & (rng.random((H, W)) < 0.5) & np.isfinite(z)
    z[drop] = np.nan
    own[drop] = -1
    return z, own


def make_scene(i, seed, size=(640, 480), sensor="tabletop22"):
    """Scene ``i`` of the set of ``seed``: ``(xyz (H, W, 3) float32, truth (H, W) int32, sidecar)``.
    ``sensor`` changes only the sensing: the geometry and the camera are the same draws."""
    if sensor not in SENSORS:
        raise ValueError(f"sensor {sensor!r}: one of {SENSORS}")
    rng = np.random.default_rng([seed, 2200 + i])
    meshes, objects, info = build_scene(rng)
    H_t = info["table"][2]
    eye, R, cam = camera_pose(rng, H_t)
    W, H = size
    fx = 525.0 * W / 640
    intr = (W, H, fx, fx, (W - 1) / 2, (H - 1) / 2)
    t, nrm, owner, rays_cam, dirs = raycast(meshes, eye, R, intr)
    keep_floor = bool(rng.random() < 0.2)
    if not keep_floor:  # mOSD crop: nothing lower than 1 cm under the table top
        hit_z = eye[2] + t * dirs[:, 2]
        t = np.where(hit_z < H_t - 0.01, np.inf, t)
    z, own = sense(t, nrm, owner, rays_cam, dirs, intr, rng, sensor=sensor)
    xyz = (rays_cam * z[..., None]).astype(np.float32)
    up = R @ np.array([0.0, 0.0, 1.0])
    side = {"format": "tabletop-scene", "version": 1, "scene_id": f"t{i:04d}",
            "intrinsics": {"width": W, "height": H, "fx": fx, "fy": fx, "cx": (W - 1) / 2, "cy": (H - 1) / 2},
            "objects": objects,
            "params": {**info, "floor_kept": keep_floor, "camera": cam, "true_up": up.round(9).tolist(),
                       "world_to_camera": np.vstack([np.hstack([R, (-R @ eye)[:, None]]),
                                                     [0, 0, 0, 1]]).round(9).tolist()}}
    if sensor != "tabletop22":
        side["params"]["sensor"] = sensor
    return xyz, own.astype(np.int32), side


def make_set(out, n, seed, size, sensor="tabletop22"):
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    for i in range(n):
        xyz, truth, side = make_scene(i, seed, size, sensor=sensor)
        sid = side["scene_id"]
        _write_npy(out / f"{sid}.npy", xyz)
        _write_npy(out / f"{sid}.objects.npy", truth)
        _write_json(out / f"{sid}.json", side)
    dt = time.perf_counter() - t0
    meta = {"seed": seed, "n": n, "size": list(size)}
    if sensor != "tabletop22":
        meta["sensor"] = sensor
    _write_json(out / "tabletop.json", meta)
    print(f"made {n} scenes ({size[0]}x{size[1]}) in {dt:.1f} s, {1000 * dt / max(n, 1):.0f} ms/scene -> {out}")


# ----------------------------------------------------------------------------- scoring


def score_set(out, model, min_pixels=150, min_iou=0.5, verbose=False):
    """Classify and score every scene of ``out`` with ``model``; returns the summary dict."""
    from planerel.classify.classifier import Classifier
    from planerel.features.facts import describe_scene
    from planerel.features.object_eval import miss_kind, proposal_image, score_objects
    from planerel.ilp.scenes import segment_cached
    from planerel.io import readers as io

    scenes = sorted(Path(out).glob("t[0-9][0-9][0-9][0-9].npy"))
    rows, frames = [], []
    with Classifier(model) as clf:
        for p in scenes:
            side = json.loads(p.with_suffix(".json").read_text())
            truth = np.load(p.with_name(p.stem + ".objects.npy"))
            small = [o["index"] for o in side["objects"] if (truth == o["index"]).sum() < min_pixels]
            truth = np.where(np.isin(truth, small), -1, truth)  # not judged: too little in view
            cloud = io.read(p)
            ans = clf.classify(cloud, scene_id=p.stem)
            # the proposals' pixels as evaluate-objects counts them: planes plus the points of
            # the curved clusters (the same description the classifier made, with its masks)
            desc = describe_scene(cloud, segment_cached(cloud, method=clf.method, params=clf.seg_params),
                                  scene_id=p.stem, **clf._describe_kw)
            if [tuple(o.planes) for o in desc.objects] != [tuple(o.labels) for o in ans.objects]:
                raise RuntimeError(f"{p.stem}: the description differs from the classifier's")
            prop = proposal_image(ans.labels, [o.labels for o in ans.objects], [o.mask for o in desc.objects])
            kinds = {o["index"]: o["kind"] for o in side["objects"]}
            sc = score_objects(prop, truth, name=p.stem, types=kinds, min_iou=min_iou)
            pr = side["params"]
            cond = "floor kept" if pr.get("floor_kept") else ("wall" if pr.get("wall") else "mOSD-like")
            fr = {"scene": p.stem, "cond": cond, "objects": sc.n_objects, "found": sc.found, "false": sc.false,
                  "merged": sc.merged, "split": sc.split, "seconds": round(ans.seconds, 2),
                  "false_classes": []}
            matched = {sc.best_prop[k] for k in sc.best_iou if sc.best_iou[k] >= min_iou}
            for j, o in enumerate(ans.objects):
                if j not in matched:
                    fr["false_classes"].append(o.klass)
            for o in side["objects"]:
                k = o["index"]
                if k not in sc.best_iou:
                    continue
                iou = sc.best_iou[k]
                pred = ans.objects[sc.best_prop[k]].klass if iou >= min_iou else "none"
                why = "found" if iou >= min_iou else miss_kind(k, prop, truth, ans.labels)
                # the class of the proposal holding most of the object (found or not)
                pk = prop[truth == k]
                pk = pk[pk >= 0]
                held = ans.objects[int(np.bincount(pk).argmax())].klass if pk.size else "none"
                rows.append({"scene": p.stem, "object": k, "class": o["class"], "kind": o["kind"],
                             "pred": pred, "held_by": held, "iou": round(float(iou), 3), "why": why,
                             "pixels": int((truth == k).sum())})
            frames.append(fr)
            if verbose:
                print(p.stem, fr, flush=True)
    return summarize(rows, frames)


def summarize(rows, frames):
    n = len(rows)
    found = sum(r["why"] == "found" for r in rows)
    per_kind = {}
    for r in rows:
        d = per_kind.setdefault(r["kind"], {"objects": 0, "found": 0, "classes": {}, "missed": {}})
        d["objects"] += 1
        d["found"] += r["why"] == "found"
        d["classes"][r["pred"]] = d["classes"].get(r["pred"], 0) + 1
        if r["why"] != "found":
            d["missed"][r["why"]] = d["missed"].get(r["why"], 0) + 1
    boxes = [r for r in rows if r["class"] == "box"]
    rounds = [r for r in rows if r["class"] == "other"]
    false = sum(f["false"] for f in frames)
    false_cls = {}
    for f in frames:
        for c in f["false_classes"]:
            false_cls[c] = false_cls.get(c, 0) + 1
    by_cond = {}
    for f in frames:
        d = by_cond.setdefault(f.get("cond", "-"), {"frames": 0, "objects": 0, "found": 0, "false": 0})
        d["frames"] += 1
        d["objects"] += f["objects"]
        d["found"] += f["found"]
        d["false"] += f["false"]
    return {"frames": len(frames), "objects": n, "found": found, "found_rate": found / max(n, 1),
            "by_condition": by_cond,
            "false": false, "false_per_frame": false / max(len(frames), 1),
            "false_classes": false_cls,
            "merged": sum(f["merged"] for f in frames), "split": sum(f["split"] for f in frames),
            "boxes": len(boxes), "boxes_box": sum(r["pred"] == "box" for r in boxes),
            "rounds": len(rounds),
            "rounds_stairs_ramp": sum(r["pred"] in ("stairs", "ramp") for r in rounds),
            "rounds_held_stairs_ramp": sum(r["held_by"] in ("stairs", "ramp") for r in rounds),
            "per_kind": per_kind, "rows": rows, "frames_detail": frames,
            "seconds_per_frame": float(np.mean([f["seconds"] for f in frames])) if frames else 0.0}


def print_summary(s):
    pct = 100 * s["found_rate"]
    print(f"{s['frames']} frames, {s['objects']} judged objects: found {s['found']}/{s['objects']} ({pct:.1f} %) "
          f"[>= 90 %: {'met' if pct >= 90 else 'not met'}]")
    print(f"false proposals {s['false']} = {s['false_per_frame']:.2f} a frame "
          f"[<= 0.5: {'met' if s['false_per_frame'] <= 0.5 else 'not met'}]; their classes {s['false_classes']}; "
          f"merged {s['merged']}, split {s['split']}")
    bb = 100 * s["boxes_box"] / max(s["boxes"], 1)
    print(f"boxes classified box {s['boxes_box']}/{s['boxes']} ({bb:.1f} %) [>= 85 %: {'met' if bb >= 85 else 'not met'}]")
    print(f"round objects answered stairs/ramp {s['rounds_stairs_ramp']}/{s['rounds']} (in the proposal holding most "
          f"of them: {s['rounds_held_stairs_ramp']}) [never: {'met' if s['rounds_stairs_ramp'] == 0 else 'not met'}]")
    print(f"classify {s['seconds_per_frame']:.2f} s a frame")
    for c, d in sorted(s["by_condition"].items()):
        print(f"  {c:10s} {d['frames']:2d} frames: found {d['found']}/{d['objects']} "
              f"({100 * d['found'] / max(d['objects'], 1):.1f} %), false {d['false'] / max(d['frames'], 1):.2f} a frame")
    for k in KINDS:
        d = s["per_kind"].get(k)
        if d:
            cls = ", ".join(f"{c} {v}" for c, v in sorted(d["classes"].items()))
            mis = ", ".join(f"{c} {v}" for c, v in sorted(d["missed"].items()))
            print(f"  {k:15s} found {d['found']:3d}/{d['objects']:3d}  classes: {cls}" + (f"; missed: {mis}" if mis else ""))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    m = sub.add_parser("make")
    m.add_argument("out")
    m.add_argument("--n", type=int, default=40)
    m.add_argument("--seed", type=int, default=11)
    m.add_argument("--size", default="640x480")
    m.add_argument("--sensor", default="tabletop22", choices=SENSORS,
                   help="tabletop22 (default, the sets as made before) or mosd (fitted to the real mOSD frames)")
    s = sub.add_parser("score")
    s.add_argument("out")
    s.add_argument("model")
    s.add_argument("--json")
    s.add_argument("--verbose", action="store_true")
    s.add_argument("--min-pixels", type=int, default=150,
                   help="judge only objects with at least this many valid pixels (default 150)")
    a = ap.parse_args(argv)
    if a.cmd == "make":
        W, H = (int(v) for v in a.size.lower().split("x"))
        make_set(a.out, a.n, a.seed, (W, H), sensor=a.sensor)
    else:
        res = score_set(a.out, a.model, min_pixels=a.min_pixels, verbose=a.verbose)
        print_summary(res)
        if a.json:
            _write_json(Path(a.json), res)
    return 0


if __name__ == "__main__":
    sys.exit(main())
