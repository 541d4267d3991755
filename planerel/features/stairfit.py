"""Planes for a staircase the region grower left unassigned: a stepped profile fitted along gravity.

A flight 2-4 m away at 160x120 shows risers a few pixels tall and treads one to three pixels
deep; the region grower's minimum region (set from the noise) and its normal window are larger
than such faces, so most of the flight's pixels are in no plane (docs/results.md, "The wall
test and the far steps' limit").  Their points still lie on a staircase: seen along the
flight's horizontal direction ``d`` and gravity ``h``, on a polyline of horizontal treads
``h = h0 + k r`` and vertical risers ``d = d0 + k t``.  The noise of one pixel (a few cm at 3 m)
is below the rise (0.08-0.30 m), so the profile can be fitted to a cluster's points even when
no single face can be.

The rule (:func:`stepped_cluster_labels`):

1. **Clusters.**  The unexplained pixels (no plane, or a plane under ``tiny_area``:
   :func:`planerel.features.curved.unexplained_clusters` without an opening) grouped in the
   grid with 3-D neighbours within ``edge_depth * max(1, z)``; clusters of at least
   ``min_pixels`` pixels are tried.
2. **Direction.**  A least-squares plane ``h = a . q + c`` over the points' horizontal
   positions ``q`` gives the flight's direction (the gradient) and its slope; the slope must
   lie in ``slope`` (a ramp of the judge set rises at most 0.36, a staircase 0.4-1).
3. **Profile.**  A grid search over the rise ``r`` (``rise``), the slope (0.75-1.3 times the
   fitted one, which a flight seen as treads alone underestimates) and the phase of the tread
   levels, with the profile's midline through the points' centroid, minimises the mean
   truncated squared distance of the points to the polyline (truncated at ``tol(z) = clip(a +
   b z^2, lo, hi)``: about two noise sigmas of a Kinect-like sensor); the run is ``r / slope``
   and must lie in ``run``.
4. **Test.**  The fit is kept when at least ``min_inliers`` of the points lie within ``tol``
   of the polyline, at most ``plane_ratio`` times that share within ``tol`` of the plane of
   step 2 (a ramp or a noisy flat patch fits its plane as well as any staircase), and at least
   ``min_faces`` treads or risers hold ``face_pixels`` inliers each, and the faces are at least
   ``min_width`` wide across the flight (median over the faces of the 2-98 % range of the
   inliers' horizontal coordinate across the flight: a flight is at least 0.6 m wide, the
   stepped pieces of furniture and clutter of a real office are 0.07-0.38 m wide).
5. **Labels.**  Each such face becomes a plane (new labels after the largest one) of the
   points within ``keep * tol`` of it; then the unexplained pixels of the other clusters that
   lie within the fitted flight's extent (its lateral extent widened by ``reach`` metres, its
   length by one run) and within ``tol`` of the profile join the faces (a far flight's grazing
   treads split its pixels into several clusters).  The faces of one fit are one proposal
   (:func:`join_groups`).

The planes are measured as any other (:func:`planerel.features.planes.measure_planes`), except
that a face's normal is the one the fit assumed and tested (up for a tread, the flight's
horizontal direction for a riser): a strip one to three pixels across with a few cm of noise
gives no normal of its own.  The proposals, relations and facts of such a flight are then
those of a segmented one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planerel.errors import InputError

#: The grid of :func:`fit_profile`: rise step (metres), slope factors, phases of the levels.
RISE_STEP = 0.005
SLOPE_FACTORS = np.array([0.75, 0.85, 0.95, 1.05, 1.15, 1.3])
N_PHASES = 12

__all__ = ["StairFitParams", "ProfileFit", "profile_distance", "fit_profile",
           "stepped_cluster_labels", "remeasure_stepped_clusters", "join_groups"]


@dataclass(frozen=True)
class StairFitParams:
    """Parameters of :func:`stepped_cluster_labels` (see the module docstring for the rule)."""

    min_pixels: int = 100
    edge_depth: float = 0.10
    tiny_area: float = 0.0005
    slope: tuple = (0.25, 1.5)
    rise: tuple = (0.08, 0.30)
    run: tuple = (0.12, 0.60)
    tol: tuple = (0.005, 0.004, 0.01, 0.04)
    min_inliers: float = 0.8
    plane_ratio: float = 0.75
    min_faces: int = 3
    face_pixels: int = 8
    min_width: float = 0.5
    keep: float = 2.0
    reach: float = 0.10
    max_fit_points: int = 400

    def __post_init__(self) -> None:
        for name in ("edge_depth", "tiny_area", "min_inliers", "plane_ratio", "keep", "reach",
                     "min_width"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) or v < 0:
                raise InputError(f"{name} must be a number >= 0, got {v!r}")
        for name in ("min_pixels", "min_faces", "face_pixels", "max_fit_points"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise InputError(f"{name} must be an integer >= 1, got {v!r}")
        for name in ("slope", "rise", "run"):
            v = getattr(self, name)
            if (not isinstance(v, (tuple, list)) or len(v) != 2
                    or not all(isinstance(x, (int, float)) and np.isfinite(x) for x in v)
                    or not 0 < v[0] <= v[1]):
                raise InputError(f"{name} must be two numbers 0 < low <= high, got {v!r}")
        v = self.tol
        if (not isinstance(v, (tuple, list)) or len(v) != 4
                or not all(isinstance(x, (int, float)) and np.isfinite(x) and x >= 0 for x in v)
                or not 0 < v[2] <= v[3]):
            raise InputError(f"tol must be (a, b, lo, hi) with 0 < lo <= hi, got {v!r}")


@dataclass(frozen=True)
class ProfileFit:
    """A staircase profile in ``(d, h)``: treads ``h = h0 + k r`` for ``d`` in
    ``[d0 + k t, d0 + (k+1) t]``, risers ``d = d0 + k t`` for ``h`` in
    ``[h0 + (k-1) r, h0 + k r]`` (``d`` taken in the direction the flight rises)."""

    slope: float
    rise: float
    run: float
    h0: float
    d0: float
    cost: float


def profile_distance(d, h, r, t, h0, d0):
    """Distance of the points ``(d, h)`` to the staircase polyline, and the face each is
    nearest to: ``2k`` tread ``k``, ``2k + 1`` riser ``k`` (see :class:`ProfileFit`).

    ``d``, ``h`` broadcast with ``h0``, ``d0`` (a grid of phases at once)."""
    u = (d - d0) / t
    v = (h - h0) / r
    k0 = np.floor((u + v) / 2)
    best = np.full(np.broadcast(u, v).shape, np.inf)
    seg = np.zeros(best.shape, np.int64)
    for dk in (-1.0, 0.0, 1.0, 2.0):
        k = k0 + dk
        # tread k
        a = d0 + k * t
        e = np.hypot(d - np.clip(d, a, a + t), h - (h0 + k * r))
        m = e < best
        best = np.where(m, e, best)
        seg = np.where(m, 2 * k.astype(np.int64), seg)
        # riser k
        top = h0 + k * r
        e = np.hypot(d - a, h - np.clip(h, top - r, top))
        m = e < best
        best = np.where(m, e, best)
        seg = np.where(m, 2 * k.astype(np.int64) + 1, seg)
    return best, seg


def fit_profile(d, h, tol, params: StairFitParams | None = None, slope=None) -> ProfileFit | None:
    """Grid search of the staircase profile closest to the points (rule step 3).

    Parameters
    ----------
    d, h : ndarray (N,)
        Horizontal coordinate along the rising direction and height, metres.
    tol : ndarray (N,)
        Per-point truncation of the squared distance, metres.
    slope : float, optional
        The points' fitted slope (default: least squares of ``h`` on ``d``).

    Returns
    -------
    ProfileFit or None
        None when no rise / slope of the grid gives a run in ``params.run``.
    """
    from planerel.features._stairfit_kernels import profile_costs

    p = params or StairFitParams()
    d = np.ascontiguousarray(d, dtype=np.float64)
    h = np.ascontiguousarray(h, dtype=np.float64)
    tol = np.ascontiguousarray(tol, dtype=np.float64)
    if slope is None:
        slope = float(np.polyfit(d, h, 1)[0])
    if not slope > 0 or d.size == 0:
        return None
    rises = np.arange(p.rise[0], p.rise[1] + 1e-9, RISE_STEP)
    cost = profile_costs(d, h, tol, rises, SLOPE_FACTORS, N_PHASES, float(slope),
                         float(p.run[0]), float(p.run[1]))
    k = int(np.argmin(cost))  # the first of equal costs: rise, slope factor, phase order
    if not np.isfinite(cost.flat[k]):
        return None
    a, b, j = np.unravel_index(k, cost.shape)
    r = float(rises[a])
    s = float(slope * SLOPE_FACTORS[b])
    h0 = j / N_PHASES * r
    d0 = (h0 - r / 2 - (float(h.mean()) - s * float(d.mean()))) / s
    return ProfileFit(s, r, r / s, h0, d0, float(cost.flat[k]))


def _tolerance(z, p: StairFitParams):
    a, b, lo, hi = p.tol
    return np.clip(a + b * np.asarray(z, float) ** 2, lo, hi)


def _horizontal_axes(up):
    up = np.asarray(up, float)
    x = np.array([1.0, 0.0, 0.0]) if abs(up[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(up, x)
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(up, e1)


def stepped_cluster_labels(cloud, planes, params: StairFitParams | None = None):
    """Planes for the staircases among the unexplained pixels (rule steps 1-5).

    Parameters
    ----------
    cloud : Cloud
        Organized cloud ``(H, W, 3)``.
    planes : PlaneSet
        The measured planes (their label image and up vector).

    Returns
    -------
    (ndarray (H, W) int32, list of set of int, dict) or None
        The label image with the new faces, the new labels of each fitted flight, and
        ``{label: normal}`` of the new faces (up for a tread, the flight's horizontal direction
        for a riser: the orientation the fit assumed and tested); None when no cluster is a
        staircase.
    """
    from planerel.features._curved_kernels import list_components, unexplained_open
    from planerel.features.planes import label_max

    p = params or StairFitParams()
    xyz = np.asarray(cloud.xyz, float)
    lab = np.asarray(planes.labels)
    up = np.asarray(planes.up, float)
    # step 1: the unexplained pixels as a list (row-major) and their grid components, as
    # planerel.features.curved.unexplained_clusters finds them (no opening, no support)
    known = [q.label for q in planes if q.area >= p.tiny_area and q.label >= 0]
    explained = np.zeros(max(known, default=-1) + 1, bool)
    explained[known] = True
    _, rows, cols = unexplained_open(cloud.valid, lab, explained, 0)
    if not len(rows):
        return None
    ids, n_comp = list_components(rows, cols, xyz, float(p.edge_depth), lab.shape[0])
    sizes = np.bincount(ids, minlength=n_comp)
    big = np.flatnonzero(sizes >= p.min_pixels)
    if not big.size:
        return None
    pts = xyz[rows, cols]
    z = pts[:, 2]
    taken = np.zeros(len(rows), bool)
    e1, e2 = _horizontal_axes(up)
    out = None
    groups = []
    normals = {}
    nxt = label_max(lab) + 1
    # the largest first; equal sizes by their first pixel (row-major)
    for c in big[np.argsort(-sizes[big], kind="stable")]:
        idx = np.flatnonzero(ids == c)
        if taken[idx].any():
            continue
        P = pts[idx]
        h = P @ up
        X = np.c_[P @ e1, P @ e2, np.ones(len(h))]
        coef = np.linalg.lstsq(X, h, rcond=None)[0]
        g = float(np.hypot(coef[0], coef[1]))
        if not p.slope[0] <= g <= p.slope[1]:
            continue
        f = (coef[0] * e1 + coef[1] * e2) / g
        side = np.cross(up, f)
        lat = P @ side
        if float(lat.max() - lat.min()) < p.min_width:
            continue  # no face can be min_width wide (step 4), no fit needed
        d = P @ f
        tol = _tolerance(z[idx], p)
        if len(d) > p.max_fit_points:
            # a fixed, evenly spaced subset (row-major order): deterministic
            sub = np.linspace(0, len(d) - 1, p.max_fit_points).astype(np.int64)
        else:
            sub = np.arange(len(d))
        fit = fit_profile(d[sub], h[sub], tol[sub], p, slope=g)
        if fit is None:
            continue
        dist, seg = profile_distance(d, h, fit.rise, fit.run, fit.h0, fit.d0)
        inl = dist < tol
        share = float(inl.mean())
        plane_share = float((np.abs(h - X @ coef) < tol).mean())
        faces, counts = np.unique(seg[inl], return_counts=True)
        faces = faces[counts >= p.face_pixels]
        if share < p.min_inliers or plane_share > p.plane_ratio * share or len(faces) < p.min_faces:
            continue
        widths = [float(np.subtract(*np.percentile(lat[inl & (seg == fc)], [98, 2])))
                  for fc in faces]
        if np.median(widths) < p.min_width:
            continue
        # the other unexplained pixels within the flight's extent that lie on its profile
        lo_l, hi_l = lat.min() - p.reach, lat.max() + p.reach
        lo_d, hi_d = d.min() - fit.run, d.max() + fit.run
        other = np.flatnonzero((ids != c) & ~taken)
        if other.size:
            Q = pts[other]
            d2, l2 = Q @ f, Q @ side
            near = (l2 >= lo_l) & (l2 <= hi_l) & (d2 >= lo_d) & (d2 <= hi_d)
            if near.any():
                other, Q, d2 = other[near], Q[near], d2[near]
                dist2, seg2 = profile_distance(d2, Q @ up, fit.rise, fit.run, fit.h0, fit.d0)
                tol2 = _tolerance(Q[:, 2], p)
                on = dist2 < tol2
                idx = np.concatenate([idx, other[on]])
                dist = np.concatenate([dist, dist2[on]])
                seg = np.concatenate([seg, seg2[on]])
                tol = np.concatenate([tol, tol2[on]])
        if out is None:
            out = lab.astype(np.int32, copy=True)
        keep = dist < p.keep * tol
        new = set()
        for face in faces:
            sel = idx[keep & (seg == face)]
            out[rows[sel], cols[sel]] = nxt
            taken[sel] = True
            new.add(nxt)
            normals[nxt] = up if face % 2 == 0 else f  # tread / riser
            nxt += 1
        taken[ids == c] = True
        groups.append(new)
    return None if out is None else (out, groups, normals)


def remeasure_stepped_clusters(cloud, planes, plane_params=None, params: StairFitParams | None = None):
    """:func:`stepped_cluster_labels` on measured planes, and the planes measured again when a
    flight was fitted (with the same up vector, its source and confidence kept).

    Returns
    -------
    (PlaneSet, list of set of int)
        The planes (the given ones when nothing was fitted) and each flight's plane labels
        (those that have a measured plane).
    """
    from dataclasses import replace

    from planerel.features.planes import measure_planes

    got = stepped_cluster_labels(cloud, planes, params)
    if got is None:
        return planes, []
    lab, groups, normals = got
    again = measure_planes(cloud, lab, planes.up, plane_params, normals=normals)
    again = replace(again, up_source=planes.up_source, up_confidence=planes.up_confidence)
    known = {q.label for q in again}
    groups = [g & known for g in groups]
    return again, [g for g in groups if g]


def join_groups(groups, flights):
    """Each fitted flight's planes in one proposal: the proposals holding any of its planes
    are joined with all of them.

    Parameters
    ----------
    groups : sequence of sequences of int
        Proposals (plane labels).
    flights : sequence of sets of int
        Plane labels of each fitted flight.

    Returns
    -------
    list of tuple of int
        Proposals, each sorted, ordered by their smallest label.
    """
    out = [set(g) for g in groups]
    for fl in flights:
        fl = set(fl)
        if not fl:
            continue
        hit = [g for g in out if g & fl]
        rest = [g for g in out if not g & fl]
        joined = set(fl)
        for g in hit:
            joined |= g
        out = rest + [joined]
    return sorted((tuple(sorted(g)) for g in out if g), key=lambda c: c[0])
