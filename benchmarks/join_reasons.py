"""Why environment planes end in an object's proposal: every join rule's pairs, printed for the
planes of the best-matching proposal that lie mostly off the labelled object.

    nice .venv/bin/python benchmarks/join_reasons.py MODEL SCENE.npy [SCENE.npy ...] \
        [--param proposals.NAME=VALUE ...]

SCENE: an independent-generator scene (``independent_scenes.py make``: ``iNNNN.npy`` with its
``.json`` and ``.objects.npy``).  For each labelled object: the proposal with the best pixel
IoU, its class, and each of its planes (pixels, share on the object, orientation, area, at the
border); for each plane with under half its pixels on the object, the join rules of
:func:`planerel.features.proposals.propose_objects` whose pairs hold it (``convex_pairs``,
``cavity_pairs``, ``group_channel_pairs``, ``step_chain_pairs``, ``flight_sides``, ...).
The rules are wrapped in this process only (walls36, docs/objects.md "A stairwell's walls are
no flight's sides").
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

RULES = ("convex_pairs", "cavity_pairs", "occluded_channel_pairs", "split_panel_pairs",
         "occluded_piece_pairs", "step_chain_pairs", "stacked_board_pairs", "open_tread_pairs",
         "group_channel_pairs")


def _instrument(log: list, calls: list) -> None:
    import planerel.features.facts as F
    import planerel.features.proposals as R

    def wrap(name):
        f = getattr(R, name)

        def g(*a, **k):
            out = f(*a, **k)
            log.append((name, {(int(x[0]), int(x[1])) for x in out}))
            return out
        setattr(R, name, g)
    for n in RULES:
        wrap(n)
    fs = R.flight_side

    def flight_side(face, steps, *a, **k):
        ok = fs(face, steps, *a, **k)
        if ok:
            log.append(("flight_sides", {(face.label, steps[0].label)}))
        return ok
    R.flight_side = flight_side
    prop = R.propose_objects

    def propose(planes, *a, **k):
        log.clear()
        out = prop(planes, *a, **k)
        calls.append((planes, list(log)))
        return out
    R.propose_objects = propose
    F.propose_objects = propose


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("model")
    ap.add_argument("scenes", nargs="+")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    a = ap.parse_args(argv)
    log: list = []
    calls: list = []
    _instrument(log, calls)
    from planerel.classify.classifier import Classifier
    from planerel.commands.classify import _params
    from planerel.io import readers as io

    with Classifier(a.model, seg_params=_params(a.param)) as clf:
        for path in a.scenes:
            p = Path(path)
            side = json.loads(p.with_suffix(".json").read_text())
            truth = np.load(p.with_name(p.stem + ".objects.npy"))
            calls.clear()
            ans = clf.classify(io.read(p), scene_id=p.stem)
            lab = ans.labels
            print(f"== {p}: {side['params'].get('kind')}; answers "
                  + ", ".join(f"{o.klass} {tuple(o.labels)}" for o in ans.objects))
            if not calls or not ans.objects:
                continue
            planes, rules = calls[-1]
            byl = {q.label: q for q in planes}
            for o in side["objects"]:
                m = truth == o["index"]
                if not m.any():
                    continue

                def iou(obj, m=m, lab=lab):
                    pm = np.isin(lab, list(obj.labels))
                    return np.count_nonzero(pm & m) / max(1, np.count_nonzero(pm | m))
                best = max(ans.objects, key=iou)
                print(f"  object {o['index']} {o['class']} ({o['kind']}, {int(m.sum())} px): "
                      f"best proposal {best.klass} IoU {iou(best):.3f}")
                for k in best.labels:
                    pl = lab == k
                    on = np.count_nonzero(pl & m) / max(1, int(pl.sum()))
                    q = byl.get(k)
                    desc = f"{q.orientation} {q.area:.2f} m^2 border {q.touches_border}" if q else "?"
                    print(f"    plane {k}: {int(pl.sum())} px, {on:.2f} on the object, {desc}")
                    if on < 0.5:
                        for name, prs in rules:
                            hits = sorted(pr for pr in prs if k in pr)
                            if hits:
                                print(f"      joined by {name}: {hits}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
