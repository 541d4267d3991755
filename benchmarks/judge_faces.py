"""How thin a face region growing resolves, on the independent judge set's staircases.

    .venv/bin/python benchmarks/judge_faces.py DIR [--variant NAME=VALUE ...]

``DIR`` is a set of ``benchmarks/independent_scenes.py make``.  For every true face
(``iNNNN.planes.npy``) of every judged staircase (>= 150 pixels) it measures the face's
thickness in pixels (median over image columns of its pixels in that column: a riser's
height, a tread's depth as seen) and whether the segmentation resolved it (half of its pixels
in one region, which lies at least 70 % on the face), and prints, per thickness bin, resolved
faces and the share of their pixels that lie in any region.  Then, per class, the objects that
planerel's proposals find at IoU >= 0.5 on those planes (as ``independent_scenes.py score
--true-planes`` does for the default).  Each ``--variant`` (a ``segment()`` parameter, e.g.
``min_region_scale=0.5``) is measured after the default, in the same run.  The faces are
counted twice: on the segmentation, and on the label image after describing the scene
(``describe_scene``'s labels: stepped planes split, far flights' faces from the stepped profile
of their unassigned points, :mod:`planerel.features.stairfit`).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

BINS = ((1, 2), (2, 3), (3, 4), (4, 6), (6, 9), (9, 13), (13, 10**6))


def _value(text):
    for cast in (int, float):
        try:
            return cast(text)
        except ValueError:
            pass
    return text


def face_stats(lab, truth, planes, stairs, counts):
    """Add the faces of the staircases ``stairs`` (object ids) to ``counts[bin] = [resolved,
    faces, share in a region]``; ``lab`` is the segmentation, ``planes`` the true planes."""
    for k in stairs:
        m = truth == k
        for pl in np.unique(planes[m]):
            pm = m & (planes == pl)
            if pl < 0 or pm.sum() < 10:
                continue
            cols = pm.sum(axis=0)
            thick = float(np.median(cols[cols > 0]))
            seg = lab[pm]
            seg = seg[seg >= 0]
            ok = False
            if seg.size:
                best = np.bincount(seg).argmax()
                ok = ((seg == best).sum() >= 0.5 * pm.sum()
                      and (pm & (lab == best)).sum() >= 0.7 * (lab == best).sum())
            b = next(b for b in BINS if b[0] <= thick < b[1])
            counts[b][0] += ok
            counts[b][1] += 1
            counts[b][2] += float((lab[pm] >= 0).mean())


def measure(out, params, min_pixels=150):
    from planerel.features.object_eval import frame_proposals, score_objects
    from planerel.io import readers as io
    from planerel.segment import segment

    counts = {b: [0, 0, 0.0] for b in BINS}
    described = {b: [0, 0, 0.0] for b in BINS}
    found = {}
    for p in sorted(Path(out).glob("i[0-9][0-9][0-9][0-9].npy")):
        side = json.loads(p.with_suffix(".json").read_text())
        truth = np.load(p.with_name(p.stem + ".objects.npy"))
        cloud = io.read(p)
        lab = segment(cloud, **params).labels
        judged = [o for o in side["objects"] if (truth == o["index"]).sum() >= min_pixels]
        planes = np.load(p.with_name(p.stem + ".planes.npy"))
        stairs = [o["index"] for o in judged if o["class"] == "stairs"]
        face_stats(lab, truth, planes, stairs, counts)
        prop, desc, _ms = frame_proposals(cloud, labels=lab)
        face_stats(np.asarray(desc.labels), truth, planes, stairs, described)
        sc = score_objects(prop, truth, min_iou=0.5)
        for o in judged:
            d = found.setdefault(o["class"], [0, 0])
            d[0] += sc.best_iou.get(o["index"], 0.0) >= 0.5
            d[1] += 1
    return counts, found, described


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir")
    ap.add_argument("--variant", action="append", default=[], metavar="NAME=VALUE")
    a = ap.parse_args(argv)
    runs = [("default", {})] + [(v, {v.split("=", 1)[0]: _value(v.split("=", 1)[1])}) for v in a.variant]
    for name, params in runs:
        counts, found, described = measure(a.dir, params)
        print(f"== {name}")
        for what, cs in (("segmentation", counts), ("described", described)):
            print(f"  staircase faces resolved by thickness (px), {what}: " + "; ".join(
                f"{b[0]}-{b[1] - 1 if b[1] < 10**6 else '+'} {c[0]}/{c[1]} ({c[2] / max(c[1], 1):.2f} in a region)"
                for b, c in cs.items()))
        print("  objects found by the proposals: " + ", ".join(f"{c} {v[0]}/{v[1]}" for c, v in sorted(found.items())))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
