"""Extending a learned theory (``learn_rules(prior=...)``): the prior clauses are kept as they
are, the learner sees only the positives they do not prove, every negative stays."""

from __future__ import annotations

import os

import pytest

from planerel.errors import InputError
from planerel.ilp import pipeline as P
from planerel.ilp import scenes as S
from planerel.ilp.aleph_export import aleph_files
from planerel.synth.generator import generate_dataset

CLASSES = ["box", "stairs", "ramp"]


@pytest.fixture(scope="module")
def gt_descs(tmp_path_factory):
    """4 box, 4 stairs, 4 ramp scenes at 160x120, ground-truth planes."""
    out = tmp_path_factory.mktemp("ds") / "train"
    generate_dataset(out, n_box=4, n_stairs=4, n_ramp=4, seed=3, size=(640, 480), subsample=4)
    descs, skipped = S.describe_scenes(out, method="gt", jobs=1, cache="none")
    assert not skipped
    return descs


@pytest.fixture(autouse=True)
def _private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("PLANEREL_CACHE", str(tmp_path / "cache"))


def _positives(text: str) -> set:
    return {ln.strip() for ln in text.splitlines() if ln.strip()}


def test_skip_positives_leaves_them_out_of_the_examples_file_only(gt_descs):
    full = aleph_files(gt_descs, "box", classes=CLASSES)
    boxes = sorted(_positives(full["box.f"]))
    assert len(boxes) >= 2
    gone = boxes[0][len("box("):-len(").")]
    part = aleph_files(gt_descs, "box", classes=CLASSES, skip_positives={gone})
    assert _positives(part["box.f"]) == set(boxes[1:])
    assert part["box.n"] == full["box.n"]
    # the object's facts stay in the background: only its example is gone
    assert f"has_plane({gone}," in part["box.b"]
    assert f"examples: {len(boxes) - 1} positive" in part["box.b"]
    with pytest.raises(InputError, match="per-class task"):
        aleph_files(gt_descs, "class", classes=CLASSES, skip_positives={gone})


def test_extending_a_theory_with_itself_learns_nothing_new(gt_descs):
    base = P.learn_rules(gt_descs, CLASSES, engine="builtin", jobs=1)
    assert base.clauses()
    again = P.learn_rules(gt_descs, CLASSES, engine="builtin", jobs=1, prior=base.rules)
    assert again.rules == base.rules
    assert again.stats == base.stats
    assert again.proof_domain == base.proof_domain


def test_prior_clauses_come_first_and_are_never_left_out(gt_descs):
    # a prior that proves every object (boxes, stairs and ramps alike): its false positives
    # would make drop_redundant leave it out once a learned clause proves the boxes too
    loose = "box(A) :- has_plane(A,B)."
    model = P.learn_rules(gt_descs, CLASSES, engine="builtin", jobs=1,
                          prior={"box": (loose,)})
    assert model.rules["box"][0] == loose
    assert not any(d[1] == loose for d in model.dropped)
    stats = {i: (k, tp, fp) for i, k, tp, fp in model.stats}
    assert stats[1][0] == "box" and stats[1][2] > 0        # its false positives are counted


def test_extend_only_learns_those_classes_and_keeps_the_others_as_they_are(gt_descs):
    # a narrow prior for box and stairs: extending every class adds clauses to both
    narrow = {"box": ("box(A) :- has_plane(A,B), nhorizontal(A,9).",),
              "stairs": ("stairs(A) :- has_plane(A,B), nhorizontal(A,9).",)}
    every = P.learn_rules(gt_descs, CLASSES, engine="builtin", jobs=1, prior=narrow)
    assert len(every.rules["box"]) > 1 and every.rules["ramp"]
    only = P.learn_rules(gt_descs, CLASSES, engine="builtin", jobs=1, prior=narrow,
                         extend_only=["ramp"])
    assert only.rules["box"] == narrow["box"] and only.rules["stairs"] == narrow["stairs"]
    assert only.rules["ramp"] == every.rules["ramp"]  # the same files, the same search
    # the positives the kept clauses leave unproved are counted as uncovered
    n_box = sum(o.klass == "box" for d in gt_descs for o in d.objects)
    assert only.uncovered["box"] == n_box
    with pytest.raises(InputError, match="needs a prior theory"):
        P.learn_rules(gt_descs, CLASSES, engine="builtin", jobs=1, extend_only=["ramp"])
    with pytest.raises(InputError, match="--extend-only names door"):
        P.learn_rules(gt_descs, CLASSES, engine="builtin", jobs=1, prior=narrow,
                      extend_only=["door"])


def test_a_prior_for_a_class_without_examples_is_refused(gt_descs):
    with pytest.raises(InputError, match="prior theory has rules for door"):
        P.learn_rules(gt_descs, CLASSES, engine="builtin", jobs=1,
                      prior={"door": ("door(A) :- has_plane(A,B).",)})


def test_learn_cli_extends_a_model_and_refuses_what_it_cannot(tmp_path, capsys):
    from planerel.cli import main

    ds = tmp_path / "ds"
    generate_dataset(ds, n_box=3, n_stairs=3, n_ramp=3, seed=5, size=(640, 480), subsample=4)
    base, ext = tmp_path / "base", tmp_path / "ext"
    assert main(["learn", str(ds), "-o", str(base), "--method", "gt", "--cache", "none",
                 "--engine", "builtin"]) == 0
    assert main(["learn", str(ds), "-o", str(ext), "--method", "gt", "--cache", "none",
                 "--engine", "builtin", "--extend", str(base)]) == 0
    import json

    m_base = json.loads((base / "metrics.json").read_text())
    m_ext = json.loads((ext / "metrics.json").read_text())
    assert m_ext["prior_rules"] == m_base["rules"]
    for k, clauses in m_base["rules"].items():
        assert m_ext["rules"][k][:len(clauses)] == clauses
    assert "extending a prior theory" in (ext / "rules.pl").read_text()
    only = tmp_path / "only"
    assert main(["learn", str(ds), "-o", str(only), "--method", "gt", "--cache", "none",
                 "--engine", "builtin", "--extend", str(base), "--extend-only", "ramp"]) == 0
    m_only = json.loads((only / "metrics.json").read_text())
    assert m_only["rules"]["box"] == m_base["rules"]["box"]
    assert m_only["rules"]["stairs"] == m_base["rules"]["stairs"]
    capsys.readouterr()
    # no model there; --folds with --extend: one line each, no model written
    assert main(["learn", str(ds), "-o", str(tmp_path / "x"), "--method", "gt",
                 "--extend", str(tmp_path / "nowhere")]) == 2
    assert "no model folder there" in capsys.readouterr().err
    assert main(["learn", str(ds), "-o", str(tmp_path / "y"), "--method", "gt",
                 "--extend", str(base), "--folds", "3"]) == 2
    assert "no --folds" in capsys.readouterr().err
    assert main(["learn", str(ds), "-o", str(tmp_path / "z"), "--method", "gt",
                 "--extend-only", "ramp"]) == 2
    assert "needs a prior theory" in capsys.readouterr().err
    assert not any((tmp_path / n).exists() for n in ("x", "y", "z"))


def test_a_prior_with_rules_for_other_needs_other_rules(gt_descs):
    """A model learned with --other-rules has rules for ``other``: extending it without them
    would drop those rules without a word."""
    prior = {"box": ("box(A) :- has_plane(A,B).",), "other": ("other(A) :- has_plane(A,B).",)}
    with pytest.raises(InputError, match="--other-rules"):
        P.learn_rules(gt_descs, CLASSES, engine="builtin", jobs=1, prior=prior)


@pytest.mark.real_aleph
@pytest.mark.skipif(not os.environ.get("PLANEREL_ALEPH"),
                    reason="PLANEREL_ALEPH not set (path to the real aleph.pl)")
def test_the_real_aleph_extends_a_theory_from_the_same_files(gt_descs):
    """The extension's files are ordinary Aleph files (the proved positives left out of
    ``.f``): the real Aleph learns from them, and the prior clause stays first."""
    narrow = "box(A) :- has_plane(A,B), orientation(B,inclined)."
    model = P.learn_rules(gt_descs, CLASSES, engine="aleph", jobs=1, prior={"box": (narrow,)})
    assert "aleph" in model.engine.lower()
    assert model.rules["box"][0] == narrow
    assert len(model.rules["box"]) >= 2            # the boxes it leaves get clauses of their own
    preds = P.prolog_predict(model, gt_descs)
    truth = {o.id: o.klass for d in gt_descs for o in d.objects}
    assert sum(p.klass == truth[p.object_id] == "box" for p in preds) >= 3
