"""Frames with no floor plane: the faces ``tall_face/1`` would add with a floor level taken from
the feet of upright faces (feet44, docs/objects.md "A floor level from the feet of upright
faces"; :attr:`planerel.features.relations.RelationParams.tall_feet_level`, off by default).
A measuring tool: the measurements it made found no margin, so the switch stays off.

Usage::

    feet_level.py MODEL DIR [DIR ...] [--tol 0.03 0.05] [--up X,Y,Z]

``DIR`` is a labelled set (``labels.json``, :mod:`real_unseen`) or an independent set
(``iNNNN.npy`` with its ``.objects.npy`` and ``.json``).  Every frame is segmented and described
with ``MODEL``'s settings (the frame's ``up`` when labelled, else estimated; an independent
scene's sidecar up; ``--up`` forces one, camera frame).  On the frames where no floor plane is
found, per shaped upright plane (``tall_faces``' shape tests): its kind (``box`` when half its
pixels lie in a ``box`` rectangle, ``uns`` in an ``unscored`` one, else ``non``; on an
independent scene the generator's majority object), its foot and top levels; and per ``--tol``:
the shared feet level (:func:`planerel.features.tall_face.feet_level`: level, spread, count),
the share of the frame's measured points more than 5 cm under it, and the tall faces the switch
adds.  The last line totals the added tall faces by kind.
"""

from __future__ import annotations

import argparse
import glob
import json
import os
import sys
from dataclasses import replace

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def _frames(d):
    """``(set, file, path, labels.json frame or None, truth path or None)`` of a set folder."""
    if os.path.exists(os.path.join(d, "labels.json")):
        doc = json.load(open(os.path.join(d, "labels.json")))
        for fr in doc["frames"]:
            yield doc.get("set", os.path.basename(d)), fr["file"], os.path.join(d, fr["file"]), fr, None
    else:
        for p in sorted(glob.glob(os.path.join(d, "i*[0-9].npy"))):
            yield os.path.basename(d), os.path.basename(p), p, None, p.replace(".npy", ".objects.npy")


def _kinds(lab, fr, truth_path, path):
    """A function: a plane's pixel mask -> its kind (see the module's docstring)."""
    sys.path.insert(0, HERE)
    from real_unseen import rect_mask

    if fr is not None:
        objs = fr.get("objects", [])
        boxes = [rect_mask(lab.shape, o["box"]) for o in objs if o["class"] == "box"]
        unsc = [rect_mask(lab.shape, b) for b in fr.get("unscored", [])]

        def kind(pm):
            n = pm.sum()
            if any((pm & m).sum() >= 0.5 * n for m in boxes):
                return "box"
            return "uns" if any((pm & m).sum() >= 0.5 * n for m in unsc) else "non"
        return kind
    truth = np.load(truth_path)
    meta = json.load(open(path.replace(".npy", ".json")))
    cls = {o["index"]: o["class"] + ":" + o.get("kind", "") for o in meta["objects"]}

    def kind(pm):
        v, c = np.unique(truth[pm], return_counts=True)
        k = cls.get(int(v[np.argmax(c)]), "bg")
        return "box" if k.startswith("box") else f"non({k})"
    return kind


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("model")
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--tol", type=float, nargs="+", default=[0.03, 0.05])
    ap.add_argument("--up", default=None, help="X,Y,Z: the up vector in the camera frame")
    a = ap.parse_args(argv)
    import planerel
    from planerel.classify.classifier import Classifier
    from planerel.features.facts import describe_scene
    from planerel.features.relations import feet_level, tall_faces
    from planerel.features.solid import face_profile_of
    from planerel.ilp.scenes import segment_cached

    forced = None if a.up is None else np.asarray(a.up.split(","), float)
    tot = {t: {"box": 0, "non": 0, "uns": 0} for t in a.tol}
    n_frames = n_nofloor = 0
    with Classifier(a.model) as clf:
        for d in a.dirs:
            for setname, fname, path, fr, truth_path in _frames(d.rstrip("/")):
                n_frames += 1
                if fr is not None:
                    cloud = planerel.read(path, intrinsics=fr.get("intrinsics"),
                                          depth_scale=fr.get("depth_scale"))
                    up = None if fr.get("up") is None else np.asarray(fr["up"], float)
                else:
                    cloud, up = planerel.read(path), None
                up = forced if forced is not None else up
                labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
                desc = describe_scene(cloud, labels, scene_id="s", up=up, **clf._describe_kw)
                ps = desc.planes
                if ps.floor is not None:
                    continue
                n_nofloor += 1
                lab, xyz = np.asarray(ps.labels), cloud.xyz
                upv = np.asarray(ps.up, float)
                kind = _kinds(lab, fr, truth_path, path)
                rel = desc.relations
                p = rel.params
                base = tall_faces(ps, rel, cloud, {})
                shaped = [q for q in ps if q.orientation == "vertical" and q.width >= p.corner_width
                          and q.area >= p.standing_fill * q.length * q.width
                          and (p.tall_flat <= 0 or q.rms <= p.tall_flat * q.width)]
                profs = {q.label: face_profile_of(q, upv, lab, xyz, p.profile_points) for q in shaped}
                z = xyz[..., 2]
                levels = xyz[np.isfinite(z) & (z > 0)] @ upv
                feet = " ".join(f"{desc.plane_id(q.label)}[{kind(lab == q.label)}] "
                                f"b{profs[q.label].bottom:+.2f} t{profs[q.label].top:+.2f}"
                                for q in shaped)
                print(f"{setname}/{fname}: up {ps.up_source} conf {ps.up_confidence:.2f}; "
                      f"shaped feet: {feet}")
                for t in a.tol:
                    fl = feet_level([pr.bottom for pr in profs.values()], t, p.tall_feet_min)
                    if fl is None:
                        print(f"   tol {t}: no shared feet level")
                        continue
                    below = float((levels < fl[0] - 0.05).mean())
                    new = tall_faces(ps, replace(rel, params=replace(p, tall_feet_level=t)),
                                     cloud, {}) - base
                    ks = [(desc.plane_id(lbl), kind(lab == lbl)) for lbl in sorted(new)]
                    for _, k in ks:
                        tot[t][k if k in ("box", "uns") else "non"] += 1
                    print(f"   tol {t}: level {fl[0]:+.3f} spread {fl[1]:.3f} n {fl[2]}; points "
                          f"below level-5cm {below:.3f}; new tall: {ks}")
                sys.stdout.flush()
    print(f"frames {n_frames}, no floor plane {n_nofloor}; new tall faces per tol: {tot}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
