"""benchmarks/box_answers.py (fbox53): every ``box`` answer of the real development frames with
its truth and proof planes, and the measures tried as tests of a false box.  A measuring tool
(docs/objects.md "The false boxes of the development frames against the boxes found: measured,
nothing built (fbox53)"): no relation or gate of the model reads it."""

from __future__ import annotations

import math
import os
import sys
from pathlib import Path

import numpy as np
import pytest
from scenes_analytic import Rect, floor, render

from planerel.features.planes import measure_planes
from planerel.features.relations import Relation, relate

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
import box_answers  # noqa: E402
from test_real_rules import demo_model  # noqa: E402,F401  (the fixture)

HUNT_DATA = Path(os.environ.get("PLANEREL_HUNT_DATA", "/nonexistent"))


def _rel(a, b, angle, skirt=False, adjacent=True):
    return Relation(a, b, angle, angle <= 10, angle >= 80, 0.0, True, adjacent, 0.0, False, False,
                    skirt=skirt)


def test_skirt_fans_pairs_the_skirts_of_one_top_inside_the_proposal():
    pairs = [_rel(1, 2, 90, skirt=True), _rel(1, 3, 90, skirt=True), _rel(1, 4, 90, skirt=True),
             _rel(2, 3, 45.0), _rel(3, 2, 45.0), _rel(2, 4, 88.0), _rel(4, 2, 88.0),
             _rel(3, 4, 43.0), _rel(4, 3, 43.0), _rel(1, 9, 90, skirt=True), _rel(2, 9, 60.0)]
    # plane 9 is no plane of the proposal: its skirt and angle are not read; each pair once
    assert box_answers.skirt_fans(pairs, [1, 2, 3, 4]) == {1: [45.0, 88.0, 43.0]}
    assert box_answers.skirt_fans(pairs, [1, 2]) == {}   # one skirt: nothing to pair
    assert box_answers.beside_angles(pairs, [1, 2, 3], {2}, lambda v: v != 1) == [(2, 3, 45.0)]


def _turned_box(cx, cy, sx, sy, sz, yaw):
    """A box standing on the floor turned ``yaw`` degrees about the vertical: top and 4 sides."""
    c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    ex, ey, z = np.array([c, s, 0.0]), np.array([-s, c, 0.0]), np.array([0.0, 0.0, 1.0])
    o = np.array([cx, cy, 0.0])
    return [Rect(tuple(o + z * sz), tuple(ex), tuple(ey), sx / 2, sy / 2, 1)] + [
        Rect(tuple(o + sign * e * half + z * sz / 2), tuple(other), (0, 0, 1), ohalf, sz / 2, 1)
        for e, half, other, ohalf in ((ey, sy / 2, ex, sx / 2), (ex, sx / 2, ey, sy / 2))
        for sign in (-1, 1)]


def test_a_box_top_s_two_skirts_meet_at_a_right_angle():
    """A 0.4 x 0.3 x 0.3 m box turned 35 degrees, seen from 1.2 m: its top is the top of both
    sides in view, and they meet at 90 degrees (a can's facets meet in between)."""
    cloud, lab, _, _ = render([floor()] + _turned_box(0.0, 1.5, 0.4, 0.3, 0.3, 35.0), noise=0.0012,
                              pitch=30.0, width=640, height=480)
    planes = measure_planes(cloud, lab)
    fans = box_answers.skirt_fans(relate(planes, cloud).pairs, [p.label for p in planes])
    assert len(fans) == 1
    (angles,) = fans.values()
    assert len(angles) == 1 and angles[0] > 85.0


def test_the_cup_s_facets_are_two_skirts_of_its_rim_short_of_a_right_angle(demo_model):  # noqa: F811
    """hunt33 ucn (``$PLANEREL_HUNT_DATA/hunt33/ucn``, NVlabs/UnseenObjectClustering's
    RealSense table-tops): 000008's tapered cup is the set's one false box (skirt: its rim as
    the top, a facet as the skirt); its rim is the top of two facets 73.5 degrees apart.  Every
    right box answer of the set has no two skirts of one top between 20 and 78 degrees (the
    least over 20 on all development frames: 78.7, an rs-booth cube; the false ones 73.5-76.7:
    a margin of 2 degrees, so no gate was built).  The cup is a false box under the up as it
    was then (``gravity.refine_range`` 0): grav53's refinement levels its table and the answer
    goes, so the test pins the old up to keep the measure's case."""
    folder = HUNT_DATA / "hunt33" / "ucn"
    if not (folder / "labels.json").is_file():
        pytest.skip(f"no labelled frames in {folder} (set PLANEREL_HUNT_DATA)")
    from planerel.classify.classifier import Classifier

    with Classifier(str(demo_model), seg_params={"gravity.refine_range": "0"}) as clf:
        rows = list(box_answers.hunt_rows(clf, box_answers._Described(clf), [str(folder)]))
    false = [r for r in rows if r["status"] == "false"]
    assert [r["frame"] for r in false] == ["000008-depth.png"]
    fans = [v for vs in false[0]["skirt_fans"].values() for v in vs]
    assert any(70.0 < v < 77.0 for v in fans), fans
    right = [v for r in rows if r["status"] == "right" for vs in r["skirt_fans"].values()
             for v in vs]
    assert not any(20.0 < v < 78.0 for v in right), right
