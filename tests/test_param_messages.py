"""``--param`` in the user's words (usab90): an unknown name says which section it was looked
up in, the closest name or the section that has it, and where the section's names are listed
(``planerel params``), never an internal class or every field; every command says it the same
way; ``classify --help``'s ``--param`` entry is short; ``dataset info`` and ``learn`` say what
their object counts count."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from planerel.cli import main
from planerel.errors import InputError
from planerel.parameters import SECTIONS, names_of, parameter_rows, unknown_parameters
from planerel.synth import generate_scene


def _run(*args):
    return subprocess.run([sys.executable, "-m", "planerel.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=300)


def _error(r) -> str:
    """The one error line of a refused run, without ``planerel COMMAND: error:``."""
    assert r.returncode == 2, (r.returncode, r.stdout, r.stderr)
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and "Traceback" not in r.stderr, r.stderr
    return lines[0].split(": error: ", 1)[1]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A small scan, a hand-written model (no settings) and a tiny data set."""
    d = tmp_path_factory.mktemp("params")
    np.save(d / "box.npy", np.asarray(generate_scene("box", seed=1, subsample=8).cloud.xyz))
    (d / "model").mkdir()
    (d / "model" / "rules.pl").write_text("box(A) :- nplanes(A, 2).\n")
    assert main(["dataset", "synth", str(d / "ds"), "--n-box", "1", "--n-stairs", "1",
                 "--n-ramp", "1", "--subsample", "8", "--quiet"]) == 0
    return d


def _commands(d):
    """Every command that takes segmentation parameters, ready for ``--param``."""
    return {"classify": ["classify", d / "model", d / "box.npy"],
            "describe": ["describe", d / "box.npy", "-o", d / "f.pl"],
            "segment": ["segment", d / "box.npy", "-o", d / "seg"],
            "learn": ["learn", d / "ds", "-o", d / "m", "--cache", "none"]}


@pytest.mark.parametrize("given, said, unsaid", [
    # a parameter of another section, given bare (before: "unknown parameter(s) standing_fill
    # for RegionGrowParams; known: adapt, angle_mf, ... (32 names)")
    ("standing_fill=0.7", ["standing_fill (did you mean relations.standing_fill?)",
                           "not a segmentation parameter", "a bare NAME is a segmentation "
                           "parameter, SECTION.NAME one of the sections split, gravity",
                           f"'planerel params segmentation' lists its {len(names_of('segmentation'))} parameters"], []),
    ("thetaa=12", ["thetaa (did you mean theta?)", "'planerel params segmentation'"], []),
    ("foo=1", ["unknown parameter(s) foo: not a segmentation parameter"], ["did you mean"]),
    ("split.smal_faces=150", ["split.smal_faces (did you mean split.small_faces?)",
                              "split has no parameter 'smal_faces'",
                              f"'planerel params split' lists its {len(names_of('split'))} parameters"], []),
    ("colour.x=1", ["unknown section 'colour'", "'planerel params' lists the sections"], []),
])
def test_every_command_says_an_unknown_segmentation_name_the_same_way(files, given, said,
                                                                     unsaid):
    lines = {name: _error(_run(*args, "--param", given))
             for name, args in _commands(files).items()}
    assert len(set(lines.values())) == 1, lines  # the same message from every command
    line = lines["classify"]
    for part in said:
        assert part in line, line
    for part in [*unsaid, "Params", "known:", "adapt, angle_mf"]:
        assert part not in line, line
    assert not (files / "seg").exists() and not (files / "m").exists()


@pytest.mark.parametrize("given, said", [
    # before: "--param relations.foo: relations has no parameter 'foo' (it has parallel_tol,
    # perpendicular_tol, ... (81 names))"
    ("relations.foo=1", ["relations has no parameter 'foo'",
                         f"'planerel params relations' lists its {len(names_of('relations'))} parameters"]),
    ("relations.tol_deg=3", ["relations.tol_deg (did you mean gravity.tol_deg?)"]),
    ("planes.nope=1", ["planes has no parameter 'nope'; its parameters: horizontal_tol, "
                       "vertical_tol,", "'planerel params planes' says what they do"]),
])
def test_a_section_names_where_its_parameters_are_listed(files, given, said):
    lines = {name: _error(_run(*args, "--param", given))
             for name, args in _commands(files).items() if name in ("classify", "describe")}
    assert len(set(lines.values())) == 1, lines
    for part in said:
        assert part in lines["classify"], lines["classify"]
    assert "parallel_tol" not in lines["classify"]  # the big section is not dumped
    # decision.NAME as evaluate-model takes it
    line = _error(_run("evaluate-model", files / "model", files / "ds", "--param",
                       "decision.nope=1"))
    assert "decision has no parameter 'nope'; 'planerel params decision' lists its" in line


def test_segment_says_which_commands_take_another_section(files):
    # before: "unknown parameter(s) relations.skirt_tol for RegionGrowParams; known: ..."
    line = _error(_run(*_commands(files)["segment"], "--param", "relations.skirt_tol=0.1"))
    assert line == ("--param relations.skirt_tol: segment takes segmentation parameters (NAME "
                    "or split.NAME); relations.NAME is a setting of 'planerel classify MODEL "
                    "--param relations.skirt_tol=VALUE' (and of 'planerel describe')")


def test_the_message_is_made_in_one_place_for_python_too():
    from planerel.ilp.model_settings import with_overrides
    from planerel.segment import make_params

    with pytest.raises(InputError) as seg:
        make_params("regiongrow", standing_fill=0.7)
    assert str(seg.value) == str(unknown_parameters("segmentation", ["standing_fill"]))
    with pytest.raises(InputError, match=r"theta \(did you mean theta with --method "
                                         r"regiongrow\?\): not a segmentation parameter of "
                                         r"--method sp or snp.*its parameters: threshold,"):
        make_params("sp", theta=12)
    with pytest.raises(InputError) as rel:
        with_overrides(None, overrides={"relations.nope": "1"})
    assert str(rel.value) == str(unknown_parameters("relations", ["nope"]))
    assert "did you mean" not in str(rel.value)  # nothing close: no suggestion


def test_classify_help_says_the_syntax_in_a_few_lines():
    r = _run("classify", "--help")
    assert r.returncode == 0
    # before: 181 lines, about 100 of them the --param entry naming every gate
    assert len(r.stdout.splitlines()) < 100, r.stdout
    entry = r.stdout.split("--param NAME=VALUE  ", 1)[1].split("\n  -", 1)[0]
    assert len(entry.splitlines()) <= 12, entry
    words = " ".join(entry.split())
    for part in ("A bare NAME is a segmentation parameter", "theta=12", "SECTION.NAME",
                 "relations", "decision.planar_gate=false", "'planerel params'"):
        assert part in words, words


def test_params_lists_sections_and_their_parameters(files, capsys):
    assert main(["params"]) == 0
    out = capsys.readouterr().out
    for name in SECTIONS:
        assert f"  {name} " in out
    assert "a bare NAME is a segmentation parameter" in out
    assert main(["params", "relations"]) == 0
    out = capsys.readouterr().out
    assert "  relations.standing_fill = 0.8\n" in out
    assert "a tall_face is a rectangle" in out
    assert out.count("\n  relations.") == len(names_of("relations"))
    assert main(["params", "decision.planar_gate"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("decision.planar_gate = True (default)\n") and "facets22" in out
    # every gate the old help described has its meaning in the listing
    said = {name: meaning for name, _, meaning in parameter_rows("decision")}
    assert all(said[f"decision.{g}"] for g in names_of("decision") if g.endswith("_gate"))
    assert _error(_run("params", "relation")) == (
        "no section or parameter 'relation' (did you mean relations?); 'planerel params' lists "
        "the sections")


def test_params_shows_a_models_values(tmp_path, capsys):
    from planerel.ilp.model_settings import training_settings

    (tmp_path / "rules.pl").write_text("box(A) :- nplanes(A, 2).\n")
    data = training_settings("regiongrow", {"theta": 12})
    data["relations"]["standing_fill"] = 0.7
    (tmp_path / "model.json").write_text(json.dumps(data))
    assert main(["params", "theta", "--model", str(tmp_path)]) == 0
    assert capsys.readouterr().out.startswith("theta = 12.0 (the model's value)\n")
    assert main(["params", "relations", "--model", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert f"the values of {tmp_path}" in out and "  relations.standing_fill = 0.7\n" in out


def test_dataset_info_and_learn_say_what_they_count(tmp_path):
    """``dataset info`` counts the ground truth (scenes per class, objects in view); ``learn``
    the objects whose segmented planes show their class, and the rest on a ``not examples:``
    line: the two add up."""
    ds = tmp_path / "ds"
    assert main(["dataset", "synth", str(ds), "--world", "varied", "--n-box", "2",
                 "--n-stairs", "2", "--n-ramp", "2", "--seed", "1", "--quiet"]) == 0
    r = _run("dataset", "info", ds)
    assert r.returncode == 0, r.stderr
    assert "6 scenes; box 2, ramp 2, stairs 2 (scenes by the class of their main object" in r.stdout
    seen = int(r.stdout.split(" ground-truth objects with pixels in view: ")[0].rsplit("\n", 1)[1])
    assert "planerel learn takes as examples only the objects whose segmented planes" in r.stdout
    r = _run("learn", ds, "-o", tmp_path / "m", "--engine", "builtin", "-j", "1", "--cache",
             "none")
    assert r.returncode == 0, r.stderr
    m = json.loads((tmp_path / "m" / "metrics.json").read_text())
    left = sum(sum(v.values()) for v in m["excluded"].values())
    assert m["n_examples"] + m["n_other"] + left == seen  # every object in view, counted once
    assert sum(m["examples"].values()) == m["n_examples"]
    assert f"{m['n_examples']} example objects from 6 scenes; classes: " in r.stdout
    assert ("examples per class: " + ", ".join(f"{k} {m['examples'][k]}" for k in m["classes"])
            + " (the objects whose segmented planes show their class)\n") in r.stdout
    assert left  # this set has objects the segmentation does not show as their class
    line = next(ln for ln in r.stdout.splitlines() if ln.startswith("not examples: "))
    assert f"not examples: {left} ground-truth object(s)" in line
    for klass, why in m["excluded"].items():
        assert f"{klass} {sum(why.values())} (" in line
    assert "'planerel dataset info' counts every scene and every object in view" in line
