"""fbox59: an upright face far taller than it is wide is no box's side: a wall's end, a post,
a furniture side seen edge-on (``decision.narrow_face_gate``; docs/objects.md "Faces far
taller than wide are no box's (fbox59)").

Rendered scenes are ray-cast rectangles with one label each (tests/scenes_analytic.py); Prolog
runs for real (swipl through pyswip).  With ``PLANEREL_HUNT_DATA`` (the folder holding the
development hunts, e.g. ``/work``) the gate is checked on the real frame it was measured on,
with the demo's model.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.ilp import metrics as M

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ramp_model import answer_holding, one_rule_model, rules_text  # noqa: E402
from scenes_analytic import box, floor, render  # noqa: E402
from test_real_rules import demo_model  # noqa: E402,F401  (the fixture)

STATS = [(1, "box", 40, 4)]
RULES = rules_text("box(A) :- has_plane(A,B), nhorizontal(A,0), tall_face(B).\n", STATS)
THING = 1


def _model(path: Path, *, gate=True) -> Path:
    return one_rule_model(path, RULES, STATS, narrow_face_gate=gate)


def _scene(width, height):
    """``(cloud, up, labels, object of each label)``: a solid ``width`` m wide and 0.3 m deep,
    ``height`` m tall, standing on the floor 1.5 m ahead of a camera 0.5 m up looking level
    (its top over the camera's eye: a box seen as one face)."""
    rects = [floor(), *box(0.0, 1.65, width, 0.3, height, obj=THING)]
    cloud, lab, up, objs = render(rects, pitch=0, cam_height=0.5, width=320, height=240,
                                  noise=0.001)
    return cloud, up, lab, objs


def _answer(model, scene, **kw):
    """The answer of the proposal holding most of the solid's pixels."""
    return answer_holding(model, scene, THING, **kw)


def test_a_post_is_no_box(tmp_path):
    """A 0.1 m wide, 0.9 m tall front (9 times as tall as wide): refused; a box with the gate
    off, as before fbox59."""
    o = _answer(_model(tmp_path / "m"), _scene(0.1, 0.9))
    assert o.klass == "other"
    why = [r for r in o.refused if isinstance(r, M.NarrowFaceRefusal)]
    assert len(why) == 1 and why[0].klass == "box" and why[0].rule == 1
    assert why[0].ratio == pytest.approx(9.0, rel=0.15) and why[0].bound == 6.5
    assert "wide" in why[0].reason and why[0].to_dict()["faces"]
    assert _answer(_model(tmp_path / "off", gate=False), _scene(0.1, 0.9)).klass == "box"


def test_a_tall_box_stays_a_box(tmp_path):
    """A 0.25 m wide, 0.9 m tall front (3.6 times): a box."""
    o = _answer(_model(tmp_path / "m"), _scene(0.25, 0.9))
    assert o.klass == "box"
    assert not any(isinstance(r, M.NarrowFaceRefusal) for r in o.refused)


def test_the_bound_is_a_setting(tmp_path):
    o = _answer(_model(tmp_path / "m"), _scene(0.1, 0.9),
                seg_params={"decision.narrow_face_ratio": "12"})
    assert o.klass == "box"


def test_face_extent_and_the_image_border():
    """The measure on a made face: a vertical plane 0.9 m tall and 0.1 m wide 2 m ahead; the
    same pixels moved to the image's left column, or with a nearer surface just beyond an end,
are cut (the width a lower bound)."""
    from types import SimpleNamespace

    from planerel.features.face_shape import face_extent

    H, W = 120, 160
    up = np.array([0.0, -1.0, 0.0])   # camera y points down
    rows, cols = np.mgrid[0:90, 0:10]
    xyz = np.full((H, W, 3), np.nan)
    lab = np.full((H, W), -1)

    def place(c0):
        xyz[:] = np.nan
        lab[:] = -1
        xyz[10 + rows, c0 + cols] = np.stack([cols * 0.01, 0.45 - rows * 0.01,
                                              np.full(rows.shape, 2.0)], axis=-1)
        lab[10 + rows, c0 + cols] = 7

    face = SimpleNamespace(label=7, normal=(0.0, 0.0, -1.0))
    place(70)
    e = face_extent(face, up, xyz, lab)
    assert e.height == pytest.approx(0.87, abs=0.02)
    assert e.width == pytest.approx(0.09, abs=0.01)
    assert not e.cut and e.ratio == pytest.approx(e.height / e.width) and e.ratio > 6.5
    # a nearer surface just beyond its right end (a tall box partly behind a nearer one):
    # its width is a lower bound; a farther one (what lies behind) is not
    for z, hidden in ((1.5, True), (2.6, False)):
        xyz[10 + rows, 80 + cols] = np.stack([0.1 + cols * 0.01, 0.45 - rows * 0.01,
                                              np.full(rows.shape, z)], axis=-1)
        lab[10 + rows, 80 + cols] = 9
        assert face_extent(face, up, xyz, lab).cut is hidden
    place(0)
    assert face_extent(face, up, xyz, lab).cut
    assert face_extent(SimpleNamespace(label=8, normal=(0.0, 0.0, -1.0)), up, xyz, lab) is None
    assert face_extent(SimpleNamespace(label=7, normal=(0.0, -1.0, 0.0)), up, xyz, lab) is None


def test_decision_params():
    p = M.DecisionParams()
    assert p.narrow_face_gate is True and p.narrow_face_ratio == 6.5
    with pytest.raises(InputError):
        M.DecisionParams(narrow_face_gate="yes")
    with pytest.raises(InputError):
        M.DecisionParams(narrow_face_ratio=-1)


HUNT = Path(os.environ.get("PLANEREL_HUNT_DATA", "/nonexistent"))


@pytest.mark.skipif(not (HUNT / "hunt45" / "morbius").is_dir(),
                    reason="PLANEREL_HUNT_DATA not set")
def test_the_hutch_side(demo_model):  # noqa: F811
    """morbius livingroom: a wooden hutch's side seen edge-on from a low camera (0.96 m tall,
    0.13 m wide, cut by the image's top) was a false box: refused; box with the gate off."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from real_unseen import read_frame, read_labels

    from planerel.classify.classifier import Classifier

    folder = HUNT / "hunt45" / "morbius"
    frame = next(f for f in read_labels(str(folder))["frames"]
                 if f["file"].startswith("livingroom"))
    cloud, up = read_frame(str(folder), frame)
    boxes = {}
    for gate in (True, False):
        with Classifier(str(demo_model),
                        seg_params={"decision.narrow_face_gate": str(gate).lower()}) as clf:
            ans = clf.classify(cloud, up=up)
        boxes[gate] = sum(o.klass == "box" for o in ans.objects)
        narrow = [r for o in ans.objects for r in o.refused
                  if isinstance(r, M.NarrowFaceRefusal)]
        assert len(narrow) == (1 if gate else 0)
        if gate:
            assert 6.5 < narrow[0].ratio < 9
    assert boxes[False] == boxes[True] + 1
