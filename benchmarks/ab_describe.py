"""Issue 22's "rest" (``describe_scene`` minus ``measure_planes``) of this checkout against
another planerel, both in ONE process, alternated frame by frame.

``bench_speed_class.py --stage describe`` runs each side in its own process, one after the
other, and its rounds move by +-20 % with the load of the other sessions on the machine (the
same code measured 0.65-1.11 of itself, docs/benchmarks.md).  Here both packages are loaded in
one process (the reference as a renamed copy, ``planerel_ref``: its imports rewritten), each
frame is described by one side and then the other (the order swapped every pass), and
``measure_planes`` is timed inside each call and taken off.  A burst of load hits both sides
alike.  Per round: the sum over the frames of each frame's minimum (and median) over
``--passes`` passes, and the ratio this checkout / reference.  A checkout against itself
measured 1.00-1.04 (minima) and 0.97-1.01 (medians) at load 2.7-3.0 (speed22s).

    git archive main planerel | tar -x -C /tmp/refmain
    .venv/bin/python benchmarks/ab_describe.py /tmp/refmain [--passes 20] [--rounds 3]
    git archive 29f9aa3^ planerel | tar -x -C /tmp/ref29      # the layout before planerel.features
    .venv/bin/python benchmarks/ab_describe.py /tmp/ref29
    # the other direction (the script favours "this checkout" by about 2 %, speed23): the old
    # code as this checkout, this one as the reference, the same labels (this one's segment)
    git archive HEAD planerel | tar -x -C /tmp/refnew
    (cd /tmp && PYTHONPATH=/tmp/ref29 CHECKOUT/.venv/bin/python CHECKOUT/benchmarks/ab_describe.py \
        /tmp/refnew --labels-from-reference)

Frames: the Kinect TIFFs and the mOSD PCDs of ``../shared/data`` (bench_speed_class.py's ten),
labels from this checkout's ``segment(cloud)`` (``--labels-from-reference``: the reference's),
computed once and given to both sides.
"""

from __future__ import annotations

import argparse
import importlib
import re
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

from _setup import data_dir, kinect_files, one_core

_IMPORT = re.compile(r"\b(from|import) planerel\b")


def renamed_copy(folder: Path, dest: Path, name: str = "planerel_ref") -> Path:
    """Copy ``folder/planerel`` to ``dest/name`` with its imports of ``planerel`` rewritten
    (``from planerel...``, ``import planerel...``, ``"planerel.``); compiled caches left out
    (numba's name the module they were built for)."""
    src = folder / "planerel"
    out = dest / name
    shutil.copytree(src, out, ignore=shutil.ignore_patterns("__pycache__"))
    for f in out.rglob("*.py"):
        text = f.read_text()
        new = _IMPORT.sub(lambda m: f"{m.group(1)} {name}", text).replace('"planerel.', f'"{name}.')
        if new != text:
            f.write_text(new)
    return out


def _side(package: str):
    """``(describe_scene, read, planes module)`` of ``package`` (either layout)."""
    try:
        planes = importlib.import_module(package + ".features.planes")
        describe = importlib.import_module(package + ".features.facts").describe_scene
        read = importlib.import_module(package + ".io.readers").read
    except ImportError:  # before planerel.features (November 2026)
        planes = importlib.import_module(package + ".planes")
        describe = importlib.import_module(package + ".facts").describe_scene
        read = importlib.import_module(package + ".io").read
    return describe, read, planes


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("reference", help="folder holding the reference planerel/ package")
    ap.add_argument("--passes", type=int, default=20)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--labels-from-reference", action="store_true",
                    help="segment with the reference's planerel, not this checkout's: for the "
                         "other direction (an old checkout given by PYTHONPATH as 'this "
                         "checkout', the new one as the reference) with the same labels")
    a = ap.parse_args(argv)
    if not (Path(a.reference) / "planerel").is_dir():
        ap.error("give the folder that holds the reference planerel/ package")
    one_core()
    tmp = tempfile.TemporaryDirectory()
    renamed_copy(Path(a.reference), Path(tmp.name))
    sys.path.insert(0, tmp.name)

    files = kinect_files() + sorted(str(p) for p in data_dir("mosd").glob("*.pcd"))
    sides = [_side("planerel"), _side("planerel_ref")]
    clouds = [[s[1](f) for f in files] for s in sides]
    seg = 1 if a.labels_from_reference else 0
    segment = importlib.import_module(("planerel_ref" if seg else "planerel") + ".segment").segment
    labels = [segment(c).labels for c in clouds[seg]]
    inner = [0.0]

    def timed(mod):
        f = mod.measure_planes

        def w(*args, **kw):
            t = time.process_time()
            try:
                return f(*args, **kw)
            finally:
                inner[0] += time.process_time() - t
        mod.measure_planes = w

    for s in sides:
        timed(s[2])

    def rest(k: int, i: int) -> float:
        inner[0] = 0.0
        t = time.process_time()
        sides[k][0](clouds[k][i], labels[i])
        return time.process_time() - t - inner[0]

    for _ in range(2):  # compile and warm up
        for i in range(len(files)):
            rest(0, i)
            rest(1, i)
    print(f"this checkout {sides[0][2].__file__}\nreference     {a.reference}")
    print("load", open("/proc/loadavg").read().split()[:3], time.strftime("%H:%M:%S UTC", time.gmtime()))
    for r in range(a.rounds):
        got = [[[] for _ in files] for _ in sides]
        for p in range(a.passes):
            for i in range(len(files)):
                for k in ((0, 1) if (p + i) % 2 else (1, 0)):
                    got[k][i].append(rest(k, i))
        lo = [sum(1000 * min(x) for x in g) for g in got]
        med = [sum(1000 * statistics.median(x) for x in g) for g in got]
        kin = [sum(1000 * min(x) for x in g[:len(kinect_files())]) for g in got]
        print(f"round {r + 1}: the rest, sum of minima {lo[1]:7.2f} -> {lo[0]:7.2f} ms "
              f"({lo[0] / lo[1]:.3f}); Kinect frames {kin[1]:6.2f} -> {kin[0]:6.2f} "
              f"({kin[0] / kin[1]:.3f}); sum of medians {med[1]:7.2f} -> {med[0]:7.2f} "
              f"({med[0] / med[1]:.3f})", flush=True)
    print("load", open("/proc/loadavg").read().split()[:3], time.strftime("%H:%M:%S UTC", time.gmtime()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
