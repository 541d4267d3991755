"""Region growing: the paper's Algorithm 1 as written against planerel's variants of it, side
by side, on the paper-sized synthetic sets (training seed 0 and held-out seed 1000) and on the
SegComp ABW images.

    .venv/bin/python benchmarks/bench_rg_variants.py [--abw DIR] [--sets train,heldout,abw]
        [--baselines heldout]     # also SP / SNP at the paper's thresholds on those sets

Each row adds or swaps one thing (docs/segmentation.md, "The paper's algorithm and planerel's
variants"); scores are SegComp at T = 0.8, averages per image, all ground-truth planes; ms is
the median wall time of segment() per image in this process (shared machine: a guide).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

_P = dict(preset="paper")  # adapt off, one delta per image, paper's order, no seed test
_G = dict(_P, delta_mode="depth", angle_order="reversed", seed_test=True)  # planerel's growing

#: (name, segment() keywords), each row changing one thing against the row it names.
VARIANTS = (
    ("1 paper: Algorithm 1 as written (preset=paper)", _P),
    ("2 = 1 + delta per depth band", dict(_P, delta_mode="depth")),
    ("3 = 2 + reversed phases", dict(_P, delta_mode="depth", angle_order="reversed")),
    ("4 = 2 + seed test", dict(_P, delta_mode="depth", seed_test=True)),
    ("5 = 2 + reversed + seed test (planerel's growing)", _G),
    ("6 = 5 + completion + leftover planes", dict(_G, refine=True, leftover_planes=True)),
    ("7 = 6 + post-processing (preset=kinect)", dict(preset="kinect")),
    ("8 = 7 + noise adaptation (planerel default)", {}),
    ("9 = 8 with the paper's growing rules", dict(angle_order="paper", seed_test=False)),
    ("10 = 1 with adapted normals and sizes", dict(_P, adapt=True)),
)

#: The RANSAC baselines at the paper's thresholds (``--baselines``).
BASELINES = tuple((f"{m.upper()} {t}", dict(method=m, threshold=t, seed=0))
                  for m, ts in (("sp", (0.005, 0.01, 0.03, 0.05)), ("snp", (0.01, 0.03, 0.05)))
                  for t in ts)


def _row(scores, ms) -> str:
    import numpy as np

    a = np.array([[q.correct, q.over, q.under, q.missed, q.noise, q.sparse, q.n_gt]
                  for q in scores], dtype=float)
    m = a.mean(axis=0)
    pct = 100 * a[:, 0].sum() / a[:, 6].sum()
    return (f"correct {m[0]:5.2f} of {m[6]:5.2f} ({pct:3.0f} %) | over {m[1]:.2f} under "
            f"{m[2]:.2f} missed {m[3]:.2f} noise {m[4]:.2f} sparse {m[5]:.2f} | {ms:6.1f} ms")


def _score(items, kw):
    from planerel.segment import segment
    from planerel.segment.evaluate import evaluate

    kw = dict(kw)
    method = kw.pop("method", "regiongrow")
    scores, ts = [], []
    for cloud, gt in items:
        t = time.perf_counter()
        seg = segment(cloud, method, **kw)
        ts.append((time.perf_counter() - t) * 1000)
        scores.append(evaluate(seg.labels, gt, tolerance=0.8))
    return scores, statistics.median(ts)


def _synthetic(seed: int, camera):
    from planerel.synth.generator import generate_scene, scene_seed

    items, i = [], 0
    for kind, k in (("box", 12), ("stairs", 15), ("ramp", 18)):
        for _ in range(k):
            kw = {} if camera is None else {"camera": camera}
            sc = generate_scene(kind, scene_seed(seed, i), (640, 480), 4, **kw)
            items.append((kind, (sc.cloud, sc.gt_labels)))
            i += 1
    return items


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--abw", default=None, metavar="DIR")
    ap.add_argument("--sets", default="train,heldout,abw")
    ap.add_argument("--baselines", default="", metavar="SETS",
                    help="also SP / SNP at the paper's thresholds on these sets (slow)")
    args = ap.parse_args(argv)
    base_sets = set(filter(None, args.baselines.split(",")))
    sets = set(args.sets.split(","))
    from planerel.synth.generator import CameraRange

    synth_sets = []
    if "train" in sets:
        synth_sets.append(("train", "paper-sized training set (seed 0; planerel's defaults "
                           "were chosen on it)", 0, None))
    if "heldout" in sets:
        synth_sets.append(("heldout", "held-out set (seed 1000, camera height 0.7-1.7 m, "
                           "distance 1.0-2.2 m)", 1000, CameraRange(height=(0.7, 1.7),
                                                                    distance=(1.0, 2.2))))
    for key, title, seed, cam in synth_sets:
        items = _synthetic(seed, cam)
        print(f"{title}: 45 scenes (12 box, 15 stairs, 18 ramp) at 160x120, per image")
        for name, kw in VARIANTS + (BASELINES if key in base_sets else ()):
            scores, ms = _score([x for _, x in items], kw)
            print(f"  {name:50s} {_row(scores, ms)}")
            per = []
            for kind in ("box", "stairs", "ramp"):
                sc = [s for (k, _), s in zip(items, scores, strict=True) if k == kind]
                per.append(f"{kind} {100 * sum(q.correct for q in sc) / sum(q.n_gt for q in sc):.0f} %")
            print(f"  {'':50s} {', '.join(per)}")
    if "abw" in sets:
        root = Path(__file__).resolve().parents[2] / "shared" / "data" / "abw"
        abw = Path(args.abw) if args.abw else root
        files = sorted(abw.glob("*.range"))
        if not files:
            print(f"SegComp ABW: no *.range files in {abw}")
            return 0
        from planerel.io.readers import read_abw, read_abw_gt

        items = [(read_abw(f), read_abw_gt(f.with_suffix(".gt-seg"))) for f in files]
        h, w = items[0][1].shape
        print(f"SegComp ABW, {len(files)} images at {w}x{h}, per image")
        for name, kw in VARIANTS + (BASELINES if "abw" in base_sets else ()):
            scores, ms = _score(items, kw)
            print(f"  {name:50s} {_row(scores, ms)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
