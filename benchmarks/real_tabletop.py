"""Real table-top frames nobody on the team made: boxes and round objects, point-annotated.

    .venv/bin/python benchmarks/real_tabletop.py [--osd DIR] [--uois DIR] [--model out/model]
        [--param NAME=VALUE ...] [--json F] [--verbose]

Two sets of real RGB-D frames, never copied into planerel:

* ``--osd DIR``: five frames of the Object Segmentation Database (OSD, TU Wien; the set the
  shared mOSD PCDs come from, "the rest of the mOSD set" of issue 22): ``learn6``, ``test42``,
  ``test50``, ``test63``, ``test64``, Kinect v1, 640x480, fx = fy = 525, cx = 320, cy = 240,
  16-bit depth in millimetres. They are the sample data of the public repository
  gist-ailab/uoais: ``git clone https://github.com/gist-ailab/uoais`` and copy
  ``sample_data/disparity/NAME.png`` (depth in mm despite the folder's name) to
  ``DIR/NAME_depth.png`` (``sample_data/image_color/NAME.png`` to ``DIR/NAME_rgb.png`` to look
  at them).
* ``--uois DIR``: nine frames of an Intel RealSense camera (640x480, fx 612.937, fy 613.173,
  cx 322.549, cy 248.158, depth in millimetres) from the example images of chrisdxie/uois
  (commit ae57aab, ``example_images/image_000N.npy``: a dict with ``rgb`` and ``depth``):
  ``DIR`` holds either those ``.npy`` files or their depth as ``image_000N_depth.png``.

No frame has a staircase or a ramp. The truth is a hand-made list of points (below, ``TRUTH``):
one pixel well inside each object, read off the RGB image, with its kind:

* ``box``: a box-like object (cereal and tea boxes, cartons, books, plastic food containers,
  a wooden or foam block) that should be answered ``box``;
* ``round``: bowls, mugs, cups, cans, bottles, tubes: never ``stairs`` or ``ramp`` (issue 22);
* ``other``: none of the classes (a drill, a mustard bottle): an answer ``box`` is false;
* ``thing``: neither judged as a box nor as other (a meat tin with rounded corners, a Duplo
  brick, a bag): only never ``stairs`` / ``ramp``.

Each point's answer is the class of the proposal holding most of the valid pixels in a 9x9
window around it (planes and curved clusters, as ``evaluate-objects`` counts them), or
``none`` when no proposal holds any. The script prints per frame every class answer and every
point's answer, then the lines: boxes answered ``box``, round objects answered ``stairs`` /
``ramp``, ``other`` objects answered ``box``, and every ``stairs`` / ``ramp`` answer of a frame
(all false: there are none of these classes in view).
"""
from __future__ import annotations

import argparse
import json
import os
import sys

import numpy as np

OSD_INTRINSICS = (640, 480, 525.0, 525.0, 320.0, 240.0)
UOIS_INTRINSICS = (640, 480, 612.937, 613.173, 322.549, 248.158)

# (x, y, kind, name): x = column, y = row of the 640x480 image.
TRUTH = {
    "osd/learn6": [(300, 235, "box", "cereal box"), (250, 300, "box", "small box in front")],
    "osd/test42": [(290, 150, "round", "round tin on top"), (290, 240, "round", "dotted cup"),
                   (290, 300, "round", "can"), (290, 370, "round", "upturned bowl")],
    "osd/test50": [(180, 270, "box", "box standing left"), (290, 170, "round", "tube lying across"),
                   (365, 245, "box", "box standing right"), (270, 295, "box", "grey block"),
                   (372, 305, "box", "small box"), (440, 290, "round", "white can"),
                   (385, 375, "box", "book lying")],
    "osd/test63": [(150, 370, "box", "biscuit box lying"), (345, 395, "box", "cocoa carton"),
                   (385, 455, "box", "red box lying"), (310, 240, "box", "tea box on a book"),
                   (372, 255, "box", "green book"), (232, 262, "box", "blue book"),
                   (420, 270, "box", "milk carton"), (510, 232, "box", "box at the back right"),
                   (260, 320, "round", "biscuit roll lying"), (240, 210, "round", "mug"),
                   (175, 225, "round", "bottle"), (355, 175, "round", "can"),
                   (595, 320, "round", "bowl"), (540, 320, "round", "can in the bowl")],
    "osd/test64": [(165, 150, "box", "cereal box standing"), (175, 300, "box", "wooden block"),
                   (290, 262, "box", "green book"), (350, 225, "box", "cocoa carton"),
                   (265, 298, "box", "small white box lying"), (232, 245, "box", "blue book"),
                   (465, 320, "box", "milk carton"), (540, 235, "box", "box lying right"),
                   (352, 145, "box", "small box at the back"), (240, 160, "round", "bottle"),
                   (305, 150, "round", "white can"), (130, 235, "round", "bowl"),
                   (290, 355, "round", "mug"), (515, 175, "round", "tube standing")],
    "uois/image_0000": [(490, 250, "box", "Cheez-It box"), (205, 190, "round", "dark cup"),
                        (300, 250, "round", "white mug"), (175, 265, "round", "small can"),
                        (235, 365, "round", "teal bowl"), (420, 375, "round", "white bowl"),
                        (545, 365, "round", "soup can"), (285, 110, "other", "mustard bottle"),
                        (355, 160, "other", "drill"), (75, 305, "thing", "meat tin")],
    "uois/image_0001": [(480, 320, "box", "Cheez-It box"), (220, 225, "round", "dark cup"),
                        (325, 275, "round", "white mug"), (170, 185, "round", "soup can"),
                        (155, 240, "round", "small can"), (185, 350, "round", "teal bowl"),
                        (305, 425, "round", "white bowl"), (282, 175, "other", "mustard bottle"),
                        (390, 170, "other", "drill"), (75, 310, "thing", "meat tin")],
    "uois/image_0002": [(265, 75, "box", "Cheez-It box"), (310, 210, "round", "teal bowl"),
                        (465, 255, "round", "white bowl"), (480, 135, "round", "dark cup"),
                        (145, 175, "round", "soup can"), (195, 140, "other", "mustard bottle"),
                        (380, 150, "other", "drill"), (155, 255, "thing", "meat tin")],
    "uois/image_0003": [(265, 75, "box", "Cheez-It box"), (310, 210, "round", "teal bowl"),
                        (465, 260, "round", "white bowl"), (485, 125, "round", "dark cup"),
                        (550, 130, "round", "water bottle"), (145, 175, "round", "soup can"),
                        (195, 140, "other", "mustard bottle"), (380, 150, "other", "drill"),
                        (155, 255, "thing", "meat tin")],
    "uois/image_0004": [(255, 130, "round", "wipes canister"), (425, 175, "round", "cashew can"),
                        (470, 280, "round", "purple cup"), (245, 300, "thing", "Duplo brick")],
    "uois/image_0005": [(245, 125, "box", "small container"), (445, 200, "box", "large container"),
                        (130, 95, "thing", "bag")],
    "uois/image_0006": [(550, 230, "box", "large container"), (290, 245, "box", "small container"),
                        (275, 200, "box", "marker box on the container"),
                        (145, 110, "round", "wipes canister"), (255, 130, "round", "robot can"),
                        (365, 175, "round", "purple cup"), (365, 290, "round", "mug"),
                        (530, 385, "round", "purple cup"), (418, 195, "thing", "Duplo brick"),
                        (85, 215, "thing", "bag")],
    "uois/image_0007": [(225, 140, "round", "mug"), (355, 90, "round", "purple cup"),
                        (100, 255, "thing", "Duplo brick")],
    "uois/image_0008": [(270, 300, "round", "wipes canister"), (145, 270, "round", "purple cup"),
                        (360, 100, "round", "bottle"), (330, 250, "round", "green mug"),
                        (385, 230, "round", "orange mug"), (435, 180, "round", "robot can"),
                        (500, 175, "box", "container")],
}


def frames(osd: str | None, uois: str | None) -> list[tuple[str, str, tuple]]:
    """``(key, path, intrinsics)`` of every frame found; key as in ``TRUTH``."""
    out = []
    if osd:
        for name in ("learn6", "test42", "test50", "test63", "test64"):
            p = os.path.join(osd, f"{name}_depth.png")
            if os.path.exists(p):
                out.append((f"osd/{name}", p, OSD_INTRINSICS))
    if uois:
        for i in range(9):
            for p in (os.path.join(uois, f"image_000{i}_depth.png"),
                      os.path.join(uois, f"image_000{i}.npy")):
                if os.path.exists(p):
                    out.append((f"uois/image_000{i}", p, UOIS_INTRINSICS))
                    break
    return out


def read_frame(path: str, intrinsics):
    """The frame as a planerel cloud (a uois ``.npy`` dict's ``depth``, or a depth PNG)."""
    import planerel
    from planerel.io.cloud import depth_to_cloud

    if path.endswith(".npy"):
        d = np.load(path, allow_pickle=True).item()  # the uois example format: a pickled dict
        return depth_to_cloud(np.asarray(d["depth"]), intrinsics, 1000.0, source=path)
    return planerel.read(path, intrinsics=intrinsics, depth_scale=1000)


def point_answer(prop: np.ndarray, x: int, y: int, half: int = 4) -> int:
    """The proposal holding most pixels of the (2 half + 1)^2 window at column x, row y; -1 if none."""
    win = prop[max(0, y - half): y + half + 1, max(0, x - half): x + half + 1]
    k = win[win >= 0]
    return int(np.bincount(k).argmax()) if k.size else -1


def frame(clf, key: str, path: str, intrinsics) -> dict:
    from planerel.features.facts import describe_scene
    from planerel.features.object_eval import answer_masks, proposal_image
    from planerel.ilp.scenes import segment_cached

    stem = key.split("/")[1]
    cloud = read_frame(path, intrinsics)
    ans = clf.classify(cloud, scene_id=stem)
    desc = describe_scene(cloud, segment_cached(cloud, method=clf.method, params=clf.seg_params),
                          scene_id=stem, **clf._describe_kw)
    prop = proposal_image(ans.labels, [o.labels for o in ans.objects],
                          answer_masks(desc.objects, ans.objects))
    points = []
    for x, y, kind, name in TRUTH[key]:
        k = point_answer(prop, x, y)
        points.append({"x": x, "y": y, "kind": kind, "name": name,
                       "object": ans.objects[k].object_id if k >= 0 else None,
                       "answer": ans.objects[k].klass if k >= 0 else "none"})
    answered = [{"object": o.object_id, "class": o.klass, "planar_fraction": o.planar_fraction,
                 "planes": len(o.labels)} for o in ans.objects if o.klass != "other"]
    return {"frame": key, "planes": len(desc.planes), "objects": len(ans.objects),
            "seconds": round(ans.seconds, 2), "answered": answered, "points": points}


def summarize(rows: list[dict]) -> dict:
    pts = [p for r in rows for p in r["points"]]
    boxes = [p for p in pts if p["kind"] == "box"]
    rounds = [p for p in pts if p["kind"] == "round"]
    others = [p for p in pts if p["kind"] == "other"]
    return {
        "frames": len(rows),
        "boxes": len(boxes), "boxes_box": sum(p["answer"] == "box" for p in boxes),
        "round": len(rounds),
        "round_stairs_ramp": sum(p["answer"] in ("stairs", "ramp") for p in rounds),
        "other": len(others), "other_box": sum(p["answer"] == "box" for p in others),
        "objects_stairs_ramp": sum(p["answer"] in ("stairs", "ramp") for p in pts),
        "stairs_answers": sum(a["class"] == "stairs" for r in rows for a in r["answered"]),
        "ramp_answers": sum(a["class"] == "ramp" for r in rows for a in r["answered"]),
        "box_answers": sum(a["class"] == "box" for r in rows for a in r["answered"]),
    }


def print_summary(s: dict, label: str) -> None:
    print(f"{label}: {s['frames']} frames; boxes `box` {s['boxes_box']}/{s['boxes']}; "
          f"round objects stairs/ramp {s['round_stairs_ramp']}/{s['round']}; "
          f"other objects `box` {s['other_box']}/{s['other']}; annotated objects held by a "
          f"stairs/ramp answer {s['objects_stairs_ramp']}; answers: stairs {s['stairs_answers']}, "
          f"ramp {s['ramp_answers']} (all false), box {s['box_answers']}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--osd", help="folder of the OSD frames (NAME_depth.png)")
    ap.add_argument("--uois", help="folder of the uois RealSense frames (image_000N.npy or _depth.png)")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--json", help="write every frame's figures here")
    ap.add_argument("--verbose", action="store_true", help="print every point's answer")
    a = ap.parse_args(argv)
    if not (a.osd or a.uois):
        ap.error("give --osd DIR and/or --uois DIR")
    from planerel.classify.classifier import Classifier
    from planerel.commands.classify import _params

    todo = frames(a.osd, a.uois)
    if not todo:
        print("no frames found (OSD: NAME_depth.png; uois: image_000N.npy or image_000N_depth.png)",
              file=sys.stderr)
        return 2
    with Classifier(a.model, seg_params=_params(a.param)) as clf:
        rows = [frame(clf, *t) for t in todo]
    for r in rows:
        cls = ", ".join(f"{x['object']} {x['class']}" for x in r["answered"]) or "nothing"
        print(f"{r['frame']}: {r['planes']} planes, {r['objects']} objects; answered: {cls}")
        for p in r["points"]:
            bad = ((p["kind"] == "box" and p["answer"] != "box")
                   or (p["kind"] == "other" and p["answer"] == "box")
                   or p["answer"] in ("stairs", "ramp"))
            if a.verbose or bad:
                print(f"  {'x' if bad else ' '} {p['name']} ({p['kind']}, {p['x']},{p['y']}): "
                      f"{p['answer']} {p['object'] or ''}")
    for label, sel in (("OSD", "osd/"), ("RealSense", "uois/"), ("all", "")):
        part = [r for r in rows if r["frame"].startswith(sel)]
        if part:
            print_summary(summarize(part), label)
    if a.json:
        with open(a.json, "w") as fh:
            json.dump({"frames": rows, "summary": summarize(rows)}, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
