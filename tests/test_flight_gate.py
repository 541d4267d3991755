"""pile26: ``stairs`` only for an object whose faces show a staircase's steps.

The demo's stairs rules say "two parallel planes, one above the other" (with more below, or a
level lower one).  On a real RealSense pallet of cartons seen from above (three heights of
merged carton tops), on boxes of two heights touching in the independent judge sets, on a
machine's faces and on a pile in a crowded mOSD frame they proved ``stairs``.  With
``decision.flight_gate`` the decision refuses stairs unless the object's faces make a flight's
regular row (``flight_faces``) or its steps are one flight's (``flight_evidence``: the lowest
a stair's rise and run, every other one, two or three of it).  Prolog runs for real (swipl
through pyswip, and ``prolog_predict``'s own swipl process); scenes are ray-cast and segmented.
"""

from __future__ import annotations

import json
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.features import relations as R
from planerel.ilp import metrics as M

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scenes_analytic import box, floor, render, stairs  # noqa: E402

STATS = [(1, "stairs", 9, 1)]
# a hand-written model: any object of two planes or more is stairs
RULES = ("stairs(A) :- has_plane(A,B), has_plane(A,C), B \\== C.\n"
         + "".join(f"planerel_rule_stats({i}, {k}, {tp}, {fp}).\n" for i, k, tp, fp in STATS))


def _model(path: Path, *, gate=True, recorded=True) -> Path:
    from planerel.ilp.model_settings import training_settings

    path.mkdir(parents=True, exist_ok=True)
    (path / "rules.pl").write_text(RULES)
    data = training_settings("regiongrow", {}, rule_stats=STATS)
    data["decision"]["flight_gate"] = gate
    if not recorded:  # a model.json written before pile26
        del data["decision"]["flight_gate"]
    (path / "model.json").write_text(json.dumps(data))
    return path


def _describe(rects, **view):
    from planerel.features.facts import describe_scene
    from planerel.segment import segment

    cloud, _lab, up, _objs = render(rects, width=640, height=480, noise=0.0003, **view)
    return cloud, up, describe_scene(cloud, segment(cloud).labels, scene_id="s", up=up)


@pytest.fixture(scope="module")
def two_steps():
    """A flight of two steps (rise 0.17 m, run 0.28 m) and no floor in view, seen from 0.9 m
    pitched 45 degrees down: two treads and two risers, no row of three."""
    return _describe(stairs(0.0, 1.0, n=2), pitch=45, cam_height=0.9)


@pytest.fixture(scope="module")
def low_box():
    """A box of 40 x 30 x 25 cm on the floor, its top and two faces in view: no step."""
    return _describe([floor()] + box(0.0, 1.6, 0.4, 0.3, 0.25), pitch=35, cam_height=1.2)


def _answers(model, scene, **kw):
    from planerel.classify.classifier import Classifier

    cloud, up, _desc = scene
    with Classifier(model, **kw) as clf:
        return clf.classify(cloud, up=up, scene_id="s")


def _two(answer):
    (o,) = [o for o in answer.objects if len(o.labels) >= 2]
    return o


# --------------------------------------------------------------------------- the steps


def test_the_steps_of_real_frames():
    """The steps :func:`flight_steps` measured on the real frames (rise, run in metres;
    docs/objects.md, "Carton piles and false answers on unseen frames") and what
    :func:`steps_of_one_flight` says of them."""
    # elmasry's stone flight, two treads and two risers, no floor in view: one flight
    assert R.steps_of_one_flight([(5, 0, 0.145, 0.298), (6, 3, 0.171, 0.234)])
    # the palletizer's pile (pallet_a): 0.10 m from the back row to the front rows and 0.20 m
    # from the back row to the tall carton beside them, whose run is no longer: no flight
    assert not R.steps_of_one_flight([(26, 42, 0.204, 0.299), (27, 42, 0.197, 0.635),
                                      (27, 44, 0.098, 0.269)])
    # pallet_b: the pile and the machine, steps of 0.09-0.31 m on every run
    assert not R.steps_of_one_flight([(19, 39, 0.305, 0.452), (22, 31, 0.206, 0.272),
                                      (23, 31, 0.198, 0.579), (23, 36, 0.098, 0.262),
                                      (23, 39, 0.091, 0.413), (36, 31, 0.1, 0.382)])
    # conf22 i0038, boxes of two heights touching: one step 0.30 m high, 0.67 m deep
    assert not R.steps_of_one_flight([(4, 1, 0.301, 0.668)])
    # mOSD test49, a pile of boxes on a table: 7 cm, under a stair's rise
    assert not R.steps_of_one_flight([(16, 4, 0.073, 0.337)])
    # tune21 i0051, a three-step flight seen from 4 m: one step seen
    assert R.steps_of_one_flight([(10, 7, 0.133, 0.319)])
    # a flight seen whole: one-rise steps and two-rise pairs (the same pitch)
    assert R.steps_of_one_flight([(9, 3, 0.109, 0.281), (13, 3, 0.199, 0.552),
                                  (13, 9, 0.09, 0.271), (22, 9, 0.194, 0.545)])
    assert not R.steps_of_one_flight([])


def test_two_steps_without_a_row_are_a_flight(two_steps):
    _cloud, _up, desc = two_steps
    (o,) = [o for o in desc.objects if len(o.planes) >= 3]
    steps = R.flight_steps(desc.planes, o.planes)
    assert not R.flight_faces(desc.planes, o.planes)
    assert [(round(r, 2), round(g, 2)) for _a, _b, r, g in steps] == [(0.17, 0.28)]
    assert R.flight_evidence(desc.planes, o.planes)


def test_a_pile_of_three_heights_is_no_flight():
    """Cartons packed as the real pallet's: a row 0.36 m high before a block 0.46 m high and a
    carton 0.56 m high beside it (all touching), seen from 1.6 m pitched 60 degrees down.
    Its planes hold three steps of two rises on runs that do not grow with them."""
    y0 = 0.8
    pile = (box(0.0, y0 + 0.1, 0.9, 0.2, 0.36) + box(0.15, y0 + 0.4, 0.6, 0.4, 0.46)
            + box(-0.3, y0 + 0.4, 0.3, 0.4, 0.56))
    _cloud, _up, desc = _describe([floor()] + pile, pitch=60, cam_height=1.6)
    planes = sorted({lab for o in desc.objects if len(o.planes) >= 2 for lab in o.planes})
    tops = sorted(round(p.height, 2) for p in desc.planes
                  if p.label in planes and p.orientation == "horizontal")
    assert tops == [0.36, 0.46, 0.56]
    steps = R.flight_steps(desc.planes, planes)
    assert sorted(round(r, 1) for _a, _b, r, _g in steps) == [0.1, 0.1, 0.2]
    assert not R.flight_faces(desc.planes, planes)
    assert not R.flight_evidence(desc.planes, planes)


def test_a_box_has_no_step(low_box):
    _cloud, _up, desc = low_box
    (o,) = [o for o in desc.objects if len(o.planes) >= 2]
    assert R.flight_steps(desc.planes, o.planes) == []
    assert not R.flight_evidence(desc.planes, o.planes)


# --------------------------------------------------------------------------- the decision


def test_stairs_is_refused_for_a_box_and_kept_for_two_steps(tmp_path, low_box, two_steps):
    model = _model(tmp_path / "m")
    o = _two(_answers(model, low_box))
    assert o.klass == "other" and ("stairs", 1) in o.fired
    (r,) = o.refused
    assert isinstance(r, M.FlightRefusal) and r.klass == "stairs"
    assert o.to_dict()["refused"] == [{"class": "stairs", "reason": r.reason}]
    assert "no steps of one flight's rise and run" in r.reason
    (f,) = [o for o in _answers(model, two_steps).objects if len(o.labels) >= 3]
    assert f.klass == "stairs" and f.refused == ()


@pytest.mark.parametrize("how", ["model.json before pile26", "gate off", "param off"])
def test_without_the_gate_the_rule_decides(tmp_path, low_box, how):
    kw = {"seg_params": {"decision.flight_gate": "false"}} if how == "param off" else {}
    model = _model(tmp_path / "m", gate=how != "gate off",
                   recorded=how != "model.json before pile26")
    o = _two(_answers(model, low_box, **kw))
    assert o.klass == "stairs" and o.refused == ()


def test_the_param_turns_it_on_for_an_old_model(tmp_path, low_box):
    model = _model(tmp_path / "m", recorded=False)
    o = _two(_answers(model, low_box, seg_params={"decision.flight_gate": "true"}))
    assert o.klass == "other" and [r.klass for r in o.refused] == ["stairs"]


def test_prolog_predict_decides_with_the_same_gate(low_box, two_steps):
    from planerel.ilp import pipeline as P

    model = P.Model(("stairs",), {"stairs": (RULES.splitlines()[0],)}, stats=tuple(STATS))
    assert model.flight_gate
    for scene, want in ((low_box, "other"), (two_steps, "stairs")):
        _cloud, _up, desc = scene
        ids = [o.id for o in desc.objects if len(o.planes) >= 2]
        on = {p.object_id: p for p in P.prolog_predict(model, [desc], ids)}
        off = {p.object_id: p for p in P.prolog_predict(replace(model, flight_gate=False),
                                                          [desc], ids)}
        big = max(ids, key=lambda i: len(next(o for o in desc.objects if o.id == i).planes))
        assert on[big].klass == want and off[big].klass == "stairs"


def test_refusals_without_prolog():
    stats = [(1, "box", 9, 1), (2, "stairs", 9, 1), (3, "stairs", 1, 1)]
    hits = [("box", 1, {}, ""), ("stairs", 2, {}, "")]
    assert M.flight_refusals(hits, stats, None) == (hits, ())
    assert M.flight_refusals(hits, stats, True) == (hits, ())
    asked = []
    assert M.flight_refusals(hits[:1], stats, lambda: asked.append(1)) == (hits[:1], ())
    assert asked == []  # no stairs hit: the planes are not looked at
    kept, refused = M.flight_refusals(hits, stats, lambda: False)
    assert kept == hits[:1] and refused == (M.FlightRefusal("stairs"),)
    # a stairs rule that takes no part in the decision (precision <= 0.5): refused silently
    assert M.flight_refusals([("stairs", 3, {}, "")], stats, False) == ([], ())
    best, why = M.decide(hits, stats, ["box", "stairs"], flight=False)
    assert best == hits[0] and why == (M.FlightRefusal("stairs"),)
    assert M.decide(hits, stats, ["box", "stairs"])[1] == ()  # default: off


def test_the_setting():
    assert M.FLIGHT_GATE is M.DecisionParams().flight_gate is True
    with pytest.raises(InputError, match="flight_gate must be true or false"):
        M.DecisionParams(flight_gate="on")


# --------------------------------------------------------------------------- fragments (flight48)


@pytest.fixture(scope="module")
def fragmented_flight():
    """A flight of three steps (rise 0.17 m, run 0.28 m) seen from 0.9 m pitched 55 degrees
    down, its first riser 0.9 m ahead: the image's top row cuts the second riser a few
    centimetres over its foot (the varied world's 160x120 flights so, accept45).  The planes
    of every proposal: the first riser, the first tread, a strip of the second riser."""
    from scenes_analytic import stairs as flight

    _cloud, _up, desc = _describe([floor()] + flight(0.0, 0.9, n=3), pitch=55, cam_height=0.9)
    return desc, sorted({lab for o in desc.objects for lab in o.planes})


def test_a_flight_seen_in_fragments_shows_its_steps(fragmented_flight):
    desc, planes = fragmented_flight
    kinds = sorted(desc.planes.by_label(lab).orientation for lab in planes)
    assert kinds == ["horizontal", "vertical", "vertical"]
    # one tread, and the risers' areas differ more than 3 times: no step of whole faces
    assert R.flight_steps(desc.planes, planes) == []
    assert not R.flight_evidence(desc.planes, planes, fragments=False)
    # the strip stands on the first riser's top edge: one step of the flight's rise and run
    ((lo, hi, rise, run),) = R.stacked_riser_steps(desc.planes, planes)
    assert desc.planes.by_label(lo).height < desc.planes.by_label(hi).height
    assert rise == pytest.approx(0.17, abs=0.01) and run == pytest.approx(0.28, abs=0.01)
    assert R.flight_fragments(desc.planes, planes)
    assert R.flight_evidence(desc.planes, planes)


def test_a_pile_of_two_heights_is_still_no_flight():
    """A carton 0.25 m high and 0.3 m deep before one 0.55 m high (touching), seen from 1.2 m
    pitched 35 degrees down: the back carton's face is seen from the front one's top up,
    0.30 m of it, more than a rise (0.25 m) over its foot: no stacked riser; the tops 0.30 m
    apart are no stair's rise either."""
    pile = box(0.0, 1.15, 0.6, 0.3, 0.25) + box(0.0, 1.5, 0.6, 0.4, 0.55)
    _cloud, _up, desc = _describe([floor()] + pile, pitch=35, cam_height=1.2)
    (o,) = [o for o in desc.objects if len(o.planes) >= 2]
    assert sorted(round(desc.planes.by_label(lab).height, 2) for lab in o.planes
                  if desc.planes.by_label(lab).orientation == "horizontal") == [0.25, 0.55]
    assert R.stacked_riser_steps(desc.planes, o.planes) == []
    assert not R.flight_fragments(desc.planes, o.planes)
    assert not R.flight_evidence(desc.planes, o.planes)


def test_stacked_risers_ask_a_stair_and_a_foot_on_the_top_edge():
    """:func:`stacked_riser_steps` on hand-made planes: two risers of 1.0 and 0.2 m width."""
    from planerel.features.planes import PlaneSet

    def riser(label, y, z0, z1, x0=-0.5, x1=0.5):
        return _vertical(label, y, z0, z1, x0, x1)

    def steps(*planes):
        ps = PlaneSet(tuple(planes), np.array([0.0, 0.0, 1.0]), "given", None, 0.0)
        return R.stacked_riser_steps(ps, [p.label for p in planes])

    low = riser(1, 1.0, 0.0, 0.17)
    ((_a, _b, rise, run),) = steps(low, riser(2, 1.28, 0.17, 0.22, 0.1, 0.3))
    assert (round(rise, 2), round(run, 2)) == (0.17, 0.28)
    assert steps(low, riser(2, 1.28, 0.0, 0.34, 0.1, 0.3)) == []    # a face from the floor
    assert steps(low, riser(2, 1.28, 0.21, 0.3, 0.1, 0.3)) == []    # its foot over the top edge
    assert steps(low, riser(2, 1.28, 0.17, 0.40, 0.1, 0.3)) == []   # taller than a rise
    assert steps(low, riser(2, 1.70, 0.17, 0.34, 0.1, 0.3)) == []   # 0.70 m on: no stair's run
    assert steps(low, riser(2, 1.28, 0.17, 0.34, 0.6, 0.9)) == []   # beside it, not above
    assert steps(riser(1, 1.0, 0.0, 0.05), riser(2, 1.28, 0.05, 0.1)) == []  # 5 cm: no rise


def _vertical(label, y, z0, z1, x0, x1):
    """A plane facing -y at ``y``, ``x0..x1`` wide and ``z0..z1`` high (z up, floor at 0)."""
    from planerel.features.planes import Plane

    hull3d = np.array([[x0, y, z0], [x1, y, z0], [x1, y, z1], [x0, y, z1]], float)
    c = hull3d.mean(0)
    return Plane(label=label, n_points=100, normal=np.array([0.0, -1.0, 0.0]), offset=-y,
                 centroid=c, rms=0.001, axes=np.array([[1.0, 0, 0], [0, 0, 1.0]]),
                 hull=np.array([[x0, z0], [x1, z0], [x1, z1], [x0, z1]]) - [c[0], c[2]],
                 hull3d=hull3d, area=(x1 - x0) * (z1 - z0), length=max(x1 - x0, z1 - z0),
                 width=min(x1 - x0, z1 - z0), incline=90.0, orientation="vertical",
                 height=float(c[2]), distance=float(np.linalg.norm(c)), bbox=(0, 0, 10, 10))


def test_the_fragments_setting(tmp_path, low_box):
    assert M.FLIGHT_FRAGMENTS is M.DecisionParams().flight_fragments is True
    with pytest.raises(InputError, match="flight_fragments must be true or false"):
        M.DecisionParams(flight_fragments="on")
    from planerel.classify.classifier import Classifier
    from planerel.ilp import pipeline as P

    model = _model(tmp_path / "m")
    with Classifier(model) as clf:
        assert clf.flight_gate and clf.flight_fragments
    with Classifier(model, seg_params={"decision.flight_fragments": "false"}) as clf:
        assert clf.flight_gate and not clf.flight_fragments
    assert P.Model(("stairs",), {}).flight_fragments
