"""Time the synthetic-scene generator: one 640x480 scene per class, and the paper-sized
45-scene data set (12 box, 15 stairs, 18 ramp) at 160x120 written to a temporary folder.

Run: ``.venv/bin/python benchmarks/bench_synth.py [--repeat N]``.
Targets (issue 2): a 640x480 scene in under 1 s; the 45-scene 160x120 set in under 10 s.
"""

from __future__ import annotations

import argparse
import tempfile
import time


def main(argv=None) -> int:
    from planerel.synth import CLASSES, generate_dataset, generate_scene

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="scenes per class at 640x480 (default 3)")
    args = ap.parse_args(argv)
    generate_scene("box", 0, subsample=4)  # warm up imports
    print("640x480 scene (ray casting + sensor model + cloud), best / mean of "
          f"{args.repeat} seeds:")
    for kind in CLASSES:
        times = []
        for seed in range(args.repeat):
            t0 = time.perf_counter()
            s = generate_scene(kind, seed)
            times.append(time.perf_counter() - t0)
        print(f"  {kind:7s} {min(times) * 1000:7.1f} ms / {sum(times) / len(times) * 1000:7.1f} ms"
              f"  ({len(s.planes)} planes, {int((s.depth_mm > 0).sum())} valid pixels)")
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        generate_dataset(tmp, 12, 15, 18, seed=0, size=(640, 480), subsample=4)
        dt = time.perf_counter() - t0
    print(f"45-scene data set at 160x120, generated and written: {dt:.2f} s "
          f"({dt / 45 * 1000:.1f} ms per scene)")
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        generate_dataset(tmp, 12, 15, 18, seed=0, size=(640, 480), subsample=1)
        dt = time.perf_counter() - t0
    print(f"45-scene data set at 640x480, generated and written: {dt:.2f} s "
          f"({dt / 45 * 1000:.1f} ms per scene)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
