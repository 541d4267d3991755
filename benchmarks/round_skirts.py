"""Round things answered ``box`` by ``skirt/2``: measures of a skirt pair's top and face that
could tell a can's flat cap and a facet of its side from a box's top and side (round44,
docs/objects.md "Cans and cups answered box by the skirt clause: measured, nothing built").
A measuring tool, not a relation of the model: the measurements it made found no margin.

For every object proposal holding a ``skirt`` pair (both planes in the proposal), and for every
such pair, one record with the proposal's answer, the truth under it and, per pair:

* the top's outline in its own plane (the convex hull of its points): ``fill`` (hull area over
  the minimum rotated rectangle's: 1 for a rectangle, pi/4 for a disc), ``circ_res`` (RMS of
  the hull's outline's distance to its best circle, over the circle's radius: 0 for a disc,
  0.107 for a square, 0.25 for a 2:1 rectangle), ``sides`` (the rectangle's, m);
* the face's bend across its width: the face's points' distances to their own plane fit
  (along the face's horizontal axis and height), the median of 9 bins over the central 70 %
  of its width, fitted with a parabola: ``bend_radius`` (m; negative when the face bulges
  towards the sensor, as a can's side does), ``width`` (2nd-98th percentile, m), ``sag_mm``
  (the parabola's sag over the whole width);
* ``width_ratio``: the face's width over the top's extent along the same axis (a facet of a
  cylinder is a chord, narrower than the cap; a box's side spans its top's edge);
* ``edge_bow_mm``: the top's edge towards the face (the 95th percentile of its points'
  distance towards the face's plane, in 10 bins across the face's width) fitted with a
  parabola: its sag (a cap's rim is an arc, a box's edge a line; negative bows towards the
  face);
* ``cover``: the skirt's own cover (:func:`planerel.features.solid.skirt_measures`, the share
  of the top's extent that the face covers 30-70 % of its reach down, as the rule measured
  it; the rule asks 0.7).

Usage::

    round_skirts.py hunt MODEL SETDIR [SETDIR ...]     labelled frames (real_unseen.py folders)
    round_skirts.py tabletop MODEL EXTDATA             real_tabletop.py's OSD and UOIS frames
    round_skirts.py mosd MODEL PCD [PCD ...]           mOSD frames (truth: OSD's categories)
    round_skirts.py indep MODEL SCENE.npy [...]        independent_scenes.py scenes
    round_skirts.py train MODEL DATASET                a synthetic data set (its ground truth)
    round_skirts.py summary FILE.jsonl [...]           per truth, each measure's object-level
                                                       extreme (the value of the pair that
                                                       would keep the object's skirt)

Each collecting command prints one JSON line per proposal.
"""

from __future__ import annotations

import contextlib
import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def _basis(n):
    a = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(n, a)
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(n, e1)


def circle_fit(p) -> tuple:
    """``(centre, radius, relative RMS)`` of the algebraic circle fit to 2-D points ``p``."""
    a = np.c_[2 * p, np.ones(len(p))]
    sol = np.linalg.lstsq(a, (p ** 2).sum(1), rcond=None)[0]
    c = sol[:2]
    r = float(np.sqrt(max(sol[2] + c @ c, 1e-12)))
    d = np.linalg.norm(p - c, axis=1) - r
    return c, r, float(np.sqrt((d ** 2).mean()) / r)


def top_shape(points, normal) -> dict:
    """``fill``, ``circ_res``, ``radius`` and ``sides`` of a top's points (module docstring)."""
    from shapely.geometry import MultiPoint

    c = points.mean(0)
    e1, e2 = _basis(np.asarray(normal, float))
    uv = np.c_[(points - c) @ e1, (points - c) @ e2]
    hull = MultiPoint([tuple(q) for q in uv]).convex_hull
    rect = hull.minimum_rotated_rectangle
    ring = hull.exterior
    s = np.array([ring.interpolate(t, normalized=True).coords[0]
                  for t in np.linspace(0, 1, 96, endpoint=False)])
    _, r, res = circle_fit(s)
    xs = np.array(rect.exterior.coords)[:4]
    sides = sorted([float(np.linalg.norm(xs[1] - xs[0])), float(np.linalg.norm(xs[2] - xs[1]))])
    return {"fill": round(hull.area / max(rect.area, 1e-12), 3), "circ_res": round(res, 3),
            "radius": round(r, 4), "sides": [round(v, 4) for v in sides]}


def _towards_sensor(v, at):
    return v if v @ (-at) >= 0 else -v


def face_bend(points, normal, up) -> dict:
    """``width``, ``bend_radius`` and ``sag_mm`` of a face's points (module docstring)."""
    c = points.mean(0)
    n = _towards_sensor(np.asarray(normal, float), c)
    d = np.cross(up, n)
    d /= np.linalg.norm(d)
    s, h, r = (points - c) @ d, (points - c) @ up, (points - c) @ n
    b = np.c_[s, np.ones_like(s), h]
    r0 = r - b @ np.linalg.lstsq(b, r, rcond=None)[0]
    lo, hi = np.percentile(s, [2, 98])
    q1, q2 = np.percentile(s, [15, 85])
    edges = np.linspace(q1, q2, 10)
    bx, by = [], []
    for i in range(9):
        k = (s >= edges[i]) & (s < edges[i + 1])
        if k.sum() >= 5:
            bx.append(0.5 * (edges[i] + edges[i + 1]))
            by.append(float(np.median(r0[k])))
    out = {"width": round(float(hi - lo), 4), "bend_radius": None, "sag_mm": None}
    if len(bx) >= 5:
        a = float(np.polyfit(bx, by, 2)[0])
        out["bend_radius"] = round(1 / (2 * a), 4) if a else 1e9
        out["sag_mm"] = round(a * ((hi - lo) / 2) ** 2 * 1000, 2)
    return out


def edge_and_width(top_points, face_points, normal, up) -> dict:
    """``width_ratio`` and ``edge_bow_mm`` of a skirt pair (module docstring)."""
    c = face_points.mean(0)
    n = np.asarray(normal, float)
    m = n - (n @ up) * up
    m = _towards_sensor(m / np.linalg.norm(m), c)
    d = np.cross(up, m)
    d /= np.linalg.norm(d)
    sf = (face_points - c) @ d
    lo, hi = np.percentile(sf, [2, 98])
    st, g = (top_points - c) @ d, (top_points - c) @ m
    tlo, thi = np.percentile(st, [2, 98])
    out = {"width_ratio": round(float((hi - lo) / max(thi - tlo, 1e-6)), 3), "edge_bow_mm": None}
    edges = np.linspace(lo, hi, 11)
    xs, es = [], []
    for i in range(10):
        k = (st >= edges[i]) & (st < edges[i + 1])
        if k.sum() >= 5:
            xs.append(0.5 * (edges[i] + edges[i + 1]))
            es.append(float(np.percentile(g[k], 95)))
    if len(xs) >= 5:
        a = float(np.polyfit(xs, es, 2)[0])
        out["edge_bow_mm"] = round(a * ((hi - lo) / 2) ** 2 * 1000, 2)
    return out


@contextlib.contextmanager
def recording_covers():
    """Within: every skirt the relations accept records its cover, as the rule measured it
    (:func:`planerel.features.solid.is_skirt` wrapped in the relations module), in the dict
    yielded, by ``(top label, face label)``."""
    from planerel.features import relations, solid

    covers = {}
    plain = relations.is_skirt

    def is_skirt(top, face, up, prof, labels, xyz, intr, normals=None, parallel_tol=10.0,
                 tol=0.08, reach_min=0.07, cover_min=0.7, beyond_max=0.4):
        ok = plain(top, face, up, prof, labels, xyz, intr, normals, parallel_tol, tol,
                   reach_min, cover_min, beyond_max)
        if ok:
            span = solid._skirt_geometry(top, up, prof)[3]
            covers[(int(top.label), int(face.label))] = 0.0 if span is None else float(
                solid._skirt_cover(face, up, prof, labels, xyz, intr, normals, parallel_tol, 24,
                                   *span))
        return ok

    relations.is_skirt = is_skirt
    try:
        yield covers
    finally:
        relations.is_skirt = plain


def measure(desc, answers, cloud, truth_of, covers) -> list:
    """One record per proposal of ``answers`` holding a skirt pair (module docstring)."""
    planes = desc.planes
    lab = np.asarray(desc.labels)
    up = np.asarray(planes.up, float)
    h, w = lab.shape
    pts = np.asarray(cloud.xyz, float).reshape(h, w, 3)
    out = []
    for o in answers:
        labs = set(o.labels)
        pairs = [(r.a, r.b) for r in desc.relations if r.skirt and r.a in labs and r.b in labs]
        if not pairs:
            continue
        pix = np.isin(lab, list(labs))
        bound = set(o.bindings.values())
        rec = {"obj": o.object_id, "klass": o.klass, "rule": o.rule_index,
               "fired": [list(f) for f in o.fired], "truth": truth_of(pix), "pairs": []}
        for a, b in pairs:
            top, face = planes.by_label(a), planes.by_label(b)
            tp, fp = pts[lab == a], pts[lab == b]
            tp, fp = tp[np.isfinite(tp).all(1)], fp[np.isfinite(fp).all(1)]
            row = {"top": desc.plane_id(a), "face": desc.plane_id(b),
                   "bound": desc.plane_id(a) in bound and desc.plane_id(b) in bound,
                   "truncated": a in desc.truncated, "distance": round(float(np.linalg.norm(fp.mean(0))), 3)}
            row.update(top_shape(tp, top.normal))
            row.update(face_bend(fp, face.normal, up))
            row.update(edge_and_width(tp, fp, face.normal, up))
            cov = covers.get((int(a), int(b)))
            row["cover"] = None if cov is None else round(cov, 3)
            rec["pairs"].append(row)
        out.append(rec)
    return out


def _describe(clf, cloud, up=None):
    from planerel.features.facts import describe_scene
    from planerel.ilp.scenes import segment_cached

    labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
    kw = dict(clf._describe_kw)
    if up is not None:
        kw["up"] = np.asarray(up, float)
    with recording_covers() as covers:
        desc = describe_scene(cloud, labels, scene_id="s", **kw)
    return desc, clf.answer_description(desc, xyz=cloud.xyz), covers


def _emit(records, src):
    for r in records:
        r["src"] = src
        print(json.dumps(r), flush=True)


def hunt(clf, folders):
    import planerel

    sys.path.insert(0, HERE)
    from real_unseen import read_labels, rect_mask

    for folder in folders:
        doc = read_labels(folder)
        for fr in doc["frames"]:
            cloud = planerel.read(os.path.join(folder, fr["file"]), intrinsics=fr.get("intrinsics"),
                                  depth_scale=fr.get("depth_scale"))
            desc, ans, covers = _describe(clf, cloud, fr.get("up"))
            shape = np.asarray(desc.labels).shape
            rects = [(o["class"], rect_mask(shape, o["box"])) for o in fr.get("objects", [])]
            skip = [rect_mask(shape, b) for b in fr.get("unscored", [])]

            def truth_of(pix, rects=rects, skip=skip):
                n = pix.sum()
                for k, m in rects:
                    if (pix & m).sum() >= 0.5 * n:
                        return k
                return "unscored" if any((pix & m).sum() >= 0.5 * n for m in skip) else "false"

            _emit(measure(desc, ans, cloud, truth_of, covers), f"{doc.get('set')}/{fr['file']}")


def tabletop(clf, extdata):
    sys.path.insert(0, HERE)
    import real_tabletop as tt

    for key, path, intr in tt.frames(os.path.join(extdata, "osd"), os.path.join(extdata, "uois")):
        cloud = tt.read_frame(path, intr)
        desc, ans, covers = _describe(clf, cloud)

        def truth_of(pix, key=key):
            ks = [f"{k}:{name}" for x, y, k, name in tt.TRUTH[key]
                  if pix[max(0, y - 4):y + 5, max(0, x - 4):x + 5].mean() >= 0.5]
            return "|".join(ks) or "none"

        _emit(measure(desc, ans, cloud, truth_of, covers), key)


def mosd(clf, paths):
    from pathlib import Path

    from planerel.features.object_eval import frame_truth

    sys.path.insert(0, HERE)
    import real_mosd

    for p in map(Path, paths):
        _, cat, ty = real_mosd.category(p.stem)
        ((_, cloud, truth, _),) = list(frame_truth(p))
        desc, ans, covers = _describe(clf, cloud)
        tr = np.asarray(truth)

        def truth_of(pix, tr=tr, cat=cat, ty=ty):
            v = tr[pix]
            return "bg" if (v >= 1).sum() < 0.5 * pix.sum() else f"{ty or 'object'}:{cat}"

        _emit(measure(desc, ans, cloud, truth_of, covers), "mosd/" + p.stem)


def _majority(img, pix, names):
    v = img[pix]
    v = v[v >= 0].astype(int)
    if v.size < 0.5 * pix.sum():
        return "none"
    k = int(np.bincount(v).argmax())
    return "none" if (v == k).sum() < 0.5 * pix.sum() else names.get(k, "none")


def indep(clf, paths):
    import planerel

    for p in paths:
        cloud = planerel.read(p)
        tr = np.load(p.replace(".npy", ".objects.npy"))
        with open(p.replace(".npy", ".json")) as fh:
            names = {o["index"]: o["kind"] for o in json.load(fh)["objects"]}
        desc, ans, covers = _describe(clf, cloud)
        _emit(measure(desc, ans, cloud, lambda pix, tr=tr, names=names: _majority(tr, pix, names), covers),
              f"{os.path.basename(os.path.dirname(os.path.abspath(p)))}/{os.path.basename(p)}")


def train(clf, dataset):
    from planerel.features.dataset import load_manifest, load_scene

    for row in load_manifest(dataset):
        cloud, gt, meta = load_scene(dataset, row.scene_id)
        names = {o["index"]: f"{o['class']}:{o.get('kind') or ''}" for o in meta["objects"]}
        g = np.asarray(gt)
        img = np.full(g.shape, -1)
        for p in meta["planes"]:
            img[g == p["index"]] = p["object_index"]
        desc, ans, covers = _describe(clf, cloud)
        _emit(measure(desc, ans, cloud, lambda pix, img=img, names=names: _majority(img, pix, names), covers),
              "train/" + row.scene_id)


def kind(truth: str) -> str:
    """The summary's class of a record's truth."""
    if truth in ("false", "unscored"):
        return truth
    if truth.startswith("round"):
        return "round"
    if truth.startswith("box") or truth in ("touching box", "tall box"):
        return "box"
    if truth.startswith("object:"):
        return "mosd object (" + truth.split(":")[1] + ")"
    return "other"


#: (measure, how a pair's value keeps the object's skirt: "max" = the largest value of its pairs
#: is the one a "refuse under t" test would have to pass, "min" the smallest)
SUMMARY = (("fill", "max"), ("circ_res", "max"), ("width_ratio", "max"), ("cover", "max"),
           ("convex_radius", "max"), ("edge_bow_mm", "max"))


def _value(p, name):
    if name == "convex_radius":  # a face bulging towards the sensor: its radius; else flat
        r = p.get("bend_radius")
        return abs(r) if r is not None and r < 0 else 1e9
    v = p.get(name)
    return v if v is not None else float("nan")


def summary(files):
    recs = []
    for fn in files:
        with open(fn) as fh:
            recs += [json.loads(line) for line in fh if line.strip()]
    groups = {}
    for r in recs:
        k = kind(r["truth"])
        if r["klass"] != "box" and k != "round":
            continue
        groups.setdefault(k, []).append(r)
    for k, rs in sorted(groups.items()):
        only = sum(not any(c == "box" and i != 1 for c, i in r["fired"]) for r in rs)
        print(f"{k}: {len(rs)} proposals ({sum(r['klass'] == 'box' for r in rs)} answered box, "
              f"{only} proved box by skirt/2 alone)")
        for name, how in SUMMARY:
            vals = []
            for r in rs:
                v = [_value(p, name) for p in r["pairs"]]
                v = [x for x in v if x == x]
                if v:
                    vals.append((max(v) if how == "max" else min(v), r["src"], r["obj"]))
            vals.sort()
            low = ", ".join(f"{v:.3g} ({s.split('/')[-1][:24]} {o})" for v, s, o in vals[:3])
            print(f"    {name:14s} lowest {low}; median {vals[len(vals) // 2][0]:.3g}")


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) < 2:
        print(__doc__)
        return 2
    cmd = argv[0]
    if cmd == "summary":
        summary(argv[1:])
        return 0
    from planerel.classify.classifier import Classifier

    many = {"hunt": hunt, "mosd": mosd, "indep": indep}
    one = {"tabletop": tabletop, "train": train}
    if cmd not in many and cmd not in one:
        print(__doc__)
        return 2
    with Classifier(argv[1]) as clf:
        if cmd in many:
            many[cmd](clf, argv[2:])
        else:
            one[cmd](clf, argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main())
