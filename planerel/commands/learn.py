"""``planerel learn``: segment, describe, export, learn and cross-validate a data set."""

from __future__ import annotations

import sys

from planerel.commands._common import jobs_option

__all__ = ["register", "run"]


def register(sub) -> None:
    p = sub.add_parser(
        "learn",
        help="learn box/stairs/ramp rules from a data set (with k-fold cross-validation)",
        description="Segment every scene of a data set (cached), describe its planes and "
                    "relations, write the Aleph files, learn one theory per class and write "
                    "MODEL_DIR/rules.pl, the Aleph files used, metrics.json, model.json, "
                    "(with --background) background.pl and (with --folds) a cross-validated "
                    "confusion matrix (confusion.png). The model folder is written whole or not "
                    "at all (docs/formats.md, 'The model folder').",
    )
    p.add_argument("dataset", help="a data set folder (planerel dataset synth, docs/formats.md)")
    p.add_argument("-o", "--output", required=True, metavar="MODEL_DIR", help="model folder")
    p.add_argument("--classes", metavar="A,B,...",
                   help="classes to learn (default: all classes of the data set); the objects "
                        "of the other classes are kept as negatives, of class other")
    p.add_argument("--engine", choices=["auto", "aleph", "builtin"], default="auto",
                   help="auto (default): the real Aleph when found (PLANEREL_ALEPH or the SWI "
                        "pack), else planerel's learner; aleph: require the real Aleph; "
                        "builtin: planerel's learner")
    p.add_argument("--folds", type=int, default=0, metavar="K",
                   help="stratified K-fold cross-validation (0 = none; 10 is usual)")
    p.add_argument("--seed", type=int, default=0, help="seed of the fold assignment")
    p.add_argument("--heldout", metavar="DATASET",
                   help="also score the model on this data set, object by object (a held-out "
                        "set: another seed and other world parameters, e.g. planerel dataset "
                        "synth --world varied --seed 7 --range camera_pitch_deg=40,75)")
    p.add_argument("--timeout", type=float, default=1800.0, metavar="S",
                   help="stop a learning run after S seconds of wall time, per class (default "
                        "1800: a 1,000-scene varied set takes 3-11 minutes; the rule query and "
                        "each cross-validation fold get the same limit)")
    p.add_argument("-j", "--jobs", type=jobs_option, default=None, metavar="N",
                   help="worker processes for segmenting and describing, and folds run at "
                        "once (default: all cores)")
    p.add_argument("--scheduler", metavar="tcp://HOST:8786",
                   help="segment and describe the scenes on a Dask cluster (docs/batches.md)")
    p.add_argument("--method", choices=["regiongrow", "sp", "snp", "gt"], default="regiongrow",
                   help="planes from region growing (default), a RANSAC baseline, or the "
                        "ground-truth labels (gt)")
    p.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                   help="a segmentation parameter, NAME or split.NAME (repeatable); 'planerel "
                        "params segmentation' and 'planerel params split' list them")
    p.add_argument("--cache", metavar="DIR", help="segmentation cache folder (default "
                   "$PLANEREL_CACHE or ~/.cache/planerel; 'none' disables it)")
    p.add_argument("--set", action="append", default=[], metavar="[CLASS:]NAME=VALUE",
                   dest="settings",
                   help="Aleph setting for the learner (repeatable), e.g. --set noise=6; "
                        "CLASS:NAME for one class only, e.g. --set box:noise=12")
    p.add_argument("--task", metavar="FILE.pl",
                   help="task file with settings and modeb declarations (default "
                        "modes_relational.pl; a name in planerel's aleph/ folder such as "
                        "modes_facing.pl, or a path)")
    p.add_argument("--background", metavar="FILE.pl",
                   help="a Prolog file of clauses (facts and rules, no directives) defining "
                        "predicates of your own over planerel's vocabulary, for --task modeb "
                        "lines to name: checked before any scene is described, given to the "
                        "learner and copied into the model, which classify loads with the "
                        "rules (docs/learner.md, 'Background predicates of your own'); one "
                        "file. With --extend, the extended model's background by default")
    p.add_argument("--recipe", metavar="NAME",
                   help="a named task + settings + --other-rules measured together; "
                        "'varied' for --world varied data sets (docs/learner.md, 'Recipes'); "
                        "--task, --set and --other-rules given as well take precedence")
    p.add_argument("--other-rules", action="store_true",
                   help="also learn rules for class other (objects of none of the classes in "
                        "the data set): they prove 'none of the classes' and compete with the "
                        "class rules by precision (docs/results.md, 'Rules for other')")
    p.add_argument("--keep-redundant", action="store_true",
                   help="keep every clause the learner returned; by default a clause whose "
                        "training positives the class's other clauses all prove, and that "
                        "proves objects of other classes, is left out (docs/learner.md)")
    p.add_argument("--members", type=int, default=1, metavar="K",
                   help="learn K theories on K disjoint parts of the data set (stratified by "
                        "each scene's class) and answer by their vote (docs/learner.md, "
                        "'Members: a vote of theories'); default 1: one theory on all scenes")
    p.add_argument("--extend", metavar="MODEL_DIR",
                   help="keep that model's rules as they are and learn only clauses for the "
                        "positives they do not prove (every negative stays): new kinds of "
                        "objects added to a data set without the old rules' bounds moving "
                        "(docs/learner.md, 'Extending a theory')")
    p.add_argument("--extend-only", metavar="CLASSES",
                   help="with --extend: learn clauses for these classes only (comma-separated); "
                        "every other class keeps the extended model's clauses as they are")
    p.set_defaults(func=run)


def _params(items) -> dict:
    from planerel.errors import InputError
    from planerel.parameters import segmentation_only

    out = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or not name:
            raise InputError(f"--param takes NAME=VALUE, got {item!r}")
        out[name.strip()] = value.strip()
    segmentation_only(out, "learn")
    return out


def _excluded_line(excluded: dict) -> str:
    """One line on the ground-truth objects that are no example (``{class: {reason: n}}``,
    :func:`planerel.ilp.pipeline.excluded_counts`), "" when there are none: why ``learn``
    counts fewer objects than ``planerel dataset info``."""
    n = sum(sum(v.values()) for v in excluded.values())
    if not n:
        return ""
    parts = [f"{k} {sum(v.values())} ({', '.join(f'{why} {c}' for why, c in v.items())})"
             for k, v in excluded.items()]
    return (f"not examples: {n} ground-truth object(s) whose segmented planes do not show their "
            f"class: {'; '.join(parts)} ('planerel dataset info' counts every scene and every "
            "object in view; docs/formats.md, \"Counting objects\")")


def _settings(items) -> dict:
    """``["noise=6", "box:noise=12"]`` -> ``{"noise": "6", "box:noise": "12"}``."""
    from planerel.ilp.learn import parse_settings

    out = {}
    for item in items:
        cls, sep, rest = item.partition(":")
        if sep and "=" not in cls:
            out.update({f"{cls.strip()}:{k}": v for k, v in parse_settings([rest]).items()})
        else:
            out.update(parse_settings([item]))
    return out


def _check_cache(path) -> None:
    """Refuse a ``--cache`` folder that cannot be written, leaving no folder behind.

    The segmentation cache skips an unwritable folder without a word (an unwritable default
    cache only costs time); a folder the user names and cannot write is a mistake to say."""
    import contextlib
    from pathlib import Path

    from planerel.atomic import check_output_dir

    folder = Path(path)
    made = [p for p in (folder, *folder.parents) if not p.exists()]  # deepest first
    try:
        check_output_dir(folder, "--cache")
    finally:  # the probe made them; learning makes them again when it writes
        for p in made:
            with contextlib.suppress(OSError):
                p.rmdir()


def run(args) -> int:
    from planerel.ilp.pipeline import learn_model

    classes = [c.strip() for c in args.classes.split(",") if c.strip()] if args.classes else None
    if args.classes is not None and not classes:
        from planerel.errors import InputError

        raise InputError(f"--classes names no class, got {args.classes!r}; e.g. --classes box,stairs")
    if args.cache is not None and str(args.cache).lower() not in ("", "none", "off"):
        _check_cache(args.cache)
    prior, background = None, args.background
    if args.extend:
        from planerel.ilp.pipeline import prior_rules

        prior = prior_rules(args.extend)
        if background is None:  # the prior rules may call the predicates of its background
            from planerel.ilp.background import model_background
            from planerel.ilp.model_settings import read_settings

            rules = f"{args.extend}/rules.pl"
            settings = read_settings(rules)
            background = model_background(rules, settings.background if settings else None)
    only = ([c.strip() for c in args.extend_only.split(",") if c.strip()]
            if args.extend_only is not None else None)
    m = learn_model(args.dataset, args.output, classes=classes, engine=args.engine,
                    folds=args.folds, seed=args.seed, timeout=args.timeout, jobs=args.jobs,
                    method=args.method, seg_params=_params(args.param), cache=args.cache,
                    log=lambda s: print(s, file=sys.stderr), scheduler=args.scheduler,
                    heldout=args.heldout, settings=_settings(args.settings) or None,
                    other_rules=args.other_rules, keep_redundant=args.keep_redundant,
                    task=args.task, recipe=args.recipe, members=args.members, prior=prior,
                    extend_only=only, background=background)
    print(f"engine: {m['engine']}")
    print(f"{m['n_examples']} example objects from {m['n_scenes']} scenes; classes: "
          f"{', '.join(m['classes'])}"
          + (f"; {m['n_other']} objects of class other (negatives for every class)"
             if m.get("n_other") else ""))
    per_class = m.get("examples") or {}
    if per_class:
        print("examples per class: " + ", ".join(f"{k} {per_class.get(k, 0)}" for k in m["classes"])
              + " (the objects whose segmented planes show their class)")
    left = _excluded_line(m.get("excluded") or {})
    if left:
        print(left)
    if m.get("member_models"):
        for member in m["member_models"]:
            print(f"member {member['member']} of {m['members']} ({member['n_scenes']} scenes):")
            for k in [*m["classes"], "other"]:
                for r in member["rules"].get(k) or []:
                    print(f"  {r}" + ("   % none of the classes" if k == "other" else ""))
        print(f"answers: the vote of the {m['members']} members")
    else:
        _print_rules(m)
    cv = m.get("cross_validation")
    if cv:
        print(f"{cv['k']}-fold cross-validation: accuracy {cv['accuracy']:.3f}")
        _print_scores(cv, m["classes"])
        for line in _ruleless_folds(cv, m["classes"], _settings(args.settings)):
            print(f"note: {line}", file=sys.stderr)
    held = m.get("heldout")
    if held:
        print(f"held out ({held['dataset']}, {held['n_scenes']} scenes): accuracy "
              f"{held['accuracy']:.3f}")
        _print_scores(held, m["classes"])
    print(f"model written to {args.output}")
    return 0


def _ruleless_folds(cv: dict, classes, settings: dict) -> list[str]:
    """One line per class that some cross-validation folds learned no rule for (its test
    objects then answered ``other`` there: user89's 3-fold run at ``minpos`` 3 on 4 scenes a
    class fell from 0.917 to 0.417 with no word), naming the likely cause."""
    folds = cv.get("folds") or []
    rows = dict(zip(cv.get("classes") or [], cv.get("confusion") or [], strict=False))
    out = []
    for k in classes:
        empty = [f["fold"] for f in folds
                 if not any(str(r).startswith(f"{k}(") for r in f.get("rules") or [])]
        if not empty:
            continue
        n = sum(rows.get(k) or []) or None
        minpos = settings.get(f"{k}:minpos", settings.get("minpos"))
        train = "" if not n else (f"; a fold trains on about {round(n * (len(folds) - 1) / len(folds))} "
                                  f"of its {n} examples")
        hint = (f", with minpos {minpos}" if minpos is not None else "")
        out.append(f"{len(empty)} of {len(folds)} cross-validation folds learned no rule for "
                   f"{k} (their {k} objects were answered other){train}{hint}: give more "
                   "scenes or a smaller minpos; the folds' rules are in metrics.json")
    return out


def _print_rules(m: dict) -> None:
    print("rules (trained on all data):")
    for k in m["classes"]:
        rules = m["rules"].get(k) or []
        for r in rules:
            print(f"  {r}")
        if not rules:
            print(f"  % no rule for {k}")
    for r in m["rules"].get("other") or []:
        print(f"  {r}   % none of the classes")
    for k, r, tp, fp in m.get("dropped_redundant") or []:
        print(f"  % left out: {r}  (its {tp} training {k} are proved by the other {k} rules; "
              f"it also proved {fp} other objects)")


def _print_scores(res: dict, classes) -> None:
    """The confusion matrix of cross-validation or a held-out set, ``other`` as a row too."""
    cols = list(classes) + ["other"]
    print("  " + " " * 8 + "".join(f"{c:>9}" for c in cols) + "   <- predicted")
    for k, row in zip(classes, res["confusion"], strict=True):
        acc = res["per_class"].get(k)
        print(f"  {k:>8}" + "".join(f"{v:>9}" for v in row)
              + (f"   {acc:.3f}" if acc is not None else ""))
    if res.get("other"):
        o = res["other"]
        print(f"  {'other':>8}" + "".join(f"{o['predicted'].get(c, 0):>9}" for c in cols)
              + f"   {o['rejected']:.3f} (right answer: other)")
        print(f"  open-set accuracy (all objects, other included): "
              f"{res['open_set_accuracy']:.3f}")
