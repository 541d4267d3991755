"""cut70: a flight seen from its landing at a yaw, its treads running out of the image's bottom
edge at a slant (``ProposalParams.step_cut_chain``; docs/results.md "Stairs from the top seen at
a yaw: treads cut at a slant")."""

from __future__ import annotations

import math

import pytest
from scenes_analytic import Rect, floor, render

from planerel.errors import InputError
from planerel.features.facts import describe_scene
from planerel.features.relations import CUT_CHAIN_BORDER, ProposalParams, _border_share
from planerel.features.step_geometry import _cut_lengthwise

RISE, RUN, WIDTH, NOSE, X0 = 0.19, 0.30, 1.4, 0.25, 0.3


def _turn(v, yaw):
    c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    return (c * v[0] - s * v[1], s * v[0] + c * v[1], v[2])


def _flight(yaw, n=5, pitch=42.0, eye=1.0, noise=0.001):
    """The landing (support, ``n`` rises up, its edge ``NOSE`` in front of the camera's feet)
    and a flight going down away from it (object 1), turned ``yaw`` degrees about the
    vertical through (``X0``, ``NOSE``); the camera ``eye`` m over the landing."""
    top = n * RISE
    pivot = (X0, NOSE, 0.0)

    def rect(center, e1, e2, a, b, obj):
        c = _turn([center[i] - pivot[i] for i in range(3)], yaw)
        return Rect(tuple(c[i] + pivot[i] for i in range(3)), _turn(e1, yaw), _turn(e2, yaw),
                    a, b, obj)

    rects = [floor(), rect((0, NOSE - 1.0, top), (1, 0, 0), (0, 1, 0), WIDTH / 2 + 0.5, 1.0, -1)]
    for i in range(1, n):
        rects.append(rect((0, NOSE + (i - 0.5) * RUN, top - i * RISE), (1, 0, 0), (0, 1, 0),
                          WIDTH / 2, RUN / 2, 1))
    for i in range(n):
        rects.append(rect((0, NOSE + i * RUN, top - (i + 0.5) * RISE), (1, 0, 0), (0, 0, 1),
                          WIDTH / 2, RISE / 2, 1))
    return render(rects, pitch=pitch, cam_height=top + eye, noise=noise)


def _treads(desc, objs):
    return {p.label for p in desc.planes if objs[p.label] == 1 and p.orientation == "horizontal"}


def _holding(desc, label):
    return next((set(o.planes) for o in desc.objects if label in o.planes), set())


def test_a_tread_cut_at_a_slant_extends_the_row():
    cloud, lab, _up, objs = _flight(yaw=25)
    off = describe_scene(cloud, lab, proposal_params=ProposalParams(step_cut_chain=False))
    treads = _treads(off, objs)
    ps = off.planes
    cut = _cut_lengthwise([p for p in ps if p.label in treads], True, ps.labels)
    share = {p.label: _border_share(ps.labels, p) for p in ps if p.label in cut}
    slant = {k for k, v in share.items() if v < CUT_CHAIN_BORDER}
    whole_cut = set(cut) - slant
    # the scene holds both kinds: a tread cut at a slant and the top tread cut all along
    assert len(slant) == 1 and len(whole_cut) == 1
    (s,), (w,) = slant, whole_cut
    # off: the slanted tread is no member of the row of whole treads
    row = _holding(off, min(treads, key=lambda k: ps.by_label(k).height))
    assert len(row & treads) >= 2 and s not in row
    on = describe_scene(cloud, lab)  # on by default
    assert ProposalParams().step_cut_chain
    row_on = _holding(on, s)
    assert row & treads <= row_on
    # the top tread whose depth the border hides (as a landing's) stays out
    assert w not in row_on


def test_a_flight_seen_straight_on_is_unchanged():
    # no yaw: the whole treads make the row anyway, the cut top tread stays out either way
    cloud, lab, _up, objs = _flight(yaw=0)
    off = describe_scene(cloud, lab, proposal_params=ProposalParams(step_cut_chain=False))
    on = describe_scene(cloud, lab)
    assert sorted(map(tuple, (o.planes for o in off.objects))) == \
        sorted(map(tuple, (o.planes for o in on.objects)))
    treads = _treads(off, objs)
    top = max(treads, key=lambda k: off.planes.by_label(k).height)
    assert len(_holding(on, min(treads, key=lambda k: off.planes.by_label(k).height))) >= 3
    assert top not in _holding(on, min(treads, key=lambda k: off.planes.by_label(k).height))


def test_step_cut_chain_validated():
    with pytest.raises(InputError):
        ProposalParams(step_cut_chain=1)
