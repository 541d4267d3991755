"""The paper's RANSAC baselines, written for planerel (no PCL needed).

- **SP** (PCL ``SACSegmentation`` with ``SACMODEL_PLANE``): a point is an inlier of a plane when
  its distance to it is below ``threshold``.
- **SNP** (``SACSegmentationFromNormals`` with ``SACMODEL_NORMAL_PLANE``): the distance is
  ``w * angle + (1 - w) * |point-plane distance|`` with ``angle`` the angle in radians between
  the point's normal and the plane's normal (either orientation) and ``w`` the normal distance
  weight (paper: 0.1); points without a normal are never inliers.

Iterative extraction: draw hypotheses from 3 remaining points (seeded), keep the one with most
inliers, remove its inliers, repeat until fewer than ``min_region_size`` points remain, the best
plane has fewer inliers than that, or ``max_planes`` planes were taken.  Hypotheses are scored
together (one matrix product per batch) on a seeded sample of the remaining points; the number
of hypotheses adapts to the inlier ratio found (``probability``), up to ``max_iterations``.
Reported planes are the least-squares fit of each plane's inliers.
"""

from __future__ import annotations

import math

import numpy as np

from planerel.errors import InputError
from planerel.segment.params import RansacParams
from planerel.segment.result import Segmentation, SegPlane, fit_planes

__all__ = ["ransac_segment", "SP_THRESHOLDS", "SNP_THRESHOLDS"]

#: Distance thresholds (m) the paper evaluates.
SP_THRESHOLDS = (0.005, 0.01, 0.03, 0.05)
SNP_THRESHOLDS = (0.01, 0.03, 0.05)

_BATCH = 64


def _distances(P, N, planes, w, use_normals):
    """(n_points, n_hyp) distances of points P (n, 3) (normals N) to planes (h, 4)."""
    d = np.abs(P @ planes[:, :3].T + planes[:, 3][None, :])
    if not use_normals:
        return d
    c = np.abs(N @ planes[:, :3].T)
    np.clip(c, 0.0, 1.0, out=c)
    ang = np.arccos(c)
    return w * ang + (1.0 - w) * d


def ransac_segment(cloud, params: RansacParams | None = None, *, normals=None,
                   use_normals: bool = False) -> Segmentation:
    """Segment planes by iterative RANSAC (SP, or SNP with ``use_normals``).

    Parameters
    ----------
    cloud : Cloud
    params : RansacParams, optional
    normals : ndarray, shape (H, W, 3), optional
        SNP only; computed with :mod:`planerel.segment.normals` when not given.
    use_normals : bool
        True for SNP.

    Returns
    -------
    Segmentation
        ``method`` is ``"snp"`` or ``"sp"``.
    """
    from planerel.segment.regiongrow import check_cloud, resolve_min_region_size

    p = params if params is not None else RansacParams()
    if not isinstance(p, RansacParams):
        raise InputError(f"ransac: params must be RansacParams, got {type(p).__name__}")
    check_cloud(cloud)
    method = "snp" if use_normals else "sp"
    xyz = cloud.xyz
    h, w, _ = xyz.shape
    flat = xyz.reshape(-1, 3)
    min_size = resolve_min_region_size(p.min_region_size, h * w)
    ok = cloud.valid.reshape(-1).copy()
    nflat = None
    nrm_img = None
    if use_normals:
        if normals is None:
            from planerel.segment import normals as nmod

            if cloud.organized:
                nrm_img = nmod.organized_normals(xyz, smooth=p.normal_smooth, radius=p.normal_radius,
                                                 jump_factor=p.jump_factor,
                                                 intrinsics=cloud.intrinsics)
            else:
                nrm_img = nmod.knn_normals(flat, k=p.knn).reshape(xyz.shape)
        else:
            nrm_img = np.asarray(normals, dtype=np.float64)
            if nrm_img.shape != xyz.shape:
                raise InputError(f"ransac: normals shape {nrm_img.shape} differs from the cloud's {xyz.shape}")
        nflat = nrm_img.reshape(-1, 3)
        ok &= np.isfinite(nflat).all(axis=1)
    rng = np.random.default_rng(p.seed)
    labels = np.full(h * w, -1, dtype=np.int32)
    remaining = np.flatnonzero(ok)
    n_planes = 0
    iters_used = []
    log1p = math.log(1.0 - p.probability)
    while len(remaining) >= max(min_size, 3) and n_planes < p.max_planes:
        R = remaining
        if len(R) > p.score_sample:
            S = np.sort(rng.choice(R, size=p.score_sample, replace=False))
        else:
            S = R
        PS = flat[S]
        NS = nflat[S] if use_normals else None
        best_count = -1
        best_plane = None
        done = 0
        needed = p.max_iterations
        while done < min(needed, p.max_iterations):
            b = min(_BATCH, p.max_iterations - done)
            tri = rng.integers(0, len(R), size=(b, 3))
            A = flat[R[tri[:, 0]]]
            B = flat[R[tri[:, 1]]]
            C = flat[R[tri[:, 2]]]
            nvec = np.cross(B - A, C - A)
            norm = np.linalg.norm(nvec, axis=1)
            good = norm > 1e-12
            done += b
            if not good.any():
                continue
            nvec = nvec[good] / norm[good][:, None]
            off = -np.einsum("ij,ij->i", nvec, A[good])
            planes = np.column_stack([nvec, off])
            d = _distances(PS, NS, planes, p.normal_weight, use_normals)
            counts = (d < p.threshold).sum(axis=0)
            k = int(np.argmax(counts))
            if counts[k] > best_count:
                best_count = int(counts[k])
                best_plane = planes[k]
                ratio = best_count / len(S)
                if ratio >= 1.0:
                    needed = done
                elif ratio > 0:
                    needed = int(math.ceil(log1p / math.log(1.0 - ratio ** 3)))
        iters_used.append(done)
        if best_plane is None:
            break
        dall = _distances(flat[R], nflat[R] if use_normals else None, best_plane[None, :],
                          p.normal_weight, use_normals)[:, 0]
        inl = R[dall < p.threshold]
        if len(inl) < min_size:
            break
        labels[inl] = n_planes
        n_planes += 1
        keep = np.ones(len(R), bool)
        keep[dall < p.threshold] = False
        remaining = R[keep]
    planes = SegPlane.from_fits(*fit_planes(flat, labels, n_planes))
    info = {"min_region_size": min_size, "iterations": iters_used,
            "unassigned_remaining": int(len(remaining))}
    return Segmentation(labels.reshape(h, w), planes, method, p, nrm_img, info)
