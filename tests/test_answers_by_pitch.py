"""benchmarks/answers_by_pitch.py (small99): how a setting moves the real frames' ``box``
answers, frame by frame, split by how steeply the camera looks down.  A measuring tool."""

from __future__ import annotations

import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
import answers_by_pitch as abp  # noqa: E402


def _row(s, f, status, pitch):
    return {"set": s, "frame": f, "status": status, "pitch": pitch, "proof": []}


def test_frames_that_move_are_summed_in_their_pitch_band(tmp_path, capsys):
    before = [_row("a", "top", "right", 80.0), _row("b", "room", "right", 10.0),
              _row("c", "still", "false", 70.0), _row("c", "still", "right", 70.0)]
    after = [_row("a", "top", "right", 80.0), _row("a", "top", "right", 80.0),
             _row("a", "top", "false", 80.0),            # +1 right, +1 false at 80
             _row("b", "room", "false", 10.0),           # right -> false at 10
             _row("c", "still", "right", 70.0), _row("c", "still", "false", 70.0),
             _row("d", "new", "unscored", None)]         # no pitch in its rows
    moved, totals = abp.compare(before, after, split=60)
    assert [(s, f) for s, f, _, _ in moved] == [("a", "top"), ("b", "room"), ("d", "new")]
    assert moved[0][2] == 80.0 and moved[0][3] == {"right": 1, "false": 1, "unscored": 0}
    assert totals[(">= 60", "right")] == 1 and totals[(">= 60", "false")] == 1
    assert totals[("< 60", "right")] == -1 and totals[("< 60", "false")] == 1
    assert totals[("unknown", "unscored")] == 1
    # the command line reads box_answers' JSON lines and prints the bands
    pb, pa = tmp_path / "b.jsonl", tmp_path / "a.jsonl"
    pb.write_text("".join(json.dumps(r) + "\n" for r in before))
    pa.write_text("".join(json.dumps(r) + "\n" for r in after))
    assert abp.main([str(pb), str(pa), "--split", "60"]) == 0
    out = capsys.readouterr().out
    assert "pitch >= 60: right +1, false +1, unscored +0" in out
    assert "pitch < 60: right -1, false +1, unscored +0" in out
    assert "pitch unknown: right +0, false +0, unscored +1" in out
