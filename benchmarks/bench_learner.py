"""Benchmark planerel's learner on the box / stairs / ramp task, against the real Aleph.

Usage
-----
    .venv/bin/python benchmarks/bench_learner.py                  # the demo's 45-scene set
    .venv/bin/python benchmarks/bench_learner.py --scenes 1000    # a larger set, same generator
    .venv/bin/python benchmarks/bench_learner.py --dataset DIR    # an existing data set
    .venv/bin/python benchmarks/bench_learner.py --thresholds     # counts with lazy thresholds
    .venv/bin/python benchmarks/bench_learner.py STEM [STEM ...]  # exported Aleph problems
    .venv/bin/python benchmarks/bench_learner.py --world varied --counts 34 33 33 --seed 1 \
        --heldout-counts 10 10 10                                 # varied world, held-out scored
    .venv/bin/python benchmarks/bench_learner.py --world varied --counts 334 333 333 --seed 1 \
        --labels segment --heldout-counts 100 100 100             # what `planerel learn` learns from

Without stems it generates the data set (the demo's: 12 box, 15 stairs, 18 ramp scenes, seed 0,
640x480 subsampled 4x; ``--scenes N`` scales the three counts), exports it with ``planerel
export-aleph`` and the relational task file (``aleph/modes_relational.pl``, or ``--task FILE``),
and learns ``box/1``, ``stairs/1`` and ``ramp/1`` in turn. Per class it prints the training
accuracy, clauses explored, the learner's search CPU time and the whole process's wall and CPU
time (SWI-Prolog start-up and loading the ``.b`` included). When the real Aleph is found
(``PLANEREL_ALEPH=/path/to/aleph_orig.pl``) it runs on the same files in the same run and the
ratios builtin / Aleph are printed (< 1: planerel's learner is faster). CPU times are the
figures to compare on a shared machine; wall times depend on the load.

``--heldout DIR`` (an ``export-aleph`` folder with the same classes) or ``--heldout-counts``
(a held-out set generated like the training set, seed + 1) scores every learned theory on
unseen scenes (:func:`planerel.ilp.learn.score_theory`; unit clauses left out, as ``planerel
learn`` does).
"""

from __future__ import annotations

import argparse
import re
import resource
import sys
import tempfile
import time
from pathlib import Path

CLASSES = ("box", "stairs", "ramp")
DEMO_COUNTS = (12, 15, 18)


def _child_cpu() -> float:
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def run(stem: Path, engine: str, settings, timeout: float):
    """One learning run: (LearnResult or None, process CPU seconds, error text)."""
    from planerel.errors import PlanerelError
    from planerel.ilp.learn import learn

    c0 = _child_cpu()
    try:
        r = learn(stem, engine=engine, settings=settings, timeout=timeout)
    except PlanerelError as exc:
        return None, _child_cpu() - c0, str(exc)
    return r, _child_cpu() - c0, ""


def aleph_search_seconds(output: str) -> float | None:
    """Aleph's own ``[time taken] [S]`` (induce), when its printout has it."""
    m = re.findall(r"\[time taken\]\s*\[([0-9.eE+-]+)\]", output)
    return float(m[-1]) if m else None


def counts_as_thresholds(src: Path, dest: Path) -> Path:
    """A harder variant of a task file: the plane counts as numbers compared with lazily
    evaluated lteq/gteq thresholds (``nhorizontal(+obj, -nhorizontal)``, ``lteq(+nhorizontal,
    #nhorizontal)``) instead of constants; bottom clauses grow and searches run longer.  The
    variant holds the task's directive lines with its includes expanded (``task_directives``)."""
    from planerel.ilp.aleph_export import task_directives

    text = "\n".join(task_directives(str(src))) + "\n"
    extra = []
    for name in ("nhorizontal", "nvertical", "ninclined"):
        text = text.replace(f"{name}(+obj, #{name})", f"{name}(+obj, -{name})")
        extra += [f":- modeb(1, gteq(+{name}, #{name})).", f":- modeb(1, lteq(+{name}, #{name}))."]
    dest.write_text(text + "\n% counts compared with thresholds (bench_learner.py --thresholds)\n"
                    + "\n".join(extra) + "\n")
    return dest


def make_task(folder: Path, scenes: int, dataset: str | None, task: str | None, seed: int,
              thresholds: bool = False, world: str = "paper", counts=None,
              labels: str = "gt") -> list[Path]:
    from importlib.resources import files

    from planerel.ilp.aleph_export import export_dataset
    from planerel.synth.generator import generate_dataset

    if dataset is None:
        k = scenes / sum(DEMO_COUNTS)
        nb, ns, nr = counts or (max(1, round(c * k)) for c in DEMO_COUNTS)
        t0 = time.perf_counter()
        dataset = str(generate_dataset(folder / "data", n_box=nb, n_stairs=ns, n_ramp=nr, seed=seed,
                                       size=(640, 480), subsample=4, world=world))
        print(f"data set: {nb} box, {ns} stairs, {nr} ramp scenes ({world} world, seed {seed}), "
              f"generated in {time.perf_counter() - t0:.1f} s")
    if task is None:
        rel = files("planerel.aleph").joinpath("modes_relational.pl")
        task = str(rel) if rel.is_file() else None
    if thresholds and task is not None:
        task = str(counts_as_thresholds(Path(task), folder / "task_thresholds.pl"))
    print(f"task file: {task or 'planerel default (aleph/modes_objects.pl)'}")
    export_dataset(dataset, folder / "aleph", target="all", task=task, labels=labels)
    return [folder / "aleph" / c for c in CLASSES]


def main(argv=None) -> int:
    from planerel.ilp.learn import find_aleph, parse_settings, score_theory

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("stems", nargs="*", help="Aleph problem stems (default: export a data set)")
    ap.add_argument("--scenes", type=int, default=sum(DEMO_COUNTS),
                    help="scenes to generate (default 45, the demo's set)")
    ap.add_argument("--dataset", help="an existing data set instead of generating one")
    ap.add_argument("--task", help="task file for the export (default aleph/modes_relational.pl)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--thresholds", action="store_true",
                    help="harder variant: plane counts compared with lazy lteq/gteq thresholds")
    ap.add_argument("--keep", metavar="DIR", help="write data and task here and keep them")
    ap.add_argument("--set", action="append", default=[], dest="settings", metavar="NAME=VALUE")
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds per learning run")
    ap.add_argument("--no-aleph", action="store_true", help="do not run the real Aleph")
    ap.add_argument("--world", default="paper", choices=("paper", "varied"),
                    help="synthetic world of the generated set (default: the demo's paper world)")
    ap.add_argument("--counts", type=int, nargs=3, metavar=("BOX", "STAIRS", "RAMP"),
                    help="scene counts of the generated set (instead of --scenes)")
    ap.add_argument("--labels", default="gt", choices=("gt", "segment"),
                    help="planes of the exported objects: ground truth (default) or region growing "
                         "(segment: the files `planerel learn DATASET` writes and learns from)")
    ap.add_argument("--heldout", metavar="DIR", help="exported Aleph problems to score the theories on")
    ap.add_argument("--heldout-counts", type=int, nargs=3, metavar=("BOX", "STAIRS", "RAMP"),
                    help="generate a held-out set like the training set (seed + 1) and score on it")
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
        stems = make_task(folder, args.scenes, args.dataset, args.task, args.seed, args.thresholds,
                          args.world, args.counts, args.labels)
        if args.heldout_counts and not args.heldout:
            held = make_task(folder / "heldout", 0, None, args.task, args.seed + 1, args.thresholds,
                             args.world, args.heldout_counts, args.labels)
            args.heldout = str(held[0].parent)
    aleph = None if args.no_aleph else find_aleph()
    if aleph is None and not args.no_aleph:
        print("real Aleph: not found (set PLANEREL_ALEPH=/path/to/aleph_orig.pl to compare)")
    elif aleph is not None:
        print(f"real Aleph: {aleph[1]}")

    totals = {"builtin": [0.0, 0.0, 0.0], "aleph": [0.0, 0.0, 0.0]}   # wall, cpu, search
    paired = [0.0, 0.0, []]       # process CPU of both learners over the classes both finished
    for stem in stems:
        engines = ["builtin"] + (["aleph"] if aleph else [])
        res = {}
        for engine in engines:
            r, cpu, err = run(stem, engine, settings, args.timeout)
            res[engine] = (r, cpu)
            if r is None:
                print(f"== {stem.name} [{engine}]: {err}")
                continue
            search = r.search_seconds if engine == "builtin" else aleph_search_seconds(r.output)
            t = totals[engine]
            t[0] += r.seconds
            t[1] += cpu
            t[2] += search or 0.0
            print(f"== {stem.name} [{engine}]: train accuracy {r.accuracy:.3f} "
                  f"(tp {r.train.tp} fn {r.train.fn} fp {r.train.fp} tn {r.train.tn}), "
                  f"{r.clauses_explored} clauses, search {search if search is not None else float('nan'):.3f} s, "
                  f"process {cpu:.2f} s CPU / {r.seconds:.2f} s wall, {len(r.rules)} rules")
            if args.heldout:
                general = [c for c in r.rules if ":-" in c]
                h = score_theory(Path(args.heldout) / stem.name, general, timeout=args.timeout)
                print(f"   held out ({len(general)} general clauses): accuracy {h.accuracy:.3f} "
                      f"(tp {h.tp} fn {h.fn} fp {h.fp} tn {h.tn})")
            for rule in r.rules[:6]:
                print("     ", rule)
            if len(r.rules) > 6:
                print(f"      ... {len(r.rules) - 6} more")
        if all(res.get(e, (None,))[0] is not None for e in ("builtin", "aleph")):
            b, a = res["builtin"][1], res["aleph"][1]
            print(f"   ratio builtin/Aleph, process CPU: {b / a:.2f}")
            paired[0] += b
            paired[1] += a
            paired[2].append(stem.name)
    b = totals["builtin"]
    print(f"total builtin: process {b[1]:.2f} s CPU / {b[0]:.2f} s wall, search {b[2]:.2f} s "
          f"({len(stems)} classes; target <= 5 s on the 45-scene set)")
    if aleph:
        a = totals["aleph"]
        print(f"total Aleph:   process {a[1]:.2f} s CPU / {a[0]:.2f} s wall, search {a[2]:.2f} s")
        if paired[1] > 0:
            print(f"ratio builtin/Aleph over the classes both finished ({', '.join(paired[2])}): "
                  f"process CPU {paired[0]:.2f} / {paired[1]:.2f} s = {paired[0] / paired[1]:.2f}")
    if tmp is not None:
        tmp.cleanup()
    return 0


if __name__ == "__main__":
    sys.exit(main())
