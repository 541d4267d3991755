"""Aleph export: STEM.b/.f/.n load in swipl with no warnings; lazy thresholds; bad input."""

from __future__ import annotations

import re
import shutil
import subprocess

import pytest

from planerel.cli import main
from planerel.errors import InputError
from planerel.ilp.aleph_export import aleph_files, check_setting, describe_dataset, export_aleph

SWIPL = shutil.which("swipl") or "/usr/bin/swipl"
pytestmark = pytest.mark.skipif(not shutil.which(SWIPL), reason="swipl not installed")

# Stand-ins for Aleph's directives, and a hook that records every warning and error.
_HARNESS = r"""
:- dynamic planerel_msg/1, a_set/2, a_mode/3, a_det/2, a_lazy/1.
user:message_hook(T, Kind, _) :- memberchk(Kind, [warning, error]), assertz(planerel_msg(T)), fail.
set(N, V) :- assertz(a_set(N, V)).
modeh(R, M) :- assertz(a_mode(h, R, M)).
modeb(R, M) :- assertz(a_mode(b, R, M)).
determination(T, B) :- assertz(a_det(T, B)).
lazy_evaluate(P) :- assertz(a_lazy(P)).
examples(File, Ts) :- setup_call_cleanup(open(File, read, S), terms(S, Ts), close(S)).
terms(S, Ts) :- read_term(S, T, []), ( T == end_of_file -> Ts = [] ; Ts = [T|R], terms(S, R) ).
check(Stem) :-
    atomic_list_concat([Stem, '.b'], B), atomic_list_concat([Stem, '.f'], F),
    atomic_list_concat([Stem, '.n'], N),
    consult(B), examples(F, Pos), examples(N, Neg),
    ( planerel_msg(M) -> format("MSG ~q~n", [M]) ; true ),
    length(Pos, NP), length(Neg, NN),
    aggregate_all(count, a_mode(_, _, _), NM), aggregate_all(count, a_det(_, _), ND),
    forall(member(E, Pos), (arg(1, E, O), obj(O), has_plane(O, _))),
    forall(member(E, Neg), (arg(1, E, O), obj(O))),
    format("~w ~w ~w ~w~n", [NP, NN, NM, ND]).
"""


def _swipl(tmp_path, goal: str) -> str:
    h = tmp_path / "harness.pl"
    h.write_text(_HARNESS)
    proc = subprocess.run([SWIPL, "-q", "-g", goal, "-g", "halt", "-t", "halt(4)", str(h)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == "" and "MSG" not in proc.stdout, proc.stderr + proc.stdout
    return proc.stdout


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    d = tmp_path_factory.mktemp("ds")
    assert main(["dataset", "synth", str(d), "--n-box", "2", "--n-stairs", "2", "--n-ramp", "2",
                 "--seed", "3", "--quiet"]) == 0
    return d


@pytest.fixture(scope="module")
def descs(dataset):
    descs, skipped = describe_dataset(dataset)
    assert skipped == []
    return descs


def test_export_all_loads_without_warnings(tmp_path, descs):
    res = export_aleph(descs, tmp_path, "all")
    assert res.stems == ("box", "ramp", "stairs")
    assert res.counts == {"box": 2, "stairs": 2, "ramp": 2}
    assert len(res.files) == 9
    for stem in res.stems:
        out = _swipl(tmp_path, f"check('{tmp_path / stem}')")
        npos, nneg, nmodes, ndet = map(int, out.split())
        assert (npos, nneg) == (2, 4)
        assert nmodes >= 10 and ndet >= 5
    text = (tmp_path / "stairs.b").read_text()
    assert ":- modeh(1, stairs(+obj))." in text
    assert ":- set(search, heuristic)." in text and ":- set(evalfn, laplace)." in text
    assert ":- lazy_evaluate(lteq/2)." in text
    assert ":- dynamic((has_plane/2" in text
    # one type per numeric attribute
    assert "gteq(+incline, #incline)" in text and "gteq(+height, #height)" in text


def test_multiclass_and_determinism(tmp_path, descs):
    a = aleph_files(descs, "class")
    b = aleph_files(descs, "class")
    assert a == b
    assert ":- modeh(1, class(+obj, #cls))." in a["class.b"]
    assert a["class.f"].count("\n") == 6 and a["class.n"].count("\n") == 12
    export_aleph(descs, tmp_path, "class")
    out = _swipl(tmp_path, f"check('{tmp_path / 'class'}')")
    assert out.split()[:2] == ["6", "12"]


def test_lazy_threshold_protocol(tmp_path, descs):
    export_aleph(descs, tmp_path, "box")
    goal = (f"consult('{tmp_path / 'box.b'}'), "
            "gteq([[2, 3, 4], [0, 1, 1]], T1), writeln(T1), "
            "lteq([[0.1, 0.2, 0.25], [0.4, 0.5]], T2), writeln(T2), "
            "lteq(0.3, T3), writeln(T3), "
            "(lteq(0.3, 0.2) -> writeln(yes) ; writeln(no)), "
            "(gteq(0.3, 0.2) -> writeln(yes) ; writeln(no)), "
            "(gteq([[], [1]], _) -> writeln(yes) ; writeln(no))")
    assert _swipl(tmp_path, goal).split() == ["2", "0.3", "0.3", "no", "yes", "no"]


def test_bad_targets_and_settings(tmp_path, descs):
    with pytest.raises(InputError, match="no examples"):
        aleph_files(descs, "cat")
    one = [d for d in descs if d.objects and d.objects[0].klass == "box"]
    with pytest.raises(InputError, match="at least two classes"):
        aleph_files(one, "box")
    with pytest.raises(InputError, match="illegal value"):
        check_setting("search", "sideways")
    with pytest.raises(InputError, match="unknown or unsupported"):
        check_setting("speed", 3)
    assert check_setting("nodes", "2000") == "2000"
    files = aleph_files(descs, "ramp", settings={"nodes": 100})
    assert ":- set(nodes, 100)." in files["ramp.b"]
    assert len(re.findall(r":- set\(nodes, \d+\)\.", files["ramp.b"])) == 1  # the override replaces the task's
    task = tmp_path / "task.pl"
    task.write_text(":- modeh(1, ramp(+obj)).\n:- modeb(1, nplanes(+obj, -n)).\n")
    with pytest.raises(InputError, match="must not hold modeh"):
        aleph_files(descs, "ramp", task=str(task))


def test_export_command(tmp_path, dataset, capsys):
    out = tmp_path / "task"
    assert main(["export-aleph", str(dataset), str(out), "--target", "stairs"]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["stairs.b", "stairs.f", "stairs.n"]
    assert main(["export-aleph", str(dataset), str(out), "--set", "nodes"]) == 2
    assert "NAME=VALUE" in capsys.readouterr().err


def test_builtin_learner_reads_the_export(tmp_path, descs):
    learn = pytest.importorskip("planerel.ilp.learn")
    export_aleph(descs, tmp_path, "stairs")
    res = learn.learn(str(tmp_path / "stairs"), engine="builtin", timeout=60)
    assert res.rules, res.output
    assert res.train.tp == 2 and res.train.fp == 0


def test_relational_task_learns_stairs_from_pairwise_relations(tmp_path, descs):
    """aleph/modes_relational.pl: no step_up mode; the builtin learner's stairs rule joins
    planes through pairwise relations."""
    learn = pytest.importorskip("planerel.ilp.learn")
    files = aleph_files(descs, "stairs", task="modes_relational.pl")
    b = files["stairs.b"]
    assert "step_up(+" not in b
    for mode in ("adjacent(+plane, -plane)", "parallel(+plane, -plane)",
                 "perpendicular(+plane, -plane)", "above(+plane, -plane)",
                 "angle(+plane, +plane, -angle)", "gap(+plane, +plane, -gap)",
                 "rise(+plane, +plane, -rise)", "area(+plane, -area)",
                 "plane_length(+plane, -plength)", "plane_width(+plane, -pwidth)",
                 "gteq(+gap, #gap)", "lteq(+angle, #angle)"):
        assert f"modeb(1, {mode})" in b or f"modeb(*, {mode})" in b, mode
    export_aleph(descs, tmp_path, "stairs", task="modes_relational.pl")
    out = _swipl(tmp_path, f"check('{tmp_path / 'stairs'}')")
    assert out.split()[:2] == ["2", "4"]
    res = learn.learn(str(tmp_path / "stairs"), engine="builtin", timeout=60)
    assert res.train.tp == 2 and res.train.fp == 0
    pairwise = ("adjacent(", "parallel(", "perpendicular(", "above(", "angle(", "gap(", "rise(")
    assert any(p in r for r in res.rules for p in pairwise), res.rules


def test_step_up_task_is_optional(tmp_path, descs):
    """The hand-written detector is a mode only in aleph/modes_objects.pl (--task)."""
    learn = pytest.importorskip("planerel.ilp.learn")
    default = aleph_files(descs, "stairs")["stairs.b"]
    assert "step_up(+" not in default and "parallel(+plane, -plane)" in default
    export_aleph(descs, tmp_path, "stairs", task="modes_objects.pl")
    text = (tmp_path / "stairs.b").read_text()
    assert "modeb(*, step_up(+plane, -plane))" in text and "parallel(+plane" not in text
    res = learn.learn(str(tmp_path / "stairs"), engine="builtin", timeout=60)
    assert res.train.tp == 2 and res.train.fp == 0
    assert any("step_up(" in r for r in res.rules), res.rules
