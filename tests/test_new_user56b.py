"""What the new-user pass of 2026-12-02 (user56) noticed and left alone, fixed
(docs/robustness.md, "New-user walkthrough, 2026-12-02 (user56)").

Each test runs the real command line in a subprocess (real swipl, no mocks).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from test_new_user import _one_error_line, _run  # the first pass's helpers

from planerel.cli import main
from planerel.synth import generate_scene


@pytest.fixture(scope="module")
def scan(tmp_path_factory):
    """A small scene (a box, 80x60) as an XYZ .npy."""
    path = tmp_path_factory.mktemp("scan") / "box.npy"
    np.save(path, np.asarray(generate_scene("box", seed=1, subsample=8).cloud.xyz))
    return path


def _dataset(folder: Path, n: int, seed: int = 0) -> Path:
    assert main(["dataset", "synth", str(folder), "--n-box", str(n), "--n-stairs", str(n),
                 "--n-ramp", str(n), "--seed", str(seed), "--subsample", "8", "--quiet"]) == 0
    return folder


def test_dash_as_output_is_refused_not_made_a_file(scan, tmp_path):
    # before: `describe X -o -` wrote a facts file named "-" (no command writes to stdout
    # with "-"); `./-` still names such a file on purpose
    _one_error_line(_run("describe", scan, "-o", "-", "-j", "1", cwd=tmp_path),
                    "-o -: planerel writes no output to stdout")
    rules = tmp_path.parent / f"{tmp_path.name}.rules.pl"
    rules.write_text("box(A) :- nvertical(A, B), B >= 2.\n")
    _one_error_line(_run("classify", rules, scan, "-o", "-", "-j", "1", cwd=tmp_path), "-o -:")
    _one_error_line(_run("segment", scan, "-o", "-", "-j", "1", cwd=tmp_path), "-o -:")
    assert not list(tmp_path.iterdir())
    r = _run("describe", scan, "-o", "./-", "-j", "1", cwd=tmp_path)
    assert r.returncode == 0 and (tmp_path / "-").is_file(), r.stderr


def test_learn_where_no_class_learns_a_rule_is_an_error(scan, tmp_path):
    # before: the model was written ("% no rule for box", ...), exit 0; classify then
    # refused it ("the model has no rules")
    ds = _dataset(tmp_path / "ds", 1)
    out = tmp_path / "m"
    r = _run("learn", ds, "-o", out, "--engine", "builtin", "-j", "1", "--cache", "none")
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    assert "no class learned a rule" in r.stderr and "no model written" in r.stderr
    assert not out.exists()
    # a model already there stays as it was
    good = _dataset(tmp_path / "good", 2)
    assert main(["learn", str(good), "-o", str(out), "--engine", "builtin", "-j", "1",
                 "--cache", "none"]) == 0
    before = (out / "rules.pl").read_bytes()
    r = _run("learn", ds, "-o", out, "--engine", "builtin", "-j", "1", "--cache", "none")
    assert r.returncode == 2 and (out / "rules.pl").read_bytes() == before
    assert _run("classify", out, scan).returncode == 0


def test_a_subsample_that_leaves_no_point_names_the_option(tmp_path):
    # before: "X: has no valid point (need at least 3)", blaming the file
    big = tmp_path / "big.npy"
    np.save(big, np.asarray(generate_scene("box", seed=1, subsample=2).cloud.xyz))
    line = _one_error_line(_run("describe", big, "-o", tmp_path / "f.pl", "--subsample",
                                "1000", "-j", "1"), "--subsample 1000 leaves",
                           "give a smaller --subsample")
    assert "has no valid point" not in line
    r = _run("describe", big, "-o", tmp_path / "f.pl", "--subsample", "2", "-j", "1")
    assert r.returncode == 0, r.stderr


def test_a_multi_page_tiff_says_only_its_first_page_is_read(tmp_path):
    # before: read from its first page without a word
    tifffile = pytest.importorskip("tifffile")
    xyz = np.asarray(generate_scene("box", seed=1, subsample=4).cloud.xyz)
    depth = np.nan_to_num(xyz[..., 2] * 1000).astype(np.uint16)
    one, multi = tmp_path / "one.tiff", tmp_path / "multi.tiff"
    tifffile.imwrite(one, depth)
    with tifffile.TiffWriter(multi) as tw:
        for _ in range(3):
            tw.write(depth)
    r = _run("describe", multi, "-o", tmp_path / "m.pl", "--intrinsics", "kinect", "-j", "1")
    assert r.returncode == 0, r.stderr
    assert "the TIFF holds 3 pages; only the first is read" in r.stderr, r.stderr
    r = _run("describe", one, "-o", tmp_path / "o.pl", "--intrinsics", "kinect", "-j", "1")
    assert r.returncode == 0 and "pages" not in r.stderr, r.stderr
    # the same facts as the single page (the header names the input)
    facts = [(tmp_path / f).read_text().splitlines() for f in ("m.pl", "o.pl")]
    strip = [[ln.replace("multi", "X").replace("one", "X") for ln in f
              if not ln.startswith("%")] for f in facts]
    assert strip[0] == strip[1]


@pytest.mark.parametrize("option", ["size_classes", "slender_classes", "range_classes"])
def test_a_gate_class_the_model_lacks_is_an_error(scan, tmp_path, option):
    # before: `--param decision.size_classes=chair` only warned that it differs from training
    # (the gate then held for no class); `learn --set chair:noise=1` was already an error
    rules = tmp_path / "rules.pl"
    rules.write_text("box(A) :- nvertical(A, B), B >= 2.\n"
                     "stairs(A) :- nvertical(A, B), B >= 5.\n")
    _one_error_line(_run("classify", rules, scan, "--param", f"decision.{option}=box,chair"),
                    f"decision.{option}=box,chair", "'chair' is not a class of the model "
                    "(box, stairs)")
    r = _run("classify", rules, scan, "--param", f"decision.{option}=stairs")
    assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr
