"""How slender the tops of box proofs are: true boxes, thin walls and slabs (slab36).

    .venv/bin/python benchmarks/slender_proofs.py MODEL [--independent DIR ...]
        [--labelled DIR ...] [--scans FILE ...] [--over 3.5]

Every ``box`` answer of ``MODEL`` with the slenderness gate off (``decision.slender_gate=false``,
so that what the gate would refuse is seen), and the slenderness of its proof's top:
``plane_length / plane_width`` of each horizontal or inclined plane the chosen proof binds
(:func:`planerel.ilp.metrics.plane_slenderness`), the largest; ``-`` for a proof of faces only
(``tall_face``, ``corner``).  On sets of the independent generator (``--independent``, made
by ``independent_scenes.py make``) each answer is a true box (the proposal matched to a
labelled box at IoU >= 0.5) or false; on real frames (``--labelled``: folders with a
``labels.json`` as ``real_unseen.py`` reads; ``--scans``: files ``planerel.read`` reads) every
box answer is listed with its value over ``--over``.  The model's training domain
(``model.json``, ``slender_domain``) and the gate's bound are printed first.
docs/objects.md, "Thin walls and slabs are no boxes".
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent


def _answer(clf, cloud, scene_id, up=None):
    """``(desc, answers)`` of one scan, as ``Classifier.classify`` makes them."""
    from planerel.features.facts import describe_scene
    from planerel.ilp.scenes import segment_cached

    labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
    desc = describe_scene(cloud, labels, scene_id=scene_id, up=up,
                          **clf._describe_kw)
    return desc, clf.answer_description(desc, xyz=cloud.xyz)


def _top(desc, answer):
    """The slenderness of the answer's proof's most slender top, or None (faces only)."""
    from planerel.ilp.metrics import plane_slenderness, proof_slenderness

    return proof_slenderness(answer.bindings, plane_slenderness([desc]))


def independent(clf, folder):
    """``[(slenderness or None, true box?, scene, object id, rule)]`` of the box answers."""
    from planerel.features.object_eval import proposal_image, score_objects
    from planerel.io import readers as io

    sys.path.insert(0, str(HERE))
    from independent_scenes import default_min_pixels

    folder = Path(folder)
    min_pixels = default_min_pixels(folder)
    rows = []
    for p in sorted(folder.glob("i[0-9][0-9][0-9][0-9].npy")):
        side = json.loads(p.with_suffix(".json").read_text())
        truth = np.load(p.with_name(p.stem + ".objects.npy"))
        desc, answers = _answer(clf, io.read(p), p.stem)
        prop = proposal_image(desc.labels, [a.labels for a in answers])
        types = {o["index"]: o["class"] for o in side["objects"]}
        sc = score_objects(prop, truth, types=types, min_iou=0.5)
        boxes = {sc.best_prop[o["index"]] for o in side["objects"]
                 if o["class"] == "box" and sc.best_iou.get(o["index"], 0) >= 0.5
                 and (truth == o["index"]).sum() >= min_pixels}
        for j, a in enumerate(answers):
            if a.klass == "box":
                rows.append((_top(desc, a), j in boxes, p.stem, a.object_id, a.rule_index))
    return rows


def real(clf, frames):
    """``[(slenderness or None, frame, object id, rule)]`` of the box answers on ``frames``
    (``(path, read keywords, up)``)."""
    import planerel

    rows = []
    for path, kw, up in frames:
        desc, answers = _answer(clf, planerel.read(path, **kw), "s", up)
        rows += [(_top(desc, a), str(path), a.object_id, a.rule_index)
                 for a in answers if a.klass == "box"]
    return rows


def _labelled_frames(folder):
    doc = json.loads((Path(folder) / "labels.json").read_text())
    for f in doc["frames"]:
        kw = {k: f[k] for k in ("intrinsics", "depth_scale") if f.get(k) is not None}
        up = None if f.get("up") is None else np.asarray(f["up"], float)
        yield Path(folder) / f["file"], kw, up


def _fmt(v):
    return "-" if v is None else f"{v:.2f}"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("model")
    ap.add_argument("--independent", nargs="*", default=[], metavar="DIR")
    ap.add_argument("--labelled", nargs="*", default=[], metavar="DIR")
    ap.add_argument("--scans", nargs="*", default=[], metavar="FILE")
    ap.add_argument("--over", type=float, default=3.5,
                    help="list the real box answers whose top is more slender than this")
    a = ap.parse_args(argv)
    from planerel.classify.classifier import Classifier
    from planerel.ilp.model_settings import read_settings

    settings = read_settings(Path(a.model) / "rules.pl")
    dec = settings.decision_params()
    for k, hi, n in settings.slender_domain:
        gated = k in {c.strip() for c in dec.slender_classes.split(",")}
        print(f"training domain: {k} tops at most {hi:g} times as long as wide ({n} positives)"
              + (f"; refused over {hi * (1 + dec.slender_margin):.2f}" if gated else ""))
    with Classifier(a.model, seg_params={"decision.slender_gate": "false"}) as clf:
        for d in a.independent:
            rows = independent(clf, d)
            for ok in (True, False):
                vals = sorted((r for r in rows if r[1] == ok),
                              key=lambda r: -1 if r[0] is None else r[0])
                tops = [r[0] for r in vals if r[0] is not None]
                print(f"{Path(d).name}: {'true' if ok else 'false'} box answers {len(vals)}, "
                      f"{len(tops)} proved with a top, the most slender "
                      f"{_fmt(max(tops, default=None))}")
                if not ok:
                    for r in vals:
                        print(f"   {r[2]} {r[3]} rule {r[4]}: top {_fmt(r[0])}")
        frames = [f for d in a.labelled for f in _labelled_frames(d)]
        frames += [(Path(f), {}, None) for f in a.scans]
        if frames:
            rows = real(clf, frames)
            tops = sorted((r for r in rows if r[0] is not None), key=lambda r: r[0])
            print(f"real frames: {len(frames)}, box answers {len(rows)}, {len(tops)} proved with "
                  f"a top, the most slender {_fmt(tops[-1][0] if tops else None)}")
            for r in tops:
                if r[0] > a.over:
                    print(f"   {r[1]} {r[2]} rule {r[3]}: top {_fmt(r[0])}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
