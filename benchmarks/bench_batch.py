"""Batch throughput and memory: ``planerel describe`` over many scenes with --jobs 1, --jobs 2
and a 2-worker Dask LocalCluster.

A folder of N scenes is made from ``--base`` distinct synthetic scenes (box / stairs / ramp at
``--size``, seed 0) by linking each scene's depth PNG and sidecar under N names, so every
scene is read, segmented and described in full.  Each configuration runs in a fresh process;
its wall time, its own peak resident memory and the largest worker's peak are reported
(``getrusage``: RUSAGE_SELF and RUSAGE_CHILDREN, which holds the largest finished child).

    python benchmarks/bench_batch.py --scenes 1000 --size 640x480
    python benchmarks/bench_batch.py --scenes 10000 --size 160x120 --configs j2
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

CHILD = r"""
import json, resource, sys, time
from planerel.cli import main
folder, out, mode = sys.argv[1], sys.argv[2], sys.argv[3]
argv = ["describe", folder, "-o", out]
t0 = time.perf_counter()
if mode.startswith("dask"):
    from distributed import LocalCluster
    n = int(mode[4:])
    with LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster:
        t0 = time.perf_counter()  # the cluster's start-up is not the batch's time
        rc = main(argv + ["--scheduler", cluster.scheduler_address])
        t1 = time.perf_counter()
else:
    rc = main(argv + ["--jobs", mode[1:]])
    t1 = time.perf_counter()
self_kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
child_kb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
print(json.dumps({"rc": rc, "seconds": t1 - t0, "self_mb": self_kb / 1024,
                  "worker_mb": child_kb / 1024}))
"""


def make_folder(root: Path, n: int, base: int, size: str) -> Path:
    src = root / "base"
    subprocess.run([sys.executable, "-m", "planerel.cli", "dataset", "synth", str(src),
                    "--n-box", str(base - 2 * (base // 3)), "--n-stairs", str(base // 3),
                    "--n-ramp", str(base // 3), "--size", size, "--subsample", "1", "--seed",
                    "0", "--quiet"], check=True, stdout=subprocess.DEVNULL)
    ids = sorted(p.name.split(".")[0] for p in src.glob("s*.depth.png"))
    folder = root / "scenes"
    folder.mkdir()
    for k in range(n):
        sid = ids[k % len(ids)]
        (folder / f"x{k:06d}.depth.png").symlink_to(src / f"{sid}.depth.png")
        (folder / f"x{k:06d}.json").symlink_to(src / f"{sid}.json")
    return folder


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", type=int, default=1000)
    ap.add_argument("--base", type=int, default=50, help="distinct scenes (default 50)")
    ap.add_argument("--size", default="640x480")
    ap.add_argument("--configs", default="j1,j2,dask2",
                    help="comma list of jN (local processes) and daskN (LocalCluster workers)")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="planerel-bench-") as tmp:
        folder = make_folder(Path(tmp), args.scenes, args.base, args.size)
        print(f"describe {args.scenes} scenes at {args.size} ({args.base} distinct), "
              f"{os.cpu_count()} cores", flush=True)
        ref = None
        for mode in args.configs.split(","):
            out = Path(tmp) / f"{mode}.pl"
            r = subprocess.run([sys.executable, "-c", CHILD, str(folder), str(out), mode],
                               capture_output=True, text=True)
            if r.returncode != 0:
                print(f"{mode}: failed\n{r.stderr[-2000:]}")
                continue
            m = json.loads(r.stdout.strip().splitlines()[-1])
            rate = args.scenes / m["seconds"]
            ref = ref or rate
            print(f"{mode:>6}: {m['seconds']:7.1f} s, {rate:6.2f} scenes/s ({rate / ref:.2f}x "
                  f"{args.configs.split(',')[0]}), peak memory: main process "
                  f"{m['self_mb']:.0f} MB, largest worker {m['worker_mb']:.0f} MB, facts "
                  f"{out.stat().st_size / 1e6:.1f} MB", flush=True)
            out.unlink()


if __name__ == "__main__":
    main()
