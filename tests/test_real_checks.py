"""benchmarks/real_checks.py: the real-data checks of a model in one run, saved and compared
(the shared frames with the demo's model, learned as ``make demo`` learns it, real swipl)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import real_checks  # noqa: E402
from test_real_rules import demo_model  # noqa: E402,F401  (the fixture)


def test_lines_are_kept_without_timings_and_compared():
    assert real_checks.TIMING.sub("", "i0001_o3: box  [1877 ms]") == "i0001_o3: box"
    # a count before a word starting with s is no timing
    assert real_checks.TIMING.sub("", "answers: box 2 stairs 1") == "answers: box 2 stairs 1"
    before = {"mosd": ["all: found 423"], "stairs": ["4 of 4"], "gone": ["x"]}
    now = {"mosd": ["all: found 424"], "stairs": ["4 of 4"], "new": ["y"]}
    assert real_checks.compare(now, before) == [
        "gone: - x", "mosd: - all: found 423", "mosd: + all: found 424", "new: + y"]
    assert real_checks.compare(before, before) == []


def test_the_shared_frames_and_missing_sets(demo_model, tmp_path):  # noqa: F811
    res = real_checks.checks(str(demo_model), [], tmp_path / "none", tmp_path / "none", [tmp_path / "h"],
                             [tmp_path / "indep"])
    # the Kinect frames' box and the mOSD boxes are the only class answers of the shared frames
    shared = res["shared frames"]
    assert sum(line.strip().startswith("frame_") and ": box" in line for line in shared) == 3
    assert all(": box" in line for line in shared), shared
    # a set that is not here is skipped, and says what is missing
    assert res["whole mOSD"][0].startswith("skipped: no ") and "mosd" in res["whole mOSD"][0]
    assert res["staircases"][0].startswith("skipped: no ")
    assert res[f"independent {tmp_path / 'indep'}"] == [f"skipped: no {tmp_path / 'indep'}"]
    # saved and compared by the command: identical runs print "identical", exit 0
    saved = tmp_path / "run.json"
    saved.write_text(json.dumps(res))
    assert real_checks.main(["--model", str(demo_model), "--tabletop", str(tmp_path / "none"),
                             "--stairs", str(tmp_path / "none"),
                             "--hunts", str(tmp_path / "h"), "--independent",
                             str(tmp_path / "indep"), "--compare", str(saved)]) == 0
