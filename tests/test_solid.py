"""skirt(Top, Face): a vertical face hanging below a horizontal plane as a box's side below its
top; furniture showing the same two planes (a chair's seat and back or legs, a table's top and
legs) is not.  corner(P, Q): two vertical walls of one solid, level tops, neither a post."""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import Rect, box, floor, render, stairs

from planerel.errors import InputError
from planerel.features.facts import describe_scene, facts_text
from planerel.features.planes import measure_planes
from planerel.features.relations import RelationParams, relate
from planerel.features.solid import face_points, face_profile, skirt_measures


def _relations(rects, merge=(), **kw):
    """Render, give the labels in each group of ``merge`` the first one's label, relate."""
    cloud, lab, _, _ = render(rects, noise=0.0012, **kw)
    for group in merge:
        lab = np.where(np.isin(lab, group), group[0], lab).astype(np.int32)
    ps = measure_planes(cloud, lab)
    return cloud, lab, ps, relate(ps, cloud)


def _prof(face, ps, lab, cloud):
    return face_profile(face, ps.up, face_points(face, lab, cloud.xyz))


def _vrect(cx, cy, half_w, z0, z1, along_x=True):
    e1 = (1, 0, 0) if along_x else (0, 1, 0)
    return Rect((cx, cy, (z0 + z1) / 2), e1, (0, 0, 1), half_w, (z1 - z0) / 2, 1)


def test_box_side_hangs_below_its_top_not_the_other_way():
    # floor 0, top 1, front 2, left 3 (right and back hidden)
    cloud, lab, ps, rel = _relations([floor()] + box(0.6, 2.5, 0.5, 0.5, 0.4))
    top, front = ps.by_label(1), ps.by_label(2)
    offset, reach, cover, beyond = skirt_measures(top, front, ps.up,
                                                  _prof(front, ps, lab, cloud), lab,
                                                  cloud.xyz, cloud.intrinsics)
    assert offset == pytest.approx(0.0, abs=0.02)
    assert reach == pytest.approx(0.4, abs=0.03)
    assert cover > 0.9 and beyond < 0.03
    assert {p.label for p in ps} == {0, 1, 2, 3}
    assert rel.get(1, 2).skirt and rel.get(1, 3).skirt
    assert not rel.get(2, 1).skirt  # direction: skirt(Top, Face)
    assert not rel.get(0, 2).skirt  # the floor is below the face, not at its top
    assert rel.get(2, 3).corner and rel.get(3, 2).corner
    assert not rel.get(1, 2).corner  # a top is no wall
    text = facts_text([describe_scene(cloud, lab, scene_id="s0001")])
    assert "skirt(s0001_p01, s0001_p02)." in text and "skirt(s0001_p02," not in text


def test_risers_are_no_skirts():
    _, _, ps, rel = _relations([floor()] + stairs(0.0, 2.2, 2, rise=0.17, run=0.28))
    # stairs(): riser 1, tread 2, riser 3, tread 4
    assert not rel.get(2, 1).skirt  # the lowest riser: the next one rises from its tread
    assert rel.get(4, 3).adjacent and rel.get(3, 2).adjacent
    assert not rel.get(4, 3).skirt  # the next one stands on tread 2, 0.28 m deep: a step
    assert not rel.get(2, 3).skirt  # the next riser rises from the tread


def test_chair_seat_back_edge_and_flush_legs_are_no_skirt():
    s, h, t, leg = 0.45, 0.45, 0.04, 0.035
    cy = 2.3
    seat = Rect((0.0, cy, h), (1, 0, 0), (0, 1, 0), s / 2, s / 2, 1)
    # back rising from the seat's far edge; front edge strip with the front legs flush
    # below it, segmented as one U-shaped plane
    back = _vrect(0.0, cy + s / 2, s / 2, h, h + 0.45)
    edge = _vrect(0.0, cy - s / 2, s / 2, h - t, h)
    legs = [_vrect(x, cy - s / 2, leg / 2, 0.0, h - t) for x in (-s / 2 + leg / 2, s / 2 - leg / 2)]
    cloud, lab, ps, rel = _relations([floor(), seat, back, edge] + legs, merge=[(3, 4, 5)],
                                     pitch=30)
    assert ps.by_label(1).orientation == "horizontal"
    assert {p.label for p in ps} >= {1, 2, 3}
    assert rel.get(1, 2).adjacent and rel.get(1, 3).adjacent
    assert not rel.get(1, 2).skirt  # the back reaches up
    assert not rel.get(1, 3).skirt  # halfway down only the two legs
    _, reach, cover, _ = skirt_measures(ps.by_label(1), ps.by_label(3), ps.up,
                                        _prof(ps.by_label(3), ps, lab, cloud), lab,
                                        cloud.xyz, cloud.intrinsics)
    assert reach == pytest.approx(h, abs=0.04) and cover < 0.4
    # the edge strip alone is a slab's thickness, too short to be a box's side
    cloud, lab, ps, rel = _relations([floor(), seat, edge], pitch=30)
    assert rel.get(1, 2).adjacent and not rel.get(1, 2).skirt


def test_side_half_hidden_and_split_by_a_box_in_front_is_still_a_skirt():
    """A tall box's front side, split in two by a smaller box standing in front of it: each
    piece covers the top's extent where it is seen, the other piece (parallel, on the same
    plane) counts as the side and the part behind the small box as hidden."""
    cx, cy, sx, sy, h = 0.5, 3.0, 0.8, 0.5, 0.5
    top = Rect((cx, cy, h), (1, 0, 0), (0, 1, 0), sx / 2, sy / 2, 1)
    y = cy - sy / 2
    left = Rect((cx - sx / 4, y, h / 2), (1, 0, 0), (0, 0, 1), sx / 4, h / 2, 1)
    right = Rect((cx + sx / 4, y, h / 2), (1, 0, 0), (0, 0, 1), sx / 4, h / 2, 1)
    small = box(cx, y - 0.35, 0.3, 0.3, 0.35, obj=2)
    cloud, lab, ps, rel = _relations([floor(), top, left, right] + small, pitch=25)
    assert rel.get(1, 2).adjacent and rel.get(1, 3).adjacent
    for face in (2, 3):
        _, _, cover, _ = skirt_measures(ps.by_label(1), ps.by_label(face), ps.up,
                                        _prof(ps.by_label(face), ps, lab, cloud), lab,
                                        cloud.xyz, cloud.intrinsics)
        assert cover < 0.6  # its own pixels alone: about half the top's extent
        assert rel.get(1, face).skirt  # with the other piece and the hidden part


def test_side_face_running_on_under_a_slope_is_no_skirt():
    """A ramp with a top platform: its side face hangs below the platform but runs on under
    the slope, 1.5 m past the platform's end."""
    run, h, plat = 1.5, 0.4, 0.5
    x0 = 0.8
    ramp_side = Rect((x0, 2.0 + (run + plat) / 2, h / 2), (0, 1, 0), (0, 0, 1),
                     (run + plat) / 2, h / 2, 1)
    top = Rect((x0 + 0.4, 2.0 + run + plat / 2, h), (1, 0, 0), (0, 1, 0), 0.4, plat / 2, 1)
    cloud, lab, ps, rel = _relations([floor(), ramp_side, top], cam_height=1.5, pitch=30)
    assert rel.get(2, 1).adjacent
    _, reach, cover, beyond = skirt_measures(ps.by_label(2), ps.by_label(1), ps.up,
                                             _prof(ps.by_label(1), ps, lab, cloud), lab,
                                             cloud.xyz, cloud.intrinsics)
    assert cover > 0.9 and beyond == pytest.approx(run, abs=0.1)
    assert not rel.get(2, 1).skirt


def test_corner_needs_level_tops_and_walls_wider_than_a_post():
    # a box's front face and, at its left edge, a wall of another height at right angles
    low = box(0.6, 2.5, 0.5, 0.5, 0.4)
    tall = Rect((0.35, 2.5, 0.35), (0, 1, 0), (0, 0, 1), 0.25, 0.35, 1)
    _, _, ps, rel = _relations([floor(), low[1], tall], pitch=20)
    assert rel.get(1, 2).adjacent and rel.get(1, 2).perpendicular
    assert not rel.get(1, 2).corner
    # a square post 4 cm wide: two faces, level tops, too narrow; 20 cm wide: a corner
    for half, corner in ((0.02, False), (0.1, True)):
        post = [Rect((0.3, 2.5 - half, 0.4), (1, 0, 0), (0, 0, 1), half, 0.4, 1),
                Rect((0.3 - half, 2.5, 0.4), (0, 1, 0), (0, 0, 1), half, 0.4, 1)]
        _, _, ps, rel = _relations([floor()] + post, pitch=10, cam_height=0.6)
        assert {1, 2} <= {p.label for p in ps}
        r = rel.get(1, 2)
        assert r.adjacent and r.perpendicular and r.corner == corner


def test_no_cloud_no_skirt_and_params_checked():
    cloud, lab, _, _ = render([floor()] + box(0.0, 2.5, 0.5, 0.5, 0.4), noise=0.0012)
    ps = measure_planes(cloud, lab)
    assert not any(r.skirt or r.corner for r in relate(ps))
    assert any(r.skirt for r in relate(ps, cloud))
    # (a side standing on the floor need reach only skirt_grounded_reach since flat23:
    # switched off to see the reach asked of every face)
    assert not any(r.skirt for r in relate(ps, cloud, RelationParams(skirt_reach=0.5, skirt_reach_share=0,
                                                                     skirt_grounded_reach=0)))
    # the reach asked of a short top's face is scaled down: 0.15 x 0.5 m < 0.4 m
    assert any(r.skirt for r in relate(ps, cloud, RelationParams(skirt_reach=0.5)))
    with pytest.raises(InputError, match="skirt_cover"):
        RelationParams(skirt_cover=1.5)
    with pytest.raises(InputError, match="skirt_reach"):
        RelationParams(skirt_reach=-0.1)
    with pytest.raises(InputError, match="skirt_reach_share"):
        RelationParams(skirt_reach_share=-0.1)


@pytest.mark.parametrize("sx, sy, sz", [(0.24, 0.16, 0.045), (0.12, 0.10, 0.04), (0.30, 0.20, 0.05)])
def test_low_box_lying_on_a_table_has_a_skirt(sx, sy, sz):
    # a box lying flat (a tea or a cereal box: 4-5 cm high) seen from 1 m, 45 degrees down, as
    # on a table top: its sides reach less than skirt_reach (7 cm), but its top is short, so
    # the reach asked scales down with the top's long side (0.15 x 0.12-0.30 m)
    cloud, lab, ps, rel = _relations([floor()] + box(0.0, 0.9, sx, sy, sz), pitch=45, cam_height=0.8,
                                     width=320, height=240)
    top, front = ps.by_label(1), ps.by_label(2)
    assert top.orientation == "horizontal" and front.orientation == "vertical"
    _, reach, cover, _ = skirt_measures(top, front, ps.up, _prof(front, ps, lab, cloud), lab,
                                        cloud.xyz, cloud.intrinsics)
    assert reach == pytest.approx(sz, abs=0.01) and reach < 0.07 and cover > 0.7
    assert rel.get(1, 2).skirt
    # without the scaled reach (and without flat23's reach of a side standing on the ground,
    # which also passes it: tests/test_flatbox.py) no skirt
    assert not relate(ps, cloud, RelationParams(skirt_reach_share=0,
                                                skirt_grounded_reach=0)).get(1, 2).skirt
    assert relate(ps, cloud, RelationParams(skirt_reach_share=0)).get(1, 2).skirt


def test_a_long_slab_edge_is_no_skirt():
    # a table top 1.2 x 0.7 m and its 4 cm edge strip: the top is long, the full 7 cm is asked
    t = 0.04
    top = Rect((0.0, 2.4, 0.75), (1, 0, 0), (0, 1, 0), 0.6, 0.35, 1)
    edge = _vrect(0.0, 2.4 - 0.35, 0.6, 0.75 - t, 0.75)
    cloud, lab, ps, rel = _relations([floor(), top, edge], pitch=30)
    assert rel.get(1, 2).adjacent and not rel.get(1, 2).skirt
    # the same edge under a short top (a 0.2 m board) would pass: the scaling is by the top's length
    top_s = Rect((0.0, 2.4, 0.75), (1, 0, 0), (0, 1, 0), 0.1, 0.08, 1)
    edge_s = _vrect(0.0, 2.4 - 0.08, 0.1, 0.75 - t, 0.75)
    cloud, lab, ps, rel = _relations([floor(), top_s, edge_s], pitch=30)
    assert rel.get(1, 2).adjacent and rel.get(1, 2).skirt


def test_face_percentiles_are_numpys():
    """The face profile's percentiles without np.percentile's overhead are its floats, ties
    and every small size included."""
    from planerel.features.solid import _percentiles_2_98

    rng = np.random.default_rng(4)
    for n in [*range(1, 40), 97, 1000, 4001]:
        for x in (rng.normal(size=(2, n)), np.round(rng.normal(size=(2, n)), 1),
                  np.stack([np.arange(n, dtype=float), np.arange(n, 0, -1, dtype=float)]),
                  np.zeros((2, n))):
            ref = [tuple(float(v) for v in np.percentile(row, [2.0, 98.0])) for row in x]
            assert _percentiles_2_98(x) == ref


def _raised_box(cx, cy, sx, sy, sz, z0, obj):
    """``box()`` standing at height ``z0`` (on another box)."""
    return [Rect((r.center[0], r.center[1], r.center[2] + z0), r.e1, r.e2, r.a, r.b, obj)
            for r in box(cx, cy, sx, sy, sz, obj)]


def _skirt_facts(cloud, lab, objects, **kw):
    desc = describe_scene(cloud, lab, scene_id="s0001", objects=objects,
                          relation_params=RelationParams(**kw))
    return {line for line in facts_text([desc]).splitlines() if line.startswith("skirt(")}


def test_a_box_on_a_box_is_a_skirt_of_its_own_object_not_a_riser():
    # a 0.3 x 0.2 m box standing on a 0.6 x 0.4 m one (0.3 m high): the upper front stands on
    # the lower top, 0.4 m deep (a tread's depth), as a riser on a tread; labels: floor 0, lower top 1, front 2,
    # left 3, right 4, back 5, upper top 6, front 7, left 8, right 9, back 10
    rects = [floor()] + box(0.0, 2.4, 0.6, 0.4, 0.3) + _raised_box(0.0, 2.4, 0.3, 0.2, 0.2, 0.3, 2)
    cloud, lab, ps, rel = _relations(rects, pitch=30, width=320, height=240)
    # relate alone: the upper front stands on a tread, and rises from the lower top parallel
    # to the lower front (the next riser)
    assert rel.get(6, 7).adjacent and not rel.get(6, 7).skirt
    assert rel.get(1, 2).adjacent and not rel.get(1, 2).skirt
    assert [lbl for lbl, _ in rel.skirt_steps[(6, 7)]] == [1]
    assert [lbl for lbl, _ in rel.skirt_steps[(1, 2)]] == [7]
    present = [p.label for p in ps]
    lower = [k for k in present if 1 <= k <= 5]
    upper = [k for k in present if 6 <= k <= 10]
    # two objects: each box's front is its top's skirt (the riser over the lower top is the
    # side of a solid with a top at its top edge)
    two = _skirt_facts(cloud, lab, [lower, upper])
    assert "skirt(s0001_p06, s0001_p07)." in two and "skirt(s0001_p01, s0001_p02)." in two
    # one object (a flight of two steps): its risers stand on its own tread
    one = _skirt_facts(cloud, lab, [lower + upper])
    assert "skirt(s0001_p06, s0001_p07)." not in one and "skirt(s0001_p01, s0001_p02)." not in one
    # the rule off: relate's answer
    assert "skirt(s0001_p06, s0001_p07)." not in _skirt_facts(cloud, lab, [lower, upper],
                                                              skirt_own_steps=False)
    with pytest.raises(InputError, match="skirt_own_steps"):
        RelationParams(skirt_own_steps=1)


def test_a_panel_rising_from_a_top_stays_a_riser_unless_it_has_a_top():
    # a low box (0.25 m) and a panel rising from the back of its top (a wall behind a desk,
    # its lower part hidden by the box): another object, but with no top of its own, so the
    # box's front is still no skirt; a taller box behind it (the panel with a top) is a solid
    # beside the low box: then the front is a skirt
    panel = _vrect(0.0, 2.4 + 0.2, 0.25, 0.25, 0.6)
    rects = [floor()] + box(0.0, 2.4, 0.5, 0.4, 0.25) + [panel]
    cloud, lab, ps, rel = _relations(rects, pitch=30, width=320, height=240)
    assert rel.get(1, 2).adjacent and not rel.get(1, 2).skirt  # the panel rises from the top
    assert [lbl for lbl, _ in rel.skirt_steps[(1, 2)]] == [6]
    low = [k for k in (1, 2, 3, 4, 5) if k in {p.label for p in ps}]
    assert "skirt(s0001_p01, s0001_p02)." not in _skirt_facts(cloud, lab, [low, [6]])
    lid = Rect((0.0, 2.4 + 0.3, 0.6), (1, 0, 0), (0, 1, 0), 0.25, 0.1, 1)
    cloud, lab, ps, rel = _relations(rects + [lid], pitch=30, width=320, height=240)
    assert not rel.get(1, 2).skirt
    assert "skirt(s0001_p01, s0001_p02)." in _skirt_facts(cloud, lab, [low, [6, 7]])
    assert "skirt(s0001_p01, s0001_p02)." not in _skirt_facts(cloud, lab, [low + [6, 7]])


def test_a_flights_risers_stay_risers_in_its_proposal():
    # the proposals make the flight one object: its treads and risers keep each other no skirt
    cloud, lab, _, rel = _relations([floor()] + stairs(0.0, 2.2, 3, rise=0.17, run=0.28), pitch=30,
                                    width=320, height=240)
    assert rel.skirt_steps  # relate denied skirts only for steps
    desc = describe_scene(cloud, lab, scene_id="s0001")
    assert len(desc.objects) == 1
    assert not any(r.skirt for r in desc.relations)
