"""The main job, end to end (``make demo``).

1. Generate the paper-sized synthetic set: 12 box, 15 stairs, 18 ramp scenes at 160x120.
2. Learn the class rules with 10-fold cross-validation (the real Aleph when installed,
   else planerel's own learner); print the rules and the confusion matrix.
3. Generate a held-out set with another seed and other camera ranges, classify every scene
   by logic query, and score it.
4. Write everything to ``out/``: data sets, model (rules.pl, metrics.json, confusion.png),
   explanation images of the held-out scenes, and summary.json.

Run: ``.venv/bin/python examples/demo.py --out out``
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="out", help="output folder (default out/)")
    ap.add_argument("--folds", type=int, default=10)
    ap.add_argument("--engine", default="auto", choices=["auto", "builtin", "aleph"])
    ap.add_argument("--jobs", type=int, default=None, help="worker processes (default: all cores)")
    args = ap.parse_args(argv)

    from planerel.classify import Classifier, classify_dataset
    from planerel.errors import PlanerelError
    from planerel.pipeline import draw_confusion, learn_model
    from planerel.synth import CameraRange, generate_dataset
    from planerel.writers import write_json

    out = Path(args.out)
    t0 = time.perf_counter()
    try:
        train = generate_dataset(out / "data" / "train", n_box=12, n_stairs=15, n_ramp=18,
                                 seed=0, size=(640, 480), subsample=4)
        held = generate_dataset(out / "data" / "heldout", n_box=12, n_stairs=15, n_ramp=18,
                                seed=1000, size=(640, 480), subsample=4,
                                camera=CameraRange(height=(0.7, 1.7), distance=(1.0, 2.2)))
        print(f"data: {train} (training), {held} (held out: seed 1000, other camera ranges)")
        m = learn_model(train, out / "model", engine=args.engine, folds=args.folds, seed=0,
                        jobs=args.jobs, log=lambda s: print(s, file=sys.stderr))
        print(f"engine: {m['engine']}")
        print("rules:")
        for k in m["classes"]:
            for r in m["rules"].get(k) or [f"% no rule for {k}"]:
                print(f"  {r}")
        cv = m["cross_validation"]
        print(f"{args.folds}-fold cross-validation accuracy: {cv['accuracy']:.3f}")
        _print_confusion(cv["confusion"], m["classes"])

        clf = Classifier(out / "model" / "rules.pl")
        res = classify_dataset(clf, held, out_dir=out / "classified")
        print(f"held-out accuracy: {res['accuracy']:.3f} "
              f"({len(res['scenes'])} scenes, median {res['ms_per_scene']} ms per scene; "
              f"object proposal matches the true object in {res['proposal_match']:.0%})")
        _print_confusion(res["confusion"], res["classes"])
        draw_confusion(out / "heldout_confusion.png", res["confusion"], res["classes"],
                       title=f"held-out set, accuracy {res['accuracy']:.3f}")
        write_json(out / "summary.json", {"cross_validation_accuracy": cv["accuracy"],
                                          "heldout_accuracy": res["accuracy"],
                                          "heldout": res, "engine": m["engine"],
                                          "rules": m["rules"]})
    except PlanerelError as exc:
        print(f"demo: error: {exc}", file=sys.stderr)
        return 2
    print(f"everything is in {out}/ ({time.perf_counter() - t0:.1f} s)")
    return 0


def _print_confusion(conf, classes):
    cols = list(classes) + ["other"]
    print("  " + " " * 8 + "".join(f"{c:>9}" for c in cols) + "   <- predicted")
    for k, row in zip(classes, conf, strict=True):
        print(f"  {k:>8}" + "".join(f"{v:>9}" for v in row))


if __name__ == "__main__":
    sys.exit(main())
