"""Issue 22, tenth pass: a shelf's stacked boards are one proposal (planerel.features.boards),
a chair's backrest stays with its seat (``ProposalParams.riser_max``) while two boxes of one
width stay apart (docs/objects.md "Tenth pass").

Scenes are ray-cast rectangles with one label each (tests/scenes_analytic.py): what is tested
is the proposal rule, not the segmentation.
"""

from __future__ import annotations

from types import SimpleNamespace as NS

import numpy as np
import pytest
from scenes_analytic import Rect, floor, render, stairs
from test_proposals_scenes import _box, _proposals

from planerel.errors import InputError
from planerel.features.boards import footprint_overlap, stacked_board_pairs
from planerel.features.facts import describe_scene
from planerel.features.relations import ProposalParams

#: a camera above and in front of the stack, looking down on it
HIGH = dict(pitch=40, cam_height=2.2, width=320, height=240)


def _boards(heights, cx=0.0, cy=2.2, width=0.8, depth=0.35, obj=1):
    """Horizontal boards (thin plates) one above another, as a shelf's boards seen with its
    panels not segmented."""
    return [Rect((cx, cy, z), (1, 0, 0), (0, 1, 0), width / 2, depth / 2, obj) for z in heights]


def test_stacked_boards_are_one_proposal():
    for heights in ((0.3, 0.6, 0.9), (0.25, 0.5, 0.75, 1.0), (0.4, 0.8, 1.2, 1.6)):
        props, seen = _proposals([floor()] + _boards(heights), **HIGH)
        assert len(seen[1]) == len(heights)
        assert seen[1] in props, (heights, props)
        # without the rule every board is a proposal of its own
        # (the open treads off too: a shelf's boards are slabs at regular levels, riser26)
        apart, _ = _proposals([floor()] + _boards(heights),
                              ProposalParams(stacked_boards=False, open_treads=False), **HIGH)
        assert sum(1 for p in apart if p & seen[1]) == len(heights), (heights, apart)


def test_two_boards_or_an_irregular_stack_are_no_shelf():
    # two planes one over the other (a box on a box, a table and its lower board): no stack
    props, seen = _proposals([floor()] + _boards((0.4, 0.8)), **HIGH)
    assert sum(1 for p in props if p & seen[1]) == 2
    # rises 0.15 and 0.45 m: not evenly spaced
    props, seen = _proposals([floor()] + _boards((0.3, 0.45, 0.9)), **HIGH)
    assert sum(1 for p in props if p & seen[1]) == 3
    # with a regularity tolerance that takes them, one stack
    lab = _labels_of([floor()] + _boards((0.3, 0.45, 0.9)))
    assert len(stacked_board_pairs(lab[0], lab[1], regular=0.7)) == 2
    # boards beyond board_rise_max apart
    # (the open treads off: boards 0.3 m apart are slabs one rise apart to them, riser26)
    props, seen = _proposals([floor()] + _boards((0.3, 0.6, 0.9)),
                             ProposalParams(board_rise_max=0.25, open_treads=False), **HIGH)
    assert sum(1 for p in props if p & seen[1]) == 3


def _labels_of(rects, **view):
    cloud, lab, _up, _objs = render(rects, **(view or HIGH))
    d = describe_scene(cloud, lab)
    return d.planes, [p.label for p in d.planes if p.label not in d.support]


def test_a_staircase_is_no_stack_of_boards():
    # a flight's treads rise alike but each lies one run beyond the last: footprints apart
    planes, cands = _labels_of([floor()] + stairs(0.0, 2.0, n=4), pitch=35, cam_height=1.8,
                               width=320, height=240)
    treads = [p for p in planes if p.orientation == "horizontal" and p.label in cands]
    assert len(treads) >= 3
    assert stacked_board_pairs(planes, cands) == set()


def test_footprint_overlap():
    def sq(x0, y0, s, z):
        return NS(hull3d=np.array([[x0, y0, z], [x0 + s, y0, z], [x0 + s, y0 + s, z], [x0, y0 + s, z]]))

    up = (0.0, 0.0, 1.0)
    assert footprint_overlap(sq(0, 0, 1, 0), sq(0, 0, 1, 0.5), up) == pytest.approx(1.0)
    # a strip in front of the board above lies within it
    assert footprint_overlap(sq(0, 0, 1, 0), sq(0.2, 0.2, 0.3, 0.3), up) == pytest.approx(1.0)
    assert footprint_overlap(sq(0, 0, 1, 0), sq(0.5, 0, 1, 0.3), up) == pytest.approx(0.5)
    assert footprint_overlap(sq(0, 0, 1, 0), sq(1.0, 0, 1, 0.3), up) == pytest.approx(0.0)
    line = NS(hull3d=np.array([[0, 0, 0], [1, 0, 0]], float))
    assert footprint_overlap(line, sq(0, 0, 1, 0.3), up) == 0.0


def test_bad_board_parameters_are_refused():
    planes, cands = _labels_of([floor()] + _boards((0.3, 0.6, 0.9)))
    for kw in (dict(min_overlap=1.5), dict(rise=(0.5, 0.2)), dict(min_boards=1)):
        with pytest.raises(InputError):
            stacked_board_pairs(planes, cands, **kw)
    for kw in (dict(board_overlap=-0.1), dict(board_overlap=2.0), dict(board_rise_max=-1.0),
               dict(riser_max=-0.1)):
        with pytest.raises(InputError):
            ProposalParams(**kw)


def _chair(back, cx=0.0, cy=2.0, seat=0.45, seat_h=0.45, obj=1):
    """A chair's seat and backrest (no legs: the segmentation seldom finds them)."""
    return [Rect((cx, cy, seat_h), (1, 0, 0), (0, 1, 0), seat / 2, seat / 2, obj),
            Rect((cx, cy + seat / 2, seat_h + back / 2), (1, 0, 0), (0, 0, 1), seat / 2, back / 2, obj)]


@pytest.mark.parametrize("back", [0.35, 0.5, 0.55])
def test_a_chairs_backrest_stays_with_its_seat(back):
    props, seen = _proposals([floor()] + _chair(back), pitch=30, cam_height=1.6, width=320, height=240)
    assert len(seen[1]) == 2 and seen[1] in props, (back, props)
    if back > 0.45:
        # the limit before the tenth pass cut it off its seat (LCCP's concave edge)
        cut, _ = _proposals([floor()] + _chair(back), ProposalParams(riser_max=0.45), pitch=30,
                            cam_height=1.6, width=320, height=240)
        assert seen[1] not in cut


@pytest.mark.parametrize("h1,h2", [(0.5, 1.05), (0.4, 0.9), (0.45, 1.0)])
def test_two_boxes_of_one_width_a_tall_riser_apart_stay_two(h1, h2):
    # a box and a taller one of the same width touching its back: the lower top and the taller
    # front meet as tread and riser, and the risers' heights are alike, but a flight's riser
    # is at most 1.5 x step_rise_max (0.45 m) high: two objects, whatever riser_max allows
    rects = [floor()] + _box(0.0, 2.0, 0.5, 0.3, h1, obj=1) + _box(0.0, 2.3, 0.5, 0.3, h2, obj=2)
    props, seen = _proposals(rects, pitch=30, cam_height=1.8)
    assert seen[1] in props and seen[2] in props, (h1, h2, props)
