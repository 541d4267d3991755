"""Benchmark classification by logic query: segment + describe + Prolog query per scene.

Usage
-----
    .venv/bin/python benchmarks/bench_classify.py [--scenes 30] [--size 640x480 --subsample 4]

Learns a model on a small synthetic set (ground-truth planes, so the model is the same every
run), then classifies freshly generated scenes after one warm-up call and prints the median
time per scene end to end, with the share of each stage measured in the same run.  Target:
at most 50 ms per 160x120 scene on one core (``taskset -c 0``).
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", type=int, default=30)
    ap.add_argument("--subsample", type=int, default=4)
    args = ap.parse_args()

    from planerel.classify.classifier import Classifier
    from planerel.features.facts import describe_scene
    from planerel.ilp.pipeline import learn_rules
    from planerel.ilp.scenes import describe_scenes
    from planerel.segment import segment
    from planerel.synth.generator import CLASSES, generate_dataset, generate_scene

    with tempfile.TemporaryDirectory() as tmp:
        ds = generate_dataset(Path(tmp) / "train", n_box=4, n_stairs=4, n_ramp=4, seed=5,
                              size=(640, 480), subsample=args.subsample)
        descs, _ = describe_scenes(ds, method="gt", jobs=1, cache="none")
        model = learn_rules(descs, list(CLASSES))
        rules = Path(tmp) / "rules.pl"
        rules.write_text(model.text())
        clf = Classifier(rules)
        scenes = [generate_scene(CLASSES[i % 3], seed=900 + i, size=(640, 480),
                                 subsample=args.subsample) for i in range(args.scenes)]
        clf.classify(scenes[0].cloud, scene_id="s9999")  # warm-up: numba cache, Prolog
        total, seg_t, desc_t = [], [], []
        for i, sc in enumerate(scenes):
            t0 = time.perf_counter()
            clf.classify(sc.cloud, scene_id=f"s{i:04d}")
            total.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            lab = segment(sc.cloud).labels
            seg_t.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            describe_scene(sc.cloud, lab, scene_id="s0000")
            desc_t.append(time.perf_counter() - t0)
    h, w = scenes[0].cloud.shape
    med = statistics.median(total) * 1000
    ms, md = statistics.median(seg_t) * 1000, statistics.median(desc_t) * 1000
    print(f"classify {w}x{h}, {len(scenes)} scenes: median {med:.1f} ms per scene end to end")
    print(f"  segmentation {ms:.1f} ms, description {md:.1f} ms, "
          f"facts + Prolog query {max(0.0, med - ms - md):.1f} ms (by difference)")
    print(f"  target 50 ms at 160x120: ratio {med / 50:.2f}")


if __name__ == "__main__":
    main()
