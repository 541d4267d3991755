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


@pytest.fixture(scope="module")
def frame(tmp_path_factory):
    """A box scene as a bare 16-bit depth PNG (no sidecar), 160x120, and its camera."""
    d = tmp_path_factory.mktemp("frame")
    s = generate_scene("box", seed=1, subsample=4)
    Image.fromarray(np.asarray(s.depth_mm, dtype=np.uint16)).save(d / "box_depth.png")
    return d / "box_depth.png", (160, 120, 131.25, 131.25, 79.875, 59.875)


def _answers(stdout: str) -> list:
    return [(o["object"], o["class"], o["proof_planes"])
            for s in json.loads(stdout) for o in s["objects"]]


def test_intrinsics_from_a_camera_json_file(frame, tmp_path):
    # before: "--intrinsics must be 'kinect' or W,H,fx,fy,cx,cy; got 'camera.json'": the
    # camera file a researcher has (a sidecar's, a ROS camera_info's K) had to be typed out
    png, (w, h, fx, fy, cx, cy) = frame
    rules = tmp_path / "r.pl"
    rules.write_text("box(A) :- nvertical(A, B), B >= 1.\n")
    want = _run("classify", rules, png, "--json", "-j", "1", "--intrinsics",
                f"{w},{h},{fx},{fy},{cx},{cy}")
    assert want.returncode == 0, want.stderr
    plain = tmp_path / "camera.json"
    plain.write_text(json.dumps({"width": w, "height": h, "fx": fx, "fy": fy, "cx": cx,
                                 "cy": cy}))
    side = tmp_path / "sidecar.json"
    side.write_text(json.dumps({"intrinsics": {"width": w, "height": h, "fx": fx, "fy": fy,
                                               "cx": cx, "cy": cy}, "depth_scale": 1000}))
    ros = tmp_path / "camera_info.json"
    ros.write_text(json.dumps({"image_width": w, "image_height": h, "camera_matrix": {
        "rows": 3, "cols": 3, "data": [fx, 0, cx, 0, fy, cy, 0, 0, 1]}}))
    flat = tmp_path / "k.json"
    flat.write_text(json.dumps({"width": w, "height": h, "K": [fx, 0, cx, 0, fy, cy, 0, 0, 1]}))
    for cam in (plain, side, ros, flat):
        r = _run("classify", rules, png, "--json", "-j", "1", "--intrinsics", cam)
        assert r.returncode == 0, (cam.name, r.stderr)
        assert _answers(r.stdout) == _answers(want.stdout), cam.name
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"fx": fx}))
    for cam, needle in ((bad, "holds neither width, height, fx"),
                        (tmp_path / "none.json", "cannot read the camera JSON")):
        r = _run("describe", png, "-o", tmp_path / "f.pl", "-j", "1", "--intrinsics", cam)
        err = [ln for ln in r.stderr.splitlines() if ln.strip()]
        assert r.returncode == 2 and len(err) == 1 and needle in err[0], r.stderr
    assert not (tmp_path / "f.pl").exists()
