"""``benchmarks/merge_why.py`` (ground75): the join rules that hold a box merged with what lies
outside its rectangle, named by rule and the two planes' orientations, counted without naming
a frame."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import merge_why  # noqa: E402

ORI = {1: "vertical", 2: "horizontal", 3: "inclined", 4: "vertical"}


def test_only_pairs_across_the_rectangle_count_named_by_rule_and_orientations():
    rules = [("convex_pairs", {(1, 2), (1, 4)}),   # 1 inside, 2 outside: across; 1-4 inside
             ("split_panel_pairs", {(3, 2)}),       # both outside
             ("cavity_pairs", {(4, 9)})]            # 9 outside, not a measured plane
    got = merge_why.joins_across(rules, ORI, inside={1, 4}, outside={2, 3, 9})
    assert got == {("convex_pairs", "hv"), ("cavity_pairs", "?v")}


def test_the_table_counts_boxes_and_names_no_frame():
    rows = [{"set": "s/a", "frame": "f1", "joins": [["convex_pairs", "hv"]]},
            {"set": "s/a", "frame": "f2", "joins": [["convex_pairs", "hv"],
                                                    ["split_panel_pairs", "vv"]]},
            {"set": "s/b", "frame": "f3", "joins": []}]
    out = merge_why.table(rows)
    assert "merged boxes: 3; with no join across their rectangle: 1" in out
    assert "| convex_pairs | hv | 2 |" in out and "| split_panel_pairs | vv | 1 |" in out
    assert "f1" not in out and "s/a" not in out
