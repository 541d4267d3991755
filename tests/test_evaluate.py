"""SegComp scoring (Hoover et al. 1996), IoU, angle errors, sparse planes."""

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.segment.evaluate import evaluate, segcomp, sparse_planes


def _gt():
    g = np.full((20, 40), -1, np.int32)
    g[:, :10] = 0
    g[:, 10:20] = 1
    g[:, 20:30] = 2
    g[:10, 30:40] = 3
    return g


def test_perfect_segmentation_is_all_correct():
    g = _gt()
    s = evaluate(g + 5 * (g >= 0), g)  # other ids, same regions
    assert (s.correct, s.over, s.under, s.missed, s.noise) == (4, 0, 0, 0, 0)
    assert s.mean_iou == pytest.approx(1.0)
    assert s.n_gt == 4 and s.n_pred == 4


def test_over_under_missed_noise():
    g = _gt()
    p = np.full_like(g, -1)
    p[:10, :10] = 0          # region 0 split in two -> over-segmentation
    p[10:, :10] = 1
    p[:, 10:30] = 2          # regions 1 and 2 merged -> under-segmentation
    # region 3 left out -> missed
    p[10:, 30:40] = 3        # pixels of no GT region -> noise
    r = segcomp(p, g)
    assert r["correct"] == []
    assert r["over"] == [(0, [0, 1])]
    assert r["under"] == [(2, [1, 2])]
    assert r["missed"] == [3]
    assert r["noise"] == [3]
    s = evaluate(p, g)
    assert (s.correct, s.over, s.under, s.missed, s.noise) == (0, 1, 1, 1, 1)


def test_tolerance_decides_correct_detection():
    g = _gt()
    p = g.copy()
    p[:3, 10:20] = 0  # region 0 grows into region 1: 30 of 230 pixels foreign (87%)
    assert evaluate(p, g, tolerance=0.8).correct == 4
    assert evaluate(p, g, tolerance=0.9).correct == 2
    with pytest.raises(InputError, match="tolerance"):
        evaluate(p, g, tolerance=0.3)
    with pytest.raises(InputError, match="tolerance"):
        evaluate(p, g, tolerance=float("nan"))


def test_angle_errors_of_correct_planes():
    g = _gt()
    gn = np.array([[0, 0, -1.0], [0, -1.0, 0], [1.0, 0, 0], [0, 0, 1.0]])
    t = np.radians(3.0)
    pn = gn.copy()
    pn[0] = [np.sin(t), 0, -np.cos(t)]
    pn[3] = -pn[3]  # orientation is ignored
    s = evaluate(g, g, pred_normals=pn, gt_normals=gn)
    assert s.angle_errors[0] == pytest.approx(3.0)
    assert s.mean_angle_error == pytest.approx(0.75)


def test_sparse_planes():
    lab = np.full((60, 80), -1, np.int32)
    lab[5:25, 5:30] = 0        # one compact piece
    lab[5:25, 40:75] = 1       # two separate pieces of one label -> sparse
    lab[40:55, 5:30] = 1
    lab[40:55, 40:75] = 2
    lab[30, 60] = 2            # a one-pixel speck does not make a plane sparse
    lab[30:32, 10:12] = 2      # nor does a tiny piece
    assert sparse_planes(lab) == [1]
    assert evaluate(lab, lab).sparse == 1


def test_bad_label_inputs():
    with pytest.raises(InputError, match="differ in shape"):
        evaluate(np.zeros((3, 3), np.int32), np.zeros((4, 3), np.int32))
    with pytest.raises(InputError, match="2-D"):
        evaluate(np.zeros(9, np.int32), np.zeros(9, np.int32))
    with pytest.raises(InputError, match="integers"):
        evaluate(np.zeros((3, 3)), np.zeros((3, 3), np.int32))


def test_empty_prediction_counts_every_gt_region_missed():
    g = _gt()
    s = evaluate(np.full_like(g, -1), g)
    assert (s.correct, s.missed, s.noise, s.n_pred) == (0, 4, 0, 0)
    assert s.mean_iou == 0.0
    assert s.to_dict()["missed"] == 4
