"""A wall rising behind a box's top is no stair riser (skirt36, docs/objects.md "A wall
behind a box is no next riser").  A plane rising from a skirt's top denies the skirt as a
flight's next riser only when it rises at most ``riser_rise_max`` above the top, or has a
tread at its top edge: a stair's riser rises one step, a wall or a cabinet standing behind a
box rises far above with nothing on it.  Analytic scenes; each test fails with the parameter
that switches the rule off (``riser_rise_max=0``)."""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import Rect, box, floor, render, stairs, wall

from planerel.errors import InputError
from planerel.features.planes import measure_planes
from planerel.features.relations import RelationParams, relate

VIEW = {"pitch": 25, "cam_height": 1.2, "width": 320, "height": 240}


def _relate(rects, params=None, **view):
    cloud, lab, _, objs = render(rects, noise=0.0012, **(view or VIEW))
    ps = measure_planes(cloud, lab)
    return cloud, ps, relate(ps, cloud, params)


def _against_wall(height: float):
    """A 0.5 x 0.4 x 0.3 m box on the floor 2 m away whose back stands flush against a
    vertical plane ``height`` m tall and as wide as the box (a cabinet's front, seen above the
    box only, as office1's): labels 0 floor, 1 the cabinet's face, 2 the box's top, 3 its
    front."""
    sides = box(0.0, 2.0, 0.5, 0.4, 0.3)
    face = Rect((0.0, 2.2, height / 2), (1, 0, 0), (0, 0, 1), 0.24, height / 2, 2)
    return [floor(), face] + sides[:4]


def test_a_box_against_a_tall_cabinet_has_a_skirt():
    cloud, ps, rel = _relate(_against_wall(1.4))
    top, front, cab = ps.by_label(2), ps.by_label(3), ps.by_label(1)
    assert top.orientation == "horizontal" and front.orientation == "vertical"
    assert cab.orientation == "vertical" and rel.get(2, 1).adjacent
    assert rel.get(2, 3).skirt and (2, 3) not in rel.skirt_steps
    # before skirt36: the cabinet's face, parallel to the front, "rose from" the top
    off = relate(ps, cloud, RelationParams(riser_rise_max=0.0))
    assert not off.get(2, 3).skirt
    assert {lbl for lbl, _ in off.skirt_steps[(2, 3)]} == {1}


def test_a_step_up_behind_a_box_still_denies_its_skirt():
    # the plane behind rises 0.2 m over the box's top: one stair's rise, as before
    cloud, ps, rel = _relate(_against_wall(0.5))
    assert not rel.get(2, 3).skirt
    assert {lbl for lbl, _ in rel.skirt_steps[(2, 3)]} == {1}


def test_a_tall_plane_with_a_tread_on_it_still_denies_the_skirt():
    # a block 0.9 m high behind the box (0.6 m over its top), its top (label 1) a horizontal plane at its top edge:
    # a high step (another solid's top), not a bare wall
    sides = box(0.0, 2.0, 0.5, 0.4, 0.3)
    block = box(0.0, 2.45, 0.48, 0.5, 0.9, obj=2)[:2]  # its top, then its front
    cloud, ps, rel = _relate([floor()] + block + sides[:4])
    top, front, riser, tread = ps.by_label(3), ps.by_label(4), ps.by_label(2), ps.by_label(1)
    assert tread.orientation == "horizontal" and riser.orientation == "vertical"
    assert top.orientation == "horizontal" and front.orientation == "vertical"
    assert rel.get(2, 1).adjacent and rel.get(3, 2).adjacent
    # the block's front rises 0.6 m over the box's top: past riser_rise_max, kept by its tread
    level = float(np.asarray(top.centroid, float) @ np.asarray(ps.up, float))
    assert dict(rel.skirt_steps[(3, 4)])[2] - level > RelationParams().riser_rise_max
    assert not rel.get(3, 4).skirt
    assert {lbl for lbl, _ in rel.skirt_steps[(3, 4)]} == {2}


def test_a_flights_tread_and_riser_are_still_no_skirt():
    rects = [floor(), wall()] + stairs(0.3, 2.2, 3, rise=0.17, run=0.28)
    cloud, ps, rel = _relate(rects)
    for tread, riser, nxt in ((3, 2, 4), (5, 4, 6)):
        assert ps.by_label(tread).orientation == "horizontal"
        assert not rel.get(tread, riser).skirt
        assert nxt in {lbl for lbl, _ in rel.skirt_steps.get((tread, riser), ())}
    # a flight of tall risers (0.3 m, past STAIR_RISE) is denied the same way
    rects = [floor(), wall()] + stairs(0.3, 2.2, 3, rise=0.3, run=0.3)
    cloud, ps, rel = _relate(rects)
    assert not rel.get(3, 2).skirt


def test_skirt36_parameter_is_checked():
    with pytest.raises(InputError, match="riser_rise_max"):
        RelationParams(riser_rise_max=-0.1)
