"""synth22y: the legs of a table or a chair seen without its top are one object
(``ProposalParams.legs_apart``, :func:`planerel.features.tables.leg_objects`; docs/objects.md
"Legs without a top (synth22y)").

Scenes are ray-cast from rectangles (tests/scenes_analytic.py) with their true plane labels: the
legs of a 1.2 x 0.8 m table (6 cm posts, 0.72 m tall, their front and outer faces) standing on
the floor with no top (the varied world's low views see a table so: the top above the image,
or too thin and far to segment), chairs' legs (3.5 cm, 0.42 m), boxes.
"""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import Rect, box, floor, render

from planerel.errors import InputError
from planerel.features.facts import describe_scene
from planerel.features.relations import ProposalParams

VIEW = dict(pitch=25, cam_height=1.3, width=320, height=240, noise=0.001)
OFF = ProposalParams(legs_apart=0)


def _legs(cx=0.0, cy=2.5, sx=1.2, sy=0.8, h=0.72, leg=0.06, obj=9, z0=0.0):
    """The four legs (front and outer faces) of a table (or a chair) of ``sx`` x ``sy``."""
    out = []
    half = h / 2
    for lx in (-1, 1):
        for ly in (-1, 1):
            x, y = cx + lx * (sx / 2 - 0.03 - leg / 2), cy + ly * (sy / 2 - 0.03 - leg / 2)
            out.append(Rect((x, y - leg / 2, z0 + half), (1, 0, 0), (0, 0, 1), leg / 2, half, obj))
            out.append(Rect((x + lx * leg / 2, y, z0 + half), (0, 1, 0), (0, 0, 1), leg / 2, half, obj))
    return out


def _scene(rects, params=None, unassign=None):
    rects = [floor(), *rects]
    cloud, lab, _up, objs = render(rects, **VIEW)
    if unassign is not None:
        gone = [k for k, r in enumerate(rects) if unassign(r)]
        lab = np.where(np.isin(lab, gone), -1, lab)
    return describe_scene(cloud, lab, proposal_params=params), objs, lab


def _holding(d, objs, obj):
    return [o for o in d.objects if any(objs[x] == obj for x in o.planes)]


def test_the_legs_of_a_table_without_its_top_are_one_object():
    d, objs, lab = _scene(_legs())
    tables = _holding(d, objs, 9)
    assert len(tables) == 1
    t = tables[0]
    assert all(objs[x] == 9 for x in t.planes)
    legs_seen = {p.label for p in d.planes if objs[p.label] == 9}
    assert len(legs_seen) >= 4 and set(t.planes) == legs_seen  # every leg face measured
    # before (legs_apart 0): each leg a proposal of its own
    old, _, _ = _scene(_legs(), params=OFF)
    assert len(_holding(old, objs, 9)) >= 3


def test_a_chairs_legs_beside_a_tables_are_not_level_with_them():
    # a chair (0.42 m legs, 3.5 cm) 0.3 m in front of the table: its legs are one object, the
    # table's another (their feet within legs_apart, their tops 0.3 m apart)
    chair = _legs(cx=-0.2, cy=1.75, sx=0.42, sy=0.42, h=0.42, leg=0.035, obj=7)
    d, objs, _ = _scene([*_legs(cx=0.2, cy=2.6), *chair])
    tables, chairs = _holding(d, objs, 9), _holding(d, objs, 7)
    assert len(tables) == 1 and all(objs[x] == 9 for x in tables[0].planes)
    assert len(chairs) == 1 and all(objs[x] == 7 for x in chairs[0].planes)


def test_posts_farther_apart_than_legs_apart_stay_apart():
    # two single posts 2.4 m apart (more than 1.8 m): not one object
    a = _legs(cx=-1.2, cy=2.5, sx=0.12, sy=0.12, obj=3)[:2]
    b = _legs(cx=1.2, cy=2.5, sx=0.12, sy=0.12, obj=4)[:2]
    d, objs, _ = _scene([*a, *b])
    assert len(_holding(d, objs, 3)) == 1 and len(_holding(d, objs, 4)) == 1
    assert _holding(d, objs, 3)[0] is not _holding(d, objs, 4)[0]
    # 1.4 m apart they are
    a = _legs(cx=-0.7, cy=2.5, sx=0.12, sy=0.12, obj=3)[:2]
    b = _legs(cx=0.7, cy=2.5, sx=0.12, sy=0.12, obj=4)[:2]
    d, objs, _ = _scene([*a, *b])
    assert _holding(d, objs, 3) == _holding(d, objs, 4) and len(_holding(d, objs, 3)) == 1


def test_a_box_among_the_legs_is_no_leg():
    d, objs, _ = _scene([*_legs(), *box(0.0, 2.0, 0.3, 0.3, 0.72, obj=2)])
    boxes = _holding(d, objs, 2)
    assert len(boxes) == 1 and all(objs[x] == 2 for x in boxes[0].planes)
    assert all(objs[x] == 9 for o in _holding(d, objs, 9) for x in o.planes)


def test_posts_not_standing_on_the_floor_are_no_legs():
    # the same legs hanging 0.3 m above the floor (a rack's rods): each apart, as before
    d, objs, _ = _scene(_legs(z0=0.3))
    old, _, _ = _scene(_legs(z0=0.3), params=OFF)
    assert len(_holding(d, objs, 9)) == len(_holding(old, objs, 9)) >= 3


def test_legs_no_plane_explains_are_joined_too():
    # the legs left unlabelled: the curved stage's clusters of their pixels are the posts
    d, objs, lab = _scene(_legs(), unassign=lambda r: r.obj == 9)
    posts = [o for o in d.objects if not o.planes and o.mask is not None]
    old, _, _ = _scene(_legs(), params=OFF, unassign=lambda r: r.obj == 9)
    before = [o for o in old.objects if not o.planes and o.mask is not None]
    assert len(before) >= 3 and len(posts) == 1
    assert posts[0].mask.sum() == sum(int(o.mask.sum()) for o in before)


def test_legs_apart_is_checked():
    with pytest.raises(InputError, match="legs_apart"):
        ProposalParams(legs_apart=-1.0)


def _open_box(cx=0.0, cy=2.0, sx=0.4, sy=0.3, sz=0.2, t=0.01, obj=5, sides=True):
    """An open box seen over its near wall: the near wall's outside, the far wall's inside,
    the bottom inside and (``sides``) the side walls' outsides and insides."""
    out = [Rect((cx, cy - sy / 2, sz / 2), (1, 0, 0), (0, 0, 1), sx / 2, sz / 2, obj),
           Rect((cx, cy + sy / 2 - t, sz / 2), (1, 0, 0), (0, 0, 1), sx / 2 - t, sz / 2, obj),
           Rect((cx, cy, t), (1, 0, 0), (0, 1, 0), sx / 2 - t, sy / 2 - t, obj)]
    if sides:
        for s in (-1, 1):
            out.append(Rect((cx + s * sx / 2, cy, sz / 2), (0, 1, 0), (0, 0, 1), sy / 2, sz / 2, obj))
            out.append(Rect((cx + s * (sx / 2 - t), cy, sz / 2), (0, 1, 0), (0, 0, 1),
                            sy / 2 - t, sz / 2, obj))
    return out


@pytest.mark.parametrize("sides", [False, True])
def test_an_open_boxs_near_and_far_walls_are_one_object(sides):
    d, objs, _ = _scene(_open_box(sides=sides))
    held = _holding(d, objs, 5)
    assert len(held) == 1 and all(objs[x] == 5 for x in held[0].planes)
    near, far = 1, 2  # the labels of the near wall's outside and the far wall's inside
    assert {near, far} <= set(held[0].planes)
    # before (open_walls False): without its side walls in view (the varied world's open
    # boxes and shelves seen straight on) the near wall a proposal apart from the far one;
    # with them the cavity rules' occluded channel joined them already
    old, _, _ = _scene(_open_box(sides=sides), params=ProposalParams(open_walls=False))
    apart = [o for o in old.objects if near in o.planes] != [o for o in old.objects if far in o.planes]
    assert apart != sides


def test_two_closed_boxes_one_behind_the_other_stay_apart():
    # as high as each other, 0.1 m apart: the near one's top lies between the two faces
    d, objs, _ = _scene([*box(0.0, 1.9, 0.4, 0.2, 0.2, obj=1), *box(0.0, 2.2, 0.4, 0.2, 0.2, obj=2)])
    a, b = _holding(d, objs, 1), _holding(d, objs, 2)
    assert len(a) == 1 and len(b) == 1 and a[0] is not b[0]
    assert all(objs[x] == 1 for x in a[0].planes) and all(objs[x] == 2 for x in b[0].planes)


def test_a_far_wall_higher_than_the_near_one_is_another_object():
    # a near 0.2 m face and a far face rising to 0.35 m (a taller thing behind): not one rim
    near = Rect((0.0, 1.85, 0.1), (1, 0, 0), (0, 0, 1), 0.2, 0.1, 1)
    far = Rect((0.0, 2.14, 0.175), (1, 0, 0), (0, 0, 1), 0.19, 0.175, 2)
    d, objs, _ = _scene([near, far])
    a, b = _holding(d, objs, 1), _holding(d, objs, 2)
    assert len(a) == 1 and len(b) == 1 and a[0] is not b[0]
    # level (the far face 0.2 m high too) they are one
    far = Rect((0.0, 2.14, 0.1), (1, 0, 0), (0, 0, 1), 0.19, 0.1, 2)
    d, objs, _ = _scene([near, far])
    assert _holding(d, objs, 1) == _holding(d, objs, 2)


def test_open_walls_is_checked():
    with pytest.raises(InputError, match="open_walls"):
        ProposalParams(open_walls=1)
