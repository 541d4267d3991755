"""``planerel classify``: classify the objects of scans with a learned model."""

from __future__ import annotations

import json
from pathlib import Path

from planerel.commands._common import add_input_options

__all__ = ["register", "run"]


def register(sub) -> None:
    p = sub.add_parser(
        "classify",
        help="classify the objects in scans with learned rules, and show the planes that prove it",
        description="For each scan: segment, describe, propose objects, and ask Prolog which "
                    "class each object satisfies. Prints the class (or 'unknown' when no rule "
                    "fires; when several fire, the rule with the best training precision wins), "
                    "the rule and the planes bound to its variables. With -o, also writes "
                    "NAME.classified.png (proof planes highlighted) and NAME.classified.json.",
    )
    p.add_argument("rules", help="MODEL_DIR/rules.pl from planerel learn")
    p.add_argument("inputs", nargs="+", metavar="INPUT", help="scans (any format planerel reads)")
    p.add_argument("--json", action="store_true", help="print one JSON document instead of text")
    p.add_argument("-o", "--output", metavar="OUT_DIR", help="write explanation images and JSON")
    p.add_argument("--method", choices=["regiongrow", "sp", "snp"], default="regiongrow",
                   help="segmentation method (default regiongrow)")
    add_input_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from planerel.classify import Classifier, explanation_image
    from planerel.commands._common import read_input
    from planerel.naming import scene_names
    from planerel.writers import write_json

    names = scene_names(args.inputs)
    clf = Classifier(args.rules, method=args.method)
    results = []
    for path, stem in zip(args.inputs, names, strict=True):
        cloud = read_input(path, args)
        ans = clf.classify(cloud, scene_id=stem)
        results.append(ans.to_dict())
        if args.output:
            out = Path(args.output)
            from PIL import Image

            from planerel.atomic import atomic_path

            with atomic_path(out / f"{stem}.classified.png", suffix=".png") as tmp:
                Image.fromarray(explanation_image(ans, cloud.depth)).save(tmp, format="PNG")
            write_json(out / f"{stem}.classified.json", ans.to_dict())
        if not args.json:
            print(f"{path}: {ans.n_planes} planes, {len(ans.objects)} object(s) "
                  f"[{ans.seconds * 1000:.0f} ms]")
            if not ans.objects:
                print("  no object proposal (only support planes, or no plane at all)")
            for o in ans.objects:
                print(f"  {o.object_id}: {o.klass}")
                if o.rule:
                    print(f"    rule:   {o.rule}")
                    print(f"    planes: {', '.join(o.proof_planes) or '(the rule binds no plane)'}")
    if args.json:
        print(json.dumps(results, indent=2))
    return 0
