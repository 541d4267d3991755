"""lead61: the far growing's planes (``far_theta``, on by default) prove no box and no ramp
(``decision.far_gate``; docs/segmentation.md "Far planes"); stairs may use them.

That growing joins depth beyond ``far_depth`` that the first growing left in no plane, at a
wider angle, to recover a far flight's treads and risers; on the development frames its planes
also made three false boxes (skirts on far background surfaces) and a false ramp (a strip of a
far floor the sensor bends).  The gate turns a ``box`` or ``ramp`` answer whose proof binds
such a plane into ``other``.

Rendered scenes are ray-cast rectangles (tests/scenes_analytic.py); Prolog runs for real.  With
``PLANEREL_HUNT_DATA`` the gate is checked on the two real frames it was measured on.
"""

from __future__ import annotations

import dataclasses
import os
import sys
from pathlib import Path

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.ilp import metrics as M

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ramp_model import one_rule_model, rules_text  # noqa: E402
from scenes_analytic import Rect, floor, ramp, render  # noqa: E402
from test_real_rules import demo_model  # noqa: E402,F401  (the fixture)

STATS = [(1, "box", 40, 4)]
RULES = rules_text("box(A) :- has_plane(A,B), oblique_share(A,C), lying(B), lteq(C,0.02).\n", STATS)
THING = 1


def _model(path: Path, *, gate=True) -> Path:
    return one_rule_model(path, RULES, STATS, far_gate=gate)


def _described():
    """A book-size top (0.25 x 0.15 m) lying 4 cm over the floor, 1.2 m ahead of a camera
    1 m up looking 45 degrees down: ``(cloud, description, the top's label)``."""
    from planerel.features.facts import describe_scene
    from planerel.segment import segment

    rects = [floor(), Rect((0.0, 1.2, 0.04), (1, 0, 0), (0, 1, 0), 0.125, 0.075, THING)]
    cloud, lab, up, objs = render(rects, pitch=45, cam_height=1.0, width=320, height=240,
                                  noise=0.001)
    truth = np.where(lab >= 0, np.asarray(objs)[np.maximum(lab, 0)], -1)
    seg = segment(cloud)
    desc = describe_scene(cloud, seg.labels, up=up)
    share = [(int(((desc.labels == p.label) & (truth == THING)).sum()), p.label)
             for p in desc.planes]
    return cloud, desc, max(share)[1]


def _box_answer(answers, top_id):
    return next(a for a in answers if top_id in a.planes)


def test_a_box_proved_through_a_far_plane_is_refused(tmp_path):
    from planerel.classify.classifier import Classifier

    cloud, desc, top = _described()
    top_id = desc.plane_id(top)
    assert not desc.far  # 1.2 m: nothing for the far growing
    with Classifier(_model(tmp_path / "m")) as clf:
        a = _box_answer(clf.answer_description(desc, xyz=cloud.xyz), top_id)
        assert a.klass == "box" and top_id in a.proof_planes
        # the same description, its top marked as a far plane
        far = dataclasses.replace(desc, far=frozenset({top}))
        b = _box_answer(clf.answer_description(far, xyz=cloud.xyz), top_id)
    assert b.klass == "other"
    why = [r for r in b.refused if isinstance(r, M.FarPlaneRefusal)]
    assert len(why) == 1 and why[0].planes == (top_id,) and why[0].rule == 1
    assert "far growing" in why[0].reason and why[0].to_dict()["planes"] == [top_id]
    # with the gate off the far plane proves the box
    with Classifier(_model(tmp_path / "off", gate=False)) as clf:
        c = _box_answer(clf.answer_description(far, xyz=cloud.xyz), top_id)
    assert c.klass == "box"


def test_a_ramp_proved_through_a_far_plane_is_refused(tmp_path):
    from planerel.classify.classifier import Classifier
    from planerel.features.facts import describe_scene
    from planerel.segment import segment

    stats = [(1, "ramp", 30, 2)]
    rules = rules_text("ramp(A) :- has_plane(A,B), slope(B,C), lteq(C,28).\n", stats)
    cloud, lab, up, _ = render([floor(), *ramp(0.0, 1.5, 15.0, 1.5, 1.0)],
                               pitch=30, cam_height=1.2, width=320, height=240, noise=0.001)
    desc = describe_scene(cloud, segment(cloud).labels, up=up)
    slope = [p.label for p in desc.planes if p.orientation == "inclined"]
    assert len(slope) == 1
    with Classifier(one_rule_model(tmp_path / "m", rules, stats)) as clf:
        a = [x for x in clf.answer_description(desc, xyz=cloud.xyz) if x.klass == "ramp"]
        assert len(a) == 1
        far = dataclasses.replace(desc, far=frozenset(slope))
        b = [x for x in clf.answer_description(far, xyz=cloud.xyz) if slope[0] in x.labels]
    assert len(b) == 1 and b[0].klass == "other"
    why = [r for r in b[0].refused if isinstance(r, M.FarPlaneRefusal)]
    assert len(why) == 1 and why[0].klass == "ramp" and "ramp" in why[0].reason


def test_far_planes_are_the_description_s_planes_mostly_in_the_far_mask():
    from planerel.features.facts import far_planes

    _, desc, top = _described()
    lab = np.asarray(desc.labels)
    mask = lab == top
    assert far_planes(desc, mask) == frozenset({top})
    # a plane with under half its pixels in the mask is not far
    ys, xs = np.nonzero(mask)
    part = np.zeros_like(mask)
    part[ys[: len(ys) // 3], xs[: len(xs) // 3]] = True
    assert top not in far_planes(desc, part)
    assert far_planes(desc, np.zeros_like(mask)) == frozenset()
    assert far_planes(desc, np.zeros((3, 3), bool)) == frozenset()  # another image: none


def test_decision_params():
    assert M.DecisionParams().far_gate is True
    with pytest.raises(InputError, match="far_gate"):
        M.DecisionParams(far_gate="yes")


HUNT = Path(os.environ.get("PLANEREL_HUNT_DATA", "/nonexistent"))
FRAMES = [("hunt33", "ucn", "000007-depth"), ("hunt36", "nvblox-lounge", "lounge_000000_depth")]


@pytest.mark.skipif(not all((HUNT / h / s).is_dir() for h, s, _ in FRAMES),
                    reason="PLANEREL_HUNT_DATA not set")
@pytest.mark.parametrize("hunt,folder,stem", FRAMES)
def test_the_development_frames(demo_model, hunt, folder, stem):  # noqa: F811
    """A false box on each, proved through a far plane (a skirt on a far background
    surface), once far_theta was on: refused; the frame's other answers stay."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from real_unseen import read_frame, read_labels

    from planerel.classify.classifier import Classifier

    where = str(HUNT / hunt / folder)
    frame = next(f for f in read_labels(where)["frames"] if Path(f["file"]).stem == stem)
    cloud, up = read_frame(where, frame)
    with Classifier(str(demo_model)) as clf:
        ans = clf.classify(cloud, up=up)
    with Classifier(str(demo_model), seg_params={"decision.far_gate": "false"}) as clf:
        off = clf.classify(cloud, up=up)
    refused = [(o, r) for o in ans.objects for r in o.refused
               if isinstance(r, M.FarPlaneRefusal)]
    assert len(refused) == 1 and refused[0][0].klass == "other"
    gained = [o for o in off.objects if o.klass == "box"]
    assert len(gained) == sum(o.klass == "box" for o in ans.objects) + 1
    assert refused[0][1].planes
