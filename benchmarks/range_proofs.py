"""How far from the sensor the proofs of class answers lie: true answers and false ones (range40).

    .venv/bin/python benchmarks/range_proofs.py MODEL [--independent DIR ...]
        [--labelled DIR ...] [--scans FILE ...] [--stairs DIR] [--over 4.0]

Every class answer of ``MODEL`` with the range gate off (``decision.range_gate=false``, so that
what the gate would refuse is seen), and its proof's range: the farthest centroid distance from
the sensor among the planes the chosen proof binds (:func:`planerel.ilp.metrics.plane_ranges`,
the ``distance/2`` fact).  On sets of the independent generator (``--independent``) each
answer is true (the proposal matched at IoU >= 0.5 to a labelled object of the class) or false;
on real frames (``--labelled``: folders with a ``labels.json`` as ``real_unseen.py`` reads;
``--scans``: files ``planerel.read`` reads; ``--stairs``: stair-perception's ``*_depth.png``
with real_stairs.py's intrinsics) every answer over ``--over`` metres is listed.  The model's
training domain (``model.json``, ``range_domain``) and the gate's bound per class are printed
first.  docs/results.md, "Proofs farther away than any training proof".
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from slender_proofs import _answer, _labelled_frames  # noqa: E402

CLASSES = ("box", "stairs", "ramp")


def _range(desc, answer):
    from planerel.ilp.metrics import plane_ranges, proof_range

    return proof_range(answer.bindings, plane_ranges([desc]))


def independent(clf, folder):
    """``[(range or None, class, true?, scene, object id, rule)]`` of the class answers."""
    import json

    import numpy as np
    from independent_scenes import default_min_pixels

    from planerel.features.object_eval import proposal_image, score_objects
    from planerel.io import readers as io

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
        true = {(o["class"], sc.best_prop[o["index"]]) for o in side["objects"]
                if sc.best_iou.get(o["index"], 0) >= 0.5
                and (truth == o["index"]).sum() >= min_pixels}
        for j, a in enumerate(answers):
            if a.klass in CLASSES:
                rows.append((_range(desc, a), a.klass, (a.klass, j) in true, p.stem,
                             a.object_id, a.rule_index))
    return rows


def real(clf, frames):
    """``[(range or None, class, frame, object id, rule)]`` of the class answers on ``frames``
    (``(path, read keywords, up)``)."""
    import planerel

    rows = []
    for path, kw, up in frames:
        desc, answers = _answer(clf, planerel.read(path, **kw), "s", up)
        rows += [(_range(desc, a), a.klass, str(path), a.object_id, a.rule_index)
                 for a in answers if a.klass in CLASSES]
    return rows


def _fmt(v):
    return "-" if v is None else f"{v:.2f}"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("model")
    ap.add_argument("--independent", nargs="*", default=[], metavar="DIR")
    ap.add_argument("--labelled", nargs="*", default=[], metavar="DIR")
    ap.add_argument("--scans", nargs="*", default=[], metavar="FILE")
    ap.add_argument("--stairs", default=None, metavar="DIR",
                    help="stair-perception's samples (its *_depth.png)")
    ap.add_argument("--over", type=float, default=4.0,
                    help="list the real class answers whose proof lies farther than this (m)")
    a = ap.parse_args(argv)
    from real_stairs import INTRINSICS

    from planerel.classify.classifier import Classifier
    from planerel.ilp.model_settings import read_settings

    settings = read_settings(Path(a.model) / "rules.pl")
    dec = settings.decision_params()
    gated = {c.strip() for c in dec.range_classes.split(",")}
    for k, hi, n in settings.range_domain:
        print(f"training domain: {k} proofs' planes at most {hi:g} m away ({n} positives); "
              f"bound {hi * (1 + dec.range_margin):.2f} m"
              + (" (gated)" if k in gated else " (not gated)"))
    with Classifier(a.model, seg_params={"decision.range_gate": "false"}) as clf:
        for d in a.independent:
            rows = independent(clf, d)
            for k in CLASSES:
                for ok in (True, False):
                    vals = sorted((r for r in rows if r[1] == k and r[2] == ok),
                                  key=lambda r: -1 if r[0] is None else r[0])
                    if not vals:
                        continue
                    far = [r[0] for r in vals if r[0] is not None]
                    print(f"{Path(d).name}: {'true' if ok else 'false'} {k} answers "
                          f"{len(vals)}, proofs {_fmt(min(far, default=None))}-"
                          f"{_fmt(max(far, default=None))} m")
                    if not ok:
                        for r in vals:
                            if r[0] is not None and r[0] > a.over:
                                print(f"   {r[3]} {r[4]} rule {r[5]}: {_fmt(r[0])} m")
        frames = [f for d in a.labelled for f in _labelled_frames(d)]
        frames += [(Path(f), {}, None) for f in a.scans]
        if a.stairs:
            frames += [(p, {"intrinsics": INTRINSICS, "depth_scale": 1000}, None)
                       for p in sorted(Path(a.stairs).glob("*_depth.png"))]
        if frames:
            rows = real(clf, frames)
            for k in CLASSES:
                far = sorted((r for r in rows if r[1] == k and r[0] is not None),
                             key=lambda r: r[0])
                print(f"real frames: {len(frames)}, {k} answers "
                      f"{sum(r[1] == k for r in rows)}, proofs {_fmt(far[0][0] if far else None)}"
                      f"-{_fmt(far[-1][0] if far else None)} m")
                for r in far:
                    if r[0] > a.over:
                        print(f"   {r[2]} {r[3]} rule {r[4]}: {_fmt(r[0])} m")
    return 0


if __name__ == "__main__":
    sys.exit(main())
