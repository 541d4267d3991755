"""Independent judge scenes: box / stairs / ramp / clutter scenes made WITHOUT planerel's generators.

Nothing here imports ``planerel.synth.generator*``: the geometry is built as trimesh meshes (world z up,
floor ``z = 0``, metres), the depth image is ray cast by this file's own vectorised
Moller-Trumbore routine (trimesh's ``ray`` module needs ``rtree``, which planerel does not
install), the camera poses, dimensions and sensor noise are drawn here.  Each scene is written as

``iNNNN.npy``          ``(H, W, 3)`` float32 XYZ in the camera frame (x right, y down, z forward), NaN = missing
``iNNNN.json``         sidecar: ``intrinsics``, ``up`` (camera frame), ``objects`` [{index, class, kind}], ``params``
``iNNNN.objects.npy``  ``(H, W)`` int32 truth: ``k >= 1`` object k, 0 environment (floor, walls, landings), -1 missing
``iNNNN.planes.npy``   ``(H, W)`` int32 true plane id (coplanar faces of one object), -1 missing

which :func:`planerel.io.readers.read` reads as is (the sidecar gives the up vector).  Classes: ``box``,
``stairs``, ``ramp`` and ``other`` (tables, chairs, cylinders, laptops; with ``--furniture`` also
room furniture).

Usage::

    python benchmarks/independent_scenes.py make OUT_DIR [--n 60] [--seed 7] [--size 160x120]
        [--kinds box,stairs,ramp] [--sensor plain|kinect|stereo|tof] [--heights LOW,HIGH] [--furniture]
        [--speckle-floor KEEP] [--stereo-sigma PX] [--stereo-wave PX] [--riser-lean LOW,HIGH]
    python benchmarks/independent_scenes.py score OUT_DIR MODEL_DIR [MODEL_DIR ...] [--figures DIR] [--min-pixels 150] [--by-planes]
    python benchmarks/independent_scenes.py dev DEST [--only NAME ...] [--force]

``dev DEST`` makes the team's independent development sets (``DEST/dev_i`` ... ``DEST/dev_tof``,
:data:`DEV_SETS`: the arguments each was made with) that ``DEST`` does not hold yet; the main real
check (``benchmarks/real_checks.py --independent``) reads them.  Same arguments, same scenes, so a
machine that lost them gets them back bit for bit (about twenty minutes on two cores).

``--kinds`` is the cycle of primary kinds (scene ``i`` is ``kinds[i % len(kinds)]``; a kind may
repeat to weigh it): ``box``, ``stairs``, ``ramp``, ``small_box`` (2-5 boxes of 3-12 cm on a
table seen from 0.35-0.9 m), ``tote_blocks`` (8-22 toy blocks of 2.5-7 cm and 0-2 cartons in
an open tote, piled, seen from 0.6-0.9 m above: :func:`_tote_blocks`), ``pallet`` (one to three
EUR-built pallets in a row holding a wrapped load, one to three cartons set apart, or nothing:
:func:`_pallets`) and ``stairs_top`` (a descending flight seen
from its landing as a person or a robot standing at the top would: 0.5-1.7 m eye height,
0.15-1.0 m back from the landing's nose, pitch 30-60 degrees).  The default cycle
``box,stairs,ramp`` makes the same scenes as before the option existed.  ``--sensor kinect``
quantises depth as the real Kinect frames of ``../shared/data/kinect`` do (3 mm z^2) and drops a
band of ``W / 160`` pixels (4 at 640x480) at depth jumps; ``--sensor stereo`` is an active stereo
pair (D435-like: the matcher's disparity noise, correlated over its window, :func:`render`;
``--stereo-sigma`` sets that noise and ``--stereo-wave`` adds a real D4xx camera's undulation
over tens of pixels, wave82: ``dev_stw``); ``--riser-lean LOW,HIGH`` leans each flight's risers
back from their nosings, as carpeted risers lean (riser92: ``dev_rake``, :func:`staircase`);
``--sensor tof`` a Kinect v2-like time-of-flight camera whose dark objects' upright faces are
five times as noisy and holed (tof72, measured on hunt71's stairwell: :func:`render`);
``plain`` (the default) is the original sensor, unchanged.  ``score``'s ``--min-pixels`` defaults to 150 pixels scaled with the image area (150 at
160x120, 2 400 at 640x480).

``--furniture`` (furn44) adds 1-3 pieces of room furniture of class ``other`` to each scene, in
the camera's view (:func:`add_furniture`; a piece that finds no free place in 80 draws is left
out, so some scenes get none): cabinets (doors) and chests of drawers 0.4-1.2 m wide, 0.5-1.1 m
high, 0.35-0.6 m deep, half of them on a recessed plinth (6-10 cm high, 3-6 cm back), half
with an overhanging top, most with door or drawer fronts 18 mm proud and handles; wardrobes
0.8-2.0 m wide, 1.6-2.0 m high; open bookcases 0.8-2.0 m high with shelves and rows of books;
sofas (seat 0.42-0.48 m, back 0.75-0.9 m, arms, legs or a base to the floor); beds (0.43-0.6
m, a headboard, seen from the foot or the side); radiators on brackets; waste bins (an open box
or round); closed doors recessed 0-4 cm in a wall of their own with a frame.  Pieces of 1.4 m
or narrower stand against a wall of their own half of the time.  The pieces are drawn from a
generator of their own (``[seed, i, 44]``): a scene with them is the scene without them plus
the pieces (same camera, same primary objects and clutter); without the option every scene is
byte-identical to what the generator made before it (tests/test_independent_scenes.py).  The
sidecar's ``params.furniture`` lists each piece's kind, object index, dimensions, place and
yaw.

``score`` classifies every scene with each model (:class:`planerel.classify.classifier.Classifier`, the code
behind ``planerel classify --json``), matches the proposals to the labelled objects
(:func:`planerel.features.object_eval.score_objects`, IoU >= 0.5) and prints per model, over the objects with at least ``--min-pixels`` valid pixels, the object
accuracy per class, the confusion matrix, and how many objects got no proposal; and the class
answers on proposals matching no judged object, with how many of them lie on a labelled object
too small to judge (:func:`small_matches`: a toy block in a tote, 207 of dev_tote's 225 in
session 98) and how many of those name its class.  Same seed, same scenes.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np
import trimesh

CLASSES = ("box", "stairs", "ramp", "other")

# ----------------------------------------------------------------------------- geometry


def _box(extents, center, yaw=0.0):
    m = trimesh.creation.box(extents=extents)
    T = trimesh.transformations.rotation_matrix(yaw, [0, 0, 1])
    T[:3, 3] = center
    m.apply_transform(T)
    return m


def _place(mesh, x, y, yaw):
    """Rotate a mesh built at the origin by ``yaw`` about z and move it to (x, y)."""
    T = trimesh.transformations.rotation_matrix(yaw, [0, 0, 1])
    T[:3, 3] = [x, y, 0.0]
    mesh.apply_transform(T)
    return mesh


def staircase(n, rise, run, width, side_walls, lean=0.0):
    """Stairs ascending along +x from x = 0; each step a solid block to the floor.

    ``lean`` (degrees): each riser leans back this much from its nosing, as a carpeted
    riser does (the carpet runs from the nosing back to the tread below; building codes
    allow up to 30 degrees): a wedge in front of each block's face, its nosing
    ``rise * tan(lean)`` nearer than its foot, the run from nosing to nosing unchanged.

    Returns (stairs mesh, list of environment meshes (side walls))."""
    steps = [_box((run, width, (i + 1) * rise), ((i + 0.5) * run, 0.0, (i + 1) * rise / 2))
             for i in range(n)]
    if lean:
        d, w = rise * np.tan(np.radians(lean)), width / 2
        for i in range(n):
            x, lo, hi = i * run, i * rise, (i + 1) * rise
            steps.append(trimesh.convex.convex_hull(np.array(
                [[x, y, lo] for y in (-w, w)] + [[x, y, hi] for y in (-w, w)]
                + [[x - d, y, hi] for y in (-w, w)], float)))
    walls = []
    if side_walls:
        h = n * rise + 0.9
        for s in (-1, 1):
            walls.append(_box((n * run + 0.4, 0.08, h), (n * run / 2, s * (width / 2 + 0.04), h / 2)))
    return trimesh.util.concatenate(steps), walls


def ramp(length, angle_deg, width):
    """A wedge rising along +x from z = 0 at x = 0 to its top at x = length."""
    h = length * np.tan(np.radians(angle_deg))
    w = width / 2
    pts = np.array([[0, -w, 0], [0, w, 0], [length, -w, 0], [length, w, 0],
                    [length, -w, h], [length, w, h]], float)
    return trimesh.convex.convex_hull(pts)


#: ``pallet`` (pallet97): a pallet's deck height (m) and board thickness, as an EUR / ISO
#: pallet's (EN 13698-1: 144 mm, boards 22 mm, blocks 78 mm)
PALLET_HEIGHT, PALLET_BOARD = 0.144, 0.022


def pallet(length, width, rng):
    """A wooden block pallet ``length`` x ``width`` (along x, y), its deck at
    :data:`PALLET_HEIGHT`, centred on the origin: five deck boards along x with gaps between
    them, three cross boards under them, nine blocks and three bottom boards (the EUR
    pallet's build, the boards' widths drawn around its 100-145 mm), one mesh."""
    t, h = PALLET_BOARD, PALLET_HEIGHT
    parts = []
    # deck boards: the outer two wider, the five spread over the width
    wide, narrow = rng.uniform(0.12, 0.145), rng.uniform(0.08, 0.1)
    widths = [wide, narrow, wide, narrow, wide]
    gap = (width - sum(widths)) / 4
    y = -width / 2
    for w in widths:
        parts.append(_box((length, w, t), (0.0, y + w / 2, h - t / 2)))
        y += w + gap
    xs = (-length / 2 + 0.0725, 0.0, length / 2 - 0.0725)
    ys = (-width / 2 + 0.05, 0.0, width / 2 - 0.05)
    for x in xs:  # cross boards under the deck
        parts.append(_box((0.145, width, t), (x, 0.0, h - 1.5 * t)))
        for yb in ys:  # blocks
            parts.append(_box((0.145, 0.1, h - 3 * t), (x, yb, t + (h - 3 * t) / 2)))
    for yb in ys:  # bottom boards
        parts.append(_box((length, 0.1, t), (0.0, yb, t / 2)))
    return trimesh.util.concatenate(parts)


def table(rng):
    L, W, H = rng.uniform(0.6, 1.4), rng.uniform(0.5, 0.9), rng.uniform(0.65, 0.78)
    t = 0.03
    parts = [_box((L, W, t), (0, 0, H - t / 2))]
    for sx in (-1, 1):
        for sy in (-1, 1):
            parts.append(_box((0.05, 0.05, H - t), (sx * (L / 2 - 0.05), sy * (W / 2 - 0.05), (H - t) / 2)))
    return trimesh.util.concatenate(parts)


def chair(rng):
    s, H = rng.uniform(0.38, 0.48), rng.uniform(0.42, 0.48)
    parts = [_box((s, s, 0.04), (0, 0, H)),
             _box((0.03, s, rng.uniform(0.35, 0.5)), (-s / 2, 0, H + 0.22))]
    for sx in (-1, 1):
        for sy in (-1, 1):
            parts.append(_box((0.03, 0.03, H), (sx * (s / 2 - 0.02), sy * (s / 2 - 0.02), H / 2)))
    return trimesh.util.concatenate(parts)


def cylinder(rng):
    r, h = rng.uniform(0.08, 0.3), rng.uniform(0.2, 1.0)
    m = trimesh.creation.cylinder(radius=r, height=h, sections=24)
    m.apply_translation([0, 0, h / 2])
    return m


def laptop(rng):
    w, d = rng.uniform(0.3, 0.4), rng.uniform(0.22, 0.28)
    base = _box((d, w, 0.02), (0, 0, 0.01))
    lid = _box((0.008, w, d), (0, 0, d / 2))
    open_deg = rng.uniform(95, 125)  # lid angle to the base
    T = trimesh.transformations.rotation_matrix(np.radians(open_deg - 90), [0, 1, 0])
    lid.apply_transform(T)
    lid.apply_translation([-d / 2, 0, 0.02])
    return trimesh.util.concatenate([base, lid])


# ----------------------------------------------------------------------------- room furniture (--furniture)
#
# Pieces of class ``other`` a robot near the floor sees most: their fronts are upright rectangles
# standing on the floor.  Each builder returns the piece built at the origin, standing on z = 0,
# its front facing -y (front face at y = -depth / 2, back at +depth / 2), with its width (x),
# depth (y), height and the details drawn; the door builder also returns its wall.

FURNITURE = ("cabinet", "chest", "wardrobe", "bookcase", "sofa", "bed", "radiator", "bin", "door")


def _front_panels(w, h, z0, d, cols, rows, rng, proud=0.018, gap=0.003):
    """Door or drawer fronts over the front ``x in [-w/2, w/2]``, ``z in [z0, z0 + h]`` of a body
    whose front is at ``y = -d/2``: ``cols x rows`` panels ``proud`` in front, ``gap`` apart, with a
    handle (2 cm proud) on each at random."""
    parts = []
    pw, ph = (w - (cols + 1) * gap) / cols, (h - (rows + 1) * gap) / rows
    handles = rng.random() < 0.7
    for ci in range(cols):
        for ri in range(rows):
            cx = -w / 2 + gap + pw / 2 + ci * (pw + gap)
            cz = z0 + gap + ph / 2 + ri * (ph + gap)
            parts.append(_box((pw, proud, ph), (cx, -d / 2 - proud / 2, cz)))
            if handles:
                if rows > 1:  # a drawer: a bar across its upper middle
                    size, at = (min(0.16, 0.5 * pw), 0.02, 0.02), (cx, cz + 0.25 * ph)
                else:  # a door: an upright bar near its free edge
                    size, at = (0.02, 0.02, 0.14), (cx + (0.4 if ci % 2 == 0 else -0.4) * pw, cz)
                parts.append(_box(size, (at[0], -d / 2 - proud - 0.01, at[1])))
    return parts


def _carcass(rng, w, d, h, cols, rows):
    """A cabinet body: optional recessed plinth (kick board), optional overhanging top, door or
    drawer fronts.  Returns (parts, details)."""
    plinth = rng.random() < 0.5
    pz = rng.uniform(0.06, 0.10) if plinth else 0.0
    recess = rng.uniform(0.03, 0.06) if plinth else 0.0
    top = rng.random() < 0.5
    tt = rng.uniform(0.02, 0.03) if top else 0.0
    over = rng.uniform(0.01, 0.03) if top else 0.0
    body_h = h - pz - tt
    parts = [_box((w, d, body_h), (0, 0, pz + body_h / 2))]
    if plinth:
        parts.append(_box((w - 2 * recess, d - recess, pz), (0, recess / 2, pz / 2)))
    if top:
        parts.append(_box((w + 2 * over, d + over, tt), (0, -over / 2, h - tt / 2)))
    fronts = rng.random() < 0.8
    if fronts:
        parts += _front_panels(w, body_h, pz, d, cols, rows, rng)
    return parts, {"plinth": round(pz, 3), "top_overhang": round(over, 3),
                   "fronts": f"{cols}x{rows}" if fronts else "plain"}


def furniture_piece(sub, rng):
    """One piece of room furniture of kind ``sub`` (one of :data:`FURNITURE`), built at the origin
    (front facing -y, standing on the floor).

    Returns
    -------
    mesh : trimesh.Trimesh
        The piece (the object: class ``other``).
    env : list of trimesh.Trimesh
        Environment parts that come with it (a door's wall and frame).
    dims : dict
        ``width``, ``depth``, ``height`` and the details drawn.
    """
    env = []
    if sub == "cabinet":  # cupboard, sideboard, low cabinet: doors
        w, h, d = rng.uniform(0.4, 1.2), rng.uniform(0.5, 1.1), rng.uniform(0.35, 0.6)
        parts, det = _carcass(rng, w, d, h, cols=1 if w < 0.6 else 2, rows=1)
    elif sub == "chest":  # chest of drawers, nightstand
        w, h, d = rng.uniform(0.4, 1.2), rng.uniform(0.5, 1.1), rng.uniform(0.35, 0.6)
        parts, det = _carcass(rng, w, d, h, cols=1 if w < 0.8 else 2, rows=int(rng.integers(2, 6)))
    elif sub == "wardrobe":
        w, h, d = rng.uniform(0.8, 2.0), rng.uniform(1.6, 2.0), rng.uniform(0.5, 0.62)
        parts, det = _carcass(rng, w, d, h, cols=2 if w < 1.3 else 3, rows=1)
    elif sub == "bookcase":  # open shelves, a back panel, rows of books
        w, h, d = rng.uniform(0.6, 1.0), rng.uniform(0.8, 2.0), rng.uniform(0.25, 0.35)
        t = 0.018
        parts = [_box((t, d, h), (s * (w / 2 - t / 2), 0, h / 2)) for s in (-1, 1)]
        parts.append(_box((w - 2 * t, t, h), (0, d / 2 - t / 2, h / 2)))  # back
        parts.append(_box((w - 2 * t, d, t), (0, 0, h - t / 2)))  # top
        kick = rng.uniform(0.05, 0.08)
        parts.append(_box((w - 2 * t, t, kick), (0, -d / 2 + 0.02 + t / 2, kick / 2)))
        levels = [kick] + list(np.arange(kick + rng.uniform(0.28, 0.38), h - 0.2, rng.uniform(0.28, 0.38)))
        books = 0
        for z in levels:
            parts.append(_box((w - 2 * t, d - t, t), (0, -t / 2, z + t / 2)))
            x = -w / 2 + t
            while x < w / 2 - t - 0.05:  # groups of books, or a gap
                gw = min(rng.uniform(0.05, 0.3), w / 2 - t - x)
                if rng.random() < 0.7:
                    bh = rng.uniform(0.15, 0.26)
                    bd = min(rng.uniform(0.15, 0.22), d - t - 0.01)
                    parts.append(_box((gw, bd, bh), (x + gw / 2, d / 2 - t - bd / 2, z + t + bh / 2)))
                    books += 1
                x += gw
        det = {"shelves": len(levels), "book_groups": books}
    elif sub == "sofa":  # seat at ~0.45 m, a back, arms, legs or a base to the floor
        w, d = rng.uniform(1.4, 2.2), rng.uniform(0.8, 0.95)
        seat = rng.uniform(0.42, 0.48)
        h = rng.uniform(0.75, 0.9)
        arm_w, arm_h = rng.uniform(0.1, 0.25), rng.uniform(0.55, 0.65)
        legs = rng.random() < 0.5
        lz = rng.uniform(0.05, 0.15) if legs else 0.0
        back_d = rng.uniform(0.15, 0.25)
        parts = [_box((w - 2 * arm_w, d - back_d, seat - lz), (0, -back_d / 2, lz + (seat - lz) / 2)),
                 _box((w, back_d, h - lz), (0, d / 2 - back_d / 2, lz + (h - lz) / 2))]
        parts += [_box((arm_w, d - back_d, arm_h - lz), (s * (w / 2 - arm_w / 2), -back_d / 2,
                                                           lz + (arm_h - lz) / 2)) for s in (-1, 1)]
        if legs:
            parts += [_box((0.04, 0.04, lz), (sx * (w / 2 - 0.05), sy * (d / 2 - 0.05), lz / 2))
                      for sx in (-1, 1) for sy in (-1, 1)]
        det = {"seat": round(seat, 3), "legs": round(lz, 3)}
    elif sub == "bed":  # base and mattress ~0.5 m, a headboard; seen from its foot or its side
        bw, bl = rng.uniform(0.9, 1.8), rng.uniform(1.9, 2.1)
        base = rng.uniform(0.25, 0.35)
        mat = rng.uniform(0.18, 0.25)
        parts = [_box((bw, bl, base), (0, 0, base / 2)),
                 _box((bw - 0.02, bl - 0.02, mat), (0, 0, base + mat / 2))]
        head = rng.random() < 0.7
        if head:
            hh = rng.uniform(0.9, 1.2)
            parts.append(_box((bw + 0.04, 0.05, hh), (0, bl / 2 + 0.025, hh / 2)))
        h = base + mat
        if rng.random() < 0.5:  # seen from its side: the long side is the front
            m = trimesh.util.concatenate(parts)
            m.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 0, 1]))
            parts = [m]
            w, d = bl + (0.05 if head else 0.0), bw + 0.04 * head
            det = {"seen_from": "side", "headboard": head}
        else:
            w, d = bw + 0.04 * head, bl + (0.05 if head else 0.0)
            det = {"seen_from": "foot", "headboard": head}
    elif sub == "radiator":  # a panel on brackets, 10-15 cm over the floor
        w, hh, d = rng.uniform(0.5, 1.2), rng.uniform(0.4, 0.7), rng.uniform(0.07, 0.11)
        lift = rng.uniform(0.1, 0.15)
        parts = [_box((w, d, hh), (0, 0, lift + hh / 2))]
        parts += [_box((0.03, 0.03, lift), (s * (w / 2 - 0.08), 0.0, lift / 2)) for s in (-1, 1)]
        h = lift + hh
        det = {"lift": round(lift, 3)}
    elif sub == "bin":  # waste bin: an open box or a round one
        if rng.random() < 0.5:
            w, d, h = rng.uniform(0.25, 0.4), rng.uniform(0.2, 0.3), rng.uniform(0.3, 0.6)
            t = 0.01
            parts = [_box((w, t, h), (0, s * (d / 2 - t / 2), h / 2)) for s in (-1, 1)]
            parts += [_box((t, d - 2 * t, h), (s * (w / 2 - t / 2), 0, h / 2)) for s in (-1, 1)]
            parts.append(_box((w - 2 * t, d - 2 * t, t), (0, 0, t / 2)))
            det = {"shape": "open box"}
        else:
            r, h = rng.uniform(0.12, 0.2), rng.uniform(0.3, 0.6)
            c = trimesh.creation.cylinder(radius=r, height=h, sections=24)
            c.apply_translation([0, 0, h / 2])
            parts, w, d = [c], 2 * r, 2 * r
            det = {"shape": "round"}
    elif sub == "door":  # a closed door in a wall, recessed in its opening, with a frame
        w, h, d = rng.uniform(0.78, 0.9), rng.uniform(1.98, 2.05), 0.04
        wl = rng.uniform(2.0, 4.0)  # the wall's length
        off = rng.uniform(-0.3, 0.3) * (wl - w - 0.3)  # the door's place along it
        wt = 0.1
        rec = rng.uniform(0.0, 0.04)  # the door's face behind the wall's face
        # the wall's front face at y = -d / 2 - rec, so the door's face is rec behind it
        wy = -d / 2 - rec + wt / 2
        left = (off - w / 2) - (-wl / 2)
        right = wl / 2 - (off + w / 2)
        env += [_box((left, wt, 2.5), (-wl / 2 + left / 2, wy, 1.25)),
                _box((right, wt, 2.5), (off + w / 2 + right / 2, wy, 1.25)),
                _box((w, wt, 2.5 - h), (off, wy, h + (2.5 - h) / 2))]
        if rng.random() < 0.7:  # architrave: a frame 6-8 cm wide, 1.5 cm proud of the wall
            a = rng.uniform(0.06, 0.08)
            fy = -d / 2 - rec - 0.0075
            env += [_box((a, 0.015, h + a), (s * (w / 2 + a / 2) + off, fy, (h + a) / 2)) for s in (-1, 1)]
            env.append(_box((w, 0.015, a), (off, fy, h + a / 2)))
        parts = [_box((w, d, h), (off, 0, h / 2)),
                 _box((0.12, 0.05, 0.02), (off + 0.35 * w, -d / 2 - 0.025, 1.0))]  # handle
        det = {"recess": round(rec, 3), "wall_length": round(wl, 3), "along": round(off, 3),
               "frame": len(env) > 3}
        d = d + rec  # the piece's front as placed is the wall's face
    else:
        raise ValueError(f"furniture {sub!r}: one of {FURNITURE}")
    dims = {"width": round(float(w), 3), "depth": round(float(d), 3), "height": round(float(h), 3), **det}
    return trimesh.util.concatenate(parts), env, dims


def _hull2(points):
    """Counter-clockwise convex hull of 2-D points (monotone chain)."""
    pts = sorted(set(map(tuple, np.round(points, 6).tolist())))
    if len(pts) < 3:
        return np.asarray(pts, float)

    def half(seq):
        out = []
        for p in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                                     - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 0:
                out.pop()
            out.append(p)
        return out

    lo, hi = half(pts), half(pts[::-1])
    return np.asarray(lo[:-1] + hi[:-1], float)


def _overlap2(a, b, margin=0.0):
    """True when the convex polygons ``a`` and ``b`` (2-D points) come within ``margin``
    (separating axis test)."""
    for poly in (a, b):
        n = len(poly)
        if n < 2:
            continue
        for k in range(n):
            e = poly[(k + 1) % n] - poly[k]
            ax = np.array([-e[1], e[0]])
            norm = np.linalg.norm(ax)
            if norm == 0:
                continue
            ax /= norm
            pa, pb = a @ ax, b @ ax
            if pa.max() + margin < pb.min() or pb.max() + margin < pa.min():
                return False
    return True


def add_furniture(meshes, objects, eye, R, intr, rng, target, n_range=(1, 3)):
    """Place 1-3 pieces of room furniture (:func:`furniture_piece`) in the camera's view.

    A piece stands 1-5 m from the eye within the middle of the image's width, its front turned
    to the camera (+-0.35 rad), clear of every mesh already placed (their footprints' convex
    hulls, 5 cm apart), off the line of sight to the primary object and 0.4 m or more from the
    eye; pieces 1.4 m or narrower stand against a wall of their own (2.5 m high, 0.1 m thick,
    1-3 m longer than the piece, 0-2 cm behind it) half of the time (a door always does).
    Drawn from ``rng`` only (the scene's own draws are untouched).

    Returns
    -------
    meshes, objects : list
        The scene's, with the pieces (class ``other``, their kind as ``kind``) and walls added.
    placed : list of dict
        Each piece's kind, index, dimensions, place, yaw and ``wall``.
    """
    meshes, objects = list(meshes), list(objects)
    W, H, fx, fy, cx, cy = intr
    hull = [_hull2(m.vertices[:, :2]) for m, _k in meshes[1:]]  # meshes[0]: the floor
    fwd = R[2, :2] / max(np.linalg.norm(R[2, :2]), 1e-9)
    look = float(np.arctan2(fwd[1], fwd[0]))
    half_fov = float(np.arctan((W / 2) / fx))
    sight = np.array([eye[:2], np.asarray(target)[:2]])
    placed = []
    for _ in range(int(rng.integers(n_range[0], n_range[1] + 1))):
        sub = FURNITURE[int(rng.integers(0, len(FURNITURE)))]
        mesh, env, dims = furniture_piece(sub, rng)
        walled = sub == "door" or (dims["width"] <= 1.4 and rng.random() < 0.5)
        if walled and sub != "door":
            wl = dims["width"] + rng.uniform(1.0, 3.0)
            gap = rng.uniform(0.0, 0.02)
            env = [_box((wl, 0.1, 2.5), (rng.uniform(-0.3, 0.3) * (wl - dims["width"]),
                                         dims["depth"] / 2 + gap + 0.05, 1.25))]
        for _try in range(80):
            bearing = look + rng.uniform(-0.7, 0.7) * half_fov
            dist = rng.uniform(1.0, 5.0)
            x, y = eye[0] + dist * np.cos(bearing), eye[1] + dist * np.sin(bearing)
            to_eye = np.arctan2(eye[1] - y, eye[0] - x)
            yaw = float(np.arctan2(np.cos(to_eye), -np.sin(to_eye)) + rng.uniform(-0.35, 0.35))
            T = trimesh.transformations.rotation_matrix(yaw, [0, 0, 1])
            T[:3, 3] = [x, y, 0.0]
            parts = [mesh.copy().apply_transform(T)] + [e.copy().apply_transform(T) for e in env]
            feet = [_hull2(p.vertices[:, :2]) for p in parts]
            if any(_overlap2(f, h, 0.05) for f in feet for h in hull):
                continue
            if any(_overlap2(f, sight, 0.1) for f in feet):
                continue
            if any(_overlap2(f, eye[None, :2], 0.4) for f in feet):
                continue
            # the piece's front middle must fall inside the image, in front of the camera
            front = T[:3, :3] @ np.array([0.0, -dims["depth"] / 2, min(dims["height"] / 2, eye[2])]) + T[:3, 3]
            pc = R @ (front - eye)
            if pc[2] < 0.5:
                continue
            u, v = fx * pc[0] / pc[2] + cx, fy * pc[1] / pc[2] + cy
            if not (0 <= u < W and 0 <= v < H):
                continue
            view = np.array([eye[:2], front[:2] + 0.05 * (eye[:2] - front[:2]) / np.linalg.norm(eye[:2] - front[:2])])
            if any(_overlap2(h, view) for h in hull):  # something already placed hides its front
                continue
            break
        else:
            continue
        objects.append({"index": len(objects) + 1, "class": "other", "kind": sub})
        meshes.append((parts[0], len(objects)))
        meshes += [(p, 0) for p in parts[1:]]
        hull += feet
        placed.append({"kind": sub, "index": len(objects), **dims, "x": round(float(x), 3),
                       "y": round(float(y), 3), "yaw": round(yaw, 3), "wall": bool(walled)})
    return meshes, objects, placed


# ----------------------------------------------------------------------------- scenes


def build_scene(kind, rng, lean=0.0):
    """Meshes of one scene around a primary object of class ``kind`` (a flight's risers
    leaning back ``lean`` degrees: :func:`staircase`).

    Returns
    -------
    meshes : list of (trimesh.Trimesh, int)
        Each mesh with its object index (0 = environment).
    objects : list of dict
        ``{index, class, kind}`` for index 1, 2, ...
    target : ndarray (3,)
        The point the camera looks towards (the primary object's middle).
    info : dict
        Drawn parameters; ``camera_side`` (yaw the camera looks along), ``eye_floor`` (floor
        height under the camera).
    """
    floor = _box((30, 30, 0.02), (0, 0, -0.01))
    meshes = [(floor, 0)]
    objects = []
    info = {"kind": kind}
    look_yaw = rng.uniform(-np.pi, np.pi)  # direction the camera looks along (horizontal)
    eye_floor = 0.0
    taken = []  # (x, y, radius) footprints to keep clutter apart

    def add(mesh, klass, sub):
        objects.append({"index": len(objects) + 1, "class": klass, "kind": sub})
        meshes.append((mesh, len(objects)))

    if kind == "box":
        n = int(rng.integers(1, 4))
        tall = rng.random() < 0.35  # camera below the top: the top is out of view
        wall = rng.random() < 0.4
        yaw = rng.uniform(-np.pi, np.pi)
        c, s = np.cos(yaw), np.sin(yaw)
        x0 = 0.0
        dims = []
        for i in range(n):
            e = np.array([rng.uniform(0.15, 1.0), rng.uniform(0.15, 1.0),
                          rng.uniform(0.5, 1.1) if tall else rng.uniform(0.1, 0.8)])
            touching = i > 0 and rng.random() < 0.6
            gap = 0.0 if touching else rng.uniform(0.25, 0.6)
            if i > 0:
                x0 += dims[-1][0] / 2 + gap + e[0] / 2
            dims.append(e)
            ctr = np.array([x0 * c, x0 * s, e[2] / 2])
            add(_box(e, ctr, yaw), "box", "touching box" if touching else ("tall box" if tall else "box"))
        info.update(n_boxes=n, tall=tall, wall=wall, dims=[d.round(3).tolist() for d in dims])
        span = x0 + dims[0][0] / 2 + dims[-1][0] / 2
        target = np.array([x0 / 2 * c, x0 / 2 * s, 0.3])
        if wall:  # a wall touching the boxes' backs
            depth = max(d[1] for d in dims)
            off = np.array([-s, c]) * (depth / 2 + 0.05)
            wc = np.array([x0 / 2 * c, x0 / 2 * s]) + off
            meshes.append((_box((span + 3, 0.1, 2.5), (wc[0], wc[1], 1.25), yaw), 0))
            look_yaw = yaw + np.pi / 2 + rng.uniform(-0.6, 0.6)  # look at the wall's front
        taken.append((target[0], target[1], span / 2 + 0.6))
    elif kind in ("stairs", "stairs_top"):
        n = int(rng.integers(2, 11))
        rise, run = rng.uniform(0.14, 0.21), rng.uniform(0.22, 0.35)
        width = rng.uniform(0.8, 1.6)
        walls = rng.random() < 0.5
        down = rng.random() < 0.35 or kind == "stairs_top"
        st, ws = staircase(n, rise, run, width, walls, lean)
        yaw = rng.uniform(-np.pi, np.pi)
        _place(st, 0, 0, yaw)
        add(st, "stairs", "stairs from the top" if kind == "stairs_top"
            else ("descending stairs" if down else "ascending stairs"))
        for w in ws:
            meshes.append((_place(w, 0, 0, yaw), 0))
        c, s = np.cos(yaw), np.sin(yaw)
        if down:  # a landing one rise above the top tread (its nose is the first riser down),
            # the camera on it looking down the flight
            hl = (n + 1) * rise
            land = _box((3.0, width + (0.16 if walls else 0.0) + 2, hl), (n * run + 1.5, 0, hl / 2))
            meshes.append((_place(land, 0, 0, yaw), 0))
            eye_floor = hl
            look_yaw = yaw + np.pi + rng.uniform(-0.5, 0.5)
            target = np.array([n * run / 2 * c, n * run / 2 * s, n * rise / 2])
        else:
            look_yaw = yaw + rng.uniform(-0.7, 0.7)
            target = np.array([n * run / 2 * c, n * run / 2 * s, n * rise / 2])
        info.update(steps=n, rise=round(rise, 3), run=round(run, 3), width=round(width, 3),
                    side_walls=walls, descending=down)
        if lean:
            info["riser_lean"] = round(float(lean), 2)
        if kind == "stairs_top":  # the camera stands on the landing (see landing_pose)
            info.update(flight_yaw=float(yaw), nose_x=float(n * run), landing_z=float((n + 1) * rise))
        taken.append((target[0], target[1], n * run / 2 + width / 2 + 0.6))
    elif kind == "ramp":
        L, a, w = rng.uniform(1.0, 4.0), rng.uniform(4.0, 20.0), rng.uniform(0.8, 2.0)
        r = ramp(L, a, w)
        yaw = rng.uniform(-np.pi, np.pi)
        r.apply_translation([-L / 2, 0, 0])
        _place(r, 0, 0, yaw)
        add(r, "ramp", "ramp")
        target = np.array([0.0, 0.0, L * np.tan(np.radians(a)) / 3])
        info.update(length=round(L, 3), angle_deg=round(a, 2), width=round(w, 3))
        taken.append((0.0, 0.0, L / 2 + 0.6))
    elif kind == "small_box":
        # 2-5 small boxes (a product, a toy, a parcel: edges 3-12 cm) on a table top, side by
        # side in a row (touching or a few cm apart), seen from 0.35-0.9 m (close_pose)
        H = rng.uniform(0.6, 0.8)
        L, W = rng.uniform(0.8, 1.4), rng.uniform(0.6, 0.9)
        meshes.append((_box((L, W, 0.03), (0, 0, H - 0.015)), 0))
        for x in (-L / 2 + 0.05, L / 2 - 0.05):
            for y in (-W / 2 + 0.05, W / 2 - 0.05):
                meshes.append((_box((0.05, 0.05, H - 0.03), (x, y, (H - 0.03) / 2)), 0))
        n = int(rng.integers(2, 6))
        yaw = rng.uniform(-np.pi, np.pi)
        c, s = np.cos(yaw), np.sin(yaw)
        x0, dims = 0.0, []
        for i in range(n):
            e = np.array([rng.uniform(0.03, 0.12), rng.uniform(0.03, 0.12), rng.uniform(0.02, 0.10)])
            touching = i > 0 and rng.random() < 0.5
            if i > 0:
                x0 += dims[-1][0] / 2 + (0.0 if touching else rng.uniform(0.02, 0.08)) + e[0] / 2
            dims.append(e)
            own = yaw if touching or i == 0 else yaw + rng.uniform(-0.5, 0.5)
            add(_box(e, np.array([x0 * c, x0 * s, H + e[2] / 2]), own), "box",
                "touching small box" if touching else "small box")
        # the row centred on the table
        shift = np.array([-x0 / 2 * c, -x0 / 2 * s, 0.0])
        for m, k in meshes:
            if k > 0:
                m.apply_translation(shift)
        target = np.array([0.0, 0.0, H + 0.03])
        info.update(n_boxes=n, table_height=round(H, 3), dims=[d.round(3).tolist() for d in dims])
        taken.append((0.0, 0.0, max(L, W) / 2 + 0.6))
    elif kind == "pallet":
        target, look_yaw, radius = _pallets(rng, meshes, add, info)
        taken.append((target[0], target[1], radius))
    elif kind == "tote_blocks":
        target = _tote_blocks(rng, meshes, add, info)
        taken.append((0.0, 0.0, 0.9))
    else:
        raise ValueError(kind)
    # clutter: 0-2 objects of no class, to the sides of the primary
    for _ in range(int(rng.integers(0, 3)) if kind != "other" else 0):
        sub = ["table", "chair", "cylinder", "laptop"][int(rng.integers(0, 4))]
        m = {"table": table, "chair": chair, "cylinder": cylinder, "laptop": laptop}[sub](rng)
        rad = float(np.linalg.norm(m.bounds[1, :2] - m.bounds[0, :2])) / 2
        for _try in range(20):
            ang = look_yaw + rng.choice([-1, 1]) * rng.uniform(0.6, 1.4)
            dist = rng.uniform(0.8, 2.2)
            x, y = target[0] + dist * np.cos(ang), target[1] + dist * np.sin(ang)
            if all(np.hypot(x - tx, y - ty) > rad + tr for tx, ty, tr in taken):
                break
        else:
            continue
        taken.append((x, y, rad))
        add(_place(m, x, y, rng.uniform(-np.pi, np.pi)), "other", sub)
    info["look_yaw"] = float(look_yaw)
    info["eye_floor"] = float(eye_floor)
    return meshes, objects, target, info


def _pallets(rng, meshes, add, info):
    """A ``pallet`` scene's content (pallet97): one to three pallets (:func:`pallet`,
    1.0-1.25 x 0.8-1.2 m) side by side 0.05-0.5 m apart on a warehouse floor, a wall behind
    them half of the time.  A pallet holds a load wrapped into one block (``pallet load``,
    0.3-1.5 m high, inset 0-4 cm from the deck's edges: a stack of cartons whose faces lie
    flush is one cuboid to a depth sensor), one to three cartons of 0.2-0.6 m set apart on
    its deck (``carton on pallet``), or nothing (an ``empty pallet``, class ``other``: a
    low slatted platform, no box).  The first pallet is loaded.  The pallets are environment
    (object 0) under a load; each load and carton is a ``box``.  Returns ``(target,
    look_yaw, radius)``: the point the camera looks at (the first load's middle), the yaw it
    looks along (at the row's long side or an end, 0-45 degrees off square) and the
    clutter's keep-out radius."""
    n = int(rng.integers(1, 4))
    yaw = rng.uniform(-np.pi, np.pi)
    c, s = np.cos(yaw), np.sin(yaw)
    x0, loads, prev = 0.0, [], None
    target = None
    for i in range(n):
        L, W = rng.uniform(1.0, 1.25), rng.uniform(0.8, 1.2)
        if i > 0:
            x0 += prev / 2 + rng.uniform(0.05, 0.5) + L / 2
        prev = L
        u = rng.random()
        what = "pallet load" if (i == 0 and u < 0.6) or (i > 0 and u < 0.45) else (
            "carton on pallet" if i == 0 or u < 0.8 else "empty pallet")
        cx, cy = x0 * c, x0 * s
        p = _place(pallet(L, W, rng), cx, cy, yaw)
        if what == "empty pallet":
            add(p, "other", what)
            loads.append({"kind": what, "pallet": [round(L, 3), round(W, 3)]})
            continue
        meshes.append((p, 0))
        if what == "pallet load":
            inset = rng.uniform(0.0, 0.04, size=2)
            e = np.array([L - 2 * inset[0], W - 2 * inset[1], rng.uniform(0.3, 1.5)])
            add(_box(e, (cx, cy, PALLET_HEIGHT + e[2] / 2), yaw), "box", what)
            loads.append({"kind": what, "pallet": [round(L, 3), round(W, 3)],
                          "load": e.round(3).tolist()})
            if target is None:
                target = np.array([cx, cy, PALLET_HEIGHT + e[2] / 2])
            continue
        # one to three cartons in a row along the pallet, apart, each within the deck
        k = int(rng.integers(1, 4))
        ex = [rng.uniform(0.2, min(0.6, L / k - 0.06)) for _ in range(k)]
        free = L - sum(ex)
        gaps = rng.dirichlet(np.ones(k + 1)) * free
        x, dims = -L / 2 + gaps[0], []
        for j in range(k):
            e = np.array([ex[j], rng.uniform(0.2, min(0.5, W - 0.02)), rng.uniform(0.15, 0.6)])
            off = rng.uniform(-(W - e[1]) / 2, (W - e[1]) / 2)
            lx = x + e[0] / 2
            ctr = (cx + lx * c - off * s, cy + lx * s + off * c, PALLET_HEIGHT + e[2] / 2)
            add(_box(e, ctr, yaw + rng.uniform(-0.15, 0.15)), "box", what)
            dims.append(e.round(3).tolist())
            x += e[0] + gaps[j + 1]
            if target is None:
                target = np.array([ctr[0], ctr[1], PALLET_HEIGHT + e[2] / 2])
        loads.append({"kind": what, "pallet": [round(L, 3), round(W, 3)], "cartons": dims})
    # the row's middle, for the wall and the camera
    mid = np.array([x0 / 2 * c, x0 / 2 * s])
    wall = rng.random() < 0.5
    if wall:  # a warehouse wall behind the row, 0.1-0.6 m past the deepest pallet's back
        depth = 1.2 / 2 + rng.uniform(0.1, 0.6)
        wc = mid + np.array([-s, c]) * depth
        meshes.append((_box((x0 + 4.0, 0.2, 3.0), (wc[0], wc[1], 1.5), yaw), 0))
    side = rng.random() < 0.7  # the row's long side, or an end
    look = yaw + np.pi / 2 if side else yaw + (0.0 if rng.random() < 0.5 else np.pi)
    if wall and not side:
        look = yaw + np.pi / 2
    info.update(n_pallets=n, pallets=loads, wall=bool(wall))
    return target, float(look + np.radians(rng.uniform(-45, 45))), float(x0 / 2 + 1.3)


#: ``tote_blocks`` (tote67): the blocks' edges (m), cube or cuboid, and the cartons'
TOTE_BLOCK_EDGE, TOTE_CARTON_EDGE = (0.025, 0.07), (0.08, 0.22)
#: the height map's cell (m) the blocks are stacked on
TOTE_CELL = 0.004


def _tote_blocks(rng, meshes, add, info):
    """A ``tote_blocks`` scene's content (tote67): an open tote (a plastic bin 0.35-0.6 x
    0.25-0.4 m, walls 0.08-0.2 m high and 1 cm thick) on the floor or on a table, holding 0-2
    cartons and 8-22 toy blocks (cubes and cuboids with edges of 2.5-7 cm, yawed at random),
    each dropped at a random place and resting level on whatever is highest under its
    footprint (the tote's floor or the blocks already in: a height map of
    :data:`TOTE_CELL` cells), so blocks touch, pile and stand on each other as in a bin of
    toys.  The tote and the table are environment (object 0); each block and carton is a
    ``box``.  Returns the point the camera looks at (the tote's middle at its rim)."""
    on_table = rng.random() < 0.5
    base = rng.uniform(0.6, 0.8) if on_table else 0.0
    if on_table:
        L, W = rng.uniform(0.9, 1.4), rng.uniform(0.7, 0.9)
        meshes.append((_box((L, W, 0.03), (0, 0, base - 0.015)), 0))
        for x in (-L / 2 + 0.05, L / 2 - 0.05):
            for y in (-W / 2 + 0.05, W / 2 - 0.05):
                meshes.append((_box((0.05, 0.05, base - 0.03), (x, y, (base - 0.03) / 2)), 0))
    tl, tw, th, t = rng.uniform(0.35, 0.6), rng.uniform(0.25, 0.4), rng.uniform(0.08, 0.2), 0.01
    yaw = rng.uniform(-np.pi, np.pi)
    c, s = np.cos(yaw), np.sin(yaw)
    rot = np.array([[c, -s], [s, c]])
    parts = [((tl, tw, t), (0.0, 0.0, t / 2))]
    parts += [((tl, t, th), (0.0, sy * (tw - t) / 2, th / 2)) for sy in (-1, 1)]
    parts += [((t, tw, th), (sx * (tl - t) / 2, 0.0, th / 2)) for sx in (-1, 1)]
    for e, (x, y, z) in parts:
        xy = rot @ np.array([x, y])
        meshes.append((_box(e, (xy[0], xy[1], base + z), yaw), 0))
    # the height map over the tote's inside, in the tote's own frame
    nx, ny = int((tl - 2 * t) / TOTE_CELL), int((tw - 2 * t) / TOTE_CELL)
    hmap = np.zeros((nx, ny))
    gx = (np.arange(nx) + 0.5) * TOTE_CELL - (tl - 2 * t) / 2
    gy = (np.arange(ny) + 0.5) * TOTE_CELL - (tw - 2 * t) / 2
    GX, GY = np.meshgrid(gx, gy, indexing="ij")
    n_cartons, n_blocks = int(rng.integers(0, 3)), int(rng.integers(8, 23))
    dims, placed = [], 0
    for j in range(n_cartons + n_blocks):
        carton = j < n_cartons
        lo, hi = TOTE_CARTON_EDGE if carton else TOTE_BLOCK_EDGE
        if not carton and rng.random() < 0.5:  # a cube
            e = np.full(3, rng.uniform(lo, min(hi, 0.05)))
        else:
            e = np.array([rng.uniform(lo, hi), rng.uniform(lo, hi), rng.uniform(lo, hi) * 0.7])
        e[2] = min(e[2], th + 0.02)
        for _try in range(30):
            a = rng.uniform(-np.pi, np.pi)
            r = 0.5 * np.hypot(e[0], e[1])
            x = rng.uniform(-(tl - 2 * t) / 2 + r * 0.7, (tl - 2 * t) / 2 - r * 0.7)
            y = rng.uniform(-(tw - 2 * t) / 2 + r * 0.7, (tw - 2 * t) / 2 - r * 0.7)
            ca, sa = np.cos(a), np.sin(a)
            u = (GX - x) * ca + (GY - y) * sa
            v = -(GX - x) * sa + (GY - y) * ca
            foot = (np.abs(u) <= e[0] / 2) & (np.abs(v) <= e[1] / 2)
            if not foot.any():
                continue
            z0 = float(hmap[foot].max())
            if z0 + e[2] <= th + 0.03:
                break
        else:
            continue
        hmap[foot] = z0 + e[2]
        xy = rot @ np.array([x, y])
        add(_box(e, (xy[0], xy[1], base + t + z0 + e[2] / 2), yaw + a), "box",
            "carton" if carton else ("stacked block" if z0 > 0 else "toy block"))
        dims.append(e.round(3).tolist())
        placed += 1
    info.update(on_table=bool(on_table), tote=[round(tl, 3), round(tw, 3), round(th, 3)],
                base=round(float(base), 3), n_boxes=placed, dims=dims)
    return np.array([0.0, 0.0, base + th])


def above_pose(target, look_yaw, rng, pitch=None):
    """Eye and camera axes of a ``tote_blocks`` scene: 0.6-0.9 m from the tote's middle,
    looking down at it at a pitch of 55-90 degrees (a bin-picking camera on a stand or an
    arm; ``pitch``: ``(low, high)`` degrees instead, the same draw), roll +-10 degrees."""
    D = rng.uniform(0.6, 0.9)
    lo, hi = (55.0, 89.5) if pitch is None else pitch
    pitch = np.radians(rng.uniform(lo, hi))
    return _pose_down(target, look_yaw, look_yaw, D, pitch, np.radians(rng.uniform(-10, 10)))


# ----------------------------------------------------------------------------- camera + rays


def camera_pose(target, look_yaw, eye_floor, rng, tall=False, heights=None):
    """Eye position and camera axes (right, down, forward as rows of R: x_cam = R (p - eye)).

    ``heights``: ``(low, high)`` eye heights over the floor in metres instead of 0.3-2.0 (0.3-0.5
    for a tall box): the same random draws, so a set made without it is unchanged."""
    lo, hi = heights if heights is not None else ((0.3, 0.5) if tall else (0.3, 2.0))
    h = rng.uniform(lo, hi)
    eye_z = eye_floor + h
    for _ in range(50):
        D = rng.uniform(0.8, 4.0)
        pitch = np.arctan2(eye_z - target[2], D)
        if 0.0 <= pitch <= np.radians(75):
            break
    pitch = float(np.clip(pitch + np.radians(rng.uniform(-5, 5)), 0.0, np.radians(75)))
    eye = np.array([target[0] - D * np.cos(look_yaw), target[1] - D * np.sin(look_yaw), eye_z])
    yaw = look_yaw + np.radians(rng.uniform(-8, 8))
    f = np.array([np.cos(pitch) * np.cos(yaw), np.cos(pitch) * np.sin(yaw), -np.sin(pitch)])
    r = np.array([np.sin(yaw), -np.cos(yaw), 0.0])
    d = np.cross(f, r)
    roll = np.radians(rng.uniform(-12, 12))
    r2 = np.cos(roll) * r + np.sin(roll) * d
    d2 = np.cross(f, r2)
    R = np.stack([r2, d2, f])
    return eye, R, {"height": round(h, 3), "distance": round(D, 3),
                    "pitch_deg": round(float(np.degrees(pitch)), 2),
                    "roll_deg": round(float(np.degrees(roll)), 2)}


def close_pose(target, look_yaw, rng):
    """Eye and camera axes of a ``small_box`` scene: 0.35-0.9 m from the table's middle,
    looking down at it at a pitch of 35-85 degrees (a grasping arm's or a person's view of a
    table top), yaw +-8 degrees off, roll +-10 degrees."""
    D = rng.uniform(0.35, 0.9)
    pitch = np.radians(rng.uniform(35, 85))
    yaw = look_yaw + np.radians(rng.uniform(-8, 8))
    return _pose_down(target, look_yaw, yaw, D, pitch, np.radians(rng.uniform(-10, 10)))


def _pose_down(target, look_yaw, yaw, D, pitch, roll):
    """Eye ``D`` m from ``target`` back along ``look_yaw`` and up at ``pitch`` (radians), the
    camera's axes looking along ``yaw`` at that pitch and rolled by ``roll``: ``(eye, R,
    camera dict)`` as :func:`camera_pose` returns them (``close_pose``, ``above_pose``)."""
    eye = target - D * np.array([np.cos(pitch) * np.cos(look_yaw), np.cos(pitch) * np.sin(look_yaw),
                                 -np.sin(pitch)])
    f = np.array([np.cos(pitch) * np.cos(yaw), np.cos(pitch) * np.sin(yaw), -np.sin(pitch)])
    r = np.array([np.sin(yaw), -np.cos(yaw), 0.0])
    d = np.cross(f, r)
    r2 = np.cos(roll) * r + np.sin(roll) * d
    R = np.stack([r2, np.cross(f, r2), f])
    return eye, R, {"height": round(float(eye[2]), 3), "distance": round(D, 3),
                    "pitch_deg": round(float(np.degrees(pitch)), 2),
                    "roll_deg": round(float(np.degrees(roll)), 2)}


def landing_pose(info, rng):
    """Eye and camera axes of a ``stairs_top`` scene: standing on the landing 0.15-1.0 m back
    from its nose (the first riser down), 0.5-1.7 m eye height (a small robot to a person),
    up to a quarter of the flight's width off its middle, looking down the flight (yaw +-0.3 rad)
    at a pitch of 30-60 degrees, roll +-8 degrees."""
    back = rng.uniform(0.15, 1.0)
    h = rng.uniform(0.5, 1.7)
    off = rng.uniform(-0.25, 0.25) * info["width"]
    fy = info["flight_yaw"]
    c, s = np.cos(fy), np.sin(fy)
    lx, ly = info["nose_x"] + back, off  # flight frame: the flight ascends along +x
    eye = np.array([lx * c - ly * s, lx * s + ly * c, info["landing_z"] + h])
    pitch = np.radians(rng.uniform(30, 60))
    yaw = fy + np.pi + rng.uniform(-0.3, 0.3)
    f = np.array([np.cos(pitch) * np.cos(yaw), np.cos(pitch) * np.sin(yaw), -np.sin(pitch)])
    r = np.array([np.sin(yaw), -np.cos(yaw), 0.0])
    d = np.cross(f, r)
    roll = np.radians(rng.uniform(-8, 8))
    r2 = np.cos(roll) * r + np.sin(roll) * d
    R = np.stack([r2, np.cross(f, r2), f])
    return eye, R, {"height": round(h, 3), "back_from_nose": round(back, 3),
                    "pitch_deg": round(float(np.degrees(pitch)), 2),
                    "roll_deg": round(float(np.degrees(roll)), 2)}


def cast(tri, origin, dirs, chunk=1500):
    """First hit of each ray on triangles (vectorised Moller-Trumbore).

    Parameters
    ----------
    tri : ndarray (T, 3, 3)
    origin : ndarray (3,)
    dirs : ndarray (N, 3)

    Returns
    -------
    t : ndarray (N,)   distance along the ray (inf = no hit)
    face : ndarray (N,) int   hit triangle, -1 none
    """
    v0 = tri[:, 0]
    e1 = tri[:, 1] - v0
    e2 = tri[:, 2] - v0
    s = origin[None, :] - v0  # (T, 3)
    q = np.cross(s, e1)  # (T, 3), independent of the ray
    tq = np.einsum("ij,ij->i", e2, q)
    N = len(dirs)
    t_out = np.full(N, np.inf)
    f_out = np.full(N, -1, np.int64)
    for a in range(0, N, chunk):
        D = dirs[a:a + chunk]  # (n, 3)
        p = np.cross(D[:, None, :], e2[None, :, :])  # (n, T, 3)
        det = np.einsum("ntk,tk->nt", p, e1)
        ok = np.abs(det) > 1e-12
        inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
        u = np.einsum("ntk,tk->nt", p, s) * inv
        v = (D @ q.T) * inv
        t = tq[None, :] * inv
        hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 1e-6)
        t = np.where(hit, t, np.inf)
        k = np.argmin(t, axis=1)
        t_out[a:a + chunk] = t[np.arange(len(D)), k]
        f_out[a:a + chunk] = np.where(np.isfinite(t_out[a:a + chunk]), k, -1)
    return t_out, f_out


def plane_ids(meshes):
    """A plane id per face of the concatenated meshes: faces of one object with the same normal
    and offset (to 1 mm / 0.001) share an id.  Returns ndarray (F,) int."""
    keys = {}
    out = []
    for m, k in meshes:
        n = m.face_normals
        off = np.einsum("ij,ij->i", n, m.triangles[:, 0])
        for a, b in zip(np.round(n, 3).tolist(), np.round(off, 3).tolist(), strict=True):
            out.append(keys.setdefault((k, *a, b), len(keys)))
    return np.asarray(out)


SENSORS = ("plain", "kinect", "stereo", "tof")
#: the ``tof`` sensor (tof72, measured on hunt71's Kinect v2 stairwell frames, 960 wide, with
#: 12 px patch plane fits): depth noise sigma (m per m of depth) of an ordinary surface (1.2-2.4
#: mm at 1.4-2.2 m) and of a dark one (10-11 mm at 2.0-2.25 m: the flight's risers), each
#: correlated over a square of ``W / TOF_CORR`` px (neighbour correlation 0.5-0.8 ordinary, 0.9
#: dark); a dark surface's holes cover :data:`TOF_DARK_HOLES` of it in blobs (18-31 %, blobs of
#: 3 px median, 15 px at the 90th percentile); the chance that an object is dark
TOF_SIGMA, TOF_DARK_SIGMA, TOF_DARK_HOLES, TOF_DARK_P = 0.0008, 0.005, 0.25, 0.5
TOF_CORR, TOF_DARK_CORR, TOF_HOLE_CORR = 320, 120, 320
#: the ``stereo`` sensor: baseline (m), disparity noise (px, RMS), disparity step (px) and the
#: matching window as a share of the image width (D435-like: 50 mm, 0.08 px subpixel RMS,
#: 1/32 px, a 7 px window at 640 wide)
STEREO_BASE, STEREO_SIGMA, STEREO_STEP, STEREO_WINDOW = 0.05, 0.08, 1.0 / 32, 7 / 640
#: ``--stereo-wave``'s undulation: its correlation length (the Gaussian's sigma) as a share of
#: the image width (wave82: real D4xx frames are smooth pixel to pixel but wavy over tens of
#: pixels, ``NoiseModel.wave`` 3.2-4.3 and ``quad`` 0.0006-0.0008 at 640-681 wide on rs-booth,
#: aims-low, sunrgbd-rs and vreloc, against 2.0 and 0.0012-0.0015 for the ``stereo`` sensor's
#: matching noise alone; ``--stereo-sigma 0.04 --stereo-wave 0.15`` gives 3.0-4.1 and
#: 0.0007-0.0008)
STEREO_WAVE_LENGTH = 6 / 640


def render(meshes, eye, R, intr, rng, noise=True, planes=False, sensor="plain", speckle=None,
           wave=None, stereo_sigma=STEREO_SIGMA):
    """Organized XYZ ``(H, W, 3)`` in the camera frame and the object id per pixel (and with
    ``planes`` the true plane id per pixel, -1 missing, as a third result).

    Sensor model ``plain`` (this file's own): depth noise sigma = 1.5 mm + 2.5 mm * z^2, depth
    quantised in steps of 1 mm * z^2 (coarser far away, as a disparity sensor; the step is
    taken at the noisy depth, so the values are no fixed lattice), 2 % random dropouts, no
    return beyond 6 m or at grazing incidence (|cos| < 0.1), and half of the pixels at depth
    jumps > 4 cm dropped.

    ``kinect`` (stairs16r, measured on the real frames of ``../shared/data/kinect`` and
    ``mosd``): depth noise sigma = 1.4 mm * z^2 (Khoshelham and Elberink 2012: 1.425 mm z^2)
    correlated between neighbours (white noise averaged over a square of ``round(W / 160)``
    pixels, scaled back to unit variance; the real frames' residuals on flat patches: 1.0 mm
    at 1 m, 8-11 mm at 3-4 m, neighbour correlation 0.6-0.8); depth on fixed levels of
    inverse depth 0.003 / m apart (disparity levels: steps of 3 mm * z^2; the real frames:
    1-2 mm at 0.7 m, 3 mm at 1.0 m, 6-8 mm at 1.5 m); the same dropouts, range and grazing
    limits; and at half the pixels of each depth jump > 4 cm of the noise-free depth, a band
    of ``round(W / 160)`` pixels on its far side dropped (one pixel at 160x120, four at
    640x480; the real frames' invalid runs across a > 4 cm jump: 2-5 px at 640x480).

    ``stereo`` (step60, an active stereo pair such as the D435's): the noise is the matcher's,
    in disparity ``d = fx b / z`` (``b`` :data:`STEREO_BASE`): unit noise averaged over the
    matching window (:data:`STEREO_WINDOW` of the width) times :data:`STEREO_SIGMA` px, the
    disparity on steps of :data:`STEREO_STEP` px, so the depth error grows as ``z^2 / (fx b)``
    (at 640 wide and 60 degrees: 1.2 cm at 2 m, 2.6 cm at 3 m, 4.6 cm at 4 m, with the window's
    spatial correlation); no return under a disparity of 2 px; the ``kinect`` edge band;
    no isolated random dropouts (a matcher's holes come in blobs, not modelled).

    ``tof`` (tof72, a Kinect v2-like time-of-flight camera, measured on hunt71's stairwell
    frames): depth noise sigma = :data:`TOF_SIGMA` * z correlated over ``W / TOF_CORR`` px, no
    quantisation; each object (not the room) is *dark* with chance :data:`TOF_DARK_P`, and a
    dark object's upright faces (a flight's risers, a box's sides: low infrared return) get
    :data:`TOF_DARK_SIGMA` * z correlated over ``W / TOF_DARK_CORR`` px and holes in blobs over
    :data:`TOF_DARK_HOLES` of them; the same random dropouts, range and grazing limits; no
    shadow band, but at half the pixels on the far side of a depth jump > 4 cm a *flying
    pixel*: a depth drawn between the near and the far surface (the pixel's truth: none).

    ``speckle`` (ground75, ``--speckle-floor``): ``(keep, generator)``: each pixel of the floor
    (the room's level faces at floor height) keeps its depth with chance ``keep``, drawn from
    ``generator`` (its own, so the rest of the scene is the scene without it): a dark floor,
    or a floor an active sensor sees at a grazing angle, measured as scattered pixels no
    region grows over (hunt45's R200 frame under a table: 16 % of the floor's pixels).

    ``wave`` (wave82, ``--stereo-wave``, ``stereo`` only): ``(sigma, generator)``: a smooth
    disparity error of ``sigma`` px RMS, correlated over :data:`STEREO_WAVE_LENGTH` of the
    width (unit white noise under a Gaussian filter), drawn from ``generator`` (its own, so the
    rest of the scene is the scene without it): the undulation of a real active-stereo
    camera's depth over a flat surface, which a 5 px patch does not see and a 25 px one does
    (``NoiseModel.wave`` of real D4xx frames 3-7).  ``stereo_sigma``: the matching noise, px
    RMS (:data:`STEREO_SIGMA`; the same draws scaled).
    """
    if sensor not in SENSORS:
        raise ValueError(f"sensor {sensor!r}: one of {SENSORS}")
    W, H, fx, fy, cx, cy = intr
    uu, vv = np.meshgrid(np.arange(W), np.arange(H))
    rays_cam = np.stack([(uu - cx) / fx, (vv - cy) / fy, np.ones_like(uu, float)], -1).reshape(-1, 3)
    dirs = rays_cam @ R  # camera -> world (R rows are the axes)
    dirs_n = dirs / np.linalg.norm(dirs, axis=1, keepdims=True)
    tri = np.concatenate([m.triangles for m, _ in meshes])
    normals = np.concatenate([m.face_normals for m, _ in meshes])
    owner = np.concatenate([np.full(len(m.faces), k) for m, k in meshes])
    t, face = cast(tri, eye, dirs_n)
    pid = np.where(face >= 0, plane_ids(meshes)[np.maximum(face, 0)], -1) if planes else None
    z = t / np.linalg.norm(rays_cam, axis=1)  # range along the ray -> depth along z
    valid = face >= 0
    truth = np.where(valid, owner[np.maximum(face, 0)], -1)
    if speckle is not None:
        keep, speckle_rng = speckle
        f = np.maximum(face, 0)
        on_floor = valid & (owner[f] == 0) & (normals[f][:, 2] > 0.9) \
            & (np.abs(tri[f][:, 0, 2]) < 1e-6)
        valid &= ~(on_floor & (speckle_rng.random(len(valid)) >= keep))
    cosi = np.abs(np.einsum("ij,ij->i", normals[np.maximum(face, 0)], dirs_n))
    if noise:
        valid &= z < 6.0
        valid &= cosi > 0.1
        z_geo = np.where(valid, z, 1e3).reshape(H, W)  # noise-free depth, no return = far
        kept = rng.random(len(z)) > 0.02
        if sensor != "stereo":  # a matcher leaves no isolated holes (its holes are blobs)
            valid &= kept
        zz = np.where(valid, z, 1.0)
        if sensor == "kinect":
            zz = zz + _correlated_noise(rng, H, W, max(1, round(W / 160))) * 0.0014 * zz ** 2
        elif sensor == "tof":
            k = max(1, round(W / TOF_CORR))
            zz = zz + _correlated_noise(rng, H, W, k) * TOF_SIGMA * zz
            dark = _tof_dark(owner, normals, face, valid, rng)
            kd = max(1, round(W / TOF_DARK_CORR))
            zz = np.where(dark, zz + _correlated_noise(rng, H, W, kd) * TOF_DARK_SIGMA * zz, zz)
            # holes in blobs: a smoothed unit noise above its (1 - TOF_DARK_HOLES) quantile
            blob = _correlated_noise(rng, H, W, max(1, round(W / TOF_HOLE_CORR)))
            valid &= ~(dark & (blob > _normal_quantile(1.0 - TOF_DARK_HOLES)))
        elif sensor == "stereo":
            disp = fx * STEREO_BASE / zz
            disp = disp + _correlated_noise(rng, H, W, max(1, round(W * STEREO_WINDOW))) \
                * stereo_sigma
            if wave is not None:
                disp = disp + _smooth_noise(wave[1], H, W, W * STEREO_WAVE_LENGTH) * wave[0]
            disp = np.round(disp / STEREO_STEP) * STEREO_STEP
            valid &= disp >= 2.0
            zz = fx * STEREO_BASE / np.maximum(disp, 2.0)
        else:
            zz = zz + rng.normal(0, 1, len(z)) * (0.0015 + 0.0025 * zz ** 2)
        if sensor == "kinect":  # levels of inverse depth 0.003 / m apart: steps of 3 mm z^2
            zz = 1.0 / (np.maximum(np.round(1.0 / (zz * 0.003)), 1.0) * 0.003)
        elif sensor == "plain":
            step = 0.001 * zz ** 2
            zz = np.round(zz / step) * step
        z = zz
    z = np.where(valid, z, np.nan).reshape(H, W)
    truth = np.where(valid, truth, -1).reshape(H, W)
    if noise:
        zp = np.nan_to_num(z, nan=1e3)
        if sensor == "tof":
            fly = _flying(z_geo, rng) & np.isfinite(z)
            near = _near_side(z_geo)
            z[fly] = near[fly] + rng.random(int(fly.sum())) * (z_geo[fly] - near[fly])
            truth[fly] = -1
            if planes:
                pid = np.where(fly.reshape(-1), -1, pid)
            drop = np.zeros((H, W), bool)
        elif sensor in ("kinect", "stereo"):
            drop = _edge_band(z_geo, max(1, round(W / 160)), rng) & np.isfinite(z)
        else:
            jump = np.zeros((H, W), bool)
            jump[:, 1:] |= np.abs(np.diff(zp, axis=1)) > 0.04
            jump[1:, :] |= np.abs(np.diff(zp, axis=0)) > 0.04
            drop = jump & (rng.random((H, W)) < 0.5) & np.isfinite(z)
        z[drop] = np.nan
        truth[drop] = -1
    xyz = rays_cam.reshape(H, W, 3) * z[..., None]
    if planes:
        pid = np.where(np.isfinite(z), pid.reshape(H, W), -1).astype(np.int32)
        return xyz.astype(np.float32), truth.astype(np.int32), pid
    return xyz.astype(np.float32), truth.astype(np.int32)


def _smooth_noise(rng, H, W, s):
    """Unit-variance noise ``(H * W,)`` correlated over ``s`` pixels: white noise under a
    Gaussian filter of sigma ``s``, scaled by ``2 sqrt(pi) s`` back to unit variance (the
    filter's squared weights sum to ``1 / (4 pi s^2)``)."""
    from scipy.ndimage import gaussian_filter

    n = gaussian_filter(rng.normal(0, 1, (H, W)), s, mode="reflect")
    return (n * 2.0 * np.sqrt(np.pi) * s).reshape(-1)


def _correlated_noise(rng, H, W, k):
    """Unit-variance noise ``(H * W,)`` correlated over ``k`` pixels: white noise averaged over a
    ``k x k`` square (a sensor that matches windows, as a structured-light one does) and scaled
    by ``k`` back to unit variance."""
    from scipy.ndimage import uniform_filter

    n = rng.normal(0, 1, (H, W))
    if k > 1:
        n = uniform_filter(n, size=k, mode="reflect") * k
    return n.reshape(-1)


def _tof_dark(owner, normals, face, valid, rng):
    """``(H * W,)`` bool: the pixels on an upright face (``|n_z| < 0.3``, world z up) of a dark
    object (``tof``: each object ``k >= 1`` dark with chance :data:`TOF_DARK_P`, drawn in the
    order of the object ids)."""
    ids = np.unique(owner)
    dark_ids = ids[(ids >= 1) & (rng.random(len(ids)) < TOF_DARK_P)]
    f = np.maximum(face, 0)
    return valid & np.isin(owner[f], dark_ids) & (np.abs(normals[f][:, 2]) < 0.3)


def _normal_quantile(q):
    """The standard normal's ``q`` quantile."""
    from scipy.stats import norm

    return float(norm.ppf(q))


def _near_side(zp):
    """``(H, W)``: the nearest of each pixel's four neighbours' noise-free depths (its own at
    the border)."""
    near = zp.copy()
    near[:, 1:] = np.minimum(near[:, 1:], zp[:, :-1])
    near[:, :-1] = np.minimum(near[:, :-1], zp[:, 1:])
    near[1:, :] = np.minimum(near[1:, :], zp[:-1, :])
    near[:-1, :] = np.minimum(near[:-1, :], zp[1:, :])
    return near


def _flying(zp, rng):
    """``(H, W)`` bool: half of the pixels more than 4 cm beyond a neighbour (the far side of a
    depth jump of the noise-free depth ``zp``), where a time-of-flight pixel mixes the two
    surfaces' returns."""
    return (zp - _near_side(zp) > 0.04) & (rng.random(zp.shape) < 0.5)


def _edge_band(zp, width, rng):
    """Pixels to drop at depth jumps > 4 cm (``kinect`` sensor): each jump pixel on the far side
    is dropped with probability 1/2, and with it the ``width - 1`` pixels behind it along the
    axis of the jump (a shadow band as a structured-light sensor leaves).  ``zp``: the
    noise-free depth, pixels with no return set far (jumps of the geometry, not of the noise
    or of random dropouts)."""
    H, W = zp.shape
    band = np.zeros((H, W), bool)
    dx = np.diff(zp, axis=1)  # > 0: the right pixel is farther
    dy = np.diff(zp, axis=0)
    coin = rng.random((H, W)) < 0.5
    for k in range(width):
        right = np.zeros((H, W), bool)
        right[:, 1 + k:] = (dx > 0.04)[:, :W - 1 - k] & coin[:, 1:W - k]
        left = np.zeros((H, W), bool)
        left[:, :W - 1 - k] = (dx < -0.04)[:, k:] & coin[:, k:W - 1]
        down = np.zeros((H, W), bool)
        down[1 + k:, :] = (dy > 0.04)[:H - 1 - k, :] & coin[1:H - k, :]
        up = np.zeros((H, W), bool)
        up[:H - 1 - k, :] = (dy < -0.04)[k:, :] & coin[k:H - 1, :]
        band |= right | left | down | up
    return band


KINDS = ("box", "stairs", "ramp", "stairs_top", "small_box", "tote_blocks", "pallet")


def make_scene(i, seed, size=(160, 120), noise=True, kinds=("box", "stairs", "ramp"), sensor="plain",
               heights=None, furniture=False, speckle_floor=None, stereo_wave=None,
               stereo_sigma=None, riser_lean=None, view_pitch=None):
    """Scene ``i`` of the set of ``seed``: (xyz, truth, sidecar dict, meshes, eye, R, plane ids).

    ``kinds``: the cycle of primary kinds (scene ``i`` is ``kinds[i % len(kinds)]``);
    ``heights``: the camera's eye heights (:func:`camera_pose`; not for ``stairs_top``);
    ``furniture``: add 1-3 pieces of room furniture in view (:func:`add_furniture`, drawn from
    a generator of its own, ``[seed, i, 44]``: the scene without them is the same scene);
    ``speckle_floor``: the share of the floor's pixels measured (:func:`render`'s ``speckle``,
    drawn from a generator of its own, ``[seed, i, 75]``); ``stereo_wave``: the ``stereo``
    sensor's undulation, px of disparity (:func:`render`'s ``wave``, drawn from a generator of
    its own, ``[seed, i, 82]``); ``stereo_sigma``: its matching noise, px (default
    :data:`STEREO_SIGMA`); ``riser_lean``: ``(low, high)`` degrees, a flight's risers lean
    back by an angle drawn in it (:func:`staircase`; a generator of its own, ``[seed, i, 92]``:
    the scene is otherwise the same scene); ``view_pitch``: ``(low, high)`` degrees, a
    ``tote_blocks`` camera's pitch down (default 55-89.5: :func:`above_pose`)."""
    if (stereo_wave is not None or stereo_sigma is not None) and sensor != "stereo":
        raise ValueError("stereo_wave, stereo_sigma: for the stereo sensor only")
    rng = np.random.default_rng([seed, i])
    kind = kinds[i % len(kinds)]
    if kind not in KINDS:
        raise ValueError(f"kind {kind!r}: one of {KINDS}")
    lean = 0.0 if riser_lean is None else float(
        np.random.default_rng([seed, i, 92]).uniform(*riser_lean))
    meshes, objects, target, info = build_scene(kind, rng, lean)
    if kind == "stairs_top":
        eye, R, cam = landing_pose(info, rng)
    elif kind == "small_box":
        eye, R, cam = close_pose(target, info["look_yaw"], rng)
    elif kind == "tote_blocks":
        eye, R, cam = above_pose(target, info["look_yaw"], rng, view_pitch)
    else:
        eye, R, cam = camera_pose(target, info["look_yaw"], info["eye_floor"], rng,
                                  tall=bool(info.get("tall")), heights=heights)
    W, H = size
    hfov = np.radians(rng.uniform(55, 70))
    fx = (W / 2) / np.tan(hfov / 2)
    intr = (W, H, fx, fx, (W - 1) / 2, (H - 1) / 2)
    placed = None
    if furniture:
        meshes, objects, placed = add_furniture(meshes, objects, eye, R, intr,
                                                np.random.default_rng([seed, i, 44]), target)
    speckle = None if speckle_floor is None else (
        float(speckle_floor), np.random.default_rng([seed, i, 75]))
    wave = None if stereo_wave is None else (
        float(stereo_wave), np.random.default_rng([seed, i, 82]))
    xyz, truth, pid = render(meshes, eye, R, intr, rng, noise=noise, planes=True, sensor=sensor,
                             speckle=speckle, wave=wave,
                             stereo_sigma=STEREO_SIGMA if stereo_sigma is None else float(stereo_sigma))
    up = R @ np.array([0.0, 0.0, 1.0])
    side = {"format": "independent-scene", "version": 1, "scene_id": f"i{i:04d}",
            "class": {"stairs_top": "stairs", "small_box": "box", "tote_blocks": "box",
                      "pallet": "box"}.get(kind, kind),
            "intrinsics": {"width": W, "height": H, "fx": float(fx), "fy": float(fx),
                           "cx": (W - 1) / 2, "cy": (H - 1) / 2},
            "up": up.round(9).tolist(),
            "world_to_camera": np.vstack([np.hstack([R, (-R @ eye)[:, None]]), [0, 0, 0, 1]]).round(9).tolist(),
            "objects": objects, "params": {**info, "camera": cam}}
    if sensor != "plain":
        side["params"]["sensor"] = sensor
    if placed is not None:
        side["params"]["furniture"] = placed
    if speckle_floor is not None:
        side["params"]["speckle_floor"] = float(speckle_floor)
    if stereo_wave is not None:
        side["params"]["stereo_wave"] = float(stereo_wave)
    if stereo_sigma is not None:
        side["params"]["stereo_sigma"] = float(stereo_sigma)
    return xyz, truth, side, meshes, eye, R, pid


def _write_json(path, obj):
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(json.dumps(obj, indent=1, sort_keys=True))
    tmp.replace(path)


def _write_npy(path, arr):
    tmp = path.with_name(path.name + ".tmp.npy")
    np.save(tmp, arr)
    tmp.replace(path)


def make_set(out, n, seed, size, kinds=("box", "stairs", "ramp"), sensor="plain", heights=None,
             furniture=False, speckle_floor=None, stereo_wave=None, stereo_sigma=None,
             riser_lean=None, view_pitch=None):
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    for i in range(n):
        xyz, truth, side, *_, pid = make_scene(i, seed, size, kinds=kinds, sensor=sensor,
                                               heights=heights, furniture=furniture,
                                               speckle_floor=speckle_floor,
                                               stereo_wave=stereo_wave,
                                               stereo_sigma=stereo_sigma,
                                               riser_lean=riser_lean,
                                               view_pitch=view_pitch)
        sid = side["scene_id"]
        _write_npy(out / f"{sid}.planes.npy", pid)
        _write_npy(out / f"{sid}.npy", xyz)
        _write_npy(out / f"{sid}.objects.npy", truth)
        _write_json(out / f"{sid}.json", side)
    dt = time.perf_counter() - t0
    meta = {"seed": seed, "n": n, "size": list(size)}
    if tuple(kinds) != ("box", "stairs", "ramp") or sensor != "plain":
        meta.update(kinds=list(kinds), sensor=sensor)
    if heights is not None:
        meta["heights"] = list(heights)
    if furniture:
        meta["furniture"] = True
    if speckle_floor is not None:
        meta["speckle_floor"] = float(speckle_floor)
    if stereo_wave is not None:
        meta["stereo_wave"] = float(stereo_wave)
    if stereo_sigma is not None:
        meta["stereo_sigma"] = float(stereo_sigma)
    if riser_lean is not None:
        meta["riser_lean"] = [float(v) for v in riser_lean]
    if view_pitch is not None:
        meta["view_pitch"] = [float(v) for v in view_pitch]
    _write_json(out / "independent.json", meta)
    print(f"made {n} scenes ({size[0]}x{size[1]}) in {dt:.1f} s, {1000 * dt / max(n, 1):.0f} ms/scene -> {out}")


# ----------------------------------------------------------------------------- scoring


def _orientations(clf, cloud, scene_id):
    """``{plane id: "h" | "v" | "i"}`` of a scene as ``clf`` segments and describes it."""
    from planerel.features.facts import describe_scene
    from planerel.ilp.scenes import segment_cached

    labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
    desc = describe_scene(cloud, labels, scene_id=scene_id, **clf._describe_kw)
    return {desc.plane_id(p.label): p.orientation[0] for p in desc.planes}


def _shows(ori, plane_ids):
    """Orientation letters of the planes ``plane_ids`` (sorted; ``ori`` from
    :func:`_orientations`): what a proposal shows, e.g. ``vv`` for two vertical faces without
    a top."""
    return "".join(sorted(ori[q] for q in plane_ids if q in ori))


def default_min_pixels(out):
    """150 pixels at 160x120 (0.8 % of the image, about 1 %), scaled with the set's image area
    (``independent.json``'s size): 2 400 at 640x480, the same share of the image."""
    meta = Path(out) / "independent.json"
    W, H = json.loads(meta.read_text())["size"] if meta.exists() else (160, 120)
    return max(1, round(150 * W * H / (160 * 120)))


def judged_matches(ans, side, truth, min_iou, min_pixels) -> tuple:
    """How one scene's answer ``ans`` matches its objects (``side``: the scene's sidecar,
    ``truth``: its object image): ``(scores, judged, matched)``, the
    :func:`planerel.features.object_eval.score_objects` result, the sidecar's objects that are
    judged (visible, at least ``min_pixels`` pixels) and the indices of the proposals that
    match one of them at IoU >= ``min_iou``.  :func:`score_set` and
    ``spurious_answers.py`` judge with it."""
    from planerel.features.object_eval import proposal_image, score_objects

    prop = proposal_image(ans.labels, [o.labels for o in ans.objects])
    types = {o["index"]: o["class"] for o in side["objects"]}
    sc = score_objects(prop, truth, types=types, min_iou=min_iou)
    judged, matched = [], set()
    for o in side["objects"]:
        k = o["index"]
        if k not in sc.best_iou or (truth == k).sum() < min_pixels:
            continue  # not visible, or under min_pixels (1 % of the image): not judged
        judged.append(o)
        if sc.best_iou[k] >= min_iou:
            matched.add(sc.best_prop[k])
    return sc, judged, matched


def small_matches(sc, side, truth, min_iou, min_pixels) -> dict:
    """``{proposal index: class}`` of the proposals that match (IoU >= ``min_iou``, the
    object's best) a labelled object too small to be judged (under ``min_pixels``;
    ``sc`` :func:`judged_matches`' scores): an answer there lies on a real object (a toy
    block in a tote), so it is no answer on nothing, but it is not scored either."""
    sizes = np.bincount(np.asarray(truth).ravel().clip(min=0))
    out = {}
    for o in side["objects"]:
        k = o["index"]
        small = k >= len(sizes) or sizes[k] < min_pixels
        if k in sc.best_iou and sc.best_iou[k] >= min_iou and small:
            out.setdefault(sc.best_prop[k], o["class"])
    return out


def score_set(out, models, figures=None, min_iou=0.5, min_pixels=None, by_planes=False,
              params=()):
    """Score every model of ``models`` on the scenes under ``out``; ``params`` (``NAME=VALUE``
    strings, as ``planerel classify --param`` takes them) override the models' settings."""
    from planerel.classify.classifier import Classifier, explanation_image
    from planerel.commands.classify import _params
    from planerel.io import readers as io

    out = Path(out)
    min_pixels = default_min_pixels(out) if min_pixels is None else min_pixels
    scenes = sorted(p for p in out.glob("i[0-9][0-9][0-9][0-9].npy"))
    results = {}
    for mdir in models:
        rows = []
        t_all = []
        spurious = 0  # proposals matching no labelled object that got a class
        small = [0, 0]  # of those, on a labelled object under min_pixels: answers, class right
        spurious_at = {}  # scene -> those proposals' classes (in the --json output)
        with Classifier(mdir, seg_params=_params(list(params))) as clf:
            for p in scenes:
                side = json.loads(p.with_suffix(".json").read_text())
                truth = np.load(p.with_name(p.stem + ".objects.npy"))
                cloud = io.read(p)
                ans = clf.classify(cloud, scene_id=p.stem)
                t_all.append(ans.seconds)
                sc, judged, matched = judged_matches(ans, side, truth, min_iou, min_pixels)
                bad = False
                ori = None  # the scene's plane orientations, described once when needed
                for o in judged:
                    k = o["index"]
                    iou = sc.best_iou[k]
                    pred = ans.objects[sc.best_prop[k]].klass if iou >= min_iou else "none"
                    rows.append({"scene": p.stem, "object": k, "class": o["class"], "kind": o["kind"],
                                 "pred": pred, "iou": round(iou, 3),
                                 "pixels": int((truth == k).sum())})
                    if by_planes and iou >= min_iou:
                        ori = ori if ori is not None else _orientations(clf, cloud, p.stem)
                        rows[-1]["shows"] = _shows(ori, ans.objects[sc.best_prop[k]].planes)
                    ok = pred == o["class"] or (o["class"] == "other" and pred == "none")
                    bad |= not ok
                tiny = small_matches(sc, side, truth, min_iou, min_pixels)
                extra = []
                for j, o in enumerate(ans.objects):
                    if j not in matched and o.klass != "other":
                        extra.append(o.klass)
                        if j in tiny:  # on a labelled object too small to judge
                            small[0] += 1
                            small[1] += o.klass == tiny[j]
                spurious += len(extra)
                if extra:
                    spurious_at[p.stem] = extra
                if figures and (bad or extra):
                    from PIL import Image
                    fd = Path(figures) / Path(mdir).name
                    fd.mkdir(parents=True, exist_ok=True)
                    Image.fromarray(explanation_image(ans, cloud.depth)).save(fd / f"{p.stem}.png")
        results[str(mdir)] = {**summarize(rows, spurious, len(scenes), t_all), "rows": rows,
                              "spurious_at": spurious_at,
                              "spurious_on_small": {"answers": small[0], "class_right": small[1],
                                                    "min_pixels": min_pixels}}
        print_summary(str(mdir), results[str(mdir)], rows)
        if by_planes:
            print_by_planes(rows)
    return results


def print_by_planes(rows):
    """Right / matched per class, kind and what the matched proposal shows (``--by-planes``)."""
    from collections import Counter

    seen, right = Counter(), Counter()
    for r in rows:
        if "shows" in r:
            key = (r["class"], r["kind"], r["shows"] or "-")
            seen[key] += 1
            right[key] += r["pred"] == r["class"] or (r["class"] == "other" and r["pred"] == "none")
    print("  by what the matched proposal shows (h horizontal, v vertical, i inclined planes):")
    for key in sorted(seen):
        print(f"    {key[0]:7s} {key[1]:18s} {key[2]:10s} {right[key]:3d}/{seen[key]:3d}")


def proposals_on_true_planes(out, min_iou=0.5, min_pixels=None):
    """Found rate per class of planerel's proposals (regiongrow segmentation vs the true planes
    ``iNNNN.planes.npy``): how much of the proposal loss is segmentation."""
    from planerel.features.object_eval import frame_proposals, score_objects
    from planerel.io import readers as io

    min_pixels = default_min_pixels(out) if min_pixels is None else min_pixels
    found = {}
    for p in sorted(Path(out).glob("i[0-9][0-9][0-9][0-9].npy")):
        side = json.loads(p.with_suffix(".json").read_text())
        truth = np.load(p.with_name(p.stem + ".objects.npy"))
        planes = np.load(p.with_name(p.stem + ".planes.npy"))
        cloud = io.read(p)
        for how, lab in (("regiongrow", None), ("true planes", planes)):
            prop, _d, _ms = frame_proposals(cloud, labels=lab)
            sc = score_objects(prop, truth, min_iou=min_iou)
            for o in side["objects"]:
                k = o["index"]
                if k in sc.best_iou and (truth == k).sum() >= min_pixels:
                    d = found.setdefault(how, {}).setdefault(o["class"], [0, 0])
                    d[0] += sc.best_iou[k] >= min_iou
                    d[1] += 1
    for how, d in found.items():
        print(f"proposals on {how:11s}: " + ", ".join(f"{c} {v[0]}/{v[1]}" for c, v in sorted(d.items())))
    return found


def summarize(rows, spurious, n_scenes, times):
    preds = CLASSES + ("none",)
    conf = {c: {q: 0 for q in preds} for c in CLASSES}
    for r in rows:
        conf[r["class"]][r["pred"]] += 1
    per = {}
    for c in CLASSES:
        tot = sum(conf[c].values())
        right = conf[c][c] + (conf[c]["none"] if c == "other" else 0)
        per[c] = {"objects": tot, "correct": right, "accuracy": right / tot if tot else None,
                  "no_proposal": conf[c]["none"]}
    tot = sum(p["objects"] for p in per.values())
    cls = [c for c in CLASSES if c != "other"]
    tc = sum(per[c]["objects"] for c in cls)
    return {"scenes": n_scenes, "objects": tot,
            "accuracy": sum(p["correct"] for p in per.values()) / tot,
            "accuracy_classes": sum(per[c]["correct"] for c in cls) / tc,
            "per_class": per, "confusion": conf, "spurious_class_answers": spurious,
            "ms_per_scene": 1000 * float(np.mean(times))}


def print_summary(name, s, rows):
    print(f"\n== model {name}: {s['scenes']} scenes, {s['objects']} visible objects, "
          f"{s['ms_per_scene']:.0f} ms/scene classify")
    print(f"object accuracy {s['accuracy']:.3f} (box/stairs/ramp only {s['accuracy_classes']:.3f}); "
          f"class answers on proposals matching no object: {s['spurious_class_answers']}")
    tiny = s.get("spurious_on_small")
    if tiny:
        print(f"  of those, on labelled objects too small to judge (under {tiny['min_pixels']} "
              f"pixels): {tiny['answers']}, their class right {tiny['class_right']}")
    for c, p in s["per_class"].items():
        acc = "-" if p["accuracy"] is None else f"{p['accuracy']:.3f}"
        print(f"  {c:7s} {p['correct']:3d}/{p['objects']:3d} = {acc}   no proposal: {p['no_proposal']}")
    preds = CLASSES + ("none",)
    print("  confusion (rows true, columns predicted; none = no proposal at IoU >= 0.5)")
    print("  " + " " * 8 + "".join(f"{q:>8s}" for q in preds))
    for c in CLASSES:
        print("  " + f"{c:>8s}" + "".join(f"{s['confusion'][c][q]:8d}" for q in preds))
    by_kind = {}
    for r in rows:
        d = by_kind.setdefault(r["kind"], [0, 0])
        d[0] += 1
        d[1] += r["pred"] == r["class"] or (r["class"] == "other" and r["pred"] == "none")
    print("  by kind: " + ", ".join(f"{k} {v[1]}/{v[0]}" for k, v in sorted(by_kind.items())))


#: The independent development sets: name -> ``make`` arguments (docs/benchmarks.md "The
#: development sets, made again by one command").  ``dev_st`` and ``dev_stk`` were first made
#: without their command written down: after the reset of 2026-12-02 they were made anew with
#: these arguments (other scenes than before); ``dev_srk`` (2026-12-02) is ``dev_sr``'s scenes
#: seen by the Kinect-like sensor at 640x480.
DEV_SETS = {
    "dev_i": "--n 60 --seed 3201",
    "dev_k": "--n 40 --seed 3202 --sensor kinect --size 640x480",
    "dev_sr": "--n 60 --seed 3203 --kinds stairs,ramp,stairs_top",
    "dev_st": "--n 80 --seed 3205 --kinds stairs,stairs_top,ramp",
    "dev_stk": "--n 40 --seed 3205 --kinds stairs,stairs_top,ramp --sensor kinect --size 640x480",
    "dev_srk": "--n 60 --seed 3203 --kinds stairs,ramp,stairs_top --sensor kinect --size 640x480",
    "dev_low": "--n 40 --seed 3206 --sensor kinect --size 640x480 --kinds box --heights 0.1,0.3",
    "dev_lowb": "--n 40 --seed 4401 --sensor kinect --size 640x480 --kinds box --heights 0.1,0.3",
    "dev_lowr": "--n 20 --seed 4402 --sensor kinect --size 640x480 --kinds ramp --heights 0.1,0.3",
    "dev_furn": "--n 40 --seed 3207 --sensor kinect --size 640x480 --kinds box --heights 0.1,0.3 "
                "--furniture",
    "dev_furn_n": "--n 40 --seed 3207 --sensor kinect --size 640x480 --kinds box --heights 0.3,2.0 "
                  "--furniture",
    # step60: the same kinds of flights seen by an active stereo pair (D435-like disparity
    # noise): real flights at 2-4 m whose steps the segmentation does not make planes of
    "dev_sts": "--n 60 --seed 6002 --kinds stairs,stairs_top,ramp --sensor stereo --size 640x480",
    # small64: 2-5 small boxes (edges 3-12 cm) on a table seen from 0.35-0.9 m (close_pose)
    "dev_small": "--n 40 --seed 6401 --kinds small_box --sensor kinect --size 640x480",
    # tote67: 8-22 toy blocks (2.5-7 cm) and 0-2 cartons in a tote seen from 0.6-0.9 m above
    "dev_tote": "--n 30 --seed 6701 --kinds tote_blocks --sensor kinect --size 640x480",
    "dev_toteo": "--n 30 --seed 6711 --kinds tote_blocks --sensor kinect --size 640x480 "
                 "--view-pitch 20,50",
    # tof72: flights, ramps and boxes seen by a Kinect v2-like time-of-flight camera whose dark
    # objects' upright faces (risers, box sides) are noisy and holed (hunt71's stairwell)
    "dev_tof": "--n 60 --seed 7201 --kinds stairs,stairs_top,ramp,box --sensor tof --size 512x424",
    # riser73: flights and ramps seen by a low robot's Kinect-like camera 0.25-0.5 m over the
    # floor (a tracked rescue robot): risers seen, treads edge on
    "dev_lows": "--n 40 --seed 7301 --kinds stairs,ramp --sensor kinect --size 640x480 "
                "--heights 0.25,0.5",
    # ground75: boxes seen from 0.3-0.8 m over a floor measured only as speckle (15 % of its
    # pixels): no floor plane, the boxes' faces stand on ground no plane took (hunt45's R200)
    "dev_speck": "--n 40 --seed 7501 --kinds box --sensor kinect --size 640x480 "
                 "--heights 0.3,0.8 --speckle-floor 0.15",
    # wave82: dev_sts's scenes seen by a stereo pair with a real D4xx's noise spectrum (less
    # matching noise, undulation over tens of pixels: NoiseModel.wave 3.0-4.1, as rs-booth,
    # aims-low, sunrgbd-rs and vreloc measure 3.2-4.3): flights whose steps grow no planes
    "dev_stw": "--n 60 --seed 6002 --kinds stairs,stairs_top,ramp --sensor stereo --size 640x480 "
               "--stereo-sigma 0.04 --stereo-wave 0.15",
    # riser92: dev_stk's flights (the same scenes) with carpeted risers leaning back 5-25
    # degrees from their nosings (a real carpeted flight's measure 11-13: hunt92 depth_21)
    "dev_rake": "--n 40 --seed 3205 --kinds stairs,stairs_top,ramp --sensor kinect --size 640x480 "
                "--riser-lean 5,25",
    # pallet97: loads and cartons on pallets in a warehouse, seen by a time-of-flight camera
    # (a forklift's or a logistics robot's) and by a Kinect-like one: faces whose foot stands
    # a pallet's height over the floor
    "dev_pal": "--n 40 --seed 9702 --kinds pallet --sensor tof --size 640x480",
    "dev_palk": "--n 40 --seed 9703 --kinds pallet --sensor kinect --size 640x480",
}


def _share(text: str) -> float:
    """``--speckle-floor``'s value: a share in 0..1 (argparse reports anything else)."""
    try:
        v = float(text)
    except ValueError:
        v = float("nan")
    if not 0.0 <= v <= 1.0:
        raise argparse.ArgumentTypeError(f"a share of the floor's pixels in 0..1, got {text!r}")
    return v


def _pixels(text: str) -> float:
    """``--stereo-wave`` / ``--stereo-sigma``'s value: pixels of disparity, 0 or more."""
    try:
        v = float(text)
    except ValueError:
        v = float("nan")
    if not 0.0 <= v < float("inf"):
        raise argparse.ArgumentTypeError(f"pixels of disparity, 0 or more, got {text!r}")
    return v


def _degrees(text: str) -> tuple:
    """``--riser-lean``'s value: ``LOW,HIGH`` degrees, 0 <= LOW <= HIGH < 45."""
    try:
        lo, hi = (float(v) for v in text.split(","))
    except ValueError:
        lo = hi = float("nan")
    if not 0.0 <= lo <= hi < 45.0:
        raise argparse.ArgumentTypeError(f"LOW,HIGH degrees, 0 <= LOW <= HIGH < 45, got {text!r}")
    return lo, hi


def _pitches(text: str) -> tuple[float, float]:
    """``--view-pitch``'s ``LOW,HIGH``: degrees down, 0 <= LOW <= HIGH <= 89.5."""
    try:
        lo, hi = (float(v) for v in text.split(","))
    except ValueError:
        lo = hi = float("nan")
    if not 0.0 <= lo <= hi <= 89.5:
        raise argparse.ArgumentTypeError(f"LOW,HIGH degrees, 0 <= LOW <= HIGH <= 89.5, got {text!r}")
    return lo, hi


def _make(a) -> None:
    """Run ``make`` with parsed arguments ``a``."""
    W, H = (int(v) for v in a.size.lower().split("x"))
    heights = None if a.heights is None else tuple(float(v) for v in a.heights.split(","))
    make_set(a.out, a.n, a.seed, (W, H), kinds=tuple(a.kinds.split(",")), sensor=a.sensor,
             heights=heights, furniture=a.furniture, speckle_floor=a.speckle_floor,
             stereo_wave=a.stereo_wave, stereo_sigma=a.stereo_sigma, riser_lean=a.riser_lean,
             view_pitch=a.view_pitch)


def _parser() -> argparse.ArgumentParser:
    """The command line's parser (``make``, ``score``, ``dev``)."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    m = sub.add_parser("make")
    m.add_argument("out")
    m.add_argument("--n", type=int, default=60)
    m.add_argument("--seed", type=int, default=7)
    m.add_argument("--size", default="160x120")
    m.add_argument("--kinds", default="box,stairs,ramp",
                   help=f"comma-separated cycle of primary kinds, of {', '.join(KINDS)} (a kind may repeat)")
    m.add_argument("--sensor", default="plain", choices=SENSORS)
    m.add_argument("--heights", default=None, metavar="LOW,HIGH",
                   help="camera eye heights over the floor, metres (default 0.3,2.0; 0.3,0.5 for "
                        "a tall box): e.g. 0.1,0.3 for a camera near the floor")
    m.add_argument("--furniture", action="store_true",
                   help="add 1-3 pieces of room furniture (class other: cabinets, chests, wardrobes, "
                        "bookcases, sofas, beds, radiators, bins, doors) in view; off: the same "
                        "scenes as before the option")
    m.add_argument("--speckle-floor", type=_share, default=None, metavar="KEEP",
                   help="measure only this share of the floor's pixels, scattered (a dark floor, "
                        "or one an active sensor sees at a grazing angle: no plane grows on it); "
                        "off: the same scenes as before the option")
    m.add_argument("--stereo-wave", type=_pixels, default=None, metavar="PX",
                   help="with --sensor stereo: a smooth disparity error of PX px RMS correlated "
                        "over tens of pixels (a real D4xx camera's undulation); off: the same "
                        "scenes as before the option")
    m.add_argument("--stereo-sigma", type=_pixels, default=None, metavar="PX",
                   help=f"with --sensor stereo: the matching noise, px RMS (default {STEREO_SIGMA})")
    m.add_argument("--riser-lean", type=_degrees, default=None, metavar="LOW,HIGH",
                   help="a flight's risers lean back from their nosings by an angle drawn in "
                        "LOW..HIGH degrees (a carpeted flight's); off: the same scenes as "
                        "before the option")
    m.add_argument("--view-pitch", type=_pitches, default=None, metavar="LOW,HIGH",
                   help="tote_blocks scenes: the camera looks down LOW..HIGH degrees (default "
                        "55,89.5: a bin-picking camera; e.g. 20,50 for one on a robot's head "
                        "looking into the tote obliquely); off: the same scenes as before the "
                        "option")
    s = sub.add_parser("score")
    s.add_argument("out")
    s.add_argument("models", nargs="+")
    s.add_argument("--figures")
    s.add_argument("--json")
    s.add_argument("--true-planes", action="store_true",
                   help="also count proposals found on the true planes (segmentation's share)")
    s.add_argument("--by-planes", action="store_true",
                   help="also split the matched objects by what their proposal shows (hv, vv, v, ...)")
    s.add_argument("--min-pixels", type=int, default=None,
                   help="judge only objects with at least this many valid pixels "
                        "(default 150 scaled with the image area: 150 at 160x120, 2400 at 640x480)")
    s.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                   help="override a setting of the models, as planerel classify --param does "
                        "(repeatable)")
    d = sub.add_parser("dev")
    d.add_argument("dest")
    d.add_argument("--only", nargs="+", choices=sorted(DEV_SETS), default=None)
    d.add_argument("--force", action="store_true", help="make a set again even if DEST holds it")
    return ap


def main(argv=None):
    ap = _parser()
    a = ap.parse_args(argv)
    if a.cmd == "make":
        if a.sensor != "stereo" and (a.stereo_wave is not None or a.stereo_sigma is not None):
            ap.error("--stereo-wave and --stereo-sigma are for --sensor stereo only")
        _make(a)
    elif a.cmd == "dev":
        for name in a.only or DEV_SETS:
            out = Path(a.dest) / name
            if out.exists() and not a.force:
                print(f"{out}: there already (--force makes it again)")
                continue
            t0 = time.perf_counter()
            _make(ap.parse_args(["make", str(out)] + DEV_SETS[name].split()))
            print(f"{out}: made ({DEV_SETS[name]}) in {time.perf_counter() - t0:.0f} s")
    else:
        res = score_set(a.out, a.models, a.figures, min_pixels=a.min_pixels, by_planes=a.by_planes,
                        params=a.param)
        if a.true_planes:
            res["proposals_found"] = proposals_on_true_planes(a.out, min_pixels=a.min_pixels)
        if a.json:
            _write_json(Path(a.json), res)
    return 0


if __name__ == "__main__":
    sys.exit(main())
