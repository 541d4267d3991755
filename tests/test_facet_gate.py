"""cube53: no ``box`` through an upright plane that is a facet of a round side
(``decision.facet_gate``, docs/objects.md "Cans seen as two or three facets").

A RealSense D435 at 0.6-0.8 m segments a 6-7 cm can's side into two or three planes 40-69
degrees apart; the cap over one of them is a box's top to ``skirt/2``.  A box's two faces meet
at 79-90 degrees (the D435 rounds a small box's corner), a bevel strip on its edge at under 20.
:func:`planerel.ilp.metrics.facet_refusals` refuses a ``box`` hit whose proof binds an upright
plane with an adjacent upright plane of its object meeting it convexly and level at
``facet_min``-``facet_max`` degrees, and none at ``face_pair_angle`` or more.  Scenes are
ray-cast (tests/scenes_analytic.py), segmented and described for real.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.ilp import metrics as M

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scenes_analytic import Rect, box, floor, render  # noqa: E402


def test_facet_refusals():
    hits = [("box", 1, {"A": "o1", "B": "p3", "C": "p4"}, "box(A) :- ...", None),
            ("box", 4, {"A": "o1", "B": "p5", "C": "p6"}, "box(A) :- ...", None),
            ("stairs", 2, {"A": "o1", "B": "p4"}, "stairs(A) :- ...", None)]
    stats = [(1, "box", 58, 6), (4, "box", 40, 3), (2, "stairs", 70, 1)]
    kept, refused = M.facet_refusals(hits, stats, {"p4": 57.8}.get)
    assert [(h[0], h[1]) for h in kept] == [("box", 4), ("stairs", 2)]
    (r,) = refused
    assert (r.klass, r.rule, r.plane, r.angle) == ("box", 1, "p4", 57.8)
    assert "facet of a round side" in r.reason and r.to_dict()["angle"] == 57.8
    # no facet plane in the proof, or the gate off: every hit kept
    assert len(M.facet_refusals(hits, stats, {}.get)[0]) == 3
    assert len(M.facet_refusals(hits, stats, None)[0]) == 3


def test_the_verdict_on_one_plane():
    from planerel.classify.classifier import _facet_of

    assert _facet_of(((57.8,), False), 25.0, 70.0) == 57.8
    assert _facet_of(((18.8, 67.9), False), 25.0, 70.0) == 67.9
    assert _facet_of(((18.8, 86.6), True), 25.0, 70.0) is None      # a box's corner
    assert _facet_of(((78.7,), False), 25.0, 70.0) is None           # a rounded box corner
    assert _facet_of(((), False), 25.0, 70.0) is None


def test_the_settings_are_checked():
    assert (M.DecisionParams().facet_gate, M.DecisionParams().facet_min,
            M.DecisionParams().facet_max, M.DecisionParams().facet_bridge) == (True, 25.0, 70.0,
                                                                               True)
    for bad in ({"facet_gate": 1}, {"facet_min": -1.0}, {"facet_max": float("nan")},
                {"facet_bridge": "yes"}, {"facet_max": 120.0},
                {"facet_min": 80.0, "facet_max": 70.0}):
        with pytest.raises(InputError):
            M.DecisionParams(**bad)


def _prism(cx, cy, radius, height, sides=6, turn=30.0, obj=2):
    """The upright faces of a regular prism standing on the floor (no cap: the angles between
    its faces are what is measured), its first face's normal ``turn`` degrees from -y."""
    out = []
    apothem = radius * math.cos(math.pi / sides)
    for k in range(sides):
        phi = math.radians(-90.0 + turn + 360.0 * k / sides)
        n = (math.cos(phi), math.sin(phi))
        out.append(Rect((cx + apothem * n[0], cy + apothem * n[1], height / 2),
                        (-n[1], n[0], 0.0), (0.0, 0.0, 1.0), radius * math.sin(math.pi / sides),
                        height / 2, obj))
    return out


def _chamfered_box(cx, cy, half, height, cut, obj=3):
    """A box standing on the floor whose vertical edge nearest a camera on its right (+x) and
    in front (-y) is cut by a 45-degree chamfer ``cut`` m along each face: its front face, the
    chamfer and its right face (the top a full square; the far sides hidden)."""
    s2 = math.sqrt(0.5)
    return [Rect((cx, cy, height), (1, 0, 0), (0, 1, 0), half, half, obj),
            Rect((cx - cut / 2, cy - half, height / 2), (1, 0, 0), (0, 0, 1), half - cut / 2,
                 height / 2, obj),
            Rect((cx + half, cy + cut / 2, height / 2), (0, 1, 0), (0, 0, 1), half - cut / 2,
                 height / 2, obj),
            Rect((cx + half - cut / 2, cy - half + cut / 2, height / 2), (s2, s2, 0.0),
                 (0, 0, 1), cut * s2, height / 2, obj)]


def _faces_of_objects(rects, width=320, height=240, pitch=30.0, cam_height=1.0, **widths):
    from planerel.classify.classifier import _facet_angles
    from planerel.features.facts import describe_scene
    from planerel.segment import segment

    cloud, _lab, up, _objs = render(rects, width=width, height=height, pitch=pitch,
                                    cam_height=cam_height, noise=0.0003)
    labels = segment(cloud).labels
    desc = describe_scene(cloud, labels, scene_id="s", up=up)
    pid = {p.label: desc.plane_id(p.label) for p in desc.planes}
    table = _facet_angles(desc, cloud.xyz, pid, **widths)
    out = []
    for o in desc.objects:
        mine = frozenset(o.planes)
        found = [table(pid[lab], mine) for lab in o.planes]
        verts = [f for lab, f in zip(o.planes, found, strict=True)
                 if desc.planes.by_label(lab).orientation == "vertical"]
        centre = np.nanmean(cloud.xyz[np.isin(desc.labels, list(o.planes))], axis=0)
        out.append((centre, verts))
    return out


def test_a_hexagonal_prism_shows_facets_and_a_box_a_corner():
    """A hexagonal prism (radius 0.2 m) seen with faces 60 degrees apart, and a box with
    its front and side faces 90 degrees apart, ray-cast and described for real: the prism's
    faces each have a facet neighbour at 60 degrees and no corner partner (the gate's verdict
    a facet), the box's faces a corner partner (no facet)."""
    from planerel.classify.classifier import _facet_of

    rects = [floor(), *_prism(0.5, 2.2, 0.2, 0.4), *box(-0.6, 2.2, 0.4, 0.4, 0.4)]
    objs = _faces_of_objects(rects)
    prism = [v for c, v in objs if c[0] > 0.2]
    boxes = [v for c, v in objs if c[0] < -0.2]
    assert len(prism) == 1 and len(boxes) == 1, objs
    (pv,), (bv,) = prism, boxes
    pv = [f for f in pv if f[0]]     # the upright planes with a neighbour (three faces seen)
    assert len(pv) >= 2 and len(bv) == 2, (pv, bv)
    for angles, corner in pv:
        assert not corner and any(abs(a - 60.0) < 3.0 for a in angles), pv
        assert _facet_of((angles, corner), 25.0, 70.0) is not None
    for angles, corner in bv:
        assert corner and any(abs(a - 90.0) < 3.0 for a in angles), bv
        assert _facet_of((angles, corner), 25.0, 70.0) is None


def test_a_box_face_with_a_chamfer_strip_is_no_facet():
    """A box's two faces 0.32 m wide joined by a 45-degree chamfer 0.11 m wide: the faces meet
    no plane at a corner's angle, but the chamfer is far narrower than they are (2.8 times,
    over ``curved.facet_wide_ratio`` 1.5), so it is a bevel strip, not a neighbouring facet of
    a round side (as ``curved.facet_planes`` reads it).  Were widths not compared, both faces
    would be facets at 45 degrees."""
    from planerel.classify.classifier import _facet_of

    rects = [floor(), *_chamfered_box(-0.6, 2.2, 0.2, 0.4, 0.08)]
    (objs,) = [v for c, v in _faces_of_objects(rects) if c[0] < -0.2]
    assert len(objs) >= 3, objs
    assert all(_facet_of(f, 25.0, 70.0) is None for f in objs), objs
    (same,) = [v for c, v in _faces_of_objects(rects, wide_ratio=100.0) if c[0] < -0.2]
    assert sum(_facet_of(f, 25.0, 70.0) is not None for f in same) >= 2, same


def test_a_fan_of_three_strips_is_round_though_its_ends_meet_at_a_corner_angle():
    """Three upright strips 4.1, 2.8 and 4.1 cm wide, 45 degrees apart (a 6 cm block whose
    edge is cut by a 2 cm chamfer: the geometry of rs-booth 1025_test9's can, strips 4.0, 2.4
    and 3.1 cm, 53.9 and 40.9 degrees apart, its ends 85.2), seen from 0.8 m: the two ends
    meet at 90 degrees, a box corner's angle, but the strip between them is a facet
    neighbour of both, alike in width (``decision.facet_bridge``): every strip is a facet.
    Without the bridge the ends read as a box's corner.  Under 5 cm wide
    (``curved.facet_max_width``) a bevelled block and a can's fan are the same planes: the
    bridge cannot tell them apart (docs/objects.md)."""
    from planerel.classify.classifier import _facet_of

    rects = [floor(), *_chamfered_box(-0.45, 0.75, 0.03, 0.12, 0.02)]
    kw = {"width": 640, "height": 480, "pitch": 35.0, "cam_height": 0.6}
    (bridged,) = [v for c, v in _faces_of_objects(rects, bridge=(25.0, 70.0), **kw)]
    (plain,) = [v for c, v in _faces_of_objects(rects, **kw)]
    assert len(bridged) == 3 and len(plain) == 3, (bridged, plain)
    assert all(_facet_of(f, 25.0, 70.0) is not None for f in bridged), bridged
    assert sum(f[1] for f in plain) == 2 and sum(f[1] for f in bridged) == 0, plain
