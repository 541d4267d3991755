"""How right a ``stairs`` answer's flight measures and a ``ramp`` answer's slope are
(``ObjectAnswer.measures``, planerel.features.object_measures; docs/results.md "A flight's and a
slope's measures").  A measuring tool: it prints figures, it asserts nothing.

Usage::

    flight_measures.py SET [SET ...] [--model out/model] [--json F]

``SET`` is an ``independent_scenes.py`` set (``/work/dev/dev_st``: each scene's JSON names the
flight's ``rise``, ``run`` and whether it goes down away from the camera, ``descending``, or the
ramp's ``angle_deg``).  Every flight or ramp the model answers rightly (the set's own rule: the
best proposal's IoU with the object at least 0.5, and its class) is compared with the truth:

- flights: the absolute error of the measured rise and run (metres), the share whose
  ``going`` is right (``down`` for a descending flight, ``up`` otherwise; ``across`` is
  wrong either way);
- ramps: the absolute error of the measured slope (degrees).

Printed per set: how many were measured (and how many right answers had no measures), the
median and 90th percentile of each error, and the share going the right way.

``--real DIR ...``: labelled real folders (``real_unseen.py``'s ``labels.json``, or a folder of
them): every ``stairs`` or ``ramp`` answer with half of its pixels in a rectangle of its class
is listed with its measures and the rectangle's description.  Real frames carry no measured
truth, so these are for reading against the description (a lab's model staircase, a house's
flight).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def measure_set(folder, clf, min_iou: float = 0.5) -> list:
    """One row per rightly answered flight or ramp of the set ``folder``: ``{scene, class,
    kind, truth, measures}`` (``measures`` None when the answer carries none)."""
    from independent_scenes import default_min_pixels

    from planerel.features.object_eval import proposal_image, score_objects
    from planerel.io import readers as io

    folder = Path(folder)
    min_pixels = default_min_pixels(folder)
    rows = []
    for p in sorted(folder.glob("i[0-9][0-9][0-9][0-9].npy")):
        side = json.loads(p.with_suffix(".json").read_text())
        kinds = {o["index"]: (o["class"], o["kind"]) for o in side["objects"]}
        if not any(c in ("stairs", "ramp") for c, _k in kinds.values()):
            continue
        truth = np.load(p.with_name(p.stem + ".objects.npy"))
        ans = clf.classify(io.read(p), scene_id=p.stem)
        prop = proposal_image(ans.labels, [o.labels for o in ans.objects])
        sc = score_objects(prop, truth, types={k: c for k, (c, _) in kinds.items()},
                           min_iou=min_iou)
        for k, (cls, kind) in kinds.items():
            if cls not in ("stairs", "ramp") or k not in sc.best_iou:
                continue
            if (truth == k).sum() < min_pixels or sc.best_iou[k] < min_iou:
                continue
            a = ans.objects[sc.best_prop[k]]
            if a.klass != cls:
                continue
            prm = side.get("params", {})
            truth_of = ({"rise": prm.get("rise"), "run": prm.get("run"),
                         "descending": bool(prm.get("descending"))} if cls == "stairs"
                        else {"angle_deg": prm.get("angle_deg")})
            rows.append({"scene": p.stem, "class": cls, "kind": kind, "truth": truth_of,
                         "measures": a.measures})
    return rows


def real_rows(folder, clf) -> list:
    """``(set, frame, class, rectangle's description, measures)`` of every rightly answered
    ``stairs`` or ``ramp`` of the labelled real folder ``folder`` (``real_unseen.py``'s rule:
    half of the answer's pixels in a rectangle of its class)."""
    from real_unseen import read_frame, read_labels, rect_mask

    doc = read_labels(folder)
    out = []
    for fr in doc["frames"]:
        cloud, up = read_frame(folder, fr)
        ans = clf.classify(cloud, scene_id="s", up=up, camera_height=fr.get("camera_height"))
        lab = np.asarray(ans.labels)
        for o in ans.objects:
            if o.klass not in ("stairs", "ramp"):
                continue
            pix = np.isin(lab, list(o.labels))
            for r in fr["objects"]:
                if r["class"] == o.klass and (pix & rect_mask(lab.shape, r["box"])).sum() \
                        >= 0.5 * pix.sum():
                    out.append((Path(folder).name, fr["file"], o.klass, r.get("what", ""),
                                o.measures))
                    break
    return out


def summary(rows) -> dict:
    """Errors and shares over ``rows`` (:func:`measure_set`)."""
    out = {}
    fl = [r for r in rows if r["class"] == "stairs"]
    fm = [r for r in fl if r["measures"]]
    if fl:
        rise = np.array([abs(r["measures"]["rise_m"] - r["truth"]["rise"]) for r in fm])
        run = np.array([abs(r["measures"]["run_m"] - r["truth"]["run"]) for r in fm
                        if r["measures"]["run_m"] is not None])
        way = [r["measures"]["going"] == ("down" if r["truth"]["descending"] else "up")
               for r in fm]
        out["stairs"] = {"answered": len(fl), "measured": len(fm),
                         "rise_err_median": _q(rise, 50), "rise_err_p90": _q(rise, 90),
                         "run_err_median": _q(run, 50), "run_err_p90": _q(run, 90),
                         "going_right": int(sum(way))}
    rl = [r for r in rows if r["class"] == "ramp"]
    rm = [r for r in rl if r["measures"]]
    if rl:
        err = np.array([abs(r["measures"]["slope_deg"] - r["truth"]["angle_deg"]) for r in rm])
        out["ramp"] = {"answered": len(rl), "measured": len(rm),
                       "slope_err_median": _q(err, 50), "slope_err_p90": _q(err, 90)}
    return out


def _q(a, q):
    return None if len(a) == 0 else round(float(np.percentile(a, q)), 3)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("sets", nargs="*")
    ap.add_argument("--real", nargs="+", default=[], metavar="DIR")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    from planerel.classify.classifier import Classifier

    everything = {}
    with Classifier(a.model) as clf:
        for s in a.sets:
            rows = measure_set(s, clf)
            sm = summary(rows)
            everything[s] = {"summary": sm, "rows": rows}
            st, rp = sm.get("stairs"), sm.get("ramp")
            if st:
                print(f"{s}: flights {st['measured']}/{st['answered']} measured; rise error "
                      f"median {st['rise_err_median']} m (90 % {st['rise_err_p90']}), run error "
                      f"median {st['run_err_median']} m (90 % {st['run_err_p90']}); going right "
                      f"{st['going_right']}/{st['measured']}")
            if rp:
                print(f"{s}: ramps {rp['measured']}/{rp['answered']} measured; slope error "
                      f"median {rp['slope_err_median']} degrees (90 % {rp['slope_err_p90']})")
        for d in a.real:
            d = Path(d)
            folders = [d] if (d / "labels.json").exists() else sorted(
                x for x in d.iterdir() if (x / "labels.json").exists())
            for folder in folders:
                for name, frame, klass, what, m in real_rows(folder, clf):
                    print(f"{name}/{frame}: {klass} {json.dumps(m)} | {what}")
    if a.json:
        Path(a.json).write_text(json.dumps(everything, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
