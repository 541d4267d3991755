"""Real table-top boxes the rules missed (realbox, docs/objects.md): a box top's rounded edge
read as a fan of facets, a narrow top's fit tilted towards its face by that edge, and a box
leaning on something (its top inclined 10-25 degrees).  Rendered analytic scenes; each test
fails with the earlier behaviour (the parameter that switches the rule off)."""

from __future__ import annotations

import importlib.util
import math
import os
import sys
from pathlib import Path

import numpy as np
import pytest
from scenes_analytic import Rect, box, floor, render

from planerel.errors import InputError
from planerel.features.curved import CurvedParams
from planerel.features.facts import describe_scene
from planerel.features.planes import measure_planes
from planerel.features.relations import RelationParams, leans_towards, relate

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_real_rules import demo_model  # noqa: E402,F401  (the fixture)

# a table-top view: 1 m away, 45 degrees down, 320x240
VIEW = {"pitch": 45, "cam_height": 0.8, "width": 320, "height": 240}


def _rot_x(deg: float) -> np.ndarray:
    a = math.radians(deg)
    return np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])


def _tilted_box(cx, cy, sx, sy, sz, z0, deg, obj=1):
    """``box(...)``'s top and four sides, rotated by ``deg`` about the x axis through the
    box's centre (positive: the top's normal turns towards -y, the camera) and lifted to
    ``z0`` above the floor at its centre."""
    R = _rot_x(deg)
    c0 = np.array([cx, cy, sz / 2])
    out = []
    for r in box(cx, cy, sx, sy, sz, obj):
        c = R @ (np.asarray(r.center, float) - c0) + np.array([cx, cy, z0])
        out.append(Rect(tuple(c), tuple(R @ np.asarray(r.e1, float)),
                        tuple(R @ np.asarray(r.e2, float)), r.a, r.b, obj))
    return out


def _relate(rects, relation_params=None, **view):
    cloud, lab, _, _ = render(rects, noise=0.0012, **(view or VIEW))
    ps = measure_planes(cloud, lab)
    return cloud, lab, ps, relate(ps, cloud, relation_params)


def test_a_box_leaning_16_degrees_has_a_skirt_in_its_own_frame():
    # a 16 x 12 x 6 cm block leaning back 16 degrees (the real OSD frames' grey and wooden
    # blocks lie so on a book): top 1, front 2, left 3, right 4 (seen: 1, 2, 3)
    rects = [floor()] + _tilted_box(0.14, 0.75, 0.16, 0.12, 0.06, 0.06, -16.0)
    cloud, lab, ps, rel = _relate(rects)
    top, side = ps.by_label(1), ps.by_label(3)
    assert top.orientation == "inclined" and top.incline == pytest.approx(16, abs=2)
    assert side.orientation == "vertical"
    assert rel.get(1, 3).skirt  # the left side hangs below the top in the top's own frame
    assert not rel.get(3, 1).skirt
    # before realbox (tops horizontal only): no skirt
    assert not relate(ps, cloud, RelationParams(skirt_tilted=0.0)).get(1, 3).skirt


def test_a_long_tilted_plane_and_an_end_face_past_a_strip_are_no_tilted_skirt():
    # a ramp's slope (1.2 m, 15 degrees) with its vertical side face below it: longer than a
    # box one can tip over
    a = math.radians(15.0)
    slope = Rect((0.0, 2.0 + 0.6 * math.cos(a), 0.6 * math.sin(a)), (1, 0, 0),
                 (0, math.cos(a), math.sin(a)), 0.4, 0.6, 1)
    # the side: a vertical rectangle under the slope's left edge, as high as the slope's rise
    side = Rect((-0.4, 2.0 + 0.6 * math.cos(a), 0.6 * math.sin(a) / 2), (0, 1, 0), (0, 0, 1),
                0.6 * math.cos(a), 0.6 * math.sin(a) / 2, 1)
    _, _, ps, rel = _relate([floor(), slope, side], pitch=30, cam_height=1.2)
    assert ps.by_label(1).orientation == "inclined"
    assert not rel.get(1, 2).skirt
    # a lying cylinder's strip (5 cm wide, 13 degrees) and its end face (10 cm across) below
    # it: the end reaches past both of the strip's ends
    R = _rot_x(-13.0)
    strip = Rect((0.0, 0.75, 0.09), (1, 0, 0), tuple(R @ np.array([0, 1.0, 0])), 0.07, 0.025, 1)
    end = Rect((-0.07, 0.75, 0.05), (0, 1, 0), (0, 0, 1), 0.05, 0.04, 1)
    _, _, ps, rel = _relate([floor(), strip, end])
    assert ps.by_label(1).orientation == "inclined" and ps.by_label(2).orientation == "vertical"
    assert rel.get(1, 2).adjacent and not rel.get(1, 2).skirt


def test_a_narrow_top_leaning_towards_its_front_has_a_skirt():
    # a cereal box standing, 24 x 6 x 30 cm: its narrow top's fit tilted 7 degrees towards
    # the front by the rounded edge (real Kinect and RealSense frames: 6.4 and 6.8 degrees)
    top = Rect((0.0, 0.8, 0.30), (1, 0, 0), tuple(_rot_x(7.0) @ np.array([0, 1.0, 0])), 0.12,
               0.03, 1)
    front = Rect((0.0, 0.77, 0.15), (1, 0, 0), (0, 0, 1), 0.12, 0.15, 1)
    cloud, _, ps, rel = _relate([floor(), top, front])
    t, f = ps.by_label(1), ps.by_label(2)
    assert t.orientation == "inclined" and t.incline == pytest.approx(7, abs=1.5)
    assert leans_towards(t, f, ps.up)
    assert rel.get(1, 2).skirt
    # before realbox: a skirt's top had to be horizontal
    assert not relate(ps, cloud, RelationParams(skirt_top_tilt=0.0, skirt_tilted=0.0)).get(1, 2).skirt
    # the same top leaning away from the front (a ramp's slope falling away from the face
    # below its high end) does not lean towards it
    away = Rect((0.0, 0.8, 0.30), (1, 0, 0), tuple(_rot_x(-7.0) @ np.array([0, 1.0, 0])), 0.12,
                0.03, 1)
    _, _, ps2, _ = _relate([floor(), away, front])
    assert not leans_towards(ps2.by_label(1), ps2.by_label(2), ps2.up)


def _bevelled_box():
    """A box 24 cm wide, 10 cm deep, 10 cm high whose top-front edge is rounded into two
    1.2 cm strips at 30 and 60 degrees: top 1, front 2, strips 3 and 4."""
    w, d, h, s = 0.24, 0.10, 0.10, 0.012
    y0, yf = 0.8, 0.8 - d / 2  # centre, front plane
    a30, a60 = math.radians(30), math.radians(60)
    # from the front's top edge (yf, h - e) up and back to the top's front edge (yf + e, h)
    e = s * (math.cos(a30) + math.cos(a60))  # both strips' horizontal (= vertical) run
    top = Rect((0.0, (yf + e + y0 + d / 2) / 2, h), (1, 0, 0), (0, 1, 0), w / 2,
               (y0 + d / 2 - yf - e) / 2, 1)
    front = Rect((0.0, yf, (h - e) / 2), (1, 0, 0), (0, 0, 1), w / 2, (h - e) / 2, 1)
    # the strip beside the front: 60 degrees from horizontal; then 30 degrees
    d1 = np.array([0, math.cos(a60), math.sin(a60)])
    p1 = np.array([0, yf, h - e]) + d1 * s / 2
    d2 = np.array([0, math.cos(a30), math.sin(a30)])
    p2 = np.array([0, yf, h - e]) + d1 * s + d2 * s / 2
    lower = Rect(tuple(p1), (1, 0, 0), tuple(d1), w / 2, s / 2, 1)
    upper = Rect(tuple(p2), (1, 0, 0), tuple(d2), w / 2, s / 2, 1)
    return [floor(), top, front, lower, upper]


def test_a_rounded_box_edge_is_no_fan_of_facets():
    cloud, lab, _, _ = render(_bevelled_box(), noise=0.0012, **VIEW)
    desc = describe_scene(cloud, lab, scene_id="s0001")
    planes = {p.label for p in desc.planes}
    assert {1, 2, 3, 4} <= planes
    assert desc.relations.get(1, 2).skirt
    (obj,) = [o for o in desc.objects if 1 in o.planes]
    assert {1, 2} <= set(obj.planes)
    assert obj.planar_fraction >= 0.9 and not obj.curved
    # before realbox: top, strips and front linked 30 degrees apart, four directions, a fan;
    # the top and the strips were facets and the box read round (the gate refused `box`)
    # (and before the wide-face rule, facet_max_width, which since 0.05 m keeps this front
    # flat on its own)
    old = describe_scene(cloud, lab, scene_id="s0001",
                         curved_params=CurvedParams(skirt_faces=False, facet_max_width=0.0))
    (old_obj,) = [o for o in old.objects if 1 in o.planes]
    assert old_obj.planar_fraction < 0.7


def test_realbox_parameters_are_checked():
    with pytest.raises(InputError, match="skirt_faces"):
        CurvedParams(skirt_faces=1)
    with pytest.raises(InputError, match="skirt_top_tilt"):
        RelationParams(skirt_top_tilt=50.0)
    with pytest.raises(InputError, match="skirt_tilted"):
        RelationParams(skirt_tilted=-1.0)


def test_a_lying_cylinders_strip_and_end_face_are_no_flat_faces():
    from planerel.features.curved import skirt_faces

    # the strip on top of a lying cylinder (14 x 5 cm, level) and its end face below it, 10 cm
    # across: a skirt (as before realbox), but the end reaches past both ends of the strip
    strip = Rect((0.0, 0.75, 0.10), (1, 0, 0), (0, 1, 0), 0.07, 0.025, 1)
    end = Rect((-0.07, 0.75, 0.05), (0, 1, 0), (0, 0, 1), 0.05, 0.05, 1)
    cloud, _, ps, rel = _relate([floor(), strip, end])
    assert rel.get(1, 2).skirt
    assert skirt_faces(ps, rel, cloud) == set()
    # a box's top and front end together: flat faces; without the cloud nothing is measured
    cloud, _, ps, rel = _relate([floor()] + box(0.0, 0.8, 0.16, 0.10, 0.08))
    assert rel.get(1, 2).skirt
    assert {1, 2} <= skirt_faces(ps, rel, cloud)
    assert skirt_faces(ps, rel, None) == set()


# the real frames (``PLANEREL_TABLETOP_DATA`` holding ``osd/`` and ``uois/``,
# benchmarks/real_tabletop.py): the boxes these rules made `box`, and nothing new false
_DATA = Path(os.environ.get("PLANEREL_TABLETOP_DATA", "/nonexistent"))
_FIXED = {  # (frame, annotation name): the rule that made it `box`
    ("uois/image_0001", "Cheez-It box"): "skirt_faces",
    ("osd/test63", "milk carton"): "skirt_faces",
    ("osd/test50", "small box"): "skirt_faces",
    ("uois/image_0005", "large container"): "skirt_faces",
    ("uois/image_0000", "Cheez-It box"): "skirt_top_tilt",
    ("osd/test50", "grey block"): "skirt_tilted",
    ("osd/test64", "wooden block"): "skirt_tilted",
    ("osd/test63", "tea box on a book"): "skirt_tilted",
    # ("osd/test63", "green book") was `box` only as part of the tea box's proposal; since
    # apart_gap (docs/objects.md) the two are separate proposals and the book alone is `other`
}


def test_real_tabletop_boxes_fixed(demo_model):  # noqa: F811  (the imported fixture)
    spec = importlib.util.spec_from_file_location(
        "real_tabletop", Path(__file__).resolve().parents[1] / "benchmarks" / "real_tabletop.py")
    rt = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(rt)
    todo = rt.frames(str(_DATA / "osd"), str(_DATA / "uois"))
    if len(todo) < 14:
        pytest.skip(f"no real table-top frames under {_DATA} (set PLANEREL_TABLETOP_DATA)")
    from planerel.classify import Classifier

    with Classifier(demo_model) as clf:
        rows = [rt.frame(clf, *t) for t in todo]
    got = {(r["frame"], p["name"]): p["answer"] for r in rows for p in r["points"]}
    assert all(got[k] == "box" for k in _FIXED), {k: got[k] for k in _FIXED}
    s = rt.summarize(rows)
    assert s["boxes_box"] >= 15  # main: 6 of 34
    assert s["round_stairs_ramp"] == 0 and s["other_box"] == 0  # 14b64af: 10 of 54, 0 of 8
    assert s["stairs_answers"] <= 1  # 14b64af: 11 (falsecls, docs/results.md)
