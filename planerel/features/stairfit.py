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
   ``min_pixels`` pixels are tried.  With ``inclined_planes`` the pixels of each segmented
   inclined plane (not the floor; its incline within a factor 2 of ``slope``'s, its length at
   least ``min_width``) are tried as a group too: a flight seen from above whose treads and
   risers grew into one sloping region.  A tread of such a fit at the floor's level (the
   lowest plane's when no floor was found) is the floor and does not count among the faces
   (a box's front and top grown into one plane with a strip of floor is one step), and when
   the fit is kept the plane's pixels go to the faces or to none.
2. **Direction.**  A least-squares plane ``h = a . q + c`` over the points' horizontal
   positions ``q`` gives the flight's direction (the gradient) and its slope; the slope must
   lie in ``slope`` (a ramp of the judge set rises at most 0.36, a staircase 0.4-1).
3. **Profile.**  A grid search over the rise ``r`` (``rise``), the slope (0.75-1.3 times the
   fitted one, which a flight seen as treads alone underestimates) and the phase of the tread
   levels, with the profile's midline through the points' centroid, minimises the mean
   truncated squared distance of the points to the polyline; the run is ``r / slope`` and must
   lie in ``run``.  **Distances are in noise sigmas along each pixel's ray** (``ray_noise``,
   :func:`ray_metric`): a depth sensor errs along the ray, so a point ``p`` has the covariance
   ``noise_floor^2 I + sigma_z(z)^2 v v^T`` in the flight's ``(d, h)`` plane, ``v = (f . p, up
   . p) / z``, with ``sigma_z`` the sensor's depth noise measured in the cloud
   (:func:`depth_sigma`); the distance to a face is the Mahalanobis distance to its nearest
   point, truncated at ``sigmas``.  A flight seen down its slope from a landing has rays at
   a grazing angle to its treads: the noise smears each tread along the ray, nearly along the
   flight's plane, and an isotropic tolerance large enough for it lets that plane explain the
   points as well as the profile (docs/results.md, "Far flights ...").  When the cloud's noise
   cannot be measured (``depth_sigma`` None) the distances are metres, truncated at the
   isotropic ``tol(z) = clip(a + b z^2, lo, hi)`` (about two sigmas of a Kinect-like sensor).
   On a wavy frame (an active stereo camera's depth, ``NoiseModel.wavy``) with ``wavy_noise``
   the noise is the measured one times the frame's ``wave`` (:func:`depth_sigma`).
4. **Test.**  The fit is kept when at least ``min_inliers`` of the points lie within the
   truncation of the polyline (on a wavy frame ``wavy_min_inliers``, and the rise must be at
   least ``2 sigmas`` noise sigmas: :func:`_resolved`), at most ``plane_ratio`` times that
   share within it of the plane of step 2 (in the same metric; a ramp or a noisy flat patch
   fits its plane as well as any staircase), and at least ``min_faces`` treads or risers hold
   ``face_pixels`` inliers each, and the faces are at least ``min_width`` wide across the
   flight (median over the faces of the 2-98 % range of the inliers' horizontal coordinate
   across the flight: a flight is at least 0.6 m wide, the stepped pieces of furniture and
   clutter of a real office are 0.07-0.38 m wide).
5. **Labels.**  Each such face becomes a plane (new labels after the largest one) of the
   points within ``keep`` truncations of it; then the unexplained pixels of the other clusters
   that lie within the fitted flight's extent (its lateral extent widened by ``reach`` metres,
   its length by one run) and on the profile join the faces (a far flight's grazing treads
   split its pixels into several clusters).  Segmented planes (not the floor) with at least
   ``join_share`` of their points inside that extent (its length widened by ``join_reach``
   more: the near tread the region grower did find, whose inner part hides behind the
   landing) and on the profile join the flight (``join_planes``).  The planes of one fit are
   one proposal (:func:`join_groups`).

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
from planerel.features._defaults import defaults
from planerel.features.planes import label_max
from planerel.features.vectors import vec_norm

#: The grid of :func:`fit_profile`: rise step (metres), slope factors, phases of the levels.
RISE_STEP = 0.005
SLOPE_FACTORS = np.array([0.75, 0.85, 0.95, 1.05, 1.15, 1.3])
N_PHASES = 12
VEC_LIMIT = 1e6  # metres: profile_costs_vec is profile_costs bit for bit below (fit_profile)

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
    ray_noise: bool = True
    sigmas: float = 2.0
    noise_floor: float = 0.005
    min_inliers: float = 0.8
    plane_ratio: float = 0.75
    min_faces: int = 3
    face_pixels: int = 8
    min_width: float = 0.5
    keep: float = 2.0
    reach: float = 0.10
    max_fit_points: int = 400
    join_planes: bool = True
    join_share: float = 0.8
    join_reach: float = 0.35
    inclined_planes: bool = True
    wavy_noise: bool = True
    wavy_min_inliers: float = 0.65

    def __post_init__(self) -> None:
        for name in ("edge_depth", "tiny_area", "min_inliers", "plane_ratio", "keep", "reach",
                     "min_width", "join_share", "join_reach", "wavy_min_inliers"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) or v < 0:
                raise InputError(f"{name} must be a number >= 0, got {v!r}")
        for name in ("sigmas", "noise_floor"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) or v <= 0:
                raise InputError(f"{name} must be a number > 0, got {v!r}")
        for name in ("ray_noise", "join_planes", "inclined_planes", "wavy_noise"):
            if not isinstance(getattr(self, name), (bool, np.bool_)):
                raise InputError(f"{name} must be True or False, got {getattr(self, name)!r}")
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


def profile_distance(d, h, r, t, h0, d0, metric=None):
    """Distance of the points ``(d, h)`` to the staircase polyline, and the face each is
    nearest to: ``2k`` tread ``k``, ``2k + 1`` riser ``k`` (see :class:`ProfileFit`).

    ``d``, ``h`` broadcast with ``h0``, ``d0`` (a grid of phases at once).  ``metric``: each
    point's ``(m11, m12, m22)`` (columns of an ``(N, 3)`` array, :func:`ray_metric`): the
    distance is then ``sqrt(e^T M e)`` to the nearest point of each face in that metric (in
    noise sigmas); None: metres."""
    if metric is None:
        m11, m12, m22 = 1.0, 0.0, 1.0
    else:
        metric = np.asarray(metric, float)
        m11, m12, m22 = metric[:, 0], metric[:, 1], metric[:, 2]
    u = (d - d0) / t
    v = (h - h0) / r
    k0 = np.floor((u + v) / 2)
    best = np.full(np.broadcast(u, v).shape, np.inf)
    seg = np.zeros(best.shape, np.int64)

    def seg2(ax, ay, bx, by):
        ux, uy, ex, ey = bx - ax, by - ay, d - ax, h - ay
        umu = ux * ux * m11 + 2 * ux * uy * m12 + uy * uy * m22
        ume = ux * ex * m11 + (ux * ey + uy * ex) * m12 + uy * ey * m22
        s = np.clip(np.divide(ume, umu, out=np.zeros(np.broadcast(ume, umu).shape),
                              where=umu > 0), 0.0, 1.0)
        wx, wy = ex - s * ux, ey - s * uy
        return wx * wx * m11 + 2 * wx * wy * m12 + wy * wy * m22

    for dk in (-1.0, 0.0, 1.0, 2.0):
        k = k0 + dk
        a = d0 + k * t
        top = h0 + k * r
        for e, face in ((seg2(a, top, a + t, top), 2 * k.astype(np.int64)),          # tread k
                        (seg2(a, top - r, a, top), 2 * k.astype(np.int64) + 1)):     # riser k
            m = e < best
            best = np.where(m, e, best)
            seg = np.where(m, face, seg)
    return np.sqrt(best), seg


def ray_metric(points, f, up, sigma_z, floor):
    """Each point's noise metric in the flight's ``(d, h)`` plane (rule step 3).

    A depth sensor errs along each pixel's ray: a depth error ``e`` moves the point ``p`` by
    ``e p / z``.  With ``sigma_z(z)`` along the ray and an isotropic ``floor`` (the faces'
    own unevenness, the pixel's lateral extent), the covariance of ``(d, h) = (p . f, p . up)``
    is ``C = floor^2 I + sigma_z^2 v v^T`` with ``v = (f . p, up . p) / z``.

    Returns
    -------
    ndarray (N, 3)
        ``(m11, m12, m22)`` of ``C^-1`` (Sherman-Morrison): ``e^T C^-1 e`` is the squared
        distance in noise sigmas.
    """
    p = np.asarray(points, float)
    z = p[:, 2]
    vd = (p @ f) / z
    vh = (p @ up) / z
    a = float(floor) ** 2
    s2 = np.asarray(sigma_z, float) ** 2
    c = s2 / (a + s2 * (vd * vd + vh * vh))
    return np.column_stack([(1 - c * vd * vd) / a, -c * vd * vh / a, (1 - c * vh * vh) / a])


def depth_sigma(cloud, wavy: bool = False):
    """``sigma_z(z)``: the depth noise along the rays of ``cloud`` (rule step 3), or None.

    The sensor's noise model measured in the cloud (:func:`planerel.segment.noise.estimate_noise`,
    the model the segmentation and the floor test use); beyond the depth ``z_b`` of the deepest
    band it was measured in it grows at least as a disparity sensor's, ``s_b (z / z_b)^2`` with
    ``s_b`` the model's noise at ``z_b`` (a far flight lies beyond the patches a small image can measure: a
    single band at 2 m fits a constant as well as ``z^2``).  None when the cloud is too small
    or too broken to measure it (not ``reliable``): the scale of the noise is then unknown and
    the fit keeps the isotropic tolerance ``tol``.

    With ``wavy``, on a frame whose depth undulates (an active stereo camera's:
    :attr:`planerel.segment.noise.NoiseModel.wavy`) the noise is that times the frame's
    ``wave``: the pixel-to-pixel noise the model measures is then a fraction of the error a
    face's points carry over the tens of pixels a step spans (docs/objects.md, "A staircase
    profile at a wavy camera's noise").

    The function returned has the attribute ``wavy``: whether it was so scaled.
    """
    from planerel.segment.noise import estimate_noise

    if not getattr(cloud, "organized", False):
        return None
    model = estimate_noise(cloud, waviness=True) if wavy else estimate_noise(cloud)
    if not model.reliable or model.kind == "none":
        return None
    zb = model.bands[-1][0] if model.bands else model.z_median
    sb = float(model.sigma(zb))
    k = float(model.wave) if wavy and model.wavy else 1.0

    def sigma(z):
        z = np.asarray(z, float)
        return k * np.maximum(model.sigma(z), np.where(z > zb, sb * (z / zb) ** 2, 0.0))

    sigma.wavy = k > 1.0

    return sigma


def fit_profile(d, h, tol, params: StairFitParams | None = None, slope=None,
                metric=None) -> ProfileFit | None:
    """Grid search of the staircase profile closest to the points (rule step 3).

    Parameters
    ----------
    d, h : ndarray (N,)
        Horizontal coordinate along the rising direction and height, metres.
    tol : ndarray (N,)
        Per-point truncation of the distance (metres; with ``metric``, in its units).
    slope : float, optional
        The points' fitted slope (default: least squares of ``h`` on ``d``).
    metric : ndarray (N, 3), optional
        Each point's noise metric (:func:`ray_metric`); default: metres.

    Returns
    -------
    ProfileFit or None
        None when no rise / slope of the grid gives a run in ``params.run``.
    """
    from planerel.features._stairfit_kernels import profile_costs, profile_costs_vec

    p = params or StairFitParams()
    d = np.ascontiguousarray(d, dtype=np.float64)
    h = np.ascontiguousarray(h, dtype=np.float64)
    tol = np.ascontiguousarray(tol, dtype=np.float64)
    if metric is None:
        metric = np.zeros((d.size, 3))
        metric[:, 0] = metric[:, 2] = 1.0
    metric = np.ascontiguousarray(metric, dtype=np.float64)
    if slope is None:
        slope = float(np.polyfit(d, h, 1)[0])
    if not slope > 0 or d.size == 0:
        return None
    rises = np.arange(p.rise[0], p.rise[1] + 1e-9, RISE_STEP)
    # the vectorised kernel where it gives the same costs (points within 1e6 m, finite)
    costs = (profile_costs_vec if bool(np.all(np.abs(d) < VEC_LIMIT) & np.all(np.abs(h) < VEC_LIMIT))
             else profile_costs)
    cost = costs(d, h, metric, tol * tol, rises, SLOPE_FACTORS, N_PHASES, float(slope),
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


def _resolved(P, fit: ProfileFit, sigma_z, sigmas: float) -> bool:
    """Whether the profile's treads stand apart in the noise (rule step 4, on a wavy frame):
    each face's points are taken within ``sigmas`` noise sigmas of it, so two treads a rise
    apart are told apart only when ``rise >= 2 sigmas sigma_z`` at the points' median depth.
    Under that the bands of the levels cover all heights and any cloud fits some profile (a
    floor 5-8 m from a D4xx did, at 0.67-0.96 of its points).  ``sigma_z`` along the ray,
    not its part across the profile: a wavy camera's error moves a face as a whole.

    ``P`` ``(N, 3)`` the cluster's points."""
    return bool(fit.rise >= 2.0 * sigmas * float(sigma_z(np.median(P[:, 2]))))


def _tolerance(z, p: StairFitParams):
    a, b, lo, hi = p.tol
    return np.clip(a + b * np.asarray(z, float) ** 2, lo, hi)


def _cross(a, b):
    """``np.cross`` of two 3-vectors, the same products and differences (without its axis
    handling, 10 us a call)."""
    a0, a1, a2 = float(a[0]), float(a[1]), float(a[2])
    b0, b1, b2 = float(b[0]), float(b[1]), float(b[2])
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def _horizontal_axes(up):
    up = np.asarray(up, float)
    x = np.array([1.0, 0.0, 0.0]) if abs(up[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = _cross(up, x)
    e1 /= vec_norm(e1)
    return e1, _cross(up, e1)


def _on_profile(Q, frame, p: StairFitParams):
    """The points ``Q`` against a fitted flight (rule step 5): which lie inside its extent, and
    for those the distance to the profile, the nearest face and the limit (metres or sigmas).

    ``frame``: the flight's direction ``f``, its lateral axis, up, its extent ``(lateral low,
    high, along low, high)``, the :class:`ProfileFit` and ``sigma_z`` (False: the
    isotropic ``tol``)."""
    f, side, up, (lo_l, hi_l, lo_d, hi_d), fit, sigma_z = frame
    d2, l2 = Q @ f, Q @ side
    near = (l2 >= lo_l) & (l2 <= hi_l) & (d2 >= lo_d) & (d2 <= hi_d)
    Q = Q[near]
    if sigma_z:
        m2 = ray_metric(Q, f, up, sigma_z(Q[:, 2]), p.noise_floor)
        lim2 = np.full(len(Q), float(p.sigmas))
    else:
        m2 = None
        lim2 = _tolerance(Q[:, 2], p)
    dist2, seg2 = profile_distance(d2[near], Q @ up, fit.rise, fit.run, fit.h0, fit.d0, m2)
    return near, dist2, seg2, lim2


def _slope_candidates(pts, ids, n, e1, e2, up, slope, margin=1e-4, min_det=1e-6):
    """Which of the ``n`` clusters (``ids`` of the points ``pts``) may pass the slope test of
    rule step 2.

    The least-squares plane ``h = a . q + c`` of every cluster at once
    (:func:`planerel.features._stairfit_kernels.cluster_slopes`, from its centred sums); a
    cluster is ruled out only when that slope lies outside ``slope`` widened by ``margin``
    (relative) and its normal equations are well conditioned (``min_det``): the exact fit
    (``np.linalg.lstsq``) decides for every other one, so the rule's result does not change,
    only the clusters that certainly fail are not fitted one by one.
    """
    from planerel.features._stairfit_kernels import cluster_slopes

    g, sure = cluster_slopes(np.ascontiguousarray(pts, dtype=np.float64),
                             np.ascontiguousarray(ids, dtype=np.int64), int(n),
                             np.asarray(e1, float), np.asarray(e2, float), np.asarray(up, float),
                             float(min_det))
    return ~sure | ((g >= slope[0] * (1 - margin)) & (g <= slope[1] * (1 + margin)))


def _gather(xyz: np.ndarray, rows, cols) -> np.ndarray:
    """``xyz[rows, cols]`` (``(N, 3)``): for a C-contiguous cloud through the flat index
    (``np.take``: the same values, about a quarter of the fancy indexing's time)."""
    if xyz.ndim == 3 and xyz.flags.c_contiguous:
        return np.take(xyz.reshape(-1, xyz.shape[2]),
                       np.asarray(rows, np.int64) * xyz.shape[1] + np.asarray(cols, np.int64),
                       axis=0)
    return xyz[rows, cols]


def _lut_pixels(lab, valid, lut, boxes):
    """``rr, cc = np.nonzero(valid & (lab >= 0))`` and ``lut[lab[rr, cc]]``, read from the box
    that holds the pixel ``boxes`` ``(row0, col0, row1, col1)`` only: the same pixels, in the
    same order, when every pixel whose ``lut`` entry is wanted lies in one of the boxes (the
    planes' pixel boxes of ``lab``; others may be missed)."""
    y0, x0 = min(b[0] for b in boxes), min(b[1] for b in boxes)
    y1, x1 = max(b[2] for b in boxes), max(b[3] for b in boxes)
    sub = lab[y0:y1, x0:x1]
    rr, cc = np.nonzero(valid[y0:y1, x0:x1] & (sub >= 0))
    return rr + y0, cc + x0, lut[sub[rr, cc]]


def _surely_narrow(P, e1, e2, up, min_width, margin=1e-3, min_det=1e-3) -> bool:
    """Whether the width test of rule step 4 fails for the points ``P`` (``lat.max() -
    lat.min() < min_width`` along ``up x f``, ``f`` the horizontal direction of the slope of
    their least-squares plane ``h = a u + b v + c``), known without ``np.linalg.lstsq``: the
    plane from its centred normal equations (well conditioned: ``det >= min_det`` times the
    product of their diagonal, else False), the width along its direction plus ``margin``
    times the points' horizontal reach ``R`` (``hypot`` of their ranges along ``e1``, ``e2``)
    below ``min_width``.  Two directions ``d`` apart give widths at most ``R d`` apart, and
    ``d <= 2 |da, db| / g``: the margin covers coefficients up to ``1.25e-4`` apart at a
    slope ``g`` of 0.25 or more (a smaller one fails the slope test before the width test),
    where the two solutions of one well-conditioned system agree to about 1e-14 (the real
    frames' clusters).  So the rule's result does not change; the exact fit is skipped.

    The sums, the plane and the ranges in one compiled function
    (:func:`planerel.features._stairfit_kernels.width_bound`, three passes over ``P``; its
    sums in another order than numpy's, well inside the margin)."""
    from planerel.features._stairfit_kernels import width_bound

    ok, width, reach = width_bound(np.ascontiguousarray(P, dtype=np.float64),
                                   np.asarray(e1, float), np.asarray(e2, float),
                                   np.asarray(up, float), float(min_det))
    return bool(ok) and width + margin * reach < min_width


def _narrow_clusters(pts, ids, n, e1, e2, min_width, margin=1e-9):
    """Which of the ``n`` clusters (``ids`` of the points ``pts``) certainly fail the width
    test of rule step 4 (``lat.max() - lat.min() < min_width`` along the fitted flight's
    lateral axis, a horizontal unit vector): their points' horizontal reach
    (:func:`planerel.features._stairfit_kernels.cluster_spans`, ``hypot`` of the ranges along
    ``e1`` and ``e2``) bounds every horizontal direction's range, so a cluster whose reach is
    below ``min_width`` with a margin (relative and in metres, for rounding) is left out
    before its exact fit; every other one is fitted as before, so the rule's result does not
    change."""
    from planerel.features._stairfit_kernels import cluster_spans

    span = cluster_spans(np.ascontiguousarray(pts, dtype=np.float64),
                         np.ascontiguousarray(ids, dtype=np.int64), int(n),
                         np.asarray(e1, float), np.asarray(e2, float))
    return _narrow_of(span, min_width, margin)


def _narrow_of(span, min_width, margin=1e-9):
    """Which reaches (:func:`_narrow_clusters`' spans) are below ``min_width`` with the margin."""
    return span * (1 + margin) + margin < min_width


def _narrow_clusters_at(xyz, rows, cols, ids, n, e1, e2, min_width, margin=1e-9):
    """:func:`_narrow_clusters` of the points ``xyz[rows, cols]`` read in place
    (:func:`planerel.features._stairfit_kernels.cluster_spans_at`: the same values as from
    their gathered copy)."""
    from planerel.features._stairfit_kernels import cluster_spans_at

    xyz = np.asarray(xyz)
    if xyz.dtype != np.float64 or xyz.ndim != 3:
        return _narrow_clusters(_gather(xyz, rows, cols), ids, n, e1, e2, min_width, margin)
    span = cluster_spans_at(xyz, np.asarray(rows, np.int64), np.asarray(cols, np.int64),
                            np.ascontiguousarray(ids, dtype=np.int64), int(n),
                            np.asarray(e1, float), np.asarray(e2, float))
    return _narrow_of(span, min_width, margin)


def _stepped_cluster_labels(cloud, planes, params: StairFitParams | None = None,
                            gather_all: bool = False, why: dict | None = None):
    """Planes for the staircases among the unexplained pixels (rule steps 1-5).

    Parameters
    ----------
    cloud : Cloud
        Organized cloud ``(H, W, 3)``.
    planes : PlaneSet
        The measured planes (their label image and up vector).
    gather_all : bool
        Every cluster's points gathered and sloped, not only those of the large clusters the
        width bound leaves (as before 2026-11-30; the same result: the tests compare).
    why : dict, optional
        Filled for a measuring tool (``benchmarks/stairfit_why.py``; the result is the same):
        ``"clusters"``: ``(rows, cols, ids, n_comp, sizes)`` of the candidate pixels (ids of
        ``n_comp`` and above: segmented inclined planes), ``"verdicts"``: ``{cluster: (test,
        measures)}`` for each cluster of ``min_pixels`` or more, the first test of rule steps
        2-4 it fails (``narrow``, ``slope``, ``taken``, ``plane``, ``no fit``, ``resolve``,
        ``inliers``, ``faces``, ``face width``) or ``kept``.

    Returns
    -------
    ((ndarray (H, W) int32, list of set of int, dict) or None, (ndarray, ndarray))
        The label image with the new faces, the new labels of each fitted flight, and
        ``{label: normal}`` of the new faces (up for a tread, the flight's horizontal direction
        for a riser: the orientation the fit assumed and tested); None when no cluster is a
        staircase. Then the unexplained pixels of step 1, ``(rows, cols)`` (row-major).
    """
    from planerel.features._curved_kernels import list_components_spans, unexplained_pixels

    p = params or defaults(StairFitParams)
    xyz = np.asarray(cloud.xyz, float)
    lab = np.asarray(planes.labels)
    up = np.asarray(planes.up, float)
    # step 1: the unexplained pixels as a list (row-major) and their grid components, as
    # planerel.features.curved.unexplained_clusters finds them (no opening, no support)
    known = [q.label for q in planes if q.area >= p.tiny_area and q.label >= 0]
    explained = np.zeros(max(known, default=-1) + 1, bool)
    explained[known] = True
    rows, cols = unexplained_pixels(cloud.valid, lab, explained)
    pixels = (rows, cols)
    e1, e2 = _horizontal_axes(up)
    spans = None  # the components' horizontal reach (the width test's bound), taken with them
    if len(rows):
        ids, n_comp, spans = list_components_spans(rows, cols, xyz, float(p.edge_depth),
                                                   lab.shape[0], e1, e2)
    else:
        ids, n_comp = np.zeros(0, np.int64), 0
    n_all = n_comp
    if p.inclined_planes:
        # segmented inclined planes (not the floor) are candidates too: a flight seen from
        # above whose treads and risers grew into one sloping region
        # (only planes that could pass the slope and width tests: their incline within a
        # factor 2 of the slopes', their length at least min_width)
        # (the slopes' bounds only for a frame with such a plane: most have none)
        cand = [q for q in planes
                if q.orientation == "inclined" and not q.is_floor and q.label >= 0
                and q.n_points >= p.min_pixels and q.length >= p.min_width]
        if cand:
            lo, hi = np.degrees(np.arctan([p.slope[0] / 2, p.slope[1] * 2]))
            cand = [q.label for q in cand if lo <= q.incline <= hi]
        if cand:
            lut = np.full(max(label_max(lab), 0) + 1, -1, np.int64)
            lut[cand] = n_comp + np.arange(len(cand))
            # their pixels from the box of their pixel boxes, not the whole image
            chosen = set(cand)
            rr, cc, pid = _lut_pixels(lab, cloud.valid, lut,
                                      [q.bbox for q in planes if q.label in chosen])
            on = pid >= 0
            rows = np.concatenate([np.asarray(rows), rr[on]])
            cols = np.concatenate([np.asarray(cols), cc[on]])
            ids = np.concatenate([np.asarray(ids, np.int64), pid[on]])
            n_all += len(cand)
    if not len(rows):
        return None, pixels
    sizes = np.bincount(ids, minlength=n_all)
    big = np.flatnonzero(sizes >= p.min_pixels)
    if why is not None:
        why["clusters"] = (np.asarray(rows), np.asarray(cols), np.asarray(ids), n_comp, sizes)
        why["verdicts"] = verdicts = {int(c): ("narrow", {}) for c in big}

    def note(c, test, **measures):
        if why is not None:
            verdicts[int(c)] = (test, {k: round(float(v), 3) for k, v in measures.items()})

    if not big.size:
        return None, pixels
    # the clusters that certainly fail the width test first (their reach, measured with the
    # components; with inclined planes among the candidates, one compiled pass over their
    # pixels' points): when every large cluster does (most frames), nothing below is needed
    # (no point gathered, no slope; the loop would skip every cluster)
    if spans is not None and n_all == n_comp:
        narrow = _narrow_of(spans, p.min_width)
    else:
        narrow = _narrow_clusters_at(xyz, rows, cols, ids, n_all, e1, e2, p.min_width)
    if narrow[big].all():
        return None, pixels  # (every verdict "narrow")
    # only the large clusters the width bound leaves are looked at below: their points
    # gathered (each cluster's in its order: the same points and the same sums, so the same
    # slopes) and their slopes taken, not every cluster's (a Kinect frame's one wide cluster
    # of 270); the other clusters' points are gathered only when a fitted flight asks for them
    look = np.full(n_all, bool(gather_all))
    look[big[~narrow[big]]] = True
    at = np.flatnonzero(look[ids])
    pts = _gather(xyz, rows[at], cols[at])
    ids_at = ids[at]
    taken = np.zeros(len(rows), bool)
    maybe = _slope_candidates(pts, ids_at, n_all, e1, e2, up, p.slope)
    sigma_z = None  # the sensor's noise along the rays, measured when a cluster is fitted
    out = None
    groups = []
    normals = {}
    nxt = None  # the first new label, label_max(lab) + 1, taken when a fit is kept
    # the largest first; equal sizes by their first pixel (row-major)
    for c in big[np.argsort(-sizes[big], kind="stable")]:
        if narrow[c]:
            continue  # no horizontal direction spans min_width (the width test below fails)
        if not maybe[c]:
            note(c, "slope")
            continue  # its plane's slope is outside p.slope (step 2), with a margin
        idx = np.flatnonzero(ids == c)
        if taken[idx].any():
            note(c, "taken")
            continue
        P = pts[ids_at == c]  # pts[idx] of every cluster's points: the same rows
        if _surely_narrow(P, e1, e2, up, p.min_width):
            continue  # the width test below fails whatever the exact fit's slope
        h = P @ up
        X = np.c_[P @ e1, P @ e2, np.ones(len(h))]
        coef = np.linalg.lstsq(X, h, rcond=None)[0]
        g = float(np.hypot(coef[0], coef[1]))
        if not p.slope[0] <= g <= p.slope[1]:
            note(c, "slope", slope=g)
            continue
        f = (coef[0] * e1 + coef[1] * e2) / g
        side = _cross(up, f)
        lat = P @ side
        if float(lat.max() - lat.min()) < p.min_width:
            continue  # no face can be min_width wide (step 4), no fit needed
        d = P @ f
        if p.ray_noise and sigma_z is None:
            sigma_z = depth_sigma(cloud, p.wavy_noise) or False
        if sigma_z:
            metric = ray_metric(P, f, up, sigma_z(P[:, 2]), p.noise_floor)
            lim = np.full(len(d), float(p.sigmas))
        else:
            metric = None
            lim = _tolerance(P[:, 2], p)
        res = h - X @ coef
        if metric is None:
            plane_share = float((np.abs(res) < lim).mean())
        else:
            # the plane's distance in the same metric: across the line h = g d + c of the
            # (d, h) plane (normal n), e^2 / (n^T C n) with C = M^-1
            n0, n1 = -g / np.hypot(g, 1.0), 1.0 / np.hypot(g, 1.0)
            m11, m12, m22 = metric[:, 0], metric[:, 1], metric[:, 2]
            ncn = (m22 * n0 * n0 - 2 * m12 * n0 * n1 + m11 * n1 * n1) / (m11 * m22 - m12 * m12)
            plane_share = float((np.abs(res * n1) / np.sqrt(ncn) < lim).mean())
        if plane_share > p.plane_ratio:
            note(c, "plane", slope=g, plane=plane_share)
            continue  # the plane test fails whatever the profile's share (at most 1)
        if len(d) > p.max_fit_points:
            # a fixed, evenly spaced subset (row-major order): deterministic
            sub = np.linspace(0, len(d) - 1, p.max_fit_points).astype(np.int64)
        else:
            sub = np.arange(len(d))
        fit = fit_profile(d[sub], h[sub], lim[sub], p, slope=g,
                          metric=None if metric is None else metric[sub])
        if fit is None:
            note(c, "no fit", slope=g, plane=plane_share)
            continue
        wavy = bool(sigma_z) and sigma_z.wavy
        if wavy and not _resolved(P, fit, sigma_z, p.sigmas):
            note(c, "resolve", slope=g, plane=plane_share, rise=fit.rise)
            continue
        dist, seg = profile_distance(d, h, fit.rise, fit.run, fit.h0, fit.d0, metric)
        inl = dist < lim
        share = float(inl.mean())
        faces, counts = np.unique(seg[inl], return_counts=True)
        faces = faces[counts >= p.face_pixels]
        min_in = p.wavy_min_inliers if wavy else p.min_inliers
        if share < min_in or plane_share > p.plane_ratio * share or len(faces) < p.min_faces:
            note(c, "inliers" if share < min_in
                 else "plane" if plane_share > p.plane_ratio * share else "faces",
                 slope=g, plane=plane_share, share=share, faces=len(faces), rise=fit.rise,
                 run=fit.run)
            continue
        if c >= n_comp:
            # a sloping plane's points on the floor's level (the lowest plane's when no floor
            # was found) are the floor, not a tread: a box's front and top grown into one
            # plane with a strip of floor is one step
            lvl = fit.h0 + (faces // 2) * fit.rise
            faces = faces[(faces % 2 == 1) | (np.abs(lvl - planes.floor_level) >= fit.rise / 2)]
            if len(faces) < p.min_faces:
                note(c, "faces", slope=g, plane=plane_share, share=share, faces=len(faces))
                continue
        widths = [float(np.subtract(*np.percentile(lat[inl & (seg == fc)], [98, 2])))
                  for fc in faces]
        if np.median(widths) < p.min_width:
            note(c, "face width", slope=g, share=share, width=np.median(widths))
            continue
        # the other unexplained pixels within the flight's extent that lie on its profile
        lo_l, hi_l = lat.min() - p.reach, lat.max() + p.reach
        lo_d, hi_d = d.min() - fit.run, d.max() + fit.run

        frame = (f, side, up, (lo_l, hi_l, lo_d, hi_d), fit, sigma_z)
        other = np.flatnonzero((ids != c) & (ids < n_comp) & ~taken)
        if other.size:
            near, dist2, seg2, lim2 = _on_profile(_gather(xyz, rows[other], cols[other]),
                                                  frame, p)
            if near.any():
                on = dist2 < lim2
                idx = np.concatenate([idx, other[near][on]])
                dist = np.concatenate([dist, dist2[on]])
                seg = np.concatenate([seg, seg2[on]])
                lim = np.concatenate([lim, lim2[on]])
        if out is None:
            out = lab.astype(np.int32, copy=True)
            nxt = label_max(lab) + 1
        if c >= n_comp:
            own = ids == c  # a segmented inclined plane: its pixels go to the faces or none
            out[rows[own], cols[own]] = -1
        keep = dist < p.keep * lim
        new = set()
        for face in faces:
            sel = idx[keep & (seg == face)]
            out[rows[sel], cols[sel]] = nxt
            taken[sel] = True
            new.add(nxt)
            normals[nxt] = up if face % 2 == 0 else f  # tread / riser
            nxt += 1
        taken[ids == c] = True
        if p.join_planes:
            # segmented planes of the flight (the near tread the region grower found): most of
            # their points inside the flight's extent and on its profile
            # (the extent along the flight widened by join_reach more: seen from above, the
            # inner part of each tread, up to a whole run, is hidden behind the nosing of the
            # one above it, and a fit may take every other level at half the rise and run)
            wide = (f, side, up, (lo_l, hi_l, lo_d - p.join_reach, hi_d + p.join_reach), fit,
                    sigma_z)
            for q in planes:
                if q.is_floor or q.label < 0:
                    continue
                rr, cc = np.nonzero((lab == q.label) & cloud.valid)
                if not len(rr):
                    continue
                near, dist2, _, lim2 = _on_profile(xyz[rr, cc], wide, p)
                if (near.mean() >= p.join_share
                        and (dist2 < lim2).sum() >= p.join_share * len(rr)):
                    new.add(int(q.label))
        groups.append(new)
        note(c, "kept", slope=g, plane=plane_share, share=share, faces=len(faces),
             rise=fit.rise, run=fit.run)
    return (None if out is None else (out, groups, normals)), pixels


def stepped_cluster_labels(cloud, planes, params: StairFitParams | None = None):
    """Planes for the staircases among the unexplained pixels (rule steps 1-5): the first item
    of :func:`_stepped_cluster_labels` (same parameters), ``(labels (H, W) int32, flights,
    normals)`` or None; the pixel list it also returns is for ``describe_scene`` only."""
    return _stepped_cluster_labels(cloud, planes, params)[0]


def remeasure_stepped_clusters(cloud, planes, plane_params=None, params: StairFitParams | None = None):
    """:func:`stepped_cluster_labels` on measured planes, and the planes measured again when a
    flight was fitted (with the same up vector, its source and confidence kept).

    Returns
    -------
    (PlaneSet, list of set of int)
        The planes (the given ones when nothing was fitted) and each flight's plane labels
        (those that have a measured plane).
    """
    return _remeasure_stepped_clusters(cloud, planes, plane_params, params)[:2]


def _remeasure_stepped_clusters(cloud, planes, plane_params=None, params=None):
    """:func:`remeasure_stepped_clusters` and, when nothing was fitted (the planes returned
    are the given ones), the unexplained pixels of step 1 as rows and columns (row-major:
    valid pixels of no plane of ``tiny_area`` m^2 or more), else None; for
    :func:`planerel.features.curved.unexplained_clusters` to open without scanning the image
    again."""
    from planerel.features.planes import measure_planes  # (looked up at each call: see facts)

    got, pixels = _stepped_cluster_labels(cloud, planes, params)
    if got is None:
        return planes, [], pixels
    lab, groups, normals = got
    again = measure_planes(cloud, lab, planes.up, plane_params, normals=normals)
    again = again.with_up_of(planes)
    known = {q.label for q in again}
    groups = [g & known for g in groups]
    return again, [g for g in groups if g], None


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
