"""Scoring a segmentation against ground truth: the SegComp classification (Hoover et al.,
"An experimental comparison of range image segmentation algorithms", IEEE PAMI 18(7), 1996),
mean IoU, normal angle errors and sparse planes.

SegComp at overlap tolerance ``T`` (0.5 < T <= 1), with ``O(M, G)`` the number of pixels that
machine region ``M`` and ground-truth region ``G`` share:

- **correct detection**: ``O >= T |M|`` and ``O >= T |G|`` (one machine, one GT region);
- **over-segmentation**: a GT region ``G`` and machine regions ``M1..Mx`` (x >= 2) with
  ``O(Mi, G) >= T |Mi|`` for each and ``sum O(Mi, G) >= T |G|``;
- **under-segmentation**: a machine region ``M`` and GT regions ``G1..Gx`` (x >= 2) with
  ``O(M, Gi) >= T |Gi|`` for each and ``sum O(M, Gi) >= T |M|``;
- **missed**: a GT region in none of the above; **noise**: a machine region in none of the above.

Each region takes part in one classification at most: correct detections first, then
over-segmentations, then under-segmentations.  Region sizes count every pixel of the region in
its own image, including machine pixels on unlabelled ground truth (as SegComp does).

**Sparse planes** (the paper's Table 7): a machine region whose pixels form two or more
spatially separate pieces of significant size.  Pieces are the 8-connected components of the
region's mask after a one-pixel closing (so isolated one-pixel gaps from noise do not split it);
a piece is significant when it holds at least ``sparse_fraction`` of the region's pixels and at
least ``sparse_min_pixels`` pixels.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from planerel.errors import InputError

__all__ = [
    "SegScore",
    "segcomp",
    "sparse_planes",
    "evaluate",
    "overlap_matrix",
    "DEFAULT_TOLERANCE",
]

DEFAULT_TOLERANCE = 0.8


@dataclass(frozen=True)
class SegScore:
    """SegComp counts and extra measures of one image.

    Attributes
    ----------
    tolerance : float
    n_gt, n_pred : int
        Ground-truth and machine regions compared.
    correct, over, under, missed, noise : int
        SegComp counts (``over`` counts GT regions, ``under`` machine regions).
    mean_iou : float
        Mean over GT regions of the best IoU with any machine region (0 when there is no GT).
    angle_errors : tuple of float
        Degrees between the machine and the true normal of each correct detection (when normals
        were given).
    mean_angle_error : float or None
    sparse : int
        Sparse machine regions.
    correct_pairs : tuple of (int, int)
        (machine id, GT id) of the correct detections.
    """

    tolerance: float
    n_gt: int
    n_pred: int
    correct: int
    over: int
    under: int
    missed: int
    noise: int
    mean_iou: float
    angle_errors: tuple = ()
    mean_angle_error: float | None = None
    sparse: int = 0
    correct_pairs: tuple = field(default=(), repr=False)

    def __post_init__(self) -> None:
        for name in ("n_gt", "n_pred", "correct", "over", "under", "missed", "noise", "sparse"):
            if int(getattr(self, name)) < 0:
                raise InputError(f"score {name} must be >= 0")

    def to_dict(self) -> dict:
        """Plain-number dictionary (for JSON)."""
        return {
            "tolerance": self.tolerance,
            "n_gt": self.n_gt,
            "n_pred": self.n_pred,
            "correct": self.correct,
            "over_segmented": self.over,
            "under_segmented": self.under,
            "missed": self.missed,
            "noise": self.noise,
            "mean_iou": round(self.mean_iou, 6),
            "mean_angle_error_deg": (None if self.mean_angle_error is None
                                     else round(self.mean_angle_error, 6)),
            "sparse": self.sparse,
        }


def _labels(name: str, lab) -> np.ndarray:
    a = np.asarray(lab)
    if a.ndim != 2:
        raise InputError(f"{name} labels must be a 2-D (H, W) array, got shape {a.shape}")
    if not np.issubdtype(a.dtype, np.integer):
        raise InputError(f"{name} labels must be integers, got dtype {a.dtype}")
    return a.astype(np.int64)


def _check_tol(tolerance) -> float:
    try:
        t = float(tolerance)
    except (TypeError, ValueError):
        raise InputError(f"tolerance must be a number, got {tolerance!r}") from None
    if not math.isfinite(t) or not 0.5 < t <= 1.0:
        raise InputError(f"tolerance must lie in (0.5, 1], got {tolerance!r}")
    return t


def overlap_matrix(pred, gt):
    """Overlap counts of two label images.

    Returns
    -------
    pred_ids (P,), gt_ids (G,), overlap (P, G) int64, pred_sizes (P,), gt_sizes (G,)
        Only ids >= 0 are regions.
    """
    p = _labels("predicted", pred)
    g = _labels("ground-truth", gt)
    if p.shape != g.shape:
        raise InputError(f"predicted labels {p.shape} and ground truth {g.shape} differ in shape")
    pid, pinv = np.unique(p.reshape(-1), return_inverse=True)
    gid, ginv = np.unique(g.reshape(-1), return_inverse=True)
    counts = np.bincount(pinv * len(gid) + ginv, minlength=len(pid) * len(gid)).reshape(len(pid), len(gid))
    pk = pid >= 0
    gk = gid >= 0
    psize = counts.sum(axis=1)[pk]
    gsize = counts.sum(axis=0)[gk]
    return pid[pk], gid[gk], counts[np.ix_(pk, gk)], psize, gsize


def segcomp(pred, gt, tolerance: float = DEFAULT_TOLERANCE):
    """SegComp classification.

    Returns
    -------
    dict
        ``correct`` list of (pred id, gt id), ``over`` list of (gt id, [pred ids]), ``under`` list
        of (pred id, [gt ids]), ``missed`` gt ids, ``noise`` pred ids, and ``iou`` (per GT id the
        best IoU), ``n_pred``, ``n_gt``.
    """
    t = _check_tol(tolerance)
    pid, gid, ov, ps, gs = overlap_matrix(pred, gt)
    P, G = ov.shape
    fit_m = ov >= t * ps[:, None]  # O(M, G) >= T |M|
    fit_g = ov >= t * gs[None, :]  # O(M, G) >= T |G|
    used_p = np.zeros(P, bool)
    used_g = np.zeros(G, bool)
    correct = []
    for i, j in zip(*np.nonzero(fit_m & fit_g), strict=True):
        if not used_p[i] and not used_g[j]:
            used_p[i] = used_g[j] = True
            correct.append((int(pid[i]), int(gid[j])))
    over = []
    for j in range(G):
        if used_g[j]:
            continue
        ms = np.flatnonzero(fit_m[:, j] & ~used_p)
        if len(ms) >= 2 and ov[ms, j].sum() >= t * gs[j]:
            used_g[j] = True
            used_p[ms] = True
            over.append((int(gid[j]), [int(pid[m]) for m in ms]))
    under = []
    for i in range(P):
        if used_p[i]:
            continue
        gs_ = np.flatnonzero(fit_g[i, :] & ~used_g)
        if len(gs_) >= 2 and ov[i, gs_].sum() >= t * ps[i]:
            used_p[i] = True
            used_g[gs_] = True
            under.append((int(pid[i]), [int(gid[g]) for g in gs_]))
    union = ps[:, None] + gs[None, :] - ov
    with np.errstate(invalid="ignore", divide="ignore"):
        iou = np.where(union > 0, ov / np.maximum(union, 1), 0.0)
    best = iou.max(axis=0) if P else np.zeros(G)
    return {
        "correct": correct,
        "over": over,
        "under": under,
        "missed": [int(gid[j]) for j in range(G) if not used_g[j]],
        "noise": [int(pid[i]) for i in range(P) if not used_p[i]],
        "iou": {int(gid[j]): float(best[j]) for j in range(G)},
        "n_pred": P,
        "n_gt": G,
    }


def sparse_planes(labels, *, fraction: float = 0.1, min_pixels: int | str = "auto") -> list[int]:
    """Ids of sparse regions: two or more separate pieces of significant size.

    Parameters
    ----------
    labels : ndarray, shape (H, W), int
    fraction : float
        A piece is significant when it holds at least this share of its region's pixels.
    min_pixels : int or "auto"
        ... and at least this many pixels; ``"auto"``: 10 at 160x120, scaled with the pixel count.
    """
    from scipy import ndimage

    lab = _labels("predicted", labels)
    h, w = lab.shape
    if min_pixels == "auto":
        min_px = max(3, int(round(10 * h * w / (160 * 120))))
    else:
        min_px = int(min_pixels)
    out = []
    ids = np.unique(lab[lab >= 0])
    if len(ids) == 0:
        return out
    objs = ndimage.find_objects(np.where(lab >= 0, lab + 1, 0))
    st = np.ones((3, 3), bool)
    for rid in ids:
        sl = objs[rid] if rid < len(objs) else None
        if sl is None:
            continue
        sl = tuple(slice(max(s.start - 2, 0), s.stop + 2) for s in sl)
        m = lab[sl] == rid
        closed = ndimage.binary_closing(m, structure=st) | m
        comp, nc = ndimage.label(closed, structure=st)
        if nc < 2:
            continue
        sizes = np.bincount(comp[m], minlength=nc + 1)[1:]
        total = int(m.sum())
        big = (sizes >= fraction * total) & (sizes >= min_px)
        if int(big.sum()) >= 2:
            out.append(int(rid))
    return out


def _angle_deg(a, b) -> float:
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    c = abs(float(a @ b) / (np.linalg.norm(a) * np.linalg.norm(b)))
    return math.degrees(math.acos(min(1.0, c)))


def evaluate(pred, gt, *, tolerance: float = DEFAULT_TOLERANCE, pred_normals=None,
             gt_normals=None, sparse_fraction: float = 0.1) -> SegScore:
    """Score a predicted label image against ground truth.

    Parameters
    ----------
    pred, gt : ndarray, shape (H, W), int
        Label images, -1 (any negative) = unassigned.
    tolerance : float
        SegComp overlap tolerance T (default 0.8).
    pred_normals, gt_normals : mapping id -> (3,) or ndarray (K, 3), optional
        Plane normals by id; when both are given the angle error of each correct detection is
        reported (the sign of a normal is ignored).

    Returns
    -------
    SegScore
    """
    r = segcomp(pred, gt, tolerance)
    errs = []
    if pred_normals is not None and gt_normals is not None:
        for pi, gi in r["correct"]:
            try:
                a = pred_normals[pi]
                b = gt_normals[gi]
            except (IndexError, KeyError):
                raise InputError(f"no normal for predicted plane {pi} or ground-truth plane {gi}") from None
            errs.append(_angle_deg(a, b))
    ious = list(r["iou"].values())
    return SegScore(
        tolerance=_check_tol(tolerance),
        n_gt=r["n_gt"],
        n_pred=r["n_pred"],
        correct=len(r["correct"]),
        over=len(r["over"]),
        under=len(r["under"]),
        missed=len(r["missed"]),
        noise=len(r["noise"]),
        mean_iou=float(np.mean(ious)) if ious else 0.0,
        angle_errors=tuple(errs),
        mean_angle_error=float(np.mean(errs)) if errs else None,
        sparse=len(sparse_planes(pred, fraction=sparse_fraction)),
        correct_pairs=tuple(r["correct"]),
    )
