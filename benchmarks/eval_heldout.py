"""Cross-validation and held-out accuracy of rules learned from one training set (issue 16).

What ``planerel learn TRAIN --folds K --heldout HELD`` reports, as one JSON line with the
times of each stage, for tables over training seeds (docs/results.md, "Honest evaluation").

Run: ``.venv/bin/python benchmarks/eval_heldout.py TRAIN HELD --folds 10 --tag paper_s0``

``--confirm HELD2`` (repeatable) scores the same model on a further held-out set, a
confirmation set never used for a choice, so that one command gives both figures of a cell.

Two figures per set, both in the JSON: ``accuracy`` counts the classes' objects only (box,
stairs, ramp: a closed set), ``open_set_accuracy`` counts class ``other``'s objects too (right
when answered ``other``).  The varied-world tables of docs/results.md (issue 16) give
``open_set_accuracy``; a line on stderr names both for every set, so that the two are not
taken for one another (they were once: docs/results.md, "the drift after stairs16r /
tabletop22b (drift16)").
"""

from __future__ import annotations

import argparse
import json
import sys
import time


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("train")
    ap.add_argument("held")
    ap.add_argument("--folds", type=int, default=10, help="0: no cross-validation")
    ap.add_argument("--timeout", type=float, default=1800.0,
                    help="seconds per learner run (default 1800, as planerel learn: at 120 s "
                         "the rules for other of a 600-scene varied set were stopped)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--tag", default="")
    ap.add_argument("--setting", action="append", default=[], metavar="NAME=VALUE",
                    help="learner setting (e.g. noise=10, minacc=0.8); repeatable")
    ap.add_argument("--save", default=None,
                    help="folder for the model (rules.pl, model.json: planerel classify reads it) and "
                         "the held-out answers (answers.json)")
    ap.add_argument("--confirm", action="append", default=[], metavar="HELD2",
                    help="a further held-out set (a confirmation set, never used for a choice) "
                         "scored with the same model, under 'confirm' in the output; repeatable")
    ap.add_argument("--task", default=None, metavar="FILE.pl",
                    help="task file (default planerel's aleph/modes_relational.pl; a name in "
                         "planerel.aleph such as modes_slope.pl, or a path)")
    ap.add_argument("--recipe", default=None, metavar="NAME",
                    help="a named task + settings + --other-rules (planerel learn --recipe; "
                         "'varied' is the facing cell); --task, --setting and --other-rules "
                         "given as well take precedence")
    ap.add_argument("--other-rules", action="store_true",
                    help="learn rules for class other too (planerel learn --other-rules)")
    ap.add_argument("--keep-redundant", action="store_true",
                    help="keep clauses that add only false positives (planerel learn "
                         "--keep-redundant)")
    ap.add_argument("--members", type=int, default=1, metavar="K",
                    help="learn K theories on K disjoint parts of TRAIN and score their vote "
                         "(planerel learn --members; --folds must be 0)")
    args = ap.parse_args(argv)

    from planerel.ilp import pipeline as P
    from planerel.ilp.scenes import describe_scenes

    settings = {}
    for item in args.setting:
        name, _, value = item.partition("=")
        try:
            settings[name] = float(value) if "." in value else int(value)
        except ValueError:  # a word: evalfn=coverage, search=heuristic
            settings[name] = value

    from planerel.ilp.recipes import apply_recipe, recipe_decision

    args.task, settings, args.other_rules = apply_recipe(
        args.recipe, task=args.task, settings=settings, other_rules=args.other_rules)
    decision = recipe_decision(args.recipe)  # as planerel learn writes it into the model
    parts = P._member_parts(args.train, None, args.members, args.folds)
    t0 = time.perf_counter()
    descs, _ = describe_scenes(args.train, jobs=args.jobs, progress=False)
    classes = P._classes_arg(None, descs)
    t1 = time.perf_counter()
    cv = None
    if args.folds:
        cv = P.cross_validate(descs, classes, folds=args.folds, jobs=args.jobs, progress=False,
                              timeout=args.timeout, settings=settings or None, task=args.task,
                              other_rules=args.other_rules, keep_redundant=args.keep_redundant,
                              decision=decision)
        cv = {k: cv.get(k) for k in ("accuracy", "per_class", "confusion", "other",
                                     "open_set_accuracy", "open_set_confusion", "n_examples",
                                     "excluded")}
    t2 = time.perf_counter()
    kw = dict(engine="auto", timeout=args.timeout, settings=settings or None,
              other_rules=args.other_rules, keep_redundant=args.keep_redundant, task=args.task)
    if parts is None:
        model = P.learn_rules(descs, classes, **kw)
    else:
        model = P.learn_members(descs, classes, parts, args.members, jobs=args.jobs,
                                log=lambda s: print(s, file=sys.stderr, flush=True), **kw)
    model = P.with_decision(model, decision)
    t3 = time.perf_counter()
    held = P.held_out_scores(model, args.held, jobs=args.jobs, progress=False,
                             timeout=args.timeout)
    answers = held.pop("predictions")
    confirm = []
    for other in args.confirm:
        res = P.held_out_scores(model, other, jobs=args.jobs, progress=False,
                                timeout=args.timeout)
        res.pop("predictions")
        confirm.append(res)
    if args.save:
        from pathlib import Path

        from planerel.atomic import write_text

        out = Path(args.save)
        out.mkdir(parents=True, exist_ok=True)
        if parts is not None:  # a members model folder (planerel learn --members's layout)
            P.write_members(out, model, method="regiongrow", seg_params=None, decision=decision)
        else:
            write_text(out / "rules.pl", model.text())
            # a model folder planerel classify reads as planerel learn's (settings, rule
            # precision, the classes' planar fractions, the rules' proof scales)
            from planerel.ilp.model_settings import MODEL_FILE, training_settings
            from planerel.io.writers import write_json

            write_json(out / MODEL_FILE, training_settings(
                "regiongrow", None, rule_stats=model.stats, planar_domain=model.planar_domain,
                proof_domain=model.proof_domain, decision=decision))
        write_text(out / "answers.json", json.dumps(answers, indent=0, sort_keys=True))
    t4 = time.perf_counter()
    for res in (held, *confirm):
        print(summary(res), file=sys.stderr)
    print(json.dumps({"tag": args.tag, "train": args.train, "held": args.held,
                      "settings": settings, "task": args.task, "recipe": args.recipe,
                      "classes": list(classes), "rules": model.clauses(), "stats": model.stats, "cv": cv,
                      "heldout": held, "confirm": confirm,
                      "seconds": {"describe": round(t1 - t0, 1), "cv": round(t2 - t1, 1),
                                  "learn": round(t3 - t2, 1), "heldout": round(t4 - t3, 1)}}))
    return 0


def summary(res: dict) -> str:
    """One line naming a set's two figures: ``open_set_accuracy`` (the issue 16 tables'
    figure) and ``accuracy`` (the classes' objects only)."""
    def fig(x):
        return "n/a" if x is None else f"{x:.4f}"

    other = res.get("other") or {}
    return (f"{res['dataset']}: open-set accuracy {fig(res.get('open_set_accuracy'))} "
            f"({res['n_examples'] + other.get('n', 0)} objects, other included); "
            f"classes only {fig(res.get('accuracy'))} ({res['n_examples']} objects)")


if __name__ == "__main__":
    raise SystemExit(main())
