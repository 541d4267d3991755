"""Curved / unexplained-point proposals (planerel.features.curved): found rate, planar fractions, time.

    .venv/bin/python benchmarks/bench_curved.py [--repeat N] [--synth N]

Frames: the mOSD frames of ``../shared/data/mosd`` (640x480; ``learn0-5`` boxes, ``test31``
cylinders) and N cluttered varied-world scenes (320x240, 2-3 extra objects, seed 22, types by
kind: cylinders are clutter).  Each frame is segmented once; then ``describe_scene`` runs with
``CurvedParams(enabled=False)`` (the same-run reference: no cluster proposals; planar fractions
are still measured), with the defaults and with ``min_area`` 0.002 m^2, interleaved, ``--repeat`` times; the median per
frame is summed.  Printed: ms per frame of both and their ratio; per source and object type
the found rate (IoU >= 0.5), false proposals per frame, and for the found objects the mean
planar fraction and how many are ``curved``.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time

from _setup import cluttered_set, data_dir

MOSD_TYPES = {"test31": "round"}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--synth", type=int, default=30, help="synthetic scenes (0 = none)")
    args = ap.parse_args(argv)
    from planerel.features.curved import CurvedParams
    from planerel.features.facts import describe_scene
    from planerel.features.object_eval import frame_truth, proposal_image, score_objects, summarize
    from planerel.segment import segment

    data = data_dir("mosd")
    inputs = [(p, MOSD_TYPES.get(p.stem, "box"), "mosd")
              for p in (sorted(data.glob("*.pcd")) if data.is_dir() else [])]
    tmp = tempfile.TemporaryDirectory()
    if args.synth:
        inputs.append((cluttered_set(tmp.name, args.synth, seed=22), None, "synth"))
    frames = []
    for path, ty_name, src in inputs:
        for name, cloud, truth, ty in frame_truth(path, ty_name, "kind"):
            frames.append((src, name, cloud, segment(cloud).labels, truth, ty))
    variants = {"no clusters": CurvedParams(enabled=False), "default": CurvedParams(),
                "min_area 0.002": CurvedParams(min_area=0.002)}
    times = {k: [] for k in variants}
    scores = {k: {"mosd": [], "synth": []} for k in variants}
    for src, name, cloud, labels, truth, ty in frames:
        per = {k: [] for k in variants}
        for _ in range(args.repeat):
            for k, cp in variants.items():
                t0 = time.perf_counter()
                d = describe_scene(cloud, labels, curved_params=cp)
                per[k].append(time.perf_counter() - t0)
                if len(per[k]) == 1:
                    img = proposal_image(d.labels, [o.planes for o in d.objects],
                                         [o.mask for o in d.objects])
                    s = score_objects(img, truth, name=name, types=ty)
                    s.planar = {o: d.objects[j].planar_fraction for o, j in s.best_prop.items()
                                if 0 <= j < len(d.objects)}
                    s.curved = {o: d.objects[j].curved for o, j in s.best_prop.items()
                                if 0 <= j < len(d.objects)}
                    scores[k][src].append(s)
        for k in variants:
            times[k].append(statistics.median(per[k]))
    nf = len(frames)
    print(f"{nf} frames, describe_scene (planes, relations, proposals, curved) per frame:")
    for k in variants:
        print(f"  {k:12s} {1000 * sum(times[k]) / nf:7.1f} ms")
    ref = sum(times["no clusters"])
    print(f"  ratio default / no clusters: {sum(times['default']) / ref:.3f}")
    for src in ("mosd", "synth"):
        for k in variants:
            if not scores[k][src]:
                continue
            t = summarize(scores[k][src])
            print(f"{src} [{k}]: {t['frames']} frames, found {t['found']}/{t['objects']} "
                  f"({100 * t['found_rate']:.1f} %), false {t['false_per_frame']:.2f}/frame "
                  f"(background {t['background_per_frame']:.2f}, fragments "
                  f"{t['fragment_per_frame']:.2f}), merged {t['merged']}, split {t['split']}")
            for ty, d in sorted(t["by_type"].items()):
                pf = d["mean_planar_fraction"]
                print(f"    {ty:12s} found {d['found']}/{d['objects']}, planar fraction "
                      f"{'-' if pf is None else f'{pf:.2f}'}, curved {d['curved']}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
