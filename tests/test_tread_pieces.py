"""pieces71: a tread seen as two coplanar pieces side by side is tested whole in the step chains
(``ProposalParams.step_tread_pieces``, :mod:`planerel.features.tread_pieces`; docs/results.md
"A tread in pieces")."""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import Rect, floor, render

from planerel.errors import InputError
from planerel.features.facts import describe_scene
from planerel.features.relations import ProposalParams, step_chain_pairs
from planerel.features.tread_pieces import PIECE_LEVEL, tread_unions

RISE, RUN, WIDTH, NOSE = 0.2, 0.3, 1.2, 0.8


def _flight_from_top(gap=0.15, split_at=0.1, lift=0.0, behind=False, whole=False, pitch=45.0,
                     eye=1.0):
    """The landing the camera stands on (support: it runs out of the image's bottom edge), two
    treads going down away from it (object 1) and the floor.  The upper tread is two pieces
    side by side along its length, ``gap`` m apart, the cut ``split_at`` m off its middle
    (the right piece ``lift`` m higher); with ``behind`` the two pieces lie one behind the
    other along the flight instead; with ``whole`` it is one tread."""
    top = 3 * RISE
    rects = [floor(), Rect((0, NOSE - 1.0, top), (1, 0, 0), (0, 1, 0), WIDTH / 2 + 0.5, 1.0, -1)]
    y1, z1 = NOSE + 0.5 * RUN, top - RISE
    if whole:
        rects.append(Rect((0, y1, z1), (1, 0, 0), (0, 1, 0), WIDTH / 2, RUN / 2, 1))
    elif behind:
        # split 0.6 of a run from the nosing: the landing's nosing hides the near 0.08 m
        # (camera 2 m over it), the near piece's far part is seen
        y0, cut = NOSE, NOSE + 0.6 * RUN
        rects += [Rect((0, (y0 + cut - gap / 2) / 2, z1), (1, 0, 0), (0, 1, 0), WIDTH / 2,
                       (cut - gap / 2 - y0) / 2, 1),
                  Rect((0, (cut + gap / 2 + y0 + RUN) / 2, z1 + lift), (1, 0, 0), (0, 1, 0),
                       WIDTH / 2, (y0 + RUN - cut - gap / 2) / 2, 1)]
    else:
        cut = split_at
        left_w = WIDTH / 2 + cut - gap / 2   # from -WIDTH/2 to cut - gap/2
        right_w = WIDTH / 2 - cut - gap / 2  # from cut + gap/2 to WIDTH/2
        rects += [Rect((-WIDTH / 2 + left_w / 2, y1, z1), (1, 0, 0), (0, 1, 0), left_w / 2,
                       RUN / 2, 1),
                  Rect((WIDTH / 2 - right_w / 2, y1, z1 + lift), (1, 0, 0), (0, 1, 0),
                       right_w / 2, RUN / 2, 1)]
    rects.append(Rect((0, NOSE + 1.5 * RUN, top - 2 * RISE), (1, 0, 0), (0, 1, 0), WIDTH / 2,
                      RUN / 2, 1))
    for i in range(3):
        rects.append(Rect((0, NOSE + i * RUN, top - (i + 0.5) * RISE), (1, 0, 0), (0, 0, 1),
                          WIDTH / 2, RISE / 2, 1))
    return render(rects, pitch=pitch, cam_height=top + eye, noise=0.001)


def _treads(desc, objs):
    """The labels of the flight's treads."""
    return {p.label for p in desc.planes if objs[p.label] == 1 and p.orientation == "horizontal"}


def _steps(desc, treads, on):
    return step_chain_pairs(desc.planes, treads, (0.08, 0.3), (0.12, 0.6), tread_pieces=on)


def test_a_tread_in_two_pieces_joins_the_flight():
    cloud, lab, _up, objs = _flight_from_top()
    off = describe_scene(cloud, lab, proposal_params=ProposalParams(step_tread_pieces=False))
    treads = _treads(off, objs)
    assert len(treads) == 3  # two pieces and the lower tread
    # each piece alone spans under half the flight's width: no step, no one proposal
    assert not _steps(off, treads, False)
    assert not any(treads <= set(o.planes) for o in off.objects)
    on = describe_scene(cloud, lab, proposal_params=ProposalParams(step_tread_pieces=True))
    assert any(treads <= set(o.planes) for o in on.objects)
    # each piece makes a step with the lower tread
    low = min(treads, key=lambda k: on.planes.by_label(k).height)
    assert _steps(on, treads, True) == {(low, k) for k in treads - {low}}
    # the steps themselves (the stair_step/2 facts) name the larger piece only: one step
    big = max(treads - {low}, key=lambda k: on.planes.by_label(k).area)
    steps = step_chain_pairs(on.planes, treads, (0.08, 0.3), (0.12, 0.6), tread_pieces=True,
                             chain=False)
    assert {(s[0], s[1]) for s in steps} == {(low, big)}


def test_the_union_stands_for_both_pieces():
    cloud, lab, up, objs = _flight_from_top()
    desc = describe_scene(cloud, lab)
    ps = desc.planes
    treads = [p for p in ps if objs[p.label] == 1 and p.orientation == "horizontal"]
    unions = tread_unions(treads, np.asarray(ps.up), np.cos(np.radians(10.0)), 100)
    assert list(unions) == [100]
    u, pieces = unions[100]
    by = {p.label: p for p in treads}
    assert len(pieces) == 2
    assert u.area == pytest.approx(sum(by[k].area for k in pieces))
    # the union spans the tread's width (less nothing: the gap lies inside it)
    assert u.length == pytest.approx(WIDTH, abs=0.05)
    # as deep as the pieces as seen (the landing's nosing hides the tread's near part)
    assert u.width == pytest.approx(max(by[k].width for k in pieces), abs=0.02)
    assert min(by[k].height for k in pieces) <= u.height <= max(by[k].height for k in pieces)


@pytest.mark.parametrize("kw", [dict(lift=2 * PIECE_LEVEL), dict(gap=0.45),
                                dict(behind=True, gap=0.02, eye=2.0),
                                dict(gap=0.05, split_at=0.45)])
def test_no_union_of_what_is_not_one_tread(kw):
    # pieces at two levels, far apart along the length, one behind the other, or a tread and
    # a sliver beside it (0.125 of 1.15 m: under PIECE_SHARE) are no tread
    cloud, lab, _up, objs = _flight_from_top(**kw)
    desc = describe_scene(cloud, lab)
    ps = desc.planes
    treads = [p for p in ps if objs[p.label] == 1 and p.orientation == "horizontal"]
    assert len(treads) == 3
    assert tread_unions(treads, np.asarray(ps.up), np.cos(np.radians(10.0)), 100) == {}


def test_a_whole_flight_is_the_same_either_way():
    # one tread, nothing to join: the proposals are the same
    cloud, lab, _up, _objs = _flight_from_top(whole=True)
    a = describe_scene(cloud, lab, proposal_params=ProposalParams(step_tread_pieces=False))
    b = describe_scene(cloud, lab, proposal_params=ProposalParams(step_tread_pieces=True))
    assert [sorted(o.planes) for o in a.objects] == [sorted(o.planes) for o in b.objects]


def test_a_bad_value_is_refused():
    with pytest.raises(InputError, match="step_tread_pieces"):
        ProposalParams(step_tread_pieces="yes")
