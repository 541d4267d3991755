"""``planerel evaluate-objects``: object proposals scored against ground-truth objects."""

from __future__ import annotations

import json
import sys

__all__ = ["register", "run"]


def register(sub) -> None:
    p = sub.add_parser(
        "evaluate-objects",
        help="score object proposals against per-pixel object labels (mOSD PCDs, data sets)",
        description="Segment each frame with the default settings, propose objects and score the "
                    "proposals against the frame's true objects: found (best proposal IoU >= "
                    "--min-iou), false proposals per frame (background / fragments), objects merged "
                    "into one proposal, objects split over several, per object type. Inputs: PCDs "
                    "with a label field in the mOSD convention (label L >= 10 is object L // 10) or "
                    "planerel data-set folders with object labels (dataset synth --world varied).",
    )
    p.add_argument("inputs", nargs="+", metavar="INPUT", help="PCD files or data-set folders")
    p.add_argument("--types", nargs="+", metavar="TYPE",
                   help="object type per input for the per-type figures (default: the data set's "
                        "classes, else 'object')")
    p.add_argument("--type-by", default="class", choices=["class", "kind"],
                   help="a data set's object types: their classes (default) or the generator's "
                        "kinds (cylinder, chair, open box, ...)")
    p.add_argument("--method", default="regiongrow", choices=["regiongrow", "sp", "snp"],
                   help="segmentation method (default regiongrow)")
    p.add_argument("--min-iou", type=float, default=0.5, help="IoU for a found object (default 0.5)")
    p.add_argument("--json", metavar="FILE", help="also write per-frame scores and totals as JSON")
    p.set_defaults(func=run)


def _pct(x) -> str:
    return "-" if x is None else f"{100 * x:.1f} %"


def run(args) -> int:
    from planerel.atomic import check_output_file, write_text
    from planerel.features.object_eval import evaluate_frames

    if args.json is not None:  # a bad --json (also "") fails here, not after scoring every frame
        check_output_file(args.json, "--json")

    def show(s):
        print(f"{s.name}: {s.found}/{s.n_objects} found, {s.n_proposals} proposals, {s.false} false "
              f"({s.background} background, {s.fragment} fragments), {s.merged} merged, "
              f"{s.split} split, {s.ms:.0f} ms describe+propose", file=sys.stderr)

    scores, tot = evaluate_frames(args.inputs, types=args.types, method=args.method,
                                  min_iou=args.min_iou, progress=show, type_by=args.type_by)
    print(f"{tot['frames']} frames, {tot['objects']} objects: found {tot['found']} "
          f"({_pct(tot['found_rate'])}), false proposals {tot['false_per_frame']:.2f} per frame "
          f"(background {tot['background_per_frame']:.2f}, fragments {tot['fragment_per_frame']:.2f}), "
          f"merged {tot['merged']}, split {tot['split']}")
    for t, d in sorted(tot["by_type"].items()):
        pf = d.get("mean_planar_fraction")
        shape = "" if pf is None else (f", planar fraction {pf:.2f} (mean of the found), "
                                       f"{d['curved']} curved")
        print(f"  {t}: {d['found']}/{d['objects']} found ({_pct(d['found_rate'])}){shape}")
    if args.json is not None:
        write_text(args.json, json.dumps({"frames": [s.as_dict() for s in scores], "total": tot},
                                         indent=1) + "\n")
    return 0
