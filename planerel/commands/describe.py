"""``planerel describe``: scans -> Prolog facts (planes, relations, objects)."""

from __future__ import annotations

import sys
from pathlib import Path

from planerel.commands._common import (
    add_batch_options,
    add_camera_height_option,
    add_input_options,
)
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
    p.add_argument("inputs", nargs="+", metavar="INPUT",
                   help="scans (any format planerel reads): files, folders or glob patterns")
    p.add_argument("-o", "--output", required=True, metavar="OUT.pl", help="the facts file to write")
    p.add_argument("--labels", nargs="+", metavar="LABELS",
                   help="label images (.npy, data-set label PNG, .gt-seg), one per input, used "
                        "instead of segmenting")
    p.add_argument("--method", default=None, choices=["regiongrow", "sp", "snp"],
                   help="segmentation method when no labels are given (default: the --model's, "
                        "else regiongrow)")
    p.add_argument("--model", metavar="MODEL",
                   help="segment and measure with the settings a model was learned with (its "
                        "model.json: segmentation, gravity, planes, relations, proposals, "
                        "curved), so the facts are the ones 'planerel classify MODEL' reasons on")
    p.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                   help="a segmentation parameter (theta=12, split.merge_side=3, "
                        "small_scale=0.35) or SECTION.NAME of gravity, planes, relations, "
                        "proposals, curved (relations.lying_rise=0.02); repeatable; over a "
                        "--model's value it is used and a warning says so; 'planerel params' "
                        "lists the sections and their parameters")
    p.add_argument("--ids", nargs="+", metavar="ID", help="scene ids, one per input")
    p.add_argument("--no-planner", action="store_true",
                   help="leave out plane_model/3 and hull/2 (the facts for robot planners)")
    p.add_argument("--pairs", default="object+adjacent",
                   choices=["object+adjacent", "object", "adjacent", "all", "none"],
                   help="which plane pairs get relation facts (default: all pairs within an "
                        "object and adjacent pairs across the scene)")
    p.add_argument("--mesh", metavar="DIR",
                   help="also write each scene's planes as a mesh DIR/NAME.planes.ply (each "
                        "plane's polygon, one colour per plane; opens in any 3-D viewer)")
    p.add_argument("--mesh-format", choices=["ply", "glb"], default="ply",
                   help="mesh file type (default ply; glb for web viewers)")
    p.add_argument("--graph", metavar="DIR",
                   help="also write each scene graph (planes = nodes, relations = edges) as "
                        "DIR/NAME.graphml")
    p.add_argument("--graph-format", choices=["graphml", "json"], default="graphml",
                   help="graph file type (default graphml; json = networkx node-link)")
    p.add_argument("--top-slope", action="store_true",
                   help="also measure top_slope/2, the slope of each object's upright face's "
                        "top edge (a ramp's side seen from lower than its top; about 1 ms a "
                        "frame; docs/predicates.md)")
    add_input_options(p)
    add_camera_height_option(p)
    add_batch_options(p)
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


def _describe_task(task: dict):
    """Worker: read, segment (or read labels) and describe one scan; returns
    ``(scene_id, facts by predicate, summary line, segmentation note, up comment)``."""
    from planerel.commands._common import (
        given_camera_height,
        given_up,
        read_input,
        sparse_note,
    )
    from planerel.features.facts import describe_scene, scene_facts, up_comment, view_up
    from planerel.io import readers as io

    path = task["path"]
    note = ""
    far = ()  # the far growing's planes (none in a label image read from a file)
    cloud = read_input(path, task["read"])
    if not cloud.organized:
        raise InputError(f"{path}: describe needs an organized cloud (a depth image, an "
                         "organized PCD / .npy, or an unorganized cloud read without "
                         "--no-organize), got an unorganized one")
    if task["labels"] is not None:
        labels = io.read_label_image(task["labels"])
    else:
        from planerel.segment import segment

        seg = segment(cloud, task["method"],
                      up=view_up(cloud, given_up(task["read"]),
                                 (task.get("describe_kw") or {}).get("gravity_params")),
                      **dict(task.get("seg_params") or {}))
        labels = seg.labels
        note = seg_settings_line(seg.info)
        far = seg.info.get("far_labels") or ()
    d = describe_scene(cloud, labels, scene_id=task["name"], up=given_up(task["read"]), far=far,
                       camera_height=given_camera_height(task["read"]),
                       top_slope=bool(task.get("top_slope")), **(task.get("describe_kw") or {}))
    if task.get("mesh") and len(d.planes):
        from planerel.io.exports import write_mesh

        write_mesh(Path(task["mesh"]) / f"{d.scene_id}.planes.{task['mesh_format']}", d)
    if task.get("graph"):
        from planerel.io.exports import write_graph

        write_graph(Path(task["graph"]) / f"{d.scene_id}.{task['graph_format']}", d)
    line = (f"{path}: {d.scene_id}: {len(d.planes)} planes, {len(d.objects)} object proposals, "
            f"{d.planes.up_estimate.describe()}"
            + ("" if len(d.planes) or len(d.objects)
               else f" ({sparse_note(cloud, 0) or 'no plane found'}: only the scene fact is "
                    "written)"))
    return d.scene_id, scene_facts(d, task["params"]), line, note, up_comment(d)


def _settings(args):
    """The segmentation and feature settings of this run (a
    :class:`~planerel.ilp.model_settings.ModelSettings`): ``--model``'s, changed by
    ``--method`` and ``--param`` (a warning on stderr for each value that differs from the
    model's), or the defaults changed by them.  ``decision.NAME`` is refused: it changes
    answers, not facts."""
    from planerel.commands.classify import _params
    from planerel.ilp.model_settings import read_settings, with_overrides

    given = _params(args.param)
    for name in given:
        if name.startswith("decision."):
            raise InputError(f"--param {name}: decision parameters change classify's answers, "
                             "not the facts; describe takes segmentation and feature parameters")
    base = None
    if args.model is not None:
        rules = Path(args.model)
        rules = rules / "rules.pl" if rules.is_dir() else rules
        if not rules.is_file():
            raise InputError(f"--model {args.model}: no such model (give MODEL_DIR or "
                             "MODEL_DIR/rules.pl)")
        base = read_settings(rules)
        if base is None:
            print(f"warning: --model {args.model}: the model keeps no settings (no "
                  "model.json); the defaults are used", file=sys.stderr)
    settings, warnings = with_overrides(base, method=args.method, overrides=given)
    for w in warnings:
        print(f"warning: {w}", file=sys.stderr)
    # the gt method of a model learned on ground truth has nothing to segment with here
    if settings.method == "gt":
        settings, _ = with_overrides(settings, method="regiongrow")
    from planerel.segment import make_params, split_fields

    seg = dict(settings.seg_params)
    seg.pop("split", None)
    make_params(settings.method, **split_fields(seg)[0])  # a bad name fails before any work
    return settings


def run(args) -> int:
    from planerel.batch import BatchResult, report_failures, run_batch, write_errors
    from planerel.commands._common import check_input_options, inputs_of, read_options
    from planerel.features.facts import FactParams, FactsWriter
    from planerel.io.naming import scene_names

    check_input_options(args)  # a bad --up, --subsample, ... fails here, before any work
    paths = inputs_of(args)
    n = len(paths)
    if args.labels is not None and len(args.labels) != n:
        raise InputError(f"--labels needs one label image per input: {n} inputs, "
                         f"{len(args.labels)} label images")
    ids = scene_names(paths, args.ids, prolog=True)
    # the outputs, after the inputs (a refused input creates nothing), before any work
    from planerel.atomic import check_not_inputs, check_output_dir, check_output_file

    check_output_file(args.output, "-o")
    check_not_inputs([args.output, str(args.output) + ".errors.tsv"], paths)
    for option, folder in (("--mesh", args.mesh), ("--graph", args.graph)):
        if folder is not None:  # "" is refused, not ignored
            check_output_dir(folder, option)
    settings = _settings(args)
    params = FactParams(pairs=args.pairs, planner=not args.no_planner)
    opts = read_options(args)
    tasks = [{"path": str(p), "name": i, "read": opts, "method": settings.method,
              "seg_params": dict(settings.seg_params), "describe_kw": settings.describe_kwargs(),
              "params": params,
              "labels": args.labels[k] if args.labels else None, "mesh": args.mesh,
              "mesh_format": args.mesh_format, "graph": args.graph,
              "graph_format": args.graph_format, "top_slope": args.top_slope}
             for k, (p, i) in enumerate(zip(paths, ids, strict=True))]
    shown = ", ".join(str(p) for p in paths[:20]) + (f", ... ({n} inputs)" if n > 20 else "")
    res = BatchResult()
    with FactsWriter(args.output, params, header="planerel describe: " + shown) as out:
        for _, (sid, facts, line, note, up_line) in run_batch(
                _describe_task, tasks, jobs=args.jobs, scheduler=args.scheduler,
                keep_going=args.keep_going, label=lambda t: t["path"], desc="describe",
                result=res):
            out.add((sid, facts))
            out.note_up(up_line)
            if note:
                out.note(f"{sid}: {note}")
            print(line, file=sys.stderr)
    errors = write_errors(str(args.output) + ".errors.tsv", res.failures)
    k = out.n_scenes
    print(f"facts for {k} scene{'s' if k != 1 else ''} -> {args.output}")
    return report_failures("describe", res.failures, errors, res.n_tasks)
