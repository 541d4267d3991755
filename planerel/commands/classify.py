"""``planerel classify``: classify the objects of scans with a learned model."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from planerel.commands._common import (
    add_batch_options,
    add_camera_height_option,
    add_input_options,
)

__all__ = ["register", "run"]


def register(sub) -> None:
    p = sub.add_parser(
        "classify",
        help="classify the objects in scans with learned rules, and show the planes that prove it",
        description="For each scan: segment, describe, propose objects, and ask Prolog which "
                    "class each object satisfies. Prints the class (or 'other', none of the "
                    "classes, when no rule fires; when several fire, the rule with the best "
                    "training precision wins: Laplace (tp+1)/(tp+fp+2), and rules at or below "
                    "0.5 do not count), "
                    "the rule and the planes bound to its variables. With -o, also writes "
                    "NAME.classified.png (proof planes highlighted) and NAME.classified.json.",
    )
    p.add_argument("rules", help="the model from planerel learn: MODEL_DIR or MODEL_DIR/rules.pl")
    p.add_argument("inputs", nargs="*", metavar="INPUT",
                   help="scans (any format planerel reads): files, folders or glob patterns "
                        "(one or more)")
    p.add_argument("--json", action="store_true", help="print one JSON document instead of text")
    p.add_argument("-o", "--output", metavar="OUT_DIR", help="write explanation images and JSON")
    p.add_argument("--method", choices=["regiongrow", "sp", "snp"], default=None,
                   help="segmentation method (default: the model's, from MODEL_DIR/model.json)")
    p.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                   help="override a setting the model was learned with (repeatable; a warning "
                        "says when it differs from training). A bare NAME is a segmentation "
                        "parameter (theta=12); SECTION.NAME sets one of the sections split, "
                        "gravity, planes, relations, proposals, curved and decision (the "
                        "choice among the rules that fired and its gates, e.g. "
                        "decision.planar_gate=false). 'planerel params' lists the sections, "
                        "'planerel params SECTION --model MODEL' each parameter with the "
                        "model's value and what it does")
    add_input_options(p)
    add_camera_height_option(p)
    add_batch_options(p)
    p.set_defaults(func=run)


_CLASSIFIERS: dict = {}


def _classifier(rules: str, method: str | None, params: tuple = ()):
    """This process's classifier for a model (loaded once per worker process)."""
    from planerel.classify.classifier import Classifier

    key = (rules, method, params)
    if key not in _CLASSIFIERS:
        _CLASSIFIERS[key] = Classifier(rules, method=method, seg_params=dict(params))
    return _CLASSIFIERS[key]


def _params(items) -> dict:
    from planerel.errors import InputError

    out = {}
    for item in items:
        name, sep, value = str(item).partition("=")
        if not sep or not name.strip():
            raise InputError(f"--param takes NAME=VALUE, got {item!r}")
        out[name.strip()] = value.strip()
    return out


def measures_line(klass: str, m: dict) -> str:
    """One line of a ``stairs`` or ``ramp`` answer's measures, in words."""
    far = m.get("distance_m")
    if klass == "stairs":
        run = "run not seen" if m["run_m"] is None else f"run {m['run_m']:.2f} m"
        return (f"flight: going {m['going']}, {m['rises_seen']} rise(s) in view, rise "
                f"{m['rise_m']:.2f} m, {run}, {m['width_m']:.2f} m wide"
                + ("" if far is None else f", nearest step {far:.2f} m away"))
    return (f"slope: going {m['going']}, {m['slope_deg']:.1f} degrees, {m['length_m']:.2f} x "
            f"{m['width_m']:.2f} m seen" + ("" if far is None else f", nearest point {far:.2f} m away"))


def _classify_task(task: dict):
    """Worker: read and classify one scan, write its explanation image and JSON when asked;
    returns ``(answer as a dict, text lines)``."""
    from planerel.commands._common import (
        given_camera_height,
        given_up,
        read_input,
        sparse_note,
    )

    path, stem = task["path"], task["name"]
    clf = _classifier(task["rules"], task["method"], task["params"])
    cloud = read_input(path, task["read"])
    ans = clf.classify(cloud, scene_id=stem, up=given_up(task["read"]),
                       camera_height=given_camera_height(task["read"]))
    if task["out"]:
        from PIL import Image

        from planerel.atomic import atomic_path
        from planerel.classify.explain_render import explanation_picture
        from planerel.io.writers import write_json

        out = Path(task["out"])
        with atomic_path(out / f"{stem}.classified.png", suffix=".png") as tmp:
            Image.fromarray(explanation_picture(ans, cloud.depth)).save(tmp, format="PNG")
        write_json(out / f"{stem}.classified.json", ans.to_dict())
    up = f"up {ans.up_source}" + (f" (confidence {ans.up_confidence:.2f})"
                                  if ans.up_source in ("estimated", "default") else "") \
        + (", upside down" if ans.up_upside_down else "") \
        + (", from the floor under the camera" if ans.up_near_floor else "") \
        + (", with the floor's speckle" if ans.up_sparse_floor else "")
    floor = f"floor {ans.floor}" if ans.floor else "no floor plane"
    lines = [f"{path}: {ans.n_planes} planes, {len(ans.objects)} object(s) "
             f"[{ans.seconds * 1000:.0f} ms]; {up}, {floor}"]
    sparse = sparse_note(cloud, ans.n_planes)
    lines += [f"  note: {n}" for n in ([sparse] if sparse else ans.notes())]
    if not cloud.organized:
        lines.append("  note: an unorganized cloud (no image grid: --no-organize): relations "
                     "that look through the image (skirt/2, a tilted floor) are not found; read "
                     "without --no-organize, a depth image or an organized cloud of the scene "
                     "gives the model what it was trained on")
    if not ans.objects:
        lines.append("  no object proposal (only support planes, or no plane at all)")
    for o in ans.objects:
        shape = ""
        if o.planar_fraction is not None:
            shape = f"  (planar fraction {o.planar_fraction:.2f}{', curved' if o.curved else ''})"
        lines.append(f"  {o.object_id}: {o.klass}{shape}")
        if o.measures:
            lines.append(f"    {measures_line(o.klass, o.measures)}")
        if o.votes:
            lines.append(f"    votes:  {', '.join(v.klass for v in o.votes)} (members 1-"
                         f"{len(o.votes)}; the rule is member {o.member}'s)")
        for r in o.refused:
            lines.append(f"    refused {r.klass}: {r.reason}")
        if o.rule:
            prec = f"  (training precision {o.precision:.3f})" if o.precision is not None else ""
            lines.append(f"    rule:   {o.rule}{prec}")
            lines.append(f"    planes: {', '.join(o.proof_planes) or '(the rule binds no plane)'}")
    return ans.to_dict(), lines


def _check_model_argument(args) -> None:
    """Say which argument is wrong when the model and the scans are mixed up (user89): the
    model forgotten (``classify scan.pcd``), the two swapped (``classify scan.pcd MODEL``),
    or a facts file from ``describe`` given as the model."""
    from planerel.errors import InputError
    from planerel.io.naming import SCAN_EXTENSIONS

    usage = "planerel classify MODEL INPUT... (MODEL: a folder from planerel learn, or its rules.pl)"
    model = Path(args.rules)
    if model.is_file() and model.name.lower().endswith(SCAN_EXTENSIONS):
        raise InputError(f"{model}: is a scan, not a model; the model comes first: {usage}")
    if model.is_dir() and not (model / "rules.pl").is_file():
        raise InputError(f"{model}: holds no rules.pl, so it is no model; the model comes "
                         f"first: {usage}")
    if model.is_file():
        try:
            with open(model, "rb") as fh:
                head = fh.read(4096).decode("utf-8", "replace")
        except OSError:  # unreadable: the model's loader says so in its own words
            head = ""
        if head.startswith("% planerel describe") or "\nscene(" in head:
            raise InputError(f"{model}: is a facts file from planerel describe, not a model "
                             f"(rules); {usage}")
    if not args.inputs:
        raise InputError(f"no INPUT: give one or more scans after the model: {usage}")


def run(args) -> int:
    from planerel.batch import (
        BatchResult,
        report_failures,
        resolve_jobs,
        run_batch,
        write_errors,
    )
    from planerel.commands._common import check_input_options, inputs_of, read_options
    from planerel.io.naming import scene_names

    _check_model_argument(args)
    check_input_options(args)  # a bad --up, --subsample, ... fails here, before any work
    paths = inputs_of(args)
    names = scene_names(paths, ids_option=False, prolog=True)
    rules = str(Path(args.rules).resolve())
    jobs = 1 if len(paths) == 1 else resolve_jobs(args.jobs)
    # A bad model fails here, before any scan is read.  Worker processes start from a fork
    # server, so none inherits this process's Prolog engine; each loads the model once.
    params = tuple(sorted(_params(args.param).items()))
    clf = _classifier(rules, args.method, params)
    from planerel.classify.classifier import check_gate_classes

    check_gate_classes(dict(params), clf.classes)
    for w in clf.warnings:
        print(f"warning: {w}", file=sys.stderr)
    if args.output:  # a bad output folder is one error, not a failure of every scan
        from planerel.atomic import check_not_inputs, check_output_dir

        check_not_inputs([Path(args.output) / f"{n}.classified{e}" for n in names
                          for e in (".png", ".json")], paths)
        check_output_dir(args.output, "-o")
    opts = read_options(args)
    tasks = [{"path": str(p), "name": n, "read": opts, "rules": rules, "method": args.method,
              "params": params, "out": args.output} for p, n in zip(paths, names, strict=True)]
    res = BatchResult()
    results = []
    from planerel.atomic import stale_files_removed

    # half-written files of workers killed (Ctrl-C) in this run or an earlier one go
    with stale_files_removed(args.output or None):
        for _, (answer, lines) in run_batch(_classify_task, tasks, jobs=jobs,
                                            scheduler=args.scheduler, keep_going=args.keep_going,
                                            label=lambda t: t["path"], desc="classify",
                                            result=res, mp_context="forkserver"):
            if args.json:
                results.append(answer)
            else:
                print("\n".join(lines))
    if args.json:
        print(json.dumps(results, indent=2))
    errors = None
    if args.output:
        errors = write_errors(Path(args.output) / "errors.tsv", res.failures)
    return report_failures("classify", res.failures, errors, res.n_tasks)

