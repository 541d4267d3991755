"""The scenes of a folder for gentle_ramps.py and corner_top_edge.py (ramp42)."""

import glob
import json
import os

import planerel


def items(d):
    if os.path.exists(os.path.join(d, "labels.json")):
        doc = json.load(open(os.path.join(d, "labels.json")))
        for f in doc["frames"]:
            p = os.path.join(d, f["file"])
            yield (
                os.path.basename(os.path.normpath(d)) + "/" + f["file"],
                (
                    lambda p=p, f=f: planerel.read(
                        p, intrinsics=f.get("intrinsics"), depth_scale=f.get("depth_scale")
                    )
                ),
                None,
                f.get("up"),
            )
    elif glob.glob(os.path.join(d, "i*.npy")):
        for p in sorted(glob.glob(os.path.join(d, "i[0-9]*.npy"))):
            if p.endswith(".objects.npy") or p.endswith(".planes.npy"):
                continue
            meta = json.load(open(p[:-4] + ".json"))
            yield (
                os.path.basename(os.path.normpath(d)) + "/" + os.path.basename(p),
                (lambda p=p: planerel.read(p)),
                (p, meta),
                None,
            )
    else:
        for p in sorted(glob.glob(os.path.join(d, "s[0-9]*.json"))):
            meta = json.load(open(p))
            yield (
                os.path.basename(os.path.normpath(d)) + "/" + os.path.basename(p),
                (
                    lambda p=p: __import__("planerel.features.dataset", fromlist=["x"]).load_scene(
                        os.path.dirname(p), os.path.basename(p)[:-5]
                    )[0]
                ),
                (p, meta),
                None,
            )


_items = items


def items(d):
    pcds = sorted(glob.glob(os.path.join(d, "*.pcd")))
    if pcds and not os.path.exists(os.path.join(d, "labels.json")):
        for p in pcds:
            yield (
                os.path.basename(os.path.normpath(d)) + "/" + os.path.basename(p),
                (lambda p=p: planerel.read(p)),
                None,
                None,
            )
    else:
        yield from _items(d)
