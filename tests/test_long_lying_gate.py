"""fbox58: a top seen alone (its sides unseen) longer than a lying box's is no box: a keyboard
on a desk, a desk's foot bar on the floor, a floor strip (``decision.long_lying_gate``;
docs/objects.md "hunt58: rooms, labs and offices nobody had tuned on; false boxes of lying
tops (fbox58)").

Rendered scenes are ray-cast rectangles with one label each (tests/scenes_analytic.py); Prolog
runs for real (swipl through pyswip).  With ``PLANEREL_HUNT_DATA`` (the folder holding the
development hunts, e.g. ``/work``) the gate is checked on the real frames it was measured on,
with the demo's model.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

from planerel.errors import InputError
from planerel.ilp import metrics as M

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ramp_model import answer_holding, one_rule_model, rules_text  # noqa: E402
from scenes_analytic import Rect, floor, render  # noqa: E402
from test_real_rules import demo_model  # noqa: E402,F401  (the fixture)

STATS = [(1, "box", 40, 4)]
RULES = rules_text("box(A) :- has_plane(A,B), oblique_share(A,C), lying(B), lteq(C,0.02).\n", STATS)
THING = 1


def _model(path: Path, *, gate=True) -> Path:
    return one_rule_model(path, RULES, STATS, long_lying_gate=gate)


def _scene(length):
    """``(cloud, up, labels, object of each label)``: the top of a flat thing ``length`` x
    0.15 m lying 4 cm over the floor 1.2 m ahead of a camera 1.0 m up looking 45 degrees
    down (its sides left out: seen edge-on, as a keyboard's or a book's)."""
    rects = [floor(), Rect((0.0, 1.2, 0.04), (1, 0, 0), (0, 1, 0), length / 2, 0.075, THING)]
    cloud, lab, up, objs = render(rects, pitch=45, cam_height=1.0, width=320, height=240,
                                  noise=0.001)
    return cloud, up, lab, objs


def _answer(model, scene, **kw):
    """The answer of the proposal holding most of the top's pixels."""
    return answer_holding(model, scene, THING, **kw)


def test_a_long_top_alone_is_no_box(tmp_path):
    o = _answer(_model(tmp_path / "m"), _scene(0.5))
    assert o.klass == "other"
    why = [r for r in o.refused if isinstance(r, M.LongLyingRefusal)]
    assert len(why) == 1 and why[0].klass == "box" and why[0].rule == 1
    assert why[0].length == pytest.approx(0.5, abs=0.03) and why[0].bound == 0.4
    assert "alone" in why[0].reason and why[0].to_dict()["top"]
    # with the gate off it is a box, as before fbox58
    assert _answer(_model(tmp_path / "off", gate=False), _scene(0.5)).klass == "box"


def test_a_book_size_top_stays_a_box(tmp_path):
    o = _answer(_model(tmp_path / "m"), _scene(0.25))
    assert o.klass == "box"
    assert not any(isinstance(r, M.LongLyingRefusal) for r in o.refused)


def test_the_bound_is_a_setting(tmp_path):
    o = _answer(_model(tmp_path / "m"), _scene(0.5),
                seg_params={"decision.long_lying_length": "0.6"})
    assert o.klass == "box"


def test_decision_params():
    p = M.DecisionParams()
    assert p.long_lying_gate is True and p.long_lying_length == 0.4
    with pytest.raises(InputError):
        M.DecisionParams(long_lying_gate="yes")
    with pytest.raises(InputError):
        M.DecisionParams(long_lying_length=-0.1)


HUNT = Path(os.environ.get("PLANEREL_HUNT_DATA", "/nonexistent"))


@pytest.mark.skipif(not (HUNT / "hunt58" / "gg-tum-desk").is_dir(),
                    reason="PLANEREL_HUNT_DATA not set")
def test_the_development_desk(demo_model):  # noqa: F811
    """gg-tum-desk's keyboard (depth1) and the desk's foot bar (depth2) were false boxes:
    refused; the monitor's foot (16 cm) and the book lying flat (its sides seen) keep their
    answers."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from real_unseen import read_frame, read_labels

    from planerel.classify.classifier import Classifier

    folder = HUNT / "hunt58" / "gg-tum-desk"
    for frame in read_labels(str(folder))["frames"]:
        cloud, up = read_frame(str(folder), frame)
        with Classifier(str(demo_model)) as clf:
            ans = clf.classify(cloud, up=up)
        long = [r for o in ans.objects for r in o.refused
                if isinstance(r, M.LongLyingRefusal)]
        assert len(long) == 1 and 0.45 < long[0].length < 0.6, frame["file"]
        assert sum(o.klass == "box" for o in ans.objects) == {"depth1.png": 2,
                                                               "depth2.png": 1}[frame["file"]]
