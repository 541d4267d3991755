"""The training world's panel part: steep panels and sofas (class ``other``) beside ramps.

A large inclined plane too steep to walk on is no ramp.  Real rooms' far upholstered furniture
measured 27-75 degrees and was ``ramp`` by the demo's "an inclined plane of 0.4 m^2 or more"
(docs/objects.md, "Steep planes are no ramps"); the panel part gives the learner such planes
as negatives.  Geometry is checked exactly, scenes are generated, described and segmented for
real.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.synth import geometry as sg
from planerel.synth.world import CLUTTER, WorldRange, generate_world_scene

SMALL = dict(size=(640, 480), subsample=8)


def _incline(poly) -> float:
    n = poly.normal()
    return math.degrees(math.acos(min(1.0, abs(float(n[2])))))


def test_sofa_geometry_back_leans_over_a_level_seat():
    g = sg.sofa_geometry(1.8, 0.9, 0.42, 0.55, 68.0, seat_tilt_deg=3.0, arm_height=0.62)
    roles = {}
    for p in g.polygons:
        roles.setdefault(g.planes[p.plane].role, []).append(p)
    (back,) = roles["back"]
    (seat,) = roles["seat"]
    assert _incline(back) == pytest.approx(68.0, abs=1e-6)
    assert _incline(seat) == pytest.approx(3.0, abs=1e-6)
    # the back rises from the seat's rear edge to inside the sofa's footprint
    pts = np.asarray(back.vertices, float)
    assert pts[:, 0].min() == pytest.approx(-0.45) and pts[:, 2].max() > 0.42
    # arms: outer and inner sides and fronts (``side``), tops
    assert len(roles["side"]) == 6 and len(roles["top"]) == 2
    for bad in (dict(back_deg=95.0), dict(seat_tilt_deg=40.0), dict(width=0.2)):
        kw = dict(width=1.8, depth=0.9, seat_height=0.42, back_height=0.55, back_deg=68.0)
        kw.update(bad)
        with pytest.raises(InputError):
            sg.sofa_geometry(**kw)
    with pytest.raises(InputError, match="too small"):
        sg.sofa_geometry(1.8, 0.2, 0.42, 0.9, 30.0)


def test_panel_share_makes_the_clutter_panels_and_sofas():
    kinds = {}
    for seed in range(16):
        s = generate_world_scene("ramp", seed, **SMALL,
                                 ranges=WorldRange(panel_share=1.0, extra_objects=(2, 3)))
        for o in s.objects[2:]:
            if o["class"] == "other":
                kinds[o["kind"]] = kinds.get(o["kind"], 0) + 1
                assert o["kind"] in ("panel", "sofa")
                if o["kind"] == "panel":
                    assert 30.0 <= o["params"]["tilt_deg"] <= 80.0
                    assert o["params"]["length"] >= 0.8
                else:
                    assert 60.0 <= o["params"]["back_deg"] <= 78.0
    assert kinds.get("panel", 0) >= 3 and kinds.get("sofa", 0) >= 3
    # neither is in the uniform pick: the default world is unchanged
    assert "panel" not in CLUTTER and "sofa" not in CLUTTER
    for seed in (3, 7):
        a = generate_world_scene("box", seed, **SMALL, ranges=WorldRange(panel_share=0.0))
        b = generate_world_scene("box", seed, **SMALL)
        assert [o.get("params") for o in a.objects] == [o.get("params") for o in b.objects]
        np.testing.assert_array_equal(a.depth_mm, b.depth_mm)
    with pytest.raises(InputError, match="panel share"):
        WorldRange(panel_share=1.5)


def test_training_world_panel_part(tmp_path):
    from planerel.synth.training_world import KINECT_PANELS, generate_training_world

    out = generate_training_world(tmp_path / "w", paper=(0, 0, 0), room=(0, 0, 0), panels=6,
                                  size=(320, 240), subsample=4)
    info = json.loads((out / "dataset.json").read_text())
    assert info["counts"]["panels"] == 6 and info["world"].endswith("+panels")
    rows = (out / "manifest.csv").read_text().splitlines()[1:]
    assert len(rows) == 6 and all(",ramp" in r for r in rows)
    kinds = [o["kind"] for f in sorted(out.glob("s*.json"))
             for o in json.loads(f.read_text())["objects"] if o["class"] == "other"]
    assert {"panel", "sofa"} & set(kinds)
    assert KINECT_PANELS["panel_share"] == 1.0
    with pytest.raises(InputError, match="panel scene count"):
        generate_training_world(tmp_path / "x", panels=-1)


def test_a_steep_panel_is_inclined_and_large():
    # what the ramp rule must learn to refuse: seed 6's panel (40 degrees, 0.89 m^2 in view)
    # measures inclined and over the old rule's 0.4 m^2, beside the scene's ramp (14 degrees)
    from planerel.features.facts import describe_scene
    from planerel.synth.world import _CLUTTER_DRAWS

    assert "panel" in _CLUTTER_DRAWS and "sofa" in _CLUTTER_DRAWS
    s = generate_world_scene("ramp", 6, size=(640, 480), subsample=4,
                             ranges=WorldRange(panel_share=1.0, extra_objects=(2, 3)))
    from planerel.segment import segment

    d = describe_scene(s.cloud, segment(s.cloud).labels, up=s.up)
    steep = [p for p in d.planes if p.orientation == "inclined" and p.incline > 30]
    panels = [o for o in s.objects if o.get("kind") in ("panel", "sofa")]
    assert panels
    assert steep and max(p.area for p in steep) > 0.4
    assert [p for p in d.planes if p.orientation == "inclined" and p.incline < 20 and p.area > 1]
