"""A carton's top lying on a pile, a depth step all round, is no facet (``CurvedParams.island_faces``;
docs/objects.md "A carton's top on a pile"); a round surface's touching strips stay facets."""

from __future__ import annotations

import math

from scenes_analytic import Rect, floor, render

from planerel.features.curved import CurvedParams, facet_planes
from planerel.features.facts import describe_scene


def _tilted(cx, cy, cz, axis, deg, a, b, obj):
    t = math.radians(deg)
    if axis == "y":  # tilted about the world's y axis
        e1 = (math.cos(t), 0.0, math.sin(t))
        e2 = (0.0, 1.0, 0.0)
    else:  # about x
        e1 = (1.0, 0.0, 0.0)
        e2 = (0.0, math.cos(t), math.sin(t))
    return Rect((cx, cy, cz), e1, e2, a, b, obj)


def _pile(yc=0.14, gap=0.02):
    """A level carton top 8 cm wide, 3 cm above three pieces tilted 20-30 degrees around it,
    ``gap`` m away from it in plan."""
    top = Rect((0.0, yc, 0.12), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), 0.04, 0.1, 1)
    left = _tilted(-0.08 - gap, yc, 0.09, "y", 20.0, 0.04, 0.1, 2)
    right = _tilted(0.08 + gap, yc, 0.09, "y", -30.0, 0.04, 0.1, 3)
    front = _tilted(0.0, yc - 0.14 - gap, 0.09, "x", 25.0, 0.12, 0.04, 4)
    return [floor(), top, left, right, front]


def _facets(rects):
    """The facet planes of a scene seen from 0.8 m, 80 degrees down, with island faces on and
    off."""
    cloud, lab, _up, _objs = render(rects, pitch=80, cam_height=0.8, width=320, height=240)
    d = describe_scene(cloud, lab)
    cand = [p.label for p in d.planes if p.label not in set(d.support)]
    return (facet_planes(d.planes, d.relations, cand, CurvedParams()),
            facet_planes(d.planes, d.relations, cand, CurvedParams(island_faces=False)))


def test_a_carton_top_on_a_pile_is_no_facet():
    on, off = _facets(_pile())
    assert 1 in off and 1 not in on


def _drum(yc=0.14, r=0.17, step=20.0):
    """Three strips 6 cm wide of a lying drum of radius ``r`` (their edges shared)."""
    out = []
    a = r * math.tan(math.radians(step / 2))
    for k in (-1, 0, 1):
        t = math.radians(k * step)
        out.append(Rect((r * math.sin(t), yc, 0.02 + r * math.cos(t)), (math.cos(t), 0.0, -math.sin(t)),
                        (0.0, 1.0, 0.0), a, 0.1, 1))
    return [floor()] + out


def test_a_round_surface_s_wide_strips_stay_facets():
    on, off = _facets(_drum())
    assert on == off == {1, 2, 3}
