"""Speed class of the default segmentation against an older planerel (issue 15 item 4).

``bench_adapt.py`` compares the adaptive default with the fixed settings *of the same code*;
this script compares today's ``segment(cloud)`` (the default, sensor-adaptive) with the
``segment(cloud)`` of another planerel checkout, e.g. the fixed default of the day the issue
was filed, extracted with ``git archive``.  Each side runs in its own process (one core,
numba compiled before timing), the sides alternate for ``--rounds`` rounds, and the script prints
the CPU ms per call (median of ``--repeat``) per Kinect frame and the ratio today / reference
of each round.

Usage (from the repository root)::

    git archive d6738b2^ planerel | tar -x -C /tmp/ref15      # the default before adaptation
    .venv/bin/python benchmarks/bench_speed_class.py /tmp/ref15 [--rounds 3] [--repeat 15]
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

from _setup import kinect_files, one_core

HERE = Path(__file__).resolve().parent


def child(repeat: int) -> int:
    """Time ``segment(cloud)`` of whatever planerel is first on the path; print JSON."""
    one_core()
    try:
        from planerel.io.readers import read
    except ImportError:  # before planerel.io became a package (November 2026)
        from planerel.io import read
    from planerel.segment import segment

    out = {}
    for f in kinect_files():
        c = read(f)
        segment(c)  # compile and warm up
        times = []
        for _ in range(repeat):
            t = time.process_time()
            segment(c)
            times.append(time.process_time() - t)
        out[Path(f).name.split("_depth")[0]] = 1000 * statistics.median(times)
    import planerel

    print(json.dumps({"planerel": str(Path(planerel.__file__).parent), "ms": out}))
    return 0


def _run(pythonpath: str | None, repeat: int) -> dict:
    env = dict(os.environ)
    if pythonpath:
        env["PYTHONPATH"] = pythonpath
    else:
        env.pop("PYTHONPATH", None)
    proc = subprocess.run([sys.executable, str(HERE / "bench_speed_class.py"), "--child",
                           "--repeat", str(repeat)], capture_output=True, text=True, env=env,
                          cwd=str(HERE))
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
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.child:
        return child(a.repeat)
    if not a.reference or not (Path(a.reference) / "planerel").is_dir():
        ap.error("give the folder that holds the reference planerel/ package")
    for r in range(a.rounds):
        ref = _run(str(Path(a.reference).resolve()), a.repeat)
        new = _run(None, a.repeat)
        if r == 0:
            print(f"reference: {ref['planerel']}\ntoday:     {new['planerel']}")
            print(f"{'round':>5s} {'frame':30s} {'reference ms':>13s} {'today ms':>9s} {'ratio':>6s}")
        for name, ms in ref["ms"].items():
            print(f"{r + 1:5d} {name:30s} {ms:13.2f} {new['ms'][name]:9.2f} {new['ms'][name] / ms:6.2f}")
    print(f"load average (1, 5, 15 min) at the end: {os.getloadavg()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
