"""``planerel describe``: scans -> Prolog facts (planes, relations, objects)."""

from __future__ import annotations

import sys

from planerel.commands._common import add_input_options
from planerel.errors import InputError

__all__ = ["register", "run", "seg_settings_line"]


def register(sub) -> None:
    p = sub.add_parser(
        "describe",
        help="write Prolog facts (plane attributes, relations, object proposals) for scans",
        description="Segment each scan (or use given label images), measure every plane, relate "
                    "the planes, propose objects and write all facts as one Prolog file that loads "
                    "in swipl. Scene ids come from the file names, the same names segment and classify "
                    "use (s0007.depth.png -> s0007, frame_X_depth.tiff -> frame_X) unless "
                    "--ids is given. Vocabulary: docs/predicates.md.",
    )
    p.add_argument("inputs", nargs="+", metavar="INPUT", help="scans (any format planerel reads)")
    p.add_argument("-o", "--output", required=True, metavar="OUT.pl", help="the facts file to write")
    p.add_argument("--labels", nargs="+", metavar="LABELS",
                   help="label images (.npy, data-set label PNG, .gt-seg), one per input, used "
                        "instead of segmenting")
    p.add_argument("--method", default="regiongrow", choices=["regiongrow", "sp", "snp"],
                   help="segmentation method when no labels are given (default regiongrow)")
    p.add_argument("--ids", nargs="+", metavar="ID", help="scene ids, one per input")
    p.add_argument("--no-planner", action="store_true",
                   help="leave out plane_model/3 and hull/2 (the facts for robot planners)")
    p.add_argument("--pairs", default="object+adjacent",
                   choices=["object+adjacent", "object", "adjacent", "all", "none"],
                   help="which plane pairs get relation facts (default: all pairs within an "
                        "object and adjacent pairs across the scene)")
    add_input_options(p)
    p.set_defaults(func=run)


def seg_settings_line(info: dict) -> str:
    """One line on the segmentation's measured depth noise and the settings chosen from it
    (empty when the segmentation did not measure it)."""
    nm, st = info.get("noise_model"), info.get("settings")
    if not nm or not st:
        return ""
    how = "adapted to it" if st.get("adapted") else "fixed settings"
    zref = st.get("reference_depth")
    return (f"depth noise {nm['kind']}, sigma {1000 * nm['sigma_median_m']:.2f} mm "
            f"({nm['noise_pixels']:.2f} px) at {nm['z_median_m']:.2f} m; {how}: min region "
            f"{st['min_region_size']} px, normal window {st['normal_smooth']}/{st['normal_radius']} px"
            f"{'' if zref is None else f' growing beyond {zref:g} m'}")


def run(args) -> int:
    from planerel import io
    from planerel.commands._common import read_input
    from planerel.facts import FactParams, describe_scene, write_facts
    from planerel.naming import scene_names

    n = len(args.inputs)
    if args.labels is not None and len(args.labels) != n:
        raise InputError(f"--labels needs one label image per input: {n} inputs, "
                         f"{len(args.labels)} label images")
    ids = scene_names(args.inputs, args.ids)
    descs, notes = [], []
    for k, path in enumerate(args.inputs):
        cloud = read_input(path, args)
        if not cloud.organized:
            raise InputError(f"{path}: describe needs an organized cloud (a depth image or an "
                             "organized PCD / .npy), got an unorganized one")
        if args.labels:
            labels = io.read_label_image(args.labels[k])
        else:
            from planerel.segment import segment

            seg = segment(cloud, args.method)
            labels = seg.labels
            note = seg_settings_line(seg.info)
            if note:
                notes.append(f"{ids[k]}: {note}")
        d = describe_scene(cloud, labels, scene_id=ids[k])
        descs.append(d)
        print(f"{path}: {ids[k]}: {len(d.planes)} planes, {len(d.objects)} object proposals, "
              f"up {d.planes.up_source}"
              + ("" if len(d.planes) else " (no plane found: only the scene fact is written)"),
              file=sys.stderr)
    params = FactParams(pairs=args.pairs, planner=not args.no_planner)
    header = "planerel describe: " + ", ".join(str(p) for p in args.inputs)
    write_facts(args.output, descs, params, header="\n".join([header, *notes]))
    print(f"facts for {n} scene{'s' if n != 1 else ''} -> {args.output}")
    return 0
