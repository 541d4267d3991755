"""The scenes of a folder for gentle_ramps.py and corner_top_edge.py (ramp42)."""

import glob
import json
import os

import planerel


def items(d):
    """``(name, load, truth, up)`` per scene of folder ``d``.

    ``d`` is a folder of ``.pcd`` clouds (no labels.json), a labelled real set (labels.json as
    benchmarks/real_unseen.py reads it: per-frame intrinsics, depth scale and up), an
    independent set (``i*.npy`` with their ``.json``) or a synthetic data set (``s*.json``).
    ``load()`` reads the cloud; ``truth`` is ``(path, sidecar dict)`` where the set has ground
    truth, else None; ``up`` is the frame's given up or None.
    """
    tag = os.path.basename(os.path.normpath(d))
    labelled = os.path.exists(os.path.join(d, "labels.json"))
    pcds = sorted(glob.glob(os.path.join(d, "*.pcd")))
    if pcds and not labelled:
        for p in pcds:
            yield f"{tag}/{os.path.basename(p)}", (lambda p=p: planerel.read(p)), None, None
    elif labelled:
        with open(os.path.join(d, "labels.json")) as fh:
            doc = json.load(fh)
        for f in doc["frames"]:
            p = os.path.join(d, f["file"])

            def load(p=p, f=f):
                return planerel.read(p, intrinsics=f.get("intrinsics"),
                                     depth_scale=f.get("depth_scale"))

            yield f"{tag}/{f['file']}", load, None, f.get("up")
    elif glob.glob(os.path.join(d, "i*.npy")):
        for p in sorted(glob.glob(os.path.join(d, "i[0-9]*.npy"))):
            if p.endswith((".objects.npy", ".planes.npy")):
                continue
            with open(p[:-4] + ".json") as fh:
                meta = json.load(fh)
            yield f"{tag}/{os.path.basename(p)}", (lambda p=p: planerel.read(p)), (p, meta), None
    else:
        from planerel.features.dataset import load_scene

        for p in sorted(glob.glob(os.path.join(d, "s[0-9]*.json"))):
            with open(p) as fh:
                meta = json.load(fh)

            def load(p=p):
                return load_scene(os.path.dirname(p), os.path.basename(p)[:-5])[0]

            yield f"{tag}/{os.path.basename(p)}", load, (p, meta), None
