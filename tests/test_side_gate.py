"""ramp44: ``ramp`` only for a slope the camera sees from above (``decision.side_gate``).

A ramp is walked on: its walked-on side faces up, and a camera sees that side only from above
the ramp's plane.  A camera near the floor sees the undersides of tables, beds and shelves, and
(a Kinect at grazing incidence) often no floor at all, so the foot gate, which needs a floor,
cannot refuse them.  :func:`planerel.ilp.metrics.side_refusals` refuses ``ramp`` when every
sloping proof plane is seen from below.  Scenes are ray-cast (tests/scenes_analytic.py),
segmented and described for real; Prolog runs for real (swipl through pyswip).
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from planerel.errors import InputError
from planerel.ilp import metrics as M

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ramp_model import ramp_model as _model  # noqa: E402
from ramp_model import stairs_model  # noqa: E402
from scenes_analytic import Rect, floor, ramp, render, stairs  # noqa: E402


def _ramps(model, rects, **view):
    from planerel.classify.classifier import Classifier

    cloud, _lab, up, _objs = render(rects, width=320, height=240, noise=0.0003, **view)
    with Classifier(model) as clf:
        ans = clf.classify(cloud, up=up, scene_id="s")
    return ans, [o for o in ans.objects if o.klass == "ramp"]


def _underside(lift=0.7, angle=10.0):
    """A board 1.5 x 1.2 m tilted by ``angle`` degrees, its low edge ``lift`` metres up, 1.6 m
    ahead: seen from a camera 0.15 m over the floor, its underside (no floor in the scene: a
    Kinect this low returns none)."""
    (r,) = ramp(0.0, 1.6, angle, 1.5, 1.2)
    x, y, z = r.center
    return [Rect((x, y, z + lift), r.e1, r.e2, r.a, r.b, r.obj)]


LOW = {"pitch": 0.0, "cam_height": 0.15}


def test_side_refusals():
    hits = [("ramp", 1, {"A": "o1", "B": "p3"}, "ramp(A) :- ...", None),
            ("box", 2, {"A": "o1", "B": "p4"}, "box(A) :- ...", None)]
    stats = [(1, "ramp", 73, 0), (2, "box", 9, 1)]
    kept, refused = M.side_refusals(hits, stats, {"p3": ("inclined", -0.97)}.get)
    assert [h[0] for h in kept] == ["box"]
    (r,) = refused
    assert (r.klass, r.rule, r.facing) == ("ramp", 1, -0.97) and "from below" in r.reason
    assert r.to_dict()["facing"] == -0.97
    # seen from above, not measured, not inclined, or the gate off: kept
    assert len(M.side_refusals(hits, stats, {"p3": ("inclined", 0.95)}.get)[0]) == 2
    assert len(M.side_refusals(hits, stats, {}.get)[0]) == 2
    assert len(M.side_refusals(hits, stats, {"p3": ("horizontal", -1.0)}.get)[0]) == 2
    assert len(M.side_refusals(hits, stats, None)[0]) == 2
    # one proof plane seen from above is enough
    two = [("ramp", 1, {"A": "o1", "B": "p3", "C": "p5"}, "ramp(A) :- ...", None)]
    assert len(M.side_refusals(two, stats, {"p3": ("inclined", -0.97),
                                            "p5": ("inclined", 0.9)}.get)[0]) == 1


def test_side_refusals_of_stairs():
    """A flight's treads are walked on: level planes all seen from below (a ceiling's
    terraces, a shelf's boards seen from under them) are no treads; a riser (vertical) says
    nothing, and one tread seen from above keeps the answer."""
    stats = [(5, "stairs", 40, 1)]
    hit = [("stairs", 5, {"A": "o1", "B": "p1", "C": "p2", "D": "p3"}, "stairs(A) :- ...",
            None)]
    under = {"p1": ("horizontal", -0.99), "p2": ("horizontal", -0.98), "p3": ("vertical", 0.0)}
    kept, refused = M.side_refusals(hit, stats, under.get)
    assert kept == [] and refused[0].klass == "stairs" and refused[0].facing == -0.98
    assert "treads" in refused[0].reason
    above = dict(under, p2=("horizontal", 0.99))
    assert M.side_refusals(hit, stats, above.get)[0] == hit
    # an inclined plane seen from below is the ramp's business, not the flight's
    slope = {"p1": ("inclined", -0.9), "p2": ("vertical", 0.0)}
    assert M.side_refusals(hit, stats, slope.get)[0] == hit
    # riser73: an object reaching under the camera's eye (a flight rising before a low
    # robot: its lower risers under the eye, the stair fit's level pieces on the upper risers'
    # edges seen from below) keeps the answer; a ramp is judged as before
    assert M.side_refusals(hit, stats, under.get, under_eye=True)[0] == []  # treads in the proof
    risers = {"p1": ("vertical", 0.0), "p2": ("vertical", 0.01)}
    hit2 = [("stairs", 5, {"A": "o1", "B": "p1", "C": "p2"}, "stairs(A) :- ...", None)]
    assert M.side_refusals(hit2, stats, risers.get, treads=[-1.0], under_eye=True)[0] == hit2
    assert M.side_refusals(hit2, stats, risers.get, treads=[-1.0])[0] == []
    ramp_hit = [("ramp", 1, {"A": "o1", "B": "p3"}, "ramp(A) :- ...", None)]
    assert M.side_refusals(ramp_hit, [(1, "ramp", 73, 0)], {"p3": ("inclined", -0.97)}.get,
                           under_eye=True)[0] == []


def test_decision_settings_are_checked():
    assert M.DecisionParams().side_gate is True
    with pytest.raises(InputError, match="side_gate"):
        M.DecisionParams(side_gate=1)


def test_an_underside_seen_from_a_low_camera_is_no_ramp(tmp_path):
    rects = _underside()
    ans, ramps = _ramps(_model(tmp_path / "m"), rects, **LOW)
    assert not ramps
    refused = [r for o in ans.objects for r in o.refused if isinstance(r, M.SideRefusal)]
    assert len(refused) == 1 and refused[0].facing < -0.9
    # the gate off: the underside is a ramp (no floor, so the foot gate says nothing)
    _ans, ramps = _ramps(_model(tmp_path / "off", side_gate=False), rects, **LOW)
    assert len(ramps) == 1


@pytest.mark.parametrize("view", [LOW, {"pitch": 30.0, "cam_height": 1.4}])
def test_a_ramp_seen_from_a_low_or_a_high_camera_stays(tmp_path, view):
    _ans, ramps = _ramps(_model(tmp_path / "m"), [floor()] + ramp(0.0, 1.6, 15.0, 1.5, 1.0),
                         **view)
    assert len(ramps) == 1


def _flights(model, rects, **view):
    from planerel.classify.classifier import Classifier

    cloud, _lab, up, _objs = render(rects, width=320, height=240, noise=0.0003, **view)
    with Classifier(model) as clf:
        ans = clf.classify(cloud, up=up, scene_id="s")
    return ans, [o for o in ans.objects if o.klass == "stairs"]


def _stepped_ceiling(height=2.4):
    """A flight of four steps mirrored into a ceiling ``height`` m up: level strips and
    risers seen from below (what a camera 0.1 m over the floor made of a ceiling's
    disparity terraces, hunt45); the rule binds the risers only."""
    return [Rect((r.center[0], r.center[1], height - r.center[2]), r.e1, r.e2, r.a, r.b, r.obj)
            for r in stairs(0.0, 1.2, n=4, width=1.6)] + [floor()]


def test_a_stepped_ceiling_is_no_flight(tmp_path):
    view = {"pitch": -20.0, "cam_height": 0.3}
    ans, flights = _flights(stairs_model(tmp_path / "m"), _stepped_ceiling(), **view)
    assert not flights
    (r,) = [r for o in ans.objects for r in o.refused if isinstance(r, M.SideRefusal)]
    assert r.klass == "stairs" and r.facing < -0.9 and "treads" in r.reason
    _ans, flights = _flights(stairs_model(tmp_path / "off", side_gate=False),
                             _stepped_ceiling(), **view)
    assert len(flights) == 1


@pytest.mark.parametrize("view", [{"pitch": 10.0, "cam_height": 0.3},
                                  {"pitch": 35.0, "cam_height": 1.5}])
def test_a_flight_seen_from_a_low_or_a_high_camera_stays(tmp_path, view):
    _ans, flights = _flights(stairs_model(tmp_path / "m"),
                             [floor()] + stairs(0.0, 1.4, n=4, width=1.6), **view)
    assert len(flights) == 1


def test_a_flight_rising_over_a_low_cameras_eye_stays(tmp_path):
    """riser73: eight steps rising 1.5 m before a camera 0.3 m up, looking level, depth noise
    0.002 z^2.  Its lower risers lie under the eye; over it the stair fit puts level pieces on
    the risers' top edges, seen from below, which made the side gate refuse the flight (it
    did with this scene before ``under_eye``; measured with ``classifier._under_eye``
    patched to False).  The stepped ceiling, wholly over the eye, is still refused
    (:func:`test_a_stepped_ceiling_is_no_flight`)."""
    from planerel.classify.classifier import Classifier

    rects = [floor(size=12.0, y=4.0)] + stairs(0.0, 2.0, n=8, rise=0.19, run=0.28, width=1.4)
    cloud, _lab, up, _objs = render(rects, width=320, height=240, noise=0.002, pitch=0.0,
                                    cam_height=0.3, seed=3)
    with Classifier(stairs_model(tmp_path / "m")) as clf:
        ans = clf.classify(cloud, up=up, scene_id="s")
    assert sum(o.klass == "stairs" for o in ans.objects) == 1
    assert not [r for o in ans.objects for r in o.refused if isinstance(r, M.SideRefusal)]
