"""Object proposals scored against per-pixel object truth (planerel.features.object_eval)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.features.object_eval import mosd_objects, proposal_image, score_objects, summarize


def test_mosd_objects_maps_labels_to_object_ids():
    field = np.array([[0, 1, 9, 10], [19, 20, 29, 31]], dtype=np.uint32)
    # 0 invalid -> -1; 1..9 table -> 0; L >= 10 -> L // 10
    assert mosd_objects(field).tolist() == [[-1, 0, 0, 1], [1, 2, 2, 3]]


def test_proposal_image_marks_planes_and_extra_masks():
    labels = np.array([[0, 0, 1, -1], [2, 2, -1, -1]])
    extra = np.zeros((2, 4), bool)
    extra[0, 3] = True
    extra[0, 0] = True  # already plane 0's proposal: keeps it
    img = proposal_image(labels, [(0, 2), (1,)], [None, extra])
    assert img.tolist() == [[0, 0, 1, 1], [0, 0, -1, -1]]


def _truth():
    t = np.zeros((10, 20), np.int32)  # environment
    t[2:6, 2:6] = 1  # 16 px
    t[2:6, 6:10] = 2  # 16 px, touching object 1
    t[0, :] = -1
    return t


def test_exact_proposals_are_found_and_nothing_is_false():
    t = _truth()
    p = np.full(t.shape, -1)
    p[t == 1] = 0
    p[t == 2] = 1
    s = score_objects(p, t)
    assert (s.n_objects, s.found, s.false, s.merged, s.split) == (2, 2, 0, 0, 0)
    assert s.best_iou == {1: 1.0, 2: 1.0}


def test_one_proposal_over_two_equal_objects_is_merged_and_finds_neither():
    t = _truth()
    p = np.where(t >= 1, 0, -1)
    s = score_objects(p, t)
    # IoU of each object with the union: 16 / 32 = 0.5 -> found at the 0.5 threshold
    assert s.best_iou == {1: 0.5, 2: 0.5}
    assert s.merged == 1 and s.found == 2
    s = score_objects(p, t, min_iou=0.51)
    assert s.found == 0 and s.false == 1 and s.fragment == 1 and s.background == 0


def test_split_object_background_and_fragment_counts():
    t = _truth()
    p = np.full(t.shape, -1)
    p[2:6, 2:4] = 0  # half of object 1 (IoU 0.5)
    p[2:6, 4:6] = 1  # other half: not the best match -> a fragment
    p[7:10, 12:20] = 2  # on the environment only -> background
    s = score_objects(p, t)
    assert s.split == 1 and s.found == 1
    assert (s.false, s.background, s.fragment) == (2, 1, 1)
    tot = summarize([s, score_objects(np.where(t == 2, 0, -1), t)])
    assert tot["objects"] == 4 and tot["found"] == 2 and tot["found_rate"] == 0.5
    assert tot["false_per_frame"] == 1.0


def test_score_rejects_shape_mismatch():
    with pytest.raises(InputError):
        score_objects(np.zeros((2, 2)), np.zeros((3, 2)))


def test_cli_scores_a_varied_world_data_set(tmp_path, capsys):
    from planerel.cli import main

    ds = tmp_path / "ds"
    assert main(["dataset", "synth", str(ds), "--world", "varied", "--n-box", "2", "--n-stairs", "0",
                 "--n-ramp", "0", "--quiet"]) == 0
    out = tmp_path / "scores.json"
    assert main(["evaluate-objects", str(ds), "--json", str(out)]) == 0
    res = json.loads(out.read_text())
    truth_ids = set()
    from planerel.features import dataset

    for row in dataset.load_manifest(ds):
        t = dataset.load_object_labels(ds, row.scene_id)
        truth_ids.add((row.scene_id, int((np.unique(t) >= 1).sum())))
    assert res["total"]["frames"] == 2
    assert res["total"]["objects"] == sum(n for _, n in truth_ids)
    assert "box" in res["total"]["by_type"]
    assert "found" in capsys.readouterr().out


def test_cli_rejects_a_file_without_labels(tmp_path):
    from planerel.cli import main

    f = tmp_path / "x.npy"
    np.save(f, np.ones((4, 4), np.float32))
    assert main(["evaluate-objects", str(f)]) != 0


def test_miss_kinds_name_why_an_object_is_missed():
    from planerel.features.object_eval import miss_kind

    t = np.zeros((20, 20), np.int32)
    t[2:12, 2:18] = 1  # 160 px
    t[14:18, 2:6] = 2  # 16 px: under min_pixels
    labels = np.full(t.shape, -1)
    prop = np.full(t.shape, -1)
    assert miss_kind(2, prop, t, labels) == "tiny"
    assert miss_kind(1, prop, t, labels) == "unsegmented"  # no plane on it
    labels[2:12, 2:18] = 5
    assert miss_kind(1, prop, t, labels, support=[5]) == "in support"
    assert miss_kind(1, prop, t, labels) == "dropped"  # planes, but in no proposal
    prop[2:12, 2:10] = 0
    prop[2:12, 10:18] = 1  # two halves
    assert miss_kind(1, prop, t, labels) == "split"
    prop[2:12, 2:18] = 0
    prop[12:20, :] = 0  # the proposal runs on over the environment (and object 2)
    assert miss_kind(1, prop, t, labels) == "merged with environment"
    t[12:20, 6:] = 3  # now mostly another object
    assert miss_kind(1, prop, t, labels) == "merged with object"
