"""``relations.skirt_top_solid`` (0.3, on): an open tote's rim seen from above, its inner wall
hanging under it, is no box's top; a box's top fills its outline (spurious81)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.features.relations import RelationParams, image_solidity

_SPEC = importlib.util.spec_from_file_location(
    "independent_scenes", Path(__file__).resolve().parents[1] / "benchmarks" / "independent_scenes.py")
ind = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(ind)

SKIRT_RULE = "box(A) :- has_plane(A,B), skirt(B,C).\n"


def test_a_filled_region_fills_its_hull_and_a_ring_or_a_frame_does_not():
    lab = np.zeros((60, 90), int)
    lab[10:40, 10:70] = 1                       # a filled rectangle
    lab[45:58, 5:85] = 2
    lab[47:56, 7:83] = 0                        # a frame 2 px wide
    lab[2:8, 75:88] = 3
    lab[2:5, 75:80] = 0                         # an L (a top with a corner covered)
    assert image_solidity(lab, 1) == pytest.approx(1.0)
    assert image_solidity(lab, 2) < 0.35
    assert 0.6 < image_solidity(lab, 3) < 1.0
    assert image_solidity(lab, 9) == 1.0        # no pixel: nothing to refuse
    one_row = np.zeros((5, 5), int)
    one_row[2, :] = 4
    assert image_solidity(one_row, 4) == pytest.approx(1.0)


def test_the_share_is_checked():
    with pytest.raises(InputError):
        RelationParams(skirt_top_solid=1.5)
    with pytest.raises(InputError):
        RelationParams(skirt_top_solid=-0.1)


def _view(meshes, target, eye):
    f = np.asarray(target, float) - eye
    f /= np.linalg.norm(f)
    r = np.cross(f, [0.0, 0.0, 1.0])
    r /= np.linalg.norm(r)
    R = np.stack([r, np.cross(f, r), f])
    intr = (320, 240, 280.0, 280.0, 159.5, 119.5)
    xyz, _ = ind.render(meshes, eye, R, intr, np.random.default_rng(3))
    from planerel.io.cloud import Cloud, Intrinsics
    return Cloud(xyz.astype(float), intrinsics=Intrinsics(*intr),
                 up=R @ np.array([0.0, 0.0, 1.0]))


def _tote(rim=0.02, size=(0.45, 0.3), height=0.11):
    """An open tote on a floor: its bottom and four walls ``rim`` thick (all environment)."""
    L, W = size
    floor = ind._box((30, 30, 0.02), (0, 0, -0.01))
    parts = [ind._box((L, W, 0.01), (0, 0, 0.005)),
             ind._box((L, rim, height), (0, (W - rim) / 2, height / 2)),
             ind._box((L, rim, height), (0, -(W - rim) / 2, height / 2)),
             ind._box((rim, W, height), ((L - rim) / 2, 0, height / 2)),
             ind._box((rim, W, height), (-(L - rim) / 2, 0, height / 2))]
    return [(floor, 0)] + [(p, 0) for p in parts]


def _box_answers(tmp_path, cloud, switch):
    """``box`` answers of a model whose one rule is the skirt clause."""
    from planerel.classify.classifier import Classifier

    rules = tmp_path / "rules.pl"
    rules.write_text(SKIRT_RULE)
    over = None if switch is None else {"relations.skirt_top_solid": str(switch)}
    with Classifier(rules, seg_params=over) as clf:
        ans = clf.classify(cloud, scene_id="s")
    return sum(o.klass == "box" for o in ans.objects)


def test_a_totes_rim_is_a_skirt_top_only_with_the_switch_off(tmp_path):
    cloud = _view(_tote(), (0.0, 0.0, 0.05), np.array([0.25, -0.35, 0.65]))
    assert _box_answers(tmp_path, cloud, 0.0) >= 1
    assert _box_answers(tmp_path, cloud, None) == 0  # on by default (0.3)


def test_a_boxs_top_keeps_its_skirt_with_the_switch_on(tmp_path):
    floor = ind._box((30, 30, 0.02), (0, 0, -0.01))
    box = ind._box((0.3, 0.2, 0.15), (0, 0, 0.075))
    cloud = _view([(floor, 0), (box, 1)], (0.0, 0.0, 0.07), np.array([0.4, -0.6, 0.7]))
    assert _box_answers(tmp_path, cloud, 0.0) == 1
    assert _box_answers(tmp_path, cloud, None) == 1
