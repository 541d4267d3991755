"""Speed class of the default segmentation (or description) against an older planerel.

``bench_adapt.py`` compares the adaptive default with the fixed settings *of the same code*;
this script compares today's ``segment(cloud)`` (the default, sensor-adaptive) with the
``segment(cloud)`` of another planerel checkout, e.g. the fixed default of the day the issue
was filed, extracted with ``git archive``.  Each side runs in its own process (one core,
numba compiled before timing), the sides alternate for ``--rounds`` rounds, and the script prints
the CPU ms per call (median of ``--repeat``) per Kinect frame and the ratio today / reference
of each round.

With ``--stage describe`` it times ``describe_scene(cloud, labels)`` instead (measure the
planes, relate them, propose objects: issue 22's "proposals + relations"), on the Kinect
frames and the mOSD frames, with the same labels on both sides: today's ``segment(cloud)``,
computed once by this process and handed to both.

Usage (from the repository root)::

    git archive d6738b2^ planerel | tar -x -C /tmp/ref15      # the default before adaptation
    .venv/bin/python benchmarks/bench_speed_class.py /tmp/ref15 [--rounds 3] [--repeat 15]
    git archive 29f9aa3^ planerel | tar -x -C /tmp/ref22      # the proposals before issue 22
    .venv/bin/python benchmarks/bench_speed_class.py /tmp/ref22 --stage describe --repeat 5
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

from _setup import data_dir, kinect_files, one_core

HERE = Path(__file__).resolve().parent


def _frames(stage: str) -> list[str]:
    """The frames a stage is timed on: the Kinect TIFFs, and for ``describe`` the mOSD PCDs."""
    mosd = sorted(str(p) for p in data_dir("mosd").glob("*.pcd")) if stage == "describe" else []
    return kinect_files() + mosd


def _name(f: str) -> str:
    return Path(f).name.split("_depth")[0]


def child(repeat: int, stage: str = "segment", labels: str | None = None) -> int:
    """Time ``segment(cloud)`` (or ``describe_scene(cloud, labels)`` with the labels of the
    ``labels`` .npz file) of whatever planerel is first on the path; print JSON."""
    one_core()
    try:
        from planerel.io.readers import read
    except ImportError:  # before planerel.io became a package (November 2026)
        from planerel.io import read
    if stage == "describe":
        import numpy as np

        import planerel

        # not `try: import planerel.features`: the editable install of this checkout would
        # supply a package the reference does not have
        if (Path(planerel.__file__).parent / "features").is_dir():
            from planerel.features.facts import describe_scene
            from planerel.features.planes import measure_planes
        else:  # before planerel.features (November 2026)
            from planerel.facts import describe_scene
            from planerel.planes import measure_planes

        saved = np.load(labels)
        call = lambda c, f: describe_scene(c, saved[_name(f)], scene_id="s0000")  # noqa: E731
        # the planes' measurement alone, to tell it from what follows (relations, proposals)
        part = lambda c, f: measure_planes(c, saved[_name(f)])  # noqa: E731
    else:
        from planerel.segment import segment

        call = lambda c, f: segment(c)  # noqa: E731
        part = None
    out, planes = {}, {}
    for f in _frames(stage):
        c = read(f)
        call(c, f)  # compile and warm up
        times, ptimes = [], []
        for _ in range(repeat):
            t = time.process_time()
            call(c, f)
            times.append(time.process_time() - t)
            if part is not None:
                t = time.process_time()
                part(c, f)
                ptimes.append(time.process_time() - t)
        out[_name(f)] = 1000 * statistics.median(times)
        if ptimes:
            planes[_name(f)] = 1000 * statistics.median(ptimes)
    import planerel

    print(json.dumps({"planerel": str(Path(planerel.__file__).parent), "ms": out,
                      "planes_ms": planes}))
    return 0


def _run(pythonpath: str | None, repeat: int, stage: str = "segment",
         labels: str | None = None) -> dict:
    env = dict(os.environ)
    if pythonpath:
        env["PYTHONPATH"] = pythonpath
    else:
        env.pop("PYTHONPATH", None)
    extra = ["--stage", stage] + (["--labels", labels] if labels else [])
    proc = subprocess.run([sys.executable, str(HERE / "bench_speed_class.py"), "--child",
                           "--repeat", str(repeat), *extra], capture_output=True, text=True,
                          env=env, cwd=str(HERE))
    if proc.returncode != 0 or not proc.stdout.strip():
        tail = (proc.stderr.strip().splitlines() or ["no output"])[-1]
        sys.exit(f"bench_speed_class: the {'reference' if pythonpath else 'current'} planerel "
                 f"failed ({pythonpath or 'this checkout'}): {tail}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("reference", nargs="?", help="folder holding the reference planerel/ package")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--repeat", type=int, default=15)
    ap.add_argument("--stage", choices=("segment", "describe"), default="segment",
                    help="what is timed: segment(cloud) (default) or describe_scene(cloud, labels)")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--labels", help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.child:
        return child(a.repeat, a.stage, a.labels)
    if not a.reference or not (Path(a.reference) / "planerel").is_dir():
        ap.error("give the folder that holds the reference planerel/ package")
    labels = None
    if a.stage == "describe":
        import tempfile

        import numpy as np

        from planerel.io.readers import read
        from planerel.segment import segment

        tmp = tempfile.TemporaryDirectory()
        labels = str(Path(tmp.name) / "labels.npz")
        np.savez(labels, **{_name(f): segment(read(f)).labels for f in _frames("describe")})
    for r in range(a.rounds):
        ref = _run(str(Path(a.reference).resolve()), a.repeat, a.stage, labels)
        new = _run(None, a.repeat, a.stage, labels)
        if r == 0:
            print(f"reference: {ref['planerel']}\ntoday:     {new['planerel']}")
            print(f"{'round':>5s} {'frame':30s} {'reference ms':>13s} {'today ms':>9s} {'ratio':>6s}")
        for name, ms in ref["ms"].items():
            print(f"{r + 1:5d} {name:30s} {ms:13.2f} {new['ms'][name]:9.2f} {new['ms'][name] / ms:6.2f}")
        total_ref, total_new = sum(ref["ms"].values()), sum(new["ms"].values())
        print(f"{r + 1:5d} {'all frames':30s} {total_ref:13.2f} {total_new:9.2f} "
              f"{total_new / total_ref:6.2f}")
        if ref.get("planes_ms"):
            # describe_scene minus measure_planes: relations, proposals and what they need
            pr, pn = sum(ref["planes_ms"].values()), sum(new["planes_ms"].values())
            print(f"{r + 1:5d} {'  of which measure_planes':30s} {pr:13.2f} {pn:9.2f} {pn / pr:6.2f}")
            print(f"{r + 1:5d} {'  the rest (relate, propose)':30s} {total_ref - pr:13.2f} "
                  f"{total_new - pn:9.2f} {(total_new - pn) / (total_ref - pr):6.2f}")
    print(f"load average (1, 5, 15 min) at the end: {os.getloadavg()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
