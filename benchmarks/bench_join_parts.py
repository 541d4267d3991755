"""join_parts' cost on the real frames: the compiled version (planerel.features.curved) against
the numpy reference of synth22q (tests/test_join_parts_kernels.py), both timed in this run on
the proposals describe_scene hands join_parts (join_parts on) for the Kinect TIFFs, office1.pcd
and the mOSD PCDs; checks the two give the same output (docs/objects.md, "join_parts compiled
(join22)").

    nice -n 5 taskset -c 1 .venv/bin/python benchmarks/bench_join_parts.py --repeat 9
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from _setup import data_dir, kinect_files

ROOT = Path(__file__).resolve().parents[1]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=9)
    a = ap.parse_args(argv)
    sys.path.insert(0, str(ROOT / "tests"))
    from test_join_parts_kernels import reference_join_parts

    import planerel.features.curved as cv
    from planerel.features.curved import CurvedParams
    from planerel.features.facts import describe_scene
    from planerel.io.readers import read
    from planerel.segment import segment

    new = cv.join_parts
    seen = []

    def rec(cobjs, xyz, lab, *args, **kw):
        seen.append((list(cobjs), np.array(xyz), np.array(lab), args, kw))
        return new(cobjs, xyz, lab, *args, **kw)

    files = (kinect_files() + [str(data_dir("kinect") / "office1.pcd")]
             + sorted(str(p) for p in data_dir("mosd").glob("*.pcd")))
    cv.join_parts = rec
    try:
        for f in files:
            c = read(f)
            describe_scene(c, segment(c).labels, curved_params=CurvedParams(join_parts=True))
    finally:
        cv.join_parts = new
    print(f"{'frame':34s} {'props':>5s} {'grown':>5s} {'numpy ms':>9s} {'compiled ms':>11s} "
          f"{'ratio':>6s} same")
    for f, (cobjs, xyz, lab, args, kw) in zip(files, seen, strict=True):
        got, want = new(cobjs, xyz, lab, *args, **kw), reference_join_parts(cobjs, xyz, lab,
                                                                            *args, **kw)
        same = all(g.n_points == w.n_points and (g.mask is None) == (w.mask is None)
                   and (w.mask is None or np.array_equal(g.mask, w.mask))
                   for g, w in zip(got, want, strict=True))
        ms = {}
        for fn in (reference_join_parts, new):
            ts = []
            for _ in range(a.repeat):
                t = time.process_time()
                fn(cobjs, xyz, lab, *args, **kw)
                ts.append(time.process_time() - t)
            ms[fn] = 1000 * statistics.median(ts)
        grown = sum(g.n_points != c.n_points for g, c in zip(got, cobjs, strict=True))
        print(f"{Path(f).name[:34]:34s} {len(cobjs):5d} {grown:5d} {ms[reference_join_parts]:9.2f} "
              f"{ms[new]:11.3f} {ms[reference_join_parts] / ms[new]:6.1f} {same}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
