"""The estimated up's error on every real development frame, against a truth taken from the frame.

    nice .venv/bin/python benchmarks/real_up_error.py --root /work --model /work/main/out/model \\
        [--json OUT.json] [--cache DIR] [--param gravity.NAME=VALUE ...]

Frames (kept outside the repository, under ``--root``): ``extdata``'s mOSD, OSD, uois,
stair-perception, El-Masry, palletizer, pcl-pairwise and pcl-tutorials frames, and every
labelled folder of ``hunt33 36 39 43 45 47 48 49 55 56 57``.  Each goes through the classifier's own
segmentation and ``describe`` (the model's settings; ``--param`` as ``classify``'s), and its
estimated up is compared with a truth (grav53, 2026-12-02), in this order:

1. ``grav45``: hunt45's measured floor normals (``--floors``, default
   ``ROOT/notes/grav45_floor_up.json``: a RANSAC plane of the image's bottom third);
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


def angle(u, v) -> float:
    u, v = np.asarray(u, float), np.asarray(v, float)
    c = float(u @ v) / float(np.linalg.norm(u) * np.linalg.norm(v))
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def truth_of(key, hint, planes, up, cloud, floors):
    """``(vector or None, source)``."""
    from real_stairs import levelled_up

    if hint and hint[0] == "floors" and hint[1] in floors:
        return np.asarray(floors[hint[1]], float), "grav45"
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
    ap.add_argument("--floors", help="hunt45's measured floors (default ROOT/notes/grav45_floor_up.json)")
    ap.add_argument("--param", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--cache", help="a folder for the segmentation's labels (reused by a second run)")
    ap.add_argument("--only", help="only frames whose key contains this")
    ap.add_argument("--json")
    args = ap.parse_args(argv)
    from planerel.classify.classifier import Classifier
    from planerel.features.facts import describe_scene
    from planerel.ilp.scenes import segment_cached

    fl = args.floors or os.path.join(args.root, "notes", "grav45_floor_up.json")
    floors = json.load(open(fl))["up"] if os.path.exists(fl) else {}
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
            labels = segment_cached(cloud, method=clf.method, params=clf.seg_params,
                                    files=files, cache=args.cache)
            ps = describe_scene(cloud, labels, scene_id="s", **clf._describe_kw).planes
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
