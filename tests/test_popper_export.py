"""export-popper: bk.pl and exs.pl load in SWI-Prolog, bias.pl grounds in clingo (as Popper reads
it) and follows Popper's documented format; the bias admits rules that separate the classes."""

from __future__ import annotations

import re
import shutil
import subprocess

import pytest

from planerel.cli import main
from planerel.errors import InputError
from planerel.ilp.aleph_export import describe_dataset
from planerel.ilp.popper_export import BODY_PREDICATES, export_popper, popper_files

SWIPL = shutil.which("swipl")
pytestmark = pytest.mark.skipif(SWIPL is None, reason="swipl not installed")

N = {"box": 3, "stairs": 3, "ramp": 3}


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    d = tmp_path_factory.mktemp("ds")
    assert main(["dataset", "synth", str(d), "--n-box", "3", "--n-stairs", "3", "--n-ramp", "3",
                 "--seed", "5", "--quiet"]) == 0
    return d


@pytest.fixture(scope="module")
def tasks(dataset, tmp_path_factory):
    descs, skipped = describe_dataset(dataset)
    assert skipped == []
    out = tmp_path_factory.mktemp("popper")
    folders = export_popper(descs, out)
    return descs, {f.name: f for f in folders}


def swipl(goal: str, *files) -> str:
    proc = subprocess.run([SWIPL, "-q", "--on-warning=status", "--on-error=status", "-g", goal,
                           "-t", "halt", "--", *map(str, files)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == "", proc.stderr
    return proc.stdout


# bk.pl loaded, then every term of exs.pl read: prints "pos|neg Head Object has_planes".
_READ_EXAMPLES = """
current_prolog_flag(argv, [Bk, Exs]), consult(Bk),
setup_call_cleanup(open(Exs, read, S),
  ( repeat, read_term(S, T, []),
    ( T == end_of_file -> !
    ; T =.. [Sign, E], E =.. [H, O], aggregate_all(count, has_plane(O, _), NP),
      format("~w ~w ~w ~w~n", [Sign, H, O, NP]), fail ) ),
  close(S))
"""


def test_one_folder_per_class_with_three_files(tasks):
    _, folders = tasks
    assert sorted(folders) == ["box", "ramp", "stairs"]
    for f in folders.values():
        assert sorted(p.name for p in f.iterdir()) == ["bias.pl", "bk.pl", "exs.pl"]


@pytest.mark.parametrize("target", ["box", "stairs", "ramp"])
def test_bk_and_examples_load_in_swipl(tasks, target):
    _, folders = tasks
    out = swipl(_READ_EXAMPLES, folders[target] / "bk.pl", folders[target] / "exs.pl")
    rows = [ln.split() for ln in out.splitlines()]
    assert {r[1] for r in rows} == {target}
    assert sum(r[0] == "pos" for r in rows) == N[target]
    assert sum(r[0] == "neg" for r in rows) == sum(N.values()) - N[target]
    assert {r[0] for r in rows} == {"pos", "neg"}
    assert len({r[2] for r in rows}) == len(rows)          # every object once
    assert all(int(r[3]) >= 1 for r in rows)                # with its planes in bk.pl


def _bias_atoms(path):
    clingo = pytest.importorskip("clingo", reason="clingo (Popper's grounder) is not installed")
    ctl = clingo.Control(["--warn=none"])
    ctl.add("base", [], path.read_text())
    ctl.ground([("base", [])])
    atoms = {}
    for a in ctl.symbolic_atoms:
        atoms.setdefault(a.symbol.name, []).append(a.symbol.arguments)
    return atoms


def _tuple(sym):
    return [str(x) for x in sym.arguments]


def test_bias_follows_poppers_format(tasks):
    """head_pred/2, body_pred/2, type/2 and direction/2 (tuples as in Popper's documentation,
    (t,) for one argument), max_vars/max_body/max_clauses; every body predicate is defined in
    bk.pl with that arity."""
    _, folders = tasks
    atoms = _bias_atoms(folders["stairs"] / "bias.pl")
    assert [[str(x) for x in a] for a in atoms["head_pred"]] == [["stairs", "1"]]
    body = {str(a[0]): a[1].number for a in atoms["body_pred"]}
    assert body == {n: a for n, a, _, _ in BODY_PREDICATES}
    types = {str(a[0]): _tuple(a[1]) for a in atoms["type"]}
    dirs = {str(a[0]): _tuple(a[1]) for a in atoms["direction"]}
    arity = dict(body, stairs=1)
    assert set(types) == set(dirs) == set(arity)
    for p, n in arity.items():
        assert len(types[p]) == n and len(dirs[p]) == n, p
        assert set(dirs[p]) <= {"in", "out"}
    assert types["stairs"] == ["obj"] and dirs["stairs"] == ["in"]
    # every input argument has a type some other literal (or the head) can produce
    produced = {"obj"} | {t for p in body for t, d in zip(types[p], dirs[p], strict=True) if d == "out"}
    assert all(t in produced for p in body for t, d in zip(types[p], dirs[p], strict=True) if d == "in")
    for key in ("max_vars", "max_body", "max_clauses"):
        assert len(atoms[key]) == 1 and atoms[key][0][0].number >= 1
    text = (folders["stairs"] / "bias.pl").read_text()
    assert "type(horizontal,(plane,))." in text      # Popper's spelling of a 1-tuple
    defined = swipl("current_prolog_flag(argv, [Bk]), consult(Bk), forall(member(P/A, ["
                    + ", ".join(f"{n}/{a}" for n, a in body.items())
                    + "]), (functor(G, P, A), (predicate_property(G, defined) -> true ; "
                    "format('undefined ~w/~w~n', [P, A]))))", folders["stairs"] / "bk.pl")
    assert defined == ""


_SCORE = """
current_prolog_flag(argv, [Bk, Exs, Rule]), consult(Bk), term_string(R, Rule), assertz(R),
read_file_to_terms(Exs, Ts, []),
aggregate_all(count, (member(pos(E), Ts), once(E)), TP),
aggregate_all(count, (member(neg(E), Ts), once(E)), FP),
format("~w ~w~n", [TP, FP])
"""


@pytest.mark.parametrize("target, rule", [
    # a box shows exactly one horizontal plane (its top) and has no inclined plane
    ("box", "box(A) :- nhorizontal(A,B), one(B), ninclined(A,C), zero(C)"),
    # a staircase has two horizontal treads at different heights (one rise, >= 12 cm, apart);
    # a box has one horizontal plane, a ramp at most its platform
    ("stairs", "stairs(A) :- has_plane(A,B), horizontal(B), above(B,C), horizontal(C)"),
    ("ramp", "ramp(A) :- has_plane(A,B), inclined(B)"),
    # the shipped model's stairs rule, through the relations the bias declares since ilp90
    ("stairs", "stairs(A) :- has_plane(A,B), parallel(B,C), stair_step(C,B)"),
])
def test_the_bias_admits_rules_that_separate_the_classes(tasks, target, rule):
    """Rules within the bias (its predicates, types, directions and bounds) derived from the
    generator's geometry cover every positive and no negative on these files."""
    _, folders = tasks
    atoms = _bias_atoms(folders[target] / "bias.pl")
    body = re.findall(r"([a-z_]+)\(([A-Z,]+)\)", rule.split(":-")[1])
    assert len(body) <= atoms["max_body"][0][0].number
    assert len(set(re.findall(r"[A-Z]", rule))) <= atoms["max_vars"][0][0].number
    assert {p for p, _ in body} <= {str(a[0]) for a in atoms["body_pred"]}
    out = swipl(_SCORE, folders[target] / "bk.pl", folders[target] / "exs.pl", rule)
    assert out.split() == [str(N[target]), "0"]


def test_command_and_errors(dataset, tmp_path, capsys, tasks):
    out = tmp_path / "p"
    assert main(["export-popper", str(dataset), str(out), "--target", "stairs",
                 "--max-body", "4"]) == 0
    assert [p.name for p in out.iterdir()] == ["stairs"]
    assert "max_body(4)." in (out / "stairs" / "bias.pl").read_text()
    capsys.readouterr()
    assert main(["export-popper", str(dataset), str(out), "--target", "class"]) == 2
    assert "per class" in capsys.readouterr().err
    assert main(["export-popper", str(dataset), str(out), "--max-vars", "0"]) == 2
    assert "max_vars" in capsys.readouterr().err
    descs, _ = tasks
    with pytest.raises(InputError, match="no examples"):
        popper_files(descs, "cat")
    a = popper_files(descs, "ramp")
    assert a == popper_files(descs, "ramp")                  # deterministic


def test_the_bias_declares_the_relations_the_learned_rules_rest_on(tasks):
    """Every relation of planerel's box, stairs and ramp vocabulary that ``bk.pl`` holds and the
    Aleph task's modes offer (skirt, corner, face_pair, stair_step, tall_face, lying, curved) is
    a body predicate of the bias with its types (ilp90: the bias had none of them)."""
    _, folders = tasks
    atoms = _bias_atoms(folders["box"] / "bias.pl")
    body = {str(a[0]): a[1].number for a in atoms["body_pred"]}
    for name, arity in (("skirt", 2), ("corner", 2), ("face_pair", 2), ("stair_step", 2),
                        ("tall_face", 1), ("lying", 1), ("curved", 1)):
        assert body.get(name) == arity, name
    bk = (folders["box"] / "bk.pl").read_text()
    for name in ("skirt", "corner", "stair_step"):
        assert re.search(rf"^{name}\(", bk, re.MULTILINE), name
