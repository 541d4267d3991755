"""Benchmark planerel's learner on the box / stairs / ramp task (one run per class).

Usage
-----
    .venv/bin/python benchmarks/bench_learner.py                 # synthetic 45-object task
    .venv/bin/python benchmarks/bench_learner.py STEM [STEM ...] # exported task(s), e.g. from
                                                                 # planerel export-aleph

Without stems it writes a relational stand-in for the 45-scene task (15 boxes, 15 staircases,
15 ramps; planes with orientation, incline, height, counts and step_up links, seeded noise)
using the task's own mode file ``aleph/modes_objects.pl`` and comparison predicates
``prolog/compare.pl`` when they are installed, and learns ``box/1``, ``stairs/1`` and
``ramp/1`` in turn.  It prints, per class, the rules, training accuracy, clauses explored,
search time and clauses per second, and the total time.  ``--set NAME=VALUE`` overrides
settings (defaults: those of the mode file).
"""

from __future__ import annotations

import argparse
import re
import sys
import tempfile
import time
from pathlib import Path

CLASSES = ("box", "stairs", "ramp")

FALLBACK_MODES = """\
:- set(search, heuristic).
:- set(evalfn, laplace).
:- set(clauselength, 4).
:- set(i, 2).
:- set(nodes, 5000).
:- set(minpos, 2).
:- modeb(1, nplanes(+obj, -nplanes)).
:- modeb(1, nhorizontal(+obj, -nhorizontal)).
:- modeb(1, nvertical(+obj, -nvertical)).
:- modeb(1, ninclined(+obj, -ninclined)).
:- modeb(*, has_plane(+obj, -plane)).
:- modeb(1, orientation(+plane, #orient)).
:- modeb(1, incline(+plane, -incline)).
:- modeb(1, height(+plane, -height)).
:- modeb(*, step_up(+plane, -plane)).
:- modeb(1, gteq(+nplanes, #nplanes)).
:- modeb(1, lteq(+nplanes, #nplanes)).
:- modeb(1, gteq(+nhorizontal, #nhorizontal)).
:- modeb(1, lteq(+nhorizontal, #nhorizontal)).
:- modeb(1, gteq(+ninclined, #ninclined)).
:- modeb(1, lteq(+ninclined, #ninclined)).
:- lazy_evaluate(lteq/2).
:- lazy_evaluate(gteq/2).
"""

FALLBACK_COMPARE = """\
gteq([P, N], T) :- !, min_list(P, T0), include(>(T0), N, B),
    ( B == [] -> T = T0 ; max_list(B, M), T is (T0 + M) / 2 ).
gteq(X, T) :- number(X), ( var(T) -> T = X ; number(T), X >= T ).
lteq([P, N], T) :- !, max_list(P, T0), include(<(T0), N, A),
    ( A == [] -> T = T0 ; min_list(A, M), T is (T0 + M) / 2 ).
lteq(X, T) :- number(X), ( var(T) -> T = X ; number(T), X =< T ).
"""


def _resource(package: str, name: str, fallback: str) -> str:
    from importlib.resources import files

    try:
        return files(package).joinpath(name).read_text()
    except (FileNotFoundError, ModuleNotFoundError):
        return fallback


def synthetic_objects(n_per_class: int = 15, seed: int = 0, max_steps: int = 6):
    """A list of ``(obj_id, cls, planes, step_ups)``; planes are ``(pid, orient, incline, height)``."""
    import numpy as np

    rng = np.random.default_rng(seed)
    objs = []
    k = 0
    for i in range(n_per_class * len(CLASSES)):
        cls = CLASSES[i % len(CLASSES)]
        k += 1
        sid = f"s{k:04d}"
        planes = []
        ups = []

        def add(orient, incline, height, sid=sid, planes=planes):
            pid = f"{sid}_p{len(planes):02d}"
            planes.append((pid, orient, round(float(incline), 1), round(float(height), 3)))
            return pid

        if cls == "box":
            top = rng.uniform(0.3, 0.9)
            add("horizontal", rng.normal(0, 1.5), top)
            for _ in range(int(rng.integers(1, 3))):
                add("vertical", 90 + rng.normal(0, 1.5), top / 2)
            if rng.random() < 0.15:                       # a spurious small plane (noise)
                add("inclined", rng.uniform(20, 40), top * rng.uniform(0.3, 0.9))
        elif cls == "stairs":
            rise = rng.uniform(0.15, 0.2)
            treads = []
            for s in range(int(rng.integers(3, max_steps + 1))):
                add("vertical", 90 + rng.normal(0, 1.5), (s + 0.5) * rise)
                treads.append(add("horizontal", rng.normal(0, 1.5), (s + 1) * rise))
            ups = list(zip(treads[:-1], treads[1:], strict=True))
            if rng.random() < 0.3:
                add("vertical", 90 + rng.normal(0, 1.5), rng.uniform(0.2, 0.6))  # a side wall
        else:
            h = rng.uniform(0.2, 0.5)
            add("inclined", rng.uniform(8, 30), h / 2)
            for _ in range(int(rng.integers(0, 3))):
                add("vertical", 90 + rng.normal(0, 1.5), h / 3)
            if rng.random() < 0.2:
                add("horizontal", rng.normal(0, 1.5), h)   # a landing at the top
        objs.append((f"{sid}_o1", cls, planes, ups))
    return objs


def write_task(folder: Path, objs, target: str) -> Path:
    """Write ``folder/target.b/.f/.n`` for one class; return the stem."""
    modes = _resource("planerel.aleph", "modes_objects.pl", FALLBACK_MODES)
    compare = _resource("planerel.prolog", "compare.pl", FALLBACK_COMPARE)
    preds = sorted({f"{m.group(1)}/{len(m.group(2).split(','))}"
                    for m in re.finditer(r"^:- modeb\(\s*[^,]+,\s*([a-z]\w*)\((.*)\)\)\.",
                                         modes, re.M)})
    lines = [f"% synthetic box/stairs/ramp stand-in, target {target}/1", "",
             f":- modeh(1, {target}(+obj)).", modes, ""]
    lines += [f":- determination({target}/1, {p})." for p in preds]
    lines += ["", compare, ""]
    facts: list[str] = []
    for oid, _cls, planes, ups in objs:
        counts = {o: sum(1 for p in planes if p[1] == o) for o in ("horizontal", "vertical", "inclined")}
        facts += [f"nplanes({oid}, {len(planes)}).", f"nhorizontal({oid}, {counts['horizontal']}).",
                  f"nvertical({oid}, {counts['vertical']}).", f"ninclined({oid}, {counts['inclined']})."]
        for pid, orient, inc, h in planes:
            facts += [f"has_plane({oid}, {pid}).", f"orientation({pid}, {orient}).",
                      f"incline({pid}, {inc!r}).", f"height({pid}, {h!r})."]
        facts += [f"step_up({p}, {q})." for p, q in ups]
    # group clauses by predicate (no discontiguous clauses)
    facts.sort(key=lambda f: f.split("(")[0])
    lines += facts
    (folder / f"{target}.b").write_text("\n".join(lines) + "\n")
    (folder / f"{target}.f").write_text("".join(f"{target}({o}).\n" for o, c, _, _ in objs if c == target))
    (folder / f"{target}.n").write_text("".join(f"{target}({o}).\n" for o, c, _, _ in objs if c != target))
    return folder / target


def main(argv=None) -> int:
    from planerel.learn import learn, parse_settings

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("stems", nargs="*", help="Aleph problem stems (default: the synthetic task)")
    ap.add_argument("--set", action="append", default=[], dest="settings", metavar="NAME=VALUE")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--keep", metavar="DIR", help="write the synthetic task here and keep it")
    ap.add_argument("--max-steps", type=int, default=6,
                    help="most steps of a synthetic staircase (12 gives ~25-plane objects and "
                         "bottom clauses of 150+ literals)")
    args = ap.parse_args(argv)
    settings = parse_settings(args.settings)

    tmp = None
    if args.stems:
        stems = [Path(s) for s in args.stems]
    else:
        if args.keep:
            folder = Path(args.keep)
            folder.mkdir(parents=True, exist_ok=True)
        else:
            tmp = tempfile.TemporaryDirectory(prefix="planerel-bench-")
            folder = Path(tmp.name)
        objs = synthetic_objects(seed=args.seed, max_steps=args.max_steps)
        stems = [write_task(folder, objs, c) for c in CLASSES]
    total_wall = total_search = 0.0
    total_nodes = 0
    t0 = time.perf_counter()
    for stem in stems:
        r = learn(stem, settings=settings, timeout=300)
        total_wall += r.seconds
        total_search += r.search_seconds or 0.0
        total_nodes += r.clauses_explored or 0
        print(f"== {stem.name}: train accuracy {r.accuracy:.3f} "
              f"(tp {r.train.tp} fn {r.train.fn} fp {r.train.fp} tn {r.train.tn}), "
              f"{r.clauses_explored} clauses, search {r.search_seconds:.2f} s, "
              f"{r.nodes_per_second:.0f} clauses/s, wall {r.seconds:.2f} s")
        for rule in r.rules:
            print("   ", rule)
    elapsed = time.perf_counter() - t0
    print(f"total: {len(stems)} classes, {total_nodes} clauses explored, search {total_search:.2f} s "
          f"({total_nodes / max(total_search, 1e-9):.0f} clauses/s), learner wall {total_wall:.2f} s, "
          f"elapsed {elapsed:.2f} s")
    if tmp is not None:
        tmp.cleanup()
    return 0


if __name__ == "__main__":
    sys.exit(main())
