"""Every staircase a model does not find, by the stage that loses it (stairs58, docs/objects.md
"Staircases lost, stage by stage").  A measuring tool, the staircase twin of ``real_census.py``.

Usage::

    stairs_census.py DIR [DIR ...] [--model out/model] [--param NAME=VALUE ...] [--json F]

``DIR`` is a labelled real set folder (``labels.json``, :mod:`real_unseen`; a flight is a
rectangle, found when a ``stairs`` answer has half of its pixels in it), a folder of such set
folders, or an independent set (``iNNNN.npy`` with ``.objects.npy`` truth, the sidecar's up;
a flight is its truth mask, found as ``independent_scenes.py score`` finds it: the proposal of
best IoU has IoU >= 0.5 and is answered ``stairs``; flights under the score's ``min_pixels``
are not judged).  A plane is *in* a flight when half of its pixels (and 50 or more) lie in it.
Stages of a flight not found, the first that holds:

``no plane in it``
    no plane lies in the flight (segmentation);
``faces < 2``
    fewer than two treads and fewer than two risers lie in it (``step_tilt`` of level or of
    upright under the scene's up): the steps are not planes, or are merged into one
    (segmentation; or the up, when the flight's faces lie tilted: ``tilt`` tells);
``no stair_step``
    treads or risers lie in it but ``stair_step/2`` holds for no pair of them (the step test:
    rise, run, overlap, plan overlap; :func:`planerel.features.stair_step.stair_steps`);
``no proposal``
    no proposal holds a plane of it;
``merged (C)``
    the proposal holding most of its planes' pixels has less than half of its pixels in the
    flight (the flight with the floor, a wall, a landing); ``C`` its answer;
``split (C)``
    that proposal lies in the flight but holds less than half of the flight's planes'
    pixels (independent sets: its IoU is under 0.5);
``gate refused (G)``, ``other class (C)``, ``no rule fires``
    that proposal is the flight: a stairs rule proved it and the decision refused it (``G``
    the refusals' types), or it was answered ``ramp``/``box``, or no stairs rule proved it
    (``steps_in_proposal``: how many ``stair_step`` pairs the proposal's own planes make).

Each row also tells ``in_planes`` (the share of the flight's pixels in any plane), ``range``
(median distance of its points, m), ``tilt`` (its planes' inclines, degrees, under the scene's
up), ``steps_inside`` (``stair_step`` pairs its planes make) and ``proposals`` (the answers of
every proposal holding one of its planes).
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

STAIRS = "stairs"
MIN_PLANE = 50


def flights_of(dirs) -> list:
    """``[(kind, folder)]``: ``("real", set folder)`` or ``("independent", set)``."""
    from real_census import set_folders

    out = []
    for d in map(Path, dirs):
        if any(d.glob("i[0-9][0-9][0-9][0-9].objects.npy")):
            out.append(("independent", d))
        else:
            out += [("real", f) for f in set_folders([d])]
    return out


def flight_row(clf, desc, answers, mask, found, by_iou=False, desc_xyz=None,
               why=False) -> dict:
    """The stage that loses one flight (``mask``: ``(H, W)`` bool) of a described scene
    (``by_iou``: an independent set's flight, split when its proposal's IoU is under 0.5;
    ``why``: a flight at ``no stair_step`` gets its closest pair's sub-tests,
    :func:`stair_step_why.closest_pair`)."""
    from planerel.features.relations import _step_kind
    from planerel.features.stair_step import stair_steps

    lab = np.asarray(desc.labels)
    pp = clf._describe_kw.get("proposal_params")
    tilt = pp.step_tilt if pp is not None else 12.0
    labs, counts = np.unique(lab[lab >= 0], return_counts=True)
    size = dict(zip(labs.tolist(), counts.tolist(), strict=True))
    inl = Counter(lab[mask][lab[mask] >= 0].tolist())
    inside = [L for L, n in inl.items() if n >= 0.5 * size[L] and size[L] >= MIN_PLANE]
    by_label = {p.label: p for p in desc.planes}
    kinds = Counter(_step_kind(by_label[L], tilt) for L in inside if L in by_label)
    xyz = np.asarray(desc_xyz, float) if desc_xyz is not None else None
    r = {"pixels": int(mask.sum()), "planes": len(inside),
         "in_planes": round(float((lab[mask] >= 0).mean()), 2) if mask.any() else 0.0,
         "treads": kinds["tread"], "risers": kinds["riser"], "tilted": kinds[None],
         "tilt": sorted(round(float(by_label[L].incline), 1) for L in inside if L in by_label),
         "up": desc.planes.up_source}
    if xyz is not None:
        d = np.linalg.norm(xyz[mask], axis=-1)
        d = d[np.isfinite(d) & (d > 0)]
        r["range"] = round(float(np.median(d)), 2) if d.size else None
    steps = stair_steps(desc.planes, inside, pp, by_label) if inside else frozenset()
    r["steps_inside"] = len(steps)
    if found:
        r["stage"] = "found"
        return r
    if not inside:
        r["stage"] = "no plane in it"
        return r
    if kinds["tread"] < 2 and kinds["riser"] < 2:
        r["stage"] = "faces < 2"
        return r
    if not steps:
        r["stage"] = "no stair_step"
        if why:
            from stair_step_why import closest_pair

            from planerel.features.relations import ProposalParams

            r["why"] = closest_pair(desc.planes, inside, pp or ProposalParams())
        return r
    held = sorted(((sum(size[L] for L in inside if L in set(a.labels)), j)
                   for j, a in enumerate(answers)), reverse=True)
    if not held or held[0][0] == 0:
        r["stage"] = "no proposal"
        return r
    a = answers[held[0][1]]
    pm = np.isin(lab, list(a.labels))
    share = float((pm & mask).sum()) / max(1, int(pm.sum()))
    cover = held[0][0] / max(1, sum(size[L] for L in inside))
    iou = float((pm & mask).sum()) / max(1, int((pm | mask).sum()))
    r.update(answer=a.klass, share_inside=round(share, 2), cover=round(cover, 2),
             iou=round(iou, 2), nplanes=len(a.labels),
             refused=sorted({type(x).__name__ for x in a.refused}),
             steps_in_proposal=len(stair_steps(desc.planes, a.labels, pp, by_label)),
             proposals=sorted(b.klass for b in answers if set(b.labels) & set(inside)))
    fired = any(f[0] == STAIRS for f in a.fired)
    if share < 0.5:
        r["stage"] = f"merged ({a.klass})"
    elif cover < 0.5 or (by_iou and iou < 0.5):
        r["stage"] = f"split ({a.klass})"
    elif a.klass not in (STAIRS, "other"):
        r["stage"] = f"other class ({a.klass})"
    elif fired:
        r["stage"] = f"gate refused ({', '.join(r['refused']) or '?'})"
    else:
        r["stage"] = "no rule fires"
    return r


def census(dirs, model: str, params=(), min_pixels=None, why=False, extra=None) -> list:
    """One row per labelled or true staircase of ``dirs`` (``why``: :func:`flight_row`'s;
    ``extra``: a callable ``(clf, cloud, labels, desc, mask) -> dict`` whose items join each
    flight's row, ``labels`` the segmentation's and ``mask`` the flight's ``(H, W)``)."""
    from independent_scenes import default_min_pixels
    from real_unseen import read_frame, read_labels, rect_mask, score_frame

    from planerel.classify.classifier import Classifier
    from planerel.commands.classify import _params
    from planerel.features.facts import describe_scene
    from planerel.features.object_eval import proposal_image, score_objects
    from planerel.ilp.scenes import segment_cached
    from planerel.io import readers as io

    rows = []
    with Classifier(model, seg_params=_params(list(params))) as clf:
        for kind, folder in flights_of(dirs):
            if kind == "real":
                doc = read_labels(str(folder))
                for frame in doc["frames"]:
                    if not any(o["class"] == STAIRS for o in frame.get("objects", [])):
                        continue
                    cloud, up = read_frame(str(folder), frame)
                    labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
                    desc = describe_scene(cloud, labels, scene_id="s", up=up, **clf._describe_kw)
                    answers = clf.answer_description(desc, xyz=cloud.xyz)
                    fake = type("A", (), {"labels": np.asarray(desc.labels), "objects": answers})
                    scored = score_frame(fake(), frame)
                    for o, s in zip(frame["objects"], scored["objects"], strict=True):
                        if o["class"] != STAIRS:
                            continue
                        m = rect_mask(np.asarray(desc.labels).shape, o["box"])
                        r = {"set": f"{folder.parent.name}/{folder.name}",
                             "frame": Path(frame["file"]).stem, "what": o.get("what", "")}
                        r.update(flight_row(clf, desc, answers, m, s["found"], desc_xyz=cloud.xyz,
                                           why=why))
                        if extra is not None:
                            r.update(extra(clf, cloud, labels, desc, m))
                        rows.append(r)
                    print(f"{folder.name}/{frame['file']}", file=sys.stderr, flush=True)
                continue
            mp = default_min_pixels(folder) if min_pixels is None else min_pixels
            for p in sorted(folder.glob("i[0-9][0-9][0-9][0-9].npy")):
                side = json.loads(p.with_suffix(".json").read_text())
                stairs = [o for o in side["objects"] if o["class"] == STAIRS]
                if not stairs:
                    continue
                truth = np.load(p.with_name(p.stem + ".objects.npy"))
                cloud = io.read(p)
                labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
                desc = describe_scene(cloud, labels, scene_id=p.stem, up=None, **clf._describe_kw)
                answers = clf.answer_description(desc, xyz=cloud.xyz)
                prop = proposal_image(np.asarray(desc.labels), [a.labels for a in answers])
                types = {o["index"]: o["class"] for o in side["objects"]}
                sc = score_objects(prop, truth, types=types, min_iou=0.5)
                for o in stairs:
                    k = o["index"]
                    if k not in sc.best_iou or (truth == k).sum() < mp:
                        continue
                    iou = sc.best_iou[k]
                    found = iou >= 0.5 and answers[sc.best_prop[k]].klass == STAIRS
                    r = {"set": folder.name, "frame": p.stem, "what": o["kind"],
                         "kind": "independent", "best_iou": round(float(iou), 3)}
                    r.update(flight_row(clf, desc, answers, truth == k, found, by_iou=True,
                                       desc_xyz=cloud.xyz, why=why))
                    if extra is not None:
                        r.update(extra(clf, cloud, labels, desc, truth == k))
                    rows.append(r)
                print(f"{folder.name}/{p.stem}", file=sys.stderr, flush=True)
    return rows


def census_parser(description: str) -> argparse.ArgumentParser:
    """The census's command line (set folders, model, parameters, ``--min-pixels``,
    ``--json``), shared with ``stair_step_why.py``."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("dirs", nargs="+", metavar="DIR")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--min-pixels", type=int, default=None)
    ap.add_argument("--json")
    return ap


def census_cli(name: str, description: str, argv=None, **kw):
    """The command line of a census tool with ``--aggregate`` (``stair_step_why.py``,
    ``stairfit_why.py``): parse ``argv``, refuse a missing folder, run :func:`census` with
    ``kw``.  Returns ``(args, rows)``, or ``(None, 2)`` after printing a planerel error."""
    from planerel.errors import PlanerelError

    ap = census_parser(description)
    ap.add_argument("--aggregate", action="store_true",
                    help="print only the aggregate lines (no frame names)")
    a = ap.parse_args(argv)
    missing = [d for d in a.dirs if not Path(d).is_dir()]
    if missing:
        ap.error(f"no such folder: {', '.join(missing)}")
    try:
        return a, census(a.dirs, a.model, a.param, a.min_pixels, **kw)
    except PlanerelError as e:
        print(f"{name}: {e}", file=sys.stderr)
        return None, 2


def main(argv=None) -> int:
    a = census_parser(__doc__.split("\n")[0]).parse_args(argv)
    rows = census(a.dirs, a.model, a.param, a.min_pixels)
    for s in dict.fromkeys(r["set"] for r in rows):
        these = [r for r in rows if r["set"] == s]
        print(s, len(these), dict(Counter(r["stage"] for r in these).most_common()))
    print("all", len(rows), dict(Counter(r["stage"] for r in rows).most_common()))
    for r in rows:
        if r["stage"] != "found":
            print(json.dumps(r))
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
