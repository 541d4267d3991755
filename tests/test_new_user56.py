"""Defects a new user met (docs/robustness.md, "New-user walkthrough, 2026-12-02").

Each test runs the real command line in a subprocess (real swipl, no mocks): a wrong input,
option or model folder must fail in one line through the exception hierarchy, before any work
where it can, and write nothing; a model folder whose files disagree must say so.
"""

from __future__ import annotations

import shutil
import subprocess
import sys

import numpy as np
import pytest
from test_new_user import _one_error_line, _run  # the first pass's helpers

from planerel.cli import main
from planerel.io.exports import write_pcd
from planerel.synth import generate_scene


@pytest.fixture(scope="module")
def scan(tmp_path_factory):
    """A small scene (a box, 80x60) as an XYZ .npy."""
    d = tmp_path_factory.mktemp("scan")
    path = d / "box.npy"
    np.save(path, np.asarray(generate_scene("box", seed=1, subsample=8).cloud.xyz))
    shutil.copy(path, d / "box2.npy")
    return path


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    """A model folder from ``planerel learn`` (rules.pl with its statistics, model.json)."""
    d = tmp_path_factory.mktemp("model")
    ds = d / "ds"
    assert main(["dataset", "synth", str(ds), "--n-box", "2", "--n-stairs", "2", "--n-ramp",
                 "2", "--subsample", "8", "--quiet"]) == 0
    out = d / "model"
    assert main(["learn", str(ds), "-o", str(out), "--engine", "builtin", "-j", "1",
                 "--cache", "none"]) == 0
    return out


def test_a_pcd_named_ply_is_converted_and_segmented_with_its_colours(tmp_path):
    # before: the reader sniffs the content (a PCD), but the colours were looked for by the
    # name's suffix with plyfile: "plyfile.PlyHeaderParseError: line 1: expected 'ply'", a
    # traceback, and segment left NAME.labels.npy and NAME.labels.png half of its outputs
    xyz = np.asarray(generate_scene("box", seed=1, subsample=8).cloud.xyz)
    rgb = np.zeros(xyz.shape, np.uint8)
    rgb[..., 0] = 200
    src = tmp_path / "scan.ply"
    write_pcd(src, xyz, colours=rgb)
    assert src.read_bytes().startswith(b"# .PCD")
    r = _run("convert", src, "-o", tmp_path / "out.ply")
    assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr
    from plyfile import PlyData

    v = PlyData.read(str(tmp_path / "out.ply"))["vertex"].data
    assert set(np.unique(v["red"])) == {200}  # the PCD's colours, kept
    r = _run("segment", src, "-o", tmp_path / "seg", "-j", "1")
    assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr
    assert sorted(p.name for p in (tmp_path / "seg").iterdir()) == [
        "scan.labels.npy", "scan.labels.png", "scan.pcd", "scan.planes.json", "scan.ply"]


@pytest.mark.parametrize("value, needle", [
    ("640,480,-525,525,320,240", "focal lengths must be positive"),
    ("640,480,nan,525,320,240", "fx must be finite"),
    ("0,480,525,525,320,240", "width must be a positive integer"),
])
def test_intrinsics_with_bad_numbers_are_one_error_about_the_option(scan, tmp_path, value,
                                                                    needle):
    # before: only the count of numbers was checked up front; every input then failed in
    # turn, each message ending "(--keep-going goes on past bad inputs)", and --keep-going
    # wrote a facts file of 0 scenes with exit 1
    for extra in ([], ["-k"]):
        r = _run("describe", scan, scan.with_name("box2.npy"), "-o", tmp_path / "f.pl",
                 "--intrinsics", value, *extra)
        line = _one_error_line(r, f"--intrinsics '{value}'", needle)
        assert "--keep-going" not in line
    assert not list(tmp_path.iterdir())


def test_rules_cut_short_warn_that_they_are_not_the_model(model, scan, tmp_path):
    # before: a rules.pl cut after its box clauses (a copy that stopped) loaded, answered with
    # the box rules at precision 0.500 and no stairs or ramp rule, in silence
    m = tmp_path / "m"
    shutil.copytree(model, m)
    r = _run("classify", m, scan)
    assert r.returncode == 0 and "warning" not in r.stderr, r.stderr
    text = (model / "rules.pl").read_text()
    (m / "rules.pl").write_text(text[:text.index("planerel_rule_stats(")])
    r = _run("classify", m, scan)
    assert r.returncode == 0, r.stderr
    assert "does not match" in r.stderr and "cut short" in r.stderr, r.stderr
    # a model folder's rules.pl from another model: the same warning
    other = tmp_path / "other"
    shutil.copytree(model, other)
    (other / "rules.pl").write_text(text + "planerel_rule_stats(99, box, 1, 1).\n")
    r = _run("classify", other, scan)
    assert r.returncode == 0 and "does not match" in r.stderr, r.stderr
    # hand-written rules without model.json stay quiet
    rules = tmp_path / "rules.pl"
    rules.write_text("box(A) :- nvertical(A, B), B >= 2.\n")
    r = _run("classify", rules, scan)
    assert r.returncode == 0 and "warning" not in r.stderr


def test_a_binary_file_given_as_the_model_is_one_error_line(scan, tmp_path):
    # before: SWI-Prolog printed "Warning: ...: Illegal UTF-8 start" lines before the error
    fake = tmp_path / "model.pl"
    fake.write_bytes(b"II*\x00" + bytes(range(256)) * 8)
    _one_error_line(_run("classify", fake, scan), "not a rules file (binary data")
    fake.write_bytes(b"box(A) :- \x00.\n")
    _one_error_line(_run("classify", fake, scan), "not a rules file (binary data")


def test_duplicate_ids_are_not_told_to_give_ids(scan, tmp_path):
    # before: "... have the same scene id 'a' / 'A'; ... (rename one, or give --ids)" to a
    # user who had given --ids; an empty id did not say it came from --ids
    two = scan.with_name("box2.npy")
    line = _one_error_line(_run("describe", scan, two, "-o", tmp_path / "f.pl",
                                "--ids", "a", "A"), "same scene id 'a' / 'A'")
    assert "give each input its own --ids" in line and "rename" not in line
    _one_error_line(_run("describe", scan, two, "-o", tmp_path / "f.pl", "--ids", "", "b"),
                    "empty scene id in --ids")
    assert not (tmp_path / "f.pl").exists()


def test_a_refused_run_leaves_no_empty_output_folder_behind(scan, tmp_path):
    # before: segment, classify -o, describe -o DIR/f.pl, report and export-popper made their
    # output folders up front and left them empty when the run was then refused
    bad = tmp_path / "nan.npy"
    np.save(bad, np.full((60, 80, 3), np.nan, np.float32))
    rules = tmp_path / "rules.pl"
    rules.write_text("box(A) :- nvertical(A, B), B >= 2.\n")
    ds = tmp_path / "ds"
    assert main(["dataset", "synth", str(ds), "--n-box", "1", "--n-stairs", "1", "--n-ramp",
                 "1", "--subsample", "8", "--quiet"]) == 0
    out = tmp_path / "out"
    for cmd in (["segment", bad, "-o", out / "a" / "seg", "-j", "1"],
                ["classify", rules, bad, "-o", out / "cls", "-j", "1"],
                ["describe", bad, "-o", out / "d" / "f.pl", "--mesh", out / "mesh", "-j", "1"],
                ["export-popper", ds, out / "pop", "--max-vars", "0"],
                ["report", ds, "-o", out / "rep", "--methods", "nosuch"]):
        r = _run(*cmd)
        assert r.returncode == 2, (cmd, r.stderr)
        assert not out.exists(), (cmd, sorted(out.rglob("*")))
    # a folder that was there stays, and so do the folders of a run that succeeded
    out.mkdir()
    _one_error_line(_run("segment", bad, "-o", out, "-j", "1"), "has no valid point")
    assert out.is_dir()
    r = _run("segment", scan, "-o", out / "new", "-j", "1", "--formats", "json")
    assert r.returncode == 0 and (out / "new" / "box.planes.json").is_file()


def test_a_members_model_with_a_member_that_learned_nothing_classifies(scan, tmp_path):
    # before: `learn --members 2` on a small set wrote the model ("model written to ..."; its
    # --heldout scores were printed), but classify refused it: "members/2/rules.pl: the model
    # has no rules" (a member with no rule answers "other" in the vote)
    ds = tmp_path / "ds"
    assert main(["dataset", "synth", str(ds), "--n-box", "3", "--n-stairs", "3", "--n-ramp",
                 "3", "--seed", "3", "--subsample", "8", "--quiet"]) == 0
    m = tmp_path / "m"
    assert main(["learn", str(ds), "-o", str(m), "--members", "2", "--engine", "builtin",
                 "-j", "1", "--cache", "none"]) == 0
    empty = [d for d in sorted((m / "members").iterdir())
             if not any(ln and not ln.startswith(("%", ":-", "planerel_"))
                        for ln in (d / "rules.pl").read_text().splitlines())]
    if not empty:
        pytest.skip("both members learned rules with this seed")
    r = _run("classify", m, scan, "--json")
    assert r.returncode == 0, r.stderr
    import json

    answers = json.loads(r.stdout)[0]["objects"]
    assert answers and all(a["class"] in ("box", "stairs", "ramp", "other") for a in answers)
    # a members model none of whose members learned a rule is still refused, in one line
    for d in (m / "members").iterdir():
        (d / "rules.pl").write_text("% nothing learned\n")
    _one_error_line(_run("classify", m, scan), "the model has no rules (none of its 2 members")


def test_a_closed_stdout_pipe_ends_quietly(tmp_path):
    # before: `planerel classify ... --json | head -c 10` ended with "planerel classify:
    # error: a file: Broken pipe; check the path and the disk", exit 2
    rules = tmp_path / "rules.pl"
    rules.write_text("box(A) :- nvertical(A, B), B >= 2.\n")
    scans = []
    for k in range(3):
        p = tmp_path / f"s{k}.npy"
        np.save(p, np.asarray(generate_scene("stairs", seed=k, subsample=8).cloud.xyz))
        scans.append(p)
    p = subprocess.Popen([sys.executable, "-m", "planerel.cli", "classify", str(rules),
                          *map(str, scans), "--json", "-j", "1"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    p.stdout.read(5)
    p.stdout.close()
    err = p.stderr.read().decode()
    assert p.wait(timeout=300) in (0, 141) and "Broken pipe" not in err and "Traceback" not in err, err


def test_run_all_help_does_not_start_the_benchmarks():
    # before: `benchmarks/run_all.py --help` ran every bench_*.py (minutes, child processes)
    from pathlib import Path

    script = Path(__file__).resolve().parents[1] / "benchmarks" / "run_all.py"
    import os
    import signal

    p = subprocess.Popen([sys.executable, str(script), "--help"], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, _ = p.communicate(timeout=60)
    finally:  # a run that started the benchmarks: stop them all (their own children too)
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()
    assert p.returncode == 0 and "usage" in out and "====" not in out


def test_only_the_command_line_records_the_folders_it_makes(tmp_path):
    """The Python API writes as before and keeps no list of the folders it made (a long-lived
    process would only collect them); a command line run records them until it ends."""
    from planerel import atomic

    atomic.write_text(tmp_path / "a" / "b" / "f.txt", "x")
    assert atomic._MADE is None and (tmp_path / "a" / "b" / "f.txt").read_text() == "x"
    atomic.record_made_folders()
    try:
        atomic.write_text(tmp_path / "c" / "d" / "f.txt", "x")
        assert atomic._MADE == [tmp_path / "c" / "d", tmp_path / "c"]
        (tmp_path / "c" / "d" / "f.txt").unlink()
        atomic.remove_made_folders()   # what a failed command does: empty folders go
        assert not (tmp_path / "c").exists() and atomic._MADE is None
    finally:
        atomic.forget_made_folders()
