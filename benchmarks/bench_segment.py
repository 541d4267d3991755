"""Speed of normals + region growing, first-call cost, peak memory, and the ratio to the SP / SNP
baselines, all in one run on one core.

    .venv/bin/python benchmarks/bench_segment.py [--repeat 21] [--scene synth|analytic]
    .venv/bin/python benchmarks/bench_segment.py --quality [--abw DIR] [--abw-baselines]

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
    """Median wall time (ms); the median CPU time of this process goes to ``_CPU``."""
    ts = []
    cs = []
    for _ in range(repeat):
        c = time.process_time()
        t = time.perf_counter()
        fn()
        ts.append((time.perf_counter() - t) * 1000.0)
        cs.append((time.process_time() - c) * 1000.0)
    _CPU.append(statistics.median(cs))
    return statistics.median(ts)


#: Median CPU times of the :func:`_median_ms` calls, in order (the machine is shared: wall time
#: includes waiting for the core, CPU time does not).
_CPU: list = []


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
    ap.add_argument("--quality", action="store_true",
                    help="print the quality tables of docs/segmentation.md instead of the speed")
    ap.add_argument("--abw", default=None, metavar="DIR",
                    help="SegComp ABW folder for --quality (default ../shared/data/abw)")
    ap.add_argument("--abw-baselines", action="store_true",
                    help="with --quality: also SP / SNP at the paper's thresholds on ABW (slow)")
    args = ap.parse_args(argv)
    _one_core()
    if args.quality:
        return quality(args)
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
        cpu_rg = _CPU[-1]
        t_nopost = _median_ms(lambda c=cloud: segment(c, split=False), args.repeat)
        cpu_nopost = _CPU[-1]
        t_paper = _median_ms(lambda c=cloud: segment(c, refine=False, split=False), args.repeat)
        q = evaluate(segment(cloud).labels, gt)
        q0 = evaluate(segment(cloud, split=False).labels, gt)
        row = {"size": f"{w}x{h}", "normals_ms": t_norm, "rg_total_ms": t_rg,
               "rg_cpu_ms": cpu_rg, "paper_ms": t_paper, "paper_cpu_ms": _CPU[-1],
               "nopost_ms": t_nopost, "nopost_cpu_ms": cpu_nopost, "nopost_correct": q0.correct,
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
    print(f"load average (1, 5, 15 min) at the end: {os.getloadavg()}")
    for r in rows:
        print(f"{r['size']}: segment() default (growing, completion, post-processing) "
              f"{r['rg_total_ms']:.2f} ms median wall ({r['rg_cpu_ms']:.2f} ms CPU, "
              f"{r['rg_correct']}/{r['n_gt']} correct); without post-processing (split=False) "
              f"{r['nopost_ms']:.2f} ms wall ({r['nopost_cpu_ms']:.2f} ms CPU, "
              f"{r['nopost_correct']}/{r['n_gt']} correct); the paper's algorithm only "
              f"(refine=False, split=False) {r['paper_ms']:.2f} ms wall "
              f"({r['paper_cpu_ms']:.2f} ms CPU)")
        print(f"{r['size']}: normals {r['normals_ms']:.2f} ms, segment() "
              f"{r['rg_total_ms']:.2f} ms median ({r['rg_correct']}/{r['n_gt']} correct, "
              f"{r['rg_sparse']} sparse); "
              f"SP 0.01 {r['sp0.01_ms']:.0f} ms (x{r['sp0.01_ratio']:.0f}, {r['sp0.01_correct']} correct); "
              f"SNP 0.05 {r['snp0.05_ms']:.0f} ms (x{r['snp0.05_ratio']:.0f}, {r['snp0.05_correct']} correct)")
    print(f"peak RSS of this process (640x480 frame + baselines): {peak:.0f} MB")
    peak_rg = _peak_rg_only()
    print(f"peak RSS of a process that only segments one 640x480 frame: {peak_rg:.0f} MB")
    return 0


def _visible(scene, min_size):
    """GT labels without the planes smaller than ``min_size`` pixels (SegComp practice)."""
    gt = scene.gt_labels.copy()
    for p in scene.planes:
        if p.n_pixels < min_size:
            gt[gt == p.index] = -1
    return gt


def _row(scores) -> str:
    import numpy as np

    a = np.array([[q.correct, q.over, q.under, q.missed, q.noise, q.sparse, q.n_gt]
                  for q in scores], dtype=float).mean(axis=0)
    return ("correct {:.2f}, over {:.2f}, under {:.2f}, missed {:.2f}, noise {:.2f}, "
            "sparse {:.2f}, GT planes {:.2f}".format(*a))


def quality(args) -> int:
    """The quality figures of docs/segmentation.md (region growing, default parameters)."""
    import glob
    from pathlib import Path

    from planerel.evaluate import evaluate
    from planerel.segment import segment
    from planerel.synth import CLASSES, generate_scene

    print("generator stairs (planerel.synth defaults), per image:")
    for sub, seeds in ((1, range(4)), (4, range(8))):
        every, visible = [], []
        for seed in seeds:
            sc = generate_scene("stairs", seed, size=(640, 480), subsample=sub)
            seg = segment(sc.cloud)
            every.append(evaluate(seg.labels, sc.gt_labels))
            visible.append(evaluate(seg.labels, _visible(sc, seg.info["min_region_size"])))
        h, w = sc.gt_labels.shape
        print(f"  {w}x{h} seeds 0-{seeds[-1]}, all GT planes: {_row(every)}")
        print(f"  {w}x{h} seeds 0-{seeds[-1]}, GT planes >= min_region_size: {_row(visible)}")
    print("closed staircases (steps 3/4/5, sides='closed', walls=1, seeds 0-3), GT planes >= "
          "min_region_size:")
    for sub in (4, 1):
        scores, ok = [], 0
        for steps in (3, 4, 5):
            for seed in range(4):
                sc = generate_scene("stairs", seed, size=(640, 480), subsample=sub, steps=steps,
                                    sides="closed", walls=1)
                seg = segment(sc.cloud)
                q = evaluate(seg.labels, _visible(sc, seg.info["min_region_size"]))
                scores.append(q)
                ok += q.correct >= q.n_gt - 1 and q.sparse == 0
        h, w = sc.gt_labels.shape
        print(f"  {w}x{h}: {_row(scores)}; images with >= n_gt - 1 correct and no sparse "
              f"plane: {ok} of {len(scores)}")
    print("box / stairs / ramp (seeds 0-2 each, 160x120, all GT planes), per image:")
    scores = []
    for kind in CLASSES:
        for seed in range(3):
            sc = generate_scene(kind, seed, subsample=4)
            scores.append(evaluate(segment(sc.cloud).labels, sc.gt_labels))
    print(f"  regiongrow: {_row(scores)}")
    _post_processing_table()
    abw = Path(args.abw) if args.abw else Path(__file__).resolve().parents[2] / "shared/data/abw"
    files = sorted(glob.glob(str(abw / "*.range")))
    if files:
        from planerel.io import read_abw, read_abw_gt

        runs = [("regiongrow default", "regiongrow", {}),
                ("regiongrow preset=structured-light", "regiongrow",
                 {"preset": "structured-light"})]
        if args.abw_baselines:
            runs += [(f"SP {t}", "sp", {"threshold": t}) for t in (0.005, 0.01, 0.03, 0.05)]
            runs += [(f"SNP {t}", "snp", {"threshold": t}) for t in (0.01, 0.03, 0.05)]
        clouds = [(read_abw(f), read_abw_gt(f.replace(".range", ".gt-seg"))) for f in files]
        print(f"SegComp ABW ({len(files)} images in {abw}, T = 0.8), per image:")
        for name, method, params in runs:
            scores = [evaluate(segment(c, method, **params).labels, gt, tolerance=0.8)
                      for c, gt in clouds]
            print(f"  {name}: {_row(scores)}")
    return 0


def _post_processing_table() -> None:
    """Per class, on the demo's two paper-sized sets (160x120): the paper's algorithm with
    planerel's completion, then each post-processing step added."""
    from planerel.evaluate import evaluate
    from planerel.segment import segment
    from planerel.segment.split import SplitParams
    from planerel.synth import CameraRange, generate_scene, scene_seed

    variants = (("growing + completion (split=False)", dict(split=False)),
                ("+ split bent regions + merge", dict(split_params=SplitParams(leftover=False))),
                ("+ planes in unassigned patches (default)", {}))
    sets = (("training set (seed 0)", 0, None),
            ("held-out set (seed 1000, camera height 0.7-1.7 m, distance 1.0-2.2 m)", 1000,
             CameraRange(height=(0.7, 1.7), distance=(1.0, 2.2))))
    counts = (("box", 12), ("stairs", 15), ("ramp", 18))
    for title, seed, cam in sets:
        print(f"paper-sized {title}, 160x120, all GT planes, per image:")
        scenes, i = [], 0
        for kind, k in counts:
            for _ in range(k):
                kw = {} if cam is None else {"camera": cam}
                scenes.append((kind, generate_scene(kind, scene_seed(seed, i), (640, 480), 4, **kw)))
                i += 1
        for name, kw in variants:
            for kind, _ in counts:
                sc = [evaluate(segment(x.cloud, **kw).labels, x.gt_labels)
                      for kk, x in scenes if kk == kind]
                print(f"  {name}, {kind}: {_row(sc)}")


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
