"""The exported STEM.b/.f/.n as an ILP user reads them: a plain ``swipl``, not planerel.

* With the SWI-Prolog pack's module file ``aleph.pl`` (``library(aleph)``), which exports
  neither ``set/2`` nor ``determination/2``, ``aleph:read_all(user:STEM), induce`` used to run
  every ``:- set`` and ``:- determination`` of STEM.b as an unknown procedure (105 errors and
  warnings for box) and learn one fact per example. STEM.b now defines the two when that module
  is loaded (``aleph_export.PACK_SHIM``). Checked with a stand-in module always, and with the
  real Aleph when ``PLANEREL_ALEPH`` names it (either file, each read its own way).
* One class and objects of class ``other`` (box against everything else, as a user labels a
  few real objects) make an Aleph task: ``other`` objects are its negatives.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import pytest

from planerel.cli import main
from planerel.errors import InputError
from planerel.ilp.aleph_export import aleph_files, describe_dataset, export_aleph
from planerel.ilp.learn import aleph_kind, learn

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_real_aleph import dataset  # noqa: E402,F401  (the fixture: 3 scenes a class, seed 5)

SWIPL = shutil.which("swipl") or "/usr/bin/swipl"
ALEPH = os.environ.get("PLANEREL_ALEPH", "")
pytestmark = pytest.mark.skipif(not shutil.which(SWIPL), reason="swipl not installed")

# A stand-in for the pack's module: the same exports that matter here (modeh/2, modeb/2,
# lazy_evaluate/1, no set/2, no determination/2) and set/3, determination/3 that record.
_STAND_IN = r"""
:- module(aleph, [modeh/2, modeb/2, lazy_evaluate/1, op(500, fy, #)]).
:- dynamic got/2.
modeh(_, _).
modeb(_, _).
lazy_evaluate(_).
set(N, V, M) :- assertz(got(set(N, V), M)).
determination(P, Q, M) :- assertz(got(determination(P, Q), M)).
"""

_HOOK = r"""
:- dynamic planerel_msg/1.
user:message_hook(T, Kind, _) :- memberchk(Kind, [warning, error]), assertz(planerel_msg(T)), fail.
"""


def _run(goal: str, files: list[Path], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([SWIPL, "-q", "-g", goal, "-g", "halt", "-t", "halt(4)",
                           *map(str, files)],
                          capture_output=True, text=True, timeout=300, cwd=cwd)


@pytest.fixture(scope="module")
def descs(dataset):  # noqa: F811
    descs, skipped = describe_dataset(dataset)
    assert skipped == []
    return descs


def test_the_b_file_defines_set_and_determination_for_the_pack_module(tmp_path, descs):
    export_aleph(descs, tmp_path, "box")
    (tmp_path / "aleph.pl").write_text(_STAND_IN)
    (tmp_path / "hook.pl").write_text(_HOOK)
    goal = ("use_module(aleph), consult('box.b'), "
            "( planerel_msg(M) -> format('MSG ~q~n', [M]) ; true ), "
            "aggregate_all(count, aleph:got(set(_, _), user), NS), "
            "aggregate_all(count, aleph:got(determination(box/1, _), user), ND), "
            "format('~w ~w~n', [NS, ND])")
    proc = _run(goal, [tmp_path / "hook.pl"], tmp_path)
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr
    assert "MSG" not in proc.stdout, proc.stdout
    text = (tmp_path / "box.b").read_text()
    n_set = len(re.findall(r"^:- set\(", text, re.MULTILINE))
    n_det = len(re.findall(r"^:- determination\(box/1, ", text, re.MULTILINE))
    assert proc.stdout.split() == [str(n_set), str(n_det)] and n_set >= 5 and n_det >= 10


def test_the_shim_is_skipped_without_the_pack_module(tmp_path, descs):
    """Without a module ``aleph`` (the classic aleph_orig.pl, planerel's learner) the lines do
    nothing: a set/2 of the loading module's own is called, none is defined."""
    export_aleph(descs, tmp_path, "box")
    (tmp_path / "hook.pl").write_text(_HOOK + ":- dynamic s/2.\nset(N, V) :- assertz(s(N, V)).\n"
                                      "determination(_, _).\nmodeh(_, _).\nmodeb(_, _).\n"
                                      "lazy_evaluate(_).\n")
    goal = ("consult('box.b'), ( planerel_msg(M) -> format('MSG ~q~n', [M]) ; true ), "
            "aggregate_all(count, clause(set(_, _), _), NC), "
            "aggregate_all(count, s(_, _), NS), format('~w ~w~n', [NC, NS])")
    proc = _run(goal, [tmp_path / "hook.pl"], tmp_path)
    assert proc.returncode == 0 and proc.stderr == "" and "MSG" not in proc.stdout, \
        proc.stderr + proc.stdout
    nc, ns = map(int, proc.stdout.split())
    assert nc == 1 and ns >= 5
    r = learn(tmp_path / "box", engine="builtin", timeout=120)
    assert r.train.accuracy == 1.0 and r.rules


def test_one_class_and_other_objects_make_a_task(tmp_path, descs):
    """Box against everything else: the objects of class ``other`` are the negatives."""
    relabelled = [replace(d, objects=tuple(o if o.klass == "box" else replace(o, klass="other")
                                           for o in d.objects)) for d in descs]
    files = aleph_files(relabelled, "box")
    assert len(files["box.f"].split()) == 3 and len(files["box.n"].split()) == 6
    assert "% examples: 3 positive, 6 negative; classes: box" in files["box.b"]
    res = export_aleph(relabelled, tmp_path, "all")
    assert res.stems == ("box",)
    r = learn(tmp_path / "box", engine="builtin", timeout=120)
    assert r.train.tp == 3 and r.train.fp == 0 and r.train.tn == 6
    only_boxes = [d for d in descs if d.objects and d.objects[0].klass == "box"]
    with pytest.raises(InputError, match="at least two classes; found box \\(objects of class"):
        aleph_files(only_boxes, "box")
    from planerel.ilp.popper_export import popper_files

    with pytest.raises(InputError, match="which the Popper task leaves out"):
        popper_files(relabelled, "box")
    from planerel.ilp.pipeline import _classes_arg

    # planerel learn takes one class when objects of class other are its negatives (user58)
    assert _classes_arg(None, relabelled) == ("box",)
    with pytest.raises(InputError, match="or one and objects of class 'other'"):
        _classes_arg(None, only_boxes)


# ----------------------------------------------------------- the real Aleph, by hand


def _by_hand_goal(stem: str) -> str:
    if aleph_kind(Path(ALEPH)) == "module":
        return (f"use_module('{ALEPH}'), aleph:read_all(user:{stem}), induce, "
                "( planerel_msg(M) -> format('MSG ~q~n', [M]) ; true )")
    return (f"consult('{ALEPH}'), read_all({stem}), induce, "
            "( planerel_msg(M) -> format('MSG ~q~n', [M]) ; true )")


@pytest.mark.real_aleph
@pytest.mark.skipif(not ALEPH, reason="the real Aleph is not installed here: set "
                                      "PLANEREL_ALEPH=/path/to/aleph.pl to run these tests")
def test_real_aleph_reads_the_export_by_hand(tmp_path, descs):
    """``swipl``, the Aleph file, read_all, induce: no warning or error, the same theory as
    planerel's driver of the same Aleph, a rule (not one fact per example)."""
    export_aleph(descs, tmp_path, "all")
    (tmp_path / "hook.pl").write_text(_HOOK)
    for stem in ("box", "stairs", "ramp"):
        proc = _run(_by_hand_goal(stem), [tmp_path / "hook.pl"], tmp_path)
        out = proc.stdout + proc.stderr
        assert proc.returncode == 0, out[-2000:]
        assert "MSG" not in out and "Warning" not in out and "ERROR" not in out, out[-3000:]
        theory = out.split("[theory]", 1)[1].split("[Training set performance]", 1)[0]
        clauses = [re.sub(r"\s+", "", c) + "." for c in
                   re.split(r"\.\s*\n", re.sub(r"\[Rule \d+\][^\n]*\n", "", theory)) if c.strip()]
        assert clauses and all(":-" in c for c in clauses), theory
        summary = re.search(r"\[Training set summary\] \[\[(\d+),(\d+),(\d+),(\d+)\]\]", out)
        assert summary and summary.group(2) == "0" and summary.group(3) == "0", out[-1500:]
        driven = learn(tmp_path / stem, engine="aleph", timeout=300)
        assert [re.sub(r"\s+", "", c) for c in driven.rules] == clauses
    # several classes in one session, each background unloaded before the next (docs)
    read = ("aleph:read_all(user:{s})" if aleph_kind(Path(ALEPH)) == "module" else "read_all({s})")
    goal = _by_hand_goal("box").replace(", ( planerel_msg", ", unload_file('box.b'), "
                                        + read.format(s="stairs") + ", induce, ( planerel_msg")
    proc = _run(goal, [tmp_path / "hook.pl"], tmp_path)
    out = proc.stdout + proc.stderr
    assert proc.returncode == 0 and "MSG" not in out and "Warning" not in out, out[-2000:]
    assert len(re.findall(r"\[Training set summary\] \[\[\d+,0,0,\d+\]\]", out)) == 2, out[-1500:]


# ------------------------------------ examples of your own on `planerel describe` facts


def test_own_examples_on_describe_facts(tmp_path, dataset, descs):  # noqa: F811
    """docs/predicates.md, "Examples of your own": describe scans with ``--pairs object``,
    name objects in STEM.f / STEM.n, take the task's head from an export, consult
    compare.pl and the facts; planerel's learner (and the real Aleph by hand, when
    ``PLANEREL_ALEPH`` is set) learns from it with no warning."""
    import importlib.resources as resources

    from planerel.features.dataset import load_manifest

    rows = load_manifest(dataset)
    scans = [str(dataset / r.depth) for r in rows]
    mine = tmp_path / "mine"
    assert main(["describe", *scans, "--pairs", "object", "-o", str(mine / "scans.pl"),
                 "-j", "1"]) == 0
    facts = (mine / "scans.pl").read_text()
    boxes = [f"{r.scene_id}_o1" for r in rows if r.klass == "box"]
    others = [f"{r.scene_id}_o1" for r in rows if r.klass != "box"]
    assert all(f"object({o.split('_')[0]}, {o})." in facts for o in boxes + others)
    (mine / "box.f").write_text("".join(f"box({o}).\n" for o in boxes))
    (mine / "box.n").write_text("".join(f"box({o}).\n" for o in others))
    export_aleph(descs, tmp_path / "task", "box")
    head = (tmp_path / "task" / "box.b").read_text().split("% ---- dynamic background")[0]
    compare = resources.files("planerel.prolog") / "compare.pl"
    (mine / "box.b").write_text(head + f":- consult('{compare}').\n:- consult(scans).\n")
    r = learn(mine / "box", engine="builtin", timeout=120)
    assert r.train.accuracy == 1.0 and r.rules and "warning" not in r.output.lower()
    if ALEPH:
        (mine / "hook.pl").write_text(_HOOK)
        proc = _run(_by_hand_goal("box"), [mine / "hook.pl"], mine)
        out = proc.stdout + proc.stderr
        assert proc.returncode == 0 and "MSG" not in out and "ERROR" not in out, out[-2000:]
        assert "[Training set summary] [[3,0,0,6]]" in out, out[-1500:]
