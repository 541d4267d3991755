"""What lies around every level plane of labelled real frames: the measure of a "top among
tops" test (top53, docs/objects.md "Boxes seen only by their top, packed side by side").  A
measuring tool; nothing of it is used by the classifier.

Usage::

    top_ring.py [DIR ...] [--independent DIR ...] [--model out/model] [--up SET=X,Y,Z ...] [--json F]
                [--drop 0.4] [--above 0.15] [--fill 0.85] [--step 0.02]

``DIR`` is a set folder holding ``labels.json`` (:mod:`real_unseen`) or a folder of such set
folders.  Each frame is read, segmented and described as the classifier does (``--model``'s
settings; the frame's ``up`` when labelled, or ``--up SET=X,Y,Z`` for every frame of a set
folder whose name ends with ``SET``: a mount whose up the estimate misses).  Every plane that
could be a product box's top is measured (:func:`ring_shares`): level (incline <= 10 degrees),
0.05-0.6 m long, at least 0.04 m wide, 300 pixels or more, not the floor.  Its *ring* is the
measured points within ``lying_ring`` pixels of it (the ``lying/1`` ring, its own pieces left
out); heights are along ``up`` from the top's centroid.  Per plane: ``drop`` (the ring's share
more than max(1.5 cm, 3 x the top's RMS) below the top: a step down), ``above`` (the share
above the top's level), ``level`` (within it), ``step`` (median depth of the drop, m),
``missing`` (share of ring pixels without depth), ``fill`` (area / (length x width)), and
``where`` the plane lies: ``box`` (half of its pixels in a labelled box's rectangle), ``other``
(in another class's rectangle or an unscored one) or ``outside``.  The candidate test counts
the planes with ``drop >= --drop``, ``above <= --above``, ``fill >= --fill`` and
``step >= --step`` by ``where``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

#: a product box's top: level within this (degrees), this long (m) and this wide (m)
TOP_INCLINE = 10.0
TOP_LENGTH = (0.05, 0.6)
TOP_WIDTH = 0.04
TOP_PIXELS = 300


def top_like(t, floor=None) -> bool:
    """True for a plane that could be a product box's top seen from above."""
    return (t.label != floor and t.incline <= TOP_INCLINE
            and TOP_LENGTH[0] <= t.length <= TOP_LENGTH[1] and t.width >= TOP_WIDTH)


def ring_shares(planes, params, xyz, t) -> dict | None:
    """The ring around plane ``t`` (``lying_ring`` pixels at the image's width, ``t``'s own
    pieces left out as :func:`planerel.features.lying._ground_around` does): the shares
    of its measured points that drop below ``t``'s level, lie above it or level with it, the
    median drop (m), the share of ring pixels without depth and ``t``'s fill.  None when the
    ring holds fewer than 20 measured points."""
    from scipy import ndimage as ndi

    from planerel.features import relations as R

    lab = np.asarray(planes.labels)
    up = np.asarray(planes.up, float)
    k = R._ring_width(lab, params)
    tm = lab == t.label
    ring = ndi.binary_dilation(tm, np.ones((2 * k + 1, 2 * k + 1), bool)) & ~tm
    tn, tc = np.asarray(t.normal, float), np.asarray(t.centroid, float)
    cos_tilt = math.cos(math.radians(params.skirt_tilted))
    own = [q.label for q in planes if q.label != t.label
           and abs(float(np.asarray(q.normal, float) @ tn)) >= cos_tilt
           and abs(float((np.asarray(q.centroid, float) - tc) @ tn)) <= params.lying_rise]
    ring &= ~np.isin(lab, own)
    pts = xyz[ring]
    ok = np.isfinite(pts).all(axis=1) & (pts[:, 2] > 0)
    if ok.sum() < 20:
        return None
    h = (pts[ok] - tc) @ up
    tol = max(0.005, 3.0 * float(t.rms))
    low = h < -max(0.015, tol)
    return {"drop": float(low.mean()), "above": float((h > tol).mean()),
            "level": float((np.abs(h) <= tol).mean()),
            "step": float(np.median(-h[low])) if low.any() else 0.0,
            "missing": float(1.0 - ok.mean()),
            "fill": float(t.area / max(t.length * t.width, 1e-9))}


def passes(row, drop=0.4, above=0.15, fill=0.85, step=0.02) -> bool:
    """The candidate "top among tops" test on one row of :func:`frame_rows`."""
    return (row["drop"] >= drop and row["above"] <= above and row["fill"] >= fill
            and row["step"] >= step)


def frame_rows(desc, cloud, frame, name="") -> list:
    """One row per top-like plane of a described frame (:func:`ring_shares`, ``where``)."""
    from real_unseen import rect_mask

    ps = desc.planes
    lab = np.asarray(desc.labels)
    boxes = [rect_mask(lab.shape, o["box"]) for o in frame.get("objects", ())
             if o["class"] == "box"]
    others = ([rect_mask(lab.shape, o["box"]) for o in frame.get("objects", ())
               if o["class"] != "box"]
              + [rect_mask(lab.shape, b) for b in frame.get("unscored", ())])
    rows = []
    for t in ps:
        if not top_like(t, ps.floor):
            continue
        tm = lab == t.label
        n = int(tm.sum())
        if n < TOP_PIXELS:
            continue
        sh = ring_shares(ps, desc.relations.params, cloud.xyz, t)
        if sh is None:
            continue
        where = ("box" if any((tm & b).sum() >= 0.5 * n for b in boxes) else
                 "other" if any((tm & b).sum() >= 0.5 * n for b in others) else "outside")
        rows.append({"frame": name, "plane": desc.plane_id(t.label), "where": where,
                     "incline": round(t.incline, 1), "length": round(t.length, 3),
                     "width": round(t.width, 3), "lying": t.label in desc.lying,
                     **{k: round(v, 3) for k, v in sh.items()}})
    return rows


def independent_rows(clf, folder) -> list:
    """:func:`frame_rows` for an independent set's scenes (``iNNNN.npy`` with its
    ``.objects.npy`` truth, :mod:`independent_scenes`): ``where`` is ``box`` when half of
    the plane's pixels are a box's, ``other`` another object's, ``outside`` the
    environment's (floor, walls, landings)."""
    from planerel.features.facts import describe_scene
    from planerel.ilp.scenes import segment_cached
    from planerel.io import readers as io

    rows = []
    for p in sorted(Path(folder).glob("i[0-9][0-9][0-9][0-9].npy")):
        side = json.loads(p.with_suffix(".json").read_text())
        truth = np.load(p.with_name(p.stem + ".objects.npy"))
        cls = {o["index"]: o["class"] for o in side["objects"]}
        cloud = io.read(p)
        labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
        desc = describe_scene(cloud, labels, scene_id="s", **clf._describe_kw)
        lab = np.asarray(desc.labels)
        fake = {"objects": [], "unscored": []}
        for r in frame_rows(desc, cloud, fake, f"{Path(folder).name}/{p.stem}"):
            t = int(r["plane"].rsplit("p", 1)[1])
            ks, n = np.unique(truth[lab == t], return_counts=True)
            k = int(ks[np.argmax(n)])
            r["where"] = ("outside" if k <= 0 or n.max() < 0.5 * n.sum() else
                          "box" if cls.get(k) == "box" else "other")
            rows.append(r)
    return rows


def main(argv=None) -> int:
    from real_census import set_folders
    from real_unseen import describe_frame, read_labels

    from planerel.classify.classifier import Classifier

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dirs", nargs="*")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--up", action="append", default=[], metavar="SET=X,Y,Z")
    ap.add_argument("--independent", nargs="*", default=[], metavar="DIR",
                    help="independent sets (iNNNN.npy with .objects.npy truth)")
    ap.add_argument("--json")
    ap.add_argument("--drop", type=float, default=0.4)
    ap.add_argument("--above", type=float, default=0.15)
    ap.add_argument("--fill", type=float, default=0.85)
    ap.add_argument("--step", type=float, default=0.02)
    a = ap.parse_args(argv)
    ups = {}
    for item in a.up:
        name, _, vec = item.partition("=")
        ups[name] = [float(v) for v in vec.split(",")]
    rows = []
    with Classifier(a.model) as clf:
        for folder in set_folders(a.dirs):
            doc = read_labels(str(folder))
            given = next((v for s, v in ups.items() if str(folder).rstrip("/").endswith(s)), None)
            for fr in doc["frames"]:
                if given is not None:
                    fr = {**fr, "up": given}
                stem = os.path.splitext(os.path.basename(fr["file"]))[0]
                cloud, desc = describe_frame(clf, str(folder), fr)
                rows += frame_rows(desc, cloud, fr, f"{folder.parent.name}/{folder.name}/{stem}")
        for folder in a.independent:
            rows += independent_rows(clf, folder)
    hit = [r for r in rows if passes(r, a.drop, a.above, a.fill, a.step)]
    for r in hit:
        print(f"{r['where']:8s} {r['frame']} {r['plane']}: {r['length']:.3f} x {r['width']:.3f} m, "
              f"incline {r['incline']}, drop {r['drop']:.2f} (median {r['step']:.3f} m), above "
              f"{r['above']:.2f}, fill {r['fill']:.2f}, lying {r['lying']}")
    print(f"top-like planes {dict(Counter(r['where'] for r in rows))}; passing (drop >= {a.drop}, "
          f"above <= {a.above}, fill >= {a.fill}, step >= {a.step}): "
          f"{dict(Counter(r['where'] for r in hit))}")
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
