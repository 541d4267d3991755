"""benchmarks/judge_faces.py: a staircase face counts as resolved when one region holds half
of it and lies mostly on it, and falls in the bin of its thickness in pixels."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

_SPEC = importlib.util.spec_from_file_location(
    "judge_faces", Path(__file__).resolve().parents[1] / "benchmarks" / "judge_faces.py")
jf = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(jf)


def test_faces_binned_by_thickness_and_resolved():
    truth = np.zeros((20, 30), np.int32)
    truth[2:18, 5:25] = 1  # the staircase
    planes = np.full((20, 30), -1, np.int32)
    planes[2:4, 5:25] = 0  # a 2 px tread
    planes[4:14, 5:25] = 1  # a 10 px riser
    planes[14:18, 5:25] = 2  # a 4 px face
    lab = np.full((20, 30), -1, np.int32)
    lab[4:14, 5:25] = 7  # the riser is a region of its own
    lab[14:18, 5:15] = 8  # half the 4 px face, in a region that spills onto the floor ...
    lab[18:20, 5:15] = 8  # ... by as many pixels: not resolved
    counts = {b: [0, 0, 0.0] for b in jf.BINS}
    jf.face_stats(lab, truth, planes, [1], counts)
    assert counts[(2, 3)][:2] == [0, 1] and counts[(2, 3)][2] == 0.0
    assert counts[(9, 13)] == [1, 1, 1.0]
    assert counts[(4, 6)][:2] == [0, 1] and counts[(4, 6)][2] == 0.5
    assert sum(c[1] for c in counts.values()) == 3
