"""The training world's small-face part (face31): a small box seen as one side face, its top out
of sight, so that the one-face box rule's training proofs reach down to a table-top box's face
(a RealSense's view of a cracker box: 0.03 m^2, which the decision's proof gate refused against
the face part's 0.16-0.94 m^2)."""

import json
import os
import sys
from pathlib import Path

import numpy as np
import pytest

from planerel.errors import InputError

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_real_rules import demo_model  # noqa: E402,F401  (the fixture: the shipped model)


def test_training_world_small_face_part(tmp_path):
    from planerel.synth.training_world import KINECT_SMALL_FACES, generate_training_world

    out = generate_training_world(tmp_path / "w", paper=(0, 0, 0), room=(0, 0, 0),
                                  small_faces=4, size=(640, 480), subsample=4)
    info = json.loads((out / "dataset.json").read_text())
    assert info["counts"]["small_faces"] == 4 and info["world"].endswith("+small-faces")
    rows = (out / "manifest.csv").read_text().splitlines()[1:]
    assert len(rows) == 4 and all(",box" in r for r in rows)
    lo, hi = KINECT_SMALL_FACES["box_height"]
    for f in sorted(out.glob("s*.json")):
        scene = json.loads(f.read_text())
        box = next(o for o in scene["objects"] if o["class"] == "box")
        assert lo <= box["params"]["height"] <= hi  # a small box
        cam = scene["params"]["camera"]["height"]
        assert KINECT_SMALL_FACES["camera_height"][0] <= cam <= KINECT_SMALL_FACES["camera_height"][1]
    with pytest.raises(InputError, match="small-face scene count"):
        generate_training_world(tmp_path / "x", small_faces=-1)


def test_a_small_box_seen_from_near_the_floor_shows_a_small_tall_face(tmp_path):
    """What the part teaches: the box's face is a ``tall_face`` (top out of sight) under the
    0.1 m^2 the proof gate's bound stood at before it."""
    from planerel.features.facts import describe_scene
    from planerel.io import read
    from planerel.segment import segment
    from planerel.synth.training_world import generate_training_world

    out = generate_training_world(tmp_path / "w", paper=(0, 0, 0), room=(0, 0, 0),
                                  small_faces=6, size=(640, 480), subsample=4)
    small = []
    for f in sorted(out.glob("s*.depth.png")):
        cloud = read(f)
        desc = describe_scene(cloud, segment(cloud).labels, scene_id="s")
        small += [p.area for p in desc.planes if p.label in desc.tall and p.area < 0.1]
    assert small, "no small tall face in six small-face scenes"
    assert all(a > 0.005 for a in small)


_DATA = Path(os.environ.get("PLANEREL_TABLETOP_DATA", "/nonexistent"))


def test_a_cracker_box_seen_face_on_by_a_realsense_is_a_box(demo_model):  # noqa: F811
    """UOIS image_0002 (RealSense over a table): the cracker box's face, its top cut by the
    image's top, is a tall face of 0.034 m^2; the demo model's one-face rule proves it and,
    with the small-face part, the proof gate no longer refuses it."""
    path = _DATA / "uois" / "image_0002.npy"
    if not path.is_file():
        pytest.skip(f"no UOIS frames under {_DATA} (set PLANEREL_TABLETOP_DATA)")
    root = Path(__file__).resolve().parents[1]
    sys.path.insert(0, str(root / "benchmarks"))
    from real_tabletop import UOIS_INTRINSICS, point_answer, read_frame

    from planerel.classify import Classifier

    cloud = read_frame(str(path), UOIS_INTRINSICS)
    with Classifier(demo_model) as clf:
        ans = clf.classify(cloud, scene_id="image_0002")
    prop = np.full(cloud.xyz.shape[:2], -1)
    for k, o in enumerate(ans.objects):
        prop[np.isin(ans.labels, list(o.labels))] = k
    k = point_answer(prop, 265, 75)  # the cracker box (benchmarks/real_tabletop.py)
    assert k >= 0 and ans.objects[k].klass == "box"
