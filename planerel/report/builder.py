"""The paper-reproduction report: region growing against the RANSAC baselines SP and SNP.

:func:`build_report` reruns the comparison of "Region-Growing Planar Segmentation for Robot
Action Planning" on a planerel data set (synthetic box / stairs / ramp scenes with ground
truth) and, where present, on the real data in ``../shared/data`` (SegComp ABW, Kinect, mOSD),
and writes

- ``index.html``: one self-contained page (figures embedded as base64 PNG);
- ``report.md`` and ``figures/*.png``: the same content for GitHub;
- ``results.json``: every number of the report; ``csv/*.csv``: the tables as CSV.

Everything except the measured times (section "Timing", and ``timing`` in the JSON) is
deterministic: the same data set and options give byte-identical files (``timing=False``
makes the whole output byte-identical).

Sections (paper table numbers in brackets): planes per class [1, 4]; SegComp counts at 80 %
overlap and mean IoU per method, threshold and class [2, 3, 5, 6, measured instead of graded];
sparse planes per image [7]; coloured segmentations [figures 6-9]; learning outcome per
method; object proposals against ground-truth objects (``planerel evaluate-objects``: the data
set's object labels, the mOSD frames' label field); timing at 160x120 and 640x480; real data.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from planerel.errors import InputError, PlanerelError

__all__ = [
    "MethodSpec",
    "ReportOptions",
    "ReportResult",
    "PAPER_METHODS",
    "parse_methods",
    "parse_sizes",
    "default_real_data_dir",
    "run_objects",
    "score_scenes",
    "summarise",
    "run_timing",
    "run_learning",
    "run_real_data",
    "build_report",
]

#: The methods and thresholds of the paper, in the order of its tables, then region growing
#: twice: Algorithm 1 as the paper writes it (``rgpaper``, ``preset="paper"``) and planerel's
#: default (``regiongrow``).
PAPER_METHODS = ("sp:0.005,sp:0.01,sp:0.03,sp:0.05,snp:0.01,snp:0.03,snp:0.05,rgpaper,"
                 "regiongrow")

_METHOD_NAMES = {"regiongrow": "RG", "rgpaper": "RG paper", "sp": "SP", "snp": "SNP"}


@dataclass(frozen=True)
class MethodSpec:
    """One segmentation configuration of the comparison.

    Parameters
    ----------
    method : {"regiongrow", "rgpaper", "sp", "snp"}
        ``rgpaper``: region growing with ``preset="paper"`` (Algorithm 1 as written).
    threshold : float or None
        RANSAC inlier distance in metres (sp, snp); None for region growing.
    """

    method: str
    threshold: float | None = None

    def __post_init__(self) -> None:
        if self.method not in _METHOD_NAMES:
            raise InputError(f"unknown segmentation method {self.method!r}; choose one of "
                             f"{', '.join(_METHOD_NAMES)}")
        if self.method in ("regiongrow", "rgpaper"):
            if self.threshold is not None:
                raise InputError(f"{self.method} takes no RANSAC threshold; write just "
                                 f"'{self.method}'")
        else:
            t = self.threshold
            if isinstance(t, bool) or not isinstance(t, (int, float)) or not math.isfinite(t) \
                    or t <= 0:
                raise InputError(f"{self.method} needs a positive distance threshold in metres "
                                 f"(e.g. {self.method}:0.01), got {t!r}")
            object.__setattr__(self, "threshold", float(t))

    @property
    def key(self) -> str:
        """Machine name: ``sp_0.005``, ``regiongrow``."""
        return self.method if self.threshold is None else f"{self.method}_{self.threshold:g}"

    @property
    def label(self) -> str:
        """Name in tables: ``SP 0.005``, ``RG``."""
        name = _METHOD_NAMES[self.method]
        return name if self.threshold is None else f"{name} {self.threshold:g}"

    @property
    def segment_method(self) -> str:
        """The method name :func:`planerel.segment.segment` takes."""
        return "regiongrow" if self.method == "rgpaper" else self.method

    def params(self) -> dict:
        """Keyword parameters for :func:`planerel.segment.segment`."""
        if self.method == "rgpaper":
            return {"preset": "paper"}
        return {} if self.threshold is None else {"threshold": self.threshold}


def parse_methods(text) -> tuple[MethodSpec, ...]:
    """``"sp:0.01,snp:0.05,regiongrow"`` (or ``"paper"``) -> method specs, in the given order."""
    if isinstance(text, (list, tuple)):
        items = list(text)
    else:
        s = str(text).strip()
        if s.lower() == "paper":
            s = PAPER_METHODS
        items = [p.strip() for p in s.split(",") if p.strip()]
    if not items:
        raise InputError(f"--methods lists no method: {text!r}")
    out = []
    for it in items:
        if isinstance(it, MethodSpec):
            out.append(it)
            continue
        name, _, thr = str(it).partition(":")
        name = name.strip().lower()
        if name in ("rg", "region", "regiongrowing"):
            name = "regiongrow"
        if thr.strip():
            try:
                t = float(thr)
            except ValueError:
                raise InputError(f"bad method {it!r}: threshold {thr!r} is not a number") from None
        else:
            t = None
        out.append(MethodSpec(name, t))
    keys = [m.key for m in out]
    if len(set(keys)) != len(keys):
        raise InputError(f"--methods names a configuration twice: {text!r}")
    return tuple(out)


def parse_sizes(text) -> tuple[tuple[int, int], ...]:
    """``"160x120,640x480"`` -> ``((160, 120), (640, 480))``; ``""`` -> ``()``."""
    if isinstance(text, (list, tuple)):
        return tuple((int(w), int(h)) for w, h in text)
    out = []
    for part in str(text).split(","):
        part = part.strip().lower()
        if not part:
            continue
        try:
            w, h = (int(v) for v in part.split("x"))
        except ValueError:
            raise InputError(f"a size must look like 160x120, got {part!r}") from None
        if w < 8 or h < 8 or w > 4096 or h > 4096:
            raise InputError(f"a size must lie between 8x8 and 4096x4096, got {part!r}")
        out.append((w, h))
    return tuple(out)


def default_real_data_dir() -> Path:
    """``<project root>/../shared/data`` (the project root holds the ``planerel`` package)."""
    return Path(__file__).resolve().parents[3] / "shared" / "data"


@dataclass(frozen=True)
class ReportOptions:
    """What :func:`build_report` computes.

    Parameters
    ----------
    methods : tuple of MethodSpec
        Default: the paper's SP 0.005/0.01/0.03/0.05, SNP 0.01/0.03/0.05 and region growing.
    tolerance : float
        SegComp overlap tolerance T (0.8).
    learning : bool
        Run the learning comparison (needs ``planerel.ilp.pipeline.evaluate_learning``).
    folds, seed, engine, learn_timeout :
        Passed to ``evaluate_learning`` (10 folds, seed 0, "builtin", 120 s per learning run).
    timing_sizes : tuple of (int, int)
        Image sizes ``(W, H)`` of the timing section; empty = no timing.
    timing_repeats : int
        Timed calls per method, size and scene after one warm-up call (the median is reported).
    timing_budget : float
        Seconds per (method, size) after which further repeats are skipped.
    real_data : str, Path or None
        Folder with ``abw/``, ``kinect/``, ``mosd/``; ``"auto"`` = :func:`default_real_data_dir`;
        None = no real-data section.
    real_subsample : int
        Subsampling of the 640x480 Kinect / mOSD clouds (4: the paper's 160x120).
    abw_subsample : int
        Subsampling of the 512x512 ABW images and their ground truth (2: 256x256, so that the
        slowest RANSAC configuration, SNP 0.01, takes seconds rather than minutes per image;
        1 = full size).
    figure_scenes : tuple of str
        Scene ids drawn in the figures; empty = the first ``figure_per_class`` of each class.
    figure_per_class : int
    jobs : int
        Worker processes for segmenting scenes; 0 = all cores, 1 = no pool.
    progress : bool
        Progress bars (on terminals).
    objects : bool
        Score the default object proposals against ground-truth objects where labels are
        present (:func:`run_objects`).
    """

    methods: tuple = field(default_factory=lambda: parse_methods(PAPER_METHODS))
    tolerance: float = 0.8
    learning: bool = True
    folds: int = 10
    seed: int = 0
    engine: str = "builtin"
    learn_timeout: float = 120.0
    timing_sizes: tuple = ((160, 120), (640, 480))
    timing_repeats: int = 3
    timing_budget: float = 20.0
    real_data: object = "auto"
    real_subsample: int = 4
    abw_subsample: int = 2
    figure_scenes: tuple = ()
    figure_per_class: int = 1
    jobs: int = 0
    progress: bool = False
    objects: bool = True

    def __post_init__(self) -> None:
        s = object.__setattr__
        s(self, "methods", parse_methods(self.methods))
        try:
            t = float(self.tolerance)
        except (TypeError, ValueError):
            raise InputError(f"tolerance must be a number, got {self.tolerance!r}") from None
        if not math.isfinite(t) or not 0.5 < t <= 1.0:
            raise InputError(f"tolerance must lie in (0.5, 1], got {self.tolerance!r}")
        s(self, "tolerance", t)
        for name, lo in (("folds", 2), ("timing_repeats", 1), ("real_subsample", 1),
                         ("abw_subsample", 1), ("figure_per_class", 0), ("jobs", 0), ("seed", 0)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < lo:
                raise InputError(f"{name} must be an integer >= {lo}, got {v!r}")
            s(self, name, int(v))
        for name in ("learn_timeout", "timing_budget"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
                    or v <= 0:
                raise InputError(f"{name} must be a positive number of seconds, got {v!r}")
        s(self, "timing_sizes", parse_sizes(self.timing_sizes))
        s(self, "figure_scenes", tuple(str(x) for x in self.figure_scenes))
        if self.real_data not in (None, "auto"):
            s(self, "real_data", Path(self.real_data))

    @property
    def n_jobs(self) -> int:
        """Worker processes actually used."""
        return self.jobs or (os.cpu_count() or 1)


@dataclass(frozen=True)
class ReportResult:
    """Where :func:`build_report` wrote the report, and its numbers.

    Attributes
    ----------
    out_dir, html, markdown, json : Path
    data : dict
        The content of ``results.json``.
    notes : tuple of str
        Things a reader should know (missing real data, learning not available, failures).
    """

    out_dir: Path
    html: Path
    markdown: Path
    json: Path
    data: dict
    notes: tuple = ()


# --------------------------------------------------------------------------------------------
# segmentation and scoring of one scene (runs in worker processes)

def _segment_and_score(cloud, gt, gt_normals, methods, tolerance, keep):
    """Per method: counts and scores of one cloud (and the label images when ``keep``)."""
    from planerel.segment import segment
    from planerel.segment.evaluate import evaluate, sparse_planes

    out = {}
    labels = {}
    for m in methods:
        rec = {"error": None}
        try:
            seg = segment(cloud, m.segment_method, **m.params())
        except PlanerelError as exc:
            rec.update(error=str(exc), n_planes=0)
            out[m.key] = rec
            continue
        lab = seg.labels
        rec["n_planes"] = len(seg.planes)
        if gt is not None:
            pn = np.array([p.normal for p in seg.planes]).reshape(-1, 3)
            sc = evaluate(lab, gt, tolerance=tolerance, pred_normals=pn if gt_normals is not None
                          else None, gt_normals=gt_normals)
            d = sc.to_dict()
            rec.update({k: d[k] for k in ("n_gt", "correct", "over_segmented", "under_segmented",
                                          "missed", "noise", "mean_iou", "mean_angle_error_deg")})
            rec["sparse"] = sc.sparse
            rec["sparse_ids"] = sparse_planes(lab)
        else:
            sp = sparse_planes(lab)
            rec["sparse"] = len(sp)
            rec["sparse_ids"] = sp
        out[m.key] = rec
        if keep:
            labels[m.key] = lab
    return out, labels


def _scene_task(task: dict) -> dict:
    """Worker: load one scene (data set, ABW image or cloud file), segment it with every method,
    score it.  Returns plain data (and label images for figure scenes)."""
    from planerel.io.cloud import subsample

    kind = task["kind"]
    gt = None
    gt_normals = None
    klass = task.get("class")
    if kind == "dataset":
        from planerel.features.dataset import load_scene

        cloud, gt, meta = load_scene(task["dataset"], task["scene_id"])
        klass = meta.get("class", klass)
        planes = meta.get("planes", [])
        if planes:
            gt_normals = np.array([p["normal"] for p in planes], dtype=float).reshape(-1, 3)
    elif kind == "abw":
        from planerel.io.readers import read_abw, read_abw_gt

        cloud = read_abw(task["path"])
        gt = read_abw_gt(task["gt"])
        k = task.get("subsample", 1)
        if k > 1:
            cloud = subsample(cloud, k)
            gt = np.ascontiguousarray(gt[::k, ::k])
    else:
        from planerel.io.readers import read

        cloud = subsample(read(task["path"]), task.get("subsample", 1))
    scores, labels = _segment_and_score(cloud, gt, gt_normals, task["methods"],
                                        task["tolerance"], task.get("keep", False))
    res = {"scene_id": task["scene_id"], "class": klass, "shape": list(cloud.shape),
           "n_valid": cloud.n_valid, "scores": scores}
    if gt is not None:
        res["n_gt"] = int(len(np.unique(gt[gt >= 0])))
    if task.get("keep", False):
        depth = np.asarray(cloud.depth, dtype=np.float32)
        res["images"] = {"depth": depth, "gt": None if gt is None else gt.astype(np.int32),
                         "labels": labels}
    return res


def _run_tasks(tasks, jobs: int, progress: bool, desc: str) -> list[dict]:
    """Run :func:`_scene_task` over ``tasks``; results in task order (deterministic)."""
    if not tasks:
        return []
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=len(tasks), desc=desc, unit="scene")
    results = []
    try:
        if jobs <= 1 or len(tasks) == 1:
            for t in tasks:
                results.append(_scene_task(t))
                if bar:
                    bar.update(1)
        else:
            import multiprocessing as mp
            from concurrent.futures import ProcessPoolExecutor

            ctx = mp.get_context("fork") if hasattr(os, "fork") else None
            with ProcessPoolExecutor(max_workers=min(jobs, len(tasks)), mp_context=ctx) as ex:
                for r in ex.map(_scene_task, tasks):
                    results.append(r)
                    if bar:
                        bar.update(1)
    finally:
        if bar:
            bar.close()
    return results


def score_scenes(dataset_dir, methods, *, tolerance: float = 0.8, keep=(), jobs: int = 1,
                 progress: bool = False) -> list[dict]:
    """Segment and score every scene of a data set with every method.

    Parameters
    ----------
    dataset_dir : str or Path
    methods : tuple of MethodSpec
    tolerance : float
    keep : iterable of str
        Scene ids whose label images are returned (for figures).
    jobs : int
        Worker processes (1 = in this process).

    Returns
    -------
    list of dict
        In manifest order: ``scene_id``, ``class``, ``n_gt``, ``scores`` {method key: {n_planes,
        correct, over_segmented, under_segmented, missed, noise, mean_iou,
        mean_angle_error_deg, sparse, sparse_ids, error}}, and ``images`` for kept scenes.
    """
    from planerel.features.dataset import load_manifest

    rows = load_manifest(dataset_dir)
    keep = set(keep)
    methods = parse_methods(methods)
    tasks = [{"kind": "dataset", "dataset": str(dataset_dir), "scene_id": r.scene_id,
              "class": r.klass, "methods": methods, "tolerance": tolerance,
              "keep": r.scene_id in keep} for r in rows]
    return _run_tasks(tasks, jobs, progress, "segmenting")


# --------------------------------------------------------------------------------------------
# aggregation

_COUNTS = ("correct", "over_segmented", "under_segmented", "missed", "noise")


def _mean(values):
    vals = [v for v in values if v is not None]
    return float(np.mean(vals)) if vals else None


def summarise(scenes, methods) -> dict:
    """Aggregate per-scene scores into the report's tables.

    Returns
    -------
    dict
        ``classes``; ``planes_per_class`` {method: {class|"all": {sum, mean, n_scenes}}} with a
        ``ground_truth`` entry; ``segcomp`` {method: {class|"all": {n_scenes, n_gt, correct,
        over_segmented, under_segmented, missed, noise (per-image means), mean_iou,
        mean_angle_error_deg, correct_fraction}}}; ``sparse`` {method: {class|"all": {mean,
        total, images_with_sparse, histogram {k: images}}}}; ``errors`` list of (scene, method,
        message).
    """
    methods = parse_methods(methods)
    classes = []
    for s in scenes:
        if s["class"] not in classes:
            classes.append(s["class"])
    groups = {c: [s for s in scenes if s["class"] == c] for c in classes}
    groups["all"] = list(scenes)
    ppc, seg, spa = {}, {}, {}
    errors = []
    for s in scenes:
        for m in methods:
            e = s["scores"][m.key].get("error")
            if e:
                errors.append((s["scene_id"], m.key, e))
    ppc["ground_truth"] = {}
    for c, ss in groups.items():
        vals = [s["n_gt"] for s in ss if "n_gt" in s]
        if vals:
            ppc["ground_truth"][c] = {"sum": int(sum(vals)), "mean": float(np.mean(vals)),
                                      "n_scenes": len(vals)}
    for m in methods:
        ppc[m.key], seg[m.key], spa[m.key] = {}, {}, {}
        for c, ss in groups.items():
            recs = [s["scores"][m.key] for s in ss]
            ok = [r for r in recs if not r.get("error")]
            n = [r["n_planes"] for r in ok]
            ppc[m.key][c] = {"sum": int(sum(n)), "mean": float(np.mean(n)) if n else None,
                             "n_scenes": len(ok)}
            scored = [r for r in ok if "correct" in r]
            if scored:
                d = {"n_scenes": len(scored), "n_gt": _mean(r["n_gt"] for r in scored)}
                for k in _COUNTS:
                    d[k] = _mean(r[k] for r in scored)
                d["mean_iou"] = _mean(r["mean_iou"] for r in scored)
                d["mean_angle_error_deg"] = _mean(r["mean_angle_error_deg"] for r in scored)
                tot_gt = sum(r["n_gt"] for r in scored)
                d["correct_fraction"] = (sum(r["correct"] for r in scored) / tot_gt
                                         if tot_gt else None)
                seg[m.key][c] = d
            sp = [int(r["sparse"]) for r in ok]
            hist = {}
            for v in sp:
                hist[v] = hist.get(v, 0) + 1
            spa[m.key][c] = {"mean": float(np.mean(sp)) if sp else None, "total": int(sum(sp)),
                             "images_with_sparse": int(sum(v > 0 for v in sp)),
                             "n_scenes": len(sp),
                             "histogram": {str(k): hist[k] for k in sorted(hist)}}
    return {"classes": classes, "planes_per_class": ppc, "segcomp": seg, "sparse": spa,
            "errors": errors}


# --------------------------------------------------------------------------------------------
# timing

def _timing_scene(kind: str, seed: int, size: tuple[int, int]):
    from planerel.synth.generator import generate_scene

    w, h = size
    k = 640 // w if (640 % w == 0 and 480 % h == 0 and 640 // w == 480 // h) else 0
    if k:
        return generate_scene(kind, seed, (640, 480), k).cloud
    return generate_scene(kind, seed, (w, h), 1).cloud


def run_timing(methods, sizes, *, repeats: int = 3, budget: float = 20.0, seed: int = 0,
               progress: bool = False) -> dict:
    """Wall-clock time of normals + segmentation per method and image size, in this process.

    For each size, one synthetic box, stairs and ramp scene (seeded) is segmented by each
    method: one warm-up call (reported as ``first_ms``: it includes loading the compiled
    kernels), then ``repeats`` timed calls per scene, fewer once ``budget`` seconds are spent
    (when the warm-up call alone exceeds ``budget`` it is the only measurement).

    Returns
    -------
    dict
        ``{"WxH": {method key: {median_ms, min_ms, first_ms, n_calls}}}``, plus ``cpu_count``.
    """
    import time

    from planerel.segment import segment
    from planerel.synth.generator import scene_seed

    methods = parse_methods(methods)
    out = {"cpu_count": os.cpu_count(), "repeats": repeats}
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=len(sizes) * len(methods), desc="timing", unit="method")
    try:
        for size in parse_sizes(sizes):
            clouds = [_timing_scene(kind, scene_seed(seed, i), size)
                      for i, kind in enumerate(("box", "stairs", "ramp"))]
            key = f"{size[0]}x{size[1]}"
            out[key] = {}
            for m in methods:
                t0 = time.perf_counter()
                try:
                    segment(clouds[0], m.segment_method, **m.params())
                except PlanerelError as exc:
                    out[key][m.key] = {"error": str(exc)}
                    continue
                first = time.perf_counter() - t0
                times = []
                spent = first
                if first > budget:  # too slow to repeat: the warm-up call is the measurement
                    times.append(first)
                for _ in range(repeats):
                    for c in clouds:
                        if times and spent > budget:
                            break
                        t0 = time.perf_counter()
                        segment(c, m.segment_method, **m.params())
                        dt = time.perf_counter() - t0
                        times.append(dt)
                        spent += dt
                out[key][m.key] = {"median_ms": 1000 * float(np.median(times)),
                                   "min_ms": 1000 * float(np.min(times)),
                                   "first_ms": 1000 * first, "n_calls": len(times)}
                if bar:
                    bar.update(1)
    finally:
        if bar:
            bar.close()
    return out


# --------------------------------------------------------------------------------------------
# learning

def run_learning(dataset_dir, methods, *, folds: int = 10, seed: int = 0, engine: str = "builtin",
                 timeout: float = 120.0, jobs: int = 1, ground_truth: bool = True) -> dict:
    """Cross-validated learning outcome per segmentation method.

    Calls ``planerel.ilp.pipeline.evaluate_learning`` for each method when it exists (and, with
    ``ground_truth``, once more on the ground-truth planes, key ``"gt"``: the upper bound).

    Returns
    -------
    dict
        ``available`` (bool), ``reason`` (when not available), ``methods`` {key: {accuracy
        (over the scenes whose object kept a plane), accuracy_all_scenes (skipped scenes
        counted as wrong), n_examples, skipped, per_class, classes, confusion, rules} or
        {"error": message}}.
    """
    try:
        from planerel.ilp import pipeline
    except ImportError as exc:
        return {"available": False,
                "reason": f"planerel.ilp.pipeline cannot be imported ({exc})", "methods": {}}
    fn = getattr(pipeline, "evaluate_learning", None)
    if fn is None:
        return {"available": False,
                "reason": "planerel.ilp.pipeline has no evaluate_learning", "methods": {}}
    out = {"available": True, "folds": folds, "seed": seed, "engine": engine, "methods": {}}
    runs = [(m.key, m.segment_method, m.params() or None) for m in parse_methods(methods)]
    if ground_truth:
        runs.append(("gt", "gt", None))
    for key, method, params in runs:
        try:
            r = fn(str(dataset_dir), method=method, seg_params=params, folds=folds,
                   seed=seed, engine=engine, timeout=timeout, jobs=jobs)
        except PlanerelError as exc:
            out["methods"][key] = {"error": str(exc)}
            continue
        skipped = [str(x) for x in r.get("skipped", [])]
        n_ex = int(r.get("n_examples", 0))
        acc = float(r["accuracy"])
        out["methods"][key] = {
            "accuracy": acc,
            "accuracy_all_scenes": (acc * n_ex / (n_ex + len(skipped))
                                    if n_ex + len(skipped) else None),
            "n_examples": n_ex,
            "skipped": skipped,
            "per_class": {str(k): (None if v is None else float(v))
                          for k, v in dict(r.get("per_class", {})).items()},
            "classes": [str(c) for c in r.get("classes", [])],
            "confusion": [[int(v) for v in row] for row in r.get("confusion", [])],
            "rules": [str(x) for x in r.get("rules", [])],
        }
    return out


# --------------------------------------------------------------------------------------------
# real data

#: Scenes of the real-data figures: (group, file relative to the real-data folder).
REAL_FIGURE_FILES = (
    ("kinect", "kinect/frame_20121214T142255.814212_depth.tiff"),
    ("kinect", "kinect/office1.pcd"),
    ("mosd", "mosd/learn0.pcd"),
    ("mosd", "mosd/learn2.pcd"),
    ("mosd", "mosd/learn4.pcd"),
)
#: ABW image drawn in the figure.
ABW_FIGURE_IMAGE = "abw.test.6"


def run_real_data(folder, methods, *, tolerance: float = 0.8, abw_subsample: int = 1,
                  subsample: int = 4, jobs: int = 1, progress: bool = False) -> dict:
    """SegComp scores on the ABW images and segmentations of the Kinect and mOSD clouds.

    Returns
    -------
    dict
        ``folder``, ``present`` {abw, kinect, mosd: bool}, ``abw`` (list of per-image results
        like :func:`score_scenes`, with ``images`` for the figure image), ``clouds`` (per cloud:
        counts per method and label images).
    """
    folder = Path(folder)
    methods = parse_methods(methods)
    present = {g: (folder / g).is_dir() for g in ("abw", "kinect", "mosd")}
    out = {"folder": str(folder), "present": present, "abw": [], "clouds": []}
    tasks = []
    if present["abw"]:
        for rng in sorted((folder / "abw").glob("abw.test.*.range"),
                          key=lambda p: int(p.name.split(".")[2])):
            gt = rng.with_suffix(".gt-seg")
            if not gt.is_file():
                continue
            stem = rng.name[: -len(".range")]
            tasks.append({"kind": "abw", "path": str(rng), "gt": str(gt), "scene_id": stem,
                          "class": "abw", "methods": methods, "tolerance": tolerance,
                          "subsample": abw_subsample, "keep": stem == ABW_FIGURE_IMAGE})
    n_abw = len(tasks)
    for group, rel in REAL_FIGURE_FILES:
        p = folder / rel
        if present[group] and p.is_file():
            tasks.append({"kind": "cloud", "path": str(p), "scene_id": Path(rel).name,
                          "class": group, "methods": methods, "tolerance": tolerance,
                          "subsample": subsample, "keep": True})
    res = _run_tasks(tasks, jobs, progress, "real data")
    out["abw"] = res[:n_abw]
    out["clouds"] = res[n_abw:]
    return out


#: Object type per shared mOSD frame for the object section (``mosd/README``: the ``learn``
#: frames hold boxes, ``test31`` cylindrical objects); other frames count as ``object``.
MOSD_OBJECT_TYPES = {**{f"learn{k}": "box" for k in range(6)}, "test31": "round"}


def _object_source(name: str, command: str, inputs, types=None, type_by: str = "class") -> dict:
    from planerel.features.object_eval import evaluate_frames

    scores, total = evaluate_frames(inputs, types=types, type_by=type_by)
    total = {k: v for k, v in total.items() if k != "ms_per_frame"}  # the report's numbers are
    frames = [{k: v for k, v in s.as_dict().items() if k != "ms"} for s in scores]  # repeatable
    return {"name": name, "command": command, "total": total, "frames": frames}


def run_objects(dataset_dir, real_folder=None) -> dict:
    """Object proposals scored against ground-truth objects (:mod:`planerel.features.object_eval`).

    Parameters
    ----------
    dataset_dir : path
        The report's data set: scored when its scenes have object labels (varied world),
        with the generator's kinds as types.
    real_folder : path, optional
        Folder with ``mosd/``: its PCDs with a label field are scored (types from
        :data:`MOSD_OBJECT_TYPES`).

    Returns
    -------
    dict
        ``sources``: one ``{name, command, total, frames}`` per scored source (``total`` as
        :func:`planerel.features.object_eval.summarize` without the time); ``absent``: sentences on
        what had no object labels.
    """
    from planerel.features import dataset

    out = {"sources": [], "absent": []}
    rows = dataset.load_manifest(dataset_dir)
    if any(dataset.load_object_labels(dataset_dir, r.scene_id) is not None for r in rows):
        out["sources"].append(_object_source(
            "data set", f"planerel evaluate-objects {dataset_dir} --type-by kind", [dataset_dir],
            type_by="kind"))
    else:
        out["absent"].append(f"the data set `{dataset_dir}` has no object labels (make one with "
                             "`planerel dataset synth DIR --world varied`)")
    if real_folder is not None:
        pcds = sorted((Path(real_folder) / "mosd").glob("*.pcd"))
        if pcds:
            types = [MOSD_OBJECT_TYPES.get(p.stem, "object") for p in pcds]
            out["sources"].append(_object_source(
                "mOSD (real Kinect frames)",
                "planerel evaluate-objects " + " ".join(str(p) for p in pcds)
                + " --types " + " ".join(types), pcds, types=types))
        else:
            out["absent"].append(f"no mOSD frames under `{real_folder}`")
    return out


# --------------------------------------------------------------------------------------------
# the whole report

def _figure_scene_ids(rows, options: ReportOptions) -> list[str]:
    ids = [r.scene_id for r in rows]
    if options.figure_scenes:
        for s in options.figure_scenes:
            if s not in ids:
                raise InputError(f"figure scene {s!r} is not in the data set (scenes "
                                 f"{ids[0]}..{ids[-1]})")
        return list(options.figure_scenes)
    chosen = []
    per = {}
    for r in rows:
        if per.get(r.klass, 0) < options.figure_per_class:
            chosen.append(r.scene_id)
            per[r.klass] = per.get(r.klass, 0) + 1
    return chosen


def _strip_images(items):
    return [{k: v for k, v in s.items() if k != "images"} for s in items]


def build_report(dataset_dir, out_dir, options: ReportOptions | None = None, *,
                 command: str | None = None, log=None) -> ReportResult:
    """Compute the comparison and write the report.

    Parameters
    ----------
    dataset_dir : str or Path
        A planerel data set (``manifest.csv``) with ground-truth labels.
    out_dir : str or Path
        Written (created when missing): ``index.html``, ``report.md``, ``figures/``,
        ``results.json``, ``csv/``.
    options : ReportOptions, optional
    command : str, optional
        The command line shown in the report ("how to reproduce").
    log : callable, optional
        Called with one line of progress text per stage (e.g. ``print``).

    Returns
    -------
    ReportResult

    Raises
    ------
    InputError
        Missing or malformed data set, a data set without ground truth, bad options.
    """
    from planerel.features.dataset import load_dataset_info, load_manifest
    from planerel.report.sections import build_blocks, write_outputs

    opts = options or ReportOptions()
    say = log or (lambda _msg: None)
    rows = load_manifest(dataset_dir)
    if not any(r.labels for r in rows):
        raise InputError(f"{dataset_dir}: the data set has no ground-truth labels; the report "
                         "scores segmentations against them")
    info = load_dataset_info(dataset_dir)
    notes = []
    fig_ids = _figure_scene_ids(rows, opts)
    say(f"segmenting {len(rows)} scenes with {len(opts.methods)} methods "
        f"({opts.n_jobs} worker processes)")
    scenes = score_scenes(dataset_dir, opts.methods, tolerance=opts.tolerance, keep=fig_ids,
                          jobs=opts.n_jobs, progress=opts.progress)
    summary = summarise(scenes, opts.methods)
    for sid, key, msg in summary["errors"]:
        notes.append(f"{sid} {key}: segmentation failed: {msg}")

    real = None
    if opts.real_data is not None:
        folder = default_real_data_dir() if opts.real_data == "auto" else Path(opts.real_data)
        if folder.is_dir() and any((folder / g).is_dir() for g in ("abw", "kinect", "mosd")):
            say(f"real data from {folder}")
            real = run_real_data(folder, opts.methods, tolerance=opts.tolerance,
                                 abw_subsample=opts.abw_subsample, subsample=opts.real_subsample,
                                 jobs=opts.n_jobs, progress=opts.progress)
            real["summary"] = summarise(real["abw"], opts.methods) if real["abw"] else None
        else:
            notes.append(f"real data not found at {folder} (expected abw/, kinect/, mosd/ "
                         "there); the real-data section is empty")
            real = {"folder": str(folder), "present": {}, "abw": [], "clouds": [],
                    "summary": None}

    learning = None
    if opts.learning:
        say("learning per segmentation method")
        learning = run_learning(dataset_dir, opts.methods, folds=opts.folds, seed=opts.seed,
                                engine=opts.engine, timeout=opts.learn_timeout, jobs=opts.n_jobs)
        if not learning["available"]:
            notes.append(f"learning outcome not available: {learning['reason']}")

    objects = None
    if opts.objects:
        say("object proposals against ground-truth objects")
        folder = None
        if real is not None and real.get("present", {}).get("mosd"):
            folder = real["folder"]
        objects = run_objects(dataset_dir, folder)

    timing = None
    if opts.timing_sizes:
        say("timing " + ", ".join(f"{w}x{h}" for w, h in opts.timing_sizes))
        timing = run_timing(opts.methods, opts.timing_sizes, repeats=opts.timing_repeats,
                            budget=opts.timing_budget, seed=opts.seed, progress=opts.progress)

    data = {
        "format": "planerel-report",
        "version": 1,
        "dataset": {"path": str(dataset_dir), "n_scenes": len(rows), "info": info},
        "options": {
            "methods": [m.key for m in opts.methods], "tolerance": opts.tolerance,
            "learning": opts.learning, "folds": opts.folds, "seed": opts.seed,
            "engine": opts.engine, "timing_sizes": [f"{w}x{h}" for w, h in opts.timing_sizes],
            "real_subsample": opts.real_subsample, "abw_subsample": opts.abw_subsample,
            "figure_scenes": fig_ids,
        },
        "summary": summary,
        "scenes": _strip_images(scenes),
        "real_data": None if real is None else {
            **{k: v for k, v in real.items() if k not in ("abw", "clouds")},
            "abw": _strip_images(real["abw"]), "clouds": _strip_images(real["clouds"])},
        "learning": learning,
        "objects": objects,
        "timing": timing,
        "notes": notes,
    }
    blocks = build_blocks(data, opts, scenes, real, command=command)
    out = Path(out_dir)
    paths = write_outputs(out, blocks, data)
    return ReportResult(out_dir=out, html=paths["html"], markdown=paths["markdown"],
                        json=paths["json"], data=data, notes=tuple(notes))
