"""``planerel induce``: learn rules from an Aleph problem (``STEM.b/.f/.n``)."""

from __future__ import annotations

import sys

__all__ = ["register", "run"]


def register(sub) -> None:
    p = sub.add_parser(
        "induce",
        help="learn rules from an Aleph problem STEM.b/.f/.n (planerel's learner or the real Aleph)",
        description="Run an ILP learner on STEM.b (background, modes, determinations, settings), "
                    "STEM.f (positive examples) and STEM.n (negative examples); print the theory, "
                    "the training confusion matrix with an 'accuracy:' line (and the test set's "
                    "when test_pos/test_neg are set) and the time. STEM.b is Prolog code and runs "
                    "as written, as in Aleph: induce only problems you trust (a model file, by "
                    "contrast, is read as data by 'planerel classify').",
    )
    p.add_argument("stem", help="the problem's file stem (STEM.b, STEM.f, STEM.n)")
    p.add_argument("--engine", choices=["builtin", "aleph", "auto"], default="builtin",
                   help="builtin: planerel's learner (default); aleph: the real Aleph "
                        "(PLANEREL_ALEPH=/path/aleph.pl or the SWI pack library(aleph)); "
                        "auto: the real Aleph when found, else builtin")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE", dest="settings",
                   help="an Aleph setting, applied after STEM.b is read (repeatable), "
                        "e.g. --set search=heuristic --set evalfn=laplace --set nodes=2000")
    p.add_argument("--timeout", type=float, default=120.0, metavar="S",
                   help="stop the learner after S seconds (default 120)")
    p.add_argument("--rules", metavar="OUT.pl", help="also write the learned clauses to this file")
    p.add_argument("-v", "--verbose", action="store_true",
                   help="also print the learner's own log (seeds, bottom clauses, search)")
    p.set_defaults(func=run)


def run(args) -> int:
    from planerel.atomic import check_output_file, write_text
    from planerel.ilp.learn import format_report, learn, parse_settings

    settings = parse_settings(args.settings)
    if args.rules is not None:  # a bad --rules (also "") fails here, not after the learning run
        check_output_file(args.rules, "--rules")
    result = learn(args.stem, engine=args.engine, settings=settings, timeout=args.timeout,
                   progress=lambda text: print(f"progress: {text}", file=sys.stderr, flush=True))
    for w in result.warnings:
        print(f"warning: {w}", file=sys.stderr)
    if args.verbose:
        print(result.output)
    print(format_report(result), end="")
    if args.rules is not None:
        write_text(args.rules, result.rules_text)
        print(f"rules written to {args.rules}")
    return 0
