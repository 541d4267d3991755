"""pitch71: no ``ramp`` for a flight's far part seen as one surface (``decision.pitch_gate``).

A flight seen from far shows its near steps as treads and risers and its far part, whose faces
are too small to be planes, as one surface along its nosings: a plane rising the flight's way
at the flight's pitch.  The stairs and the ramp rules both prove such an object, and the ramp
rule's higher precision won (dev_sr i0021).  :func:`planerel.ilp.metrics.pitch_refusals`
refuses ``ramp`` then.  Scenes are ray-cast (tests/scenes_analytic.py), segmented and described
for real; Prolog runs for real (swipl through pyswip).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import pytest

from planerel.errors import InputError
from planerel.ilp import metrics as M

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ramp_model import one_rule_model, rules_text  # noqa: E402
from scenes_analytic import Rect, floor, ramp, render, stairs  # noqa: E402

RISE, RUN, WIDTH, Y0 = 0.17, 0.34, 1.2, 2.0
# the demo model's stairs and ramp clauses, with its statistics: the ramp rule's Laplace
# estimate (74/75) beats the stairs rule's (43/44) when both fire
STATS = [(1, "stairs", 42, 0), (2, "ramp", 73, 0)]
RULES = rules_text("stairs(A) :- has_plane(A,B), parallel(B,C), stair_step(C,B).\n"
                   "ramp(A) :- has_plane(A,B), slope(B,C), area(B,D), gteq(D,0.53), "
                   "lteq(C,28).\n", STATS)


def _far_part(angle=None, length=1.6):
    """Four steps, then a surface rising from the top step's nosing away from the camera at
    ``angle`` degrees (the flight's pitch when None) for ``length`` metres."""
    pitch = math.degrees(math.atan2(RISE, RUN)) if angle is None else angle
    n = 4
    rects = [floor()] + stairs(0.0, Y0, n=n, rise=RISE, run=RUN, width=WIDTH)
    a = math.radians(pitch)
    e2 = (0.0, math.cos(a), math.sin(a))
    # the next step's riser to half its height, the surface rising from its top edge (a
    # convex edge, as a nosing's)
    y, z = Y0 + n * RUN, (n + 0.5) * RISE
    rects.append(Rect((0.0, y, (n + 0.25) * RISE), (1, 0, 0), (0, 0, 1), WIDTH / 2, RISE / 4, 1))
    rects.append(Rect((0.0, y + math.cos(a) * length / 2, z + math.sin(a) * length / 2),
                      (1, 0, 0), e2, WIDTH / 2, length / 2, 1))
    return rects


def _model(path, **decision):
    """The two-rule model; the foot gate off (the far part's low end lies over the floor and
    in view in these scenes: that gate is not the one tested)."""
    return one_rule_model(path, RULES, STATS, foot_gate=False, **decision)


def _answer(model, rects):
    from planerel.classify.classifier import Classifier

    cloud, _lab, up, _objs = render(rects, width=320, height=240, noise=0.0003, pitch=15.0,
                                    cam_height=1.6)
    with Classifier(model) as clf:
        return clf.classify(cloud, up=up, scene_id="s")


def _classes(ans):
    return sorted(o.klass for o in ans.objects if o.klass != "other")


def test_pitch_refusals():
    hits = [("ramp", 2, {"A": "o1", "B": "p3"}, "ramp(A) :- ...", None),
            ("stairs", 1, {"A": "o1", "B": "p4", "C": "p5"}, "stairs(A) :- ...", None)]
    kept, refused = M.pitch_refusals(hits, STATS, {"p3": (26.2, 26.6)}.get, 3.0)
    assert [h[0] for h in kept] == ["stairs"]
    (r,) = refused
    assert (r.klass, r.rule, r.incline, r.pitch) == ("ramp", 2, 26.2, 26.6)
    assert "pitch of the flight" in r.reason and r.to_dict()["pitch"] == 26.6
    # off the pitch, not measured, with no stairs hit, or the gate off: kept
    assert len(M.pitch_refusals(hits, STATS, {"p3": (20.0, 26.6)}.get, 3.0)[0]) == 2
    assert len(M.pitch_refusals(hits, STATS, {}.get, 3.0)[0]) == 2
    assert len(M.pitch_refusals(hits[:1], STATS, {"p3": (26.2, 26.6)}.get, 3.0)[0]) == 1
    assert len(M.pitch_refusals(hits, STATS, None, 3.0)[0]) == 2


def test_a_flights_far_part_is_no_ramp(tmp_path):
    on = _answer(_model(tmp_path / "on"), _far_part())
    (flight,) = [o for o in on.objects if o.klass == "stairs"]
    assert _classes(on) == ["stairs"]
    (r,) = [r for r in flight.refused if isinstance(r, M.PitchRefusal)]
    assert r.klass == "ramp" and abs(r.incline - r.pitch) <= M.PITCH_TOL
    assert r.pitch == pytest.approx(math.degrees(math.atan2(RISE, RUN)), abs=1.0)
    # without the gate the ramp rule's higher precision wins, as before
    off = _answer(_model(tmp_path / "off", pitch_gate=False), _far_part())
    assert _classes(off) == ["ramp"]


def test_a_slope_off_the_flights_pitch_stays_a_ramp(tmp_path):
    # 15 degrees after a flight of 26.6: not its far part
    ans = _answer(_model(tmp_path / "m"), _far_part(angle=15.0))
    assert _classes(ans) == ["ramp"]
    (slope,) = [o for o in ans.objects if o.klass == "ramp"]
    assert ("stairs", 1) in slope.fired  # both rules fire: the gate looked, and kept it
    assert not [r for o in ans.objects for r in o.refused if isinstance(r, M.PitchRefusal)]


def test_a_ramp_alone_stays_a_ramp(tmp_path):
    ans = _answer(_model(tmp_path / "m"),
                  [floor()] + ramp(0.0, Y0, 26.0, 2.0, WIDTH))
    assert _classes(ans) == ["ramp"]


def test_bad_values_are_refused():
    assert M.DecisionParams().pitch_gate is True
    with pytest.raises(InputError, match="pitch_gate"):
        M.DecisionParams(pitch_gate=1)
    for bad in (-1.0, 91.0, float("nan"), True):
        with pytest.raises(InputError, match="pitch_tol"):
            M.DecisionParams(pitch_tol=bad)
