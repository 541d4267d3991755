"""Result types of segmentation and the least-squares plane fit shared by every method."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from planerel.errors import InputError

__all__ = ["SegPlane", "Segmentation", "fit_planes"]


@dataclass(frozen=True, eq=False)
class SegPlane:
    """One segmented plane.

    Parameters
    ----------
    id : int
        Index of the plane; equals its value in :attr:`Segmentation.labels`.
    normal : ndarray, shape (3,)
        Unit normal towards the sensor (``normal . centroid < 0``).
    offset : float
        ``normal . x + offset = 0`` on the plane; > 0 (distance of the camera centre).
    n_points : int
        Number of points (pixels) in the segment.
    centroid : ndarray, shape (3,)
        Mean of the segment's points.
    rms : float
        Root-mean-square point-to-plane distance of the segment's points, metres.
    """

    id: int
    normal: np.ndarray
    offset: float
    n_points: int
    centroid: np.ndarray
    rms: float

    def __post_init__(self) -> None:
        n = np.array(self.normal, dtype=np.float64).reshape(-1)
        c = np.array(self.centroid, dtype=np.float64).reshape(-1)
        if n.shape != (3,) or not math.isfinite(n[0] + n[1] + n[2]):
            raise InputError(f"plane {self.id}: normal must be 3 finite numbers, got {self.normal!r}")
        norm = math.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
        if not 0.999 < norm < 1.001:
            raise InputError(f"plane {self.id}: normal must have unit length, got length {norm:.4g}")
        if c.shape != (3,) or not math.isfinite(c[0] + c[1] + c[2]):
            raise InputError(f"plane {self.id}: centroid must be 3 finite numbers")
        if int(self.n_points) < 1:
            raise InputError(f"plane {self.id}: n_points must be >= 1, got {self.n_points}")
        n.setflags(write=False)
        c.setflags(write=False)
        object.__setattr__(self, "normal", n)
        object.__setattr__(self, "centroid", c)
        object.__setattr__(self, "offset", float(self.offset))
        object.__setattr__(self, "rms", float(self.rms))
        object.__setattr__(self, "n_points", int(self.n_points))
        object.__setattr__(self, "id", int(self.id))

    @classmethod
    def from_fits(cls, normals, offsets, counts, centroids, rms) -> tuple:
        """The planes ``0 .. n - 1`` of a least-squares fit (:func:`fit_planes` outputs, shapes
        (n, 3), (n,), (n,), (n, 3), (n,)), validated once for all of them (the per-plane
        checks of the constructor cost ~10 us each, a tenth of a 160x120 segmentation)."""
        nrm = np.array(normals, dtype=np.float64).reshape(-1, 3)
        cen = np.array(centroids, dtype=np.float64).reshape(-1, 3)
        off = np.asarray(offsets, dtype=np.float64).reshape(-1)
        cnt = np.asarray(counts).reshape(-1)
        rr = np.asarray(rms, dtype=np.float64).reshape(-1)
        n = len(nrm)
        if not (len(cen) == len(off) == len(cnt) == len(rr) == n):
            raise InputError("planes: normals, offsets, counts, centroids and rms differ in length")
        if n == 0:
            return ()
        bad = ~(np.isfinite(nrm).all(axis=1) & np.isfinite(cen).all(axis=1)
                & (np.abs(np.einsum("ij,ij->i", nrm, nrm) - 1.0) < 0.002) & (cnt >= 1))
        if bad.any():  # the constructor names the problem
            i = int(np.flatnonzero(bad)[0])
            cls(i, nrm[i], off[i], int(cnt[i]), cen[i], rr[i])
        nrm.setflags(write=False)
        cen.setflags(write=False)
        planes = []
        for i, (o, c, r) in enumerate(zip(off.tolist(), cnt.tolist(), rr.tolist(), strict=True)):
            p = object.__new__(cls)
            p.__dict__.update(id=i, normal=nrm[i], offset=o, n_points=int(c), centroid=cen[i],
                              rms=r)
            planes.append(p)
        return tuple(planes)

    def with_id(self, i: int) -> SegPlane:
        """This plane renumbered ``i`` (itself when it already is): ``dataclasses.replace(self,
        id=i)`` without re-validating the other fields (its arrays are read-only, so they are
        shared).  The post-processing steps renumber every plane after each relabelling."""
        i = int(i)
        if self.id == i:
            return self
        p = object.__new__(SegPlane)
        p.__dict__.update(self.__dict__)
        p.__dict__["id"] = i
        return p

    def distance(self, points) -> np.ndarray:
        """Signed distances ``normal . p + offset`` of ``points`` (..., 3)."""
        return np.asarray(points, dtype=np.float64) @ self.normal + self.offset

    def to_dict(self) -> dict:
        """``{id, normal, offset, n_points, centroid, rms}`` with plain Python numbers."""
        return {
            "id": self.id,
            "normal": [float(x) for x in self.normal],
            "offset": self.offset,
            "n_points": self.n_points,
            "centroid": [float(x) for x in self.centroid],
            "rms": self.rms,
        }


@dataclass(frozen=True, eq=False)
class Segmentation:
    """Output of :func:`planerel.segment.segment`.

    Parameters
    ----------
    labels : ndarray, shape (H, W), int32
        Plane id per pixel (same layout as the cloud; ``(1, N)`` for unorganized clouds),
        -1 = unassigned.  Ids are ``0 .. len(planes) - 1``.
    planes : tuple of SegPlane
        ``planes[i].id == i``.
    method : str
        ``"regiongrow"``, ``"sp"`` or ``"snp"``.
    params : object
        The parameter dataclass actually used.
    normals : ndarray, shape (H, W, 3), or None
        The per-pixel normals used (NaN = unknown), when the method computed them (float32
        for organized clouds segmented by region growing, else float64).
    info : dict
        Method details: e.g. ``delta`` (metres) and ``min_region_size`` actually used.
    """

    labels: np.ndarray
    planes: tuple
    method: str
    params: object = None
    normals: np.ndarray | None = None
    info: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        lab = np.asarray(self.labels)
        if lab.ndim != 2 or lab.dtype != np.int32:
            raise InputError(f"labels must be an (H, W) int32 array, got {lab.dtype} {lab.shape}")
        planes = tuple(self.planes)
        for i, p in enumerate(planes):
            if p.id != i:
                raise InputError(f"plane ids must be 0..{len(planes) - 1} in order; plane {i} has id {p.id}")
        object.__setattr__(self, "planes", planes)

    @property
    def n_planes(self) -> int:
        return len(self.planes)

    def __repr__(self) -> str:
        # the dataclass repr printed the label and normal arrays whole
        h, w = self.labels.shape
        return (f"Segmentation(method={self.method!r}, {len(self.planes)} planes, labels {h}x{w}, "
                f"{int((self.labels >= 0).sum())} points in planes)")

    @property
    def message(self) -> str:
        """One line for people: how many planes, or that none was large enough."""
        if not self.planes:
            return f"{self.method}: no plane large enough was found (0 planes)"
        n_lab = int((self.labels >= 0).sum())
        return f"{self.method}: {len(self.planes)} planes covering {n_lab} points"

    def planes_json(self) -> list[dict]:
        """Per plane ``{id, normal, offset, n_points, centroid, rms}``."""
        return [p.to_dict() for p in self.planes]


def fit_planes(xyz_flat: np.ndarray, labels_flat: np.ndarray, n: int):
    """Least-squares (PCA) planes of labelled points.

    Parameters
    ----------
    xyz_flat : ndarray, shape (N, 3)
    labels_flat : ndarray, shape (N,), int32
        Region id per point (-1 = none); ids ``0 .. n - 1``.
    n : int

    Returns
    -------
    normals (n, 3), offsets (n,), counts (n,), centroids (n, 3), rms (n,)
        Normals point towards the sensor (``normal . centroid < 0``).
    """
    from planerel.segment._kernels import fit_planes_kernel

    if n == 0:
        z = np.zeros((0, 3))
        return z, np.zeros(0), np.zeros(0, dtype=np.int64), z.copy(), np.zeros(0)
    pts = np.ascontiguousarray(xyz_flat, dtype=np.float64)
    lab = np.ascontiguousarray(labels_flat, dtype=np.int32)
    return fit_planes_kernel(pts, lab, int(n))
