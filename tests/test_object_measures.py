"""measure70: a ``stairs`` answer's flight and a ``ramp`` answer's slope, measured
(``ObjectAnswer.measures``, :mod:`planerel.features.object_measures`; docs/results.md "A
flight's and a slope's measures").

Rendered scenes are ray-cast rectangles with one label each (tests/scenes_analytic.py), so the
truth is known to the millimetre; the classifier runs for real (segmentation, description,
Prolog through pyswip) with a hand-written model.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scenes_analytic import Rect, floor, ramp, render, stairs  # noqa: E402
from test_cut_slant_tread import _flight  # noqa: E402

from planerel.features.facts import describe_scene  # noqa: E402
from planerel.features.object_measures import flight_measures, slope_measures  # noqa: E402

STATS = [(1, "stairs", 42, 0), (2, "ramp", 73, 0)]
RULES = ("stairs(A) :- has_plane(A,B), parallel(B,C), stair_step(C,B).\n"
         "ramp(A) :- has_plane(A,B), slope(B,C), area(B,D), gteq(D,0.53), lteq(C,28).\n"
         + "".join(f"planerel_rule_stats({i}, {k}, {tp}, {fp}).\n" for i, k, tp, fp in STATS))
N, RISE, RUN, WIDTH = 5, 0.17, 0.28, 1.2


@pytest.fixture(scope="module")
def model(tmp_path_factory) -> Path:
    from planerel.ilp.model_settings import training_settings

    path = tmp_path_factory.mktemp("measures_model")
    (path / "rules.pl").write_text(RULES)
    (path / "model.json").write_text(json.dumps(training_settings("regiongrow", {},
                                                                  rule_stats=STATS)))
    return path


def _ascending():
    """A flight of ``N`` steps rising away from a camera 2.2 m up, its foot 1.8 m ahead."""
    return render([floor(), *stairs(0.0, 1.8, N, RISE, RUN, WIDTH)], pitch=35, cam_height=2.2,
                  width=320, height=240, noise=0.001)


def _one(answer, klass):
    found = [o for o in answer.objects if o.klass == klass]
    assert len(found) == 1, [(o.object_id, o.klass) for o in answer.objects]
    return found[0]


def test_an_ascending_flight_is_measured(model):
    from planerel.classify.classifier import Classifier

    cloud, _lab, _up, _objs = _ascending()
    with Classifier(model) as clf:
        ans = clf.classify(cloud)
    m = _one(ans, "stairs").measures
    assert m is not None
    assert m["rise_m"] == pytest.approx(RISE, abs=0.01)
    assert m["run_m"] == pytest.approx(RUN, abs=0.02)
    assert m["going"] == "up"
    assert m["rises_seen"] >= 3 and m["climb_m"] == pytest.approx(m["rises_seen"] * RISE, abs=0.03)
    assert m["width_m"] == pytest.approx(WIDTH, abs=0.1)
    # the nearest riser's foot: 1.8 m ahead of a camera 2.2 m up (some of it below the view)
    assert 2.2 < m["distance_m"] < 3.2
    # in the JSON of the answer too; a box or other answer carries none
    assert _one(ans, "stairs").to_dict()["measures"] == m
    assert all(o.measures is None and "measures" not in o.to_dict()
               for o in ans.objects if o.klass not in ("stairs", "ramp"))


def test_a_pair_two_rises_apart_counts_as_two_steps():
    # the flight's treads with the step pairs as an open-riser row may give them: the second
    # pair skips a tread (walrus-stairs: 0.153 and 0.308 m gave a median "rise" of 0.231)
    cloud, lab, _up, objs = _ascending()
    desc = describe_scene(cloud, lab)
    ps = desc.planes
    treads = sorted((p for p in ps if objs[p.label] == 1 and p.orientation == "horizontal"),
                    key=lambda p: p.height)
    assert len(treads) >= 4
    t = [p.label for p in treads]
    m = flight_measures(ps, t, [(t[0], t[1]), (t[1], t[3])])
    assert m["rise_m"] == pytest.approx(RISE, abs=0.01)
    assert m["run_m"] == pytest.approx(RUN, abs=0.02)
    assert m["rises_seen"] == 3


def test_a_flight_going_down_from_its_landing():
    # the flight turned 25 degrees, seen from its landing: it falls away from the camera
    cloud, lab, _up, objs = _flight(yaw=25)
    d = describe_scene(cloud, lab)
    flight = max(d.objects, key=lambda o: sum(objs[x] == 1 for x in o.planes))
    m = flight_measures(d.planes, flight.planes, d.steps)
    assert m is not None
    assert m["going"] == "down"
    assert m["rise_m"] == pytest.approx(0.19, abs=0.01)
    assert m["run_m"] == pytest.approx(0.30, abs=0.03)


def test_planes_without_a_step_give_no_flight():
    cloud, lab, _up, objs = _ascending()
    d = describe_scene(cloud, lab)
    assert flight_measures(d.planes, [p.label for p in d.planes], ()) is None


@pytest.mark.parametrize("angle, going", [(12.0, "up"), (20.0, "down"), (15.0, "across")])
def test_a_slope_is_measured(model, angle, going):
    from planerel.classify.classifier import Classifier

    a = math.radians(angle)
    if going == "up":
        rects = [floor(), *ramp(0.0, 1.6, angle=angle, length=2.0, width=1.2)]
    elif going == "down":
        # the same slope turned round: rising towards the camera, its foot 3.6 m ahead
        rects = [floor(), Rect((0.0, 3.6 - math.cos(a), math.sin(a)), (1, 0, 0),
                               (0.0, -math.cos(a), math.sin(a)), 0.6, 1.0, 1)]
    else:
        # turned a quarter: rising to the right across the line of sight (a roll ramp)
        rects = [floor(), Rect((-0.2 + math.cos(a), 2.2, math.sin(a)), (0, 1, 0),
                               (math.cos(a), 0.0, math.sin(a)), 0.6, 1.0, 1)]
    cloud, _lab, _up, _objs = render(rects, pitch=35, cam_height=2.0, width=320, height=240,
                                     noise=0.001)
    with Classifier(model) as clf:
        ans = clf.classify(cloud)
    m = _one(ans, "ramp").measures
    assert m is not None
    assert m["slope_deg"] == pytest.approx(angle, abs=1.0)
    assert m["going"] == going
    assert 1.5 < m["length_m"] < 2.1 and m["width_m"] == pytest.approx(1.2, abs=0.15)


def test_a_level_plane_gives_no_slope():
    cloud, lab, _up, _objs = _ascending()
    d = describe_scene(cloud, lab)
    level = next(p for p in d.planes if p.incline < 0.5)
    assert slope_measures(d.planes, level.label) is None or \
        slope_measures(d.planes, level.label)["slope_deg"] < 0.5
    assert slope_measures(d.planes, -7) is None


def test_the_classify_command_prints_the_flight(model, tmp_path):
    cloud, _lab, _up, _objs = _ascending()
    np.save(tmp_path / "flight.npy", np.asarray(cloud.xyz, np.float32))
    out = subprocess.run([sys.executable, "-m", "planerel", "classify", str(model),
                          str(tmp_path / "flight.npy")],
                         capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    line = next(x for x in out.stdout.splitlines() if x.strip().startswith("flight:"))
    assert "going up" in line and "rise 0.17 m" in line


def test_no_finite_hull_point_gives_no_distance():
    # JSON has no NaN: a distance that cannot be measured is None, and the text leaves it out
    from dataclasses import replace

    from planerel.commands.classify import measures_line
    from planerel.features.object_measures import _nearest

    cloud, lab, _up, _objs = _ascending()
    d = describe_scene(cloud, lab)
    p = d.planes[0]
    assert _nearest([replace(p, hull3d=np.full((4, 3), np.nan))], {p.label}) is None
    assert _nearest(d.planes, {p.label}) > 0
    m = {"going": "up", "slope_deg": 10.0, "length_m": 1.0, "width_m": 1.0, "distance_m": None}
    assert measures_line("ramp", m) == "slope: going up, 10.0 degrees, 1.00 x 1.00 m seen"
