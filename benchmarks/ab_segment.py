"""Interleaved A/B timing of ``segment()`` between two checkouts, on one core.

The VM's speed drifts by up to 1.5x from minute to minute, so two single runs cannot be
compared; this alternates fresh processes of the two checkouts (``PYTHONPATH`` pointing at each)
and reports, per case, the median and minimum of the per-call CPU time over all rounds.

    git worktree add /tmp/before HEAD~1
    .venv/bin/python benchmarks/ab_segment.py --before /tmp/before --after . --rounds 5

Cases: the generator's stairs seed 3 and box seed 1 at 160x120 and 640x480; the paper's
algorithm (``refine=False, split=False``), without post-processing (``split=False``) and the
default.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

_CHILD = r"""
import json, statistics, time
from planerel.synth.generator import generate_scene
from planerel.segment import segment
res = {}
for kind, seed in (("stairs", 3), ("box", 1)):
    for sub, inner in ((4, 60), (1, 12)):
        c = generate_scene(kind, seed=seed, subsample=sub).cloud
        for name, kw in (("paper", dict(refine=False, split=False)),
                         ("split=False", dict(split=False)), ("default", {})):
            segment(c, **kw)
            ts = []
            for _ in range(inner):
                t = time.process_time()
                segment(c, **kw)
                ts.append((time.process_time() - t) * 1000)
            res[f"{kind} {640 // sub}x{480 // sub} {name}"] = ts
print(json.dumps(res))
"""


def _run(path: str) -> dict:
    env = dict(os.environ, PYTHONPATH=os.path.abspath(path), NUMBA_NUM_THREADS="1",
               OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    cmd = [sys.executable, "-c", _CHILD]
    if hasattr(os, "sched_getaffinity"):
        cmd = ["taskset", "-c", str(min(os.sched_getaffinity(0))), *cmd]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True, cwd="/")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", required=True, help="checkout (directory holding planerel/)")
    ap.add_argument("--after", default=".", help="checkout (default: this one)")
    ap.add_argument("--rounds", type=int, default=5)
    a = ap.parse_args(argv)
    acc: dict = {"before": {}, "after": {}}
    for _ in range(a.rounds):
        for side in ("before", "after"):
            for case, ts in _run(getattr(a, side)).items():
                acc[side].setdefault(case, []).extend(ts)
    print(f"{'case (CPU ms per call)':32s} {'before median (min)':>20s} {'after median (min)':>20s}"
          "  ratio")
    for case, before in acc["before"].items():
        after = acc["after"][case]
        mb, ma = statistics.median(before), statistics.median(after)
        print(f"{case:32s} {mb:11.2f} ({min(before):6.2f}) {ma:11.2f} ({min(after):6.2f})"
              f"  {ma / mb:5.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
