"""Time attributes + relations + facts for one synthetic stairs scene at 160x120 and 640x480.

    .venv/bin/python benchmarks/bench_features.py [--repeat 20]

Ground-truth labels of a ``planerel.synth.generator`` stairs scene are used (segmentation is timed by its
own benchmark); the numba kernels are warmed up first.  Prints the median wall time per stage.
"""

from __future__ import annotations

import argparse
import statistics
import time


def main() -> None:
    from planerel.features.facts import describe_scene, facts_text
    from planerel.features.planes import measure_planes
    from planerel.features.relations import objects_from_truth, relate
    from planerel.synth.generator import generate_scene

    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeat", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    for sub in (4, 1):
        sc = generate_scene("stairs", args.seed, subsample=sub)
        obj = {p.index: (p.object_index if p.object_index > 0 else -1) for p in sc.planes}
        groups = objects_from_truth(sc.gt_labels, sc.gt_labels, obj)
        describe_scene(sc.cloud, sc.gt_labels, objects=groups)  # warm-up (numba, shapely)
        t_pl, t_rel, t_all = [], [], []
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            ps = measure_planes(sc.cloud, sc.gt_labels)
            t1 = time.perf_counter()
            relate(ps, sc.cloud)
            t2 = time.perf_counter()
            t_pl.append(t1 - t0)
            t_rel.append(t2 - t1)
            t0 = time.perf_counter()
            d = describe_scene(sc.cloud, sc.gt_labels, scene_id=sc.scene_id, objects=groups)
            facts_text([d])
            t_all.append(time.perf_counter() - t0)
        h, w = sc.gt_labels.shape
        ms = lambda xs: 1000 * statistics.median(xs)  # noqa: E731
        print(f"{w}x{h}: {len(ps)} planes | planes {ms(t_pl):.1f} ms | relations "
              f"{ms(t_rel):.1f} ms | planes+relations+proposals+facts {ms(t_all):.1f} ms "
              f"(median of {args.repeat})")


if __name__ == "__main__":
    main()
