"""Speed of normals + region growing (the issue's targets), of the completion and the planar
post-processing, per-stage times, first-call cost, peak memory, and the ratio to the SP / SNP
baselines, all in one run on one core.

    .venv/bin/python benchmarks/bench_segment.py [--repeat 21] [--scene synth|analytic]
    .venv/bin/python benchmarks/bench_segment.py --real [DIR]   # real Kinect frames only
    .venv/bin/python benchmarks/bench_segment.py --quality [--abw DIR] [--abw-baselines]

Scenes (:data:`SCENES`): the generator's staircase seed 3 and box seed 1 at 640x480 and 160x120
(``--scene analytic``: the analytic staircase of planerel.segment._scenes).
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import time

from _setup import SCENES, data_dir, kinect_files, one_core
from _setup import synth_scene as _scene


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


#: The issue's targets for normals + region growing (ms) per image size.
TARGETS = {"640x480": 10.0, "160x120": 1.0}


def _stages(cloud, repeat: int) -> dict:
    """Median CPU ms of each stage of the paper's algorithm, kernels called as ``segment()``
    calls them (planerel internals: a breakdown, not an API)."""
    import math

    import numpy as np

    from planerel.segment import _kernels as K
    from planerel.segment._graph_kernels import graph_table
    from planerel.segment._normal_kernels import normals_stream, with_graph
    from planerel.segment._workspace import _workspace, normal_rings
    from planerel.segment.normals import normal_kernel_args
    from planerel.segment.regiongrow import _NBANDS

    xyz = np.ascontiguousarray(cloud.xyz)
    h, w, _ = xyz.shape
    ws = _workspace(h, w)
    args = normal_kernel_args(xyz, intrinsics=cloud.intrinsics)
    nrm = np.empty((h, w, 3), np.float32)
    n = h * w
    min_size = 90 * n // 19200
    padded, labels = K.padded_labels(h, w)
    sums = np.zeros((n // min_size + 2, 10))
    ref = np.zeros((n // min_size + 2, 3))
    c1, c2 = math.cos(math.radians(7.5)), math.cos(math.radians(15.0))
    out = {}
    rings = normal_rings(ws, args[3], args[4])
    table = (xyz, 6.0, -1.0, True, _NBANDS, max(1, h // 120))
    out["delta table"] = _cpu_ms(lambda: graph_table(*table), repeat)
    graph = with_graph(*graph_table(*table)[1:4], ws.mask)
    out["normals + graph"] = _cpu_ms(lambda: normals_stream(xyz, *args, nrm, *rings, ws.mom,
                                                            graph), repeat)
    def grow(paper=False):
        # the paper's order: theta (c2) while the region is small, theta * angle_mf (c1) after,
        # no seed test (-2); planerel's: reversed, with the seed test
        c = (c2, c1, -2.0) if paper else (c1, c2, c1)
        return K.region_grow_grid_ws(nrm.reshape(-1, 3), ws.nvalid, ws.mask.reshape(-1), w, 4,
                                     *c, 16, 8, min_size, padded, ws.queue, ws.seedable)

    out["growing (paper's rules)"] = _cpu_ms(lambda: grow(True), repeat)
    out["growing (planerel's)"] = _cpu_ms(grow, repeat)
    nreg = grow()
    out["moments"] = _cpu_ms(lambda: K.region_sums_into(xyz.reshape(-1, 3), labels, nreg, sums,
                                                        ref, False), repeat)
    return out


def _cpu_ms(fn, repeat: int) -> float:
    ts = []
    for _ in range(repeat):
        c = time.process_time()
        fn()
        ts.append((time.process_time() - c) * 1000.0)
    return statistics.median(ts)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=21)
    ap.add_argument("--scene", choices=("synth", "analytic"), default="synth")
    ap.add_argument("--baseline-repeat", type=int, default=3)
    ap.add_argument("--quality", action="store_true",
                    help="print the quality tables of docs/segmentation.md instead of the speed")
    ap.add_argument("--abw", default=None, metavar="DIR",
                    help="SegComp ABW folder for --quality (default ../shared/data/abw)")
    ap.add_argument("--real", nargs="?", const="", default=None, metavar="DIR",
                    help="time the real frames of the Kinect folder instead (default "
                         "../shared/data/kinect: its depth TIFFs and office1.pcd)")
    ap.add_argument("--abw-baselines", action="store_true",
                    help="with --quality: also SP / SNP at the paper's thresholds on ABW (slow)")
    args = ap.parse_args(argv)
    one_core()
    if args.quality:
        return quality(args)
    if args.real is not None:
        return real_frames(args.real or data_dir("kinect"), args.repeat)
    from planerel.segment import segment
    from planerel.segment.evaluate import evaluate

    first = first_call_ms()
    print(f"first call in a fresh process (numba cache load / compile): {first:.0f} ms")
    print("median CPU ms per call (wall time in brackets), one core; quality = SegComp correct "
          "of the GT planes at T = 0.8")
    for sub in (1, 4):
        for kind, seed in (SCENES if args.scene == "synth" else (("analytic", 0),)):
            cloud, gt = _scene(args.scene, sub, kind, seed)
            h, w = cloud.shape
            size = f"{w}x{h}"
            segment(cloud)  # warm
            valid = 100.0 * cloud.n_valid / (h * w)
            st = _stages(cloud, args.repeat)
            res = {}
            for name, kw in (("paper", dict(refine=False, split=False)),
                             ("planerel growing", dict(refine=False, split=False,
                                                       angle_order="reversed", seed_test=True)),
                             ("split=False", dict(split=False)), ("default", {})):
                wall = _median_ms(lambda c=cloud, k=kw: segment(c, **k), args.repeat)
                res[name] = (_CPU[-1], wall, evaluate(segment(cloud, **kw).labels, gt))
            paper = res["paper"][0]
            target = TARGETS[size]
            print(f"{size} {kind} seed {seed} ({valid:.0f} % valid pixels, "
                  f"{res['default'][2].n_gt} GT planes):")
            print(f"  the paper's algorithm as written (normals + region growing, refine=False, "
                  "split=False):"
                  f" {paper:.2f} ms ({res['paper'][1]:.2f}); target {target:g} ms: ratio "
                  f"{paper / target:.2f}; {res['paper'][2].correct} correct")
            print("    stages: " + ", ".join(f"{k} {v:.2f}" for k, v in st.items()))
            print(f"  planerel's growing instead (reversed phases + seed test, refine=False, "
                  f"split=False): {res['planerel growing'][0]:.2f} ms "
                  f"({res['planerel growing'][1]:.2f}); {res['planerel growing'][2].correct} "
                  "correct")
            print(f"  planerel's growing + boundary completion and leftover planes (split=False): "
                  f"{res['split=False'][0]:.2f} ms ({res['split=False'][1]:.2f}); "
                  f"{res['split=False'][2].correct} correct")
            print(f"  + planar post-processing = segment() default: {res['default'][0]:.2f} ms "
                  f"({res['default'][1]:.2f}); {res['default'][2].correct} correct, "
                  f"{res['default'][2].sparse} sparse")
            if kind == (SCENES[0][0] if args.scene == "synth" else "analytic"):
                for method, thr in (("sp", 0.01), ("snp", 0.05)):
                    t = _median_ms(lambda c=cloud, m=method, t=thr:
                                   segment(c, m, threshold=t, seed=0), args.baseline_repeat)
                    q = evaluate(segment(cloud, method, threshold=thr, seed=0).labels, gt)
                    print(f"  {method.upper()} {thr}: {_CPU[-1]:.0f} ms ({t:.0f}), "
                          f"x{_CPU[-1] / res['default'][0]:.0f} the default's time, "
                          f"x{_CPU[-1] / paper:.0f} the paper's algorithm's; {q.correct} correct, "
                          f"{q.sparse} sparse")
    print(f"load average (1, 5, 15 min) at the end: {os.getloadavg()}")
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print(f"peak RSS of this process (all frames + baselines): {peak:.0f} MB")
    print(f"peak RSS of a process that only segments one 640x480 frame: {_peak_rg_only():.0f} MB")
    return 0


def real_frames(folder: str, repeat: int) -> int:
    """Median CPU ms of ``segment()`` on real frames (the paper's algorithm, ``split=False``,
    default) with the per-stage times of the paper's algorithm."""
    import glob

    from planerel.io.readers import read
    from planerel.segment import segment

    files = kinect_files(folder) + sorted(glob.glob(os.path.join(str(folder), "*.pcd")))
    if not files:
        print(f"no depth TIFFs or PCD files in {folder}: nothing to time")
        return 0
    print("median CPU ms per call (wall time in brackets), one core")
    for f in files:
        cloud = read(f)
        h, w = cloud.shape
        segment(cloud)  # warm
        res = []
        for kw in (dict(refine=False, split=False), dict(split=False), {}):
            wall = _median_ms(lambda c=cloud, k=kw: segment(c, **k), repeat)
            res.append(f"{_CPU[-1]:.2f} ({wall:.2f})")
        st = _stages(cloud, repeat)
        print(f"{os.path.basename(f)} {w}x{h}, {100.0 * cloud.n_valid / (h * w):.0f} % valid: "
              f"the paper's algorithm {res[0]}, split=False {res[1]}, default {res[2]}")
        print("    stages: " + ", ".join(f"{k} {v:.2f}" for k, v in st.items()))
    print(f"load average (1, 5, 15 min) at the end: {os.getloadavg()}")
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

    from planerel.segment import segment
    from planerel.segment.evaluate import evaluate
    from planerel.synth.generator import CLASSES, generate_scene

    print("generator stairs (planerel.synth.generator defaults), per image:")
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
    abw = Path(args.abw or data_dir("abw"))
    files = sorted(glob.glob(str(abw / "*.range")))
    if files:
        from planerel.io.readers import read_abw, read_abw_gt

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
    from planerel.segment import segment
    from planerel.segment.evaluate import evaluate
    from planerel.segment.split import SplitParams
    from planerel.synth.generator import CameraRange, generate_scene, scene_seed

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
