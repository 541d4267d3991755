"""What single relation settings cost in issue 22's "rest" (``describe_scene`` minus
``measure_planes``): this checkout's code with its defaults against the same code with one
``RelationParams`` field changed (a feature switched off), all in ONE process, the variants
alternated frame by frame (the order reversed every pass) as ``ab_describe.py`` alternates two
codes.  Per variant: the sum over the frames of each frame's minimum over ``--passes``.  A
feature's cost is the defaults' sum minus its variant's; it includes the work the feature's
answers lead to downstream.  The variants change the output: this attributes time, it checks
nothing.

    .venv/bin/python benchmarks/rest_features.py [--passes 10] \
        [--off tall_narrow_width=0 lying_small_length=0 tall_speckle_floor=0 ...]

Frames: the Kinect TIFFs and the mOSD PCDs of ``../shared/data`` (``ab_describe.py``'s ten),
labels from ``segment(cloud)``, computed once.
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import replace

from _setup import data_dir, kinect_files

OFF = ("tall_narrow_width=0", "lying_small_length=0", "tall_speckle_floor=0",
       "tall_top_cover=0", "lying_ring_band=0")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--passes", type=int, default=10)
    ap.add_argument("--off", nargs="*", default=list(OFF),
                    help="RelationParams FIELD=VALUE, one variant each (default: %(default)s)")
    a = ap.parse_args(argv)
    import planerel.features.planes as planes_mod
    from planerel.features.facts import describe_scene
    from planerel.features.relations import RelationParams
    from planerel.io.readers import read
    from planerel.segment import segment

    base = RelationParams()
    variants = {"defaults": base}
    for item in a.off:
        name, _, value = item.partition("=")
        if not hasattr(base, name):
            ap.error(f"RelationParams has no field {name!r}")
        kind = type(getattr(base, name))
        val = value.lower() in ("1", "true", "on") if kind is bool else kind(value)
        variants[item] = replace(base, **{name: val})
    files = kinect_files() + sorted(str(p) for p in data_dir("mosd").glob("*.pcd"))
    clouds = [read(f) for f in files]
    labels = [segment(c).labels for c in clouds]
    inner = [0.0]
    measure = planes_mod.measure_planes

    def timed(*args, **kw):
        t = time.process_time()
        try:
            return measure(*args, **kw)
        finally:
            inner[0] += time.process_time() - t
    planes_mod.measure_planes = timed

    def rest(p, i: int) -> float:
        inner[0] = 0.0
        t = time.process_time()
        describe_scene(clouds[i], labels[i], relation_params=p)
        return time.process_time() - t - inner[0]

    names = list(variants)
    for _ in range(2):  # compile and warm up
        for k in names:
            for i in range(len(files)):
                rest(variants[k], i)
    got = {k: [[] for _ in files] for k in names}
    print("load", open("/proc/loadavg").read().split()[:3], time.strftime("%H:%M:%S UTC", time.gmtime()))
    for p in range(a.passes):
        for i in range(len(files)):
            for k in (names if p % 2 else names[::-1]):
                got[k][i].append(rest(variants[k], i))
    d = sum(1000 * min(x) for x in got["defaults"])
    for k in names:
        s = sum(1000 * min(x) for x in got[k])
        print(f"{k:28s} {s:7.2f} ms  cost {d - s:6.2f} ms ({100 * (d - s) / d:5.1f} % of the rest)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
