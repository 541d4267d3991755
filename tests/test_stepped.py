"""Treads joined into one sloping "plane" come apart (planerel.features.stepped).

Scenes are ray cast from rectangles (tests/scenes_analytic.py) with depth noise along the ray;
the segmentation that joined the treads is imitated by giving all of them one label, so the
test is of the split and the proposal, not of region growing (the Kinect-like frames where
region growing does join them are in benchmarks/bench_stairs_from_above.py).
"""

from __future__ import annotations

import numpy as np
from scenes_analytic import Rect, floor, ramp, render

from planerel.features.facts import describe_scene
from planerel.features.relations import ProposalParams
from planerel.features.stepped import stepped_levels


def _flight_as_one_plane(n=6, rise=0.15, run=0.30, y0=1.0):
    # treads only (a flight seen from above going down: the risers face away), all one label
    rects = [floor()] + [Rect((0.0, y0 + (k + 0.5) * run, (n - k) * rise), (1, 0, 0), (0, 1, 0),
                              0.45, run / 2 - 0.01, 1) for k in range(n)]
    cloud, lab, up, objs = render(rects, pitch=40, cam_height=n * rise + 1.6, width=320,
                                  height=240, noise=0.0015, seed=4)
    lab = np.where(lab > 1, 1, lab).astype(np.int32)
    return cloud, lab, up


def test_levels_of_treads_and_not_of_a_slope():
    rng = np.random.default_rng(0)
    treads = np.concatenate([rng.normal(k * 0.17, 0.006, 300 - 30 * k) for k in range(5)])
    treads = np.concatenate([treads, rng.uniform(0, 0.68, 20)])  # a few flying pixels between
    levels = stepped_levels(treads)
    assert len(levels) == 5
    assert np.allclose([0.5 * (a + b) for a, b in levels], np.arange(5) * 0.17, atol=0.015)
    assert stepped_levels(rng.uniform(0, 0.6, 2000)) == []  # a slope fills its heights
    assert stepped_levels(rng.normal(0, 0.006, 500)) == []  # one tread
    # levels too far apart for a rise (0.45 m): shelves, not treads
    assert stepped_levels(np.concatenate([rng.normal(0, 0.006, 300), rng.normal(0.45, 0.006, 300)])) == []


def test_treads_joined_into_one_sloping_plane_become_one_staircase():
    cloud, lab, up = _flight_as_one_plane()
    off = describe_scene(cloud, lab, up=up, proposal_params=ProposalParams(split_stepped=False))
    assert [p.orientation for p in off.planes if p.label == 1] == ["inclined"]  # a "ramp"
    d = describe_scene(cloud, lab, up=up)
    treads = [p for p in d.planes if not p.is_floor]
    assert len(treads) == 6 and all(p.orientation == "horizontal" for p in treads)
    # one proposal holds them all; the label image the planes refer to has them apart
    assert [set(o.planes) for o in d.objects] == [{p.label for p in treads}]
    assert {int(x) for x in np.unique(d.labels)} == {-1, 0} | {p.label for p in treads}


def test_a_ramp_is_not_split():
    cloud, lab, up, _ = render([floor(), *ramp(0.0, 2.0, angle=12.0, length=2.5)], pitch=35,
                               cam_height=1.5, width=320, height=240, noise=0.0015, seed=2)
    d = describe_scene(cloud, lab, up=up)
    assert len(d.planes) == len(np.unique(lab[lab >= 0]))
    assert np.array_equal(d.labels[lab >= 0], lab[lab >= 0])
