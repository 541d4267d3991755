"""The estimated up's error on every real development frame, against a truth taken from the frame.

    nice .venv/bin/python benchmarks/real_up_error.py --root /work --model /work/main/out/model \\
        [--json OUT.json] [--cache DIR] [--param gravity.NAME=VALUE ...] [--floors F.json]
    nice .venv/bin/python benchmarks/real_up_error.py --root /work --write-floors F.json

Frames (kept outside the repository, under ``--root``): ``extdata``'s mOSD, OSD, uois,
stair-perception, El-Masry, palletizer, pcl-pairwise and pcl-tutorials frames, and every
labelled folder of ``hunt33 36 39 43 45 47 48 49 55 56 57``.  Each goes through the classifier's own
segmentation and ``describe`` (the model's settings; ``--param`` as ``classify``'s), and its
estimated up is compared with a truth (grav53, 2026-12-02), in this order:

1. ``grav45``: hunt45's floor, measured by :func:`floor_truth` (a seeded RANSAC plane of the
   image's bottom third within 45 degrees of the camera's down axis; none where no such plane
   holds: the R200's speckled floor of ``r200_mar_144547``); ``--floors F.json``
   (``{"up": {"SET/FILE": [x, y, z]}}``) overrides it.  Until 2026-12-04 these normals lived
   in a file outside the repository (``/work/notes/grav45_floor_up.json``), lost with the
   machine; re-measured here they agree with the errors docs/gravity.md records against it
   within about a degree on the frames both cover;
2. ``pose``: apc-shelf's camera poses (its NOTES.md);
3. ``levelled``: stair-perception's levelled cloud beside the depth image;
4. ``TRUTH`` below: a choice made by looking at the frame (a plane, a vector, "the estimate's
   axis with the other sign", or no truth: no floor or table in clear view);
5. otherwise the frame's support plane: the segmented plane of most points within 4 m whose
   normal faces the image's top (``n_y < -0.05``: a floor, table or tray seen from above).
   Every frame where it and the estimate differ by more than 5 degrees was looked at; those
   where it took a wall are in ``TRUTH``.

Error = the angle between the estimate and the truth (a flipped vector counts 180).
"""
from __future__ import annotations

import argparse
import dataclasses
import glob
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

#: (key substring) -> how the truth is taken, with why (grav53 looked at each frame).
TRUTH = {
    "hunt33/gqcnn/phoxi_depth_": ("vec", (-0.137, 0.008, -0.991),
                                  "bin37's bin floor pieces and drafted walls' bisectors (fixed PhoXi rig)"),
    "hunt33/graspnet/": ("largest", None, "the table, seen from 73 degrees above"),
    "hunt33/simod-oak/": ("none", None, "an upside-down OAK-D facing a pallet: one thin board"),
    "hunt36/arc-tote/tote_suction": ("none", None, "the tote's floor hidden under its contents"),
    "hunt36/nvblox-lounge/lounge_000422": ("plane", 7, "the floor (the support rule took a sofa)"),
    "hunt36/pcl-test/office1.pcd": ("plane", 8, "the floor strip, 3.1-3.9 m away (bent by the sensor)"),
    "hunt39/ryesw-snackbox/": ("none", None, "the desk seen edge-on; a partition fills the view"),
    "hunt43/bug-arena/arena_12-55": ("sign", None, "table legs vertical under the estimate; "
                                     "the Kinect lies upright on the floor"),
    "hunt43/bug-arena/": ("none", None, "a Kinect lying on the floor: no floor or table top in view"),
    "hunt48/arkit-rooms/a679_6790": ("sign", None, "the ceiling's axis; the phone is upright (RGB)"),
    "hunt48/arkit-rooms/a462_57402": ("sign", None, "the ceiling's axis; the phone is upright (RGB)"),
    "hunt48/arkit-rooms/a473_58528": ("largest", None, "the floor seen from straight above"),
    "hunt57/piv-office/office_cam2": ("sign", None, "the ceiling's axis: the room seen upright (ceiling "
                                      "at the image's top, door and chairs below); the support "
                                      "rule took a 0.03 m^2 chair part (grav58)"),
    "hunt49/sunrgbd-rs/depth_4": ("none", None, "a kitchen counter seen level: no floor or top segmented"),
}
#: hunt45's sets (low cameras) whose truth is the floor :func:`floor_truth` measures
GRAV45 = ("donkeycar", "mbot", "morbius")
APC = {"00": (0, -1, 0), "03": (0, -1, 0), "06": (0, -0.98, -0.17), "09": (0, -0.98, -0.17),
       "12": (0, -0.94, -0.34)}


def frames(root: str):
    """``(key, reader, truth hint)`` of every development frame under ``root``."""
    from real_stairs import INTRINSICS as SP_INTR
    from real_tabletop import OSD_INTRINSICS, UOIS_INTRINSICS, read_frame

    import planerel

    ext = os.path.join(root, "extdata")
    for f in sorted(glob.glob(f"{ext}/mosd/*.pcd")):
        yield "extdata/mosd/" + os.path.basename(f), lambda f=f: planerel.read(f), None
    for name in ("learn6", "test42", "test50", "test63", "test64"):
        p = f"{ext}/osd/{name}_depth.png"
        if os.path.exists(p):
            yield "extdata/osd/" + name, lambda p=p: read_frame(p, OSD_INTRINSICS), None
    for p in sorted(glob.glob(f"{ext}/uois/image_000?.npy")):
        yield "extdata/uois/" + os.path.basename(p), lambda p=p: read_frame(p, UOIS_INTRINSICS), None
    for p in sorted(glob.glob(f"{ext}/stair-perception/*_depth.png")):
        s = os.path.basename(p)[: -len("_depth.png")]
        yield ("extdata/stair-perception/" + s,
               lambda p=p: planerel.read(p, intrinsics=SP_INTR, depth_scale=1000),
               ("levelled", f"{ext}/stair-perception/{s}_cloud.pcd"))
    for f in sorted(glob.glob(f"{ext}/elmasry/*.pcd")):
        yield "extdata/elmasry/" + os.path.basename(f), lambda f=f: planerel.read(f), None
    folders = [f"{ext}/{x}" for x in ("palletizer", "pcl-pairwise", "pcl-tutorials")]
    for h in ("33", "36", "39", "43", "45", "47", "48", "49", "55", "56", "57"):
        folders += sorted(d for d in glob.glob(f"{root}/hunt{h}/*")
                          if os.path.isfile(d + "/labels.json"))
    for folder in folders:
        if not os.path.isfile(folder + "/labels.json"):
            continue
        for fr in json.load(open(folder + "/labels.json"))["frames"]:
            p = os.path.join(folder, fr["file"])
            key = os.path.relpath(folder, root) + "/" + fr["file"]
            hint = ("floors", os.path.basename(folder) + "/" + fr["file"])
            if "apc-shelf" in folder:
                hint = next((("pose", v) for k, v in APC.items() if f"_{k}_" in fr["file"]), hint)
            yield (key, lambda p=p, fr=fr: planerel.read(p, intrinsics=fr.get("intrinsics"),
                                                     depth_scale=fr.get("depth_scale")), hint)


def floor_truth(xyz, *, seed: int = 0, tol: float = 0.02, tries: int = 2000,
                prior_deg: float = 45.0, max_range: float = 4.0):
    """The floor's up in the camera frame, measured from the image's bottom third.

    A RANSAC plane (``tries`` seeded hypotheses, inliers within ``tol`` m) over the valid
    points of the bottom third of the rows nearer than ``max_range`` m, among the planes whose
    normal lies within ``prior_deg`` degrees of the camera's down axis (``-y``: a floor seen by
    a roughly level camera, not a wall), then refitted by least squares to its inliers three
    times.  A measuring tool's truth (hunt45's low cameras, whose floor fills the bottom of the
    image), not the estimate planerel makes.

    Parameters
    ----------
    xyz : ndarray, shape (H, W, 3)
        The organized cloud (metres, NaN where no depth).

    Returns
    -------
    ndarray, shape (3,), or None
        Unit up (``y`` negative), or None with under 50 points or no plane within the prior.
    """
    xyz = np.asarray(xyz, float)
    p = xyz[2 * xyz.shape[0] // 3:].reshape(-1, 3)
    p = p[np.all(np.isfinite(p), axis=1) & (p[:, 2] > 0) & (p[:, 2] < max_range)]
    if len(p) < 50:
        return None
    cos_prior = math.cos(math.radians(prior_deg))
    rng = np.random.default_rng(seed)
    best, most = None, 0
    for _ in range(tries):
        a, b, c = p[rng.choice(len(p), 3, replace=False)]
        n = np.cross(b - a, c - a)
        s = float(np.linalg.norm(n))
        if s < 1e-12:
            continue
        n = n / s if n[1] < 0 else -n / s
        if -n[1] < cos_prior:
            continue
        k = int(np.count_nonzero(np.abs((p - a) @ n) < tol))
        if k > most:
            best, most = (n, a), k
    if best is None:
        return None
    n, a = best
    for _ in range(3):
        q = p[np.abs((p - a) @ n) < tol]
        a = q.mean(axis=0)
        n = np.linalg.svd(q - a, full_matrices=False)[2][-1]
        n = n if n[1] < 0 else -n
    return n if -n[1] >= cos_prior else None


def angle(u, v) -> float:
    u, v = np.asarray(u, float), np.asarray(v, float)
    c = float(u @ v) / float(np.linalg.norm(u) * np.linalg.norm(v))
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def truth_of(key, hint, planes, up, cloud, floors):
    """``(vector or None, source)``."""
    from real_stairs import levelled_up

    if hint and hint[0] == "floors":
        if floors is not None:
            if hint[1] in floors:
                return np.asarray(floors[hint[1]], float), "grav45"
        elif hint[1].split("/")[0] in GRAV45:
            n = floor_truth(cloud.xyz)
            if n is not None:
                return n, "grav45"
    if hint and hint[0] == "pose":
        return np.asarray(hint[1], float), "pose"
    if hint and hint[0] == "levelled":
        lv = levelled_up(cloud, hint[1])
        if lv is not None:
            return lv, "levelled"
    for sub, (how, arg, why) in TRUTH.items():
        if sub in key:
            if how == "vec":
                return np.asarray(arg, float), "seen: " + why
            if how == "plane":
                q = next((q for q in planes if q["label"] == arg), None)
                return (None, "seen: plane missing") if q is None else \
                    (np.asarray(q["normal"], float), "seen: " + why)
            if how == "largest":
                q = max(planes, key=lambda q: q["n"])
                return np.asarray(q["normal"], float), "seen: " + why
            if how == "sign":
                return -np.asarray(up, float), "seen: " + why
            return None, "none: " + why
    cands = [q for q in planes if q["normal"][1] < -0.05 and q["dist"] < 4.0 and q["area"] >= 0.02]
    if not cands:
        return None, "none: no plane faces the image's top"
    best = max(cands, key=lambda q: q["n"])
    return np.asarray(best["normal"], float), "support plane"


def _value(text: str):
    low = text.lower()
    if low in ("true", "false"):
        return low == "true"
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--root", default="/work")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--floors", help="hunt45's floors as {\"up\": {\"SET/FILE\": [x, y, z]}} "
                    "(default: measured by floor_truth)")
    ap.add_argument("--write-floors", metavar="F.json",
                    help="write floor_truth's hunt45 floors in --floors' form (low_camera_ramps.py's "
                    "--truth) and stop")
    ap.add_argument("--param", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--cache", help="a folder for the segmentation's labels (reused by a second run)")
    ap.add_argument("--only", help="only frames whose key contains this")
    ap.add_argument("--json")
    args = ap.parse_args(argv)
    from planerel.classify.classifier import Classifier
    from planerel.features.facts import describe_scene
    from planerel.ilp.scenes import segment_cached_far

    if args.write_floors:
        measured = {}
        for _key, reader, hint in frames(args.root):
            if hint and hint[0] == "floors" and hint[1].split("/")[0] in GRAV45:
                n = floor_truth(reader().xyz)
                if n is not None:
                    measured[hint[1]] = np.round(n, 4).tolist()
        from planerel.atomic import write_text
        write_text(args.write_floors, json.dumps({"up": measured}, indent=1) + "\n")
        print(f"{len(measured)} floors written to {args.write_floors}")
        return 0
    floors = json.load(open(args.floors))["up"] if args.floors else None
    overrides = {k.strip(): _value(v.strip()) for k, _, v in (p.partition("=") for p in args.param)}
    rows = []
    with Classifier(args.model, seg_params=overrides or None) as clf:
        for key, reader, hint in frames(args.root):
            if args.only and args.only not in key:
                continue
            cloud = reader()
            if getattr(cloud, "up", None) is not None:
                cloud = dataclasses.replace(cloud, up=None)
            src = getattr(cloud, "source", None)
            files = [src] if args.cache and src and os.path.isfile(str(src)) else []
            # the classifier's own path (Classifier.classify): the far growing's planes marked
            labels, far = segment_cached_far(cloud, method=clf.method, params=clf.seg_params,
                                             files=files, cache=args.cache)
            ps = describe_scene(cloud, labels, scene_id="s", far=far, **clf._describe_kw).planes
            up = np.asarray(ps.up, float)
            planes = [{"label": int(p.label), "n": int(p.n_points), "normal": np.asarray(p.normal, float).tolist(),
                       "area": float(p.area), "dist": float(p.distance)} for p in ps]
            truth, how = truth_of(key, hint, planes, up, cloud, floors)
            err = None if truth is None else round(angle(up, truth), 2)
            flags = [f for f, on in (("upside down", ps.up_upside_down), ("near floor", ps.up_near_floor),
                                     ("speckle floor", ps.up_sparse_floor)) if on]
            rows.append({"frame": key, "up": np.round(up, 4).tolist(), "source": ps.up_source,
                         "confidence": round(float(ps.up_confidence), 3), "flags": flags,
                         "truth": None if truth is None else np.round(truth / np.linalg.norm(truth), 4).tolist(),
                         "truth_from": how, "error_deg": err})
            print(f"{key:58s} {'-' if err is None else f'{err:6.2f}'}  conf {ps.up_confidence:.2f} "
                  f"{ps.up_source} {' '.join(flags)}  [{how}]", flush=True)
    errs = [r["error_deg"] for r in rows if r["error_deg"] is not None]
    bins = [(0, 1), (1, 2), (2, 5), (5, 20), (20, 181)]
    hist = {f"{a}-{b}": sum(a < e <= b if a else e <= b for e in errs) for a, b in bins}
    print(f"{len(rows)} frames, {len(errs)} with a truth: " + ", ".join(f"{k} deg {v}" for k, v in hist.items()))
    for r in rows:
        if r["error_deg"] is not None and r["error_deg"] > 5:
            print(f"  over 5: {r['frame']} {r['error_deg']} (conf {r['confidence']}, {' '.join(r['flags'])})")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"frames": rows, "histogram": hist}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
