"""Notes where ``--up`` or ``--camera-height`` disagrees with the scan (user89: ``--up 0,1,0``
on a Kinect frame whose up the planes give with confidence 0.97, and ``--camera-height 100``
with a floor 1 m under the camera, passed without a word)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from planerel.classify.classifier import Classifier
from planerel.cli import main
from planerel.io import readers as io


@pytest.fixture(scope="module")
def frame(tmp_path_factory):
    d = tmp_path_factory.mktemp("notes")
    assert main(["dataset", "synth", str(d / "set"), "--n-box", "1", "--n-stairs", "0",
                 "--n-ramp", "0", "--seed", "6", "--quiet"]) == 0
    rules = d / "rules.pl"
    rules.write_text("box(A) :- nplanes(A, N), gteq(N, 1).\n")
    cloud = io.read(d / "set" / "s0000.depth.png")
    return rules, cloud


def _classify(rules, cloud, **kw):
    cloud = dataclasses.replace(cloud, up=None)  # estimated, as a frame without a sidecar up
    with Classifier(rules) as clf:
        return clf.classify(cloud, scene_id="s", **kw)


def test_an_up_against_a_confident_estimate_is_noted(frame):
    rules, cloud = frame
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


def test_a_camera_height_far_from_the_floor_in_view_is_noted(frame):
    rules, cloud = frame
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
