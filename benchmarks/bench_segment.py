"""Speed of normals + region growing, first-call cost, peak memory, and the ratio to the SP / SNP
baselines, all in one run on one core.

    .venv/bin/python benchmarks/bench_segment.py [--repeat 21] [--scene synth|analytic]

Scene: a synthetic staircase (planerel.synth ``stairs`` seed 3 when available, else the analytic
staircase of planerel.segment._scenes) at 640x480 and 160x120.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import time


def _one_core() -> None:
    for var in ("NUMBA_NUM_THREADS", "OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, "1")
    try:
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    except (AttributeError, OSError):
        pass


def _scene(kind: str, sub: int):
    if kind == "synth":
        try:
            from planerel.synth import generate_scene

            sc = generate_scene("stairs", seed=3, subsample=sub)
            return sc.cloud, sc.gt_labels
        except ImportError:
            pass
    from planerel.segment._scenes import staircase

    c, gt, _, _ = staircase(640 // sub, 480 // sub, seed=0)
    return c, gt


def _median_ms(fn, repeat: int) -> float:
    ts = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        ts.append((time.perf_counter() - t) * 1000.0)
    return statistics.median(ts)


def first_call_ms() -> float:
    """Time of the first segmentation in a fresh process (numba cache load or compile)."""
    code = ("import time, numpy as np;from planerel.segment._scenes import staircase;"
            "c=staircase(80,60)[0];from planerel.segment import segment;"
            "t=time.perf_counter();segment(c);print((time.perf_counter()-t)*1000)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return float(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=21)
    ap.add_argument("--scene", choices=("synth", "analytic"), default="synth")
    ap.add_argument("--baseline-repeat", type=int, default=3)
    args = ap.parse_args(argv)
    _one_core()
    from planerel.evaluate import evaluate
    from planerel.normals import organized_normals
    from planerel.segment import segment

    first = first_call_ms()
    print(f"first call in a fresh process (numba cache load / compile): {first:.0f} ms")
    rows = []
    for sub in (1, 4):
        cloud, gt = _scene(args.scene, sub)
        h, w = cloud.shape
        segment(cloud)  # warm
        t_norm = _median_ms(lambda c=cloud: organized_normals(c.xyz, intrinsics=c.intrinsics),
                            args.repeat)
        t_rg = _median_ms(lambda c=cloud: segment(c), args.repeat)
        q = evaluate(segment(cloud).labels, gt)
        row = {"size": f"{w}x{h}", "normals_ms": t_norm, "rg_total_ms": t_rg,
               "rg_correct": q.correct, "n_gt": q.n_gt, "rg_sparse": q.sparse}
        for method, thr in (("sp", 0.01), ("snp", 0.05)):
            t = _median_ms(lambda c=cloud, m=method, t=thr: segment(c, m, threshold=t, seed=0),
                           args.baseline_repeat)
            qq = evaluate(segment(cloud, method, threshold=thr, seed=0).labels, gt)
            row[f"{method}{thr}_ms"] = t
            row[f"{method}{thr}_ratio"] = t / t_rg
            row[f"{method}{thr}_correct"] = qq.correct
        rows.append(row)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    for r in rows:
        print(f"{r['size']}: normals {r['normals_ms']:.2f} ms, normals + region growing "
              f"{r['rg_total_ms']:.2f} ms median ({r['rg_correct']}/{r['n_gt']} correct, "
              f"{r['rg_sparse']} sparse); "
              f"SP 0.01 {r['sp0.01_ms']:.0f} ms (x{r['sp0.01_ratio']:.0f}, {r['sp0.01_correct']} correct); "
              f"SNP 0.05 {r['snp0.05_ms']:.0f} ms (x{r['snp0.05_ratio']:.0f}, {r['snp0.05_correct']} correct)")
    print(f"peak RSS of this process (640x480 frame + baselines): {peak:.0f} MB")
    peak_rg = _peak_rg_only()
    print(f"peak RSS of a process that only segments one 640x480 frame: {peak_rg:.0f} MB")
    return 0


def _peak_rg_only() -> float:
    code = ("import resource;from planerel.segment._scenes import staircase;"
            "c=staircase(640,480)[0];"
            "base=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss;"
            "from planerel.segment import segment;segment(c);"
            "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss/1024)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return float(out.stdout.strip().splitlines()[-1])


if __name__ == "__main__":
    sys.exit(main())
