"""Every ramp answer's sloping planes, measured against the sensor's noise and the floor (ramp48).

For each scene of the given folders (labelled real sets: a ``labels.json`` with ``frames``, as
``benchmarks/real_unseen.py`` reads them, its ``up`` given when a frame has one; independent
sets: ``iNNNN.npy`` with their sidecars), the classifier's own segment / describe / answer path,
and for every object some ramp rule proved (answered ``ramp`` or refused by a gate) each
inclined plane of its first proof (or, with ``--all``, every inclined plane of 0.5 m^2 or more at
most 28 degrees steep):

- ``area``, ``incline`` (against the up used), ``range`` (centroid distance), ``rms`` (the plane
  fit's residual, metres), ``fall`` (the plane's extent along its fall line, 2nd-98th percentile
  of its points, metres), ``rise`` (98th minus 2nd percentile of its points' heights along up),
  ``sigma`` (the frame's estimated random depth noise at the plane's median depth,
  :func:`planerel.segment.noise.estimate_noise`), ``wave`` (that model's waviness), ``depth_err``
  (``rise`` over ``sigma``);
- its low end (:func:`planerel.features.foot.slope_foot`: height over the floor, share hidden);
- the scene's up: source, confidence, whether flagged low, upside down;
- the floor plane: area, range, rms, and ``rel``, the angle between the slope's normal and the
  floor's;
- the answer, the refusals, and whether it is false (labelled sets: ``real_unseen.score_frame``)
  or the ground truth's majority object (independent sets).

Example::

    nice .venv/bin/python benchmarks/ramp_rise.py /work/hunt45/*/ /work/hunt35/*/ /work/hunt47/*/ \\
        --model out/model --json /tmp/rise.json
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


def scenes_of(folder: Path):
    """``(path, frame entry or None)`` of each scene of a folder (a training world's folder:
    its ``s*.depth.png`` scenes with a ramp)."""
    if (folder / "dataset.json").exists():
        for p in sorted(folder.glob("s*.depth.png")):
            side = json.loads(p.with_name(p.name.replace(".depth.png", ".json")).read_text())
            if any(o["class"] == "ramp" for o in side["objects"]):
                yield p, None
        return
    lab = folder / "labels.json"
    if lab.exists():
        from real_unseen import read_labels

        for fr in read_labels(str(folder))["frames"]:
            yield folder / fr["file"], fr
        return
    for p in sorted(folder.glob("i[0-9][0-9][0-9][0-9].npy")):
        yield p, None


def plane_record(ps, plane, xyz, lab, noise, foot) -> dict:
    """The measures of one inclined plane (see the module's docstring)."""
    up = np.asarray(ps.up, dtype=np.float64)
    n = np.asarray(plane.normal, dtype=np.float64)
    mask = (lab == plane.label) & np.isfinite(xyz[..., 2])
    pts = xyz[mask].astype(np.float64)
    h = pts @ up
    uphill = up - (up @ n) * n
    nu = float(np.linalg.norm(uphill))
    fall = 0.0
    if nu > 1e-9:
        s = pts @ (uphill / nu)
        fall = float(np.percentile(s, 98) - np.percentile(s, 2))
    rise = float(np.percentile(h, 98) - np.percentile(h, 2))
    zmed = float(np.median(pts[:, 2])) if len(pts) else 0.0
    sigma = float(noise.sigma(zmed)) if noise is not None else 0.0
    rec = {"area": round(plane.area, 3), "incline": round(plane.incline, 2),
           "range": round(plane.distance, 2), "rms": round(plane.rms, 4),
           "fall": round(fall, 3), "rise": round(rise, 3), "zmed": round(zmed, 2),
           "sigma": round(sigma, 4), "wave": round(float(getattr(noise, "wave", 0.0)), 2),
           "rise_sigma": round(rise / sigma, 1) if sigma > 0 else None,
           "facing": round(float(n @ up), 3),
           "foot": None if foot is None else [round(foot.low, 3), round(foot.hidden, 3)]}
    if ps.floor is not None:
        fl = ps.by_label(ps.floor)
        fn = np.asarray(fl.normal, dtype=np.float64)
        c = abs(float(np.clip(fn @ n, -1.0, 1.0)))
        rec["floor"] = {"area": round(fl.area, 2), "range": round(fl.distance, 2),
                        "rms": round(fl.rms, 4), "incline": round(fl.incline, 2),
                        "rel": round(math.degrees(math.acos(c)), 2)}
    return rec


def scene_records(clf, path: Path, frame, everything: bool, est: bool = False) -> list:
    import planerel
    from planerel.classify.classifier import SceneAnswer
    from planerel.features.facts import describe_scene
    from planerel.features.foot import slope_foot
    from planerel.ilp.scenes import segment_cached
    from planerel.segment.noise import estimate_noise

    if frame is not None:
        cloud = planerel.read(str(path), intrinsics=frame.get("intrinsics"),
                              depth_scale=frame.get("depth_scale"))
        given = frame.get("up")
        up = None if given is None else np.asarray(given, dtype=np.float64)
    else:
        cloud, up = planerel.read(str(path)), None
        if est:  # the sidecar's up dropped: the estimate decides, as on a real frame
            cloud = dataclasses.replace(cloud, up=None)
    labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
    desc = describe_scene(cloud, labels, scene_id="s", up=up, **clf._describe_kw)
    ps = desc.planes
    answers = clf.answer_description(desc, xyz=cloud.xyz)
    pid = {p.label: desc.plane_id(p.label) for p in ps}
    by_id = {v: k for k, v in pid.items()}
    lab = np.asarray(desc.labels)
    xyz = np.asarray(cloud.xyz, dtype=np.float64)
    try:
        noise = estimate_noise(cloud, waviness=True)
    except Exception:  # noqa: BLE001 - an unorganized cloud: no noise model
        noise = None
    gravity = clf._describe_kw.get("gravity_params")
    low = bool(ps.up_low(None if gravity is None else gravity.low_confidence))
    verdict = {}
    if frame is not None:
        from real_unseen import score_frame

        ans = SceneAnswer(cloud.source, "s", desc.labels, pid, answers, ps.up_source, 0.0)
        for o in answers:  # each answer judged alone: is it a false one?
            one = SceneAnswer(cloud.source, "s", desc.labels, pid, (o,), ps.up_source, 0.0)
            sc = score_frame(one, frame)
            verdict[o.object_id] = ("right" if sc["right"] else "false" if sc["false"]
                                    else "unscored" if sc["unscored"] else "-")
        del ans
    truth = side = None
    if frame is None and path.name.endswith(".depth.png"):  # a training world's scene
        from PIL import Image

        tside = json.loads(path.with_name(path.name.replace(".depth.png", ".json")).read_text())
        gt = np.array(Image.open(path.with_name(tside["files"]["labels"]))).astype(int)
        # the ground truth labels planes (value = plane index + 1): to objects
        obj = np.zeros(max(gt.max(), len(tside["planes"])) + 1, int)
        for pl in tside["planes"]:
            obj[pl["index"] + 1] = pl["object_index"] + 1
        truth = obj[gt]
        side = {"objects": [{"index": o["index"] + 1, "class": o["class"]}
                            for o in tside["objects"]]}
    elif frame is None:
        t = path.with_name(path.stem + ".objects.npy")
        truth = np.load(t) if t.exists() else None
        sj = path.with_suffix(".json")
        side = json.loads(sj.read_text()) if sj.exists() else None
    out = []
    for a in answers:
        ramp_fired = a.klass == "ramp" or any(getattr(r, "klass", None) == "ramp"
                                              for r in a.refused)
        if everything:
            cand = [by_id[i] for i in a.planes if i in by_id]
        elif ramp_fired:
            cand = [by_id[i] for i in (a.proof_planes or a.planes) if i in by_id]
        else:
            continue
        for label in cand:
            p = ps.by_label(label)
            if p.orientation != "inclined" or p.incline > 28 or (everything and p.area < 0.5):
                continue
            foot = slope_foot(ps, label, xyz, labels=desc.labels)
            rec = {"scene": str(path), "object": a.object_id, "plane": pid[label],
                   "answer": a.klass, "rule": a.rule_index,
                   "refused": sorted({type(r).__name__ for r in a.refused
                                      if getattr(r, "klass", None) == "ramp"}),
                   "up_source": ps.up_source, "confidence": round(float(ps.up_confidence), 3),
                   "up_low": low, "upside_down": bool(ps.up_upside_down),
                   "has_floor": ps.floor is not None}
            rec.update(plane_record(ps, p, xyz, lab, noise, foot))
            if frame is not None:
                rec["verdict"] = verdict.get(a.object_id, "-")
            elif truth is not None and side is not None:
                m = truth[lab == label]
                m = m[m >= 0]
                if m.size:
                    v, c = np.unique(m, return_counts=True)
                    k = int(v[np.argmax(c)])
                    rec["truth"] = "environment" if k == 0 else next(
                        o["class"] for o in side["objects"] if o["index"] == k)
            out.append(rec)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("folders", nargs="+")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--param", action="append", default=[], metavar="KEY=VALUE",
                    help="model setting override (classify's --param)")
    ap.add_argument("--all", action="store_true",
                    help="every inclined plane of 0.5 m^2 or more, not only ramp proofs")
    ap.add_argument("--est", action="store_true",
                    help="drop an independent scene's sidecar up: the estimate decides")
    ap.add_argument("--json")
    args = ap.parse_args(argv)
    from planerel.classify.classifier import Classifier
    from planerel.commands.classify import _params

    recs = []
    with Classifier(args.model, seg_params=_params(list(args.param))) as clf:
        for folder in args.folders:
            for path, frame in scenes_of(Path(folder)):
                for r in scene_records(clf, path, frame, args.all, args.est):
                    recs.append(r)
                    print(json.dumps(r), flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps(recs, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
