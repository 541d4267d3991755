"""First call of a fresh process: numba's on-disk cache of the compiled kernels, cold vs warm.

Each measurement is a new Python process that imports planerel, makes one 160x120 stairs scene
and times its first ``segment`` + ``describe`` (then a second call, the steady state).  "cold"
points ``NUMBA_CACHE_DIR`` at an empty folder, so every kernel is compiled (what every process
paid without a cache); "warm" runs again with the folder the cold run filled.

    python benchmarks/bench_first_call.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile

CHILD = r"""
import time
t0 = time.perf_counter()
from planerel.synth.generator import generate_scene
scene = generate_scene("stairs", seed=1, size=(640, 480), subsample=4)
from planerel.features.facts import describe_scene
from planerel.segment import segment
a = time.perf_counter()
d = describe_scene(scene.cloud, segment(scene.cloud).labels, scene_id="s")
b = time.perf_counter()
d = describe_scene(scene.cloud, segment(scene.cloud).labels, scene_id="s")
c = time.perf_counter()
print(f"{b - a:.4f} {c - b:.4f}")
"""


def run(cache: str) -> tuple[float, float]:
    env = {**os.environ, "NUMBA_CACHE_DIR": cache}
    out = subprocess.run([sys.executable, "-c", CHILD], env=env, capture_output=True, text=True,
                         check=True).stdout.split()
    return float(out[0]), float(out[1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    cold, warm, steady = [], [], []
    for _ in range(args.repeat):
        with tempfile.TemporaryDirectory(prefix="planerel-numba-") as cache:
            first, _ = run(cache)
            cold.append(first)
            first, second = run(cache)
            warm.append(first)
            steady.append(second)
    med = statistics.median
    print(f"first segment+describe of a fresh process, median of {args.repeat}:")
    print(f"  cold (no cache, every kernel compiled): {med(cold):7.2f} s")
    print(f"  warm (kernels loaded from the cache):   {med(warm):7.2f} s   "
          f"({med(cold) / med(warm):.1f}x faster)")
    print(f"  steady state (second call):             {med(steady) * 1000:7.1f} ms")


if __name__ == "__main__":
    main()
