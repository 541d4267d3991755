"""Which ground-truth objects are fair examples (planerel.features.truth_examples), on hand-made label
images whose answers follow from the rule's definition."""

from __future__ import annotations

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.features.truth_examples import REASONS, ExampleRule, judge_objects

# plane index: (role, object); objects 1 box, 2 stairs (two treads, one riser), 3 ramp,
# 4 other (a plate)
PLANES = [("floor", 0), ("top", 1), ("face", 1), ("tread", 2), ("riser", 2), ("slope", 3),
          ("side", 3), ("plate", 4), ("tread", 2)]
CLASSES = {1: "box", 2: "stairs", 3: "ramp", 4: "other"}


def _meta(full=None):
    objects = [{"index": k, "class": c, "n_pixels": 1} for k, c in CLASSES.items()]
    for o in objects:
        if full and o["index"] in full:
            o["n_pixels_full"] = full[o["index"]]
    return {"planes": [{"index": i, "role": r, "object_index": o} for i, (r, o) in enumerate(PLANES)],
            "objects": objects}


def _scene(shown=None):
    """An 18 x 16 image: plane i fills row block i (2 rows = 32 px) when shown (default: all),
    else floor."""
    gt = np.zeros((2 * len(PLANES), 16), np.int32)
    for i in range(len(PLANES)) if shown is None else shown:
        gt[2 * i:2 * i + 2] = i
    return gt


def _groups(labels, gt):
    """Segmented planes = ground-truth planes; one group per object with its planes."""
    obj = {i: o for i, (_r, o) in enumerate(PLANES)}
    present = np.unique(labels[labels >= 0])
    per = {}
    for x in present:
        if obj[int(x)] > 0:
            per.setdefault(obj[int(x)], []).append(int(x))
    ks = sorted(per)
    return [tuple(per[k]) for k in ks], ks


def test_objects_showing_their_class_are_examples():
    gt = _scene()
    groups, ks = _groups(gt, gt)
    assert judge_objects(gt, gt, _meta(), groups, ks, CLASSES) == {1: None, 2: None, 3: None, 4: None}


def test_a_box_with_one_face_a_single_step_and_a_ramp_without_its_slope_are_not():
    gt = _scene(shown=[0, 2, 3, 6, 7])  # box face only, one tread, ramp side only, plate
    groups, ks = _groups(gt, gt)
    got = judge_objects(gt, gt, _meta(), groups, ks, CLASSES)
    assert got == {1: "one face", 2: "fewer than two steps", 3: "slope not seen", 4: None}
    assert set(v for v in got.values() if v) <= set(REASONS)


def test_planes_covering_much_more_than_the_object_do_not_match():
    gt = _scene()
    labels = np.where(gt == 0, 1, gt)  # the floor (rows 0-1, 32 px) joins the box top
    groups, ks = _groups(gt, gt)
    # IoU of the box group {1, 2} = 64 / (64 + 32) = 0.67: still an example
    assert judge_objects(labels, gt, _meta(), groups, ks, CLASSES)[1] is None
    strict = ExampleRule(min_iou=0.7)
    assert judge_objects(labels, gt, _meta(), groups, ks, CLASSES, strict)[1] == \
        "planes do not match (IoU)"


def test_mostly_hidden_applies_to_compact_objects_only():
    gt = _scene()
    groups, ks = _groups(gt, gt)
    # every object has 64 seen pixels (plate 32); alone and unbounded it would cover 10x
    full = {1: 640, 2: 640, 3: 640, 4: 320}
    got = judge_objects(gt, gt, _meta(full), groups, ks, CLASSES)
    assert got == {1: "mostly hidden", 2: None, 3: None, 4: "mostly hidden"}
    # 64 of 200 = 0.32 >= 0.3: seen enough
    assert judge_objects(gt, gt, _meta({1: 200}), groups, ks, CLASSES)[1] is None


def test_objects_without_planes_are_counted_and_unseen_ones_ignored():
    gt = _scene(shown=[0, 1, 2, 3, 4, 5, 8])  # the plate (object 4) is not seen
    groups, ks = _groups(gt, gt)
    groups, ks = groups[1:], ks[1:]  # the box's planes were not found
    got = judge_objects(gt, gt, _meta(), groups, ks, CLASSES)
    assert got == {1: "no plane found", 2: None, 3: None}


def test_tiny_planes_do_not_count_as_shown():
    gt = _scene()
    gt[2:4, 3:] = 0  # the box top keeps 6 pixels
    groups, ks = _groups(gt, gt)
    assert judge_objects(gt, gt, _meta(), groups, ks, CLASSES)[1] == "one face"
    assert judge_objects(gt, gt, _meta(), groups, ks, CLASSES,
                         ExampleRule(min_plane_pixels=6))[1] is None


@pytest.mark.parametrize("kw", [{"min_iou": 1.5}, {"min_visible": -0.1}, {"min_iou": True},
                                {"min_plane_pixels": 0}])
def test_bad_thresholds_are_refused(kw):
    with pytest.raises(InputError):
        ExampleRule(**kw)


def test_one_tread_and_one_riser_are_one_step():
    gt = _scene(shown=[0, 1, 2, 3, 4, 5, 7])  # the second tread (plane 8) not seen
    groups, ks = _groups(gt, gt)
    assert judge_objects(gt, gt, _meta(), groups, ks, CLASSES)[2] == "fewer than two steps"
    gt = _scene(shown=[0, 1, 2, 3, 5, 7, 8])  # two treads, no riser: two steps
    groups, ks = _groups(gt, gt)
    assert judge_objects(gt, gt, _meta(), groups, ks, CLASSES)[2] is None
