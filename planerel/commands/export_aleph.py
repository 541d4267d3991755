"""``planerel export-aleph``: a data set -> Aleph learning files STEM.b / STEM.f / STEM.n."""

from __future__ import annotations

import sys

from planerel.errors import InputError

__all__ = ["register", "run"]


def register(sub) -> None:
    p = sub.add_parser(
        "export-aleph",
        help="write Aleph files (STEM.b, STEM.f, STEM.n) that learn the object classes of a data set",
        description="Describe every scene of a data set (ground-truth planes by default), take "
                    "each scene's ground-truth object as an example of its class and write an "
                    "Aleph task: one stem per class (--target all, the default), one class, or "
                    "one multi-class stem 'class' (--target class). The files load in swipl and "
                    "in Aleph; modes and settings come from aleph/modes_relational.pl.",
    )
    p.add_argument("dataset", metavar="DATASET_DIR", help="a data set (planerel dataset synth)")
    p.add_argument("out_dir", metavar="OUT_DIR", help="folder for the .b/.f/.n files")
    p.add_argument("--target", default="all", metavar="box|stairs|ramp|all|class",
                   help="the class to learn, 'all' (one task per class, default) or 'class' "
                        "(one multi-class task)")
    p.add_argument("--labels", default="gt", choices=["gt", "segment"],
                   help="plane labels: the ground truth (default) or a region-growing segmentation")
    p.add_argument("--task", metavar="FILE.pl",
                   help="a task file with settings and modeb declarations (default: "
                        "planerel's aleph/modes_relational.pl; modes_objects.pl adds the "
                        "hand-written step_up/2)")
    p.add_argument("--background", metavar="FILE.pl",
                   help="a Prolog file of clauses (no directives) defining predicates of your "
                        "own over planerel's vocabulary: checked first, then written into every "
                        "STEM.b after the derived relations (docs/learner.md, 'Background "
                        "predicates of your own')")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE", dest="settings",
                   help="override an Aleph setting in STEM.b (repeatable), e.g. --set nodes=2000")
    p.set_defaults(func=run)


def run(args) -> int:
    from planerel.ilp.aleph_export import export_dataset

    settings = {}
    for item in args.settings:
        name, eq, value = item.partition("=")
        if not eq or not name.strip():
            raise InputError(f"--set needs NAME=VALUE, got {item!r}")
        settings[name.strip()] = value.strip()
    res = export_dataset(args.dataset, args.out_dir, args.target, labels=args.labels,
                         task=args.task, settings=settings, background=args.background)
    for s in res.skipped:
        print(f"note: {s}", file=sys.stderr)
    counts = ", ".join(f"{c} {n}" for c, n in res.counts.items())
    print(f"examples: {counts}")
    print(f"wrote {', '.join(res.stems)} ({len(res.files)} files) to {args.out_dir}")
    return 0
