"""``planerel classify`` says which argument is wrong when the model and the scans are mixed
up (user89: a forgotten model said "the following arguments are required: INPUT", swapped
arguments "MODEL: the folder holds no scan"), and notes where ``--up`` or ``--camera-height``
disagrees with the scan."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from planerel.classify.classifier import Classifier
from planerel.cli import main
from planerel.io import readers as io


@pytest.fixture(scope="module")
def setup(tmp_path_factory):
    d = tmp_path_factory.mktemp("cls")
    assert main(["dataset", "synth", str(d / "set"), "--n-box", "1", "--n-stairs", "0",
                 "--n-ramp", "0", "--seed", "4", "--quiet"]) == 0
    model = d / "model"
    model.mkdir()
    (model / "rules.pl").write_text("box(A) :- nplanes(A, N), gteq(N, 1).\n")
    scan = d / "set" / "s0000.depth.png"
    facts = d / "s.pl"
    assert main(["describe", str(scan), "-o", str(facts)]) == 0
    return model, scan, facts, d / "set"


@pytest.mark.parametrize("case,said", [
    ("forgotten", "is a scan, not a model; the model comes first"),
    ("swapped", "is a scan, not a model; the model comes first"),
    ("facts", "is a facts file from planerel describe, not a model"),
    ("scans folder", "holds no rules.pl, so it is no model"),
    ("no input", "no INPUT: give one or more scans after the model"),
])
def test_mixed_up_arguments_are_named(setup, case, said, capsys):
    model, scan, facts, folder = setup
    args = {"forgotten": [str(scan)], "swapped": [str(scan), str(model)],
            "facts": [str(facts), str(scan)], "scans folder": [str(folder), str(scan)],
            "no input": [str(model)]}[case]
    assert main(["classify", *args]) == 2
    err = capsys.readouterr().err
    assert said in err and "planerel classify MODEL INPUT" in err
    assert err.count("\n") == 1  # one line, no usage dump, no traceback


def test_the_right_order_still_classifies(setup, capsys):
    model, scan, _, _ = setup
    assert main(["classify", str(model), str(scan)]) == 0
    assert ": box" in capsys.readouterr().out


def _classify(rules, cloud, **kw):
    cloud = dataclasses.replace(cloud, up=None)  # estimated, as a frame without a sidecar up
    with Classifier(rules) as clf:
        return clf.classify(cloud, scene_id="s", **kw)


def test_an_up_against_a_confident_estimate_is_noted(setup):
    """user89: ``--up 0,1,0`` on a Kinect frame whose up the planes give with confidence 0.97
    lost its box without a word; the answer now notes it."""
    rules, scan, _, _ = setup
    cloud = io.read(scan)
    truth = np.asarray(cloud.up, float)
    est = _classify(rules, cloud)
    assert est.up_confidence >= 0.8 and est.input_notes == ()
    assert np.degrees(np.arccos(np.clip(np.asarray(est.up_vector) @ truth, -1, 1))) < 5
    wrong = _classify(rules, cloud, up=-truth)
    (note,) = wrong.input_notes
    assert "the given up is 180 degrees from the up the planes give" in note
    assert note in wrong.notes() and wrong.to_dict()["input_notes"] == [note]
    assert tuple(wrong.up_vector) == pytest.approx(tuple(-truth))  # used as given
    right = _classify(rules, cloud, up=truth)
    assert right.input_notes == () and "input_notes" not in right.to_dict()


def test_a_camera_height_far_from_the_floor_in_view_is_noted(setup):
    """user89: ``--camera-height 100`` with the floor 0.71 m under the camera passed."""
    rules, scan, _, _ = setup
    cloud = io.read(scan)
    ans = _classify(rules, cloud)
    assert ans.floor is not None
    below = ans.camera_height  # None: not given
    assert below is None
    far = _classify(rules, cloud, camera_height=100.0)
    (note,) = far.input_notes
    assert note.startswith("--camera-height 100 m, but the floor plane in view lies ")
    lies = float(note.split("lies ")[1].split(" m")[0])
    assert 0.3 < lies < 3.0
    assert _classify(rules, cloud, camera_height=lies).input_notes == ()


def test_intrinsics_an_organized_cloud_does_not_use_are_noted(setup, tmp_path, capsys):
    """user89: ``--intrinsics`` on an organized PCD was ignored without a word."""
    _, scan, _, _ = setup
    pcd = tmp_path / "scan.pcd"
    assert main(["convert", str(scan), "-o", str(pcd)]) == 0
    capsys.readouterr()
    other = "160,120,100,100,80,60"
    assert main(["describe", str(pcd), "-o", str(tmp_path / "f.pl"), "--intrinsics",
                 other]) == 0
    assert "an organized cloud carries its own points; --intrinsics is not used" in \
        capsys.readouterr().err
    # a depth image takes them: no note
    assert main(["describe", str(scan), "-o", str(tmp_path / "g.pl"), "--intrinsics",
                 other]) == 0
    assert "is not used" not in capsys.readouterr().err
