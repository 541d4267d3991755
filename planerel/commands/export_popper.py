"""``planerel export-popper``: a data set -> Popper task folders (bk.pl, exs.pl, bias.pl)."""

from __future__ import annotations

import sys

from planerel.errors import InputError

__all__ = ["register", "run"]


def register(sub) -> None:
    p = sub.add_parser(
        "export-popper",
        help="write Popper tasks (bk.pl, exs.pl, bias.pl) that learn the object classes of a data set",
        description="Describe every scene of a data set (ground-truth planes by default), take "
                    "each scene's ground-truth object as an example of its class and write one "
                    "Popper task folder per class, OUT_DIR/CLASS/ with bk.pl (the same scene "
                    "facts as export-aleph), exs.pl (pos/neg) and bias.pl (head_pred, body_pred, "
                    "type, direction, max_vars/max_body/max_clauses). Run Popper on a folder: "
                    "python popper.py OUT_DIR/stairs.",
    )
    p.add_argument("dataset", metavar="DATASET_DIR", help="a data set (planerel dataset synth)")
    p.add_argument("out_dir", metavar="OUT_DIR", help="folder for the task folders")
    p.add_argument("--target", default="all", metavar="box|stairs|ramp|all",
                   help="the class to learn, or 'all' (one task folder per class, default)")
    p.add_argument("--labels", default="gt", choices=["gt", "segment"],
                   help="plane labels: the ground truth (default) or a region-growing segmentation")
    for name, default in (("max-vars", 5), ("max-body", 5), ("max-clauses", 2)):
        p.add_argument(f"--{name}", type=int, default=default, metavar="N",
                       help=f"Popper's {name.replace('-', '_')} in bias.pl (default {default})")
    p.set_defaults(func=run)


def run(args) -> int:
    from planerel.ilp.popper_export import export_dataset

    if args.target == "class":
        raise InputError("Popper tasks are per class: use --target box|stairs|ramp|all")
    bounds = {"max_vars": args.max_vars, "max_body": args.max_body,
              "max_clauses": args.max_clauses}
    folders, counts, skipped = export_dataset(args.dataset, args.out_dir, args.target,
                                              labels=args.labels, bounds=bounds)
    for s in skipped:
        print(f"note: {s}", file=sys.stderr)
    print("examples: " + ", ".join(f"{c} {n}" for c, n in counts.items()))
    print(f"wrote {', '.join(f.name for f in folders)} (bk.pl, exs.pl, bias.pl each) to {args.out_dir}")
    return 0
