"""synth22q: a flight's closed side seen on one side, raised groups that meet, an open box's
raised bottom joining its unexplained wall, and the proposals scored without mostly hidden
objects (docs/objects.md, "Synthetic misses (synth22q)").

Rendered scenes are ray-cast rectangles with one label each (tests/scenes_analytic.py); the
rectangles of one side wall are given one label, as a segmentation makes one plane of it.
"""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import Rect, floor, render, stairs

from planerel.errors import InputError
from planerel.features.curved import CurvedObject
from planerel.features.facts import describe_scene
from planerel.features.object_eval import mostly_hidden, score_objects
from planerel.features.raised import RaisedParams, _merge_meeting, with_raised
from planerel.features.relations import ProposalParams

VIEW = dict(pitch=30, cam_height=1.6, width=320, height=240, noise=0.001)
Y0, N, RUN, RISE = 2.0, 4, 0.28, 0.17


def _side(rail: float | None, level: float | None = None):
    """The left side of the 4-step flight of ``stairs(0, Y0)`` at x = -0.5, facing +x: one
    rectangle a step, ``rail`` above that step's tread (a closed side whose top follows the
    flight), or every one up to ``level`` metres (a wall with a level top)."""
    out = []
    for k in range(N):
        top = level if level is not None else (k + 1) * RISE + rail
        out.append(Rect((-0.5, Y0 + (k + 0.5) * RUN, top / 2), (0, 1, 0), (0, 0, 1), RUN / 2,
                        top / 2, 1))
    return out


def _run(rects, side_from: int, params=None):
    """Proposals (sets of labels) and the flight's labels; the rectangles from index
    ``side_from`` on are one plane (their first label)."""
    cloud, lab, _up, objs = render(rects, **VIEW)
    lab = lab.copy()
    first = side_from  # render labels rectangle i as i
    for k in range(side_from + 1, len(rects)):
        lab[lab == k] = first
    d = describe_scene(cloud, lab, proposal_params=params)
    flight = {p.label for p in d.planes if objs[p.label] == 1}
    return [set(o.planes) for o in d.objects], flight, first


def test_closed_side_following_the_flight_joins_it():
    # a side 0.5 m above each tread, seen on the left only: its edges with the treads are
    # concave and none is whole; its top stands 0.5 m above every tread
    rects = [floor()] + stairs(0.0, Y0, n=N, rise=RISE, run=RUN) + _side(0.5)
    props, flight, side = _run(rects, 1 + 2 * N)
    assert side in flight and len(flight) >= 2 * N
    assert flight in props
    off, flight0, _ = _run(rects, 1 + 2 * N, ProposalParams(side_wall_follow=0.0))
    assert flight0 == flight and flight not in off
    assert {side} in off


def test_level_wall_beside_the_flight_stays_apart():
    # the same wall with a level top 1.2 m high: it stands 1.03 m above the first tread and
    # 0.52 m above the last: a room wall, not the flight's side
    rects = [floor()] + stairs(0.0, Y0, n=N, rise=RISE, run=RUN) + _side(None, level=1.2)
    props, flight, side = _run(rects, 1 + 2 * N)
    assert {side} in props
    assert flight - {side} in props


def test_follows_flight_on_measured_caps():
    from planerel.features.cavities import follows_flight

    rects = [floor()] + stairs(0.0, Y0, n=N, rise=RISE, run=RUN) + _side(0.5)
    cloud, lab, _up, _objs = render(rects, **VIEW)
    lab = lab.copy()
    for k in range(2 + 2 * N, len(rects)):
        lab[lab == k] = 1 + 2 * N
    d = describe_scene(cloud, lab)
    byl = {p.label: p for p in d.planes}
    treads = [byl[k] for k in range(2, 1 + 2 * N, 2) if k in byl]
    face = byl[1 + 2 * N]
    assert follows_flight(face, treads, d.planes.up, cloud.xyz, d.labels)
    # one tread: nothing to tell
    assert not follows_flight(face, treads[:1], d.planes.up, cloud.xyz, d.labels)
    # a ratio of 0 asks for exactly one height above every tread: noise breaks it
    assert not follows_flight(face, treads, d.planes.up, cloud.xyz, d.labels, follow=0.0)
    with pytest.raises(InputError):
        ProposalParams(side_wall_follow=-0.5)


def test_raised_groups_that_meet_become_one():
    a = np.zeros((10, 12), bool)
    b = np.zeros_like(a)
    c = np.zeros_like(a)
    a[2:5, 1:4] = True
    b[2:5, 4:7] = True   # 4-neighbours of a
    c[7:9, 9:11] = True  # apart
    out = _merge_meeting([a, b, c], cap=100)
    assert len(out) == 2 and out[0].sum() == 18 and (out[1] == c).all()
    # overlapping masks join too; a join over the cap is not made
    b2 = np.zeros_like(a)
    b2[3:6, 2:5] = True
    assert len(_merge_meeting([a, b2], cap=100)) == 1
    assert len(_merge_meeting([a, b], cap=17)) == 2
    assert RaisedParams().merge_grown and RaisedParams().join_clusters


def test_lone_raised_group_joins_the_cluster_it_touches():
    h, w = 12, 12
    yy, xx = np.mgrid[0:h, 0:w]
    xyz = np.stack([xx * 0.01, yy * 0.01, np.full((h, w), 1.0)], axis=-1)
    cluster = np.zeros((h, w), bool)
    cluster[0:4, 0:12] = True   # an open box's inner wall, no plane
    group = np.zeros((h, w), bool)
    group[4:8, 2:10] = True     # its raised bottom, right below it
    far = np.zeros((h, w), bool)
    far[10:12, 0:3] = True      # a plate two rows away: alone
    objs = [CurvedObject((3,), None, 1.0, False, 50), CurvedObject((), cluster, 0.0, True, 48)]
    out = with_raised(objs, [(3,)], [None], [group, far], 0.8, xyz, 0.02)
    assert len(out) == 3
    assert (out[1].mask == (cluster | group)).all() and out[1].n_points == 48 + 32
    assert out[1].planar_fraction == pytest.approx(32 / 80)
    assert (out[2].mask == far).all()
    # without the cloud (join_clusters off) both groups stand alone, as before
    assert len(with_raised(objs, [(3,)], [None], [group, far], 0.8)) == 4


def test_mostly_hidden_objects_are_not_scored():
    meta = {"objects": [{"index": 0, "class": "environment"},
                        {"index": 1, "class": "box", "n_pixels": 20, "n_pixels_full": 100},
                        {"index": 2, "class": "stairs", "n_pixels": 5, "n_pixels_full": 100},
                        {"index": 3, "class": "other", "n_pixels": 40, "n_pixels_full": 100},
                        {"index": 4, "class": "other", "n_pixels": 10}]}
    assert mostly_hidden(meta) == {1}
    assert mostly_hidden(meta, min_visible=0.5) == {1, 3}
    with pytest.raises(InputError):
        mostly_hidden(meta, min_visible=1.5)
    truth = np.array([[1, 1, 2, 2], [1, 1, 2, 2], [0, 0, 3, 3]])
    prop = np.array([[0, 0, -1, -1], [0, 0, -1, -1], [-1, -1, 1, 1]])
    s = score_objects(prop, truth)
    assert (s.n_objects, s.found, s.false) == (3, 2, 0)
    s = score_objects(prop, truth, ignore={1})
    # object 1 is neither found nor missed, and its proposal is no false one
    assert (s.n_objects, s.found, s.false) == (2, 1, 0) and 1 not in s.best_iou
    s = score_objects(prop, truth, ignore={2})
    assert (s.n_objects, s.found, s.false) == (2, 2, 0)


def test_unassigned_part_touching_one_proposal_joins_it():
    from planerel.features.curved import CurvedParams, join_parts

    h, w = 14, 14
    yy, xx = np.mgrid[0:h, 0:w]
    xyz = np.stack([xx * 0.01, yy * 0.01, np.full((h, w), 1.0)], axis=-1)
    lab = np.full((h, w), -1, np.int32)
    lab[0:4, 0:8] = 1     # a seat (32 px)
    lab[0:4, 10:14] = 2   # another object's plane (16 px)
    valid = lab >= 0
    valid[4:12, 1:3] = True    # a leg under the seat: touches it only
    valid[0:4, 8:10] = True    # a part between the two planes: touches both
    valid[4:14, 10:14] = True  # a part under plane 2, larger than plane 2
    xyz[~valid] = np.nan
    objs = [CurvedObject((1,), None, 1.0, False, 32), CurvedObject((2,), None, 1.0, False, 16)]
    out = join_parts(objs, xyz, lab)
    leg = np.zeros((h, w), bool)
    leg[4:12, 1:3] = True
    assert (out[0].mask == leg).all()
    # in the proposal's pixels, not in its planar fraction
    assert out[0].planar_fraction == 1.0 and not out[0].curved and out[0].n_points == 48
    assert out[1].mask is None
    # a part far in depth from the plane it touches in the grid is not joined
    far = xyz.copy()
    far[4:12, 1:3, 2] = 1.5
    assert join_parts(objs, far, lab)[0].mask is None
    assert not CurvedParams().join_parts  # an option: its cost (docs/objects.md)


def test_chair_legs_join_the_seat_in_a_rendered_scene():
    # a seat 0.45 m up on two 3 cm legs in view, the legs left unassigned (thin: the clusters'
    # opening removes them): with join_parts they are in the seat's proposal
    from planerel.features.curved import CurvedParams

    seat = Rect((0.0, 2.0, 0.45), (1, 0, 0), (0, 1, 0), 0.22, 0.22, 1)
    legs = [Rect((sx * 0.2, 2.0 - 0.2, 0.225), (1, 0, 0), (0, 0, 1), 0.015, 0.225, 1)
            for sx in (-1, 1)]
    cloud, lab, _up, objs = render([floor(), seat] + legs, pitch=20, cam_height=1.2,
                                   width=320, height=240, noise=0.001)
    truth = np.where(lab >= 1, 1, np.where(lab == 0, 0, -1))
    lab = lab.copy()
    lab[lab >= 2] = -1
    from planerel.features.object_eval import proposal_image

    def iou(cp):
        d = describe_scene(cloud, lab, curved_params=cp)
        img = proposal_image(d.labels, [o.planes for o in d.objects], [o.mask for o in d.objects])
        return score_objects(img, truth).best_iou[1]

    assert iou(CurvedParams(join_parts=True)) > iou(CurvedParams()) + 0.05
