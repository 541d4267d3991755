"""pile26: the training world's pile part, cartons packed side by side at two heights.

``examples/demo.py --piles N`` adds it (0 in the shipped model: docs/objects.md, "Carton piles
and false answers on unseen frames").  Scenes are generated, segmented and described for real.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from planerel.errors import InputError


def test_a_pile_is_one_box_of_two_heights():
    from planerel.synth.generator import scene_seed
    from planerel.synth.piles import PILE_SETTINGS, generate_pile_scene

    a = generate_pile_scene(scene_seed(6, 0), (640, 480), 4, scene_id="s0000")
    b = generate_pile_scene(scene_seed(6, 0), (640, 480), 4, scene_id="s0000")
    assert np.array_equal(a.depth_mm, b.depth_mm)
    (pile,) = [o for o in a.objects if o["index"] == 1]
    assert pile["class"] == "box" and pile["kind"] == "carton pile"
    p = pile["params"]
    heights = sorted({round(h, 9) for row in p["layout"] for h in row})
    assert len(heights) == 2 and heights[1] == pytest.approx(p["high"])
    assert p["low"] == pytest.approx(heights[0])
    lo, hi = PILE_SETTINGS["height"]
    assert lo <= p["low"] <= hi and p["high"] > p["low"]
    assert PILE_SETTINGS["rows"][0] <= p["rows"] <= PILE_SETTINGS["rows"][1]
    assert pile["n_pixels"] >= 0.03 * 160 * 120 * 0.5


def test_pile_geometry_refuses_bad_input():
    from planerel.synth.piles import pile_geometry

    g = pile_geometry(2, 3, 0.3, 0.25, [[0.2, 0.2, 0.2], [0.4, 0.4, 0.4]])
    assert len(g.polygons) == 6 * 5  # a top and four faces a carton
    with pytest.raises(InputError, match="pile heights must be a"):
        pile_geometry(2, 3, 0.3, 0.25, [[0.2, 0.2], [0.4, 0.4]])
    with pytest.raises(InputError, match="pile heights must be a"):
        pile_geometry(1, 2, 0.3, 0.25, [[0.2, -0.1]])
    with pytest.raises(InputError, match="positive length and width"):
        pile_geometry(1, 1, 0.0, 0.25, [[0.2]])


def test_the_pile_part_makes_box_examples_of_two_levels(tmp_path):
    """Six scenes (seed 0): every pile is a box example, five show tops at two heights, and
    only one (stacked cartons 0.21 m high, the second level one stair rise above the first)
    shows steps of one flight (``flight_evidence``)."""
    from planerel.features.relations import flight_evidence
    from planerel.ilp.scenes import describe_scenes
    from planerel.synth.training_world import generate_training_world

    world = generate_training_world(tmp_path / "w", paper=(0, 0, 0), room=(0, 0, 0), piles=6,
                                    seed=0, size=(640, 480), subsample=4)
    info = json.loads((world / "dataset.json").read_text())
    assert info["counts"]["piles"] == 6 and info["world"].endswith("+piles")
    descs, _ = describe_scenes(world, jobs=1, cache="none", progress=False)
    boxes = [(d, o) for d in descs for o in d.objects if o.klass == "box"]
    assert len(boxes) == 6
    two = [(d, o) for d, o in boxes
           if len({round(p.height, 2) for p in d.planes
                   if p.label in o.planes and p.orientation == "horizontal"}) == 2]
    assert len(two) == 5
    assert sum(flight_evidence(d.planes, o.planes) for d, o in boxes) == 1
    with pytest.raises(InputError, match="pile scene count"):
        generate_training_world(tmp_path / "x", paper=(0, 0, 0), room=(0, 0, 0), piles=-1)
