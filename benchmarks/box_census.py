"""Every box of an independent set that a model does not answer ``box``, by the stage that
loses it (ibox48, docs/objects.md "Boxes the independent scenes miss").  A measuring tool.

Usage::

    box_census.py MODEL SETDIR [SETDIR ...] [--json F] [--tall] [--only i0001,i0002]

Each ``SETDIR`` is a set of :mod:`independent_scenes` (``iNNNN.npy`` with its sidecar and truth
image); a box is judged as ``independent_scenes.py score`` judges it (at least the set's
``--min-pixels``, matched by a proposal with IoU >= 0.5).  The model's segmentation and
description are those :class:`planerel.classify.classifier.Classifier` makes.  Stages:

``found``
    matched, answered ``box``;
``no plane on it``
    fewer than half of its pixels in any plane;
``one plane with a neighbour (K)``
    half or more of its pixels in planes, but every such plane lies mostly outside it (a flush
    front grown across two boxes, a face grown into the floor or a wall): ``K`` the largest
    other owner of those planes' pixels (``box``, ``floor``, ``wall/env`` or another kind);
``no proposal``
    planes on it, but no proposal holds 10 % of its pixels (dropped as a wall or a skin);
``merged (K)``
    the proposal holding most of it covers 35 % or more of it, and less than half of that
    proposal is in it: ``K`` the largest other owner of the proposal's pixels;
``split``
    two or more proposals hold 15 % or more of it each;
``partial``
    the rest (one proposal holds part of it, the other part in no plane);
``other class (C)``, ``gate refused``, ``no rule fires``
    matched, answered ``stairs`` or ``ramp``; a box rule fired and a decision gate refused
    it; no box rule fired.  For these the line gives what the proposal shows (``h``, ``v``,
    ``i`` planes) and its ``skirt``, ``tall_face``, ``face_pair``, ``lying`` facts.

With ``--tall``, each vertical plane of a ``no rule fires`` box is put through
:func:`planerel.features.tall_face.tall_faces`' tests one by one and the ones it fails are
listed: ``shape:w`` (narrower than ``corner_width``), ``shape:f`` (fills less than
``standing_fill`` of its rectangle), ``shape:r`` (RMS over ``tall_flat`` of its width),
``top-in-view`` (top edge below ``tall_eye`` and no cap strip), ``not-grounded`` (no adjacent
ground, no floor foot), ``beside-taller`` (an adjacent upright plane rises over its top and
is no solid standing beside it).
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from collections import Counter, defaultdict
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def _facts(text):
    out = defaultdict(list)
    for line in text.splitlines():
        m = re.match(r"(\w+)\((.*)\)\.$", line.strip())
        if m:
            out[m.group(1)].append(tuple(a.strip() for a in m.group(2).split(",")))
    return out


def _owners(lab_sel, truth, kinds, orientation):
    """``Counter`` of the truth owners of the pixels ``lab_sel`` (a list of (label, mask))."""
    who = Counter()
    for L, sel in lab_sel:
        for tk, c in Counter(truth[sel].tolist()).items():
            if tk > 0:
                who[kinds.get(tk, "?")] += c
            elif tk == 0:
                who["floor" if orientation.get(L) == "horizontal" else "wall/env"] += c
    return who


def _group(kind):
    return "box" if "box" in kind else kind


def tall_tests(desc, cloud, plane):
    """The :func:`~planerel.features.tall_face.tall_faces` tests ``plane`` fails (a list of
    the names of the module docstring)."""
    from planerel.features import relations as R
    from planerel.features.solid import face_profile_of, grounded

    ps, rel = desc.planes, desc.relations
    p = rel.params
    lab = np.asarray(ps.labels)
    up = np.asarray(ps.up, float)
    by = {q.label: q for q in ps}
    floor = by.get(getattr(ps, "floor", None))
    if floor is not None and floor.orientation != "horizontal":
        floor = None
    q = plane
    prof = face_profile_of(q, up, lab, cloud.xyz, p.profile_points)
    fails = []
    shape = "".join(c for c, ok in (("w", q.width >= p.corner_width),
                                    ("f", q.area >= p.standing_fill * q.length * q.width),
                                    ("r", q.rms <= p.tall_flat * q.width)) if not ok)
    if shape:
        fails.append("shape:" + shape)
    near, beside = [], []
    for r in R.adjacent_only(rel):
        if r.adjacent and r.a == q.label and r.b in by:
            b = by[r.b]
            if b.orientation == "horizontal":
                near.append(b)
            elif b.orientation == "vertical":
                beside.append(b)
    hidden = prof.top >= -p.tall_eye or R._reaches_top_row(q)
    if not hidden:
        share, depth = R.cap_strip(q, lab, cloud.xyz, up, prof.top, p.tall_cap_tol)
        if p.tall_cap <= 0 or share < p.tall_cap or not depth >= min(
                p.tall_cap_depth, p.tall_cap_ratio * (prof.hi - prof.lo)):
            fails.append("top-in-view")
    if not any(grounded(q, prof, g, up, p.standing_foot, p.skirt_tol, p.skirt_step) for g in near) \
            and not (floor is not None and p.tall_floor_fit > 0
                     and R.floor_foot(q, prof, floor, lab, cloud.xyz, up, p)):
        fails.append("not-grounded" + ("" if floor is not None else " (no floor plane)"))

    def profile(x):
        return face_profile_of(x, up, lab, cloud.xyz, p.profile_points)

    if any(profile(b).top > prof.top + p.skirt_tol
           and not R._stands_beside(q, prof, b, profile(b), lab, cloud.xyz, p) for b in beside):
        fails.append("beside-taller")
    return fails


def census(model, sets, only=None, tall=False):
    """One row (dict) per judged box of the sets."""
    from independent_scenes import default_min_pixels

    import planerel
    from planerel.classify.classifier import Classifier
    from planerel.features.facts import FactParams, describe_scene, facts_text
    from planerel.features.object_eval import proposal_image, score_objects
    from planerel.ilp.aleph_export import PAIRS
    from planerel.ilp.scenes import segment_cached

    rows = []
    with Classifier(model) as clf:
        for sd in map(Path, sets):
            minpx = default_min_pixels(sd)
            for path in sorted(sd.glob("i[0-9][0-9][0-9][0-9].npy")):
                if only and path.stem not in only:
                    continue
                side = json.loads(path.with_suffix(".json").read_text())
                truth = np.load(path.with_name(path.stem + ".objects.npy"))
                cloud = planerel.read(path)
                labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
                desc = describe_scene(cloud, labels, scene_id="s", **clf._describe_kw)
                ans = clf.answer_description(desc, xyz=cloud.xyz)
                lab = np.asarray(desc.labels)
                prop = proposal_image(lab, [o.labels for o in ans])
                types = {o["index"]: o["class"] for o in side["objects"]}
                kinds = {o["index"]: o["kind"] for o in side["objects"]}
                sc = score_objects(prop, truth, types=types, min_iou=0.5)
                ori = {q.label: q.orientation for q in desc.planes}
                by = {q.label: q for q in desc.planes}
                F = None
                for o in side["objects"]:
                    k = o["index"]
                    m = truth == k
                    if o["class"] != "box" or k not in sc.best_iou or m.sum() < minpx:
                        continue
                    iou = float(sc.best_iou[k])
                    r = {"set": sd.name, "scene": path.stem, "object": k, "kind": o["kind"],
                         "px": int(m.sum()), "iou": round(iou, 3)}
                    rows.append(r)
                    a = ans[sc.best_prop[k]] if iou >= 0.5 else None
                    r["pred"] = a.klass if a is not None else "none"
                    if r["pred"] == "box":
                        r["stage"] = "found"
                        continue
                    if a is not None:
                        if F is None:
                            F = _facts(facts_text([desc], FactParams(pairs=PAIRS, planner=False)))
                        pl = set(a.planes)
                        r["shows"] = "".join(sorted(ori[L][0] for L in a.labels if L in ori))
                        for name in ("skirt", "face_pair"):
                            r[name] = [list(x) for x in F[name] if x[0] in pl]
                        for name in ("tall_face", "lying"):
                            r[name] = [x[0] for x in F[name] if x[0] in pl]
                        r["refused"] = [type(x).__name__ for x in a.refused]
                        r["fired"] = [list(f) for f in a.fired]
                        if a.klass in ("stairs", "ramp"):
                            r["stage"] = f"other class ({a.klass})"
                        elif any(f[0] == "box" for f in a.fired):
                            r["stage"] = "gate refused"
                        else:
                            r["stage"] = "no rule fires"
                            if tall:
                                r["tall_tests"] = {desc.plane_id(L): tall_tests(desc, cloud, by[L])
                                                   for L in a.labels
                                                   if L in by and ori[L] == "vertical"}
                        continue
                    on = [L for L in np.unique(lab[m])
                          if L >= 0 and ((lab == L) & m).sum() >= 0.5 * (lab == L).sum()]
                    if not on and float((lab[m] >= 0).mean()) < 0.5:
                        r["stage"] = "no plane on it"
                        continue
                    if not on:
                        who = _owners([(L, (lab == L) & ~m) for L in np.unique(lab[m]) if L >= 0],
                                      truth, kinds, ori)
                        r["plane_shared_with"] = dict(who.most_common(3))
                        top = who.most_common(1)[0][0] if who else "?"
                        r["stage"] = f"one plane with a neighbour ({_group(top)})"
                        continue
                    inter = sorted(((int((np.isin(lab, list(b.labels)) & m).sum()), j)
                                    for j, b in enumerate(ans)), reverse=True)
                    inter = [t for t in inter if t[0] > 0]
                    if not inter or inter[0][0] < 0.1 * m.sum():
                        r["stage"] = "no proposal"
                        r["planes"] = [desc.plane_id(L) for L in on]
                        continue
                    n, j = inter[0]
                    pm = np.isin(lab, list(ans[j].labels))
                    cov, prec = n / m.sum(), n / pm.sum()
                    if prec < 0.5 and cov >= 0.35:
                        extra = pm & ~m
                        who = _owners([(L, extra & (lab == L)) for L in np.unique(lab[extra])],
                                      truth, kinds, ori)
                        r["merged_with"] = dict(who.most_common(3))
                        top = who.most_common(1)[0][0] if who else "?"
                        r["stage"] = f"merged ({_group(top)})"
                    elif sum(1 for n_, _ in inter if n_ >= 0.15 * m.sum()) >= 2:
                        r["stage"] = "split"
                    else:
                        r["stage"] = "partial"
                print(path.stem, file=sys.stderr, flush=True)
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("model")
    ap.add_argument("sets", nargs="+")
    ap.add_argument("--json")
    ap.add_argument("--tall", action="store_true")
    ap.add_argument("--only", default=None)
    a = ap.parse_args(argv)
    rows = census(a.model, a.sets, set(a.only.split(",")) if a.only else None, a.tall)
    for sd in dict.fromkeys(r["set"] for r in rows):
        these = [r for r in rows if r["set"] == sd]
        print(sd, len(these), dict(Counter(r["stage"] for r in these).most_common()))
    print("all", len(rows), dict(Counter(r["stage"] for r in rows).most_common()))
    nr = [r for r in rows if r["stage"] == "no rule fires"]
    if nr:
        print("no rule fires, by what the proposal shows:",
              dict(Counter(r["shows"] for r in nr).most_common()))
    if a.tall and nr:
        best = Counter()
        for r in nr:
            tests = r.get("tall_tests") or {}
            if tests:
                f = min(tests.values(), key=len)
                best["+".join(f)] += 1
        print("no rule fires, tall_face's tests failed by the object's best vertical plane:",
              dict(best.most_common()))
    for r in rows:
        if r["stage"] != "found":
            print(json.dumps(r))
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
