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
    fit_profile,
    join_groups,
    profile_distance,
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
    # it is the plane test that tells: the ramp's points fit a staircase too, but their plane
    # better
    assert stepped_cluster_labels(cloud, d.planes, StairFitParams(plane_ratio=2.0)) is not None
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
    cost = profile_costs(d, h, tol, rises, factors, 4, 0.5, 0.12, 0.6)
    for a, r in enumerate(rises):
        for b, f in enumerate(factors):
            s = 0.5 * f
            for j in range(4):
                h0 = j / 4 * r
                d0 = (h0 - r / 2 - (h.mean() - s * d.mean())) / s
                dist, _ = profile_distance(d, h, r, r / s, h0, d0)
                assert cost[a, b, j] == pytest.approx(np.mean(np.minimum(dist, tol) ** 2), rel=1e-9)
    # a run outside the range: no profile
    assert np.isinf(profile_costs(d, h, tol, rises, factors, 4, 0.5, 0.5, 0.6)[0]).all()
