"""How open box corners measure, on real frames or on the round part's synthetic scenes
(sensor40, docs/synthetic-world.md "Block-matching window").

    .venv/bin/python benchmarks/corner_profile.py real FILE [FILE ...] [--model out/model]
    .venv/bin/python benchmarks/corner_profile.py synth --window W [--subsample 4] [--n 120]

Every pair of planes of one described object that meet at 75-105 degrees, with >= 200 points
each (200 / subsample**2 for synthetic scenes; there both planes must lie on the ground-truth
box), segmented and described with the model's settings as ``planerel classify`` does, at the
frame's own resolution.  For the convex corners among them (each face's centroid behind the
other face's camera-facing plane) it prints

* the interior angle (180 degrees minus the angle between the faces' outward normals, PCA fits)
  on all points, and with the points within 1 cm of the shared edge left out;
* the facts' ``|90 - angle|`` (the disparity fit the ``angle`` facts use);
* the median residual of each face's points against its own plane by distance from the shared
  edge (mm, + toward the camera): a rounded edge shows as a negative band.

``--zmax`` keeps corners nearer than that (metres, default 1.1: mOSD's table-top range).
``--more`` adds, for corners whose faces are both >= 9 cm wide, the interior angle with 0-4 cm
of the edge left out (a band's opening falls, a whole-face tilt stays), and the correlation of
each corner's opening (1 cm band out) with its sensitivity to a 2 % lateral scale (a focal-
length error would make it strongly positive).
"""

from __future__ import annotations

import argparse
import itertools
import warnings
from pathlib import Path

import numpy as np

BINS = ((0, .0025), (.0025, .005), (.005, .0075), (.0075, .01), (.01, .015), (.015, .02),
        (.02, .03), (.03, .05))


def _fit(p):
    c = p.mean(0)
    n = np.linalg.svd(p - c, full_matrices=False)[2][2]
    return c, (n if n @ c < 0 else -n)


def pairs_of(clf, cloud, *, min_points: int = 200, gt_objects=None, boxes=()):
    """``[(A points, B points, facts angle)]`` of one cloud's near-perpendicular plane pairs."""
    from planerel.features.facts import describe_scene
    from planerel.ilp.scenes import segment_cached

    labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
    desc = describe_scene(cloud, labels, scene_id="s", **clf._describe_kw)
    lab = np.asarray(desc.labels)
    xyz = cloud.xyz
    planes = {p.label: p for p in desc.planes}
    out = []
    for o in desc.objects:
        for a, b in itertools.combinations(list(o.planes), 2):
            pa, pb = planes[a], planes[b]
            if pa.n_points < min_points or pb.n_points < min_points:
                continue
            d = float(np.degrees(np.arccos(min(1.0, abs(pa.normal @ pb.normal)))))
            if not 75 <= d <= 105:
                continue
            if gt_objects is not None and not any(
                    np.mean(gt_objects[lab == a] == k) > 0.8
                    and np.mean(gt_objects[lab == b] == k) > 0.8 for k in boxes):
                continue
            pts = [xyz[lab == x] for x in (a, b)]
            out.append(tuple(p[np.isfinite(p).all(1)] for p in pts) + (d,))
    return out


def summarise(pairs, zmax: float = 1.1) -> dict:
    """Interior angles, facts' deviation and the residual profile of the convex corners."""
    inter, banded, facts, profs = [], [], [], []
    for a_pts, b_pts, d in pairs:
        ca, na = _fit(a_pts)
        cb, nb = _fit(b_pts)
        if np.linalg.norm((ca + cb) / 2) > zmax:
            continue
        if not ((cb - ca) @ na < 0 and (ca - cb) @ nb < 0):
            continue
        e = np.cross(na, nb)
        e /= np.linalg.norm(e)
        l0 = np.linalg.solve(np.array([na, nb, e]), [na @ ca, nb @ cb, e @ ca])
        keep = []
        for x, c, n in ((a_pts, ca, na), (b_pts, cb, nb)):
            u = np.cross(n, e)
            u = u if (c - l0) @ u > 0 else -u
            dist, r = (x - l0) @ u, (x - c) @ n
            keep.append(x[dist > 0.01])
            profs.append([np.median(r[m]) * 1000 if (m := (dist >= lo) & (dist < hi)).sum() >= 3
                          else np.nan for lo, hi in BINS])
        inter.append(180 - np.degrees(np.arccos(np.clip(na @ nb, -1, 1))))
        if min(len(k) for k in keep) >= 10:
            banded.append(180 - np.degrees(np.arccos(np.clip(_fit(keep[0])[1] @ _fit(keep[1])[1],
                                                             -1, 1))))
        facts.append(abs(90 - d))
    inter, banded, facts = map(np.array, (inter, banded, facts))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        prof = np.nanmedian(np.array(profs), 0) if profs else np.full(len(BINS), np.nan)
    return {"n": len(inter), "interior": float(np.median(inter)) if len(inter) else np.nan,
            "share_open": float(np.mean(inter > 90)) if len(inter) else np.nan,
            "interior_band_out": float(np.median(banded)) if len(banded) else np.nan,
            "facts_dev": float(np.median(facts)) if len(facts) else np.nan,
            "profile_mm": [round(float(v), 2) for v in prof]}


def _edge_dist(a_pts, b_pts):
    """``(na, nb, distances of A's and B's points from the shared edge)``."""
    ca, na = _fit(a_pts)
    cb, nb = _fit(b_pts)
    e = np.cross(na, nb)
    e /= np.linalg.norm(e)
    l0 = np.linalg.solve(np.array([na, nb, e]), [na @ ca, nb @ cb, e @ ca])
    ds = []
    for x, c, n in ((a_pts, ca, na), (b_pts, cb, nb)):
        u = np.cross(n, e)
        ds.append((x - l0) @ (u if (c - l0) @ u > 0 else -u))
    return ds


def _opening(a_pts, b_pts, band):
    da, db = _edge_dist(a_pts, b_pts)
    ka, kb = a_pts[da > band], b_pts[db > band]
    if min(len(ka), len(kb)) < 30:
        return None
    return 180 - float(np.degrees(np.arccos(np.clip(_fit(ka)[1] @ _fit(kb)[1], -1, 1))))


def more(pairs, zmax: float = 1.1) -> None:
    """The wide-face band sweep and the lateral-scale test (``--more``)."""
    convex = []
    for a_pts, b_pts, _ in pairs:
        ca, na = _fit(a_pts)
        cb, nb = _fit(b_pts)
        if np.linalg.norm((ca + cb) / 2) <= zmax and (cb - ca) @ na < 0 and (ca - cb) @ nb < 0:
            convex.append((a_pts, b_pts))
    wide = [(a, b) for a, b in convex
            if min(np.percentile(d, 95) for d in _edge_dist(a, b)) >= 0.09]
    for band in (0.0, 0.01, 0.02, 0.03, 0.04):
        v = np.array([_opening(a, b, band) for a, b in wide], dtype=float)
        v = v[np.isfinite(v)]
        if len(v):
            print(f"faces >= 9 cm ({len(v)}), {band * 100:g} cm left out: interior median "
                  f"{np.median(v):.2f}, open {np.mean(v > 90):.2f}")
    sc = np.array([1.02, 1.02, 1.0])
    ex, sens = [], []
    for a, b in convex:
        o, o2 = _opening(a, b, 0.01), _opening(a * sc, b * sc, 0.01)
        if o is not None and o2 is not None:
            ex.append(o - 90)
            sens.append(o2 - o)
    if len(ex) > 2:
        print(f"lateral scale: {len(ex)} corners, opening median {np.median(ex):.2f}, change per "
              f"+2 % median {np.median(sens):.2f}, correlation {np.corrcoef(ex, sens)[0, 1]:.2f}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("what", choices=["real", "synth"])
    ap.add_argument("files", nargs="*", help="real frames (planerel.read)")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--window", type=float, default=0.0)
    ap.add_argument("--subsample", type=int, default=4)
    ap.add_argument("--n", type=int, default=120, help="synthetic scenes (round part seeds 0..n-1)")
    ap.add_argument("--zmax", type=float, default=1.1)
    ap.add_argument("--more", action="store_true")
    a = ap.parse_args(argv)
    warnings.filterwarnings("ignore")
    import planerel
    from planerel.classify.classifier import Classifier

    pairs = []
    with Classifier(a.model) as clf:
        if a.what == "real":
            for f in a.files:
                pairs += pairs_of(clf, planerel.read(Path(f)))
        else:
            from planerel.synth.sensor import StructuredLight
            from planerel.synth.training_world import generate_round_scene

            for seed in range(a.n):
                sc = generate_round_scene(seed, (640, 480), a.subsample,
                                          sensor=StructuredLight(window=a.window))
                boxes = [o["index"] for o in sc.objects if o["class"] == "box"]
                pairs += pairs_of(clf, sc.cloud, min_points=200 // a.subsample ** 2,
                                  gt_objects=np.asarray(sc.gt_objects), boxes=boxes)
    s = summarise(pairs, a.zmax)
    print(f"{a.what}{'' if a.what == 'real' else f' window {a.window:g} subsample {a.subsample}'}: "
          f"{s['n']} convex corners; interior median {s['interior']:.2f} (open {s['share_open']:.2f}), "
          f"1 cm band left out {s['interior_band_out']:.2f}; facts |90-angle| median "
          f"{s['facts_dev']:.2f}")
    print("residual mm by distance from the edge "
          + ", ".join(f"{lo * 1000:g}-{hi * 1000:g}" for lo, hi in BINS) + ": " + str(s["profile_mm"]))
    if a.more:
        more(pairs, a.zmax)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
