"""Every class answer on a proposal that matches no labelled object of an independent set: the
rule that gave it and what its proof planes lie on.  A measuring tool.

    .venv/bin/python benchmarks/spurious_answers.py DIR [DIR ...] [--model out/model] [--json F]

``DIR`` is a set made by ``benchmarks/independent_scenes.py make`` (``iNNNN.npy`` with its
sidecar and truth images).  Scenes are classified and matched exactly as ``independent_scenes.py
score`` does (a proposal matches an object at IoU >= 0.5; objects under the set's minimum pixel
count are not judged), so the answers listed per set are the ones ``score`` counts on its line
"class answers on proposals matching no object".  An answer on a labelled object under that
size (:func:`independent_scenes.small_matches`: a toy block in a tote) is marked so.  Each is printed with its class, the learned
rule's number (as ``planerel classify --json`` gives it, ``rule_index``: 1 is the model's first rule) and every proof plane's orientation,
pixels and the truth it lies on: the object kind holding most of its pixels (``environment`` for
the floor, walls and landings, label 0) and that share.  The summary counts answers by class and
rule and by what their proof planes lie on.  Sessions 79-81 wrote this as scratch three times to
ask "which rule fires on which wall"; ``--json`` keeps the rows.
"""

from __future__ import annotations

import argparse
import collections
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from independent_scenes import default_min_pixels, judged_matches, small_matches  # noqa: E402


def _label_of(name) -> int | None:
    """The plane label of a proof plane's name (``i0006_p03`` -> 3)."""
    if isinstance(name, (int, np.integer)):
        return int(name)
    head, sep, tail = str(name).rpartition("_p")
    return int(tail) if sep and tail.isdigit() else None


def lies_on(mask, truth, kinds: dict) -> tuple[str, float]:
    """What a plane's pixels ``mask`` lie on: ``(kind, share)``, the truth label holding most of
    them (``environment`` for 0, ``missing`` for -1, else the object's kind)."""
    vals, counts = np.unique(truth[mask], return_counts=True)
    if not len(vals):
        return "none", 0.0
    k = int(vals[np.argmax(counts)])
    kind = "environment" if k == 0 else "missing" if k < 0 else kinds.get(k, f"object {k}")
    return kind, float(counts.max() / counts.sum())


def set_rows(clf, out, min_iou: float = 0.5, min_pixels: int | None = None) -> list[dict]:
    """The answers on unmatched proposals of one set (one dict a answer)."""
    from planerel.io import readers as io

    out = Path(out)
    min_pixels = default_min_pixels(out) if min_pixels is None else min_pixels
    rows = []
    for p in sorted(out.glob("i[0-9][0-9][0-9][0-9].npy")):
        side = json.loads(p.with_suffix(".json").read_text())
        truth = np.load(p.with_name(p.stem + ".objects.npy"))
        ans = clf.classify(io.read(p), scene_id=p.stem)
        kinds = {o["index"]: o["kind"] for o in side["objects"]}
        # the objects score judges and the proposals matching them, as score_set's
        sc, _judged, matched = judged_matches(ans, side, truth, min_iou, min_pixels)
        tiny = small_matches(sc, side, truth, min_iou, min_pixels)
        lab = np.asarray(ans.labels)
        for j, o in enumerate(ans.objects):
            if j in matched or o.klass == "other":
                continue
            planes = []
            for name in o.proof_planes or o.planes:
                label = _label_of(name)
                m = lab == label if label is not None else np.zeros(lab.shape, bool)
                kind, share = lies_on(m, truth, kinds)
                planes.append({"plane": str(name), "pixels": int(m.sum()), "lies_on": kind,
                               "share": round(share, 3)})
            rows.append({"set": out.name, "scene": p.stem, "object": j + 1, "class": o.klass,
                         "rule": o.rule_index, "on_small": tiny.get(j),
                         "proof_planes": planes})
    return rows


def summary(rows: list[dict]) -> dict:
    """Counts by ``(class, rule)`` and by what the proof planes lie on (the kinds holding most
    of an answer's proof pixels)."""
    by_rule = collections.Counter(f"{r['class']} rule {r['rule']}" for r in rows)
    by_truth = collections.Counter()
    for r in rows:
        px = collections.Counter()
        for q in r["proof_planes"]:
            px[q["lies_on"]] += q["pixels"]
        by_truth[f"{r['class']} on {px.most_common(1)[0][0] if px else 'none'}"] += 1
    return {"answers": len(rows),
            "on_small": sum(r.get("on_small") is not None for r in rows),
            "on_small_right": sum(r.get("on_small") == r["class"] for r in rows),
            "by_rule": dict(by_rule.most_common()),
            "by_truth": dict(by_truth.most_common())}


def main(argv=None) -> int:
    from planerel.classify.classifier import Classifier

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    rows = []
    with Classifier(a.model) as clf:
        for d in a.dirs:
            these = set_rows(clf, d)
            rows += these
            for r in these:
                planes = " ".join(f"{q['plane']} {q['pixels']} px on {q['lies_on']} ({q['share']:.2f})"
                                  for q in r["proof_planes"])
                small = (f" (on a labelled {r['on_small']} too small to judge)"
                         if r.get("on_small") else "")
                print(f"{r['set']} {r['scene']} o{r['object']}: {r['class']} by rule {r['rule']}"
                      f"{small}: {planes}")
            print(f"{Path(d).name}: {len(these)} class answers on proposals matching no object")
    s = summary(rows)
    print(f"all: {s['answers']} answers ({s['on_small']} on labelled objects too small to judge, "
          f"{s['on_small_right']} of them of their class); by rule {s['by_rule']}; "
          f"by what they lie on {s['by_truth']}")
    if a.json:
        Path(a.json).write_text(json.dumps({"rows": rows, "summary": s}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
