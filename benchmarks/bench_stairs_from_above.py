"""Staircases on Kinect-like frames: is the flight ONE proposal, and is it called stairs?

    .venv/bin/python benchmarks/bench_stairs_from_above.py [--seeds 9000:9010] [--subsample 1 2]
        [--distance 1:3] [--model out/model] [--against CHECKOUT [--against-model DIR]]

Scenes: the varied world's staircases (planerel.synth.world, structured-light sensor model,
640x480 rendered, ``--subsample``), with the ranges of tests/test_real_rules.py (camera 0.8-1.6 m
high, pitched 25-60 degrees down, the flight 1-3 m away, 0-1 extra object), once all seen from
the top going down (descending: the risers face away, treads only) and once from the bottom
(ascending).  Each scene is segmented once (regiongrow defaults) and described with two
settings in the same run:

* ``before``: ``PlaneParams(fit="pca")``, ``ProposalParams(split_stepped=False, step_tilt=0)``
  (the plane fit, the stepped split and the tilted treads of issue 16 off; the other changes
  to the step chains stay on, so ``--against`` with a checkout of the old code gives the exact
  reference);
* ``now``: the defaults.

Per scene the *flight* is the staircase's treads and risers that the segmentation found (half
of a tread's pixels in some plane); the flight is **one proposal** when a single proposal
holds all of them and lies at least half on the staircase, **most** when it holds 3/4 of them.  The median time of ``describe_scene`` per scene is printed for each
setting (both run on the same segmentation, one after the other).
With ``--model`` the scenes are also classified (planerel.classify.Classifier, the code of
``planerel classify``) and a staircase counts as **called stairs** when a proposal lying mostly
on it is answered ``stairs`` (the criterion of tests/test_real_rules.py).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np


def _scenes(seeds, sub, descending, distance=(1.0, 3.0)):
    from planerel.segment import segment
    from planerel.synth.world import WorldRange, generate_world_scene

    ranges = WorldRange(camera_height=(0.8, 1.6), camera_pitch_deg=(25.0, 60.0),
                        object_range=distance, extra_objects=(0, 1),
                        descending=1.0 if descending else 0.0)
    for s in seeds:
        sc = generate_world_scene("stairs", s, size=(640, 480), subsample=sub, ranges=ranges)
        yield s, sc, segment(sc.cloud).labels


def flight(sc, desc, min_px=200):
    """``(found faces, faces in the best proposal, its share on the staircase)``."""
    L = getattr(desc, "labels", None)
    L = desc.planes.labels if L is None else L
    gt = sc.gt_labels
    sub2 = (sc.cloud.xyz.shape[1] / 640) ** 2
    faces = [p.index for p in sc.planes if p.object_index == 1 and p.role in ("tread", "riser")]
    found = [k for k in faces if (gt == k).sum() >= min_px * sub2
             and (L[gt == k] >= 0).sum() >= 0.5 * (gt == k).sum()]
    mine = sc.gt_objects == 1
    best = (0, 0.0)
    for o in desc.objects:
        m = np.isin(L, o.planes)
        got = sum(1 for k in found if (m & (gt == k)).sum() >= 0.5 * (gt == k).sum())
        best = max(best, (got, float((m & mine).sum() / max(1, m.sum()))))
    return len(found), best[0], best[1]


def measure(seeds, subs, variants, model=None, distance=(1.0, 3.0)):
    from planerel.features.facts import describe_scene
    from planerel.features.planes import PlaneParams
    from planerel.features.relations import ProposalParams

    settings = {"now": {}}
    if "before" in variants:  # (a checkout without these settings measures "now" only)
        settings["before"] = {"plane_params": PlaneParams(fit="pca"),
                              "proposal_params": ProposalParams(split_stepped=False, step_tilt=0.0)}
    clf = None
    if model:
        from planerel.classify import Classifier

        clf = Classifier(model)
    out = {}
    warm = False
    try:
        for sub in subs:
            for descending in (True, False):
                key = f"{'descending' if descending else 'ascending'} subsample {sub}"
                rows = out.setdefault(key, {v: {"one": 0, "most": 0, "n": 0, "ms": []}
                                            for v in variants})
                if clf is not None:
                    rows["stairs answers"] = 0
                for s, sc, lab in _scenes(seeds, sub, descending, distance):
                    if not warm:  # numba and shapely warm-up, untimed
                        for v in variants:
                            describe_scene(sc.cloud, lab, up=sc.up, **settings[v])
                        warm = True
                    for v in variants:
                        t0 = time.perf_counter()
                        d = describe_scene(sc.cloud, lab, up=sc.up, **settings[v])
                        rows[v]["ms"].append(1000 * (time.perf_counter() - t0))
                        n, got, share = flight(sc, d)
                        r = rows[v]
                        r["n"] += 1
                        r["one"] += n > 0 and got == n and share >= 0.5
                        r["most"] += n > 0 and got >= 0.75 * n and share >= 0.5
                    if clf is not None:
                        ans = clf.classify(sc.cloud, scene_id=f"k{s}", up=sc.up)
                        mine = sc.gt_objects == 1
                        for o in ans.objects:
                            px = np.isin(np.asarray(ans.labels), list(o.labels))
                            if o.klass == "stairs" and (px & mine).sum() > 0.5 * max(1, px.sum()):
                                rows["stairs answers"] += 1
                                break
    finally:
        if clf is not None:
            clf.close()
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", default="9000:9010", help="first:last+1 (default 9000:9010)")
    ap.add_argument("--subsample", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--distance", default="1:3", help="LO:HI metres from the camera to the "
                    "flight (default 1:3)")
    ap.add_argument("--model", help="also classify with this model folder")
    ap.add_argument("--against", help="also measure 'now' with the planerel of this checkout")
    ap.add_argument("--against-model", help="... and classify there with this model (one that "
                    "checkout learned)")
    ap.add_argument("--json", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--variants", nargs="+", default=["before", "now"], help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    lo, hi = (int(x) for x in a.seeds.split(":"))
    dist = tuple(float(x) for x in a.distance.split(":"))
    res = measure(range(lo, hi), a.subsample, a.variants, a.model, dist)
    if a.json:
        print(json.dumps(res))
        return 0
    ref = None
    if a.against:
        env = dict(os.environ, PYTHONPATH=str(Path(a.against).resolve()))
        cmd = [sys.executable, __file__, "--seeds", a.seeds, "--json", "--variants", "now",
               "--distance", a.distance,
               "--subsample", *map(str, a.subsample)] + (["--model", a.against_model]
                                                          if a.against_model else [])
        run = subprocess.run(cmd, env=env, capture_output=True, text=True)
        if run.returncode:
            print(run.stderr, file=sys.stderr)
        else:
            ref = json.loads(run.stdout)
    print(f"seeds {a.seeds}, flight {a.distance} m away; flight in one proposal (all found treads/risers) / in most (3/4)")
    for key, rows in res.items():
        parts = [f"{v} {r['one']}/{r['n']} ({r['most']}, describe {statistics.median(r['ms']):.0f} ms)"
                 for v, r in rows.items() if v in a.variants]
        if ref is not None:
            r = ref[key]["now"]
            parts.insert(0, f"{a.against} {r['one']}/{r['n']} ({r['most']})")
        if "stairs answers" in rows:
            parts.append(f"called stairs {rows['stairs answers']}/{rows['now']['n']}")
            if ref is not None and "stairs answers" in ref[key]:
                parts.append(f"(against: {ref[key]['stairs answers']})")
        print(f"  {key:24s} " + ", ".join(parts))
    return 0


if __name__ == "__main__":
    sys.exit(main())
