"""Object proposals scored against per-pixel ground-truth objects.

Truth is an image of object ids ``(H, W)``: ``k >= 1`` object k, ``0`` environment (floor, table,
walls), ``-1`` no truth (invalid pixel).  Sources: the ``label`` field of an mOSD PCD
(:func:`mosd_objects`: label ``L >= 10`` is part of object ``L // 10``, ``1..9`` the table,
``0`` invalid) and the ``sNNNN.objects.png`` images of a synthetic data set (varied world).

Proposals are an image of proposal indices (:func:`proposal_image`, ``-1`` = no proposal).  Per
frame (:func:`score_objects`), with IoU counted over pixels:

``found``     a true object whose best proposal overlaps it by IoU >= ``min_iou`` (0.5)
``false``     a proposal that is no object's best match at IoU >= ``min_iou``; split into
              ``background`` (under half of its pixels on objects: a wall, the table, clutter
              with no truth) and ``fragment`` (a piece of an object, or of several)
``merged``    a proposal holding at least ``share`` (20 %) of each of two or more objects
              (objects merged into one: under-segmentation of objects)
``split``     an object of which two or more proposals each hold at least ``share``
              (over-segmentation)

:func:`evaluate_frames` runs the default pipeline (segment, describe, propose) on scans and
sums the counts overall and per object type.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from planerel.errors import InputError

__all__ = ["mosd_objects", "answer_masks", "proposal_image", "score_objects", "FrameScore", "summarize",
           "evaluate_frames", "frame_truth", "miss_kind", "miss_breakdown", "MISS_KINDS",
           "mostly_hidden"]


def mosd_objects(label_field) -> np.ndarray:
    """Object ids of an mOSD label field.

    Parameters
    ----------
    label_field : ndarray, shape (H, W), unsigned int
        The PCD's ``label`` field.

    Returns
    -------
    ndarray, shape (H, W), int32
        ``L // 10`` for ``L >= 10``, 0 (environment: the table) for ``1..9``, -1 for 0.
    """
    lab = np.asarray(label_field).astype(np.int64)
    return np.where(lab >= 10, lab // 10, np.where(lab >= 1, 0, -1)).astype(np.int32)


def answer_masks(objects, answers) -> list:
    """The unexplained pixels (``SceneObject.mask``) of each answer of a scene, in answer order.

    ``objects`` are the description's objects, ``answers`` the classifier's
    (:class:`~planerel.classify.classifier.ObjectAnswer`): one per object, in the same order,
    and with ``decision.cut_boxes`` a box cut from a proposal after it (``cut_from``), whose
    mask is None (its planes are its pixels); the proposal it was cut from keeps its mask.
    """
    masks = {o.id: o.mask for o in objects}
    return [None if getattr(a, "cut_from", None) else masks.get(a.object_id) for a in answers]


def proposal_image(labels, proposals, masks=None) -> np.ndarray:
    """Proposal index per pixel.

    Parameters
    ----------
    labels : ndarray, shape (H, W), int
        Plane labels the proposals name.
    proposals : sequence of sequences of int
        Plane labels of each proposal.
    masks : sequence of ndarray (H, W) bool or None, optional
        Extra pixels of each proposal (points no plane explains), or None.

    Returns
    -------
    ndarray, shape (H, W), int32
        ``k`` for pixels of proposal ``k``, -1 elsewhere.
    """
    lab = np.asarray(labels)
    nl = int(lab.max()) + 2 if lab.size else 1
    lut = np.full(max(nl, 1) + 1, -1, np.int32)
    for k, pl in enumerate(proposals):
        for x in pl:
            if 0 <= int(x) < nl:
                lut[int(x)] = k
    out = lut[np.where(lab >= 0, lab, nl)]
    if masks is not None:
        for k, m in enumerate(masks):
            if m is not None:
                out[np.asarray(m, bool) & (out < 0)] = k
    return out


@dataclass
class FrameScore:
    """Counts of one frame (see the module docstring)."""

    name: str
    n_objects: int
    n_proposals: int
    found: int
    false: int
    background: int
    fragment: int
    merged: int
    split: int
    best_iou: dict = field(default_factory=dict)  # object id -> best IoU
    types: dict = field(default_factory=dict)  # object id -> type
    ms: float = 0.0
    best_prop: dict = field(default_factory=dict)  # object id -> index of its best proposal
    planar: dict = field(default_factory=dict)  # object id -> planar fraction of that proposal
    curved: dict = field(default_factory=dict)  # object id -> that proposal is curved

    def as_dict(self) -> dict:
        return {"frame": self.name, "objects": self.n_objects, "proposals": self.n_proposals,
                "found": self.found, "false": self.false, "background": self.background,
                "fragment": self.fragment, "merged": self.merged, "split": self.split,
                "best_iou": {str(k): round(v, 3) for k, v in self.best_iou.items()},
                "types": {str(k): v for k, v in self.types.items()}, "ms": round(self.ms, 1),
                "planar_fraction": {str(k): (None if v is None else round(v, 3))
                                    for k, v in self.planar.items()}}


def score_objects(prop_img, truth, *, name: str = "", types=None, min_iou: float = 0.5,
                  share: float = 0.2, ignore=()) -> FrameScore:
    """Score one frame's proposals against its true objects.

    Parameters
    ----------
    prop_img : ndarray, shape (H, W), int
        Proposal index per pixel, -1 none (:func:`proposal_image`).
    truth : ndarray, shape (H, W), int
        Object id per pixel: >= 1 object, 0 environment, -1 no truth.
    types : mapping object id -> str, optional
        Object types for the per-type figures (default ``"object"``).
    min_iou, share : float
        Thresholds of found / false and of merged / split.
    ignore : iterable of int
        Objects not scored (:func:`mostly_hidden`): neither found nor missed, in no merged or
        split count, and the proposal that matches one at ``min_iou`` is no false proposal.

    Returns
    -------
    FrameScore
    """
    P = np.asarray(prop_img)
    T = np.asarray(truth)
    if P.shape != T.shape:
        raise InputError(f"proposal image {P.shape} and truth {T.shape} differ in shape")
    if not (0 < min_iou <= 1) or not (0 < share <= 1):
        raise InputError(f"min_iou and share must be in (0, 1], got {min_iou!r} and {share!r}")
    npro = int(P.max()) + 1 if P.size and P.max() >= 0 else 0
    skip = {int(o) for o in ignore}
    all_ids = [int(o) for o in np.unique(T) if o >= 1]
    ids = [o for o in all_ids if o not in skip]
    nt = int(T.max()) + 2 if T.size else 1
    # joint counts: rows proposals (+1 for none), columns truth (+1 for -1)
    code = (P.astype(np.int64) + 1) * nt + (T.astype(np.int64) + 1)
    C = np.bincount(code.ravel(), minlength=(npro + 1) * nt).reshape(npro + 1, nt)
    obj_size = C[:, 1:].sum(axis=0)  # by truth id 0..nt-2
    # proposal sizes over pixels with truth (invalid pixels carry no proposal anyway)
    prop_size = C[1:, :].sum(axis=1)
    best_iou: dict = {}
    best_prop: dict = {}
    for o in all_ids:
        inter = C[1:, o + 1]
        union = prop_size + obj_size[o] - inter
        iou = np.where(union > 0, inter / np.maximum(union, 1), 0.0)
        k = int(np.argmax(iou)) if npro else -1
        best_iou[o] = float(iou[k]) if npro else 0.0
        best_prop[o] = k
    found = sum(1 for o in ids if best_iou[o] >= min_iou)
    matched = {best_prop[o] for o in all_ids if best_iou[o] >= min_iou}
    best_iou = {o: best_iou[o] for o in ids}
    best_prop = {o: best_prop[o] for o in ids}
    on_obj = C[1:, 2:].sum(axis=1) if nt > 2 else np.zeros(npro, np.int64)
    background = fragment = 0
    for k in range(npro):
        if k in matched or prop_size[k] == 0:
            continue
        if on_obj[k] < 0.5 * prop_size[k]:
            background += 1
        else:
            fragment += 1
    merged = 0
    split = 0
    if ids:
        frac = np.stack([C[1:, o + 1] / max(obj_size[o], 1) for o in ids], axis=1)  # (npro, n)
        merged = int(np.sum((frac >= share).sum(axis=1) >= 2))
        split = int(np.sum((frac >= share).sum(axis=0) >= 2))
    ty = {o: (types or {}).get(o, "object") for o in ids}
    return FrameScore(name, len(ids), sum(1 for k in range(npro) if prop_size[k] > 0), found,
                      background + fragment, background, fragment, merged, split, best_iou, ty,
                      best_prop=best_prop)


def summarize(scores) -> dict:
    """Totals over frames: found rate, false proposals per frame, merged / split, per type."""
    scores = list(scores)
    n_obj = sum(s.n_objects for s in scores)
    out = {"frames": len(scores), "objects": n_obj,
           "found": sum(s.found for s in scores),
           "found_rate": (sum(s.found for s in scores) / n_obj) if n_obj else None,
           "false_per_frame": (sum(s.false for s in scores) / len(scores)) if scores else None,
           "background_per_frame": (sum(s.background for s in scores) / len(scores)) if scores else None,
           "fragment_per_frame": (sum(s.fragment for s in scores) / len(scores)) if scores else None,
           "merged": sum(s.merged for s in scores), "split": sum(s.split for s in scores),
           "mean_best_iou": (float(np.mean([v for s in scores for v in s.best_iou.values()]))
                             if n_obj else None),
           "ms_per_frame": (sum(s.ms for s in scores) / len(scores)) if scores else None,
           "by_type": {}}
    pfs: dict = {}
    for s in scores:
        for o, t in s.types.items():
            d = out["by_type"].setdefault(t, {"objects": 0, "found": 0, "curved": 0})
            d["objects"] += 1
            d["found"] += int(s.best_iou[o] >= 0.5)
            pf = s.planar.get(o)
            if pf is not None and s.best_iou[o] >= 0.5:
                pfs.setdefault(t, []).append(pf)
                d["curved"] += int(bool(s.curved.get(o)))
    for t, d in out["by_type"].items():
        d["found_rate"] = d["found"] / d["objects"]
        # planar fraction (planerel.features.curved) of the found objects' proposals
        d["mean_planar_fraction"] = float(np.mean(pfs[t])) if t in pfs else None
    return out


def mostly_hidden(meta: dict, min_visible: float = 0.3, compact=("box", "other")) -> set:
    """Objects of a varied-world scene that the learner's fairness rule calls *mostly hidden*
    (:class:`planerel.features.truth_examples.ExampleRule`: a ``box`` or ``other`` object of
    which under ``min_visible`` of its pixels alone, ``n_pixels_full``, is seen, ``n_pixels``):
    a door leaf 10 % in view at the image border, a box 8 % visible behind another.  The
    learner neither trains on nor scores them; :func:`score_objects` leaves them out with
    ``ignore``.  Scenes without ``n_pixels_full`` (other data sets) have none.

    Parameters
    ----------
    meta : dict
        The scene's sidecar (``objects`` with ``index``, ``class``, ``n_pixels``,
        ``n_pixels_full``).

    Returns
    -------
    set of int
        Object indices.
    """
    if not 0 <= min_visible <= 1:
        raise InputError(f"min_visible must be in 0..1, got {min_visible!r}")
    out = set()
    for o in meta.get("objects") or []:
        if not isinstance(o, dict) or int(o.get("index", 0)) < 1 or o.get("class") not in compact:
            continue
        full, seen = o.get("n_pixels_full"), o.get("n_pixels")
        if full and seen is not None and seen < min_visible * float(full):
            out.add(int(o["index"]))
    return out


def frame_truth(path, type_name: str | None = None, type_by: str = "class"):
    """``(cloud, truth, types)`` frames of one input: an mOSD-style PCD with a ``label`` field
    (one frame) or a planerel data-set folder (every scene with object labels).  A data set's
    object types are their classes, or with ``type_by="kind"`` their kinds (``cylinder``,
    ``chair``, ``open box``: the generator's finer names, where the sidecar has them).

    Yields
    ------
    (str, Cloud, ndarray (H, W) int32, dict)
        Frame name, cloud, object ids (:mod:`planerel.features.object_eval` convention), types.
    """
    from planerel.features import dataset
    from planerel.io import readers as io

    p = Path(path)
    if p.is_dir():
        found = False
        for row in dataset.load_manifest(p):
            truth = dataset.load_object_labels(p, row.scene_id)
            if truth is None:
                continue
            cloud, _labels, meta = dataset.load_scene(p, row.scene_id)
            classes = dataset.object_classes(meta, row.klass)
            if type_by == "kind":
                kinds = {int(o["index"]): str(o["kind"]) for o in meta.get("objects") or []
                         if isinstance(o, dict) and o.get("kind") and "index" in o}
                classes = {k: kinds.get(k, v) for k, v in classes.items()}
            found = True
            ty = {k: type_name or v for k, v in classes.items()}
            yield f"{p.name}/{row.scene_id}", cloud, truth.astype(np.int32), ty
        if not found:
            raise InputError(f"{p}: no scene of this data set has object labels")
        return
    if p.suffix.lower() != ".pcd":
        raise InputError(f"{p}: evaluate-objects needs a PCD with a label field or a data-set folder")
    cloud = io.read(p)
    try:
        field_ = io.read_pcd_field(p, "label")
    except InputError as exc:
        raise InputError(f"{p}: no object labels ({exc})") from None
    truth = mosd_objects(field_)
    ids = [int(o) for o in np.unique(truth) if o >= 1]
    yield p.stem, cloud, truth, {o: type_name or "object" for o in ids}


def frame_proposals(cloud, *, method: str = "regiongrow", labels=None):
    """Segment (unless ``labels`` given), describe and propose; returns ``(prop_img, desc,
    ms)`` with ``ms`` the time of describing + proposing (not segmenting)."""
    from planerel.features.facts import describe_scene, view_up

    far = ()
    if labels is None:
        from planerel.segment import segment

        seg = segment(cloud, method, up=view_up(cloud))
        labels, far = seg.labels, seg.info.get("far_labels") or ()
    t0 = time.perf_counter()
    desc = describe_scene(cloud, labels, far=far)
    ms = 1000 * (time.perf_counter() - t0)
    masks = [getattr(o, "mask", None) for o in desc.objects]
    return proposal_image(desc.labels, [o.planes for o in desc.objects], masks), desc, ms


def evaluate_frames(inputs, *, types=None, method: str = "regiongrow", min_iou: float = 0.5,
                    progress=None, type_by: str = "class"):
    """Score the default proposals of every frame of ``inputs``.

    Parameters
    ----------
    inputs : sequence of path
        mOSD-style PCDs with a ``label`` field, or data-set folders.
    types : sequence of str, optional
        Object type per input (default: the data set's classes, else ``"object"``).
    type_by : str
        ``"class"`` or ``"kind"``: a data set's object types (:func:`frame_truth`).

    Returns
    -------
    (list of FrameScore, dict)
        Per-frame scores and :func:`summarize` of them.
    """
    inputs = list(inputs)
    if type_by not in ("class", "kind"):
        raise InputError(f"type_by must be 'class' or 'kind', got {type_by!r}")
    if types is not None and len(types) != len(inputs):
        raise InputError(f"--types needs one type per input: {len(inputs)} inputs, {len(types)} types")
    scores = []
    for k, path in enumerate(inputs):
        for name, cloud, truth, ty in frame_truth(path, types[k] if types else None, type_by):
            prop, desc, ms = frame_proposals(cloud, method=method)
            s = score_objects(prop, truth, name=name, types=ty, min_iou=min_iou)
            s.ms = ms
            s.planar = {o: desc.objects[k].planar_fraction for o, k in s.best_prop.items()
                        if 0 <= k < len(desc.objects)}
            s.curved = {o: desc.objects[k].curved for o, k in s.best_prop.items()
                        if 0 <= k < len(desc.objects)}
            scores.append(s)
            if progress:
                progress(s)
    return scores, summarize(scores)


#: Kinds of a missed object (:func:`miss_kind`), in the order they are tested.
MISS_KINDS = ("tiny", "unsegmented", "in support", "dropped", "split", "merged with object",
              "merged with environment", "low overlap")


def miss_kind(obj: int, prop_img, truth, labels, support=(), *, share: float = 0.2,
              min_pixels: int = 150) -> str:
    """Why a true object has no proposal at IoU >= 0.5 (one of :data:`MISS_KINDS`).

    Parameters
    ----------
    obj : int
        Object id (>= 1) in ``truth``.
    prop_img : ndarray, shape (H, W), int
        Proposal index per pixel (:func:`proposal_image`).
    truth : ndarray, shape (H, W), int
        Object id per pixel (module convention).
    labels : ndarray, shape (H, W), int
        Plane labels of the segmentation the proposals name.
    support : iterable of int
        Labels of the support planes (dropped before proposing).

    Returns
    -------
    str
        ``tiny``: fewer than ``min_pixels`` pixels in view; ``unsegmented``: under half of its
        pixels on a plane; ``in support``: at least 30 % on support planes (its faces were
        segmented into the floor or a wall); ``dropped``: under half in a proposal (the rule
        left its planes out); ``split``: two or more proposals hold ``share`` of it each;
        ``merged with object`` / ``merged with environment``: its main proposal holds more
        pixels of other objects / of the environment (table, floor, walls) than it may;
        ``low overlap``: none of these.
    """
    P = np.asarray(prop_img)
    T = np.asarray(truth)
    L = np.asarray(labels)
    m = T == obj
    n = int(m.sum())
    if n < min_pixels:
        return "tiny"
    lo = L[m]
    if np.count_nonzero(lo >= 0) < 0.5 * n:
        return "unsegmented"
    sup = list(support)
    if sup and np.count_nonzero(np.isin(lo, sup)) >= 0.3 * n:
        return "in support"
    po = P[m]
    if np.count_nonzero(po >= 0) < 0.5 * n:
        return "dropped"
    ks, cnt = np.unique(po[po >= 0], return_counts=True)
    if np.count_nonzero(cnt >= share * n) >= 2:
        return "split"
    pm = P == ks[np.argmax(cnt)]
    other = np.count_nonzero(pm & (T > 0) & ~m)
    env = np.count_nonzero(pm & (T == 0))
    if other > 0 and other >= env:
        return "merged with object"
    if env > 0:
        return "merged with environment"
    return "low overlap"


def miss_breakdown(frames) -> dict:
    """``{type: {kind: count}}`` over frames, ``found`` counted as a kind.

    Parameters
    ----------
    frames : iterable of (FrameScore, prop_img, truth, labels, support)
        A frame's score and what :func:`miss_kind` needs.
    """
    out: dict = {}
    for s, prop, truth, labels, support in frames:
        for o, iou in s.best_iou.items():
            kind = "found" if iou >= 0.5 else miss_kind(o, prop, truth, labels, support)
            d = out.setdefault(s.types.get(o, "object"), {})
            d[kind] = d.get(kind, 0) + 1
    return out
