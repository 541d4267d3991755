"""synth22r: a low box before a taller one is no flight's first step, a box's top two runs
before a flight's tread whose tread between is seen is no skipped step, and an unexplained
cluster between two faces of one object joins both (docs/objects.md, "Synthetic misses,
seed by seed (synth22r)").

Rendered scenes are ray-cast rectangles with one label each (tests/scenes_analytic.py).
"""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import Rect, box, floor, render, stairs

from planerel.errors import InputError
from planerel.features.curved import CurvedParams
from planerel.features.facts import describe_scene
from planerel.features.relations import ProposalParams, step_chain_pairs

VIEW = dict(pitch=30, cam_height=1.6, width=320, height=240, noise=0.001)


def _groups(d, objs):
    """Per proposal, the set of true objects of its planes."""
    return [{objs[x] for x in o.planes} for o in d.objects if o.planes]


# --- riser_floor: the riser below measured no higher than the tread's height --------------


def _low_before_tall(drop: float):
    """A 0.12 m box (0.6 wide, 0.15 deep) standing against the front of a 0.32 m box of the
    same width; the low box's front face has its lowest pixel row moved ``drop`` metres down
    along its plane (a hull outlier, as flying pixels make one)."""
    rects = [floor()] + box(0.0, 2.075, 0.6, 0.15, 0.12, obj=1) + box(0.0, 2.35, 0.6, 0.4, 0.32, obj=2)
    cloud, lab, up, objs = render(rects, **VIEW)
    front = 2  # box(): top, then the front face (-y)
    rows = np.nonzero((lab == front).any(1))[0]
    low = lab[rows.max()] == front
    xyz = cloud.xyz.copy()
    xyz[rows.max()][low] -= drop * np.asarray(up)
    cloud = type(cloud)(xyz, cloud.intrinsics, cloud.up, cloud.source)
    return cloud, lab, objs


@pytest.mark.parametrize("drop", [0.0, 0.035])
def test_low_box_before_taller_box_is_no_step(drop):
    cloud, lab, objs = _low_before_tall(drop)
    d = describe_scene(cloud, lab)
    groups = _groups(d, objs)
    assert {1} in groups and {2} in groups and not any(g >= {1, 2} for g in groups)


def test_low_box_joined_without_riser_floor_when_its_hull_is_inflated():
    # the rule's reason: the riser below measures 0.155 m by its hull, within 30 % of the
    # 0.20 m face above it; its tread stands 0.12 m above the floor
    cloud, lab, objs = _low_before_tall(0.035)
    off = describe_scene(cloud, lab, proposal_params=ProposalParams(riser_floor=False))
    assert any(g >= {1, 2} for g in _groups(off, objs))


def test_flight_unchanged_by_riser_floor():
    rects = [floor()] + stairs(0.0, 2.0, n=4, rise=0.17, run=0.28)
    cloud, lab, _up, objs = render(rects, **VIEW)
    on = describe_scene(cloud, lab)
    off = describe_scene(cloud, lab, proposal_params=ProposalParams(riser_floor=False))
    flight = {p.label for p in on.planes if objs[p.label] == 1}
    assert len(flight) >= 7 and flight in [set(o.planes) for o in on.objects]
    assert [o.planes for o in on.objects] == [o.planes for o in off.objects]


# --- skip_missing: a two-rise step only over a missing face --------------------------------


def _box_before_flight(top: float):
    """A 4-step flight (rise 0.17, run 0.28, 1 m wide, first riser at y = 2) and a 0.6 x 0.3 m
    box ``top`` metres high whose centre stands 0.44 m before the first tread's: its top lies
    two runs before the third tread, about two rises under it."""
    rects = [floor()] + stairs(0.0, 2.0, n=4, rise=0.17, run=0.28, obj=1) + box(0.0, 1.70, 0.6, 0.3, top, obj=2)
    cloud, lab, _up, objs = render(rects, **VIEW)
    return cloud, lab, objs


def test_box_top_off_the_flights_rises_is_no_skipped_step():
    cloud, lab, objs = _box_before_flight(0.235)
    on = describe_scene(cloud, lab)
    groups = _groups(on, objs)
    assert {2} in groups and not any(g >= {1, 2} for g in groups)
    flight = {p.label for p in on.planes if objs[p.label] == 1}
    assert flight in [set(o.planes) for o in on.objects]
    off = describe_scene(cloud, lab, proposal_params=ProposalParams(skip_missing=False))
    assert any(g >= {1, 2} for g in _groups(off, objs))


def test_skipped_step_over_a_missing_tread_still_joins():
    # the flight's second riser and tread left out (not segmented): the first and third
    # treads make a two-rise step, which the rule keeps (no face between is seen); with the
    # second tread in, the one-rise steps join the flight and the rule changes nothing
    rects = [floor()] + stairs(0.0, 2.0, n=4, rise=0.17, run=0.28, obj=1)
    cloud, lab, _up, _objs = render(rects, **VIEW)
    planes = describe_scene(cloud, lab).planes
    some = [k for k in range(1, 9) if k not in (3, 4)]
    on = step_chain_pairs(planes, some, skip_missing=True)
    assert (2, 6) in on  # tread 1 -> tread 3, two rises
    assert on == step_chain_pairs(planes, some, skip_missing=False)
    every = list(range(1, 9))
    assert step_chain_pairs(planes, every, skip_missing=True) == step_chain_pairs(planes, every)


# --- bridge_area: a cluster between two faces of one object ---------------------------------


def _open_box(unlabel_ends: bool = True):
    """An open box 1.1 x 0.4 m, 0.3 m high, long side across the view, 2.5 m away: its two
    long walls (inside of the far one, outside of the near one) are planes; its end walls
    (0.4 x 0.3 m) unlabelled, as when the segmentation leaves them."""
    cx, cy, sx, sy, h = 0.8, 2.5, 1.1, 0.4, 0.3
    rects = [floor(),
             Rect((cx, cy - sy / 2, h / 2), (1, 0, 0), (0, 0, 1), sx / 2, h / 2, 1),   # near wall
             Rect((cx, cy + sy / 2, h / 2), (1, 0, 0), (0, 0, 1), sx / 2, h / 2, 1),   # far wall
             Rect((cx - sx / 2, cy, h / 2), (0, 1, 0), (0, 0, 1), sy / 2, h / 2, 1),   # end walls
             Rect((cx + sx / 2, cy, h / 2), (0, 1, 0), (0, 0, 1), sy / 2, h / 2, 1),
             Rect((cx, cy, 0.01), (1, 0, 0), (0, 1, 0), sx / 2, sy / 2, 1)]           # bottom
    cloud, lab, _up, objs = render(rects, pitch=35, cam_height=1.6, width=320, height=240,
                                   noise=0.001)
    lab = lab.copy()
    if unlabel_ends:
        lab[np.isin(lab, [3, 4, 5])] = -1
    return cloud, lab, objs


def test_cluster_between_two_walls_joins_both():
    cloud, lab, objs = _open_box()
    on = describe_scene(cloud, lab)
    walls = {p.label for p in on.planes if objs[p.label] == 1}
    assert walls == {1, 2}
    assert any(walls <= set(o.planes) for o in on.objects)
    # (open_walls False: synth22y's rule joins two parallel walls, level, one behind the other)
    off = describe_scene(cloud, lab, curved_params=CurvedParams(bridge_area=0.0),
                         proposal_params=ProposalParams(open_walls=False))
    assert not any(walls <= set(o.planes) for o in off.objects)


def test_bridge_needs_faces_of_room_scale():
    # bridge_min above the walls' areas: the cluster joins neither
    cloud, lab, objs = _open_box()
    d = describe_scene(cloud, lab, curved_params=CurvedParams(bridge_min=0.4),
                       proposal_params=ProposalParams(open_walls=False))
    assert not any({1, 2} <= set(o.planes) for o in d.objects)


@pytest.mark.parametrize("kw", [dict(bridge_area=-0.1), dict(bridge_min=float("nan")),
                                dict(bridge_touch=-1), dict(bridge_touch=2.5)])
def test_bridge_params_validated(kw):
    with pytest.raises(InputError, match="bridge_"):
        CurvedParams(**kw)
