"""Classify time of real frames (labelled set folders, as ``real_unseen.py`` reads them), per
frame the minimum over ``--passes`` passes after one warm-up pass (numba's kernels compiled
and cached), and their sum by frame size.

    .venv/bin/python benchmarks/time_classify_real.py /work/hunt55/*/ /work/hunt56/*/ \\
        /work/hunt57/*/ [--model out/model] [--passes 3] [--json F]
    # another code on the same frames, interleaved with this one's runs (the load moves):
    git archive main planerel | tar -x -C /tmp/refmain
    PYTHONPATH=/tmp/refmain .venv/bin/python benchmarks/time_classify_real.py ...

Each process times one code; run the two alternately (ref, new, ref, new) and compare the
runs next to each other: the other sessions' load moves a run by 20 % or more.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time

import numpy as np
from real_unseen import read_frame, read_labels


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folders", nargs="+", metavar="DIR")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--passes", type=int, default=3)
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    import planerel
    from planerel.classify.classifier import Classifier

    frames = []
    for folder in a.folders:
        for fr in read_labels(folder)["frames"]:
            cloud, up = read_frame(folder, fr)
            frames.append((f"{os.path.basename(os.path.normpath(folder))}/{fr['file']}", cloud, up))
    print(f"planerel {planerel.__file__}")
    print("load", open("/proc/loadavg").read().split()[:3], time.strftime("%H:%M:%S UTC", time.gmtime()))
    best = {}
    with Classifier(a.model) as clf:
        for p in range(a.passes + 1):
            for name, cloud, up in frames:
                t = time.perf_counter()
                clf.classify(cloud, scene_id="s", up=up)
                ms = 1000 * (time.perf_counter() - t)
                if p:  # pass 0 warms up
                    best[name] = min(best.get(name, np.inf), ms)
    by_size = {}
    for name, cloud, _ in frames:
        print(f"{name:50s} {cloud.shape[1]}x{cloud.shape[0]} {best[name]:7.0f} ms")
        by_size.setdefault(f"{cloud.shape[1]}x{cloud.shape[0]}", []).append(best[name])
    for size, ms in sorted(by_size.items()):
        print(f"{size:10s} {len(ms):3d} frames  sum {sum(ms):7.0f} ms  median {statistics.median(ms):6.0f} ms")
    print(f"all        {len(best):3d} frames  sum {sum(best.values()):7.0f} ms")
    print("load", open("/proc/loadavg").read().split()[:3], time.strftime("%H:%M:%S UTC", time.gmtime()))
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(best, fh, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
