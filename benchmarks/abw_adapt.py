"""SegComp ABW with the adaptive default: per-image scores, the noise model and settings chosen
for each image, a sensitivity grid of the adaptation's two constants and a leave-one-out check.

    .venv/bin/python benchmarks/abw_adapt.py [--abw DIR]

The adaptation has two constants (planerel/segment/adapt.py): ``MIN_SIDE_SIGMAS`` (20, a
region's side in noise stds) and ``FLOOR_SCALE`` (0.25, the resolution floor of the minimum
region size).  The grid scores every pair of a few values on all images; the leave-one-out
check picks, for each image, the pair that scores best on the other nine (most correct, then
least noise) and scores the held-out image with it, so its mean says what a choice made
without an image gives on that image.
"""

from __future__ import annotations

import argparse
import glob
import sys
from pathlib import Path

import numpy as np

SIDES = (10.0, 15.0, 20.0, 25.0, 30.0)
FLOORS = (0.125, 0.25, 0.5)


def _score(clouds, side, floor, **params):
    from planerel.segment import adapt, segment
    from planerel.segment.evaluate import evaluate

    old = adapt.MIN_SIDE_SIGMAS, adapt.FLOOR_SCALE
    adapt.MIN_SIDE_SIGMAS, adapt.FLOOR_SCALE = side, floor
    try:
        out = []
        for c, gt in clouds:
            seg = segment(c, **params)
            q = evaluate(seg.labels, gt, tolerance=0.8)
            out.append((q.correct, q.over, q.under, q.missed, q.noise, q.n_gt, seg))
        return out
    finally:
        adapt.MIN_SIDE_SIGMAS, adapt.FLOOR_SCALE = old


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--abw", default=None, metavar="DIR")
    a = ap.parse_args(argv)
    from planerel.io.readers import read_abw, read_abw_gt

    folder = Path(a.abw) if a.abw else Path(__file__).resolve().parents[2] / "shared" / "data" / "abw"
    files = sorted(glob.glob(str(folder / "*.range")), key=lambda f: int(f.split(".")[-2]))
    if not files:
        print(f"no ABW images in {folder}")
        return 0
    names = [Path(f).name.replace(".range", "") for f in files]
    clouds = [(read_abw(f), read_abw_gt(f.replace(".range", ".gt-seg"))) for f in files]
    print(f"SegComp ABW, {len(files)} images in {folder}, T = 0.8, per image")
    print("defaults (adaptive): image, correct / over / under / missed / noise of GT, noise "
          "model, min region, window")
    base = _score(clouds, 20.0, 0.25)
    for name, r in zip(names, base, strict=True):
        nm, st = r[6].info["noise_model"], r[6].info["settings"]
        print(f"  {name:12s} {r[0]:2d} {r[1]} {r[2]} {r[3]:2d} {r[4]} of {r[5]:2d}   {nm['kind']} "
              f"sigma {1000 * nm['sigma_median_m']:.2f} mm = {nm['noise_pixels']:.2f} px; "
              f"min region {st['min_region_size']} px, window {st['normal_smooth']}")
    m = np.array([r[:6] for r in base], float).mean(axis=0)
    print("  mean: correct {:.2f}, over {:.2f}, under {:.2f}, missed {:.2f}, noise {:.2f}, "
          "GT {:.2f}".format(*m))
    for label, params in (("preset=kinect (the fixed settings)", {"preset": "kinect"}),
                          ("preset=structured-light", {"preset": "structured-light"})):
        rs = _score(clouds, 20.0, 0.25, **params)
        m = np.array([r[:6] for r in rs], float).mean(axis=0)
        print(f"{label}: correct {m[0]:.2f}, over {m[1]:.2f}, under {m[2]:.2f}, missed "
              f"{m[3]:.2f}, noise {m[4]:.2f}")
    print("grid (mean correct / noise): rows MIN_SIDE_SIGMAS, columns FLOOR_SCALE "
          + " ".join(str(f) for f in FLOORS))
    grid = {}
    for side in SIDES:
        cells = []
        for floor in FLOORS:
            rs = base if (side, floor) == (20.0, 0.25) else _score(clouds, side, floor)
            grid[(side, floor)] = np.array([r[:6] for r in rs], float)
            g = grid[(side, floor)].mean(axis=0)
            cells.append(f"{g[0]:5.2f} / {g[4]:.2f}")
        print(f"  {side:4.0f}: " + "   ".join(cells))
    objectives = (
        ("most correct, then least noise", lambda g: (g[0], -g[4])),
        ("correct - over - under - noise", lambda g: (g[0] - g[1] - g[2] - g[4], g[0])))
    for title, objective in objectives:
        print(f"leave-one-out, constants chosen on the other images by {title}; score of the "
              "held-out image:")
        loo, chosen = [], []
        for i in range(len(names)):
            def key(k, i=i, objective=objective):
                return (*objective(np.delete(grid[k], i, axis=0).mean(axis=0)), k == (20.0, 0.25))
            best = max(grid, key=key)
            loo.append(grid[best][i])
            chosen.append(f"{best[0]:g}/{best[1]:g}")
        m = np.array(loo).mean(axis=0)
        print(f"  chosen (side/floor) per held-out image: {', '.join(chosen)}")
        print("  mean: correct {:.2f}, over {:.2f}, under {:.2f}, missed {:.2f}, "
              "noise {:.2f}".format(*m[:5]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
