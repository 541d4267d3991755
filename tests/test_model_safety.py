"""A model file is data: malicious models run nothing, paths and names never become code,
and any number of models coexist in one process, each answering with its own rules."""

from __future__ import annotations

import subprocess

import pytest

from planerel.errors import InputError, PrologError
from planerel.ilp import pipeline as P
from planerel.ilp.prolog import DERIVED_PREDICATES, support_files

ANY_OBJECT = "nplanes(O, N), gteq(N, 1)"  # true of every object proposal


@pytest.fixture(scope="module")
def stairs_scene():
    from planerel.synth.generator import generate_scene

    return generate_scene("stairs", seed=11, size=(640, 480), subsample=4, steps=4,
                          sides="open", walls=0)


def _model(path, text):
    path.write_text(text)
    return path


# ------------------------------------------------------------------ malicious model files

MALICIOUS = {
    "directive": ":- shell('touch {m}').\nbox(O) :- " + ANY_OBJECT + ".\n",
    "initialization": ":- initialization(shell('touch {m}')).\nbox(O) :- " + ANY_OBJECT + ".\n",
    "body": "box(O) :- " + ANY_OBJECT + ", shell('touch {m}').\n",
    "body_nested": "box(O) :- ( " + ANY_OBJECT + " ; \\+ shell('touch {m}') ).\n",
    "call_variable": "box(O) :- G = shell('touch {m}'), call(G).\n",
    "head_shell": "shell(O) :- " + ANY_OBJECT + ".\n",
    "head_halt": "halt(O) :- " + ANY_OBJECT + ".\n",
    "head_not_a_class": "foo(O, P) :- " + ANY_OBJECT + ".\n",
}


@pytest.mark.parametrize("kind", sorted(MALICIOUS))
def test_malicious_model_runs_nothing_in_classify(kind, tmp_path, stairs_scene):
    from planerel.classify.classifier import Classifier

    marker = tmp_path / "pwned"
    rules = _model(tmp_path / "rules.pl", MALICIOUS[kind].format(m=marker))
    with pytest.raises(InputError, match=r"rules\.pl:\d+: ") as info:
        Classifier(rules)
    assert "\n" not in str(info.value)
    assert not marker.exists()


@pytest.mark.parametrize("kind", ["directive", "initialization", "body"])
def test_malicious_rules_run_nothing_in_the_rule_query(kind, tmp_path, stairs_scene):
    """The learner's rule query (its own swipl) reads the model as data as well."""
    from planerel.features.facts import describe_scene

    marker = tmp_path / "pwned"
    text = MALICIOUS[kind].format(m=marker)
    clause = [ln for ln in text.splitlines() if ln.startswith("box(")]
    model = P.Model(("box", "ramp"), {"box": tuple(clause), "ramp": ()})
    if kind != "body":  # a directive smuggled in as a "rule" of the Model
        model = P.Model(("box", "ramp"), {"box": (text.splitlines()[0], *clause), "ramp": ()})
    desc = describe_scene(stairs_scene.cloud, stairs_scene.gt_labels, scene_id="s0001")
    with pytest.raises(InputError, match="refused|neither planerel's vocabulary"):
        P.prolog_predict(model, [desc], [o.id for o in desc.objects] or ["s0001_o1"])
    assert not marker.exists()


def test_refused_clause_names_file_and_line(tmp_path):
    from planerel.classify.classifier import Classifier

    rules = _model(tmp_path / "rules.pl", "% comment\nbox(O) :- " + ANY_OBJECT + ".\n\n"
                   "ramp(O) :- " + ANY_OBJECT + ", open('/etc/passwd', read, _).\n")
    with pytest.raises(InputError, match=r"rules\.pl:4: the rule calls open/3"):
        Classifier(rules)


def test_old_model_header_is_accepted_and_syntax_error_is_prolog_error(tmp_path):
    from planerel.classify.classifier import Classifier

    header = (":- dynamic(planerel_rule_stats/4).\n:- multifile(planerel_rule_stats/4).\n"
              ":- style_check(-singleton).\n")
    ok = Classifier(_model(tmp_path / "a.pl", header + "box(O) :- " + ANY_OBJECT + ".\n"
                           "planerel_rule_stats(1, box, 3, 0).\n"))
    assert ok.classes == ("box",) and ok.stats == ((1, "box", 3, 0),)
    with pytest.raises(PrologError, match=r"b\.pl:2: not a valid rules file"):
        Classifier(_model(tmp_path / "b.pl", "box(O) :- nplanes(O, N).\nbox(O) :- .\n"))


def test_cofire_facts_are_read_as_data_and_checked(tmp_path):
    from planerel.classify.classifier import Classifier

    header = (":- dynamic(planerel_rule_cofire/4).\n:- multifile(planerel_rule_cofire/4).\n")
    ok = Classifier(_model(tmp_path / "a.pl", header + "box(O) :- " + ANY_OBJECT + ".\n"
                           "planerel_rule_cofire(1, 2, other, 4).\n"))
    assert ok.cofire == ((1, 2, "other", 4),)
    with pytest.raises(InputError, match=r"c\.pl:2: planerel_rule_cofire/4 needs"):
        Classifier(_model(tmp_path / "c.pl", "box(O) :- " + ANY_OBJECT + ".\n"
                          "planerel_rule_cofire(1, X, box, 4).\n"))


@pytest.mark.parametrize("name", ["halt", "shell", "atom", "is_list", "horizontal", "adjacent"])
def test_class_names_may_not_clash_with_predicates(name):
    from planerel.ilp.aleph_export import check_class_names

    with pytest.raises(InputError, match=f"class name '{name}' is a"):
        check_class_names(["box", name])
    check_class_names(["box", "stairs", "ramp", "cupboard"])  # ordinary names pass


# ------------------------------------------------------------------ isolated models


def test_two_models_interleaved_each_answer_with_their_own_rules(tmp_path, stairs_scene):
    """c1 and c2 fire for every object; c1 calls it stairs, c2 calls it ramp, whatever the
    order in which they are used and created."""
    from planerel.classify.classifier import Classifier

    a = Classifier(_model(tmp_path / "a.pl", f"stairs(O) :- {ANY_OBJECT}.\n"
                          "planerel_rule_stats(1, stairs, 5, 0).\n"))
    b = Classifier(_model(tmp_path / "b.pl", f"ramp(O) :- {ANY_OBJECT}.\n"
                          "planerel_rule_stats(1, ramp, 2, 1).\n"))
    cloud = stairs_scene.cloud
    for clf, klass in [(a, "stairs"), (b, "ramp"), (a, "stairs"), (b, "ramp")]:
        ans = clf.classify(cloud, scene_id="s0001")
        assert ans.objects, "the scene has an object proposal"
        assert {o.klass for o in ans.objects} == {klass}
        assert all(o.rule.startswith(klass + "(") for o in ans.objects)
    assert a.stats == ((1, "stairs", 5, 0),) and b.stats == ((1, "ramp", 2, 1),)
    c = Classifier(_model(tmp_path / "c.pl", f"box(O) :- {ANY_OBJECT}.\n"))  # a third one
    assert {o.klass for o in a.classify(cloud).objects} == {"stairs"}
    assert {o.klass for o in c.classify(cloud).objects} == {"box"}
    b.close()
    assert {o.klass for o in a.classify(cloud).objects} == {"stairs"}
    with pytest.raises(InputError, match="closed"):
        b.classify(cloud)


# ------------------------------------------------------------------ paths never pasted into goals


def test_rule_query_with_quotes_in_temp_folder(tmp_path, monkeypatch, stairs_scene):
    """A TMPDIR with a quote (and a crafted one that would run a command if pasted into a
    goal) changes nothing: the paths reach swipl as data."""
    import tempfile

    from planerel.features.facts import describe_scene

    monkeypatch.chdir(tmp_path)
    marker = tmp_path / "pwned"
    crafted = tmp_path / "x'), shell('touch pwned'), ('"
    crafted.mkdir()
    desc = describe_scene(stairs_scene.cloud, stairs_scene.gt_labels, scene_id="s0001")
    objs = [o.id for o in desc.objects]
    model = P.Model(("stairs", "box"), {"stairs": (f"stairs(O) :- {ANY_OBJECT}.",), "box": ()})
    monkeypatch.setattr(tempfile, "tempdir", str(crafted))
    preds = P.prolog_predict(model, [desc], objs)
    assert [p.klass for p in preds] == ["stairs"] * len(objs)
    assert not marker.exists()


def test_vocabulary_lists_every_predicate_of_the_support_files():
    """DERIVED_PREDICATES is what derived.pl and compare.pl define (apart from planerel_*
    helpers): asked of swipl, not copied from the code."""
    files = [str(p) for p in support_files() if p.name in ("derived.pl", "compare.pl")]
    goal = ("current_prolog_flag(argv, Fs), forall(member(F, Fs), load_files(F, [silent(true)])), "
            "forall(( member(F, Fs), source_file(user:H, F), functor(H, N, A), "
            "\\+ sub_atom(N, 0, _, _, planerel_) ), (write(N/A), nl))")
    out = subprocess.run(["swipl", "-q", "-g", goal, "-t", "halt", "--", *files],
                         capture_output=True, text=True, timeout=60, check=True).stdout
    found = {(ln.split("/")[0], int(ln.split("/")[1])) for ln in out.split()}
    assert found == set(DERIVED_PREDICATES)


def test_model_header_with_a_non_utf8_path_is_written_as_ascii():
    text = P.Model(("box", "ramp"), {"box": (), "ramp": ()}).text("learned from /data/set\udcff")
    assert "% learned from /data/set?" in text
    text.encode("ascii")  # raises if anything is left that a file system could refuse
