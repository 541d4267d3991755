"""``planerel learn`` says when cross-validation folds learned no rule for a class (user89:
3 folds of 4 scenes a class at ``minpos`` 3 scored 0.417, against 0.917 at the defaults, with
no word on the console)."""

from __future__ import annotations

import json

from planerel.cli import main


def test_folds_without_a_rule_are_named(tmp_path, capsys):
    data = tmp_path / "tiny"
    assert main(["dataset", "synth", str(data), "--seed", "3", "--n-box", "4", "--n-stairs",
                 "4", "--n-ramp", "4", "--quiet"]) == 0
    capsys.readouterr()
    assert main(["learn", str(data), "--folds", "3", "-o", str(tmp_path / "m"), "--set",
                 "evalfn=coverage", "--set", "minpos=3", "--set", "noise=1"]) == 0
    err = capsys.readouterr().err
    cv = json.loads((tmp_path / "m" / "metrics.json").read_text())["cross_validation"]
    for k in ("box", "stairs", "ramp"):
        empty = sum(not any(r.startswith(f"{k}(") for r in f["rules"]) for f in cv["folds"])
        line = [ln for ln in err.splitlines() if f"learned no rule for {k} " in ln]
        if empty:
            assert line and f"{empty} of 3 cross-validation folds" in line[0]
            assert "minpos 3" in line[0]
        else:
            assert not line
    assert "learned no rule" in err  # this set at minpos 3 leaves some fold without a rule
