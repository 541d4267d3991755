"""The demo's ramp clause (and its stairs clause) as one-rule models, for the tests of the
decision's ramp and stairs gates (tests/test_foot_gate.py, tests/test_side_gate.py), and the
one-rule model writer the other gates' tests use (:func:`one_rule_model`, :func:`rules_text`:
tests/test_far_gate.py, test_long_lying_gate.py, test_narrow_face_gate.py, test_hang_gate.py,
test_crowd_gate.py), and :func:`answer_holding`, the answer a gate test looks at."""

from __future__ import annotations

import json
from pathlib import Path


def rules_text(clauses: str, stats) -> str:
    """``clauses`` (Prolog text) and one ``planerel_rule_stats(I, Class, TP, FP)`` fact per
    ``(I, Class, TP, FP)`` of ``stats``."""
    return clauses + "".join(f"planerel_rule_stats({i}, {k}, {tp}, {fp}).\n"
                             for i, k, tp, fp in stats)


STATS = [(1, "ramp", 73, 0)]
# the demo model's ramp clause, by hand
RULES = rules_text("ramp(A) :- has_plane(A,B), slope(B,C), area(B,D), gteq(D,0.53), lteq(C,28).\n",
                   STATS)


# the demo model's stairs clause (a flight's risers one step apart), by hand
STAIRS_STATS = [(1, "stairs", 60, 0)]
STAIRS_RULES = rules_text("stairs(A) :- has_plane(A,B), parallel(B,C), stair_step(C,B).\n",
                          STAIRS_STATS)


def ramp_model(path: Path, **decision) -> Path:
    """Write the one-rule ramp model into ``path`` (its ``decision`` settings updated with
    ``decision``) and return ``path``."""
    return one_rule_model(path, RULES, STATS, **decision)


def stairs_model(path: Path, **decision) -> Path:
    """The one-rule stairs model, as :func:`ramp_model`."""
    return one_rule_model(path, STAIRS_RULES, STAIRS_STATS, **decision)


def one_rule_model(path: Path, rules: str, stats, **decision) -> Path:
    """Write ``rules`` with their ``stats`` as a model into ``path`` (its ``decision``
    settings updated with ``decision``) and return ``path``."""
    from planerel.ilp.model_settings import training_settings

    path.mkdir(parents=True, exist_ok=True)
    (path / "rules.pl").write_text(rules)
    data = training_settings("regiongrow", {}, rule_stats=stats)
    data["decision"].update(decision)
    (path / "model.json").write_text(json.dumps(data))
    return path


def answer_holding(model, scene, thing: int, share: float = 0.5, **kw):
    """Classify a rendered ``scene`` ``(cloud, up, labels, object of each label)`` with
    ``model`` (``kw`` to the :class:`~planerel.classify.classifier.Classifier`) and return the
    answer of the proposal holding most of object ``thing``'s pixels, which must hold more
    than ``share`` of them (the gates' tests)."""
    import numpy as np

    from planerel.classify.classifier import Classifier

    cloud, up, lab, objs = scene
    truth = np.where(lab >= 0, np.asarray(objs)[np.maximum(lab, 0)], -1)
    with Classifier(model, **kw) as clf:
        ans = clf.classify(cloud, up=up)
    held = [(int((np.isin(ans.labels, o.labels) & (truth == thing)).sum()), o)
            for o in ans.objects]
    n, o = max(held, key=lambda t: t[0])
    assert n > share * (truth == thing).sum()
    return o
