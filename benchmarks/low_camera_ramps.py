"""Ramp answers, gravity and floors per scene: what makes a large plane a ramp (ramp44).

For each scene of the given folders (independent sets: ``iNNNN.npy`` with their sidecars;
labelled real sets: a ``labels.json`` with ``frames``), the classifier's own segment / describe /
answer path, and per scene:

- the up vector used, its source and confidence, whether it was read upside down, and (with
  ``--est`` on an independent scene: its sidecar ``up`` is dropped so that the estimate decides)
  its angle to the generator's true up; with ``--truth FILE`` a labelled real frame's up is
  measured against the floor normal the file gives for it (grav45: hunt45's measured floors);
- whether a floor plane was found (the foot gate measures nothing without one);
- every inclined plane of at least 0.5 m^2 at most 28 degrees steep (what the demo's ramp rule
  can bind): its area, incline, range, ``facing`` (its normal turned to the sensor, dotted with
  up: negative = seen from below), its low end (``slope_foot``: height over the floor, share
  hidden), the answer of the proposal holding it and the refusals, and (independent scenes) the
  ground truth's majority object.

Prints a summary line per folder (``--scenes``: a line per scene and plane too) and writes every
record with ``--json``.  Example::

    nice .venv/bin/python benchmarks/low_camera_ramps.py --est /work/dev/dev_low \\
        --model out/model --param gravity.flip_min_tilt_deg=0 --param decision.side_gate=false
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
from collections import Counter
from pathlib import Path

import numpy as np


def _value(text: str):
    low = text.lower()
    if low in ("true", "false"):
        return low == "true"
    try:
        return int(text)
    except ValueError:
        try:
            return float(text)
        except ValueError:
            return text


def scenes_of(folder: Path):
    """``(path, intrinsics, depth_scale, labelled)`` of each scene of a folder."""
    lab = folder / "labels.json"
    if lab.exists():
        for fr in json.loads(lab.read_text())["frames"]:
            yield folder / fr["file"], fr.get("intrinsics"), fr.get("depth_scale"), True
        return
    for p in sorted(folder.glob("i[0-9][0-9][0-9][0-9].npy")):
        yield p, None, None, False


def scene_record(clf, path: Path, intrinsics, depth_scale, labelled: bool, est: bool,
                 truth_up=None) -> dict:
    import planerel
    from planerel.features.facts import describe_scene
    from planerel.features.foot import slope_foot
    from planerel.ilp.scenes import segment_cached

    cloud = planerel.read(str(path), intrinsics=intrinsics, depth_scale=depth_scale)
    truth = side = None
    if not labelled:
        t = path.with_name(path.stem + ".objects.npy")
        truth = np.load(t) if t.exists() else None
        sj = path.with_suffix(".json")
        side = json.loads(sj.read_text()) if sj.exists() else None
    true_up = None if cloud.up is None else np.asarray(cloud.up, dtype=np.float64)
    if est:
        cloud = dataclasses.replace(cloud, up=None)
    labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
    desc = describe_scene(cloud, labels, scene_id="s", **clf._describe_kw)
    ps = desc.planes
    answers = clf.answer_description(desc, xyz=cloud.xyz)
    up = np.asarray(ps.up, dtype=np.float64)
    dl = np.asarray(desc.labels)
    pid = {p.label: desc.plane_id(p.label) for p in ps}
    holder = {}
    for a in answers:
        for i in a.planes:
            holder[i] = a
    rec = {"scene": str(path), "up": up.round(4).tolist(), "source": ps.up_source,
           "confidence": round(float(ps.up_confidence), 3),
           "upside_down": bool(ps.up_upside_down), "floor": ps.floor is not None, "planes": []}
    if truth_up is not None:  # a labelled real frame's measured floor normal (--truth)
        true_up, est = np.asarray(truth_up, dtype=np.float64), True
        true_up = true_up / np.linalg.norm(true_up)
    if true_up is not None and est:
        c = float(np.clip(up @ true_up, -1.0, 1.0))
        rec["up_error"] = round(math.degrees(math.acos(c)), 2)
    for p in ps:
        if p.orientation != "inclined" or p.area < 0.5 or p.incline > 28:
            continue
        who = None
        if truth is not None and side is not None:
            m = truth[dl == p.label]
            if m.size:
                v, n = np.unique(m, return_counts=True)
                k = int(v[np.argmax(n)])
                who = "environment" if k == 0 else next(
                    o["class"] for o in side["objects"] if o["index"] == k)
        foot = slope_foot(ps, p.label, cloud.xyz, labels=desc.labels)
        a = holder.get(pid[p.label])
        rec["planes"].append({
            "plane": pid[p.label], "area": round(p.area, 3), "incline": round(p.incline, 2),
            "range": round(p.distance, 2),
            "facing": round(float(np.asarray(p.normal, dtype=np.float64) @ up), 3),
            "foot": None if foot is None else [round(foot.low, 3), round(foot.hidden, 3)],
            "answer": None if a is None else a.klass,
            "refused": [] if a is None else sorted({type(r).__name__ for r in a.refused}),
            "truth": who})
    return rec


def summarize(records) -> dict:
    c = Counter()
    for r in records:
        c["scenes"] += 1
        c["no floor"] += not r["floor"]
        c["upside down"] += r["upside_down"]
        if "up_error" in r:
            e = r["up_error"]
            c["up within 1 deg"] += e <= 1
            c["up 1-5 deg"] += 1 < e <= 5
            c["up 5-20 deg"] += 5 < e <= 20
            c["up over 20 deg"] += e > 20
        ramps = [p for p in r["planes"] if p["answer"] == "ramp"]
        c["scenes with a ramp answer"] += bool(ramps)
        c["... without a floor"] += bool(ramps) and not r["floor"]
        for p in r["planes"]:
            c["inclined planes"] += 1
            c["seen from below"] += p["facing"] < 0
            if p["answer"] == "ramp":
                c["ramp planes"] += 1
                if p["truth"] is not None:
                    c["ramp planes on a true ramp"] += p["truth"] == "ramp"
                    c["ramp planes on no ramp"] += p["truth"] != "ramp"
    return dict(c)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("folders", nargs="+")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--est", action="store_true",
                    help="drop an independent scene's sidecar up: the estimate decides")
    ap.add_argument("--param", action="append", default=[], metavar="KEY=VALUE",
                    help="model setting override (classify's --param), e.g. decision.side_gate=false")
    ap.add_argument("--truth", help="JSON file {\"up\": {\"SET/FRAME_FILE\": [x, y, z]}}: a labelled "
                    "real frame's measured floor normal, against which its up is measured")
    ap.add_argument("--scenes", action="store_true", help="a line per scene and plane")
    ap.add_argument("--json")
    args = ap.parse_args(argv)
    from planerel.classify.classifier import Classifier

    overrides = {}
    for item in args.param:
        key, _, val = item.partition("=")
        overrides[key.strip()] = _value(val.strip())
    truth = json.loads(Path(args.truth).read_text())["up"] if args.truth else {}
    out = {}
    with Classifier(args.model, seg_params=overrides or None) as clf:
        for folder in args.folders:
            recs = []
            for path, intr, scale, labelled in scenes_of(Path(folder)):
                r = scene_record(clf, path, intr, scale, labelled, args.est,
                                 truth.get(f"{Path(folder).name}/{path.name}"))
                recs.append(r)
                if args.scenes:
                    err = f" error {r['up_error']}" if "up_error" in r else ""
                    print(f"  {path.name}: up {r['source']} {r['confidence']}"
                          f"{' upside down' if r['upside_down'] else ''}{err}; "
                          f"floor {'yes' if r['floor'] else 'no'}")
                    for p in r["planes"]:
                        print(f"     {p}")
            out[folder] = {"summary": summarize(recs), "scenes": recs}
            print(folder, out[folder]["summary"], flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
