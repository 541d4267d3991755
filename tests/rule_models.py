"""Model folders of hand-written clauses, for the tests of the decision gates: each test
writes the one rule its gate refuses, with made-up training statistics, and switches the gate
on or off in the model's settings (as ``planerel learn`` writes them)."""

from __future__ import annotations

import json
from pathlib import Path


def rules_text(clauses: str, stats) -> str:
    """``clauses`` (Prolog text) and one ``planerel_rule_stats(I, Class, TP, FP)`` fact per
    ``(I, Class, TP, FP)`` of ``stats``."""
    return clauses + "".join(f"planerel_rule_stats({i}, {k}, {tp}, {fp}).\n"
                             for i, k, tp, fp in stats)


def rule_model(path: Path, rules: str, stats, **decision) -> Path:
    """A model folder at ``path``: ``rules.pl`` holding ``rules``, ``model.json`` the
    training settings of the default segmentation with ``stats`` and the ``decision``
    settings given (``far_gate=False``, ...)."""
    from planerel.ilp.model_settings import training_settings

    path.mkdir(parents=True, exist_ok=True)
    (path / "rules.pl").write_text(rules)
    data = training_settings("regiongrow", {}, rule_stats=stats)
    data["decision"].update(decision)
    (path / "model.json").write_text(json.dumps(data))
    return path
