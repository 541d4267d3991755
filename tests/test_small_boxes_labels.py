"""``benchmarks/small_boxes.py labels`` (small65): an independent set as a labelled folder of
rectangles, read by ``real_unseen.py`` as the real hunts are."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
import independent_scenes as ind  # noqa: E402
import real_unseen  # noqa: E402
import small_boxes  # noqa: E402


def test_each_box_becomes_the_rectangle_of_its_pixels(tmp_path):
    ind.make_set(tmp_path / "set", 2, 6401, (320, 240), kinds=("small_box",), sensor="kinect")
    doc = small_boxes.labels(str(tmp_path / "set"), str(tmp_path / "lab"), min_pixels=40)
    assert [f["file"] for f in doc["frames"]] == ["i0000.npy", "i0001.npy"]
    assert json.loads((tmp_path / "lab" / "labels.json").read_text()) == doc
    read = real_unseen.read_labels(str(tmp_path / "lab"))
    for frame in read["frames"]:
        stem = frame["file"][:-4]
        truth = np.load(tmp_path / "set" / f"{stem}.objects.npy")
        side = json.loads((tmp_path / "set" / f"{stem}.json").read_text())
        boxes = [o for o in side["objects"] if o["class"] == "box"
                 and int((truth == o["index"]).sum()) >= 40]
        assert len(frame["objects"]) == len(boxes) >= 2
        for o, b in zip(frame["objects"], boxes, strict=True):
            x0, y0, x1, y1 = o["box"]
            m = truth == b["index"]
            assert m[y0:y1, x0:x1].sum() == m.sum()            # every pixel inside
            assert m[y0, x0:x1].any() and m[y1 - 1, x0:x1].any()  # tight
        cloud, up = real_unseen.read_frame(str(tmp_path / "lab"), frame)
        assert cloud.xyz.shape[:2] == truth.shape and up is None
        assert abs(cloud.intrinsics.fx - side["intrinsics"]["fx"]) < 1e-6
