"""Measure what the planes of every ramp proof are like: true ramps against outdoor terrain.

    nice .venv/bin/python benchmarks/ramp_terrain.py --model /work/main/out/model \
        --train /work/main/out/data/model_train --independent /work/dev/dev_i /work/dev/dev_k \
        /work/dev/dev_sr --hunts /work/hunt35 [--json OUT]

For each scene, the classifier's own path (segment, describe, answer with the scan's points);
for every object one of whose fired rules is ``ramp`` (answered or refused), each inclined plane
of its proof is measured:

- ``rms / sigma``: the plane's RMS residual over the sensor's depth noise ``sigma(z)`` at its
  median range (:func:`planerel.segment.noise.estimate_noise`);
- the foot (:func:`planerel.features.foot.slope_foot`): low end's height and hidden share;
- what lies beyond the slope's top: the scene's points (not the plane's) up to ``R`` metres
  past the plane's top along its horizontal uphill direction and within its lateral extent;
  their height over the top (``above``: share more than 0.15 m over it; ``q90``);
- the truth: the labelled object most of the proposal's pixels belong to (training and
  independent scenes), or "false" for the labelled hunts (any ramp there is false).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import planerel  # noqa: E402
from planerel.classify.classifier import Classifier  # noqa: E402
from planerel.features.facts import describe_scene  # noqa: E402
from planerel.features.foot import slope_foot  # noqa: E402
from planerel.ilp.scenes import segment_cached  # noqa: E402
from planerel.segment.noise import estimate_noise  # noqa: E402

BEYOND = (0.3, 0.6, 1.0)
RISE = 0.15


def beyond_top(planes, label, xyz, lab, reach):
    """Heights over the plane's top of the points past it (see the module docstring)."""
    up = np.asarray(planes.up, float)
    plane = planes.by_label(int(label))
    n = np.asarray(plane.normal, float)
    if n @ up < 0:
        n = -n
    d = up - (up @ n) * n  # uphill, in the plane
    dh = d - (d @ up) * up
    if np.linalg.norm(dh) < 1e-9:
        return None
    dh /= np.linalg.norm(dh)
    lat = np.cross(up, dh)
    z = xyz[..., 2]
    valid = np.isfinite(z) & (z > 0)
    mask = (lab == int(label)) & valid
    P = xyz[mask]
    s, h, lt = P @ dh, P @ up, P @ lat
    top_s, top_h = np.percentile(s, 99), np.percentile(h, 99)
    l0, l1 = np.percentile(lt, 1), np.percentile(lt, 99)
    Q = xyz[valid & ~mask]
    known = np.isin(lab, [q.label for q in planes.planes])[valid & ~mask]
    qs, qh, ql = Q @ dh, Q @ up, Q @ lat
    out = {"top": float(top_h - planes.floor_level) if planes.floor is not None else None}
    for r in reach:
        sel = (qs > top_s - 0.05) & (qs <= top_s + r) & (ql >= l0) & (ql <= l1)
        dhh = qh[sel] - top_h
        out[f"n{r}"] = int(sel.sum())
        out[f"above{r}"] = float((dhh > RISE).mean()) if dhh.size else None
        out[f"q90_{r}"] = float(np.percentile(dhh, 90)) if dhh.size else None
        out[f"rough{r}"] = float(((dhh > RISE) & ~known[sel]).mean()) if dhh.size else None
        out[f"level{r}"] = float((np.abs(dhh) <= RISE).mean()) if dhh.size else None
    return out


def floor_band(planes, lab, xyz, rng, rms):
    """The floor's own roughness at the slope's range: a plane fitted to the floor's points
    within 0.8-1.25 times the slope's median range; its RMS, and the slope's RMS over it."""
    if planes.floor is None:
        return {"floor_rms": None, "rel": None}
    m = (lab == planes.floor) & np.isfinite(xyz[..., 2])
    F = xyz[m]
    r = np.linalg.norm(F, axis=1)
    F = F[(r >= 0.8 * rng) & (r <= 1.25 * rng)]
    if len(F) < 100:
        return {"floor_rms": None, "rel": None, "floor_n": int(len(F))}
    c = F - F.mean(0)
    w = np.linalg.svd(c, full_matrices=False)[1]
    frms = float(w[-1] / np.sqrt(len(F)))
    return {"floor_rms": round(frms, 4), "rel": round(rms / frms, 2) if frms > 0 else None,
            "floor_n": int(len(F))}


def measure(clf, cloud, truth=None, classes=None, false_all=False, name=""):
    labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
    desc = describe_scene(cloud, labels, scene_id="s", up=None, **clf._describe_kw)
    ans = clf.answer_description(desc, xyz=cloud.xyz)
    lab = np.asarray(desc.labels)
    P = desc.planes
    pid = {desc.plane_id(p.label): p for p in P.planes}
    noise = estimate_noise(cloud)
    xyz = np.asarray(cloud.xyz, float)
    rows = []
    for o in ans:
        if not any(f[0] == "ramp" for f in o.fired):
            continue
        pix = np.isin(lab, list(o.labels))
        if false_all:
            tru = "false"
        elif truth is not None:
            t = truth[pix]
            t = t[t > 0]
            k = int(np.bincount(t).argmax()) if t.size else 0
            tru = classes.get(k, "none") if k else "none"
        else:
            tru = "?"
        cand = (o.proof_planes if o.klass == "ramp"
                else [q for q in o.planes if q in pid and pid[q].area >= 0.5])
        for q in cand:
            p = pid.get(q)
            if p is None or p.orientation != "inclined":
                continue
            m = (lab == p.label) & np.isfinite(xyz[..., 2])
            rng = float(np.median(np.linalg.norm(xyz[m], axis=1)))
            zmed = float(np.median(xyz[m][:, 2]))
            sig = float(noise.sigma(zmed)) if noise.reliable else float("nan")
            ft = slope_foot(P, p.label, xyz, labels=desc.labels)
            row = {"scene": name, "object": o.object_id, "answer": o.klass, "truth": tru,
                   "refused": [str(r)[:60] for r in o.refused], "plane": q,
                   "incline": round(p.incline, 1), "area": round(p.area, 2), "range": round(rng, 2),
                   "rms": round(p.rms, 4), "sigma": round(sig, 4),
                   "ratio": round(p.rms / sig, 2) if sig > 0 else None,
                   "wave": round(noise.wave, 2), "noise_kind": noise.kind,
                   "low": None if ft is None else round(ft.low, 3),
                   "hidden": None if ft is None else round(ft.hidden, 2)}
            row.update(floor_band(P, lab, xyz, rng, p.rms))
            b = beyond_top(P, p.label, xyz, lab, BEYOND)
            if b:
                row.update({k: (round(v, 3) if isinstance(v, float) else v) for k, v in b.items()})
            rows.append(row)
    return rows


def _emit(rows: list, found) -> None:
    """Print each measured row (one JSON line) as it comes and keep it in ``rows``."""
    for r in found:
        print(json.dumps(r), flush=True)
        rows.append(r)


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--model", required=True)
    ap.add_argument("--train", nargs="*", default=[])
    ap.add_argument("--independent", nargs="*", default=[])
    ap.add_argument("--hunts", nargs="*", default=[])
    ap.add_argument("--json")
    ap.add_argument("--param", action="append", default=[])
    a = ap.parse_args(argv)
    rows = []
    with Classifier(a.model) as clf:
        for d in a.train:
            for p in sorted(Path(d).glob("s*.depth.png")):
                side = json.loads(p.with_name(p.name.replace(".depth.png", ".json")).read_text())
                if not any(o["class"] == "ramp" for o in side["objects"]):
                    continue
                from PIL import Image
                gt = np.array(Image.open(p.with_name(side["files"]["labels"]))).astype(int)
                # the ground truth labels planes (value = plane index + 1): to objects
                obj = np.zeros(max(gt.max(), len(side["planes"])) + 1, int)
                for pl in side["planes"]:
                    obj[pl["index"] + 1] = pl["object_index"] + 1
                truth = obj[gt]
                classes = {o["index"] + 1: o["class"] for o in side["objects"]}
                cloud = planerel.read(str(p))
                _emit(rows, measure(clf, cloud, truth, classes, name=f"train/{p.stem}"))
        for d in a.independent:
            for p in sorted(Path(d).glob("i[0-9][0-9][0-9][0-9].npy")):
                side = json.loads(p.with_suffix(".json").read_text())
                truth = np.load(p.with_name(p.stem + ".objects.npy")).astype(int)
                classes = {o["index"]: o["class"] for o in side["objects"]}
                cloud = planerel.read(str(p))
                _emit(rows, measure(clf, cloud, truth, classes, name=f"{Path(d).name}/{p.stem}"))
        for h in a.hunts:
            for lj in sorted(Path(h).glob("*/labels.json")):
                doc = json.loads(lj.read_text())
                for fr in doc["frames"]:
                    path = lj.parent / fr["file"]
                    cloud = planerel.read(str(path), intrinsics=fr.get("intrinsics"),
                                          depth_scale=fr.get("depth_scale"))
                    _emit(rows, measure(clf, cloud, false_all=True,
                                     name=f"{Path(h).name}/{lj.parent.name}/{fr['file']}"))
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1))
    summarize(rows)


SUMMARY = ("ratio", "rel", "above0.3", "above0.6", "rough0.3", "rough0.6", "rough1.0", "low",
           "hidden", "top")


def summarize(rows):
    """Min / median / max of each measure over the true ramps answered ``ramp`` (per source),
    and every false ``ramp`` answer's values."""
    groups = {}
    for r in rows:
        if r["answer"] != "ramp":
            continue
        src = r["scene"].split("/")[0]
        key = (src, "true" if r["truth"] == "ramp" else "false")
        groups.setdefault(key, []).append(r)
    for (src, kind), g in sorted(groups.items()):
        print(f"{src} {kind} ramp planes: {len(g)}")
        if kind == "false" and len(g) <= 12:
            for r in g:
                print("   ", r["scene"], r["plane"], " ".join(f"{k}={r.get(k)}" for k in SUMMARY))
            continue
        for k in SUMMARY:
            v = np.array([r[k] for r in g if r.get(k) is not None], float)
            v = v[np.isfinite(v)]
            if v.size:
                print(f"    {k}: n {v.size} min {v.min():.3f} median {np.median(v):.3f} "
                      f"max {v.max():.3f}")


if __name__ == "__main__":
    main()
