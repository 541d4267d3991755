"""The whole mOSD set (real Kinect table-tops with an object label per pixel) with a model.

    .venv/bin/python benchmarks/real_mosd.py DIR [--only learn|test] [--model out/model]
        [--param NAME=VALUE ...] [--json F] [--verbose]

``DIR`` holds the 110 PCDs of the modified Object Segmentation Database (mOSD: Richtsfeld et
al.'s OSD, relabelled and cropped to the table for geometric segmentation), which the public
repository PointCloudLibrary/data keeps under ``segmentation/mOSD/{learn,test}/`` (get it with
``git clone https://github.com/PointCloudLibrary/data`` and give a folder holding those PCDs;
they are never copied into planerel). ``../shared/data/mosd`` holds 7 of them (learn0-5,
test31); issue 22 will be checked on the rest, so the script also prints the figures of the
frames that are not among those seven (``rest``).

The frames' object types come from OSD's own scene categories (the set's README): ``learn
0-16`` / ``test 0-15`` boxes, ``learn 17-24`` / ``test 16-23`` stacked boxes (every object a
``box``), ``learn 33-44`` / ``test 31-42`` cylindric objects (cans, tins, mugs, bowls: every
object ``round``), and occluded objects (``learn 25-32`` / ``test 24-30``), mixed objects
(``test 43-54``) and complex scenes (``test 55-65``), whose objects are ``object`` (no type
judged). No frame holds a staircase or a ramp.

Per frame the script classifies with the model (``Classifier``), builds the proposal image as
``evaluate-objects`` does (the planes plus the curved clusters' pixels of the same
description) and scores it with ``score_objects`` (IoU >= 0.5). It prints issue 22's lines
for the learn and the test half and for both: objects found, false proposals a frame, boxes
answered ``box`` (of all box objects, found or not), round objects answered ``stairs`` /
``ramp`` (their found proposal, and the proposal holding most of them), and every ``stairs``
/ ``ramp`` answer of a frame (all false).
"""
from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

import numpy as np

#: OSD's scene categories: (split, first, last, category, type of every object or None).
CATEGORIES = (
    ("learn", 0, 16, "boxes", "box"), ("learn", 17, 24, "stacked boxes", "box"),
    ("learn", 25, 32, "occluded", None), ("learn", 33, 44, "cylindric", "round"),
    ("test", 0, 15, "boxes", "box"), ("test", 16, 23, "stacked boxes", "box"),
    ("test", 24, 30, "occluded", None), ("test", 31, 42, "cylindric", "round"),
    ("test", 43, 54, "mixed", None), ("test", 55, 65, "complex", None),
)


#: The frames ``../shared/data/mosd`` holds; the ``rest`` line leaves them out.
SHARED = ("learn0", "learn1", "learn2", "learn3", "learn4", "learn5", "test31")


def category(stem: str) -> tuple[str, str, str | None]:
    """``(split, category, object type or None)`` of an mOSD frame name such as ``test42``."""
    m = re.fullmatch(r"(learn|test)(\d+)", stem)
    if not m:
        raise ValueError(f"{stem}: not an mOSD frame name (learnN or testN)")
    split, n = m.group(1), int(m.group(2))
    for s, lo, hi, cat, ty in CATEGORIES:
        if s == split and lo <= n <= hi:
            return split, cat, ty
    raise ValueError(f"{stem}: outside OSD's categories")


def frame(clf, path: Path, min_iou: float = 0.5) -> tuple[dict, list[dict]]:
    from planerel.features.facts import describe_scene
    from planerel.features.object_eval import (
        answer_masks,
        frame_truth,
        proposal_image,
        score_objects,
    )
    from planerel.ilp.scenes import segment_cached

    split, cat, ty = category(path.stem)
    ((name, cloud, truth, _),) = list(frame_truth(path))
    ans = clf.classify(cloud, scene_id=name)
    desc = describe_scene(cloud, segment_cached(cloud, method=clf.method, params=clf.seg_params),
                          scene_id=name, **clf._describe_kw)
    # a box cut from a proposal (decision.cut_boxes) is an answer of its own, with no mask;
    # the proposal it was cut from keeps its mask and the rest of its planes
    own = [o for o in ans.objects if o.cut_from is None]
    if ([o.id for o in desc.objects] != [o.object_id for o in own]
            or any(not set(a.labels) <= set(o.planes) or (not a.cut_off and a.labels != o.planes)
                   for o, a in zip(desc.objects, own, strict=True))):
        raise RuntimeError(f"{name}: the description differs from the classifier's")
    prop = proposal_image(ans.labels, [o.labels for o in ans.objects],
                          answer_masks(desc.objects, ans.objects))
    ids = [int(o) for o in np.unique(truth) if o >= 1]
    sc = score_objects(prop, truth, name=name, types={o: ty or "object" for o in ids}, min_iou=min_iou)
    matched = {sc.best_prop[k] for k in sc.best_iou if sc.best_iou[k] >= min_iou}
    fr = {"frame": name, "split": split, "category": cat, "objects": sc.n_objects,
          "found": sc.found, "false": sc.false, "merged": sc.merged, "split_objects": sc.split,
          "answers": [o.klass for o in ans.objects],
          "false_classes": [o.klass for j, o in enumerate(ans.objects) if j not in matched],
          "seconds": round(ans.seconds, 2)}
    rows = []
    for k in ids:
        if k not in sc.best_iou:
            continue
        iou = sc.best_iou[k]
        pk = prop[truth == k]
        pk = pk[pk >= 0]
        rows.append({"frame": name, "split": split, "category": cat, "object": k,
                     "type": ty or "object", "iou": round(float(iou), 3),
                     "pred": ans.objects[sc.best_prop[k]].klass if iou >= min_iou else "none",
                     "held_by": ans.objects[int(np.bincount(pk).argmax())].klass if pk.size else "none"})
    return fr, rows


def summarize(frames: list[dict], rows: list[dict]) -> dict:
    boxes = [r for r in rows if r["type"] == "box"]
    rounds = [r for r in rows if r["type"] == "round"]
    n = len(rows)
    found = sum(f["found"] for f in frames)
    false = sum(f["false"] for f in frames)
    answers = [c for f in frames for c in f["answers"]]
    return {"frames": len(frames), "objects": n, "found": found, "found_rate": found / max(n, 1),
            "false": false, "false_per_frame": false / max(len(frames), 1),
            "merged": sum(f["merged"] for f in frames),
            "split": sum(f["split_objects"] for f in frames),
            "boxes": len(boxes), "boxes_box": sum(r["pred"] == "box" for r in boxes),
            "boxes_found": sum(r["pred"] != "none" for r in boxes),
            "rounds": len(rounds),
            "rounds_stairs_ramp": sum(r["pred"] in ("stairs", "ramp") for r in rounds),
            "rounds_held_stairs_ramp": sum(r["held_by"] in ("stairs", "ramp") for r in rounds),
            "rounds_box": sum(r["pred"] == "box" for r in rounds),
            "stairs_answers": answers.count("stairs"), "ramp_answers": answers.count("ramp"),
            "box_answers": answers.count("box"),
            "seconds_per_frame": float(np.mean([f["seconds"] for f in frames])) if frames else 0.0}


def summaries(frames: list[dict], rows: list[dict]) -> dict:
    """:func:`summarize` of the ``learn`` and ``test`` halves, of ``all`` frames and of the
    ``rest`` (the frames not in :data:`SHARED`); a group is left out when it is empty or, but
    for ``all``, when it holds every frame."""
    groups = (("learn", lambda f: f["split"] == "learn"), ("test", lambda f: f["split"] == "test"),
              ("all", lambda f: True), ("rest", lambda f: f["frame"] not in SHARED))
    out = {}
    for label, keep in groups:
        fs = [f for f in frames if keep(f)]
        if fs and (label == "all" or len(fs) < len(frames)):
            names = {f["frame"] for f in fs}
            out[label] = summarize(fs, [r for r in rows if r["frame"] in names])
    return out


def print_summary(s: dict, label: str) -> None:
    pct = 100 * s["found_rate"]
    bb = 100 * s["boxes_box"] / max(s["boxes"], 1)
    print(f"{label}: {s['frames']} frames, {s['objects']} objects: found {s['found']} ({pct:.1f} %, "
          f">= 90 %: {'met' if pct >= 90 else 'not met'}); false {s['false_per_frame']:.2f} a frame "
          f"(<= 0.5: {'met' if s['false_per_frame'] <= 0.5 else 'not met'}); merged {s['merged']}, "
          f"split {s['split']}")
    print(f"  boxes `box` {s['boxes_box']}/{s['boxes']} ({bb:.1f} %, >= 85 %: "
          f"{'met' if bb >= 85 else 'not met'}; found {s['boxes_found']}); round objects "
          f"stairs/ramp {s['rounds_stairs_ramp']}/{s['rounds']} (held {s['rounds_held_stairs_ramp']}; "
          f"never: {'met' if s['rounds_stairs_ramp'] == 0 else 'not met'}), round `box` {s['rounds_box']}; "
          f"answers stairs {s['stairs_answers']}, ramp {s['ramp_answers']} (all false), "
          f"box {s['box_answers']}; {s['seconds_per_frame']:.2f} s a frame")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folder", help="folder of the mOSD PCDs (learnN.pcd, testN.pcd)")
    ap.add_argument("--only", choices=("learn", "test"), help="one half of the set")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--json", help="write every frame's and object's figures here")
    ap.add_argument("--verbose", action="store_true", help="print each frame's line")
    a = ap.parse_args(argv)
    from planerel.classify.classifier import Classifier
    from planerel.commands.classify import _params

    def key(p):
        m = re.fullmatch(r"(learn|test)(\d+)", p.stem)
        return (m.group(1), int(m.group(2))) if m else ("", 0)

    paths = sorted((p for p in Path(a.folder).glob("*.pcd") if key(p)[0]), key=key)
    if a.only:
        paths = [p for p in paths if key(p)[0] == a.only]
    if not paths:
        print(f"{a.folder}: no mOSD frames (learnN.pcd, testN.pcd)", file=sys.stderr)
        return 2
    frames, rows = [], []
    with Classifier(a.model, seg_params=_params(a.param)) as clf:
        for p in paths:
            fr, rw = frame(clf, p)
            frames.append(fr)
            rows += rw
            if a.verbose:
                print(f"{fr['frame']} ({fr['category']}): found {fr['found']}/{fr['objects']}, "
                      f"false {fr['false']}, answers {fr['answers']}", flush=True)
    out = summaries(frames, rows)
    for label, s in out.items():
        print_summary(s, label if label != "rest" else f"rest (all but the {len(SHARED)} shared frames)")
    cats = {}
    for f in frames:
        cats.setdefault(f["category"], []).append(f)
    for cat, fs in cats.items():
        names = {f["frame"] for f in fs}
        s = summarize(fs, [r for r in rows if r["frame"] in names])
        print(f"  {cat:14s} {s['frames']:3d} frames: found {s['found']}/{s['objects']}, false "
              f"{s['false_per_frame']:.2f} a frame, box {s['boxes_box']}/{s['boxes']}, "
              f"answers stairs {s['stairs_answers']} ramp {s['ramp_answers']} box {s['box_answers']}")
    if a.json:
        with open(a.json, "w") as fh:
            json.dump({"summary": out, "frames": frames, "rows": rows}, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
