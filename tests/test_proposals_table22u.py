"""table22u: a table standing in the room is an object, its top still support for what stands
on it (``ProposalParams.table_legs``, :mod:`planerel.features.tables`; docs/objects.md "A table
standing in the room: support and an object (table22u)").

Scenes are ray-cast from rectangles (tests/scenes_analytic.py) with their true plane labels: a
1.2 x 0.8 m table top 0.75 m up with a 3 cm front edge, legs of 6 cm posts (their front and
outer faces) and/or an apron, a box on the top.
"""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import Rect, box, floor, render

from planerel.errors import InputError
from planerel.features.facts import describe_scene
from planerel.features.relations import ProposalParams
from planerel.features.tables import table_objects

VIEW = dict(pitch=35, cam_height=1.5, width=320, height=240, noise=0.001)
TABLE = 9  # the table's object id in the scenes


def _table(cx=0.0, cy=2.0, sx=1.2, sy=0.8, h=0.75, leg=0.06, apron=0.0, legs=True):
    out = [Rect((cx, cy, h), (1, 0, 0), (0, 1, 0), sx / 2, sy / 2, TABLE),
           Rect((cx, cy - sy / 2, h - 0.015), (1, 0, 0), (0, 0, 1), sx / 2, 0.015, TABLE)]
    if apron:
        out.append(Rect((cx, cy - sy / 2 + 0.04, h - 0.03 - apron / 2), (1, 0, 0), (0, 0, 1),
                        sx / 2 - 0.04, apron / 2, TABLE))
    if legs:
        half = (h - 0.03) / 2
        for lx in (-1, 1):
            for ly in (-1, 1):
                x, y = cx + lx * (sx / 2 - 0.05), cy + ly * (sy / 2 - 0.05)
                out.append(Rect((x, y - leg / 2, half), (1, 0, 0), (0, 0, 1), leg / 2, half, TABLE))
                out.append(Rect((x + lx * leg / 2, y, half), (0, 1, 0), (0, 0, 1), leg / 2, half, TABLE))
    return out


def _on_table(rects, h=0.75):
    return [Rect((r.center[0], r.center[1], r.center[2] + h), r.e1, r.e2, r.a, r.b, r.obj)
            for r in rects]


def _leg(r) -> bool:
    """A leg's face: the table's vertical rectangles over 0.2 m high."""
    return r.obj == TABLE and abs(r.e2[2]) == 1 and r.b > 0.1


def _scene(table_rects, extra=(), params=None, unassign=None):
    """describe_scene of the floor, the table, a box on it and ``extra``; ``unassign``: the
    rectangles (a predicate) left unlabelled (-1), as a segmentation that found no plane in
    them."""
    rects = [floor(), *table_rects, *_on_table(box(0.1, 2.0, 0.25, 0.2, 0.15, obj=1)), *extra]
    cloud, lab, _up, objs = render(rects, **VIEW)
    if unassign is not None:
        gone = [k for k, r in enumerate(rects) if unassign(r)]
        lab = np.where(np.isin(lab, gone), -1, lab)
    d = describe_scene(cloud, lab, proposal_params=params)
    return d, objs


def _holding(d, objs, obj):
    return [o for o in d.objects if any(objs[x] == obj for x in o.planes)]


def test_a_table_with_legs_in_view_is_an_object_and_its_top_support():
    d, objs = _scene(_table())
    top = 1
    assert top in d.support  # still the ground of the box on it
    tables = [o for o in d.objects if top in o.planes]
    assert len(tables) == 1
    t = set(tables[0].planes)
    assert all(objs[x] == TABLE for x in t)
    legs = {x for x in t if x not in (1, 2)}
    assert len(legs) >= 2  # the front legs' faces, with the top and its edge
    boxes = _holding(d, objs, 1)
    assert len(boxes) == 1 and all(objs[x] == 1 for x in boxes[0].planes)
    # no table plane in another proposal but legs hidden in part under the top (their visible
    # top lies more than TABLE_REACH below it: they stay apart from the table's object; the
    # two back legs, level posts, are one object of their own: legs_apart, synth22y)
    for o in _holding(d, objs, TABLE):
        if o is not tables[0]:
            assert len(o.planes) <= 2 and not (set(o.planes) & {1, 2})
    # before (table_legs 0): the top in no proposal; its edge and front legs one of their own
    old, _ = _scene(_table(), params=ProposalParams(table_legs=0))
    assert top in old.support and all(top not in o.planes for o in old.objects)
    assert any(set(o.planes) == t - {top} for o in old.objects)


def test_a_top_seen_without_legs_or_apron_stays_support_only():
    d, objs = _scene(_table(legs=False))
    assert 1 in d.support
    assert all(1 not in o.planes for o in d.objects)
    assert len(_holding(d, objs, 1)) == 1


@pytest.mark.parametrize("apron,made", [(0.12, True), (0.03, False)])
def test_an_apron_deeper_than_table_legs_makes_the_table_an_object(apron, made):
    # the apron's lowest edge 0.03 + apron below the top: 0.15 m (an apron) or 0.06 m (under
    # table_legs 0.08: as thick as a top's edge)
    d, objs = _scene(_table(legs=False, apron=apron))
    assert 1 in d.support
    tables = [o for o in d.objects if 1 in o.planes]
    assert bool(tables) == made
    if made:
        assert len(tables) == 1 and set(tables[0].planes) == {1, 2, 3}
        assert len(_holding(d, objs, 1)) == 1


def test_a_box_standing_under_the_table_is_not_the_table():
    # a 0.25 m box on the floor under the top: under its outline, but 0.5 m below it
    d, objs = _scene(_table(), extra=box(-0.2, 2.0, 0.3, 0.3, 0.25, obj=2))
    tables = [o for o in d.objects if 1 in o.planes]
    assert len(tables) == 1 and all(objs[x] == TABLE for x in tables[0].planes)
    under = _holding(d, objs, 2)
    assert len(under) == 1 and all(objs[x] == 2 for x in under[0].planes)


def test_legs_no_plane_explains_count_as_posts():
    # the legs left unlabelled: the curved stage makes clusters of their pixels; a part that
    # reaches table_legs below the top and is taller than wide is a leg
    d, objs = _scene(_table(), unassign=_leg)
    tables = [o for o in d.objects if 1 in o.planes]
    assert len(tables) == 1 and tables[0].mask is not None and tables[0].mask.sum() > 100
    old, _ = _scene(_table(), unassign=_leg, params=ProposalParams(table_legs=0))
    assert all(1 not in o.planes for o in old.objects)


def test_an_unexplained_part_wider_than_tall_is_no_leg():
    # a 12 cm apron left unlabelled: its pixels are a cluster reaching 15 cm below the top,
    # but 1.1 m wide: no post, so no table (labelled, the apron's plane makes one)
    def apron(r):
        return r.obj == TABLE and abs(r.e2[2]) == 1 and 0.05 < r.b < 0.1

    d, objs = _scene(_table(legs=False, apron=0.12), unassign=apron)
    assert 1 in d.support and all(1 not in o.planes for o in d.objects)
    assert any(o.mask is not None and not o.planes for o in d.objects) or any(
        o.mask is not None and 2 in o.planes for o in d.objects)
    d, objs = _scene(_table(legs=False, apron=0.12))
    assert any(1 in o.planes for o in d.objects)


def test_unexplained_parts_need_the_points():
    # table_objects on the table's edge with the legs' pixels as its mask: with the points the
    # legs are posts and the top joins them; without, a part no plane explains is never taken
    from planerel.features.curved import CurvedObject

    rects = [floor(), *_table(), *_on_table(box(0.1, 2.0, 0.25, 0.2, 0.15, obj=1))]
    cloud, _lab, _up, _ = render(rects, **VIEW)
    d, objs = _scene(_table(), unassign=_leg)
    t = next(o for o in d.objects if 1 in o.planes)
    edge = [CurvedObject((2,), t.mask, 1.0, False, int(t.mask.sum()))]
    pp = ProposalParams()
    assert table_objects(d.planes, d.support, edge, pp) == edge
    got = table_objects(d.planes, d.support, edge, pp, 0.8, np.asarray(cloud.xyz, float))
    assert len(got) == 1 and got[0].planes == (1, 2) and got[0].mask is not None
    assert table_objects(d.planes, d.support, edge, ProposalParams(table_legs=0), 0.8,
                         np.asarray(cloud.xyz, float)) == edge


def test_table_legs_is_checked():
    with pytest.raises(InputError, match="table_legs"):
        ProposalParams(table_legs=-0.1)
