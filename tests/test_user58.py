"""A robotics researcher's pass of 2026-12-02 (user58): what it found, fixed
(docs/robustness.md, "A robotics researcher's pass (user58)").

Real commands in subprocesses or through ``planerel.cli.main`` (real swipl, no mocks).
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from planerel.cli import main
from planerel.synth import generate_scene


def _run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "planerel.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=300, cwd=cwd)


def test_learn_one_class_against_objects_of_class_other(tmp_path):
    # before: "learning needs at least two classes; the data set has box and 3 objects of
    # class 'other'": a researcher who labelled only boxes (and the rest 'other') got no model
    ds = tmp_path / "boxes"
    assert main(["dataset", "synth", str(ds), "--world", "varied", "--n-box", "6",
                 "--n-stairs", "0", "--n-ramp", "0", "--seed", "3", "--quiet"]) == 0
    out = tmp_path / "m"
    r = _run("learn", ds, "-o", out, "--folds", "2", "--engine", "builtin", "-j", "1",
             "--cache", "none")
    assert r.returncode == 0, r.stderr
    assert "classes: box;" in r.stdout and "objects of class other" in r.stdout
    assert (out / "rules.pl").read_text().count("box(A)") >= 1
    # the model classifies: the training scenes' boxes are box
    r = _run("classify", out, *sorted(ds.glob("s*.depth.png"))[:2], "--json", "-j", "1")
    assert r.returncode == 0, r.stderr
    answers = [o["class"] for s in json.loads(r.stdout) for o in s["objects"]]
    assert "box" in answers and set(answers) <= {"box", "other"}
    # one class with no object of class other is still refused, saying what would do
    only = tmp_path / "only"
    assert main(["dataset", "synth", str(only), "--n-box", "2", "--n-stairs", "0",
                 "--n-ramp", "0", "--subsample", "8", "--quiet"]) == 0
    r = _run("learn", only, "-o", tmp_path / "m2", "--engine", "builtin", "-j", "1",
             "--cache", "none")
    assert r.returncode == 2 and "or one and objects of class 'other'" in r.stderr, r.stderr
