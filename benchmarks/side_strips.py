"""Side strips: points no plane took that continue an upright face's left or right edge behind
it, as a box's side seen edge-on would (strip42, docs/objects.md "A box seen as one upright
face: the strip of its side, measured (strip42)").  A measuring tool, not a relation of the
model: the measurements it made found no margin between boxes and other things.

For each end of a vertical face along its horizontal axis, each pixel row of the face whose end
pixel is measured is walked outward from that pixel, up to ``k`` pixels (``W / 40``: 32 at
1280, 16 at 640, 8 at 320).  The walk takes a pixel while its point is unassigned (label < 0),
measured, within ``htol`` of the face's height span, within ``tol`` of the edge along the
face's axis (``|e|``), no more than ``jump`` farther behind the face than the walk's last point
and not more than 5 mm nearer; it stops at the first pixel that fails.  The row holds the strip
when the walk reached ``behind[0]`` or more behind the face and its farthest point lies within
``phi`` times that depth of the edge (a strip at 70 degrees or more to the face: a curved
surface that goes on at 45 degrees stops there).  Per end: ``view`` (degrees; the ray through
the edge point, outward along the face's axis against its normal: negative when a side at 90
degrees there faces the sensor, positive when the face hides it), ``share`` (rows holding the
strip / rows measured), ``depth`` (m, the 90th percentile of the rows' depths), ``width_px``
(median pixels walked).

Usage::

    side_strips.py real MODEL SETDIR [SETDIR ...] [--summary]
        one line per vertical plane of >= 100 px of every labelled frame (benchmarks/real_unseen.py
        folders), with the plane's proposal, its class answer, the labelled rectangle it lies in
        (>= 50 % of its pixels), the two ends' strips and the top-edge strip of
        planerel.features.tall_face.cap_strip; --summary: per tag (box / none / unscored /
        stairs / ramp), how many single-plane proposals of at most 0.3 m (plane width and
        height span) carry a strip (a side whose view <= -5, share >= 0.5, depth >= 0.03)
    side_strips.py fit MODEL SETDIR FILE PLANE_ID [PLANE_ID ...]
        the named planes' strips, each with a plane fitted to its points (RMS, angle to the face)
    side_strips.py tabletop MODEL OSD UOIS
        benchmarks/real_tabletop.py's frames: per single-plane proposal of at most 0.3 m whose
        plane is vertical, its strips and the kind of the labelled point it holds
    side_strips.py synth DATASET MODEL f|n
        the positives (box.f) or negatives (box.n) the model's learning was given (MODEL/aleph),
        described as the learner describes them: per object its vertical plane with the best
        strip
"""

from __future__ import annotations

import math
import os
import sys

import numpy as np

#: the defaults the measurements of docs/objects.md used
TOL = 0.015
JUMP = 0.03
PHI = 0.35
BEHIND = (0.01, 0.6)
HTOL = 0.02


def side_strips(face, labels, xyz, up, *, k=None, tol=TOL, jump=JUMP, phi=PHI, behind=BEHIND,
                htol=HTOL) -> dict:
    """The strips on both ends of a vertical face (the module's docstring): ``{"L": ..., "R":
    ...}`` (L the end at the face's smaller pixel columns), each a dict of ``view``, ``share``,
    ``depth``, ``width_px``, ``rows``; plus ``"span"``, the face's height span (m, 2nd-98th
    percentile of its points' heights)."""
    labels = np.asarray(labels)
    H, W = labels.shape
    k = max(3, round(W / 40)) if k is None else int(k)
    n = np.asarray(face.normal, float)
    c = np.asarray(face.centroid, float)
    if n @ c < 0:
        n = -n                                    # away from the sensor
    d0 = float(n @ c)
    up = np.asarray(up, float)
    a = np.cross(up, n)
    a /= np.linalg.norm(a)
    m = labels == face.label
    pts = xyz[m]
    pts = pts[np.isfinite(pts).all(1)]
    out = {"span": 0.0}
    if len(pts) < 3:
        for side in "LR":
            out[side] = {"view": float("nan"), "share": 0.0, "depth": 0.0, "width_px": 0.0,
                         "rows": 0, "points": np.zeros((0, 3))}
        return out
    hh = pts @ up
    top, bot = float(np.percentile(hh, 98)), float(np.percentile(hh, 2))
    out["span"] = top - bot
    amid = float(np.median(pts @ a))
    r0, _c0, r1, _c1 = (int(v) for v in face.bbox)
    for side in "LR":
        nrows, depths, widths, views, kept = 0, [], [], [], []
        for r in range(r0, r1):
            cols = np.nonzero(m[r])[0]
            if cols.size == 0:
                continue
            ce = int(cols[0] if side == "L" else cols[-1])
            pe = xyz[r, ce]
            if not np.isfinite(pe).all() or not bot <= float(pe @ up) <= top:
                continue
            nrows += 1
            e0 = float(pe @ a)
            s = 1.0 if e0 > amid else -1.0        # outward along the face's axis
            ray = pe / np.linalg.norm(pe)
            views.append(math.degrees(math.atan2(s * float(ray @ a), float(ray @ n))))
            step = -1 if side == "L" else 1
            prev, far, walked, row = 0.0, None, 0, []
            for j in range(1, k + 1):
                cx = ce + step * j
                if not 0 <= cx < W or labels[r, cx] >= 0:
                    break
                p = xyz[r, cx]
                if not np.isfinite(p).all():
                    break
                b = float(p @ n) - d0
                e = s * (float(p @ a) - e0)
                h = float(p @ up)
                if (abs(e) > tol or b < prev - 0.005 or b - prev > jump
                        or not bot - htol <= h <= top + htol):
                    break
                walked += 1
                row.append(p)
                if far is None or b > far[0]:
                    far = (b, e)
                prev = max(prev, b)
            if far is not None and far[0] >= behind[0] and far[0] <= behind[1] \
                    and abs(far[1]) <= phi * far[0]:
                depths.append(far[0])
                widths.append(walked)
                kept.extend(row)
        out[side] = {"view": float(np.median(views)) if views else float("nan"),
                     "share": len(depths) / nrows if nrows else 0.0,
                     "depth": float(np.percentile(depths, 90)) if depths else 0.0,
                     "width_px": float(np.median(widths)) if widths else 0.0,
                     "rows": nrows,
                     "points": np.asarray(kept, float).reshape(-1, 3)}
    return out


def strip_plane(points, normal) -> tuple[float, float]:
    """A plane fitted to a strip's points (``side_strips(...)[end]["points"]``): its RMS (m) and
    its angle to the face (degrees, 0-90; a box's side: 90).  NaN, NaN under 10 points."""
    pts = np.asarray(points, float)
    if len(pts) < 10:
        return float("nan"), float("nan")
    _, sv, vt = np.linalg.svd(pts - pts.mean(0), full_matrices=False)
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    return float(sv[2] / math.sqrt(len(pts))), math.degrees(math.acos(min(1.0, abs(float(vt[2] @ n)))))


def has_strip(res: dict, view=-5.0, share=0.5, depth=0.03) -> bool:
    """A side that faces the sensor by ``-view`` degrees or more holds a strip on ``share`` of
    its rows, ``depth`` m deep or more."""
    return any(res[s]["view"] <= view and res[s]["share"] >= share and res[s]["depth"] >= depth
               for s in "LR")


def _fmt(res):
    return " | ".join(f"{s} v{res[s]['view']:+5.1f} sh{res[s]['share']:.2f} dp{res[s]['depth']:.3f}"
                      f" wpx{res[s]['width_px']:.0f}" for s in "LR")


def real(model, folders, summary=False):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from real_unseen import read_labels, rect_mask

    import planerel
    from planerel.classify.classifier import Classifier
    from planerel.features.facts import describe_scene
    from planerel.features.relations import cap_strip
    from planerel.features.solid import face_profile_of
    from planerel.ilp.scenes import segment_cached

    counts = {}
    with Classifier(model) as clf:
        for folder in folders:
            if not os.path.exists(os.path.join(folder, "labels.json")):
                print(f"{folder}: no labels.json, skipped", file=sys.stderr)
                continue
            doc = read_labels(folder)
            name = doc.get("set", os.path.basename(os.path.normpath(folder)))
            for fr in doc["frames"]:
                cloud = planerel.read(os.path.join(folder, fr["file"]),
                                      intrinsics=fr.get("intrinsics"),
                                      depth_scale=fr.get("depth_scale"))
                labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
                upv = fr.get("up")
                desc = describe_scene(cloud, labels, scene_id="s",
                                      up=None if upv is None else np.asarray(upv, float),
                                      **clf._describe_kw)
                ans = clf.answer_description(desc, xyz=cloud.xyz)
                lab = np.asarray(desc.labels)
                up = np.asarray(desc.planes.up, float)
                objs = [(o, rect_mask(lab.shape, o["box"])) for o in fr.get("objects", [])]
                uns = [rect_mask(lab.shape, b) for b in fr.get("unscored", [])]
                owner = {lb: o for o in ans for lb in o.labels}
                for p in desc.planes:
                    if p.orientation != "vertical":
                        continue
                    pm = lab == p.label
                    npx = int(pm.sum())
                    if npx < 100:
                        continue
                    tag = "none"
                    for o, mm in objs:
                        if (pm & mm).sum() / npx >= 0.5:
                            tag = o["class"]
                            break
                    else:
                        if any((pm & mm).sum() / npx >= 0.5 for mm in uns):
                            tag = "unscored"
                    o = owner.get(p.label)
                    nplanes, klass = (len(o.labels), o.klass) if o else (0, "-")
                    res = side_strips(p, lab, cloud.xyz, up)
                    prof = face_profile_of(p, up, lab, cloud.xyz)
                    csh, cdp = cap_strip(p, lab, cloud.xyz, up, prof.top)
                    strip = has_strip(res)
                    if nplanes == 1 and max(p.width, res["span"]) <= 0.3:
                        cnt = counts.setdefault(tag, [0, 0, []])
                        cnt[0] += 1
                        if strip:
                            cnt[1] += 1
                            cnt[2].append(f"{name}/{fr['file']} {desc.plane_id(p.label)} ({klass})")
                    if not summary:
                        print(f"{name}/{fr['file']} {desc.plane_id(p.label)} px{npx} w{p.width:.3f}"
                              f" h{res['span']:.3f} d{p.distance:.2f} prop{nplanes}:{klass} | "
                              f"{_fmt(res)} | cap sh{csh:.2f} dp{cdp:.3f} || {tag}", flush=True)
    if summary:
        print("single-plane proposals of at most 0.3 m, a strip (view <= -5, share >= 0.5, "
              "depth >= 0.03):")
        for tag, (n, k, which) in sorted(counts.items()):
            print(f"  {tag}: {k} of {n}" + ("".join(f"\n      {w}" for w in which)))
    return counts


def fit(model, folder, file, pids):
    """The strips of the named planes of one labelled frame, with a plane fitted to each."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from real_unseen import read_labels

    import planerel
    from planerel.classify.classifier import Classifier
    from planerel.features.facts import describe_scene
    from planerel.ilp.scenes import segment_cached

    fr = next(f for f in read_labels(folder)["frames"] if f["file"] == file)
    cloud = planerel.read(os.path.join(folder, file), intrinsics=fr.get("intrinsics"),
                          depth_scale=fr.get("depth_scale"))
    with Classifier(model) as clf:
        labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
        desc = describe_scene(cloud, labels, scene_id="s", **clf._describe_kw)
    lab = np.asarray(desc.labels)
    up = np.asarray(desc.planes.up, float)
    for p in desc.planes:
        if desc.plane_id(p.label) not in pids:
            continue
        res = side_strips(p, lab, cloud.xyz, up)
        for s in "LR":
            rms, ang = strip_plane(res[s]["points"], p.normal)
            print(f"{file} {desc.plane_id(p.label)} {s}: view {res[s]['view']:+.1f} share"
                  f" {res[s]['share']:.2f} depth {res[s]['depth']:.3f} m; plane fitted to its"
                  f" {len(res[s]['points'])} points: RMS {rms * 1000:.1f} mm, {ang:.1f} degrees"
                  " to the face")


def tabletop(model, osd, uois):
    """The table-top frames of benchmarks/real_tabletop.py (OSD, UOIS): per single-plane
    proposal of at most 0.3 m whose plane is a vertical one, its strips and the kind of the
    labelled point it holds (box / round / other; none when it holds no labelled point)."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from real_tabletop import TRUTH, frames, read_frame

    from planerel.classify.classifier import Classifier
    from planerel.features.facts import describe_scene
    from planerel.ilp.scenes import segment_cached

    counts = {}
    with Classifier(model) as clf:
        for key, path, intr in frames(osd, uois):
            cloud = read_frame(path, intr)
            labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
            desc = describe_scene(cloud, labels, scene_id="s", **clf._describe_kw)
            ans = clf.answer_description(desc, xyz=cloud.xyz)
            lab = np.asarray(desc.labels)
            up = np.asarray(desc.planes.up, float)
            by = {p.label: p for p in desc.planes}
            for o in ans:
                if len(o.labels) != 1:
                    continue
                p = by.get(next(iter(o.labels)))
                if p is None or p.orientation != "vertical":
                    continue
                pm = lab == p.label
                res = side_strips(p, lab, cloud.xyz, up)
                if int(pm.sum()) < 100 or max(p.width, res["span"]) > 0.3:
                    continue
                kind = "none"
                for x, y, k, name in TRUTH[key]:
                    if pm[max(0, y - 4): y + 5, max(0, x - 4): x + 5].any():
                        kind = f"{k}:{name}"
                        break
                strip = has_strip(res)
                cnt = counts.setdefault(kind.split(":")[0], [0, 0])
                cnt[0] += 1
                cnt[1] += strip
                print(f"{key} {desc.plane_id(p.label)} w{p.width:.3f} h{res['span']:.3f}"
                      f" d{p.distance:.2f} {o.klass} | {_fmt(res)}{' STRIP' if strip else ''}"
                      f" || {kind}", flush=True)
    for k, (n, m) in sorted(counts.items()):
        print(f"  {k}: {m} of {n} with a strip")
    return counts


def synth(dataset, model, which):
    from pathlib import Path

    from planerel.classify.classifier import Classifier
    from planerel.features.dataset import describe_truth_scene, load_manifest, load_scene
    from planerel.ilp.scenes import example_rule, segment_cached

    with open(os.path.join(model, "aleph", f"box.{which}")) as fh:
        ids = [ln.strip()[4:-2] for ln in fh if ln.startswith("box(")]
    rows = {r.scene_id: r for r in load_manifest(dataset)}
    rule = example_rule(dataset)
    with Classifier(model) as clf:
        method, params = clf.method, clf.seg_params
    n_obj = n_strip = 0
    for sid in sorted({i.split("_")[0] for i in ids}):
        r = rows[sid]
        cloud, gt, meta = load_scene(dataset, sid)
        labels = segment_cached(cloud, method=method, params=params,
                                files=[Path(dataset) / r.depth, Path(dataset) / r.meta])
        desc = describe_truth_scene(cloud, labels, gt, meta, sid, r.klass, rule=rule)
        lab = np.asarray(desc.labels)
        up = np.asarray(desc.planes.up, float)
        by = {p.label: p for p in desc.planes}
        kinds = {o["id"]: o.get("kind", "") for o in meta.get("objects", [])}
        for o in desc.objects:
            if o.id not in ids:
                continue
            ps = [by[lb] for lb in o.planes if lb in by]
            best = None
            for p in ps:
                if p.orientation != "vertical":
                    continue
                res = side_strips(p, lab, cloud.xyz, up)
                key = (has_strip(res), max(res[s]["depth"] for s in "LR"))
                if best is None or key > best[0]:
                    best = (key, p, res)
            orient = "".join(p.orientation[0] for p in ps)
            if best is None:
                print(f"{o.id} {kinds.get(o.id, '')!r} n{len(ps)} {orient}: no vertical plane")
                continue
            n_obj += 1
            n_strip += best[0][0]
            _, p, res = best
            print(f"{o.id} {kinds.get(o.id, '')!r} {lab.shape[1]}px n{len(ps)} {orient}"
                  f" w{p.width:.3f} h{res['span']:.3f} d{p.distance:.2f} | {_fmt(res)}"
                  f"{' STRIP' if best[0][0] else ''}", flush=True)
    print(f"objects with a vertical plane: {n_obj}; with a strip: {n_strip}")


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) >= 3 and argv[0] == "real":
        rest = [a for a in argv[2:] if a != "--summary"]
        real(argv[1], rest, summary="--summary" in argv)
    elif len(argv) >= 5 and argv[0] == "fit":
        fit(argv[1], argv[2], argv[3], argv[4:])
    elif len(argv) == 4 and argv[0] == "tabletop":
        tabletop(argv[1], argv[2], argv[3])
    elif len(argv) == 4 and argv[0] == "synth" and argv[3] in ("f", "n"):
        synth(argv[1], argv[2], argv[3])
    else:
        print(__doc__)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
