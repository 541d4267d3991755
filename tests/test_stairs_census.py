"""``benchmarks/stairs_census.py`` (stairs58, docs/objects.md "Staircases lost, stage by
stage"): every flight of an independent set gets one row; a flight is found exactly when
``independent_scenes.py score`` finds it, and a flight no rule can prove is lost at a stage."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
import independent_scenes as ind  # noqa: E402
import stairs_census  # noqa: E402

STAGES = ("found", "no plane in it", "faces < 2", "no stair_step", "no proposal", "merged",
          "split", "gate refused", "other class", "no rule fires")


@pytest.fixture(scope="module")
def flights(tmp_path_factory):
    out = tmp_path_factory.mktemp("st")
    ind.make_set(out, 4, 3, (160, 120), kinds=("stairs", "stairs_top"))
    return out


def _rules(tmp_path, body):
    p = tmp_path / "rules.pl"
    p.write_text(f"stairs(A) :- {body}.\n")
    return p


def test_a_flight_is_found_as_the_independent_score_finds_it(flights, tmp_path):
    rules = _rules(tmp_path, "has_plane(A,B), parallel(B,C), stair_step(C,B)")
    rows = stairs_census.census([flights], str(rules))
    scored = [r for r in ind.score_set(flights, [str(rules)])[str(rules)]["rows"]
              if r["class"] == "stairs"]
    assert len(rows) == len(scored) > 0
    by = {(r["frame"], r["best_iou"]): r["stage"] == "found" for r in rows}
    assert by == {(r["scene"], r["iou"]): r["pred"] == "stairs" for r in scored}
    assert any(r["stage"] == "found" for r in rows)


def test_a_flight_no_rule_proves_is_lost_at_a_named_stage(flights, tmp_path):
    rules = _rules(tmp_path, "has_plane(A,B), orientation(B,inclined), orientation(B,vertical)")
    rows = stairs_census.census([flights], str(rules))
    assert rows and not any(r["stage"] == "found" for r in rows)
    assert all(r["stage"].startswith(STAGES) for r in rows)
    # a flight whose planes make stair_step pairs and whose proposal is the flight: no rule
    assert any(r["stage"] == "no rule fires" and r["steps_in_proposal"] > 0 for r in rows)
