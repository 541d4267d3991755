"""A far flight left unassigned by the region grower gets its treads and risers from the stepped
profile of its points (planerel.features.stairfit).

Scenes are ray cast from rectangles (tests/scenes_analytic.py) at 160x120 with depth noise along
the ray; the flight's pixels are given no label (the region grower's answer for steps a few
pixels across: docs/results.md, judge set), the floor its own, so the test is of the fit and the
proposal, not of region growing (the judge set's far flights are in
benchmarks/independent_scenes.py).
"""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import Rect, floor, ramp, render, stairs

from planerel.errors import InputError
from planerel.features.curved import CurvedParams
from planerel.features.facts import describe_scene
from planerel.features.stairfit import (
    StairFitParams,
    depth_sigma,
    fit_profile,
    join_groups,
    profile_distance,
    ray_metric,
    stepped_cluster_labels,
)


def _unassigned(rects, *, noise=0.003, **kw):
    cloud, lab, up, objs = render(rects, width=160, height=120, noise=noise, seed=3, **kw)
    # the floor (rect 0) keeps its label, everything else is left to the fit
    lab = np.where(lab == 0, 0, -1).astype(np.int32)
    return cloud, lab, up


def _flight(n=5, rise=0.17, run=0.29, width=1.2, y0=2.6):
    return [floor(size=12.0, y=4.0), *stairs(0.0, y0, n=n, rise=rise, run=run, width=width)]


def test_profile_distance_is_zero_on_the_polyline_and_names_the_face():
    r, t, h0, d0 = 0.2, 0.3, 0.0, 0.0
    # tread 1 (h = 0.2, d in [0.3, 0.6]) and riser 2 (d = 0.6, h in [0.2, 0.4])
    d = np.array([0.45, 0.6, 0.45])
    h = np.array([0.2, 0.3, 0.25])
    dist, seg = profile_distance(d, h, r, t, h0, d0)
    np.testing.assert_allclose(dist, [0.0, 0.0, 0.05], atol=1e-12)
    assert seg.tolist() == [2, 5, 2]


def test_fit_recovers_rise_and_run_of_noisy_treads_and_risers():
    rng = np.random.default_rng(0)
    r, t = 0.17, 0.29
    d, h = [], []
    for k in range(5):
        dt = rng.uniform(k * t, (k + 1) * t, 60)  # tread k
        d += [dt]
        h += [np.full(60, k * r)]
        hr = rng.uniform((k - 1) * r, k * r, 40)  # riser k
        d += [np.full(40, k * t)]
        h += [hr]
    d = np.concatenate(d) + rng.normal(0, 0.01, 500) + 3.0
    h = np.concatenate(h) + rng.normal(0, 0.01, 500) + 0.4
    fit = fit_profile(d, h, np.full(d.size, 0.02))
    assert fit is not None
    assert abs(fit.rise - r) <= 0.015 and abs(fit.run - t) <= 0.03
    dist, _ = profile_distance(d, h, fit.rise, fit.run, fit.h0, fit.d0)
    assert (dist < 0.03).mean() > 0.9


def test_a_far_unassigned_flight_becomes_one_proposal_of_treads_and_risers():
    cloud, lab, up = _unassigned(_flight(), pitch=10.0, cam_height=1.0)
    got = stepped_cluster_labels(cloud, describe_scene(
        cloud, lab, up=up, curved_params=CurvedParams(stepped_clusters=False)).planes)
    assert got is not None and len(got[1]) == 1
    d = describe_scene(cloud, lab, up=up)
    new = [p for p in d.planes if p.label != 0]
    kinds = sorted(p.orientation for p in new)
    assert kinds.count("horizontal") >= 3 and kinds.count("vertical") >= 3
    # one proposal holds the flight's planes
    holding = [o for o in d.objects if set(o.planes) & {p.label for p in new}]
    assert len(holding) == 1 and set(holding[0].planes) >= {p.label for p in new}
    # the heights of the treads step by about the rise
    treads = sorted(p.centroid @ up for p in new if p.orientation == "horizontal")
    assert np.allclose(np.diff(treads)[:2], 0.17, atol=0.04)
    # switched off: the flight's pixels stay unassigned
    off = describe_scene(cloud, lab, up=up, curved_params=CurvedParams(stepped_clusters=False))
    assert [p.label for p in off.planes] == [0]


def test_a_ramp_and_a_narrow_stepped_object_are_not_stairs():
    cloud, lab, up = _unassigned([floor(size=12.0, y=4.0), *ramp(0.0, 2.6, angle=15.0,
                                                                    length=2.0, width=1.2)],
                                 pitch=10.0, cam_height=1.0)
    d = describe_scene(cloud, lab, up=up)
    assert [p.label for p in d.planes] == [0]
    # within an isotropic tolerance the ramp's points fit a staircase too and it is the plane
    # test that tells (their plane fits better); with the noise along the rays they fit none
    assert stepped_cluster_labels(cloud, d.planes,
                                  StairFitParams(ray_noise=False, plane_ratio=2.0)) is not None
    assert stepped_cluster_labels(cloud, d.planes, StairFitParams(plane_ratio=2.0)) is None
    # a 0.3 m wide stepped thing (a shelf, a stand): no flight is narrower than min_width
    cloud, lab, up = _unassigned(_flight(width=0.3, y0=1.8), pitch=10.0, cam_height=1.0)
    d = describe_scene(cloud, lab, up=up)
    assert [p.label for p in d.planes] == [0]
    assert stepped_cluster_labels(cloud, d.planes, StairFitParams(min_width=0.0)) is not None


def test_join_groups_puts_a_flights_planes_into_one_proposal():
    assert join_groups([(1, 2), (3,), (4, 5)], [{2, 3, 9}]) == [(1, 2, 3, 9), (4, 5)]
    assert join_groups([(1,), (2,)], []) == [(1,), (2,)]


def test_parameters_are_checked():
    with pytest.raises(InputError):
        StairFitParams(rise=(0.3, 0.1))
    with pytest.raises(InputError):
        StairFitParams(min_faces=0)
    with pytest.raises(InputError):
        StairFitParams(tol=(0.0, 0.0, 0.0, 0.01))
    with pytest.raises(InputError):
        StairFitParams(min_width=-1.0)


def test_the_labels_are_deterministic():
    cloud, lab, up = _unassigned(_flight(), pitch=10.0, cam_height=1.0)
    a = describe_scene(cloud, lab, up=up)
    b = describe_scene(cloud, lab, up=up)
    assert np.array_equal(a.labels, b.labels)
    assert [o.planes for o in a.objects] == [o.planes for o in b.objects]


_ = Rect  # the rectangles' type (the scenes above are built by scenes_analytic's helpers)


def test_the_grid_kernel_is_the_numpy_distance():
    from planerel.features._stairfit_kernels import profile_costs

    rng = np.random.default_rng(5)
    d = rng.uniform(2.0, 3.5, 200)
    h = 0.5 * d + rng.normal(0, 0.05, 200)
    tol = rng.uniform(0.01, 0.04, 200)
    rises = np.array([0.1, 0.17])
    factors = np.array([0.9, 1.1])
    eye = np.tile([1.0, 0.0, 1.0], (200, 1))
    # an anisotropic metric per point (positive definite)
    m = np.column_stack([rng.uniform(1, 9, 200), rng.uniform(-1, 1, 200), rng.uniform(1, 9, 200)])
    for metric, trunc in ((eye, tol), (m, np.full(200, 2.0))):
        cost = profile_costs(d, h, metric, trunc ** 2, rises, factors, 4, 0.5, 0.12, 0.6)
        for a, r in enumerate(rises):
            for b, f in enumerate(factors):
                s = 0.5 * f
                for j in range(4):
                    h0 = j / 4 * r
                    d0 = (h0 - r / 2 - (h.mean() - s * d.mean())) / s
                    dist, _ = profile_distance(d, h, r, r / s, h0, d0,
                                               None if metric is eye else metric)
                    assert cost[a, b, j] == pytest.approx(np.mean(np.minimum(dist, trunc) ** 2),
                                                          rel=1e-9)


def test_the_metric_distance_is_the_noise_along_the_ray_in_sigmas():
    rng = np.random.default_rng(2)
    up = np.array([0.0, -0.9, -0.4358898943540674])  # camera looking down at about 26 degrees
    f = np.cross(up, [1.0, 0.0, 0.0])
    f /= np.linalg.norm(f)
    p = np.column_stack([rng.uniform(-1, 1, 50), rng.uniform(-0.5, 0.5, 50),
                         rng.uniform(2.0, 3.5, 50)])
    sz = 0.0025 * p[:, 2] ** 2
    m = ray_metric(p, f, up, sz, 0.005)
    for i in range(50):
        # against the inverse of the covariance of (p . f, p . up) built explicitly
        v = np.array([p[i] @ f, p[i] @ up]) / p[i, 2]
        c = 0.005 ** 2 * np.eye(2) + sz[i] ** 2 * np.outer(v, v)
        ci = np.linalg.inv(c)
        np.testing.assert_allclose(m[i], [ci[0, 0], ci[0, 1], ci[1, 1]], rtol=1e-9)
    # a tread point moved along its own ray by 2 sigmas is 2 sigmas from the tread (the floor
    # adds a little), however far that moves it vertically; 2 sigmas straight up is far more
    r, t = 0.17, 0.28
    # a point 1.5 m below the camera and 2.5 m ahead, on the middle of tread 0 of a profile
    ahead = np.cross(np.cross(up, [0.0, 0.0, 1.0]), up)
    pt = -1.5 * up + 2.5 * ahead / np.linalg.norm(ahead)
    d0, h0 = float(pt @ f) - t / 2, float(pt @ up)
    m1 = ray_metric(pt[None], f, up, [0.02], 0.001)
    moved = pt + 2 * 0.02 * pt / pt[2]  # 2 sigmas along its ray
    dist, _ = profile_distance(np.array([moved @ f]), np.array([moved @ up]), r, t, h0, d0, m1)
    assert dist[0] == pytest.approx(2.0, abs=0.1)
    assert abs((moved - pt) @ up) > 0.02  # though it left the tread by more than a sigma
    lifted = pt + 2 * 0.02 * up  # the same 4 cm straight up: farther in sigmas
    dist_up, _ = profile_distance(np.array([lifted @ f]), np.array([lifted @ up]), r, t, h0, d0,
                                  m1)
    assert dist_up[0] > 3.0


def _descending(n=6, rise=0.17, run=0.28, width=1.2, y0=1.2):
    """A flight going down away from the camera, seen from its top landing: treads (their
    risers face away) at n*rise - k*rise, the landing and the floor below as support."""
    top = n * rise
    rects = [Rect((0, y0 - 1.5, top), (1, 0, 0), (0, 1, 0), 2.0, 1.5),
             Rect((0, y0 + n * run + 3.0, 0), (1, 0, 0), (0, 1, 0), 4.0, 3.0)]
    for k in range(1, n + 1):
        y = y0 + (k - 1) * run
        rects.append(Rect((0, y + run / 2, top - k * rise), (1, 0, 0), (0, 1, 0), width / 2,
                          run / 2, 1))
        rects.append(Rect((0, y, top - (k - 0.5) * rise), (1, 0, 0), (0, 0, 1), width / 2,
                          rise / 2, 1))
    return rects


def _descending_view(keep=(0, 1)):
    """The view down the flight with depth noise 2.5 mm z^2 along the rays (2-3.7 m away):
    the flight's pixels unassigned except the rects in ``keep``."""
    cloud, lab, up, _ = render(_descending(), pitch=35.0, cam_height=6 * 0.17 + 1.2,
                               noise=0.0025, seed=3)
    lab = np.where(np.isin(lab, keep), lab, -1).astype(np.int32)
    return cloud, lab, up


def test_a_descending_flight_fits_with_the_noise_along_the_rays_not_an_isotropic_tolerance():
    cloud, lab, up = _descending_view()
    planes = describe_scene(cloud, lab, up=up,
                            curved_params=CurvedParams(stepped_clusters=False)).planes
    sigma = depth_sigma(cloud)
    assert sigma is not None  # the landing and the floor give the noise model
    # measured near the camera and carried to the far treads as z^2: within a factor 1.5
    assert 0.67 < float(sigma(3.5)) / (0.0025 * 3.5 ** 2) < 1.5
    # rays looking down the flight smear its treads along the slope: its plane explains most
    # points within an isotropic tolerance, and that fit is rejected
    assert stepped_cluster_labels(cloud, planes, StairFitParams(ray_noise=False)) is None
    got = stepped_cluster_labels(cloud, planes)
    assert got is not None and len(got[1]) == 1
    out, groups, normals = got
    treads = [k for k in groups[0] if np.allclose(normals[k], up)]
    assert len(treads) >= 3
    # each fitted tread's pixels are on one true tread, the levels a rise apart
    _, truth, _, _ = render(_descending(), pitch=35.0, cam_height=6 * 0.17 + 1.2)
    heights = []
    for k in treads:
        px = truth[out == k]
        assert np.bincount(px[px >= 0]).max() >= 0.9 * len(px)
        heights.append(float(np.median(cloud.xyz[out == k] @ up)))
    steps = np.diff(sorted(heights))
    assert np.all(np.abs(steps / 0.17 - np.round(steps / 0.17)) < 0.2)
    assert np.all(np.round(steps / 0.17) >= 1)


def test_the_near_tread_the_region_grower_found_joins_the_fitted_flight():
    # the first tread (rect 2) segmented on its own, the rest left to the fit
    cloud, lab, up = _descending_view(keep=(0, 1, 2))
    d = describe_scene(cloud, lab, up=up)
    fitted = [p.label for p in d.planes if p.label > 2]
    assert len(fitted) >= 3
    holding = [o for o in d.objects if set(o.planes) & set(fitted)]
    assert len(holding) == 1 and 2 in holding[0].planes
    # without the join the near tread is an object of its own
    lone = describe_scene(cloud, lab, up=up)  # same input, deterministic
    assert [o.planes for o in lone.objects] == [o.planes for o in d.objects]
    from planerel.features.stairfit import remeasure_stepped_clusters

    planes = describe_scene(cloud, lab, up=up,
                            curved_params=CurvedParams(stepped_clusters=False)).planes
    _, flights = remeasure_stepped_clusters(cloud, planes,
                                            params=StairFitParams(join_planes=False))
    assert len(flights) == 1 and 2 not in flights[0]
    _, flights = remeasure_stepped_clusters(cloud, planes)
    assert len(flights) == 1 and 2 in flights[0]


def test_without_a_measurable_noise_model_the_fit_keeps_the_isotropic_tolerance():
    # 24 x 32 pixels: fewer complete 5 x 5 patches than the noise estimate needs
    cloud, _, _, _ = render(_descending(), pitch=35.0, cam_height=6 * 0.17 + 1.2, width=32,
                            height=24, noise=0.0025, seed=3)
    assert depth_sigma(cloud) is None
    # the flight of the 160 x 120 view: measured, and beyond its deepest band it grows as z^2
    big, _, _ = _descending_view()
    sigma = depth_sigma(big)
    from planerel.segment.noise import estimate_noise

    model = estimate_noise(big)
    zb = model.bands[-1][0]
    assert float(sigma(zb)) == pytest.approx(float(model.sigma(zb)))
    assert float(sigma(2 * zb)) == pytest.approx(max(float(model.sigma(2 * zb)),
                                                     4 * float(model.sigma(zb))))


def test_the_new_parameters_are_checked():
    with pytest.raises(InputError):
        StairFitParams(sigmas=0.0)
    with pytest.raises(InputError):
        StairFitParams(noise_floor=-0.01)
    with pytest.raises(InputError):
        StairFitParams(ray_noise="yes")
    with pytest.raises(InputError):
        StairFitParams(join_share=-1.0)


def _one_label(rects, label_of, *, noise=0.003, **kw):
    """Render; rect indices in ``label_of`` get that label, the rest keep theirs (floor 0)."""
    cloud, lab, up, _ = render(rects, width=160, height=120, noise=noise, seed=3, **kw)
    out = np.full(lab.shape, -1, np.int32)
    out[lab == 0] = 0
    for k, v in label_of.items():
        out[lab == k] = v
    return cloud, out, up


def test_a_flight_grown_into_one_sloping_plane_gets_its_treads_and_risers():
    rects = _flight(n=5, y0=2.0)
    cloud, lab, up = _one_label(rects, {k: 5 for k in range(1, len(rects))}, pitch=30.0,
                                cam_height=1.8)
    off = describe_scene(cloud, lab, up=up, curved_params=CurvedParams(stepped_clusters=False))
    assert [p.orientation for p in off.planes if p.label == 5] == ["inclined"]
    d = describe_scene(cloud, lab, up=up)
    assert 5 not in {p.label for p in d.planes}  # replaced by the fitted faces
    new = [p for p in d.planes if p.label > 5]
    kinds = [p.orientation for p in new]
    assert kinds.count("horizontal") >= 2 and kinds.count("vertical") >= 2
    holding = [o for o in d.objects if set(o.planes) & {p.label for p in new}]
    assert len(holding) == 1 and set(holding[0].planes) >= {p.label for p in new}
    # off: the sloping plane stays
    got = stepped_cluster_labels(cloud, off.planes, StairFitParams(inclined_planes=False))
    assert got is None


def test_a_ramp_plane_and_a_boxs_front_and_top_grown_into_one_plane_stay():
    cloud, lab, up = _one_label([floor(size=12.0, y=4.0), *ramp(0.0, 2.2, angle=25.0, length=2.0,
                                                                 width=1.2)], {1: 5},
                                pitch=25.0, cam_height=1.6)
    d = describe_scene(cloud, lab, up=up)
    assert [p.orientation for p in d.planes if p.label == 5] == ["inclined"]
    assert {p.label for p in d.planes} == {0, 5}
    # a box's front, its top and the floor strip before it grown into one sloping plane (as
    # the judge set's i0006) fits a profile of one rise: the floor strip's tread is the floor,
    # which leaves two faces, not a flight
    from scenes_analytic import box

    rects = [floor(size=12.0, y=4.0), *box(0.0, 2.8, 1.0, 0.3, 0.25)[:2],
             Rect((0, 2.53, 0.002), (1, 0, 0), (0, 1, 0), 0.5, 0.12, 1)]
    cloud, lab, up = _one_label(rects, {1: 5, 2: 5, 3: 5}, pitch=25.0, cam_height=1.5)
    d = describe_scene(cloud, lab, up=up, curved_params=CurvedParams(stepped_clusters=False))
    assert [p.orientation for p in d.planes if p.label == 5] == ["inclined"]
    assert stepped_cluster_labels(cloud, d.planes) is None
    assert stepped_cluster_labels(cloud, d.planes, StairFitParams(min_faces=2)) is not None


def test_cross_and_slope_candidates_match_numpy():
    """``_cross`` is ``np.cross`` bit for bit; the kernel ``cluster_slopes`` gives the slopes
    of numpy's per-cluster least squares (``np.bincount`` sums, and ``np.linalg.lstsq`` as the
    rule fits each cluster), and ``_slope_candidates`` never rules out a cluster whose exact
    slope lies in the slope range, and does rule out the clearly flat or steep ones."""
    from planerel.features._stairfit_kernels import cluster_slopes
    from planerel.features.stairfit import _cross, _horizontal_axes, _slope_candidates

    rng = np.random.default_rng(31)
    for _ in range(500):
        a, b = rng.normal(size=3) * rng.uniform(0.01, 10), rng.normal(size=3)
        assert np.array_equal(_cross(a, b), np.cross(a, b))
    lo_hi = (0.25, 1.5)
    ruled_out = 0
    for _ in range(60):
        up = rng.normal(size=3)
        up /= np.linalg.norm(up)
        e1, e2 = _horizontal_axes(up)
        n = int(rng.integers(1, 40))
        sizes = rng.integers(1, 200, n)
        ids = np.repeat(np.arange(n), sizes)
        rng.shuffle(ids)
        u = rng.normal(size=ids.size) * rng.uniform(0.01, 1, n)[ids] + rng.uniform(-3, 3, n)[ids]
        v = rng.normal(size=ids.size) * rng.uniform(0.0, 1, n)[ids] + rng.uniform(-3, 3, n)[ids]
        # slopes around the bounds and far from them; some clusters collinear (v = k u)
        g = rng.choice([0.0, 0.1, 0.25, 0.2500001, 0.7, 1.5, 1.4999999, 3.0], n)
        th = rng.uniform(0, 2 * np.pi, n)
        v = np.where((rng.random(n) < 0.1)[ids], 0.5 * u, v)
        h = (g * np.cos(th))[ids] * u + (g * np.sin(th))[ids] * v + rng.uniform(-1, 1, n)[ids]
        h += rng.normal(size=ids.size) * rng.choice([0.0, 0.01, 0.1], n)[ids]
        pts = np.outer(u, e1) + np.outer(v, e2) + np.outer(h, up)
        got, sure = cluster_slopes(pts, ids, n, e1, e2, up, 1e-6)
        # numpy: the same centred sums by np.bincount
        pu, pv, ph = pts @ e1, pts @ e2, pts @ up
        cnt = np.bincount(ids, minlength=n)
        d = [x - (np.bincount(ids, x, n) / cnt)[ids] for x in (pu, pv, ph)]
        suu, suv, svv, suh, svh = (np.bincount(ids, d[i] * d[j], n)
                                   for i, j in ((0, 0), (0, 1), (1, 1), (0, 2), (1, 2)))
        det = suu * svv - suv * suv
        want_sure = (cnt >= 3) & (det > 0) & (det > 1e-6 * suu * svv)
        assert np.array_equal(sure, want_sure)
        a = (svv * suh - suv * svh)[sure] / det[sure]
        b = (suu * svh - suv * suh)[sure] / det[sure]
        assert np.allclose(got[sure], np.hypot(a, b), rtol=1e-9, atol=1e-12)
        maybe = _slope_candidates(pts, ids, n, e1, e2, up, lo_hi)
        for c in range(n):
            P = pts[ids == c]
            X = np.c_[P @ e1, P @ e2, np.ones(len(P))]
            coef = np.linalg.lstsq(X, P @ up, rcond=None)[0]
            if lo_hi[0] <= float(np.hypot(coef[0], coef[1])) <= lo_hi[1]:
                assert maybe[c]
            ruled_out += not maybe[c]
    assert ruled_out > 300


def test_cluster_spans_and_narrow_clusters_never_rule_out_a_wide_cluster():
    """``cluster_spans`` is numpy's ``hypot`` of the per-cluster ranges along ``e1`` and ``e2``
    (NaN for a cluster holding a point that is not finite), and ``_narrow_clusters`` never
    rules out a cluster that the rule's width test (the range along the lateral axis of its
    fitted slope, numpy's products) would keep, including clusters just below and just above
    ``min_width``."""
    from planerel.features._stairfit_kernels import cluster_spans
    from planerel.features.stairfit import _cross, _horizontal_axes, _narrow_clusters

    rng = np.random.default_rng(47)
    ruled_out = kept_wide = 0
    for trial in range(80):
        up = rng.normal(size=3)
        up /= np.linalg.norm(up)
        e1, e2 = _horizontal_axes(up)
        n = int(rng.integers(1, 30))
        sizes = rng.integers(1, 150, n)
        ids = np.repeat(np.arange(n), sizes)
        rng.shuffle(ids)
        # clusters of reach around min_width (0.5): a line segment of length L (the range along
        # its own direction is exactly its reach), some a blob, at up to 8 m away
        L = rng.choice([0.1, 0.4999, 0.49999999, 0.5, 0.50000001, 0.7, 2.0], n)
        th = rng.uniform(0, 2 * np.pi, n)
        t = rng.uniform(0, 1, ids.size)
        d = np.c_[np.cos(th), np.sin(th)][ids]
        blob = (rng.random(n) < 0.3)[ids]
        off = rng.uniform(-8, 8, (n, 2))[ids]
        uv = off + d * (L[ids] * t)[:, None] + blob[:, None] * rng.normal(size=(ids.size, 2)) * 0.05
        # both ends of every segment present: its reach is L
        for c in range(n):
            k = np.flatnonzero(ids == c)
            uv[k[0]] = off[k[0]]
            uv[k[-1]] = off[k[-1]] + d[k[-1]] * L[c]
        h = rng.uniform(-1, 1, n)[ids] + rng.normal(size=ids.size) * 0.01
        pts = np.outer(uv[:, 0], e1) + np.outer(uv[:, 1], e2) + np.outer(h, up)
        if trial % 10 == 0:
            pts[rng.integers(ids.size)] = np.nan
        got = cluster_spans(pts, ids, n, e1, e2)
        pu, pv = pts @ e1, pts @ e2
        for c in range(n):
            m = ids == c
            if not np.isfinite(pts[m]).all():
                assert np.isnan(got[c])
                continue
            want = np.hypot(pu[m].max() - pu[m].min(), pv[m].max() - pv[m].min())
            assert got[c] == pytest.approx(want, rel=1e-12, abs=1e-12)
        narrow = _narrow_clusters(pts, ids, n, e1, e2, 0.5)
        for c in range(n):
            P = pts[ids == c]
            # the rule's lateral axis for any fitted slope direction: every horizontal one
            for a in np.r_[th[c] + np.pi / 2, rng.uniform(0, 2 * np.pi, 20)]:
                f = np.cos(a) * e1 + np.sin(a) * e2
                lat = P @ _cross(up, f)
                wide = not float(lat.max() - lat.min()) < 0.5
                assert not (wide and narrow[c])
                kept_wide += wide
            ruled_out += bool(narrow[c])
    assert ruled_out > 100 and kept_wide > 100


def test_gather_is_the_fancy_indexing():
    """``_gather`` gives ``xyz[rows, cols]`` (values, dtype, shape) for contiguous and strided
    clouds, NaN points and no pixel."""
    from planerel.features.stairfit import _gather

    rng = np.random.default_rng(5)
    for _ in range(50):
        H, W = (int(v) for v in rng.integers(1, 30, 2))
        xyz = rng.normal(size=(H, 2 * W, 3))
        xyz[rng.random((H, 2 * W)) < 0.2] = np.nan
        for cloud in (np.ascontiguousarray(xyz[:, :W]), xyz[:, ::2]):
            n = int(rng.integers(0, 3 * H * W))
            rows, cols = rng.integers(0, H, n), rng.integers(0, W, n)
            got, want = _gather(cloud, rows, cols), cloud[rows, cols]
            assert got.dtype == want.dtype and got.shape == want.shape
            assert np.array_equal(got, want, equal_nan=True)


def _fits_of(frames):
    """The arguments of every grid search ``fit_profile`` makes on ``frames`` (``(cloud,
    planes)``), with the costs the reference kernel gave."""
    import planerel.features._stairfit_kernels as K
    from planerel.features.stairfit import _stepped_cluster_labels

    calls, real_vec = [], K.profile_costs_vec

    def spy(*args):
        calls.append(args)
        return real_vec(*args)

    K.profile_costs_vec = spy
    try:
        for cloud, planes in frames:
            _stepped_cluster_labels(cloud, planes)
    finally:
        K.profile_costs_vec = real_vec
    return calls


def test_the_vectorised_grid_kernel_is_the_reference_bit_for_bit():
    """profile_costs_vec (float tread index, a vectorised loop into a buffer, then the sum in
    the points' order) against profile_costs: the same array, bytes compared, on random
    points with the isotropic and anisotropic metrics, skewed metrics, points far off the
    profile, ties of truncation, a grid with runs out of range; and on the fits of the
    staircase scenes the stairfit stage makes."""
    from planerel.features._stairfit_kernels import profile_costs, profile_costs_vec
    from planerel.features.stairfit import N_PHASES, RISE_STEP, SLOPE_FACTORS

    rng = np.random.default_rng(58)
    rises = np.arange(0.08, 0.30 + 1e-9, RISE_STEP)
    for t in range(40):
        n = int(rng.choice([1, 2, 7, 100, 400]))
        slope = float(rng.choice([0.2, 0.5, 0.6, 1.0, 2.5]))
        d = rng.uniform(-3.0, 4.0, n) + float(rng.choice([0.0, 50.0, -900.0]))
        h = slope * d + rng.normal(0, float(rng.choice([0.001, 0.05, 0.5])), n)
        if t % 2:
            metric = np.column_stack([rng.uniform(1, 9, n), rng.uniform(-2.9, 2.9, n),
                                      rng.uniform(1, 9, n)])
            trunc2 = np.full(n, float(rng.choice([1.0, 4.0, 1e-30])))
        else:
            metric = np.tile([1.0, 0.0, 1.0], (n, 1))
            trunc2 = rng.uniform(0.01, 0.04, n) ** 2
        args = (d, h, metric, trunc2, rises, SLOPE_FACTORS, N_PHASES, slope, 0.12, 0.60)
        a, b = profile_costs(*args), profile_costs_vec(*args)
        assert a.tobytes() == b.tobytes(), t
    frames = []
    for cloud, lab, up in (_unassigned(_flight(), pitch=10.0, cam_height=1.0),
                           _descending_view(), _descending_view(keep=(0,))):
        frames.append((cloud, describe_scene(
            cloud, lab, up=up, curved_params=CurvedParams(stepped_clusters=False)).planes))
    calls = _fits_of(frames)
    assert len(calls) >= 2
    for args in calls:
        assert profile_costs(*args).tobytes() == profile_costs_vec(*args).tobytes()


def test_fit_profile_keeps_the_reference_kernel_for_far_points():
    """Points beyond VEC_LIMIT (or not finite) are costed by profile_costs only."""
    import planerel.features._stairfit_kernels as K
    from planerel.features.stairfit import VEC_LIMIT

    rng = np.random.default_rng(3)
    d = rng.uniform(2.0, 3.5, 120)
    h = 0.6 * d + rng.normal(0, 0.01, 120)
    assert fit_profile(d, h, np.full(120, 0.02)) is not None
    real_vec = K.profile_costs_vec
    K.profile_costs_vec = None  # calling it would raise
    try:
        for bad in (VEC_LIMIT * 2, np.nan, -np.inf):
            d2 = d.copy()
            d2[0] = bad
            fit_profile(d2, h, np.full(120, 0.02), slope=0.6)
    finally:
        K.profile_costs_vec = real_vec
