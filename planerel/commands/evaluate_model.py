"""``planerel evaluate-model``: a learned model scored on a data set with ground truth."""

from __future__ import annotations

import json

from planerel.commands._common import jobs_option

__all__ = ["register", "run"]


def register(sub) -> None:
    p = sub.add_parser(
        "evaluate-model",
        help="score a learned model on a data set with ground truth (a held-out set), object "
             "by object",
        description="Score a model (a planerel learn folder, members models too) on a data set "
                    "in planerel's format: every ground-truth object, made of the segmented "
                    "planes that mostly cover it, is answered by the model's rules as planerel "
                    "classify answers (decision and vote included). Prints the accuracy over "
                    "the class objects, the open-set accuracy (objects of class other are right "
                    "when answered other) and the confusion matrix: the figures planerel learn "
                    "--heldout gives, for a model that already exists.",
    )
    p.add_argument("rules", help="the model from planerel learn: MODEL_DIR or MODEL_DIR/rules.pl")
    p.add_argument("dataset", help="a data set with ground truth (planerel dataset synth)")
    p.add_argument("--json", metavar="FILE",
                   help="also write the scores and every object's answer as JSON")
    p.add_argument("-j", "--jobs", type=jobs_option, default=None, metavar="N",
                   help="worker processes for segmenting and describing (default: all cores)")
    p.add_argument("--scheduler", metavar="tcp://HOST:8786",
                   help="describe the scenes on a Dask cluster (docs/batches.md)")
    p.add_argument("--cache", metavar="DIR", help="segmentation cache folder (default "
                   "$PLANEREL_CACHE or ~/.cache/planerel; 'none' disables it)")
    p.add_argument("--param", action="append", default=[], metavar="decision.NAME=VALUE",
                   help="score with a decision setting other than the model's (repeatable), as "
                        "planerel classify --param takes it: decision.proof_gate=false, "
                        "decision.proof_margin=0.5, decision.planar_gate, decision.veto_ratio, "
                        "...; 'planerel params decision' lists them")
    p.set_defaults(func=run)


def run(args) -> int:
    from planerel.atomic import check_output_file, write_text
    from planerel.classify.evaluate import evaluate_model
    from planerel.commands.classify import _params
    from planerel.commands.learn import _check_cache, _print_scores

    if args.json is not None:  # a bad --json fails here, not after describing every scene
        check_output_file(args.json, "--json")
    if args.cache is not None and str(args.cache).lower() not in ("", "none", "off"):
        _check_cache(args.cache)
    params = _params(args.param)
    res = evaluate_model(args.rules, args.dataset, jobs=args.jobs, cache=args.cache,
                         scheduler=args.scheduler, params=params)
    n_other = (res.get("other") or {}).get("n", 0)
    if params:
        print("decision: " + ", ".join(f"{k}={v}" for k, v in sorted(params.items())))
    print(f"{res['model']} on {res['dataset']}: {res['n_scenes']} scenes, "
          f"{res['n_examples']} class objects" + (f", {n_other} of class other" if n_other else ""))
    print(f"accuracy (class objects) {res['accuracy']:.3f}")
    _print_scores(res, res["classes"])
    err = res.get("errors") or {}
    if any(err.get(k) for k in ("decision", "unproved", "unvetoed")):
        print(f"  wrong answers: {err.get('decision', 0)} lost decisions, "
              f"{err.get('unproved', 0)} unproved, {err.get('unvetoed', 0)} unvetoed")
    for s in res["skipped"]:
        print(f"note: {s}")
    if args.json is not None:
        write_text(args.json, json.dumps(res, indent=1, sort_keys=True) + "\n")
    return 0
