"""The skirt pairs that a wider narrow-top allowance adds (or takes away), per development set.

``skirt/2`` lets a narrow top inclined towards its face be a box's top when its incline is within
``skirt_top_tilt`` degrees plus ``atan(skirt_top_noise * rms / width)`` (at most
``skirt_top_tilt`` more; :meth:`planerel.features.relations._Solid.top_tilt`).  This tool
describes every frame with the model's settings but ``skirt_top_tilt`` at the widest allowance
asked (so every such top is a candidate), and evaluates each (inclined top, face)
pair under every allowance of ``--variants`` (``T:k`` = ``skirt_top_tilt`` and
``skirt_top_noise``): ``S`` a skirt, ``s`` denied only by a step or a riser (a skirt again when
these are another object's, :func:`~planerel.features.relations.skirts_within_objects`), ``.``
none; a pair whose answer differs between them is printed with the top's
incline, size, fit RMS, the allowance of each variant, whether its normal leans towards the
camera (``cam``: the cosine between the horizontal part of its upward normal and the horizontal
direction from it to the sensor) and the labelled object its pixels lie in.

Truth per set kind: a ``labels.json`` folder (the hunts, hunt25's sets): the labelled rectangle
holding at least half of the top's pixels (else ``unlabelled``); an mOSD PCD: the object id
holding most of its pixels and the frame's OSD category type; OSD / UOIS
(``real_tabletop.TRUTH``): the truth points inside the top's pixel box; an independent scene:
the object holding most of its pixels, with its class and kind; a planerel data set
(``--dataset``, the training world, described as the learner does): the same.

Run (``nice``; 2 cores shared)::

    nice .venv/bin/python benchmarks/skirt_tilt_margin.py --model out/model \\
        --labelled /work/hunt43/*/ --mosd /work/extdata/mosd --tabletop /work/extdata \\
        --independent /work/dev/dev_i --json out.jsonl
"""
from __future__ import annotations

import argparse
import dataclasses
import glob
import json
import math
import os
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

DEFAULT_VARIANTS = "10:2,15:2,20:2,25:2,10:0,15:0,20:0,25:0"


def _variants(text: str) -> list[tuple[float, float]]:
    out = []
    for item in text.split(","):
        t, _, k = item.partition(":")
        out.append((float(t), float(k or 2)))
    return out


class Recorder:
    """Wraps ``_Solid.skirt``: every inclined top's pair evaluated under each variant."""

    def __init__(self, variants):
        from planerel.features import relations as rel

        self.rel = rel
        self.variants = variants
        self.orig = rel._Solid.skirt
        self.orig_init = rel._Solid.__init__
        self.rows: dict = {}
        rec = self
        widest = max(t for t, _ in variants)

        def init(solid, planes, cloud, params, profiles=None):
            # every top any variant allows is a candidate (relate asks top_candidate first)
            if params.skirt_top_tilt < widest:
                params = dataclasses.replace(params, skirt_top_tilt=widest)
            rec.orig_init(solid, planes, cloud, params, profiles)

        def skirt(solid, top, face):
            res = rec.orig(solid, top, face)
            if solid.xyz is None or top.orientation != "inclined":
                return res
            key = (top.label, face.label)
            if key in rec.rows:
                return res
            base, steps = solid.params, dict(solid.steps)
            outs, allow = [], []
            try:
                for t, k in rec.variants:
                    solid.params = dataclasses.replace(base, skirt_top_tilt=t, skirt_top_noise=k)
                    solid.steps = {}
                    ok = bool(rec.orig(solid, top, face))
                    # "s": denied only by a step or a riser, which skirts_within_objects
                    # restores when they are another object's
                    outs.append("S" if ok else "s" if key in solid.steps else ".")
                    allow.append(round(solid.top_tilt(top), 1) if top.incline > t else t)
            finally:
                solid.params, solid.steps = base, steps
            if len(set(outs)) > 1:
                up = solid.up
                n = np.asarray(top.normal, float)
                n = n if n @ up >= 0 else -n
                h = n - (n @ up) * up
                c = -np.asarray(top.centroid, float)  # from the top to the sensor at the origin
                c = c - (c @ up) * up
                cam = float(h @ c / (np.linalg.norm(h) * np.linalg.norm(c) + 1e-12))
                rows, cols = np.nonzero(solid.labels == top.label)
                rec.rows[key] = {
                    "top": int(top.label), "face": int(face.label),
                    "incline": round(float(top.incline), 1), "length": round(float(top.length), 3),
                    "width": round(float(top.width), 3), "rms": round(float(top.rms), 4),
                    "noise_deg": round(math.degrees(math.atan(2 * float(top.rms) / float(top.width)))
                                       if top.width > 0 else 0.0, 1),
                    "cam": round(cam, 2), "px": int(rows.size),
                    "bbox": [int(cols.min()), int(rows.min()), int(cols.max()), int(rows.max())]
                    if rows.size else None,
                    "skirt": outs, "allow": allow, "_pix": (rows, cols)}
            return res

        self.patched = skirt
        self.patched_init = init

    def __enter__(self):
        self.rel._Solid.skirt = self.patched
        self.rel._Solid.__init__ = self.patched_init
        return self

    def __exit__(self, *exc):
        self.rel._Solid.skirt = self.orig
        self.rel._Solid.__init__ = self.orig_init

    def take(self) -> list[dict]:
        out = list(self.rows.values())
        self.rows = {}
        return out


def _describe(clf, cloud, name, up=None):
    from planerel.features.facts import describe_scene
    from planerel.ilp.scenes import segment_cached

    labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
    return describe_scene(cloud, labels, scene_id=name, up=up, **clf._describe_kw)


def _majority(truth, pix):
    v = truth[pix]
    v = v[v > 0]
    if not v.size:
        return 0, 0.0
    k = int(np.bincount(v).argmax())
    return k, float((v == k).mean())


def frames_labelled(folder):
    from real_unseen import read_labels, rect_mask

    import planerel

    doc = read_labels(folder)
    for fr in doc["frames"]:
        path = os.path.join(folder, fr["file"])
        cloud = planerel.read(path, intrinsics=fr.get("intrinsics"), depth_scale=fr.get("depth_scale"))
        up = fr.get("up")

        def truth(pix, shape, fr=fr):
            best = ("unlabelled", "")
            for o in fr.get("objects", []):
                m = rect_mask(shape, o["box"])
                if m[pix].mean() >= 0.5:
                    best = (o["class"], o.get("what", "")[:60])
            return best
        yield (f"{os.path.basename(os.path.normpath(folder))}/{fr['file']}", cloud,
               None if up is None else np.asarray(up, float), truth)


def frames_mosd(folder):
    from real_mosd import category

    from planerel.features.object_eval import frame_truth

    for path in sorted(Path(folder).glob("*.pcd")):
        try:
            _, cat, ty = category(path.stem)
        except ValueError:
            continue
        ((name, cloud, tr, _),) = list(frame_truth(path))

        def truth(pix, shape, tr=tr, cat=cat, ty=ty):
            k, share = _majority(tr, pix)
            return (f"{ty or 'object'}" if k else "background", f"{cat} object {k} ({share:.0%})")
        yield f"mosd/{name}", cloud, None, truth


def frames_tabletop(root):
    from real_tabletop import TRUTH, frames, read_frame

    for key, path, intr in frames(os.path.join(root, "osd"), os.path.join(root, "uois")):
        cloud = read_frame(path, intr)

        def truth(pix, shape, key=key):
            rows, cols = pix
            hits = [(kind, name) for x, y, kind, name in TRUTH[key]
                    if rows.size and ((np.abs(cols - x) <= 4) & (np.abs(rows - y) <= 4)).any()]
            return hits[0] if hits else ("unlabelled", "")
        yield key, cloud, None, truth


def frames_independent(folder):
    import planerel

    for p in sorted(Path(folder).glob("i[0-9][0-9][0-9][0-9].npy")):
        side = json.loads(p.with_suffix(".json").read_text())
        tr = np.load(p.with_name(p.stem + ".objects.npy"))
        cloud = planerel.read(str(p))
        kinds = {o["index"]: (o["class"], o["kind"]) for o in side["objects"]}

        def truth(pix, shape, tr=tr, kinds=kinds):
            k, share = _majority(tr, pix)
            if not k:
                return ("background", "")
            c, kind = kinds.get(k, ("?", "?"))
            return (c, f"{kind} {k} ({share:.0%})")
        yield f"{Path(folder).name}/{p.stem}", cloud, None, truth


def frames_dataset(folder):
    """A planerel data set (the training world): each scene described as the learner does
    (:func:`planerel.features.dataset.describe_truth_scene`, its ground-truth objects)."""
    from planerel.features import dataset

    for row in dataset.load_manifest(Path(folder)):
        cloud, gt, meta = dataset.load_scene(folder, row.scene_id)
        tr = dataset.load_object_labels(Path(folder), row.scene_id)
        classes = dataset.object_classes(meta, row.klass)
        kinds = {int(o["index"]): str(o.get("kind", "")) for o in meta.get("objects") or []
                 if isinstance(o, dict) and "index" in o}

        def truth(pix, shape, tr=tr, classes=classes, kinds=kinds):
            if tr is None:
                return ("?", "")
            k, share = _majority(np.asarray(tr), pix)
            if not k:
                return ("background", "")
            return (classes.get(k, "?"), f"{kinds.get(k, '')} {k} ({share:.0%})")

        def describe(clf, cloud=cloud, gt=gt, meta=meta, row=row):
            from planerel.ilp.scenes import segment_cached

            labels = gt if clf.method == "gt" else segment_cached(cloud, method=clf.method,
                                                                  params=clf.seg_params)
            return dataset.describe_truth_scene(cloud, labels, gt, meta, row.scene_id, row.klass)
        yield f"{Path(folder).name}/{row.scene_id}", cloud, describe, truth


def frames_stairs(folder):
    from real_stairs import INTRINSICS

    import planerel

    for depth in sorted(glob.glob(os.path.join(folder, "*_depth.png"))):
        cloud = planerel.read(depth, intrinsics=INTRINSICS, depth_scale=1000)
        yield (f"stairs/{os.path.basename(depth)}", cloud, None,
               lambda pix, shape: ("stairs-frame", ""))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--variants", default=DEFAULT_VARIANTS,
                    help="T:k,... skirt_top_tilt:skirt_top_noise (the first is the base)")
    ap.add_argument("--labelled", nargs="*", default=[])
    ap.add_argument("--mosd")
    ap.add_argument("--tabletop", help="folder holding osd/ and uois/")
    ap.add_argument("--stairs", help="stair-perception folder")
    ap.add_argument("--independent", nargs="*", default=[])
    ap.add_argument("--dataset", nargs="*", default=[],
                    help="planerel data sets described as the learner does (the training world)")
    ap.add_argument("--json", help="append one JSON line per differing pair here")
    a = ap.parse_args(argv)
    from planerel.classify.classifier import Classifier

    variants = _variants(a.variants)
    sources = [frames_labelled(f) for f in a.labelled]
    if a.mosd:
        sources.append(frames_mosd(a.mosd))
    if a.tabletop:
        sources.append(frames_tabletop(a.tabletop))
    if a.stairs:
        sources.append(frames_stairs(a.stairs))
    sources += [frames_independent(f) for f in a.independent]
    sources += [frames_dataset(f) for f in a.dataset]
    names = [f"{t:g}:{k:g}" for t, k in variants]
    print("frame top face | incline len width rms noise_deg cam | truth | skirt under " + " ".join(names))
    out = open(a.json, "a") if a.json else None
    n_frames = 0
    with Classifier(a.model) as clf, Recorder(variants) as rec:
        for src in sources:
            for name, cloud, up, truth in src:
                n_frames += 1
                rec.take()
                desc = up(clf) if callable(up) else _describe(clf, cloud, name, up)
                lab = np.asarray(desc.labels)
                for r in rec.take():
                    pix = r.pop("_pix")
                    cls, what = truth(pix, lab.shape)
                    r.update(frame=name, truth=cls, what=what)
                    flags = "".join(r["skirt"])
                    print(f"{name} p{r['top']} p{r['face']} | {r['incline']:5.1f} "
                          f"{r['length']:.3f} {r['width']:.3f} {r['rms']:.4f} {r['noise_deg']:4.1f} "
                          f"{r['cam']:+.2f} | {cls} {what} | {flags} allow {r['allow']}", flush=True)
                    if out:
                        out.write(json.dumps(r) + "\n")
    if out:
        out.close()
    print(f"{n_frames} frames")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
