"""Small boxes near the camera (``small_scale``, docs/segmentation.md "Small planes near the
camera"): an independent set scored by real_unseen's rule, and what the second growing costs.

Usage::

    small_boxes.py found SET MODEL [MODEL ...] [--param NAME=VALUE ...] [--misses]
    small_boxes.py speed [--pcd DIR] [--frames 12] [--rounds 3] [--small-scale 0.35]
    small_boxes.py labels SET DEST [--min-pixels 150]

``found``: every scene of an ``independent_scenes.py`` set (e.g. ``dev_small``) classified by
each model; a labelled box is *found* when a ``box`` answer has at least half of its pixels in
it (the rule of ``real_unseen.py``, looser than the set's own IoU >= 0.5, which a proposal
showing two of a box's three faces can fail), and an answer of a class with half of its pixels
in no object of that class is *false*. Objects under 150 valid pixels are not judged.

``speed``: ``segment()`` of the first ``--frames`` mOSD test frames with ``small_scale`` off
(the reference) and on, alternated in one process, the median over ``--rounds``; prints the
two times, their ratio and the small planes added.

``labels``: the set as a labelled folder of rectangles, as the real hunts are (``DEST`` gets a
``labels.json`` and a link to each scene's ``.npy``): each box of at least ``--min-pixels``
valid pixels becomes the bounding rectangle of its truth pixels, so that ``real_unseen.py`` and
``box_causes.py`` score and explain the generated boxes as they do the real ones (small65:
dev_small's misses by cause).
"""

from __future__ import annotations

import argparse
import glob
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

CLASSES = ("box", "stairs", "ramp")


def found(folder: str, model: str, params=(), misses: bool = False) -> dict:
    """``{found, boxes, false, kinds: {kind: [found, boxes]}}`` of one model on one set."""
    from planerel.classify.classifier import Classifier
    from planerel.commands.classify import _params
    from planerel.io import readers as io

    out = {"found": 0, "boxes": 0, "false": 0, "kinds": {}}
    with Classifier(model, seg_params=_params(list(params))) as clf:
        for p in sorted(Path(folder).glob("i[0-9][0-9][0-9][0-9].npy")):
            side = json.loads(p.with_suffix(".json").read_text())
            truth = np.load(p.with_name(p.stem + ".objects.npy"))
            ans = clf.classify(io.read(p), scene_id=p.stem)
            lab = np.asarray(ans.labels)
            klass = {o["index"]: o["class"] for o in side["objects"]}
            hit = set()
            for o in ans.objects:
                if o.klass not in CLASSES:
                    continue
                pix = np.isin(lab, list(o.labels))
                n = int(pix.sum())
                if n == 0:
                    continue
                ks, cs = np.unique(truth[pix], return_counts=True)
                ok = [int(k) for k, c in zip(ks, cs, strict=True)
                      if k > 0 and c >= 0.5 * n and klass.get(int(k)) == o.klass]
                hit.update(ok)
                out["false"] += not ok
            for o in side["objects"]:
                if o["class"] != "box" or int((truth == o["index"]).sum()) < 150:
                    continue
                f = o["index"] in hit
                out["boxes"] += 1
                out["found"] += f
                k = out["kinds"].setdefault(o["kind"], [0, 0])
                k[0] += f
                k[1] += 1
                if misses and not f:
                    print(f"  missed {p.stem} object {o['index']} ({o['kind']}, "
                          f"{int((truth == o['index']).sum())} px)")
    return out


def labels(folder: str, dest: str, min_pixels: int = 150) -> dict:
    """Write ``dest/labels.json`` (and links to the scenes) for the independent set ``folder``:
    one frame a scene, one ``box`` rectangle ``[x0, y0, x1, y1]`` (pixels, end exclusive) a
    labelled box of at least ``min_pixels`` pixels.  Returns the labels document."""
    from planerel.atomic import write_text

    src, out = Path(folder), Path(dest)
    scenes = sorted(src.glob("i[0-9][0-9][0-9][0-9].npy"))
    if not scenes:
        sys.exit(f"small_boxes: no scene (iNNNN.npy) in {folder}")
    out.mkdir(parents=True, exist_ok=True)
    frames = []
    for p in scenes:
        side = json.loads(p.with_suffix(".json").read_text())
        truth = np.load(p.with_name(p.stem + ".objects.npy"))
        it = side["intrinsics"]
        objs = []
        for o in side["objects"]:
            ys, xs = np.nonzero(truth == o["index"])
            if o["class"] != "box" or len(ys) < min_pixels:
                continue
            objs.append({"class": "box", "what": f"{o['kind']} (object {o['index']})",
                         "box": [int(xs.min()), int(ys.min()), int(xs.max()) + 1, int(ys.max()) + 1]})
        link = out / p.name
        if not link.exists():
            link.symlink_to(p.resolve())
        frames.append({"file": p.name, "objects": objs,
                       "intrinsics": ",".join(str(it[k]) for k in ("width", "height", "fx", "fy",
                                                                   "cx", "cy"))})
    doc = {"set": src.name, "source": f"independent_scenes.py set {src.resolve()}",
           "frames": frames}
    write_text(out / "labels.json", json.dumps(doc, indent=1) + "\n")
    return doc


def speed(pcd_dir: str, frames: int, rounds: int, scale: float) -> None:
    import planerel
    from planerel.segment import segment

    files = sorted(glob.glob(os.path.join(pcd_dir, "test*.pcd")))[:frames]
    if not files:
        sys.exit(f"small_boxes: no test*.pcd under {pcd_dir}")
    clouds = [planerel.read(f) for f in files]
    for c in clouds[:2]:  # compile and warm
        segment(c, small_scale=0.0)
        segment(c, small_scale=scale, small_pitch=0.0)
    off, on, added = [], [], []
    for r in range(rounds):
        for c in clouds:
            t = time.perf_counter()
            segment(c, small_scale=0.0)
            off.append(time.perf_counter() - t)
            t = time.perf_counter()
            s = segment(c, small_scale=scale, small_pitch=0.0)
            on.append(time.perf_counter() - t)
            if r == 0:
                added.append(int(s.info.get("small_planes", 0)))
    a, b = 1e3 * float(np.median(off)), 1e3 * float(np.median(on))
    print(f"{len(clouds)} frames x {rounds}: segment {a:.1f} ms a frame (reference), "
          f"small_scale {scale} {b:.1f} ms; ratio {b / a:.2f}; small planes added {sum(added)}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    f = sub.add_parser("found", help="score an independent set by real_unseen's rule")
    f.add_argument("set")
    f.add_argument("models", nargs="+")
    f.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    f.add_argument("--misses", action="store_true", help="list the boxes missed")
    s = sub.add_parser("speed", help="segment() with small_scale against without")
    s.add_argument("--pcd", default="/work/extdata/mosd")
    s.add_argument("--frames", type=int, default=12)
    s.add_argument("--rounds", type=int, default=3)
    s.add_argument("--small-scale", type=float, default=0.35)
    lb = sub.add_parser("labels", help="the set as rectangles for real_unseen.py / box_causes.py")
    lb.add_argument("set")
    lb.add_argument("dest")
    lb.add_argument("--min-pixels", type=int, default=150)
    a = ap.parse_args(argv)
    if a.cmd == "labels":
        doc = labels(a.set, a.dest, a.min_pixels)
        n = sum(len(f["objects"]) for f in doc["frames"])
        print(f"{a.dest}: {len(doc['frames'])} frames, {n} boxes")
        return 0
    if a.cmd == "speed":
        speed(a.pcd, a.frames, a.rounds, a.small_scale)
        return 0
    for m in a.models:
        r = found(a.set, m, a.param, a.misses)
        kinds = ", ".join(f"{k} {x}/{n}" for k, (x, n) in sorted(r["kinds"].items()))
        print(f"{m}: box found {r['found']}/{r['boxes']}, false answers {r['false']}; {kinds}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
