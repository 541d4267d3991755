"""Time the synthetic-scene generator: one 640x480 scene per class, the paper-sized 45-scene
data set (12 box, 15 stairs, 18 ramp) at 160x120 written to a temporary folder, and the varied
world (issue 16): scenes per second at 160x120 written to disk, against the paper world in the
same run, plus the cost of the realistic sensor profiles.

Run: ``.venv/bin/python benchmarks/bench_synth.py [--repeat N] [--varied N]``.
Targets (issue 2): a 640x480 scene in under 1 s; the 45-scene 160x120 set in under 10 s.
Target (issue 16): 1,000 varied scenes in minutes on 2 cores.
"""

from __future__ import annotations

import argparse
import tempfile
import time


def main(argv=None) -> int:
    from planerel.synth.generator import CLASSES, generate_dataset, generate_scene

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="scenes per class at 640x480 (default 3)")
    ap.add_argument("--varied", type=int, default=150,
                    help="varied-world scenes to time at 160x120 (default 150)")
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
    from planerel.synth.sensor import sensor_profile

    print("sensor profiles, 640x480 box scene (seed 0-2), mean:")
    base = None
    for name in ("basic", "structured-light", "tof"):
        sensor = sensor_profile(name)
        t0 = time.perf_counter()
        for seed in range(3):
            generate_scene("box", seed, sensor=sensor)
        dt = (time.perf_counter() - t0) / 3
        base = base or dt
        print(f"  {name:17s} {dt * 1000:7.1f} ms  ({dt / base:.2f}x basic)")
    n = max(3, args.varied) // 3 * 3
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        generate_dataset(tmp, n // 3, n // 3, n // 3, seed=0, subsample=4, world="varied")
        dv = time.perf_counter() - t0
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        generate_dataset(tmp, n // 3, n // 3, n // 3, seed=0, subsample=4)
        dp = time.perf_counter() - t0
    print(f"{n} varied-world scenes at 160x120 (structured light), generated and written: "
          f"{dv:.2f} s = {n / dv:.1f} scenes/s; paper world, same counts: {n / dp:.1f} scenes/s "
          f"(varied {dv / dp:.2f}x slower); 1,000 varied scenes: ~{1000 / (n / dv):.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
