"""Real frames nobody on the team has seen, scored against image regions labelled by hand.

    .venv/bin/python benchmarks/real_unseen.py DIR [DIR ...] [--model out/model]
        [--param NAME=VALUE ...] [--json F]

Each ``DIR`` holds frames from a public repository (never copied into planerel) and a
``labels.json`` written beside them (also outside the repository)::

    {"set": "pcl-pairwise", "source": "owner/repo COMMIT path (licence)",
     "frames": [{"file": "capture0001.pcd",
                 "intrinsics": "W,H,fx,fy,cx,cy",      (optional; else the file's sidecar)
                 "depth_scale": 1000,                   (optional)
                 "up": [x, y, z],                       (optional; else estimated)
                 "camera_height": 0.06,                 (optional: metres over the floor)
                 "objects": [{"class": "stairs", "box": [x0, y0, x1, y1], "what": "..."}],
                 "unscored": [[x0, y0, x1, y1]],        (optional)
                 "flat": [{"box": [x0, y0, x1, y1], "what": "..."}]},  (optional)
                ...]}

``box`` is a pixel rectangle (columns ``x0:x1``, rows ``y0:y1``) around one labelled object of
a class (``box``, ``stairs``, ``ramp``); everything outside the labelled rectangles is of no
class.  An answer (an object ``planerel classify`` calls a class) is *right* when at least
half of its pixels lie in a rectangle of its class, *unscored* when half lie in an
``unscored`` rectangle (something whose shape the frame does not tell), and *false*
otherwise.  A labelled object is *found* when a right answer lies in it, and *called* the
classes of every answer with half of its pixels in it.  ``flat`` rectangles mark flat things
that are none of the classes lying on a table or the floor (a keyboard, a shut laptop, a
plate, a tray, a mat): they are of no class like everything unlabelled, and each is reported
with the classes and rules of the answers with half of their pixels in it, so the false boxes
made of flat things are counted apart (the ``hunt88`` sets, docs/objects.md).

The sets of 2026-11-30 (docs/objects.md, "Real frames nobody on the team had seen"):

* ``pcl-pairwise``: PointCloudLibrary/data ``tutorials/pairwise/capture0001-0005.pcd``
  (BSD-3): five organized 640x480 Kinect clouds of one room, an open-riser flight with a
  banister seen from its side and front at 1.7-3 m, a desk with drawer pedestals, a plant,
  an office chair;
* ``pcl-tutorials``: ``person.pcd``, ``table_scene_mug_stereo_textured.pcd``,
  ``region_growing_rgb_tutorial.pcd`` of the same repository: nothing of the classes;
* ``palletizer``: MuhammadUsamaSattar/smart_palletizer ``data/*/raw_depth.png`` with its
  ``intrinsics.json`` (no licence file): 13 cartons packed on a pallet seen from 1.1 m
  straight above, two captures.
"""

from __future__ import annotations

import argparse
import json
import os
import sys

import numpy as np

CLASSES = ("box", "stairs", "ramp")


def read_labels(folder: str) -> dict:
    """The ``labels.json`` of a set folder, checked.

    Raises
    ------
    planerel.errors.InputError
        No file, or a frame or object not of the form above.
    """
    from planerel.errors import InputError

    path = os.path.join(folder, "labels.json")
    if not os.path.exists(path):
        raise InputError(f"{folder}: no labels.json (see benchmarks/real_unseen.py)")
    with open(path) as fh:
        doc = json.load(fh)
    frames = doc.get("frames") if isinstance(doc, dict) else None
    if not isinstance(frames, list):
        raise InputError(f"{path}: needs a list 'frames'")
    for f in frames:
        if not isinstance(f, dict) or not isinstance(f.get("file"), str):
            raise InputError(f"{path}: every frame needs a 'file'")
        for o in f.get("objects", []):
            box = o.get("box") if isinstance(o, dict) else None
            if (not isinstance(o, dict) or o.get("class") not in CLASSES
                    or not isinstance(box, list) or len(box) != 4):
                raise InputError(f"{path}: {f['file']}: an object needs a 'class' of "
                                 f"{', '.join(CLASSES)} and a 'box' [x0, y0, x1, y1]")
        for o in f.get("flat", []):
            box = o.get("box") if isinstance(o, dict) else None
            if not isinstance(box, list) or len(box) != 4:
                raise InputError(f"{path}: {f['file']}: a flat thing needs a 'box' "
                                 f"[x0, y0, x1, y1]")
    return doc


def rect_mask(shape, box) -> np.ndarray:
    """Boolean ``(H, W)`` mask of the pixel rectangle ``[x0, y0, x1, y1]`` (clipped)."""
    h, w = shape
    x0, y0, x1, y1 = (int(round(v)) for v in box)
    m = np.zeros((h, w), bool)
    m[max(0, y0):min(h, y1), max(0, x0):min(w, x1)] = True
    return m


def score_frame(answer, frame: dict) -> dict:
    """Right, false and unscored answers of one frame, and what each labelled object was called.

    Parameters
    ----------
    answer : planerel.classify.classifier.SceneAnswer
        The frame's answer (``labels`` ``(H, W)``, ``objects``).
    frame : dict
        The frame's entry of ``labels.json``.

    Returns
    -------
    dict
        ``objects`` (per labelled object: ``class``, ``found``, ``called``), ``right``,
        ``false`` (``[(class, rule index, share of its pixels in the best labelled
        rectangle)]``), ``unscored``, ``flat`` (per ``flat`` rectangle: ``what`` and
        ``called``, ``[(class, rule index)]`` of the answers with half of their pixels in it).
    """
    lab = np.asarray(answer.labels)
    shape = lab.shape
    labelled = [(o, rect_mask(shape, o["box"])) for o in frame.get("objects", [])]
    unscored = [rect_mask(shape, b) for b in frame.get("unscored", [])]
    flats = [(f, rect_mask(shape, f["box"])) for f in frame.get("flat", [])]
    flat_called = [[] for _ in flats]
    called = [[] for _ in labelled]
    found = [False] * len(labelled)
    right, false, skipped = [], [], []
    for o in answer.objects:
        if o.klass not in CLASSES:
            continue
        pix = np.isin(lab, list(o.labels))
        n = int(pix.sum())
        if n == 0:
            continue
        shares = [float((pix & m).sum()) / n for _, m in labelled]
        for i, (_, m) in enumerate(flats):
            if float((pix & m).sum()) / n >= 0.5:
                flat_called[i].append((o.klass, o.rule_index))
        for i, s in enumerate(shares):
            if s >= 0.5:
                called[i].append(o.klass)
        hit = [i for i, s in enumerate(shares) if s >= 0.5 and labelled[i][0]["class"] == o.klass]
        if hit:
            right.append((o.klass, o.rule_index))
            for i in hit:
                found[i] = True
        elif any(float((pix & m).sum()) / n >= 0.5 for m in unscored):
            skipped.append((o.klass, o.rule_index))
        else:
            false.append((o.klass, o.rule_index, round(max(shares, default=0.0), 2)))
    return {"objects": [{"class": o["class"], "what": o.get("what", ""), "found": f, "called": c}
                        for (o, _), f, c in zip(labelled, found, called, strict=True)],
            "right": right, "false": false, "unscored": skipped,
            "flat": [{"what": f.get("what", ""), "called": c}
                     for (f, _), c in zip(flats, flat_called, strict=True)]}


def read_frame(folder: str, frame: dict):
    """Read one labelled frame of ``folder`` with its ``intrinsics`` and ``depth_scale``:
    ``(cloud, up)``, ``up`` the frame's own gravity-up as an array of shape (3,), or None."""
    import planerel

    cloud = planerel.read(os.path.join(folder, frame["file"]), intrinsics=frame.get("intrinsics"),
                          depth_scale=frame.get("depth_scale"))
    up = frame.get("up")
    return cloud, None if up is None else np.asarray(up, float)


def describe_frame(clf, folder: str, frame: dict):
    """Read one labelled frame of ``folder`` (its ``intrinsics``, ``depth_scale``, ``up`` and
    ``camera_height``) and describe it as ``clf`` (a
    :class:`planerel.classify.classifier.Classifier`) does, the far growing's planes marked:
    ``(cloud, SceneDescription)``."""
    from planerel.features.facts import describe_scene
    from planerel.ilp.scenes import segment_cached_far

    cloud, up = read_frame(folder, frame)
    labels, far = segment_cached_far(cloud, method=clf.method, params=clf.seg_params)
    return cloud, describe_scene(cloud, labels, scene_id="s", up=up, far=far,
                                 camera_height=frame.get("camera_height"), **clf._describe_kw)


def run(folders, model: str, params=()) -> list:
    """Classify every labelled frame of ``folders``; one row per frame."""
    import planerel
    from planerel.classify.classifier import Classifier
    from planerel.commands.classify import _params

    rows = []
    with Classifier(model, seg_params=_params(list(params))) as clf:
        for folder in folders:
            doc = read_labels(folder)
            for frame in doc["frames"]:
                path = os.path.join(folder, frame["file"])
                cloud = planerel.read(path, intrinsics=frame.get("intrinsics"),
                                      depth_scale=frame.get("depth_scale"))
                stem = os.path.splitext(os.path.basename(path))[0]
                up = frame.get("up")
                ans = clf.classify(cloud, scene_id="s",
                                   up=None if up is None else np.asarray(up, float),
                                   camera_height=frame.get("camera_height"))
                row = {"set": doc.get("set", os.path.basename(os.path.normpath(folder))),
                       "frame": stem, "objects_proposed": len(ans.objects)}
                row.update(score_frame(ans, frame))
                rows.append(row)
    return rows


def totals(rows) -> dict:
    """Labelled objects found of each class, and false answers of each class, over ``rows``."""
    out = {"frames": len(rows)}
    for k in CLASSES:
        objs = [o for r in rows for o in r["objects"] if o["class"] == k]
        out[f"{k}_found"] = sum(o["found"] for o in objs)
        out[f"{k}_labelled"] = len(objs)
        out[f"false_{k}"] = sum(1 for r in rows for f in r["false"] if f[0] == k)
    flats = [f for r in rows for f in r.get("flat", [])]
    out["flat_labelled"] = len(flats)
    for k in CLASSES:
        out[f"flat_called_{k}"] = sum(1 for f in flats if any(c[0] == k for c in f["called"]))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folders", nargs="+", metavar="DIR", help="set folders holding labels.json")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--json", help="write the rows and totals here")
    a = ap.parse_args(argv)
    rows = run(a.folders, a.model, a.param)
    for r in rows:
        objs = "; ".join(f"{o['class']} {'found' if o['found'] else 'missed'}"
                         f" (called {', '.join(o['called']) or 'nothing'})" for o in r["objects"])
        false = ", ".join(f"{k} (rule {rule}, {s:.0%} in a labelled object)" for k, rule, s in r["false"])
        print(f"{r['set']}/{r['frame']}: {r['objects_proposed']} proposals; "
              f"{objs or 'nothing labelled'}; false: {false or 'none'}"
              f"{'; unscored ' + str(len(r['unscored'])) if r['unscored'] else ''}")
    t = totals(rows)
    print("found: " + ", ".join(f"{k} {t[f'{k}_found']}/{t[f'{k}_labelled']}" for k in CLASSES)
          + "; false answers: " + ", ".join(f"{k} {t[f'false_{k}']}" for k in CLASSES)
          + f" ({t['frames']} frames)")
    if t["flat_labelled"]:
        rules = sorted({c[1] for r in rows for f in r["flat"] for c in f["called"]})
        print(f"flat things: {t['flat_labelled']}; called " + ", ".join(
            f"{k} {t[f'flat_called_{k}']}" for k in CLASSES)
              + (f" (rules {', '.join(map(str, rules))})" if rules else ""))
    if a.json:
        from planerel.atomic import write_text

        write_text(a.json, json.dumps({"rows": rows, "totals": t}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
