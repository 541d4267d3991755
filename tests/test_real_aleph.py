"""The engine ``aleph``: planerel driving the real Aleph (aleph/learner_aleph.pl).

These tests run only when ``PLANEREL_ALEPH`` names Aleph: the classic single file
(``aleph_orig.pl``, everything in module user) or the SWI-Prolog pack's module file
(``aleph.pl``). Run them once with each; the results are in docs/learner.md.
"""

from __future__ import annotations

import os
import re
import shutil
import sys
import time
from pathlib import Path

import pytest

from planerel.cli import main
from planerel.errors import LearnerError
from planerel.ilp.learn import Confusion, aleph_kind, find_aleph, learn

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_real_rules import demo_model  # noqa: E402,F401  (the fixture: make demo's model)

ILP = Path(__file__).parent / "ilp"
ALEPH = os.environ.get("PLANEREL_ALEPH", "")

pytestmark = [
    pytest.mark.real_aleph,
    pytest.mark.skipif(shutil.which("swipl") is None, reason="SWI-Prolog not installed"),
    pytest.mark.skipif(not ALEPH, reason="the real Aleph is not installed here: set "
                                         "PLANEREL_ALEPH=/path/to/aleph.pl to run these tests"),
]


def norm(clause: str) -> str:
    return re.sub(r"\s+", "", clause)


def copy_problem(name: str, dest: Path, extra_b: str = "") -> Path:
    for suffix in (".b", ".f", ".n"):
        text = (ILP / f"{name}{suffix}").read_text()
        (dest / f"{name}{suffix}").write_text(text + (extra_b if suffix == ".b" else ""))
    return dest / name


TRAINS_RULE = norm("eastbound(A) :- has_car(A,B), short(B), closed(B).")


def test_the_file_kind_is_recognised():
    kind, path = find_aleph()
    text = Path(ALEPH).read_text(errors="replace")
    declares_module = re.search(r"^\s*:-\s*module\(\s*aleph\s*,", text, re.MULTILINE) is not None
    assert kind == ("module" if declares_module else "classic") == aleph_kind(path)


def test_trains():
    r = learn(ILP / "trains", engine="aleph", timeout=120)
    assert r.engine == "aleph" and str(Path(ALEPH).resolve()) in r.engine_detail
    assert [norm(c) for c in r.rules] == [TRAINS_RULE]
    assert r.train == Confusion(tp=5, fn=0, fp=0, tn=5)
    assert r.clauses_explored is not None and r.clauses_explored > 0


def test_portray_literals_does_not_change_the_theory(tmp_path):
    """With portray_literals set Aleph prints literals through aleph_portray/1 (English);
    the theory the driver reports is still the clause."""
    portray = "\n".join([
        ":- set(portray_literals, true).",
        "aleph_portray(eastbound(T)) :- write(T), write(' heads east').",
        "aleph_portray(has_car(T, C)) :- write(T), write(' pulls '), write(C).",
        "aleph_portray(short(C)) :- write(C), write(' is a short car').",
        "aleph_portray(closed(C)) :- write(C), write(' has a roof').",
        ""])
    stem = copy_problem("trains", tmp_path, portray)
    r = learn(stem, engine="aleph", timeout=120)
    assert "heads east" in r.output          # Aleph did portray ...
    assert [norm(c) for c in r.rules] == [TRAINS_RULE]   # ... and the rule is still a clause
    assert r.train.accuracy == 1.0


def test_alephs_own_portray_example():
    """Aleph's examples/portray/train.b sets portray_literals itself."""
    stem = Path(ALEPH).parent / "examples" / "portray" / "train"
    if not stem.with_suffix(".b").is_file():
        pytest.skip(f"Aleph's example {stem}.b is not next to {ALEPH}")
    r = learn(stem, engine="aleph", timeout=120)
    assert r.rules and all(":-" in c or c.endswith(".") for c in r.rules)
    assert r.train.accuracy == 1.0


def test_problem_may_define_the_drivers_names(tmp_path):
    """The driver is a module of its own: a background that defines the names of its
    helpers changes nothing (a driver in user, where the classic Aleph and the problem
    live, met Aleph's own examples/2 and read_examples/2 that way)."""
    extra = "\n".join(["covered(x).", "confusion(a, b, c, d, e, f).", "summary(x, y).",
                       "rule_text(a, b, c).", "theory_rule(x).", "collect_theory(x).",
                       "declare_targets(x).", "main.", "run(x).", "learn(x).", ""])
    stem = copy_problem("trains", tmp_path, extra)
    r = learn(stem, engine="aleph", timeout=120)
    assert [norm(c) for c in r.rules] == [TRAINS_RULE]
    assert r.train == Confusion(tp=5, fn=0, fp=0, tn=5)


def test_family_agrees_with_builtin():
    a = learn(ILP / "grandparent", engine="aleph", timeout=120)
    b = learn(ILP / "grandparent", engine="builtin")
    assert [norm(c) for c in a.rules] == [norm(c) for c in b.rules]
    assert a.train == b.train


def test_test_set_and_settings_from_the_command(tmp_path):
    """test_pos / test_neg given as settings are scored; a threshold learned lazily (the
    comparisons also answer with an unbound threshold, which the real Aleph asks for when
    it saturates)."""
    saturate = ("gteq(X, T) :- number(X), var(T), !, T = X.\n"
                "lteq(X, T) :- number(X), var(T), !, T = X.\n")
    for suffix in (".f", ".n"):
        shutil.copy(ILP / f"threshold{suffix}", tmp_path / f"threshold{suffix}")
        shutil.copy(ILP / f"threshold_test{suffix}", tmp_path / f"threshold_test{suffix}")
    text = (ILP / "threshold.b").read_text()
    text = re.sub(r"^:- set\(test_(pos|neg).*\n", "", text, flags=re.MULTILINE)
    (tmp_path / "threshold.b").write_text(text.replace("% Lazy form", saturate + "% Lazy form", 1))
    r = learn(tmp_path / "threshold", engine="aleph", timeout=120,
              settings={"test_pos": str(tmp_path / "threshold_test.f"),
                        "test_neg": str(tmp_path / "threshold_test.n")})
    assert [norm(c) for c in r.rules] == [norm("heavy(A) :- weight(A,B), gteq(B,4.5).")]
    assert r.train.accuracy == 1.0
    assert r.test == Confusion(tp=3, fn=0, fp=0, tn=3)


def test_no_positive_example_gives_an_empty_theory(tmp_path):
    stem = copy_problem("trains", tmp_path)
    (tmp_path / "trains.f").write_text("")
    negatives = len((ILP / "trains.n").read_text().split())
    r = learn(stem, engine="aleph", timeout=120)
    assert r.rules == ()
    assert r.train == Confusion(tp=0, fn=0, fp=0, tn=negatives)


def test_timeout_stops_the_process_group(tmp_path):
    stem = copy_problem("trains", tmp_path, "short(_) :- sleep(30), fail.\n")
    t0 = time.perf_counter()
    with pytest.raises(LearnerError, match="timed out after 2 s"):
        learn(stem, engine="aleph", timeout=2)
    assert time.perf_counter() - t0 < 10


# ------------------------------------------------------------- planerel's own task


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    d = tmp_path_factory.mktemp("ds")
    assert main(["dataset", "synth", str(d), "--n-box", "3", "--n-stairs", "3", "--n-ramp", "3",
                 "--seed", "5", "--quiet"]) == 0
    return d


def test_induce_command_on_an_export(dataset, tmp_path, capsys):
    out = tmp_path / "task"
    assert main(["export-aleph", str(dataset), str(out)]) == 0
    capsys.readouterr()
    assert main(["induce", str(out / "stairs"), "--engine", "aleph"]) == 0
    text = capsys.readouterr().out
    assert "engine: aleph" in text and "accuracy: 1.000" in text
    rules = [ln for ln in text.splitlines() if ln.startswith("stairs(")]
    assert rules


def test_learn_command(dataset, tmp_path, capsys):
    model = tmp_path / "model"
    assert main(["learn", str(dataset), "-o", str(model), "--engine", "aleph", "--method", "gt",
                 "--jobs", "1", "--cache", "none"]) == 0
    out = capsys.readouterr().out
    assert "engine: aleph" in out
    rules = (model / "rules.pl").read_text()
    for k in ("box", "stairs", "ramp"):
        assert re.search(rf"^{k}\(", rules, re.MULTILINE), rules



def test_the_demos_base_box_task_learns_with_the_real_aleph(demo_model):  # noqa: F811
    """``make demo`` with the real Aleph present: its base stage's box task (``samplesize`` 8,
    ``minacc`` 0.85) made Aleph's clause-length check divide 0 by 0 (a clause covering no
    example), which stopped the demo with "Aleph failed: ... zero_divisor" (ilp90). The
    driver now lets that division give NaN (aleph/learner_aleph.pl, ``learn/1``), and the
    task learns rules that prove most of its box examples."""
    base = demo_model.with_name(demo_model.name + "_base") / "aleph" / "box"
    assert base.with_suffix(".b").is_file(), base
    assert "set(samplesize, 8)" in base.with_suffix(".b").read_text()
    r = learn(base, engine="aleph", timeout=300)
    assert r.engine == "aleph" and r.rules
    assert all(c.startswith("box(") for c in r.rules)
    assert r.train.tp > 0.8 * (r.train.tp + r.train.fn)
