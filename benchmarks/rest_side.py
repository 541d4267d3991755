"""Which side of the horizontal planes the clutter rests on, under each reading of the up (grav58).

    nice .venv/bin/python benchmarks/rest_side.py --root /work --model out/model \\
        --truth UP.json [--cache DIR] [--outline image|hull] [--tol 5] [--band 0.02 0.25] \\
        [--independent /work/dev/dev_i ...] [--json OUT.json]
    nice .venv/bin/python benchmarks/rest_side.py --truth UP.json --turned [--outline hull]

``UP.json`` is ``benchmarks/real_up_error.py --json``'s output (its truths).  Things rest on
floors, tables and shelves, on the side the up points to, and seldom hang from ceilings.  A
camera sees a plane from one side only (its normal, turned to the sensor, points to the camera),
so the clutter it sees touching a plane lies on that visible side.  Under an up ``u`` a plane
horizontal to ``u`` (within ``--tol`` degrees) is seen from above when its normal points along
``u``: the clutter touching it *rests*; seen from below, it *hangs*.  Turning ``u`` over swaps
the two, so the pair could tell a ceiling from an upside-down camera's floor, which the planes'
normals and areas cannot (docs/gravity.md, "Room frames read upside down: the clutter's side").

For every real development frame (:func:`real_up_error.frames`) it prints the resting and
hanging clutter area (m^2) under the truth, and, where ``gravity.flip`` reads the frame upside
down, under the upside-down reading and the upright one (``gravity.flip=false``); with
``--independent`` the same for the independent synthetic scenes (their sidecar ``up`` dropped,
the generator's up as the truth) where the flip fires.  Nothing of it is used by the package.
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import math
import os
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

#: Metres: a point nearer its plane than this is the plane's own fitting noise or edge.
BAND_LOW = 0.02
#: Metres: touching the plane as a thing resting on it does (its lower part).
BAND_HIGH = 0.25
#: m^2: a plane at least this large is a support (floor, table, shelf, ceiling) ...
SUPPORT_AREA = 0.05
#: ... and one of at least this much is a surface, not clutter (walls, a second table).
CLUTTER_MAX_AREA = 0.3
#: Metres: supports farther than this (centroid range) do not count.
MAX_RANGE = 4.0
#: Samples per image.
SAMPLES = 40000


def _planes(xyz, lab, nlab):
    """Unit normals turned to the sensor ``(L, 3)``, offsets ``(L,)`` (camera on the positive
    side) and areas ``(L,)`` (m^2, ``12 sqrt(l1 l2)``; 0 under 30 points) of the labels."""
    from planerel.features.labels import _moments

    counts, cent, cov, _ = _moments(xyz, lab, nlab)
    vals, vecs = np.linalg.eigh(cov)
    nrm = vecs[:, :, 0].copy()
    nrm[np.einsum("ij,ij->i", nrm, cent) > 0] *= -1
    off = -np.einsum("ij,ij->i", nrm, cent)
    area = 12.0 * np.sqrt(np.maximum(vals[:, 1], 0) * np.maximum(vals[:, 2], 0))
    area[counts < 30] = 0.0
    return nrm, off, area


def clutter_sides(cloud, labels, ups, tol_deg: float = 5.0, outline: str = "image",
                  band=(BAND_LOW, BAND_HIGH)) -> np.ndarray:
    """Clutter area resting on and hanging from the horizontal planes, per up vector.

    Parameters
    ----------
    cloud : Cloud
        Organized ``(H, W, 3)``.
    labels : array_like, shape (H, W)
        Plane labels, -1 unassigned.
    ups : array_like, shape (K, 3)
        Unit up vectors (camera frame).
    tol_deg : float
        A plane within this of horizontal w.r.t. an up is a support (``SUPPORT_AREA`` or more,
        centroid within ``MAX_RANGE``).
    outline : {"image", "hull"}
        Where clutter must lie: ``image``, between the support's pixels in its image row and in
        its image column (a thing resting on a support hides it; a wall at its edge does not);
        ``hull``, inside the convex hull of the support's points in its own plane.
    band : tuple of float
        Metres off the support's visible side that clutter must lie within: touching it by
        default; ``(0.25, 2.5)`` measures what floats over it.

    Returns
    -------
    ndarray, shape (K, 2)
        Per up, the clutter area (m^2, each sample's footprint at its range) between
        ``band`` off the visible side of the supports seen from above
        (resting) and of those seen from below (hanging).  Clutter: unassigned points and
        planes under ``CLUTTER_MAX_AREA``.
    """
    from scipy.spatial import ConvexHull, Delaunay, QhullError

    ups = np.asarray(ups, dtype=np.float64).reshape(-1, 3)
    out = np.zeros((ups.shape[0], 2))
    xyz = np.asarray(cloud.xyz, dtype=np.float64)
    H, W = xyz.shape[:2]
    valid = np.asarray(cloud.valid) & np.isfinite(xyz).all(axis=2)
    lab = np.where(valid, np.asarray(labels), -1).astype(np.int32)
    nlab = int(lab.max()) + 1
    if nlab <= 0:
        return out
    nrm, off, area = _planes(np.where(valid[..., None], xyz, 0.0), lab, nlab)
    step = max(1, int(math.sqrt(H * W / SAMPLES)))
    p = np.where(valid[..., None], xyz, 0.0)[::step, ::step]
    lb = np.where(valid[::step, ::step], lab[::step, ::step], -2)  # -2: no depth
    h, w = lb.shape
    intr = getattr(cloud, "intrinsics", None)
    fx = float(intr.fx) if intr is not None else 525.0 * W / 640.0
    foot = (np.linalg.norm(p, axis=2) * step / fx) ** 2
    small = np.ones(nlab + 2, dtype=bool)  # -1 and -2 index the last two
    small[:nlab] = area < CLUTTER_MAX_AREA
    clutter = small[lb] & (lb != -2)
    on = lb >= 0
    cnt = np.bincount(lb[on], minlength=nlab).astype(np.float64)
    mean = np.stack([np.bincount(lb[on], weights=p[on][:, i], minlength=nlab) for i in range(3)], 1)
    rng = np.linalg.norm(mean / np.maximum(cnt, 1.0)[:, None], axis=1)
    cos_tol = math.cos(math.radians(tol_deg))
    rows, cols = np.arange(h)[:, None], np.arange(w)[None, :]
    for k in np.flatnonzero((area >= SUPPORT_AREA) & (cnt >= 10) & (rng <= MAX_RANGE)):
        along = ups @ nrm[k]
        hor = np.abs(along) >= cos_tol
        if not hor.any():
            continue
        t = p @ nrm[k] + off[k]  # height on the visible side
        near = clutter & (lb != k) & (t >= band[0]) & (t <= band[1])
        if not near.any():
            continue
        mem = lb == k
        if outline == "image":
            big = np.iinfo(np.int32).max
            inside = (cols > np.where(mem, cols, big).min(axis=1)[:, None]) \
                & (cols < np.where(mem, cols, -1).max(axis=1)[:, None]) \
                & (rows > np.where(mem, rows, big).min(axis=0)[None, :]) \
                & (rows < np.where(mem, rows, -1).max(axis=0)[None, :])
            a = float(foot[near & inside].sum())
        else:
            e1 = np.cross(nrm[k], [1.0, 0.0, 0.0] if abs(nrm[k][0]) < 0.9 else [0.0, 1.0, 0.0])
            e1 /= np.linalg.norm(e1)
            basis = np.stack([e1, np.cross(nrm[k], e1)], axis=1)
            flat = p[mem] @ basis
            try:
                hull = Delaunay(flat[ConvexHull(flat).vertices])
            except QhullError:
                continue
            a = float(foot[near][hull.find_simplex(p[near] @ basis) >= 0].sum())
        out[hor & (along > 0), 0] += a
        out[hor & (along < 0), 1] += a
    return out


def _angle(u, v) -> float:
    c = float(np.dot(u, v)) / float(np.linalg.norm(u) * np.linalg.norm(v))
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def _judge(cloud, labels, truth, gp, args) -> dict:
    from planerel.features.gravity import up_from_cloud

    lab = np.where(cloud.valid, labels, -1)
    est = up_from_cloud(cloud, lab, gp)
    row = {"upside_down": bool(est.upside_down)}
    ups = [] if truth is None else [truth]
    if est.upside_down:
        upr = up_from_cloud(cloud, lab, dataclasses.replace(gp, flip=False))
        ups += [np.asarray(est.vector), np.asarray(upr.vector)]
        if truth is not None:
            row.update(error=round(_angle(est.vector, truth), 2),
                       error_upright=round(_angle(upr.vector, truth), 2))
    if ups:
        cs = clutter_sides(cloud, lab, np.array(ups, float), args.tol, args.outline, args.band)
        names = (["truth"] if truth is not None else []) + (["flip", "upright"] if est.upside_down else [])
        row.update({n: np.round(cs[i], 5).tolist() for i, n in enumerate(names)})
    return row


def _line(name, r) -> str:
    parts = [f"{name:55s}"]
    for n in ("truth", "flip", "upright"):
        if n in r:
            parts.append(f"{n} rest/hang {r[n][0]:.4f}/{r[n][1]:.4f}")
    if "error" in r:
        parts.append(f"error flip {r['error']} upright {r['error_upright']}")
    return "  ".join(parts)


def turned_sweep(outline: str, tol: float) -> dict:
    """The pose sweep turned by 180 degrees about the optical axis (docs/gravity.md, "A camera
    held upside down"; its own seeds): of the flips, how many the veto "keep the upright reading
    when its rest minus hang exceeds the flip's" would turn back, and how many of those were
    right (within 2 degrees)."""
    from planerel.features.gravity import GravityParams, up_from_cloud
    from planerel.segment import segment
    from planerel.synth.gravity_scenes import posed_scene

    turn = np.array([-1.0, -1.0, 1.0])
    tally = {"flips": 0, "right": 0, "vetoed": 0, "vetoed right": 0}
    for kind in ("box", "stairs", "ramp"):
        for pitch in range(0, 85, 5):
            for roll in (-20, -10, 0, 10, 20):
                s = posed_scene(kind, pitch, roll, seed=pitch * 7 + roll + 1000)
                xyz = s.cloud.xyz[::-1, ::-1].copy()
                xyz[..., :2] *= -1.0
                cloud = dataclasses.replace(s.cloud, xyz=xyz, up=None)
                up = s.up * turn
                for lab in (s.gt_labels[::-1, ::-1].copy(), segment(cloud, "regiongrow").labels):
                    est = up_from_cloud(cloud, lab)
                    if not est.upside_down:
                        continue
                    upr = up_from_cloud(cloud, lab, GravityParams(flip=False))
                    cs = clutter_sides(cloud, lab, np.array([est.vector, upr.vector]), tol, outline)
                    right = _angle(est.vector, up) <= 2.0
                    tally["flips"] += 1
                    tally["right"] += right
                    if cs[1, 0] - cs[1, 1] > cs[0, 0] - cs[0, 1]:
                        tally["vetoed"] += 1
                        tally["vetoed right"] += right
                        print(f"turned {kind} pitch {pitch} roll {roll}: vetoed, flip "
                              f"{_angle(est.vector, up):.1f} deg off, upright "
                              f"{_angle(upr.vector, up):.1f}", flush=True)
    return tally


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--root", default="/work")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--truth", help="real_up_error.py --json output (needed but with --turned)")
    ap.add_argument("--band", type=float, nargs=2, default=(BAND_LOW, BAND_HIGH),
                    metavar=("LOW", "HIGH"), help="metres off the support (0.25 2.5: floating)")
    ap.add_argument("--cache")
    ap.add_argument("--outline", choices=("image", "hull"), default="image")
    ap.add_argument("--tol", type=float, default=5.0)
    ap.add_argument("--independent", nargs="*", default=[])
    ap.add_argument("--turned", action="store_true",
                    help="only the turned pose sweep (synthetic): what the veto would turn back")
    ap.add_argument("--json")
    args = ap.parse_args(argv)
    if args.turned:
        print(f"turned pose sweep ({args.outline}): {turned_sweep(args.outline, args.tol)}")
        return 0
    if not args.truth:
        ap.error("--truth is needed (real_up_error.py --json's output)")
    from low_camera_ramps import scenes_of
    from real_up_error import frames

    import planerel
    from planerel.classify.classifier import Classifier
    from planerel.features.gravity import up_from_cloud
    from planerel.ilp.scenes import segment_cached

    truths = {r["frame"]: r["truth"] for r in json.load(open(args.truth))["frames"]}
    rows, tally = {}, {"rest > hang": 0, "rest < hang": 0, "none": 0}
    with Classifier(args.model) as clf:
        gp = clf._describe_kw.get("gravity_params")
        for key, reader, _ in frames(args.root):
            cloud = dataclasses.replace(reader(), up=None)
            src = getattr(cloud, "source", None)
            files = [src] if args.cache and src and os.path.isfile(str(src)) else []
            labels = segment_cached(cloud, method=clf.method, params=clf.seg_params, files=files,
                                    cache=args.cache)
            tr = truths.get(key)
            r = rows[key] = _judge(cloud, labels, None if tr is None else np.asarray(tr, float), gp, args)
            if "truth" in r:
                rest, hang = r["truth"]
                tally["rest > hang" if rest > hang else "rest < hang" if hang > rest else "none"] += 1
                if hang > rest:
                    print("hangs under the truth: " + _line(key, r), flush=True)
            if r["upside_down"]:
                print("read upside down:      " + _line(key, r), flush=True)
        print(f"real frames with a truth ({sum(tally.values())}): " + ", ".join(f"{k} {v}" for k, v in tally.items()))
        for folder in args.independent:
            nf = 0
            for path, intr, scale, _ in scenes_of(Path(folder)):
                cloud = planerel.read(str(path), intrinsics=intr, depth_scale=scale)
                tu = np.asarray(cloud.up, float)
                cloud = dataclasses.replace(cloud, up=None)
                labels = segment_cached(cloud, method=clf.method, params=clf.seg_params,
                                        files=[str(path)] if args.cache else [], cache=args.cache)
                lab = np.where(cloud.valid, labels, -1)
                if not up_from_cloud(cloud, lab, gp).upside_down:
                    continue
                nf += 1
                r = rows[str(path)] = _judge(cloud, labels, tu, gp, args)
                print("read upside down:      " + _line(str(path), r), flush=True)
            print(f"{folder}: {nf} read upside down", flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
