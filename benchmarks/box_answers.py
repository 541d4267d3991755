"""Every ``box`` answer of the real development frames: its truth, rule, proof planes and the
measures tried as tests of a false box (fbox53, docs/objects.md "The false boxes of the
development frames against the boxes found: measured, nothing built (fbox53)").  A measuring
tool: no relation or gate of the model reads it.

    .venv/bin/python benchmarks/box_answers.py MODEL [--hunts DIR ...] [--extdata DIR]
        [--mosd DIR] [--param NAME=VALUE ...] [--jsonl OUT]

``--hunts``: labelled set folders (benchmarks/real_unseen.py's ``labels.json``; an answer is
``right``, ``unscored`` or ``false`` as real_unseen.py scores it); ``--extdata``: the OSD and
UOIS table-tops under it (benchmarks/real_tabletop.py's points: ``right`` when a box point lies
in the answer, ``false`` when only another kind's does, ``unlabelled`` when none);
``--mosd``: the whole mOSD set (``right`` when most of the answer's labelled points are one
object of a box frame, ``false`` for a cylindric frame's, ``untyped`` in the occluded, mixed
and complex frames, whose objects OSD does not type).

Per answer (one JSON line): ``set``, ``frame``, ``object``, ``status``, ``rule`` (index),
``planar`` (fraction), ``planes`` (count), ``up_confidence``, ``pitch`` (degrees the
camera looks under the horizon by the frame's up: :func:`planerel.segment.view_pitch`, what the
small pass's ``small_pitch`` reads), ``proof`` (each proof plane's
label, orientation, incline, length, width, points, RMS in mm, range, height over the floor,
whether it touches the image's border or is seen in part), and two measures of the vertical
planes (fbox53):

* ``skirt_fans``: for each top of the proposal with two or more ``skirt`` faces in it, the
  angles between those faces (degrees, 0-90).  A box's sides meet at 90 degrees or are pieces
  of one side (0); the facets a region grower makes of a can's side meet in between.
* ``beside``: for each vertical proof plane, the angle to every vertical plane of the proposal
  adjacent to it.

The summary printed at the end: the false answers, and the least ``skirt_fans`` angle over 20
degrees per status.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))

#: Angles between two skirt faces of one top that are neither one side's pieces nor two sides
#: meeting at a corner lie over this (degrees); the summary reports the least of them.
FAN_LOW = 20.0


def skirt_fans(pairs, labels) -> dict:
    """``{top: [angle, ...]}``: for each plane of ``labels`` that is the top of two or more
    ``skirt`` faces among ``labels``, the angles (degrees) between every two of those faces.

    ``pairs`` are :class:`planerel.features.relations.Relation` s (``a``, ``b``, ``angle``,
    ``skirt``); a pair not among them has no angle and is left out."""
    inside = set(int(v) for v in labels)
    rel = {(int(r.a), int(r.b)): r for r in pairs if int(r.a) in inside and int(r.b) in inside}
    out = {}
    for t in sorted(inside):
        faces = sorted(f for f in inside if f != t and (t, f) in rel and rel[(t, f)].skirt)
        angles = [round(float(rel[(f, g)].angle), 1) for i, f in enumerate(faces)
                  for g in faces[i + 1:] if (f, g) in rel]
        if angles:
            out[t] = angles
    return out


def beside_angles(pairs, labels, proof, vertical) -> list:
    """``[(proof plane, plane, angle)]``: each vertical plane of ``labels`` adjacent to a
    vertical proof plane, and the angle between them (``vertical``: a label's test)."""
    inside = set(int(v) for v in labels)
    out = []
    for r in pairs:
        a, b = int(r.a), int(r.b)
        if a in proof and b in inside and b != a and r.adjacent and vertical(a) and vertical(b):
            out.append((a, b, round(float(r.angle), 1)))
    return sorted(out)


def _plane(p, truncated) -> dict:
    return {"label": int(p.label), "orientation": p.orientation, "incline": round(float(p.incline), 1),
            "length": round(float(p.length), 3), "width": round(float(p.width), 3),
            "points": int(p.n_points), "rms_mm": round(float(p.rms) * 1000, 1),
            "range": round(float(p.distance), 2), "height": round(float(p.height), 3),
            "border": bool(p.touches_border), "in_part": bool(p.label in truncated)}


def records(answer, desc) -> list:
    """``[(ObjectAnswer, pixel mask, record)]`` of the ``box`` answers of one frame."""
    from planerel.segment import view_pitch

    planes = {p.label: p for p in desc.planes}
    ids = {desc.plane_id(p.label): p.label for p in desc.planes}
    lab = np.asarray(answer.labels)
    pairs = desc.relations.pairs

    def vertical(label):
        return label in planes and planes[label].orientation == "vertical"

    out = []
    for o in answer.objects:
        if o.klass != "box":
            continue
        proof = [ids[i] for i in o.proof_planes if i in ids]
        rec = {"object": o.object_id, "rule": o.rule_index,
               "planar": None if o.planar_fraction is None else round(o.planar_fraction, 3),
               "planes": len(o.labels), "up_confidence": round(float(answer.up_confidence), 2),
               "pitch": round(view_pitch(desc.planes.up), 1),
               "proof": [_plane(planes[v], desc.truncated) for v in proof],
               "skirt_fans": {str(k): v for k, v in
                              skirt_fans(pairs, o.labels).items()},
               "beside": beside_angles(pairs, o.labels, set(proof), vertical)}
        out.append((o, np.isin(lab, list(o.labels)), rec))
    return out


class _Described:
    """The classifier's own description of the last frame it answered (no second describe)."""

    def __init__(self, clf):
        self.desc = None
        orig = clf.answer_description

        def hook(desc, xyz=None):
            self.desc = desc
            return orig(desc, xyz)

        clf.answer_description = hook


def hunt_rows(clf, seen, folders):
    from real_unseen import read_frame, read_labels, rect_mask

    for folder in folders:
        doc = read_labels(folder)
        name = doc.get("set", os.path.basename(os.path.normpath(folder)))
        for frame in doc["frames"]:
            cloud, up = read_frame(folder, frame)
            ans = clf.classify(cloud, scene_id="s", up=up)
            shape = np.asarray(ans.labels).shape
            boxes = [rect_mask(shape, o["box"]) for o in frame.get("objects", [])
                     if o["class"] == "box"]
            unscored = [rect_mask(shape, b) for b in frame.get("unscored", [])]
            for _, pix, rec in records(ans, seen.desc):
                n = max(int(pix.sum()), 1)
                if any((pix & m).sum() / n >= 0.5 for m in boxes):
                    status = "right"
                elif any((pix & m).sum() / n >= 0.5 for m in unscored):
                    status = "unscored"
                else:
                    status = "false"
                yield {"set": name, "frame": frame["file"], "status": status, **rec}


def tabletop_rows(clf, seen, extdata):
    from real_tabletop import TRUTH, frames, read_frame

    for key, path, intrinsics in frames(os.path.join(extdata, "osd"), os.path.join(extdata, "uois")):
        ans = clf.classify(read_frame(path, intrinsics), scene_id=key.split("/")[1])
        for _, pix, rec in records(ans, seen.desc):
            kinds = [f"{kind}:{name}" for x, y, kind, name in TRUTH[key]
                     if pix[max(0, y - 4): y + 5, max(0, x - 4): x + 5].any()]
            status = ("right" if any(k.startswith("box:") for k in kinds)
                      else "false" if any(k.split(":")[0] in ("round", "other") for k in kinds)
                      else "unlabelled" if not kinds else "thing")
            yield {"set": "tabletop", "frame": key, "status": status, "points": kinds, **rec}


def mosd_rows(clf, seen, folder):
    from real_mosd import category

    from planerel.features.object_eval import frame_truth

    for path in sorted(Path(folder).glob("*.pcd")):
        _, cat, kind = category(path.stem)
        ((name, cloud, truth, _),) = list(frame_truth(path))
        ans = clf.classify(cloud, scene_id=name)
        for _, pix, rec in records(ans, seen.desc):
            t = truth[pix]
            t = t[t >= 1]
            one = t.size and np.bincount(t).max() >= 0.5 * pix.sum()
            status = ("false" if not t.size else "untyped" if kind is None
                      else {"box": "right", "round": "false"}[kind] if one else "merged")
            yield {"set": "mosd", "frame": path.stem, "status": status, "category": cat, **rec}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("model")
    ap.add_argument("--hunts", nargs="*", default=[], metavar="DIR")
    ap.add_argument("--extdata", metavar="DIR", help="holds osd/ and uois/ (real_tabletop.py)")
    ap.add_argument("--mosd", metavar="DIR")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--jsonl", metavar="OUT")
    a = ap.parse_args(argv)
    sys.path.insert(0, HERE)
    from planerel.classify.classifier import Classifier
    from planerel.commands.classify import _params

    rows = []
    with Classifier(a.model, seg_params=_params(a.param)) as clf:
        seen = _Described(clf)
        if a.hunts:
            rows += list(hunt_rows(clf, seen, a.hunts))
        if a.extdata:
            rows += list(tabletop_rows(clf, seen, a.extdata))
        if a.mosd:
            rows += list(mosd_rows(clf, seen, a.mosd))
    if a.jsonl:
        with open(a.jsonl, "w") as fh:
            fh.writelines(json.dumps(r) + "\n" for r in rows)
    for r in rows:
        if r["status"] == "false":
            proof = "; ".join(f"{p['orientation'][0]}{p['incline']:.0f} {p['length'] * 100:.0f}x"
                              f"{p['width'] * 100:.0f} cm {p['points']} px" for p in r["proof"])
            print(f"false  {r['set']} {r['frame']} {r['object']} rule {r['rule']}: {proof}")
    by = {}
    for r in rows:
        fans = [v for vs in r["skirt_fans"].values() for v in vs if v > FAN_LOW]
        by.setdefault(r["status"], []).append(min(fans) if fans else None)
    for status, vals in sorted(by.items()):
        fans = sorted(v for v in vals if v is not None)
        print(f"{status}: {len(vals)} box answers; two skirts of one top at over {FAN_LOW:.0f} "
              f"degrees in {len(fans)}, the least {fans[:4]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
