"""Output check for speed work on the segmentation: saves, then compares, the labels and planes
of ``segment()`` (adaptive default and ``adapt=False``) on every shared real frame and on
synthetic scenes.

    .venv/bin/python benchmarks/same_output.py --save /tmp/before.npz    # on the old code
    .venv/bin/python benchmarks/same_output.py --compare /tmp/before.npz # on the new code

Real frames (from ``../shared/data`` when present): the Kinect TIFFs and office1.pcd, the mOSD
PCDs, the ABW images.  Synthetic: the speed scenes of bench_segment.py at 640x480 and 160x120
and ramp / box / stairs scenes of the generator (seeds 0-4, 160x120 and 320x240), where regions
are split.  Prints per scene whether the labels are identical and the largest difference of
the plane parameters; exit status 1 when any labels differ.
"""

from __future__ import annotations

import argparse
import glob
import sys

import numpy as np
from _setup import SCENES, data_dir, kinect_files, synth_scene


def _clouds():
    """``(name, cloud)`` of every scene checked."""
    from planerel.io.readers import read, read_abw
    from planerel.synth.generator import generate_scene

    for f in kinect_files():
        yield f"kinect {f.split('/')[-1][6:28]}", read(f)
    f = data_dir("kinect") / "office1.pcd"
    if f.exists():
        yield "kinect office1.pcd", read(f)
    for f in sorted(glob.glob(str(data_dir("mosd") / "*.pcd"))):
        yield f"mosd {f.split('/')[-1]}", read(f)
    for f in sorted(glob.glob(str(data_dir("abw") / "*.range"))):
        yield f"abw {f.split('/')[-1]}", read_abw(f)
    for kind, seed in SCENES:
        for sub in (1, 4):
            yield f"synth {kind} {seed} /{sub}", synth_scene("synth", sub, kind, seed)[0]
    for cls in ("ramp", "box", "stairs"):
        for seed in range(5):
            for sub in (2, 4):
                yield f"gen {cls} {seed} /{sub}", generate_scene(cls, seed=seed, subsample=sub).cloud


def _runs():
    from planerel.segment import segment

    for name, c in _clouds():
        for tag, kw in (("adapt", {}), ("fixed", {"adapt": False})):
            seg = segment(c, **kw)
            pl = np.array([[*p.normal, p.offset, p.rms] for p in seg.planes]).reshape(-1, 5)
            yield f"{name} [{tag}]", seg.labels, pl


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--save")
    g.add_argument("--compare")
    args = ap.parse_args(argv)
    if args.save:
        out = {}
        for key, lab, pl in _runs():
            out[key + " labels"] = lab
            out[key + " planes"] = pl
            print(f"{key:45s} {lab.max() + 1:3d} planes")
        np.savez_compressed(args.save, **out)
        return 0
    ref = np.load(args.compare)
    bad = 0
    for key, lab, pl in _runs():
        rl, rp = ref[key + " labels"], ref[key + " planes"]
        same = rl.shape == lab.shape and np.array_equal(rl, lab)
        dp = float(np.abs(rp - pl).max()) if same and rp.shape == pl.shape and len(pl) else 0.0
        bad += not same
        print(f"{key:45s} labels {'identical' if same else 'DIFFER':9s} "
              f"({int((rl != lab).sum()) if rl.shape == lab.shape else -1} px)  planes max diff {dp:.3g}")
    print(f"{bad} scene(s) with different labels")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
