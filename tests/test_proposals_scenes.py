"""Object proposals on small analytic scenes with known objects (issue 22).

Each scene is ray-cast from rectangles that carry their object id (tests/scenes_analytic.py);
the planes are the true ones (one label per rectangle), so what is tested is the proposal rule
(planerel.features.proposals.propose_objects), not the segmentation.  Expected proposals follow from
the scene's construction: every object's visible faces in one proposal of their own.
"""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import Rect, floor, render

from planerel.features.facts import describe_scene
from planerel.features.relations import ProposalParams


def _box(cx, cy, sx, sy, sz, z0=0.0, obj=1):
    """Top and four sides of an axis-aligned box whose bottom is at height z0."""
    zc = z0 + sz / 2
    return [
        Rect((cx, cy, z0 + sz), (1, 0, 0), (0, 1, 0), sx / 2, sy / 2, obj),
        Rect((cx, cy - sy / 2, zc), (1, 0, 0), (0, 0, 1), sx / 2, sz / 2, obj),
        Rect((cx - sx / 2, cy, zc), (0, 1, 0), (0, 0, 1), sy / 2, sz / 2, obj),
        Rect((cx + sx / 2, cy, zc), (0, 1, 0), (0, 0, 1), sy / 2, sz / 2, obj),
        Rect((cx, cy + sy / 2, zc), (1, 0, 0), (0, 0, 1), sx / 2, sz / 2, obj),
    ]


def _proposals(rects, params=None, **view):
    """Proposals as sets of object ids per plane, and the visible planes of each object."""
    cloud, lab, _up, objs = render(rects, **view)
    d = describe_scene(cloud, lab, proposal_params=params)
    seen = {}
    for p in d.planes:
        seen.setdefault(objs[p.label], set()).add(p.label)
    return [set(o.planes) for o in d.objects], seen


def _has_own_proposal(props, seen, obj):
    return seen[obj] in props


def test_box_on_a_table_comes_apart_and_keeps_its_faces_together():
    # a table top 0.7 m high (0.96 m^2, above the floor) and a box standing on it, turned so
    # that its top and two sides are seen; the box's faces meet convexly, the box and the
    # table top at a concave edge.  The table top carries the box: support (falsecls,
    # ``table_area``); without that rule it is an object of its own, apart from the box
    top = Rect((0, 2.5, 0.7), (1, 0, 0), (0, 1, 0), 0.6, 0.4, 2)
    rects = [floor(), top] + _box(0.4, 2.45, 0.3, 0.3, 0.25, z0=0.7, obj=1)
    props, seen = _proposals(rects, pitch=30, cam_height=1.5)
    assert len(seen[1]) >= 3  # top and two sides are in view
    assert _has_own_proposal(props, seen, 1) and not any(p & seen[2] for p in props)
    old = ProposalParams(table_area=0.0)
    props, seen = _proposals(rects, old, pitch=30, cam_height=1.5)
    assert _has_own_proposal(props, seen, 1) and _has_own_proposal(props, seen, 2)
    merged, _ = _proposals(rects, ProposalParams(split_concave=False, table_area=0.0), pitch=30,
                           cam_height=1.5)
    assert seen[1] | seen[2] in merged  # plain adjacency joins them


def test_box_against_a_wall_comes_apart():
    # a wall panel (1.2 x 1.2 m, under the support area) touching the box's back face
    rects = [floor(), Rect((0, 3.0, 0.6), (1, 0, 0), (0, 0, 1), 0.6, 0.6, 2)]
    rects += _box(0.0, 2.7, 0.5, 0.6, 0.4, obj=1)
    props, seen = _proposals(rects, pitch=20, cam_height=1.2)
    assert _has_own_proposal(props, seen, 1)
    assert not any(p & seen[1] and p & seen[2] for p in props)
    merged, _ = _proposals(rects, ProposalParams(split_concave=False), pitch=20, cam_height=1.2)
    assert seen[1] | seen[2] in merged


def test_tall_box_at_the_border_is_kept_and_a_wall_there_is_dropped():
    # left: a box taller than the camera, cut by the image's left border (vertical faces only,
    # one over 0.3 m^2: a wall by size), with the floor seen behind its side; right: a wall
    # panel cut by the right border at the floor's far end, nothing seen behind it
    rects = [floor(size=7, y=0)] + _box(-1.6, 2.5, 1.0, 0.8, 1.6, obj=1)
    rects.append(Rect((1.8, 3.5, 0.7), (1, 0, 0), (0, 0, 1), 0.8, 0.7, 2))
    props, seen = _proposals(rects)
    assert _has_own_proposal(props, seen, 1)
    assert not any(p & seen[2] for p in props)
    # without the look behind (wall_behind=1) the box is still kept by the floor seen beyond its
    # front's plane (wall_floor_behind, synth22t); without both tests both count as walls
    props, _ = _proposals(rects, ProposalParams(wall_behind=1))
    assert _has_own_proposal(props, seen, 1) and not any(p & seen[2] for p in props)
    props, _ = _proposals(rects, ProposalParams(wall_behind=1, wall_floor_behind=0))
    assert not any(p & seen[1] for p in props)


def test_box_behind_a_lower_box_is_no_step_of_it():
    # a taller box 4 cm behind a lower one of the same width: the front face of the far box
    # rises behind the near box's top like a riser behind a tread, but the two do not meet
    # (an occluding edge), so the tread-and-riser exception does not join them
    rects = [floor()] + _box(0.3, 2.0, 0.4, 0.3, 0.3, obj=1) + _box(0.3, 2.34, 0.4, 0.3, 0.45, obj=2)
    props, seen = _proposals(rects, pitch=30, cam_height=1.3)
    assert _has_own_proposal(props, seen, 1) and _has_own_proposal(props, seen, 2)


def _treads(n=4, rise=0.18, run=0.28, width=0.9, y0=2.0, obj=1):
    """The treads of a flight rising away from the camera, without the risers between them
    (as seen from above a descending flight, where the risers face away)."""
    return [Rect((0.0, y0 + (k + 0.5) * run, (k + 1) * rise), (1, 0, 0), (0, 1, 0), width / 2,
                 run / 2 - 0.01, obj) for k in range(n)]


def test_treads_without_risers_are_one_staircase():
    rects = [floor()] + _treads()
    props, seen = _proposals(rects, pitch=35, cam_height=1.6)
    assert len(seen[1]) == 4
    assert _has_own_proposal(props, seen, 1)
    # (the open treads off too: they join slabs at regular levels whatever joins them, riser26)
    apart, _ = _proposals(rects, ProposalParams(step_chains=False, open_treads=False), pitch=35,
                          cam_height=1.6)
    assert not any(p == seen[1] for p in apart)


def test_two_narrow_treads_are_no_staircase():
    # two faces a step apart, as narrow as box tops (0.4 m): a chain needs three faces in a
    # row, and two alone count only when they are as wide as a flight
    rects = [floor()] + _treads(n=2, width=0.4)
    props, seen = _proposals(rects, pitch=35, cam_height=1.6)
    assert len(seen[1]) == 2 and seen[1] not in props


def test_two_wide_treads_a_rise_above_the_floor_are_one_staircase():
    # two 0.9 m wide treads, the floor one more rise below them: a short flight; the floor
    # completes the row of three but does not join the proposal
    rects = [floor()] + _treads(n=2)
    props, seen = _proposals(rects, pitch=35, cam_height=1.6)
    assert len(seen[1]) == 2 and seen[1] in props


def test_two_treads_one_partly_hidden_are_one_staircase_by_their_own_axes():
    # the real Kinect v2 staircase seen from above (stair-perception 0000): a leg hides one
    # side of the lower tread, so its centroid sits off to the side; measured along the line
    # between the centroids the step looked 0.5 m deep and the treads too narrow for a flight.
    # Measured across the treads' own shortest extent (step_tread_axes) it is one step.
    upper = _treads(n=2)[1]
    lower = Rect((0.15, 2.0 + 0.5 * 0.28, 0.18), (1, 0, 0), (0, 1, 0), 0.3, 0.28 / 2 - 0.01, 1)
    rects = [floor(), lower, upper]
    props, seen = _proposals(rects, ProposalParams(step_tread_axes=True), pitch=35,
                             cam_height=1.6)
    assert len(seen[1]) == 2 and seen[1] in props
    apart, _ = _proposals(rects, ProposalParams(step_tread_axes=False), pitch=35, cam_height=1.6)
    assert seen[1] not in apart


def test_a_riser_below_in_two_pieces_still_makes_a_regular_step():
    # a real stair seen close (elmasry 1347691665): the riser below the tread segments as the
    # riser and a 5 cm strip under the nosing; measured alone, the strip (0.05 m) made the
    # step irregular against the 0.18 m riser above, and the tread and the riser above were
    # cut apart.  Measured together (riser_pieces) the riser below is 0.18 m high too.
    y0, rise, run, w = 1.6, 0.18, 0.28, 0.45
    # the strip (drawn first: it wins where the two overlap) along half the riser's top edge;
    # both the strip and the rest of the riser meet the tread
    rects = [floor(),
             Rect((-w / 2, y0, 0.155), (1, 0, 0), (0, 0, 1), w / 2, 0.025, 1),  # strip, 0.13-0.18 m
             Rect((0.0, y0, rise / 2), (1, 0, 0), (0, 0, 1), w, rise / 2, 1),     # riser 1, 0-0.18 m
             Rect((0.0, y0 + run / 2, rise), (1, 0, 0), (0, 1, 0), w, run / 2, 1),   # tread 1
             Rect((0.0, y0 + run, 1.5 * rise), (1, 0, 0), (0, 0, 1), w, rise / 2, 1),  # riser 2
             Rect((0.0, y0 + 1.5 * run, 2 * rise), (1, 0, 0), (0, 1, 0), w, run / 2, 1)]  # tread 2
    view = {"pitch": 30, "cam_height": 1.2}
    kw = {"step_chains": False}  # the tread-and-riser exception alone
    props, seen = _proposals(rects, ProposalParams(riser_pieces=True, **kw), **view)
    assert len(seen[1]) == 5 and seen[1] in props
    apart, _ = _proposals(rects, ProposalParams(riser_pieces=False, **kw), **view)
    assert not any({3, 4} <= p for p in apart)  # tread 1 and riser 2 cut apart


def test_the_lowest_tread_is_no_floor_when_no_floor_is_seen():
    # a camera close to a flight (elmasry 1347691665): no floor in view, the lowest tread is
    # the lowest horizontal plane and was taken as the floor; the flight kept one tread.  It is
    # step-shaped, a riser of one rise goes up to a tread with a riser of that height above
    # it: a tread (floor_tread), and the flight's proposal holds it.
    y0, rise, run, w = 1.0, 0.17, 0.3, 0.45
    rects = [Rect((0.0, y0 - run / 2, rise), (1, 0, 0), (0, 1, 0), w, run / 2, 1),        # tread 0
             Rect((0.0, y0, 1.5 * rise), (1, 0, 0), (0, 0, 1), w, rise / 2, 1),          # riser 1
             Rect((0.0, y0 + run / 2, 2 * rise), (1, 0, 0), (0, 1, 0), w, run / 2, 1),   # tread 1
             Rect((0.0, y0 + run, 2.5 * rise), (1, 0, 0), (0, 0, 1), w, rise / 2, 1)]    # riser 2
    view = {"pitch": 45, "cam_height": 0.95}
    props, seen = _proposals(rects, ProposalParams(floor_tread=True), **view)
    assert len(seen[1]) == 4 and seen[1] in props
    apart, _ = _proposals(rects, ProposalParams(floor_tread=False), **view)
    assert not any(0 in p for p in apart)  # tread 0 was the floor: support, in no proposal
    # the same flight on a floor, its first riser in view: the floor stays support
    riser0 = Rect((0.0, y0 - run, rise / 2), (1, 0, 0), (0, 0, 1), w, rise / 2, 1)
    props, seen = _proposals([floor(), riser0, *rects], pitch=45, cam_height=1.2)
    assert len(seen[1]) == 5 and seen[1] in props and not any(0 in p for p in props)


def test_tread_depth_axis_is_across_the_tread():
    from types import SimpleNamespace

    from planerel.features.relations import _tread_depth_axis

    # a 0.9 x 0.28 m tread turned 30 degrees about the vertical, z up
    t = np.radians(30)
    along, across = np.array([np.cos(t), np.sin(t), 0]), np.array([-np.sin(t), np.cos(t), 0])
    hull = np.array([s * 0.45 * along + r * 0.14 * across
                     for s, r in ((-1, -1), (1, -1), (1, 1), (-1, 1))])
    axis, elong = _tread_depth_axis(SimpleNamespace(hull3d=hull), np.array([0.0, 0, 1]))
    assert abs(abs(float(axis @ across)) - 1) < 1e-9
    assert elong == pytest.approx(0.9 / 0.28)
    axis, elong = _tread_depth_axis(SimpleNamespace(hull3d=hull[:2]), np.array([0.0, 0, 1]))
    assert elong == 0.0  # a segment has no depth direction


def _tilted_treads(n=4, rise=0.18, run=0.28, width=0.9, y0=2.0, tilt=8.0, obj=1):
    t = np.radians(tilt)
    return [Rect((0.0, y0 + (k + 0.5) * run, (k + 1) * rise), (1, 0, 0), (0, np.cos(t), np.sin(t)),
                 width / 2, run / 2 - 0.01, obj) for k in range(n)]


def test_treads_a_few_degrees_off_horizontal_still_chain():
    # far treads of a real flight measure a few degrees off (inclined by the 5-degree
    # horizontal tolerance); within step_tilt (12) they are treads of the chain
    rects = [floor()] + _tilted_treads()
    props, seen = _proposals(rects, pitch=35, cam_height=1.6)
    assert seen[1] in props
    apart, _ = _proposals(rects, ProposalParams(step_tilt=0.0, open_treads=False), pitch=35,
                          cam_height=1.6)
    assert not any(p == seen[1] for p in apart)


def test_a_missing_tread_does_not_cut_the_flight():
    # five treads, the middle one not found (a rail across it, too few pixels): the treads
    # two rises apart are a step of two
    tr = _treads(n=5)
    props, seen = _proposals([floor()] + tr[:2] + tr[3:], pitch=35, cam_height=1.6)
    assert len(seen[1]) == 4 and seen[1] in props


def _descending(n_treads, rise=0.18, run=0.28, width=0.9):
    """The camera's landing (environment, nose 0.8 m ahead), ``n_treads`` treads going down
    away from it (their risers face away: not seen) and the lower floor; and its height."""
    top = (n_treads + 1) * rise
    landing = Rect((0.0, -0.2, top), (1, 0, 0), (0, 1, 0), 1.5, 1.0, -1)
    treads = [Rect((0.0, 0.8 + (k + 0.5) * run, top - (k + 1) * rise), (1, 0, 0), (0, 1, 0),
                   width / 2, run / 2 - 0.01, 1) for k in range(n_treads)]
    low = Rect((0.0, 0.8 + n_treads * run + 2.0, 0.0), (1, 0, 0), (0, 1, 0), 3.0, 2.0, -1)
    return [landing, low, *treads], top


def test_descending_flight_without_the_landing_it_starts_from():
    # seen from the landing, cut by the image's bottom edge: the landing is one rise above
    # the top tread and looks like a tread, but its depth is not seen: it is no step
    for n in (2, 3, 4):
        rects, top = _descending(n)
        for pitch in (35, 45):
            props, seen = _proposals(rects, pitch=pitch, cam_height=top + 1.2)
            assert len(seen[1]) == n and seen[1] in props, (n, pitch, props)


def test_a_wall_behind_the_lowest_tread_is_no_riser():
    # a 1.2 m wall (another object) across the bottom of a flight seen from its landing: it
    # meets the lowest tread at a concave edge like the riser above a tread, but it is four
    # rises high: the tread-and-riser exception does not take it (it did before)
    for n in (3, 4):
        rects, top = _descending(n)
        rects.append(Rect((0.0, 0.8 + n * 0.28, 0.6), (1, 0, 0), (0, 0, 1), 0.5, 0.6, 2))
        props, seen = _proposals(rects, pitch=40, cam_height=top + 1.2)
        assert seen[1] in props and seen[2] in props, (n, props)


@pytest.mark.parametrize("h1,h2", [(0.2, 0.4), (0.2, 0.5), (0.18, 0.36), (0.1, 0.3)])
def test_two_touching_boxes_of_different_heights_are_two_proposals(h1, h2):
    # a box with a taller one touching its back (other width, shifted sideways), at room
    # scale and at table-top (mOSD) scale: never one object, so never one staircase
    rects = [floor()] + _box(0.0, 2.0, 0.5, 0.3, h1, obj=1) + _box(0.12, 2.3, 0.6, 0.3, h2, obj=2)
    props, seen = _proposals(rects, pitch=30, cam_height=1.4)
    assert seen[1] in props and seen[2] in props
    rects = [floor()] + _box(0.0, 1.0, 0.25, 0.15, h1 / 2, obj=1) + _box(0.05, 1.15, 0.3, 0.15, h2 / 2, obj=2)
    props, seen = _proposals(rects, pitch=45, cam_height=0.9)
    assert seen[1] in props and seen[2] in props


def test_step_ranges_are_checked():
    from planerel.errors import InputError

    with pytest.raises(InputError):
        ProposalParams(step_rise_min=0.3, step_rise_max=0.1)


def test_box_on_a_box_of_the_same_width_comes_apart():
    # a 0.25 m high box on a 0.4 m high one of the same width, set back so that a strip of
    # the lower one's top is seen: tread and riser of one flight by width, but its "risers"
    # (0.4 and 0.25 m) do not rise alike
    rects = [floor()] + _box(0.0, 2.0, 0.5, 0.5, 0.4, obj=1) + _box(0.0, 2.1, 0.5, 0.3, 0.25, z0=0.4, obj=2)
    props, seen = _proposals(rects, pitch=30, cam_height=1.4)
    assert _has_own_proposal(props, seen, 1) and _has_own_proposal(props, seen, 2)
    # a staircase's tread and the riser above it stay together (equal risers)
    from scenes_analytic import stairs

    props, seen = _proposals([floor()] + stairs(0.0, 2.0, n=3), pitch=30, cam_height=1.4)
    assert _has_own_proposal(props, seen, 1)


def test_face_seen_behind_another_across_an_occluding_edge_comes_apart():
    # a box's front 16 cm behind a low panel, 3.4 m away: the panel's top edge hides the box's
    # lower part; in the grid they touch (a 16 cm jump is under 5 % of the depth), their hulls
    # are 16 cm apart and no pixel pairs lie within 3 % of the depth: no shared edge, two
    # objects (they were one as "parallel faces of one noisy surface")
    panel = Rect((0.0, 3.3, 0.6), (1, 0, 0), (0, 0, 1), 0.5, 0.1, 2)
    front = Rect((0.1, 3.46, 0.9), (1, 0, 0), (0, 0, 1), 0.3, 0.3, 1)
    view = dict(pitch=10, cam_height=1.2, width=320, height=240, noise=0.001)
    cloud, lab, _up, _objs = render([floor(), panel, front], **view)
    d = describe_scene(cloud, lab)
    rel = d.relations.get(1, 2)
    assert rel.touching and rel.gap > 0.05
    assert {o.planes for o in d.objects} == {(1,), (2,)}


@pytest.mark.parametrize("pitch,cx,cy", [(15, -0.5, 1.8), (35, 0.4, 1.8), (50, 0.0, 1.3)])
def test_one_box_keeps_its_faces_with_the_parallel_and_sanity_checks(pitch, cx, cy):
    # the coplanar check and LCCP's sanity criterion (defaults) must not cut one box's faces:
    # seen from the front-left, front-right and above, at 320x240 with depth noise
    rects = [floor()] + _box(cx, cy, 0.45, 0.35, 0.3, obj=1)
    view = dict(pitch=pitch, cam_height=1.1, width=320, height=240, noise=0.0015)
    props, seen = _proposals(rects, **view)
    assert len(seen[1]) >= 2 and seen[1] in props
    old, _ = _proposals(rects, ProposalParams(coplanar_depth=None, sanity_angle=0), **view)
    assert old == props

