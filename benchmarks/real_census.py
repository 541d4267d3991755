"""Every labelled box of real frames that a model does not find, by the stage that loses it
(core49, docs/objects.md "Boxes lost inside a merged proposal").  A measuring tool.

Usage::

    real_census.py DIR [DIR ...] [--model out/model] [--param NAME=VALUE ...] [--json F]

``DIR`` is a set folder holding ``labels.json`` (:mod:`real_unseen`) or a folder of such set
folders (``/work/hunt48``).  Frames are read, classified and scored as ``real_unseen.py`` does
(an answer is right when half of its pixels lie in a rectangle of its class); the census is
:mod:`box_census`'s, with rectangles instead of object masks.  A plane is *in* a rectangle when
half of its pixels lie in it.  Stages of a box not found:

``no plane in it``
    no plane of 100 pixels or more lies in the rectangle;
``no proposal``
    planes lie in it, but no proposal holds any of them;
``merged (C)``
    the proposal holding most of the in-rectangle planes' pixels has less than half of its
    pixels in the rectangle (it holds the box with what it stands on or touches); ``C`` its
    answer;
``other class (C)``, ``gate refused (G)``, ``no rule fires``
    that proposal lies mostly in the rectangle and is answered ``stairs`` / ``ramp``; a box
    rule fired and the decision refused it (``G``: the refusals' types); no box rule fired.

For ``merged`` and ``gate refused`` the row tells whether a box clause proves the proposal
with proof planes that lie in the rectangle (``proof_inside``: the first proof of each box
rule that fired, Prolog's ``planerel_explain``, with the share of its planes' pixels in the
rectangle) and which of the in-rectangle planes carry a box proof's atom (``skirt``,
``tall_face``, ``face_pair``, ``lying``).  ``range`` is the median distance (m) of the
rectangle's valid points.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

BOX = "box"


def set_folders(dirs) -> list:
    """The set folders (holding ``labels.json``) of ``dirs``: each itself or its children."""
    out = []
    for d in map(Path, dirs):
        if (d / "labels.json").is_file():
            out.append(d)
        else:
            out += sorted(p.parent for p in d.glob("*/labels.json"))
    return out


def box_hits(clf, desc) -> dict:
    """``{object id: [(class, rule index, bindings)]}``: every rule that proves each object of
    ``desc`` (the first proof of each), as :meth:`Classifier._answer` asks them."""
    from planerel.children import temp_prefix
    from planerel.classify.classifier import _bindings, _obj_atom, _text
    from planerel.features.facts import FactParams, facts_text
    from planerel.ilp.aleph_export import PAIRS
    from planerel.ilp.prolog import load_file, query, unload_file

    if not desc.objects:
        return {}
    text = facts_text([desc], FactParams(pairs=PAIRS, planner=False))
    with tempfile.NamedTemporaryFile("w", suffix=".pl", prefix=temp_prefix("census"),
                                     delete=False) as fh:
        fh.write(text)
        facts = Path(fh.name)
    out = {}
    try:
        load_file(facts, "cannot load the scene facts")
        for o in desc.objects:
            out[o.id] = [(_text(r["C"]), int(r["I"]), _bindings(_text(r["B"])))
                         for r in query(f"planerel_explain_text({clf.module}, {_obj_atom(o.id)}, "
                                        "C, I, B, T)", f"census {o.id}")]
    finally:
        unload_file(facts, "cannot unload the scene facts")
        facts.unlink(missing_ok=True)
    return out


def proof_atoms(desc, labels) -> dict:
    """Which of ``labels`` carry an atom of a box proof: ``{plane id: [names]}``."""
    pid = desc.plane_id
    labels = set(labels)
    out = {}

    def add(lab, name):
        out.setdefault(pid(lab), [])
        if name not in out[pid(lab)]:
            out[pid(lab)].append(name)

    for r in desc.relations:
        for name in ("skirt", "face_pair"):
            if getattr(r, name, False) and (r.a in labels or r.b in labels):
                for x in (r.a, r.b):
                    if x in labels:
                        add(x, name)
    for lab in labels:
        if lab in desc.tall:
            add(lab, "tall_face")
        if lab in desc.lying:
            add(lab, "lying")
    return out


def census_frame(clf, desc, answers, frame, xyz) -> list:
    """One row per labelled box of ``frame`` (the rows of found boxes say ``found``)."""
    from real_unseen import rect_mask, score_frame

    lab = np.asarray(desc.labels)
    shape = lab.shape
    scored = score_frame(type("A", (), {"labels": lab, "objects": answers})(), frame)
    hits = None
    rows = []
    pid = desc.plane_id
    labs, counts = np.unique(lab[lab >= 0], return_counts=True)
    size = dict(zip(labs.tolist(), counts.tolist(), strict=True))
    z = np.linalg.norm(np.asarray(xyz, float), axis=-1)
    for o, s in zip(frame.get("objects", []), scored["objects"], strict=True):
        if o["class"] != BOX:
            continue
        m = rect_mask(shape, o["box"])
        zz = z[m & np.isfinite(z) & (z > 0)]
        r = {"what": o.get("what", ""), "box": o["box"],
             "range": round(float(np.median(zz)), 2) if zz.size else None}
        rows.append(r)
        if s["found"]:
            r["stage"] = "found"
            continue
        inl = Counter(lab[m][lab[m] >= 0].tolist())
        inside = [L for L, n in inl.items() if n >= 0.5 * size[L] and size[L] >= 100]
        if not inside:
            r["stage"] = "no plane in it"
            continue
        held = sorted(((sum(size[L] for L in inside if L in set(a.labels)), j)
                       for j, a in enumerate(answers)), reverse=True)
        if not held or held[0][0] == 0:
            r["stage"] = "no proposal"
            r["planes"] = [pid(L) for L in inside]
            continue
        j = held[0][1]
        a = answers[j]
        pm = np.isin(lab, list(a.labels))
        share = float((pm & m).sum()) / max(1, int(pm.sum()))
        r.update(proposal=a.object_id, answer=a.klass, share_inside=round(share, 2),
                 nplanes=len(a.labels), planar_fraction=a.planar_fraction,
                 refused=sorted({type(x).__name__ for x in a.refused}))
        boxed = any(f[0] == BOX for f in a.fired)
        if share < 0.5:
            r["stage"] = f"merged ({a.klass})"
        elif a.klass in ("stairs", "ramp"):
            r["stage"] = f"other class ({a.klass})"
        elif boxed:
            r["stage"] = f"gate refused ({', '.join(r['refused']) or '?'})"
        else:
            r["stage"] = "no rule fires"
        if r["stage"].startswith(("merged", "gate refused")):
            if hits is None:
                hits = box_hits(clf, desc)
            by_id = {pid(L): L for L in np.unique(lab[lab >= 0]).tolist()}
            proofs = []
            for k, i, b in hits.get(a.object_id, []):
                if k != BOX:
                    continue
                planes = [v for v in b.values() if v in by_id]
                px = sum(size.get(by_id[v], 0) for v in planes)
                pin = sum(int(((lab == by_id[v]) & m).sum()) for v in planes)
                proofs.append({"rule": i, "planes": planes,
                               "share_inside": round(pin / px, 2) if px else 0.0})
            r["box_proofs"] = proofs
            r["proof_inside"] = any(p["share_inside"] >= 0.5 for p in proofs)
            r["atoms_inside"] = proof_atoms(desc, [L for L in inside if L in set(a.labels)])
    return rows


def census(dirs, model: str, params=()) -> list:
    """One row per labelled box of the set folders of ``dirs``."""
    from real_unseen import read_labels

    import planerel
    from planerel.classify.classifier import Classifier
    from planerel.commands.classify import _params
    from planerel.features.facts import describe_scene
    from planerel.ilp.scenes import segment_cached

    rows = []
    with Classifier(model, seg_params=_params(list(params))) as clf:
        for folder in set_folders(dirs):
            doc = read_labels(str(folder))
            for frame in doc["frames"]:
                if not any(o["class"] == BOX for o in frame.get("objects", [])):
                    continue
                path = os.path.join(folder, frame["file"])
                cloud = planerel.read(path, intrinsics=frame.get("intrinsics"),
                                      depth_scale=frame.get("depth_scale"))
                up = frame.get("up")
                labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
                desc = describe_scene(cloud, labels, scene_id="s",
                                      up=None if up is None else np.asarray(up, float),
                                      **clf._describe_kw)
                answers = clf.answer_description(desc, xyz=cloud.xyz)
                stem = os.path.splitext(os.path.basename(path))[0]
                for r in census_frame(clf, desc, answers, frame, cloud.xyz):
                    rows.append({"set": f"{folder.parent.name}/{folder.name}", "frame": stem, **r})
                print(f"{folder.name}/{stem}", file=sys.stderr, flush=True)
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dirs", nargs="+", metavar="DIR")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    rows = census(a.dirs, a.model, a.param)
    hunts = list(dict.fromkeys(r["set"].split("/")[0] for r in rows))
    for h in hunts:
        these = [r for r in rows if r["set"].split("/")[0] == h]
        print(h, len(these), dict(Counter(r["stage"] for r in these).most_common()))
    print("all", len(rows), dict(Counter(r["stage"] for r in rows).most_common()))
    mg = [r for r in rows if r["stage"].startswith(("merged", "gate refused"))]
    print(f"merged or gate refused: {len(mg)}; a box proof with its planes in the rectangle: "
          f"{sum(bool(r.get('proof_inside')) for r in mg)}; a box proof's atom on an "
          f"in-rectangle plane: {sum(bool(r.get('atoms_inside')) for r in mg)}")
    for r in rows:
        if r["stage"] != "found":
            print(json.dumps(r))
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
