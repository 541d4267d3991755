"""Data set in, described scenes out: load every scene, segment it (through an on-disk cache
keyed by the input files, the parameters and the segmentation code), and describe it with its
ground-truth object (:func:`describe_scenes`, in parallel when asked).  The learning job
(:mod:`planerel.ilp.pipeline`) and the classifier start from here.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from planerel.errors import InputError

__all__ = ["cache_dir", "segment_cached", "segment_cached_far", "describe_scenes"]


# ----------------------------------------------------------------------------- caching


def cache_dir(path=None) -> Path | None:
    """The segmentation cache folder: ``path``, else ``$PLANEREL_CACHE``, else
    ``~/.cache/planerel``.  ``"none"`` / ``""`` disables caching (returns None)."""
    value = path if path is not None else os.environ.get("PLANEREL_CACHE")
    if value is None:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        return Path(base) / "planerel"
    if str(value).lower() in ("", "none", "off"):
        return None
    return Path(value)


@functools.lru_cache(maxsize=1)
def _segmentation_code_hash() -> str:
    """Hash of the source of the segmentation code (planerel/segment/, normals included), so that a
    cache written by other code -- an edited checkout, another version -- is never read back."""
    root = Path(__file__).resolve().parents[1]  # the planerel package folder
    h = hashlib.sha256()
    for f in sorted((root / "segment").glob("*.py")):
        h.update(f.name.encode())
        h.update(f.read_bytes())
    return h.hexdigest()[:16]


def _seg_key(files: Sequence[Path], method: str, params: dict) -> str:
    from planerel._version import __version__

    h = hashlib.sha256()
    for f in files:
        h.update(f.name.encode())
        h.update(Path(f).read_bytes())
    h.update(json.dumps([method, sorted((k, repr(v)) for k, v in params.items()), __version__,
                         _segmentation_code_hash()]).encode())
    return h.hexdigest()[:32]


def segment_cached(cloud, *, method: str = "regiongrow", params: dict | None = None,
                   files: Sequence[Path] = (), cache: Path | None = None) -> np.ndarray:
    """Segment ``cloud``; with ``files`` (the inputs it was read from) and a ``cache`` folder,
    the labels are stored under a key of the files' content, the method, its parameters and
    planerel's version, and a second call reads them back instead of segmenting.

    Returns
    -------
    labels : ndarray, shape (H, W), int32
    """
    return segment_cached_far(cloud, method=method, params=params, files=files, cache=cache)[0]


def segment_cached_far(cloud, *, method: str = "regiongrow", params: dict | None = None,
                       files: Sequence[Path] = (), cache: Path | None = None) -> tuple:
    """:func:`segment_cached`'s labels and the labels of the planes the segmentation's far
    growing added (``info["far_labels"]``: :func:`planerel.features.facts.describe_scene`'s
    ``far``), both cached (``KEY.npy``, ``KEY.far.npy``; an entry without the second is
    segmented again).

    Returns
    -------
    (labels (H, W) int32, far tuple of int)
    """
    from planerel.features.facts import view_up
    from planerel.segment import segment

    params = dict(params or {})
    path = far_path = None
    if cache is not None and files:
        key = _seg_key([Path(f) for f in files], method, params)
        path = Path(cache) / "seg" / f"{key}.npy"
        far_path = path.with_name(f"{key}.far.npy")
        if path.is_file() and far_path.is_file():
            try:
                labels = np.load(path, allow_pickle=False)
                far = np.load(far_path, allow_pickle=False)
                if (labels.shape == cloud.shape and labels.dtype == np.int32
                        and far.ndim == 1 and far.dtype == np.int32):
                    return labels, tuple(int(v) for v in far)
            except (OSError, ValueError):
                pass  # a damaged cache entry is recomputed and replaced
    seg = segment(cloud, method, up=view_up(cloud), **params)
    labels, far = seg.labels, tuple(int(v) for v in seg.info.get("far_labels") or ())
    if path is not None:
        from planerel.atomic import atomic_path
        from planerel.io.writers import write_labels_npy

        try:
            write_labels_npy(path, labels)
            with atomic_path(far_path, suffix=".npy") as tmp:
                np.save(tmp, np.asarray(far, np.int32), allow_pickle=False)
        except (OSError, InputError):
            pass  # an unwritable cache only costs time
    return labels, far


# ----------------------------------------------------------------------------- describing


def _describe_one(job):
    """Worker: load one data-set scene, segment (cached) and describe it with its
    ground-truth object.  Top-level so that a process pool can run it."""
    from planerel.features.dataset import describe_truth_scene, load_scene

    dataset_dir, row, method, params, cache, rule = job
    cloud, gt, meta = load_scene(dataset_dir, row.scene_id)
    if gt is None:
        raise InputError(f"{dataset_dir}: scene {row.scene_id} has no ground-truth labels, so "
                         "its object (the training example) is unknown")
    far = ()
    if method == "gt":
        labels = gt
    else:
        files = [Path(dataset_dir) / row.depth, Path(dataset_dir) / row.meta]
        labels, far = segment_cached_far(cloud, method=method, params=params, files=files,
                                         cache=cache)
    return describe_truth_scene(cloud, labels, gt, meta, row.scene_id, row.klass, rule=rule,
                                far=far)


def example_rule(dataset_dir):
    """The data set's :class:`~planerel.features.truth_examples.ExampleRule`: the defaults,
    with the fields its ``dataset.json`` names under ``"examples"`` (the demo's training world
    asks for boxes seen as one side face, ``{"box_faces": 1}``); None when it names none."""
    from planerel.features.dataset import load_dataset_info
    from planerel.features.truth_examples import ExampleRule

    given = load_dataset_info(dataset_dir).get("examples")
    if not given:
        return None
    if not isinstance(given, dict) or set(given) - {"box_faces", "box_top_height", "side_faces"}:
        raise InputError(f"{dataset_dir}: dataset.json's \"examples\" may name only "
                         f"box_faces, box_top_height and side_faces, got {given!r}")
    return ExampleRule(**given)


def _check_seg_params(method: str, seg_params: dict | None) -> None:
    """Unknown or bad segmentation parameters fail once, before any scene is segmented."""
    params = dict(seg_params or {})
    if method == "gt":
        if params:
            raise InputError(f"segmentation parameters ({', '.join(sorted(params))}) do not apply "
                             "to the ground-truth planes (method gt)")
        return
    if "params" in params:  # a parameter dataclass given whole: validated when it was made
        return
    from planerel.segment import _as_bool, make_params, split_fields

    _as_bool(params.pop("split", None), default=True)
    params, _ = split_fields(params)  # split.NAME: the post-processing's, validated here
    make_params(method, **params)


def describe_scenes(dataset_dir, *, classes: Sequence[str] | None = None,
                    method: str = "regiongrow", seg_params: dict | None = None,
                    jobs: int | None = 1, cache=None, progress: bool | None = None,
                    scheduler=None):
    """Segment and describe every scene of a data set, its ground-truth object as the example.

    Parameters
    ----------
    dataset_dir : path
        A data set in planerel's format (``planerel dataset synth``).
    classes : sequence of str, optional
        The classes learned: every class must have a scene; the objects of the scenes of
        other classes are kept as objects of class ``other`` (every class's negatives: a box
        learned alone from a data set of boxes, staircases and ramps has the staircases and
        ramps as its negatives).
    method : str
        ``"regiongrow"``, ``"sp"``, ``"snp"``, or ``"gt"`` for the ground-truth planes.
    seg_params : dict, optional
        Segmentation parameters.
    jobs : int or None
        Worker processes (None: all cores).  Results are in data-set order whatever the value.
    scheduler : str or distributed.Client, optional
        A Dask scheduler to run the scenes on instead (:func:`planerel.batch.make_executor`).
    cache : path, optional
        Segmentation cache (default :func:`cache_dir`); ``"none"`` disables it.

    Returns
    -------
    descs : list of SceneDescription
    skipped : list of str
        Scenes whose object kept no measured plane, with the reason.
    """
    from planerel.features.dataset import load_manifest

    rows = list(load_manifest(dataset_dir))
    if classes is not None:
        unknown = sorted(set(classes) - {r.klass for r in rows})
        if unknown:
            raise InputError(f"{dataset_dir}: no scene of class {', '.join(unknown)}")
    if not rows:
        raise InputError(f"{dataset_dir}: the data set has no scenes")
    _check_seg_params(method, seg_params)
    rule = example_rule(dataset_dir)  # read (and a bad "examples" refused) once, before any work
    folder = cache_dir(cache) if cache is None or isinstance(cache, (str, Path)) else None
    jobs_list = [(str(dataset_dir), r, method, dict(seg_params or {}), folder, rule) for r in rows]
    from planerel.batch import resolve_jobs, run_batch

    n_jobs = resolve_jobs(jobs) if scheduler is None and len(rows) > 4 else 1
    descs = [d for _, d in run_batch(_describe_one, jobs_list, jobs=n_jobs, scheduler=scheduler,
                                     label=lambda j: f"{j[0]}: scene {j[1].scene_id}",
                                     desc="describing", progress=progress, hint=None)]
    if classes is not None:
        descs = [unlisted_as_other(d, classes) for d in descs]
    skipped = [f"{d.scene_id}: no plane of its object was measured" for d in descs if not d.objects]
    return descs, skipped


#: The class of an object of none of the classes learned (``aleph_export.OTHER``; written out
#: here, as in ``members`` and ``metrics``: ``aleph_export`` imports this module)
OTHER = "other"


def unlisted_as_other(desc, classes):
    """``desc`` with its objects of a class not in ``classes`` as objects of class ``other``
    (:func:`describe_scenes`)."""
    import dataclasses

    if all(o.klass in classes or o.klass in (None, OTHER) for o in desc.objects):
        return desc
    objs = tuple(o if o.klass in classes or o.klass in (None, OTHER)
                 else dataclasses.replace(o, klass=OTHER) for o in desc.objects)
    return dataclasses.replace(desc, objects=objs)
