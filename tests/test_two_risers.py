"""riser73: two risers alone make a counted step when both are flight-like and the lower one
stands on a horizontal plane (``ProposalParams.step_two_risers``,
:func:`planerel.features.step_chains._two_riser_steps`; docs/results.md "A flight seen level
from a low robot: two risers")."""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import Rect, floor, render, stairs

from planerel.errors import InputError
from planerel.features.facts import describe_scene
from planerel.features.relations import ProposalParams, step_chain_pairs

RISE, RUN = 0.18, 0.30


def _low_view(rects, cam_height=0.3, drop_floor=False):
    """``rects`` seen level from a camera ``cam_height`` m over the floor, 160x120; the treads
    (horizontal rects of object 1 over the floor) left in no plane, as a segmentation leaves a
    tread seen edge on; with ``drop_floor`` the floor too."""
    cloud, lab, _up, objs = render(rects, pitch=0.0, cam_height=cam_height, noise=0.0005)
    lab = lab.copy()
    for k, r in enumerate(rects):
        flat = abs(np.asarray(r.e1) @ (0, 0, 1)) < 1e-9 and abs(np.asarray(r.e2) @ (0, 0, 1)) < 1e-9
        if flat and ((r.obj == 1 and r.center[2] > 0) or (drop_floor and r.obj == -1)):
            lab[lab == k] = -1
    return cloud, lab, objs


def _risers(desc, objs):
    return sorted(p.label for p in desc.planes
                  if objs[p.label] == 1 and p.orientation == "vertical")


def _together(desc, labels) -> bool:
    return any(set(labels) <= set(o.planes) for o in desc.objects)


def _steps(desc, labels, on):
    return step_chain_pairs(desc.planes, labels, (0.08, 0.3), (0.12, 0.6), two_risers=on)


def test_a_two_step_flight_seen_level_is_one_proposal():
    rects = [floor()] + stairs(0.0, 1.6, n=2, rise=RISE, run=RUN, width=1.2)
    cloud, lab, objs = _low_view(rects)
    off = describe_scene(cloud, lab, proposal_params=ProposalParams(step_two_risers=False))
    risers = _risers(off, objs)
    assert len(risers) == 2
    # a row of two: no counted step, each riser a proposal of its own
    assert not _steps(off, risers, False)
    assert not _together(off, risers)
    on = describe_scene(cloud, lab, proposal_params=ProposalParams(step_two_risers=True))
    lo, hi = sorted(risers, key=lambda k: on.planes.by_label(k).height)
    assert _steps(on, risers, True) == {(lo, hi)}
    assert _together(on, risers)
    # the stair_step/2 fact between them is there either way (no chain asked)
    assert (lo, hi) in {s[:2] for s in step_chain_pairs(on.planes, risers, (0.08, 0.3),
                                                        (0.12, 0.6), chain=False)}


def test_the_tread_between_seen_leaves_it_to_the_rows():
    # the same flight with its lower tread a plane (a camera that sees it): the two risers
    # are no two-riser step; whatever the rows of three make is made either way
    rects = [floor()] + stairs(0.0, 1.6, n=2, rise=RISE, run=RUN, width=1.2)
    cloud, lab, _up, objs = render(rects, pitch=0.0, cam_height=0.3, noise=0.0005)
    desc = describe_scene(cloud, lab)
    treads = [p for p in desc.planes if objs[p.label] == 1 and p.orientation == "horizontal"]
    assert treads  # the lower tread (0.18 m, under the eye) is seen
    labels = [p.label for p in desc.planes if objs[p.label] == 1]
    assert _steps(desc, labels, True) == _steps(desc, labels, False)


def test_two_narrow_faces_are_no_flight():
    # two box faces 0.4 m wide, the farther box a step taller, a run behind: narrower than a
    # flight and than 1.5 times their height
    rects = [floor(),
             Rect((0, 1.6, RISE / 2), (1, 0, 0), (0, 0, 1), 0.2, RISE / 2, 1),
             Rect((0, 1.6 + RUN, RISE), (1, 0, 0), (0, 0, 1), 0.2, RISE, 1)]
    cloud, lab, objs = _low_view(rects)
    desc = describe_scene(cloud, lab)
    risers = _risers(desc, objs)
    assert len(risers) == 2
    assert not _steps(desc, risers, True)


def test_risers_with_no_ground_at_the_foot_are_no_flight():
    rects = [floor()] + stairs(0.0, 1.6, n=2, rise=RISE, run=RUN, width=1.2)
    cloud, lab, objs = _low_view(rects, drop_floor=True)
    desc = describe_scene(cloud, lab)
    risers = _risers(desc, objs)
    assert len(risers) == 2
    assert not _steps(desc, risers, True)


def test_the_default_and_its_check():
    assert ProposalParams().step_two_risers is True
    with pytest.raises(InputError, match="step_two_risers"):
        ProposalParams(step_two_risers="yes")
