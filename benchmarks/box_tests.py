"""Why no box rule fires on a real box that has a proposal of its own (rule50, docs/objects.md
"Real boxes no box rule proves, test by test").  A measuring tool.

Usage::

    box_tests.py CENSUS.json [--model out/model] [--stage "no rule fires"] [--json F]

``CENSUS.json`` is :mod:`real_census`'s ``--json`` output (its rows name the set folder under
``/work`` or ``--root``, the frame, the labelled rectangle and the proposal holding the box).
Each frame is read, segmented and described as the census does (the model's settings, the
frame's ``up`` when labelled); for each box of ``--stage`` the holding proposal's planes are
listed (orientation, pixels, share inside the rectangle, size, the box-proof atoms on them:
``tall``, ``lying``, ``skirt(q)``, ``face_pair(q)``) with, per plane, the tests of the clause
it could prove:

- every vertical plane: ``tall_face/1``'s tests (:func:`tall_face_tests`, in
  :func:`planerel.features.tall_face.tall_faces`' order, each measured whatever the others
  say: shape, top hidden or capped by a strip, top not covered, grounded, free-standing, no
  next riser);
- every adjacent pair of vertical planes: ``face_pair/2``'s (angle, widths, level tops and
  bottoms, convex: :func:`planerel.features.solid.is_face_pair`);
- every horizontal or inclined plane with an adjacent vertical one: ``skirt``'s measures
  (:func:`planerel.features.solid.skirt_measures`: offset, reach, cover, beyond; the verdict
  is the relation's own);
- every non-vertical plane: ``lying/1``'s size tests and the best ground under it.

The last line of each box names the *closest* tests: the vertical plane with the fewest failed
``tall_face`` tests (and which fail).  The census's other stages can be listed with
``--stage``.
"""

from __future__ import annotations

import argparse
import functools
import json
import os
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def _floor_for_tall(planes, p, cloud, profile, shaped):
    """``(floor, source)``: the plane or virtual floor :func:`tall_faces` grounds faces on
    when no adjacent horizontal plane does (the floor plane; else, with no floor plane, the
    feet level or the speckle floor), ``(None, None)`` when none."""
    from planerel.features import relations as R

    by_label = {q.label: q for q in planes}
    floor = by_label.get(getattr(planes, "floor", None))
    if floor is not None and floor.orientation == "horizontal":
        return floor, "floor plane"
    if getattr(planes, "floor", None) is not None or p.tall_floor_fit <= 0:
        return None, None
    up = np.asarray(planes.up, float)
    if p.tall_feet_level > 0:
        found = R.feet_level([profile(q).bottom for q in planes if shaped(q)],
                             p.tall_feet_level, p.tall_feet_min)
        if found is not None:
            return R.VirtualFloor(up, found[0]), "feet level"
    if p.tall_speckle_floor > 0:
        from planerel.features.gravity import GravityParams, speckle_floor

        found = speckle_floor(cloud, planes.labels, up, 10.0,
                              GravityParams(sparse_floor=p.tall_speckle_floor))
        if found is not None:
            return R.VirtualFloor(up, -found[2]), "speckle floor"
    return None, None


def tall_face_tests(planes, relations, cloud, label, plane_id=str) -> list:
    """``tall_face/1``'s tests of the plane ``label``: ``[(test, passed, detail)]``, each
    measured whatever the others say, in :func:`tall_faces`' order.  The plane is a
    ``tall_face`` exactly when every test passes (``tests/test_box_tests.py`` checks this
    against :func:`tall_faces`).

    Parameters
    ----------
    planes : PlaneSet
        With ``labels`` and ``up``.
    relations : Relations
        :func:`planerel.features.relations.relate`'s on ``planes``.
    cloud : Cloud
        The organized cloud the planes were measured in.
    label : int
        A plane's label.
    plane_id : callable
        Names a label in the details.
    """
    from planerel.features import relations as R
    from planerel.features.solid import face_profile_of, grounded, level_under
    from planerel.features.tall_face import _cut_eye_ok, _top_cut, base_foot

    p = relations.params
    lab = planes.labels
    by_label = {q.label: q for q in planes}
    up = np.asarray(planes.up, float)
    face = by_label[label]
    profiles: dict = {}

    def profile(q):
        if q.label not in profiles:
            profiles[q.label] = face_profile_of(q, up, lab, cloud.xyz, p.profile_points)
        return profiles[q.label]

    def shaped(a):
        return R.tall_shaped(a, p, lab, cloud.xyz, up, noise=R.tall_noise(cloud, p))

    out = []
    fill = face.area / max(1e-12, face.length * face.width)
    out.append(("shape", bool(shaped(face)),
                f"vertical {face.orientation == 'vertical'}, width {face.width:.3f} "
                f"(>= {p.corner_width}"
                + (f", or >= {p.tall_narrow_width} and bend "
                   f"{R.face_bend(face, lab, cloud.xyz, up, p.profile_points):.2f} "
                   f"<= {p.tall_narrow_bend}" if 0 < p.tall_narrow_width <= face.width
                   < p.corner_width else "")
                + f"), fill {fill:.3f} (>= {p.standing_fill}), RMS/width "
                f"{face.rms / max(face.width, 1e-12):.3f} (<= {p.tall_flat})"))
    near, beside = [], []
    for r in R.adjacent_only(relations):
        if r.adjacent and r.a == label:
            b = by_label.get(r.b)
            if b is not None and b.orientation == "horizontal":
                near.append(b)
            elif b is not None and b.orientation == "vertical":
                beside.append(b)
    floor, source = _floor_for_tall(planes, p, cloud, profile, shaped)
    prof = profile(face)
    margin = functools.cache(lambda: R._blank_top_rows(cloud.xyz))
    top_row = R._reaches_top_row(face)
    cut_ok = _cut_eye_ok(prof, p)
    hidden = bool(prof.top >= -p.tall_eye or _top_cut(face, prof, p, margin))
    top = (f"top {prof.top:+.3f} m (hidden at >= {-p.tall_eye}), bottom {prof.bottom:+.3f} m, "
           f"reaches the image's top {top_row}"
           + (f" (counts at >= {-p.tall_cut_eye}: {cut_ok})" if p.tall_cut_eye > 0 else ""))
    capped = False
    if not hidden:
        if p.tall_cap <= 0:
            top += "; cap strip off"
        else:
            share, depth = R.cap_strip(face, lab, cloud.xyz, up, prof.top, p.tall_cap_tol)
            need = min(p.tall_cap_depth, p.tall_cap_ratio * (prof.hi - prof.lo))
            capped = bool(share >= p.tall_cap and depth >= need)
            top += (f"; cap strip share {share:.2f} (>= {p.tall_cap}), depth {depth:.3f} "
                    f"(>= {need:.3f})")
    out.append(("top hidden or capped", hidden or capped, top))
    if hidden and p.tall_top_cover > 0 and not top_row:
        out.append(("top not covered",
                    not R.top_covered(face, lab, cloud.xyz, p.tall_top_cover), ""))
    on = [(plane_id(g.label), grounded(face, prof, g, up, p.standing_foot, p.skirt_tol,
                                       p.skirt_step)) for g in near]
    foot = None
    if floor is not None and p.tall_floor_fit > 0:
        foot = bool(R.floor_foot(face, prof, floor, lab, cloud.xyz, up, p))
    level = None if floor is None else level_under(floor, face.centroid, up)
    ground = bool(getattr(planes, "floor", None) is None
                  and R.level_ground(face, prof, lab, cloud.xyz, up, p))
    # a pallet under it (pallet97): asked of the same floor as floor_foot
    base = None
    if floor is not None and p.tall_base > 0:
        base = bool(base_foot(face, prof, floor, lab, cloud.xyz, up, p))
    out.append(("grounded", any(g for _, g in on) or bool(foot) or ground or bool(base),
                f"adjacent horizontal planes {on or 'none'}; {source or 'no floor'}"
                + ("" if level is None else f" at {level:+.3f} m under it, floor_foot {foot}")
                + ("" if base is None else f", base_foot {base}")
                + f"; level unplaned ground {ground}"))
    taller = [(plane_id(q.label), round(profile(q).top - prof.top, 3),
               R._stands_beside(face, prof, q, profile(q), lab, cloud.xyz, p)) for q in beside]
    out.append(("free-standing", not any(d > p.skirt_tol and not s for _, d, s in taller),
                f"adjacent upright planes (top above its own, stands beside) {taller or 'none'}"))
    if not hidden:
        out.append(("no next riser", not R._next_riser(face, prof, planes, profile, p), ""))
    return out


def face_pair_tests(desc, cloud, a, b) -> tuple:
    """``(holds, detail)`` of ``face_pair/2`` for two adjacent vertical planes."""
    from planerel.features.solid import face_profile_of, is_face_pair

    p = desc.relations.params
    up = np.asarray(desc.planes.up, float)
    lab = desc.planes.labels
    r = desc.relations.get(a.label, b.label)
    pa, pb = (face_profile_of(q, up, lab, cloud.xyz) for q in (a, b))
    span = min(pa.top - pa.bottom, pb.top - pb.bottom)
    tol = min(p.face_pair_level, p.face_pair_level_share * span)
    shape = is_face_pair(a, b, pa, pb, p.face_pair_level, p.face_pair_width,
                         p.face_pair_level_share)
    return bool(r.face_pair), (f"angle {r.angle:.1f} (>= {p.face_pair_angle}), widths "
                               f"{a.width:.3f} {b.width:.3f} (>= {p.face_pair_width}), tops "
                               f"{abs(pa.top - pb.top):.3f} and bottoms "
                               f"{abs(pa.bottom - pb.bottom):.3f} apart (<= {tol:.3f}); "
                               f"widths, levels and convexity {shape}")


def _box_rows(desc, cloud, row, lab):
    """The lines for one census row."""
    from real_unseen import rect_mask

    from planerel.features import relations as R
    from planerel.features.lying import top_sized
    from planerel.features.solid import face_profile_of, skirt_measures

    pid = desc.plane_id
    ps = desc.planes
    p = desc.relations.params
    up = np.asarray(ps.up, float)
    by_label = {q.label: q for q in ps}
    obj = {o.id: o for o in desc.objects}[row["proposal"]]
    m = rect_mask(lab.shape, row["box"])
    mine = [by_label[L] for L in obj.planes if L in by_label]
    lines = [f"-- {row['what'][:90]} | range {row['range']} m | {row['proposal']}: "
             f"{len(mine)} planes, planar fraction {row['planar_fraction']:.2f}, "
             f"{row['share_inside']:.2f} of it in the rectangle"]
    best = None
    for q in mine:
        pm = lab == q.label
        atoms = [n for n, s in (("tall", desc.tall), ("lying", desc.lying)) if q.label in s]
        for r in desc.relations:
            if r.a == q.label:
                atoms += [f"{n}({pid(r.b)})" for n in ("skirt", "face_pair") if getattr(r, n)]
        inc = f" {q.incline:.0f} deg" if q.orientation == "inclined" else ""
        lines.append(f"   {pid(q.label)} {q.orientation}{inc}: {int(pm.sum())} px, "
                     f"{(pm & m).sum() / max(1, pm.sum()):.2f} inside, {q.width:.3f} x "
                     f"{q.length:.3f} m, area {q.area:.4f} m^2, atoms {atoms or '-'}")
        if q.orientation == "vertical":
            tests = tall_face_tests(ps, desc.relations, cloud, q.label, pid)
            for name, ok, detail in tests:
                lines.append(f"      tall_face {'ok  ' if ok else 'FAIL'} {name}: {detail}")
            failed = [n for n, ok, _ in tests if not ok]
            if best is None or len(failed) < len(best[1]):
                best = (pid(q.label), failed)
        else:
            top_like = top_sized(q, p)
            grounds = []
            for g in ps:
                if g.orientation != "horizontal" or g.label == q.label:
                    continue
                gn = np.asarray(g.normal, float)
                rise = float(gn @ (np.asarray(q.centroid) - np.asarray(g.centroid))) / float(gn @ up)
                if 0 < rise <= 0.5:
                    r = desc.relations.get(q.label, g.label)
                    grounds.append((round(rise, 3), pid(g.label), round(g.area, 3),
                                    bool(r is not None and r.adjacent),
                                    R._lies_on(q, g, up, p)))
            lines.append(f"      lying: size and incline {top_like} (incline <= "
                         f"{p.skirt_tilted}, length {p.lying_min_length}-{p.lying_length}, width "
                         f">= {p.lying_width}); grounds under it (rise, plane, area, adjacent, "
                         f"lies on) {sorted(grounds)[:3] or 'none'} (area >= "
                         f"{p.lying_ground * q.area:.3f})")
            for f in mine:
                if f.orientation != "vertical":
                    continue
                r = desc.relations.get(q.label, f.label)
                if r is None or not r.adjacent:
                    continue
                prof = face_profile_of(f, up, ps.labels, cloud.xyz)
                off, reach, cover, beyond = skirt_measures(q, f, up, prof, ps.labels,
                                                           cloud.xyz, cloud.intrinsics)
                lines.append(f"      skirt {pid(f.label)}: {r.skirt}; top's incline "
                             f"{q.incline:.1f} (<= {p.skirt_top_tilt} + its noise), offset {off:.3f} "
                             f"(<= {p.skirt_tol}), reach {reach:.3f}, cover {cover:.2f} "
                             f"(>= {p.skirt_cover}), beyond {beyond:.3f} (<= {p.skirt_beyond})")
    verts = [q for q in mine if q.orientation == "vertical"]
    for i, a in enumerate(verts):
        for b in verts[i + 1:]:
            r = desc.relations.get(a.label, b.label)
            if r is not None and r.adjacent:
                holds, detail = face_pair_tests(desc, cloud, a, b)
                lines.append(f"   face_pair {pid(a.label)}-{pid(b.label)}: {holds}; {detail}")
    nh = sum(q.orientation == "horizontal" for q in mine)
    lines.append(f"   nhorizontal {nh}; closest tall_face: "
                 + ("no vertical plane" if best is None else
                    f"{best[0]} fails {', '.join(best[1]) or 'nothing'}"))
    return lines, (None if best is None else {"plane": best[0], "fails": best[1]})


def main(argv=None) -> int:
    from real_unseen import describe_frame, read_labels

    from planerel.classify.classifier import Classifier

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("census")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--stage", default="no rule fires")
    ap.add_argument("--root", default="/work", help="folder the census's set names are under")
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    rows = [r for r in json.load(open(a.census)) if r["stage"] == a.stage]
    frames: dict = {}
    for r in rows:
        frames.setdefault((r["set"], r["frame"]), []).append(r)
    out = []
    with Classifier(a.model) as clf:
        for (st, stem), these in frames.items():
            folder = os.path.join(a.root, st)
            doc = read_labels(folder)
            fr = next(f for f in doc["frames"]
                      if os.path.splitext(os.path.basename(f["file"]))[0] == stem)
            cloud, desc = describe_frame(clf, folder, fr)
            ps = desc.planes
            print(f"==== {st}/{stem}: {cloud.xyz.shape[1]}x{cloud.xyz.shape[0]}, floor "
                  f"{desc.plane_id(ps.floor) if ps.floor is not None else None}, up "
                  f"{ps.up_source} (confidence {ps.up_confidence:.2f})")
            lab = np.asarray(desc.labels)
            for r in these:
                lines, closest = _box_rows(desc, cloud, r, lab)
                print("\n".join(lines))
                out.append({**r, "closest_tall_face": closest})
    if a.json:
        Path(a.json).write_text(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
