"""The demo's ramp clause as a one-rule model, for the tests of the decision's ramp gates
(tests/test_foot_gate.py, tests/test_side_gate.py)."""

from __future__ import annotations

import json
from pathlib import Path

STATS = [(1, "ramp", 73, 0)]
# the demo model's ramp clause, by hand
RULES = ("ramp(A) :- has_plane(A,B), slope(B,C), area(B,D), gteq(D,0.53), lteq(C,28).\n"
         + "".join(f"planerel_rule_stats({i}, {k}, {tp}, {fp}).\n" for i, k, tp, fp in STATS))


def ramp_model(path: Path, **decision) -> Path:
    """Write the one-rule model into ``path`` (its ``decision`` settings updated with
    ``decision``) and return ``path``."""
    from planerel.ilp.model_settings import training_settings

    path.mkdir(parents=True, exist_ok=True)
    (path / "rules.pl").write_text(RULES)
    data = training_settings("regiongrow", {}, rule_stats=STATS)
    data["decision"].update(decision)
    (path / "model.json").write_text(json.dumps(data))
    return path
