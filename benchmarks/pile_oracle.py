"""What a perfect segmentation and perfect proposals would buy on packed or stacked boxes
(pile56, docs/objects.md "Packed and stacked boxes: seams, oracle planes and oracle
proposals").  A measuring tool; nothing of it is used by the classifier.

Usage::

    pile_oracle.py CENSUS.json [--root /work] [--model out/model] [--stage STAGE ...]
                   [--up SET=X,Y,Z ...] [--json F]

``CENSUS.json`` is :mod:`real_census`'s ``--json`` output (default stages: the three
``merged`` ones).  Each frame holding a selected box is read and segmented as the classifier
does (``--model``'s settings; the frame's labelled ``up``, else estimated), then answered four
ways, every labelled box of the frame scored as ``real_unseen.py`` scores it:

``as is``
    the classifier's own planes and proposals;
``cut``
    every plane with at least ``SPAN`` (0.1) of its pixels in each of two labelled box
    rectangles cut along the rectangles (:func:`cut_along_rects`: a pixel in several goes to
    the one whose centre is nearest; pixels in none keep the plane's label): the segmentation
    an oracle would give packed faces that the depth bridges;
``cut+own``
    the cut planes, and one proposal per labelled box: the planes with ``OWN`` (0.6) of
    their pixels in its rectangle (:func:`own_proposals`), nothing else proposed: relations
    and proposals that never glue two boxes;
``cut+own+up``
    the same with the set's ``--up`` (a mount whose up the estimate misses), when given.

For the ``cut+own`` proposals the row lists the box-proof atoms on their planes
(:func:`real_census.proof_atoms`), how many ``skirt`` / ``face_pair`` pairs have both planes
in the proposal (pair facts are written within a proposal) and the proposal's answer.  And for every plane spanning two rectangles,
:func:`seam_parts`: does the plane fall apart along the seams the depth shows (pixels without
depth or unassigned, or points more than ``max(tol, 2 x RMS)`` behind its fit, dilated by one
pixel)?  ``parts`` counts the pieces of 2 % of the plane or more, ``boxes`` the rectangles in
which one of them has half of its pixels, ``own piece in`` the shared planes in which the box
itself has such a piece.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

#: a plane spans two boxes when this share of its pixels lies in each of two rectangles
SPAN = 0.1
#: a plane belongs to a box's own proposal when this share of its pixels lies in its rectangle
OWN = 0.6
STAGES = ("merged (other)", "merged (box)", "merged (stairs)")


def box_rects(frame: dict, shape) -> list:
    """``[(index, mask)]`` of the frame's labelled ``box`` rectangles."""
    from real_unseen import rect_mask

    return [(i, rect_mask(shape, o["box"])) for i, o in enumerate(frame.get("objects", []))
            if o.get("class") == "box"]


def spanning(lab: np.ndarray, rects) -> dict:
    """``{label: [share in each rectangle]}`` for the planes spanning two of ``rects``."""
    out = {}
    for lbl in np.unique(lab[lab >= 0]):
        m = lab == lbl
        n = int(m.sum())
        sh = [float((m & r).sum()) / n for r in rects]
        if sum(s >= SPAN for s in sh) >= 2:
            out[int(lbl)] = sh
    return out


def cut_along_rects(lab: np.ndarray, rects, boxes) -> np.ndarray:
    """``lab`` with each plane of ``boxes`` (``{label: shares}``, :func:`spanning`) cut along
    the rectangles ``rects`` ``[(x0, y0, x1, y1)]``: a new label for its pixels in each
    rectangle holding at least 5 % of it (a pixel in several rectangles: the one whose centre
    is nearest); its pixels in none keep the old label."""
    out = np.array(lab, copy=True)
    H, W = out.shape
    yy, xx = np.mgrid[:H, :W]
    d = np.full((len(rects), H, W), np.inf)
    for i, (x0, y0, x1, y1) in enumerate(rects):
        inside = (xx >= x0) & (xx < x1) & (yy >= y0) & (yy < y1)
        d[i][inside] = ((xx - (x0 + x1) / 2.0) ** 2 + (yy - (y0 + y1) / 2.0) ** 2)[inside]
    owner = np.where(np.isfinite(d.min(axis=0)), d.argmin(axis=0), -1)
    nxt = int(out.max()) + 1
    for lbl, shares in sorted(boxes.items()):
        m = lab == lbl
        for i, s in enumerate(shares):
            if s >= 0.05:
                sel = m & (owner == i)
                if sel.any():
                    out[sel] = nxt
                    nxt += 1
    return out


def own_proposals(lab: np.ndarray, rects) -> list:
    """One proposal per rectangle: the labels with :data:`OWN` of their pixels in it."""
    out = []
    for r in rects:
        cand = np.unique(lab[r & (lab >= 0)])
        out.append([int(c) for c in cand if (r & (lab == c)).sum() >= OWN * (lab == c).sum()])
    return out


def seam_parts(lab: np.ndarray, xyz: np.ndarray, valid: np.ndarray, label: int,
               tol: float = 0.004, dilate: int = 1, least: float = 0.02) -> list:
    """The pieces plane ``label`` falls into when its seams are taken out: pixel masks, largest
    first, of ``least`` of its pixels or more.  Seam pixels lie within the plane's extent (its
    mask closed by 3 pixels): without depth, unassigned, or farther than ``max(tol, 2 x RMS)``
    behind the plane's least-squares fit (away from the sensor); dilated by ``dilate``."""
    from scipy import ndimage as ndi

    m = lab == label
    n = int(m.sum())
    pts = xyz[m]
    c = pts.mean(axis=0)
    normal = np.linalg.svd(pts - c, full_matrices=False)[2][2]
    if normal @ c > 0:
        normal = -normal
    rms = float(np.sqrt(np.mean(((pts - c) @ normal) ** 2)))
    behind = np.zeros(m.shape, bool)
    behind[valid] = (xyz[valid] - c) @ normal < -max(tol, 2.0 * rms)
    seam = (~valid) | (lab < 0) | behind
    # closed on a padded mask: a plane reaching the image's border keeps its seams there
    seam &= ndi.binary_closing(np.pad(m, 3), iterations=3)[3:-3, 3:-3]
    if dilate > 0:
        seam = ndi.binary_dilation(seam, iterations=dilate)
    parts, k = ndi.label(m & ~seam)
    if k == 0:
        return []
    sizes = np.bincount(parts.ravel(), minlength=k + 1)[1:]
    return [parts == i + 1 for i in np.argsort(-sizes) if sizes[i] >= least * n]


def _answer(clf, cloud, lab, up, objects):
    """Describe ``lab`` (``objects``: the proposals, or None for the classifier's) and answer
    it: ``(SceneAnswer, SceneDescription)``."""
    from planerel.classify.classifier import SceneAnswer
    from planerel.features.facts import describe_scene

    desc = describe_scene(cloud, lab, scene_id="s", up=up, objects=objects, **clf._describe_kw)
    answers = clf.answer_description(desc, xyz=cloud.xyz)
    ids = {p.label: desc.plane_id(p.label) for p in desc.planes}
    ps = desc.planes
    return SceneAnswer(cloud.source, "s", desc.labels, ids, answers, ps.up_source, 0.0,
                       ps.up_confidence, up_vector=tuple(float(v) for v in ps.up)), desc


def frame_rows(clf, folder: str, frame: dict, up_given=None) -> list:
    """One row per labelled box of ``frame``: found as is / cut / cut+own (/ cut+own+up),
    the atoms on its own proposal's planes, and the seam parts of the planes it shares."""
    from real_census import proof_atoms
    from real_unseen import read_frame, score_frame

    from planerel.ilp.scenes import segment_cached

    cloud, up = read_frame(folder, frame)
    lab = np.asarray(segment_cached(cloud, method=clf.method, params=clf.seg_params))
    rect_list = box_rects(frame, lab.shape)
    idx = [i for i, _ in rect_list]
    rects = [r for _, r in rect_list]
    span = spanning(lab, rects)
    seams = {}
    for lbl in span:
        parts = seam_parts(lab, cloud.xyz, cloud.valid, lbl)
        hit = sorted({j for p in parts for j, r in enumerate(rects)
                      if (p & r).sum() >= 0.5 * p.sum()})
        seams[lbl] = (len(parts), hit)
    # a box has a seam piece of its own in a shared plane when half of a piece lies in it
    cut = cut_along_rects(lab, [frame["objects"][i]["box"] for i in idx], span)
    own = own_proposals(cut, rects)
    runs = {"as is": (lab, up, None), "cut": (cut, up, None), "cut+own": (cut, up, own)}
    if up_given is not None:
        runs["cut+own+up"] = (cut, np.asarray(up_given, float), own)
    found, atoms, said, inside = {}, [], [], []
    for name, (lb, u, objs) in runs.items():
        ans, desc = _answer(clf, cloud, lb, u, objs)
        sc = score_frame(ans, frame)
        found[name] = [o["found"] for o in sc["objects"]]
        if name == "cut+own":
            atoms = [proof_atoms(desc, o) for o in own]
            inside = [sum(1 for r in desc.relations if (r.skirt or r.face_pair)
                          and r.a in set(o) and r.b in set(o)) for o in own]
            by_labels = {frozenset(o.labels): o for o in ans.objects}
            said = []
            for o in own:
                a_ = by_labels.get(frozenset(o))
                said.append("-" if a_ is None else a_.klass + "".join(
                    f" refused {type(r).__name__}" for r in a_.refused))
    rows = []
    for j, i in enumerate(idx):
        shared = [lbl for lbl, sh in span.items() if sh[j] >= SPAN]
        rows.append({"frame": os.path.splitext(frame["file"])[0], "box": i,
                     "what": frame["objects"][i].get("what", ""),
                     **{k: bool(v[i]) for k, v in found.items()},
                     "own_planes": len(own[j]), "atoms": atoms[j] if atoms else {},
                     "own_answer": said[j] if said else "-",
                     "pairs_inside": inside[j] if inside else 0,
                     "shared_planes": len(shared),
                     "seam_parts": [seams[lbl][0] for lbl in shared],
                     "seam_boxes": [len(seams[lbl][1]) for lbl in shared],
                     "seam_own": sum(j in seams[lbl][1] for lbl in shared)})
    return rows


def main(argv=None) -> int:
    from real_unseen import read_labels

    from planerel.classify.classifier import Classifier

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("census")
    ap.add_argument("--root", default="/work")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--stage", action="append", default=None)
    ap.add_argument("--up", action="append", default=[], metavar="SET=X,Y,Z")
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    stages = tuple(a.stage or STAGES)
    ups = {}
    for s in a.up:
        name, v = s.split("=", 1)
        ups[name] = [float(x) for x in v.split(",")]
    census = json.load(open(a.census))
    want = {}
    for r in census:
        if r["stage"] in stages:
            want.setdefault((r["set"], r["frame"]), []).append(list(r["box"]))
    out = []
    with Classifier(a.model) as clf:
        for (st, fr), whats in sorted(want.items()):
            folder = os.path.join(a.root, st)
            doc = read_labels(folder)
            frame = next(f for f in doc["frames"] if os.path.splitext(f["file"])[0] == fr)
            up_given = next((v for k, v in ups.items() if st.endswith(k) or fr.startswith(k)), None)
            for row in frame_rows(clf, folder, frame, up_given):
                if list(frame["objects"][row["box"]]["box"]) in whats:
                    row["set"] = st
                    out.append(row)
                    cols = ["as is", "cut", "cut+own"] + (["cut+own+up"] if up_given else [])
                    flags = " ".join(f"{c}:{'Y' if row[c] else '-'}" for c in cols)
                    print(f"{st}/{row['frame']} | {row['what'][:48]} | {flags} | own planes "
                          f"{row['own_planes']} atoms {row['atoms'] or '-'} (pairs within {row['pairs_inside']}) answer {row['own_answer']} | shared planes "
                          f"{row['shared_planes']} seam parts {row['seam_parts']} boxes "
                          f"{row['seam_boxes']} own piece in {row['seam_own']}", flush=True)
    tot = {c: sum(r.get(c, False) for r in out) for c in ("as is", "cut", "cut+own", "cut+own+up")}
    print(f"boxes {len(out)}: found " + ", ".join(f"{k} {v}" for k, v in tot.items()))
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(out, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
