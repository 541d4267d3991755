"""Background predicates of the user's own (``planerel learn --background FILE``): checked as
data before any scene is described, given to the learners in ``STEM.b``, carried by the model
(``background.pl``, its SHA-256 in ``model.json``) and loaded with the rules wherever they are
queried, with the same check (docs/learner.md, "Background predicates of your own")."""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from planerel.cli import main
from planerel.errors import InputError
from planerel.ilp.aleph_export import check_task_vocabulary
from planerel.ilp.background import read_background

pytestmark = pytest.mark.skipif(shutil.which("swipl") is None, reason="SWI-Prolog not installed")

TASK = """:- set(clauselength, 3).
:- set(minpos, 2).
:- modeb(*, has_plane(+obj, -plane)).
:- modeb(1, sloped(+plane)).
:- modeb(1, levels(+obj)).
:- modeb(1, flat_top(+obj)).
"""

BACKGROUND = """% background predicates of my own
sloped(P) :- slope(P, S), S >= 15, S =< 40.
levels(O) :- nhorizontal(O, N), N >= 2.
flat_top(O) :- nhorizontal(O, 1), \\+ ( has_plane(O, P), sloped(P) ).
% a bounded chain of adjacent planes: recursion is allowed
chain(A, B, 1) :- adjacent(A, B).
chain(A, C, N) :- N > 1, adjacent(A, B), M is N - 1, chain(B, C, M).
"""

RULES = {"box": ["box(A) :- flat_top(A)."], "stairs": ["stairs(A) :- levels(A)."],
         "ramp": ["ramp(A) :- has_plane(A,B), sloped(B)."]}


def _cli(*args, env=None):
    return subprocess.run([sys.executable, "-m", "planerel.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=300, env=env)


@pytest.fixture(scope="module")
def learned(tmp_path_factory):
    """3 scenes a class, ground-truth planes, planerel's learner, a task whose modes are the
    background's predicates (and has_plane/2), 3-fold cross-validation."""
    root = tmp_path_factory.mktemp("bg")
    ds = root / "ds"
    assert main(["dataset", "synth", str(ds), "--n-box", "3", "--n-stairs", "3", "--n-ramp", "3",
                 "--subsample", "8", "--quiet"]) == 0
    (root / "task.pl").write_text(TASK)
    (root / "bg.pl").write_text(BACKGROUND)
    model = root / "model"
    assert main(["learn", str(ds), "-o", str(model), "--task", str(root / "task.pl"),
                 "--background", str(root / "bg.pl"), "--engine", "builtin", "-j", "1",
                 "--method", "gt", "--cache", str(root / "cache"), "--folds", "3"]) == 0
    return root


def test_learned_rules_call_the_background_and_the_model_carries_it(learned):
    model = learned / "model"
    assert sorted(p.name for p in model.iterdir()) == ["aleph", "background.pl", "confusion.png",
                                                       "metrics.json", "model.json", "rules.pl"]
    metrics = json.loads((model / "metrics.json").read_text())
    assert metrics["rules"] == RULES
    assert metrics["rule_stats"] == [[1, "box", 3, 0], [2, "stairs", 3, 0], [3, "ramp", 3, 0]]
    # every fold learned and answered with it too (one fold's ramp rule missed a ramp)
    assert metrics["cross_validation"]["confusion"] == [[3, 0, 0, 0], [0, 3, 0, 0], [0, 0, 2, 1]]
    assert metrics["background"] == str(learned / "bg.pl")
    data = (learned / "bg.pl").read_bytes()
    assert (model / "background.pl").read_bytes() == data
    assert json.loads((model / "model.json").read_text())["background"] == {
        "file": "background.pl", "sha256": hashlib.sha256(data).hexdigest()}
    for stem in ("box", "stairs", "ramp"):  # the learner's STEM.b: after the derived relations
        b = (model / "aleph" / f"{stem}.b").read_text()
        assert BACKGROUND.rstrip() in b
        assert b.index("% ---- derived relations") < b.index("flat_top(O) :-") \
            < b.index("% ---- scene facts")
        assert f":- determination({stem}/1, flat_top/1)." in b


def test_classify_answers_through_the_background(learned):
    ds = learned / "ds"
    r = _cli("classify", learned / "model", ds / "s0006.depth.png", ds / "s0001.depth.png",
             ds / "s0004.depth.png", "--json")
    assert r.returncode == 0, r.stderr
    answers = [[(o["class"], o["rule"], o["bindings"]) for o in s["objects"]]
               for s in json.loads(r.stdout)]
    assert answers == [
        [("ramp", "ramp(A) :- has_plane(A,B),sloped(B).", {"A": "s0006_o1", "B": "s0006_p02"})],
        [("box", "box(A) :- flat_top(A).", {"A": "s0001_o1"})],
        [("other", None, {}), ("stairs", "stairs(A) :- levels(A).", {"A": "s0004_o2"})]]


def test_a_model_without_background_writes_what_it_wrote(tmp_path):
    from planerel.ilp.model_settings import training_settings

    assert "background" not in training_settings("regiongrow", {})
    entry = {"file": "background.pl", "sha256": "0" * 64}
    with_bg = training_settings("regiongrow", {}, background=entry)
    assert with_bg.pop("background") == entry and with_bg == training_settings("regiongrow", {})


def test_the_modeb_of_a_background_predicate_passes_the_vocabulary_check(tmp_path):
    (tmp_path / "task.pl").write_text(TASK)
    (tmp_path / "bg.pl").write_text(BACKGROUND)
    with pytest.raises(InputError, match=r"modeb on sloped/1, levels/1, flat_top/1, which are "
                                         r"not planerel's vocabulary"):
        check_task_vocabulary(str(tmp_path / "task.pl"))
    bg = read_background(tmp_path / "bg.pl")
    assert bg.predicates == (("chain", 3), ("flat_top", 1), ("levels", 1), ("sloped", 1))
    check_task_vocabulary(str(tmp_path / "task.pl"), bg)
    (tmp_path / "bg2.pl").write_text("sloped(P) :- slope(P, S), S >= 15.\n")
    with pytest.raises(InputError, match=r"modeb on levels/1, flat_top/1, which are not "
                                         r"planerel's vocabulary .*nor defined in .*bg2\.pl"):
        check_task_vocabulary(str(tmp_path / "task.pl"), read_background(tmp_path / "bg2.pl"))


BAD = {
    "directive": ("big(P) :- area(P, A), A >= 0.5.\n:- initialization(shell('touch pwned')).\n",
                  r"bg\.pl:2: directive :-initialization shell\('touch pwned'\) refused: a "
                  r"background file holds clauses only"),
    "unknown": ("% mine\nbig(P) :- area(P, A), A >= 0.5.\n\nhuge(P) :- big(P), enormous(P).\n",
                r"bg\.pl:4: the rule calls enormous/1, which is neither planerel's vocabulary "
                r"nor a predicate this file defines nor a safe built-in"),
    "redefine": ("big(P) :- area(P, A), A >= 0.5.\narea(p1, 9.0).\n",
                 r"bg\.pl:2: the clause redefines area/2, which is planerel's vocabulary"),
    "syntax": ("big(P) :- area(P, A), A >= 0.5.\n\nsmall(P) :- area(P, A) A < 0.1.\n",
               r"bg\.pl:3: syntax error: operator_expected"),
    "builtin": ("big(P) :- area(P, A), A >= 0.5.\nhalt(P) :- big(P).\n",
                r"bg\.pl:2: the clause defines halt/1, a built-in, library or planerel predicate"),
    "shell": ("big(P) :- area(P, A), A >= 0.5, shell('touch pwned').\n",
              r"bg\.pl:1: the rule calls shell/1, which is neither planerel's vocabulary"),
}


@pytest.mark.parametrize("kind", sorted(BAD))
def test_a_bad_background_file_is_refused_with_file_and_line(kind, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    text, message = BAD[kind]
    (tmp_path / "bg.pl").write_text(text)
    with pytest.raises(InputError, match=message) as info:
        read_background(tmp_path / "bg.pl")
    assert "\n" not in str(info.value) and str(info.value).startswith(str(tmp_path / "bg.pl"))
    assert not (tmp_path / "pwned").exists()


@pytest.mark.parametrize("command", ["learn", "export-aleph"])
def test_the_commands_refuse_a_bad_background_before_describing(tmp_path, command):
    (tmp_path / "bg.pl").write_text(BAD["unknown"][0])
    out = tmp_path / "out"
    args = ([tmp_path / "no_dataset", out] if command == "export-aleph"
            else [tmp_path / "no_dataset", "-o", out])
    r = _cli(command, *args, "--background", tmp_path / "bg.pl")
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and f"{tmp_path / 'bg.pl'}:4: the rule calls enormous/1" in lines[0], \
        r.stderr
    assert not out.exists()


def test_export_aleph_writes_the_background_into_every_stem(learned, tmp_path):
    out = tmp_path / "out"
    assert main(["export-aleph", str(learned / "ds"), str(out), "--task", str(learned / "task.pl"),
                 "--background", str(learned / "bg.pl")]) == 0
    assert sorted(p.name for p in out.iterdir()) == [f"{s}.{e}" for s in ("box", "ramp", "stairs")
                                                     for e in ("b", "f", "n")]
    for stem in ("box", "ramp", "stairs"):
        b = (out / f"{stem}.b").read_text()
        assert f"% ---- background predicates of your own (--background {learned / 'bg.pl'})\n" \
               + BACKGROUND.rstrip() + "\n" in b
        assert f":- determination({stem}/1, sloped/1)." in b


def test_a_background_predicate_named_as_a_target_is_refused(learned):
    """A class C of the task is the learner's predicate C/1 (class/2 for the multi-class task):
    the background may not define it."""
    from planerel.ilp.aleph_export import aleph_files, describe_dataset
    from planerel.ilp.background import Background

    descs, _ = describe_dataset(learned / "ds")
    box = Background("mine.pl", "box(O) :- nplanes(O, N), N >= 1.\n", (("box", 1),))
    with pytest.raises(InputError, match=r"^mine\.pl defines box/1, the target of the learning "
                                         r"task; rename it$"):
        aleph_files(descs, "stairs", background=box)
    klass = Background("mine.pl", "class(O, box) :- nplanes(O, N), N >= 1.\n", (("class", 2),))
    with pytest.raises(InputError, match=r"^mine\.pl defines class/2, the target"):
        aleph_files(descs, "class", background=klass)
    assert "class(O, box) :-" in aleph_files(descs, "box", background=klass)["box.b"]


def _copy(learned, tmp_path) -> Path:
    model = tmp_path / "model"
    shutil.copytree(learned / "model", model)
    return model


def test_a_model_whose_background_was_edited_is_refused(learned, tmp_path):
    from planerel.classify.classifier import Classifier

    model = _copy(learned, tmp_path)
    with (model / "background.pl").open("a") as fh:
        fh.write("levels(O) :- nplanes(O, N), N >= 1.\n")
    with pytest.raises(InputError, match=r"background\.pl: the model's background file was "
                                         r"changed after learning \(its SHA-256 is not the one "
                                         r"model\.json records\)"):
        Classifier(model)
    r = _cli("classify", model, learned / "ds" / "s0001.depth.png")
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1
    assert "changed after learning" in r.stderr and r.stdout == ""
    (model / "background.pl").unlink()
    with pytest.raises(InputError, match=r"background\.pl: the model's background file is "
                                         r"missing or unreadable"):
        Classifier(model)


def test_a_model_whose_background_is_unsafe_is_refused_at_load(learned, tmp_path):
    """model.json's hash made to match: the clauses are still checked, as when learning."""
    from planerel.classify.classifier import Classifier

    model = _copy(learned, tmp_path)
    marker = tmp_path / "pwned"
    text = BACKGROUND + f"levels(O) :- shell('touch {marker}').\n"
    (model / "background.pl").write_text(text)
    settings = json.loads((model / "model.json").read_text())
    settings["background"]["sha256"] = hashlib.sha256(text.encode()).hexdigest()
    (model / "model.json").write_text(json.dumps(settings))
    with pytest.raises(InputError, match=r"model/background\.pl:8: the rule calls shell/1"):
        Classifier(model)
    assert not marker.exists()


def test_extending_a_model_keeps_its_background(learned, tmp_path):
    """--extend of a model with a background: its background is the run's when none is given
    (the prior rules call its predicates)."""
    out = tmp_path / "ext"
    assert main(["learn", str(learned / "ds"), "-o", str(out), "--task", str(learned / "task.pl"),
                 "--extend", str(learned / "model"), "--engine", "builtin", "-j", "1",
                 "--method", "gt", "--cache", str(learned / "cache")]) == 0
    assert (out / "background.pl").read_bytes() == (learned / "bg.pl").read_bytes()
    assert json.loads((out / "metrics.json").read_text())["rules"] == RULES


def test_a_members_model_carries_the_background_in_every_member(learned, tmp_path):
    out = tmp_path / "mm"
    assert main(["learn", str(learned / "ds"), "-o", str(out), "--task", str(learned / "task.pl"),
                 "--background", str(learned / "bg.pl"), "--engine", "builtin", "-j", "1",
                 "--method", "gt", "--cache", str(learned / "cache"), "--members", "3",
                 "--set", "minpos=1"]) == 0
    data = (learned / "bg.pl").read_bytes()
    for n in (1, 2, 3):
        member = out / "members" / str(n)
        assert (member / "background.pl").read_bytes() == data
        assert json.loads((member / "model.json").read_text())["background"]["sha256"] == \
            hashlib.sha256(data).hexdigest()
        assert json.loads((member / "metrics.json").read_text())["rules"] == RULES
    assert not (out / "background.pl").exists()  # the members' folders are the models
    r = _cli("classify", out, learned / "ds" / "s0006.depth.png", "--json")
    assert r.returncode == 0, r.stderr
    [[answer]] = [s["objects"] for s in json.loads(r.stdout)]
    assert (answer["class"], answer["rule"]) == ("ramp", "ramp(A) :- has_plane(A,B),sloped(B).")


def _hand_model(folder: Path, rules: str, background: str) -> Path:
    from planerel.ilp.model_settings import training_settings

    folder.mkdir()
    (folder / "rules.pl").write_text(rules)
    (folder / "background.pl").write_text(background)
    entry = {"file": "background.pl", "sha256": hashlib.sha256(background.encode()).hexdigest()}
    (folder / "model.json").write_text(json.dumps(training_settings("regiongrow", {},
                                                                    background=entry)))
    return folder


@pytest.fixture(scope="module")
def stairs_scene():
    from planerel.synth.generator import generate_scene

    return generate_scene("stairs", seed=11, size=(640, 480), subsample=4, steps=4,
                          sides="open", walls=0)


def test_two_models_with_one_predicate_name_each_answer_with_their_own(tmp_path, stairs_scene):
    """Each model's background lives in its model's module: two definitions of mine/1 in one
    process, used in turn, and one model closed."""
    from planerel.classify.classifier import Classifier

    cloud = stairs_scene.cloud
    rules = "box(A) :- mine(A).\n"
    yes = _hand_model(tmp_path / "yes", rules, "mine(O) :- nplanes(O, N), N >= 1.\n")
    no = _hand_model(tmp_path / "no", rules, "mine(O) :- nplanes(O, N), N >= 1000.\n")
    a, b = Classifier(yes), Classifier(no)
    for clf, klass in [(a, "box"), (b, "other"), (a, "box"), (b, "other")]:
        objects = clf.classify(cloud, scene_id="s0001").objects
        assert objects and {o.klass for o in objects} == {klass}
    a.close()
    assert {o.klass for o in b.classify(cloud).objects} == {"other"}
    c = Classifier(yes)
    assert {o.klass for o in c.classify(cloud).objects} == {"box"}
    for clf in (b, c):
        clf.close()


def test_a_background_predicate_that_never_ends_is_stopped(tmp_path, stairs_scene, capfd):
    """Recursion is allowed, so a proof may not end: classify stops it (an inference limit, a
    warning) and answers with the other rules; the rule query of learning says so."""
    from planerel.classify.classifier import Classifier
    from planerel.errors import PrologError
    from planerel.features.facts import describe_scene
    from planerel.ilp import pipeline as P
    from planerel.ilp.background import Background

    loop = "deep(X) :- deep(X).\n"
    rules = "box(A) :- deep(A).\nramp(A) :- nplanes(A, N), N >= 1.\n"
    with Classifier(_hand_model(tmp_path / "m", rules, loop)) as clf:
        objects = clf.classify(stairs_scene.cloud).objects
    assert objects and {(o.klass, o.rule) for o in objects} == {
        ("ramp", "ramp(A) :- nplanes(A,N),N>=1.")}
    assert "stopped after 10,000,000 inferences" in capfd.readouterr().err
    model = P.Model(("box", "ramp"), {"box": ("box(A) :- deep(A).",), "ramp": ()},
                    background=Background("mine.pl", loop, (("deep", 1),)))
    desc = describe_scene(stairs_scene.cloud, stairs_scene.gt_labels, scene_id="s0001")
    with pytest.raises(PrologError, match="stopped after 10,000,000 inferences"):
        P.prolog_predict(model, [desc], [o.id for o in desc.objects])


@pytest.mark.real_aleph
@pytest.mark.skipif(not os.environ.get("PLANEREL_ALEPH"), reason="the real Aleph is not installed "
                    "here: set PLANEREL_ALEPH=/path/to/aleph.pl to run this test")
def test_the_real_aleph_learns_with_the_background(learned, tmp_path):
    out = tmp_path / "m"
    r = _cli("learn", learned / "ds", "-o", out, "--task", learned / "task.pl",
             "--background", learned / "bg.pl", "--engine", "aleph", "-j", "1", "--method", "gt",
             "--cache", learned / "cache")
    assert r.returncode == 0, r.stderr
    assert json.loads((out / "metrics.json").read_text())["rules"] == RULES
