"""Table tops are support (falsecls, docs/objects.md "Real table-tops nobody on the team made").

A table seen with the room's floor in view is no floor-level plane and smaller than
``support_min_area``, so before this rule it was a plane of the object proposal of whatever
stood on it: on the real OSD and RealSense frames the table and a tin's lid (or a flat box
on it) were ``parallel`` and one ``above`` the other, and the demo's stairs rule 4 called the
table with its objects ``stairs`` (6 of the 13 false stairs / ramp answers).  Scenes are
ray-cast from rectangles (tests/scenes_analytic.py), with their true plane labels.
"""

from __future__ import annotations

import pytest
from scenes_analytic import Rect, box, floor, render, stairs

from planerel.errors import InputError
from planerel.features.facts import describe_scene
from planerel.features.relations import ProposalParams

VIEW = dict(pitch=40, cam_height=1.5, width=320, height=240, noise=0.001)


def _table(cx=0.0, cy=1.6, sx=1.2, sy=0.8, h=0.75, obj=9):
    """A table top with a 3 cm edge all round (no legs in view: they are thin)."""
    return [Rect((cx, cy, h), (1, 0, 0), (0, 1, 0), sx / 2, sy / 2, obj),
            Rect((cx, cy - sy / 2, h - 0.015), (1, 0, 0), (0, 0, 1), sx / 2, 0.015, obj)]


def _on_table(rects, h=0.75):
    """Rectangles of an object built on the floor, lifted onto a table top ``h`` high."""
    return [Rect((r.center[0], r.center[1], r.center[2] + h), r.e1, r.e2, r.a, r.b, r.obj)
            for r in rects]


def _scene(rects, params=None):
    cloud, lab, _up, objs = render(rects, **VIEW)
    d = describe_scene(cloud, lab, proposal_params=params)
    return d, objs


def test_a_table_with_a_box_on_it_is_support_and_the_box_its_own_object():
    rects = [floor()] + _table() + _on_table(box(0.1, 1.6, 0.2, 0.15, 0.12, obj=1))
    d, objs = _scene(rects)
    top = 1  # the table top's label (rects[1])
    assert top in d.support
    boxes = [set(o.planes) for o in d.objects if any(objs[x] == 1 for x in o.planes)]
    assert len(boxes) == 1 and all(objs[x] == 1 for x in boxes[0])
    assert all(top not in o.planes for o in d.objects)
    # before (table_area 0): the table top was an object proposal (on the real frames, one
    # with the objects on it)
    old, _ = _scene(rects, ProposalParams(table_area=0.0))
    assert top not in old.support
    assert any(top in o.planes for o in old.objects)


def test_a_table_with_a_tin_on_a_box_is_support():
    # test42's stack, in boxes: a small box on a lower one, on the table; the two tops are
    # parallel and one above the other, the table no part of them
    rects = ([floor()] + _table() + _on_table(box(0.0, 1.6, 0.16, 0.16, 0.1, obj=1))
             + _on_table(box(0.0, 1.6, 0.12, 0.12, 0.1, obj=1), h=0.85))
    d, objs = _scene(rects)
    assert 1 in d.support
    assert all(1 not in o.planes for o in d.objects)


def test_an_empty_table_and_a_large_box_are_no_support():
    # nothing stands on them: a table top alone, and a 1.0 x 0.8 x 0.6 m box's top
    d, objs = _scene([floor()] + _table())
    assert 1 not in d.support
    d, objs = _scene([floor()] + box(0.0, 1.8, 1.0, 0.8, 0.6, obj=1))
    assert 1 not in d.support
    assert any(1 in o.planes for o in d.objects)


@pytest.mark.parametrize("n", [3, 5])
def test_no_tread_of_a_flight_is_a_table(n):
    # treads 0.34-0.85 m up and 0.28 x 1.2 m (0.34 m^2): each has the next step standing on
    # it, but treads of the same size lie one rise above and below
    rects = [floor()] + stairs(0.0, 1.6, n=n, width=1.2)
    d, objs = _scene(rects)
    assert not any(objs[x] == 1 for x in d.support)
    flights = [o for o in d.objects if any(objs[x] == 1 for x in o.planes)]
    assert len(flights) == 1


def test_table_params_are_checked():
    with pytest.raises(InputError, match="table_area"):
        ProposalParams(table_area=-0.1)
    with pytest.raises(InputError, match="table_height"):
        ProposalParams(table_height=float("nan"))


def _table_in_pieces(h=0.75):
    """A 1.2 x 0.8 m table top in two pieces, a strip 0.25 m deep at the front (a tread to
    relate()) and the rest, and its 3 cm front edge."""
    return [Rect((0, 1.325, h), (1, 0, 0), (0, 1, 0), 0.6, 0.125, 9),
            Rect((0, 1.725, h), (1, 0, 0), (0, 1, 0), 0.6, 0.275, 9),
            Rect((0, 1.2, h - 0.015), (1, 0, 0), (0, 0, 1), 0.6, 0.015, 9)]


def test_a_box_standing_on_a_table_keeps_its_skirt():
    # the box's front hangs from its top down to the table's front strip, which relate()
    # takes for a tread (a face standing on a tread is a riser, no skirt); the strip was a
    # plane of the table's proposal, another object, which gave the skirt back; as support
    # it is in no object, and a tread that is support is the ground (m11's t0028 box went
    # box -> other without this rule)
    from planerel.features.relations import relate, skirts_within_objects

    rects = [floor()] + _table_in_pieces() + _on_table(box(0.0, 1.6, 0.3, 0.4, 0.15, obj=1))
    cloud, lab, _up, objs = render(rects, **VIEW)
    d = describe_scene(cloud, lab)
    top, front = 4, 5  # the box's top and its face towards the camera
    assert {1, 2} <= set(d.support) and (4, 5) in [tuple(o.planes) for o in d.objects]
    assert [x for x, _ in d.relations.skirt_steps[(top, front)]] == [1]  # the strip said no
    assert d.relations.get(top, front).skirt
    raw = relate(d.planes, cloud)
    assert not raw.get(top, front).skirt
    objects = [o.planes for o in d.objects]
    assert not skirts_within_objects(raw, objects, d.planes).get(top, front).skirt
    assert skirts_within_objects(raw, objects, d.planes, d.support).get(top, front).skirt
