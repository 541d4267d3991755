"""benchmarks/real_unseen.py's ``flat`` rectangles: flat things of no class, reported with what
each was called, and refused when malformed."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
from real_unseen import read_labels, score_frame, totals  # noqa: E402

from planerel.errors import InputError  # noqa: E402


def _answer():
    """A 20 x 30 label image: plane 1 fills rows 2-7, columns 2-11 (a keyboard lying flat),
    plane 2 rows 10-17, columns 15-27 (a carton); both answered ``box`` (rules 3 and 1)."""
    lab = np.zeros((20, 30), int)
    lab[2:8, 2:12] = 1
    lab[10:18, 15:28] = 2
    objs = [SimpleNamespace(klass="box", labels=(1,), rule_index=3),
            SimpleNamespace(klass="box", labels=(2,), rule_index=1),
            SimpleNamespace(klass="other", labels=(1, 2), rule_index=None)]
    return SimpleNamespace(labels=lab, objects=objs)


def test_a_box_on_a_flat_thing_is_false_and_reported_with_its_rule():
    frame = {"file": "f.png",
             "objects": [{"class": "box", "box": [14, 9, 29, 19], "what": "carton"}],
             "flat": [{"box": [1, 1, 13, 9], "what": "keyboard"},
                      {"box": [0, 18, 10, 20], "what": "mat nothing answered"}]}
    r = score_frame(_answer(), frame)
    assert r["right"] == [("box", 1)]
    assert r["false"] == [("box", 3, 0.0)]
    assert r["flat"] == [{"what": "keyboard", "called": [("box", 3)]},
                         {"what": "mat nothing answered", "called": []}]
    t = totals([r])
    assert (t["flat_labelled"], t["flat_called_box"], t["flat_called_stairs"]) == (2, 1, 0)
    assert t["false_box"] == 1 and t["box_found"] == 1


def test_frames_without_flat_things_score_as_before():
    frame = {"file": "f.png", "objects": [{"class": "box", "box": [14, 9, 29, 19]}]}
    r = score_frame(_answer(), frame)
    assert r["flat"] == [] and totals([r])["flat_labelled"] == 0


def test_a_malformed_flat_rectangle_is_refused(tmp_path):
    doc = {"frames": [{"file": "f.png", "objects": [], "flat": [{"box": [1, 2, 3]}]}]}
    (tmp_path / "labels.json").write_text(json.dumps(doc))
    with pytest.raises(InputError, match="flat thing needs a 'box'"):
        read_labels(str(tmp_path))
