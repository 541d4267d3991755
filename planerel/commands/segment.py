"""``planerel segment`` (scans -> planes) and ``planerel evaluate-seg`` (SegComp scores)."""

from __future__ import annotations

from pathlib import Path

from planerel.commands._common import (
    add_batch_options,
    add_input_options,
    check_input_options,
    given_up,
    parse_intrinsics,
    read_input,
)
from planerel.errors import InputError

__all__ = ["register", "run_segment", "run_evaluate", "parse_params"]


def parse_params(items) -> dict:
    """``["theta=12", "delta=auto"]`` -> ``{"theta": "12", "delta": "auto"}`` (values are
    converted by the parameter classes)."""
    out = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        name = name.strip().replace("-", "_")
        if not sep or not name or not value.strip():
            raise InputError(f"--param must look like name=value, got {item!r}")
        out[name] = value.strip()
    return out


def register(sub) -> None:
    p = sub.add_parser(
        "segment",
        help="segment scans into planes (region growing, or the SP / SNP RANSAC baselines)",
        description="Segment each scan into planes and write NAME.labels.npy ((H, W) int32, "
                    "-1 = unassigned), NAME.labels.png (colours over a depth shading), "
                    "NAME.planes.json (id, normal, offset, n_points, centroid, rms per plane, and "
                    "the up vector with its source and confidence), NAME.pcd (x y z rgb label, "
                    "label = plane + 1, 0 = none; rgb = the input's colours when it has them, "
                    "else the plane colours) and NAME.ply (valid points coloured by plane, int "
                    "label); --formats picks. "
                    "Reads every format planerel reads, including a bare (H, W, 3) XYZ .npy in "
                    "metres with NaN for invalid points.",
    )
    p.add_argument("inputs", nargs="+", metavar="INPUT",
                   help="scans to segment: files, folders (their scans) or glob patterns")
    p.add_argument("-o", "--output", required=True, metavar="OUT_DIR", help="output folder")
    p.add_argument("--method", choices=("regiongrow", "sp", "snp"), default="regiongrow",
                   help="regiongrow (the paper's Algorithm 1, default), sp (RANSAC plane) or "
                        "snp (RANSAC plane with normals)")
    p.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                   help="a method parameter, e.g. --param theta=12 --param threshold=0.03 "
                        "('planerel params segmentation', 'planerel params ransac' list them; "
                        "docs/segmentation.md); repeat for more.  Region growing also "
                        "takes --param preset=structured-light for high-resolution range "
                        "images with coarse depth steps (e.g. SegComp ABW); --param "
                        "split=false skips the planar post-processing (split=true runs it, "
                        "also after the RANSAC baselines); --param split.NAME=VALUE sets a "
                        "field of the post-processing (e.g. split.small_faces=150)")
    p.add_argument("--formats", default=",".join(FORMATS), metavar="LIST",
                   help="what to write per scan, a comma list of npy (labels), png (label "
                        "picture), json (planes), pcd (labelled PCD: x y z rgb label, PCL "
                        "PointXYZRGBL), ply (points coloured by plane); default all")
    add_input_options(p)
    add_batch_options(p)
    p.set_defaults(func=run_segment)

    e = sub.add_parser(
        "evaluate-seg",
        help="score a label image against ground truth (SegComp counts as JSON)",
        description="Compare a predicted label image with ground truth by the SegComp rules "
                    "(Hoover et al. 1996) and print correct / over / under / missed / noise, "
                    "mean IoU and sparse planes as JSON.  GT: a label .npy, a data-set label "
                    "PNG (value = id + 1, 0 = none) or a SegComp .gt-seg file (labels >= 10 are "
                    "planes).",
    )
    e.add_argument("pred", metavar="PRED.labels.npy", help="predicted labels")
    e.add_argument("gt", metavar="GT", help="ground-truth labels")
    e.add_argument("--tolerance", type=float, default=0.8, metavar="T",
                   help="overlap tolerance T in (0.5, 1] (default 0.8)")
    e.set_defaults(func=run_evaluate)


FORMATS = ("npy", "png", "json", "pcd", "ply")
#: the file each format writes, ``NAME + suffix`` in the output folder
SUFFIXES = {"npy": ".labels.npy", "png": ".labels.png", "json": ".planes.json", "pcd": ".pcd",
            "ply": ".ply"}


def _unlabelled_cloud(path) -> bool:
    """Whether ``path`` is an existing PCD or PLY file whose points carry no ``label`` field,
    so that no ``planerel segment`` wrote it (its PCD has ``label`` among its FIELDS, its PLY a
    ``label`` vertex property); a file whose header cannot be read is not called one."""
    path = Path(path)
    if not path.is_file():
        return False
    try:
        with open(path, "rb") as fh:
            head = fh.read(4096)
    except OSError:
        return False
    text = head.decode("latin-1")
    if path.suffix.lower() == ".pcd":
        fields = [ln.split()[1:] for ln in text.splitlines() if ln.upper().startswith("FIELDS")]
        return bool(fields) and "label" not in fields[0]
    if text.startswith("ply") and "end_header" in text:
        header = text.split("end_header", 1)[0]
        return not any(ln.split()[-1:] == ["label"] for ln in header.splitlines()
                       if ln.startswith("property"))
    return False


def _formats(text: str) -> tuple:
    """``"npy,pcd"`` -> ``("npy", "pcd")``, refusing unknown names."""
    items = tuple(dict.fromkeys(t.strip().lower() for t in text.split(",") if t.strip()))
    bad = [t for t in items if t not in FORMATS]
    if bad or not items:
        raise InputError(f"--formats takes a comma list of {', '.join(FORMATS)}; got {text!r}")
    return items


def _segment_task(task: dict) -> str:
    """Worker: read, segment and write one scan; returns the line to print."""
    import time

    from planerel.features.facts import view_up
    from planerel.features.gravity import resolve_up
    from planerel.io.writers import write_json, write_labels_npy, write_labels_png
    from planerel.segment import segment

    path, stem, out = task["path"], task["name"], Path(task["out"])
    cloud = read_input(path, task["read"])
    t0 = time.perf_counter()
    seg = segment(cloud, task["method"], params=task["params"], split=task.get("split"),
                  split_params=task.get("split_params"),
                  up=view_up(cloud, given_up(task["read"])))
    ms = (time.perf_counter() - t0) * 1000.0
    gravity = resolve_up(cloud, seg.labels, given_up(task["read"]))
    formats = task["formats"]
    if "npy" in formats:
        write_labels_npy(out / f"{stem}{SUFFIXES['npy']}", seg.labels)
    if "png" in formats:
        depth = cloud.depth if cloud.organized else None
        write_labels_png(out / f"{stem}{SUFFIXES['png']}", seg.labels, depth)
    if "pcd" in formats or "ply" in formats:
        from planerel.io.exports import (
            input_colours,
            plane_colours,
            write_pcd,
            write_segmentation_ply,
        )

        if "pcd" in formats:
            rgb = input_colours(path, cloud.shape, getattr(task["read"], "subsample", 1) or 1,
                                organize=getattr(task["read"], "organize", True),
                                intrinsics=parse_intrinsics(getattr(task["read"], "intrinsics",
                                                                    None)))
            write_pcd(out / f"{stem}{SUFFIXES['pcd']}", cloud.xyz, labels=seg.labels,
                      colours=rgb if rgb is not None else plane_colours(seg.labels))
        if "ply" in formats:
            write_segmentation_ply(out / f"{stem}{SUFFIXES['ply']}", cloud.xyz, seg.labels)
    if "json" in formats:
        write_json(out / f"{stem}{SUFFIXES['json']}", {
        "source": str(path),
        "method": seg.method,
        "shape": list(seg.labels.shape),
        "planes": seg.planes_json(),
        "up": gravity.to_dict(),
        "info": {k: v for k, v in seg.info.items() if k != "iterations"},
    })
    return f"{path}: {seg.message} ({ms:.1f} ms); {gravity.describe()} -> {out / stem}.*"


def run_segment(args) -> int:
    from planerel.batch import BatchResult, report_failures, run_batch, write_errors
    from planerel.commands._common import inputs_of, read_options
    from planerel.io.naming import scene_names
    from planerel.parameters import segmentation_only
    from planerel.segment import make_params, split_fields

    given = parse_params(args.param)
    segmentation_only(given, "segment")
    # split is segment()'s keyword (the post-processing), not a parameter-class field
    split = given.pop("split", None)
    if split is not None:
        from planerel.segment import _as_bool

        split = _as_bool(split, default=True)  # a bad value fails here, before any work
    given, split_params = split_fields(given)  # split.NAME: the post-processing's fields
    params = make_params(args.method, **given)
    check_input_options(args)  # a bad --up, --subsample, ... fails here, before any work
    paths = inputs_of(args)
    stems = scene_names(paths, ids_option=False)
    out = Path(args.output)
    if out.exists() and not out.is_dir():
        raise InputError(f"{out}: exists and is not a folder")
    from planerel.atomic import check_output_dir

    formats = _formats(args.formats)
    from planerel.atomic import check_not_inputs

    # segment x.pcd -o . would write the labelled cloud over the scan (user89)
    check_not_inputs([out / f"{n}{SUFFIXES[f]}" for n in stems for f in formats], paths)
    # nor over a cloud of the user's that is no input of this run (scan_depth.tiff -o . names
    # its labelled cloud scan.pcd: a scan.pcd beside it was replaced, user103)
    for path in (out / f"{n}{SUFFIXES[f]}" for n in stems for f in formats if f in ("pcd", "ply")):
        if _unlabelled_cloud(path):
            raise InputError(f"-o: {path} exists and is a point cloud without planerel's labels "
                             "(a scan of yours?); planerel does not write over it: give another "
                             "output folder")
    check_output_dir(out, "-o")  # made, and removed again when the run fails while it is empty
    opts = read_options(args)
    tasks = [{"path": str(p), "name": n, "out": str(out), "read": opts, "method": args.method,
              "params": params, "split": split, "split_params": split_params,
              "formats": formats} for p, n in zip(paths, stems, strict=True)]
    res = BatchResult()
    from planerel.atomic import stale_files_removed

    # half-written files of workers killed (Ctrl-C) in this run or an earlier one go
    with stale_files_removed(out):
        for _, line in run_batch(_segment_task, tasks, jobs=args.jobs, scheduler=args.scheduler,
                                 keep_going=args.keep_going, label=lambda t: t["path"],
                                 desc="segment", result=res):
            print(line)
    errors = write_errors(out / "errors.tsv", res.failures)
    return report_failures("segment", res.failures, errors, res.n_tasks)


def run_evaluate(args) -> int:
    import json

    from planerel.io.readers import read_label_image
    from planerel.segment.evaluate import evaluate

    pred = read_label_image(args.pred)
    gt = read_label_image(args.gt)
    score = evaluate(pred, gt, tolerance=args.tolerance)
    print(json.dumps(score.to_dict(), sort_keys=True))
    return 0
