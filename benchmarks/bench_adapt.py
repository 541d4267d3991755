"""Cost of adapting the segmentation to the sensor: ``segment()`` with the default settings
(noise model measured, parameters set from it) against the fixed settings
(``adapt=False``, = ``preset="kinect"``), interleaved call by call in one process on one core.

    .venv/bin/python benchmarks/bench_adapt.py [--repeat 15] [--subsample 2] [--kinect-only]

Scenes: the generator's staircase seed 3 and box seed 1 at 640x480 and 160x120, the three
Kinect TIFFs and mOSD learn0 (640x480) and an ABW image (512x512) from ``../shared/data`` when
present.  Prints the median CPU ms of each setting, their ratio, and the noise estimate alone.
``--subsample k`` takes every k-th row and column of the real frames (the synthetic scenes
keep their sizes); ``--kinect-only`` runs the Kinect frames alone.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

from _setup import SCENES, data_dir, kinect_files, one_core, synth_scene


def _scenes(sub: int = 1, kinect_only: bool = False):
    """``(name, cloud)``: the speed scenes of bench_segment.py at 640x480 and 160x120, the real
    Kinect frames, mOSD learn0 and ABW test.6 when present (real frames subsampled by
    ``sub``)."""
    from planerel.io.cloud import subsample
    from planerel.io.readers import read, read_abw

    def real(name, cloud):
        if sub == 1:
            return name, cloud
        h, w, _ = cloud.xyz.shape
        return name.replace(f"{w}x{h}", f"{w // sub}x{h // sub}"), subsample(cloud, sub)

    out = []
    if not kinect_only:
        for kind, seed in SCENES:
            for s in (1, 4):
                out.append((f"{kind} seed {seed} {640 // s}x{480 // s}",
                            synth_scene("synth", s, kind, seed)[0]))
    for k, f in enumerate(kinect_files()):
        out.append(real(f"kinect frame {k + 1} 640x480", read(f)))
    if kinect_only:
        return out
    f = data_dir("mosd") / "learn0.pcd"
    if f.exists():
        out.append(real("mOSD learn0 640x480", read(f)))
    f = data_dir("abw") / "abw.test.6.range"
    if f.exists():
        out.append(real("ABW test.6 512x512", read_abw(f)))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=15)
    ap.add_argument("--subsample", type=int, default=1, help="every k-th row and column of the real frames")
    ap.add_argument("--kinect-only", action="store_true", help="only the Kinect frames")
    args = ap.parse_args(argv)
    one_core()
    from planerel.segment import segment
    from planerel.segment.noise import estimate_noise

    print(f"{'scene':30s} {'fixed ms':>9s} {'adaptive ms':>12s} {'ratio':>6s} {'estimate ms':>12s}")
    ratios = []
    for name, c in _scenes(args.subsample, args.kinect_only):
        segment(c)
        segment(c, adapt=False)
        fixed, adapt, est = [], [], []
        for _ in range(args.repeat):
            t = time.process_time()
            segment(c, adapt=False)
            fixed.append(time.process_time() - t)
            t = time.process_time()
            segment(c)
            adapt.append(time.process_time() - t)
            t = time.process_time()
            estimate_noise(c)
            est.append(time.process_time() - t)
        mf, ma, me = (1000 * statistics.median(x) for x in (fixed, adapt, est))
        ratios.append(ma / mf)
        print(f"{name:30s} {mf:9.2f} {ma:12.2f} {ma / mf:6.2f} {me:12.2f}")
    print(f"load average (1, 5, 15 min) at the end: {os.getloadavg()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
