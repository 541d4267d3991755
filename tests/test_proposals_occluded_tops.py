"""Pieces of one box top seen on both sides of something nearer (issue 22, occl22):
``occluded_piece_pairs`` with ``flat`` (horizontal and inclined pieces) and ``near`` (hulls
within the relations' adjacency gap), tested against the plane through both pieces
(``plane_between``).

Scenes are ray-cast rectangles with one label each (tests/scenes_analytic.py): a box whose top
is two rectangles with a slot under a bar lying across it, or with a plate standing in front
of it; two boxes of one height side by side.
"""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import Rect, box, floor, render

from planerel.errors import InputError
from planerel.features.facts import describe_scene
from planerel.features.gaps import occluded_piece_pairs, plane_between
from planerel.features.relations import ProposalParams

VIEW = dict(pitch=35, cam_height=1.0, width=320, height=240, noise=0.001)
CX, CY, SX, SY, SZ = 0.0, 1.3, 0.40, 0.40, 0.25


def _run(rects, params=None):
    cloud, lab, _up, objs = render(rects, **VIEW)
    d = describe_scene(cloud, lab, proposal_params=params)
    seen: dict = {}
    for p in d.planes:
        seen.setdefault(objs[p.label], set()).add(p.label)
    return [set(o.planes) for o in d.objects], seen, d, cloud


def _against_top(d, cloud, a=1, b=2):
    """plane_between of planes a and b against a's plane."""
    pa = next(p for p in d.planes if p.label == a)
    return plane_between(d.labels, cloud.xyz, a, b, pa.normal, pa.centroid)


def _box_top_front_back(slot: float) -> list:
    """A box standing on the floor (object 1) whose top is two rectangles ``slot`` metres
    apart (its front and back halves), then its four sides."""
    half = (SY - slot) / 2
    top = [Rect((CX, CY - slot / 2 - half / 2, SZ), (1, 0, 0), (0, 1, 0), SX / 2, half / 2, 1),
           Rect((CX, CY + slot / 2 + half / 2, SZ), (1, 0, 0), (0, 1, 0), SX / 2, half / 2, 1)]
    return top + box(CX, CY, SX, SY, SZ, 1)[1:]


def _bar(depth: float, height: float = 0.06) -> list:
    """A bar (object 2) lying across the box's top, longer than the box is wide, over its
    slot: its top and its front face."""
    return [Rect((CX, CY, SZ + height), (1, 0, 0), (0, 1, 0), SX / 2 + 0.1, depth / 2, 2),
            Rect((CX, CY - depth / 2, SZ + height / 2), (1, 0, 0), (0, 0, 1), SX / 2 + 0.1,
                 height / 2, 2)]


def _box_left_right(plate: bool) -> list:
    """A box (object 1) whose top and front face are each two rectangles meeting at x = 0,
    then its other sides, and (``plate``) a plate 3 cm wide standing on the floor 5 cm in
    front of it (object 2), which hides a band of both."""
    a = SX / 4
    rects = [Rect((CX + sx * a, CY, SZ), (1, 0, 0), (0, 1, 0), a, SY / 2, 1) for sx in (-1, 1)]
    rects += [Rect((CX + sx * a, CY - SY / 2, SZ / 2), (1, 0, 0), (0, 0, 1), a, SZ / 2, 1)
              for sx in (-1, 1)]
    rects += box(CX, CY, SX, SY, SZ, 1)[2:]
    if plate:
        rects.append(Rect((CX, CY - SY / 2 - 0.05, 0.25), (1, 0, 0), (0, 0, 1), 0.015, 0.25, 2))
    return rects


def test_box_top_on_both_sides_of_a_bar_lying_across_it_is_one_proposal():
    # the top's two pieces lie in one plane; the bar (6 cm high) hides the slot and a band
    # behind it: their hulls lie 17-20 cm apart, beyond the relations' adjacency
    rects = [floor()] + _box_top_front_back(0.08) + _bar(0.11)
    props, seen, d, cloud = _run(rects)
    assert {1, 2} <= seen[1] and seen[1] in props
    r = d.relations.get(1, 2)
    assert not r.adjacent and r.gap > 0.1
    assert occluded_piece_pairs(d.planes, d.relations, d.labels, cloud.xyz, d.support,
                                flat=True, near=True) == {(1, 2)}
    # every pixel between them lies in front of the top's plane, but for the bar's base on it
    assert _against_top(d, cloud) == (1.0, 0.0)
    # vertical pieces only (the rule before occl22): two proposals
    apart, _, _, _ = _run(rects, ProposalParams(occluded_flat=False))
    assert not any({1, 2} <= p for p in apart)


def test_box_seen_on_both_sides_of_a_plate_in_front_is_one_proposal():
    # the plate hides a band 3-4 cm wide: the halves' hulls come within the adjacency gap
    # (adjacent, but sharing no edge and farther apart than apart_gap: cut); the near rule
    # joins them (mOSD test25)
    rects = [floor()] + _box_left_right(plate=True)
    props, seen, d, cloud = _run(rects)
    r = d.relations.get(1, 2)
    assert r.adjacent and not r.touching and 0.02 < r.gap <= 0.05
    assert seen[1] in props
    assert _against_top(d, cloud) == (1.0, 0.0)
    apart, _, _, _ = _run(rects, ProposalParams(occluded_near=False))
    assert {1, 3} in apart and {2, 4} in apart


@pytest.mark.parametrize("gap", [0.08, 0.035])
def test_two_boxes_of_one_height_with_the_floor_between_stay_apart(gap):
    # two boxes side by side, their tops in one plane 8 cm or 3.5 cm apart: the floor seen
    # between them lies behind that plane
    w = 0.30
    rects = [floor()] + box(-(gap / 2 + w / 2), CY, w, SY, SZ, 1) + box(gap / 2 + w / 2, CY, w, SY, SZ, 2)
    props, seen, d, cloud = _run(rects)
    assert not any(p & seen[1] and p & seen[2] for p in props)
    assert occluded_piece_pairs(d.planes, d.relations, d.labels, cloud.xyz, d.support,
                                flat=True, near=True) == set()
    front, behind = _against_top(d, cloud, 1, 6)
    assert behind > 0.5 and front == 0.0


@pytest.mark.parametrize("step, joined", [(0.01, True), (0.025, False)])
def test_top_pieces_at_two_heights_are_not_joined(step, joined):
    # the back piece 1 cm higher than the front one: one top within the noise; 2.5 cm higher:
    # a step, not one top, within the vertical pieces' coplanar_depth (3 cm at 1 m) but
    # beyond the flat rule's piece_depth (2 cm at 1 m; the pieces lie 1.4-1.6 m away)
    rects = [floor()] + _box_top_front_back(0.08) + _bar(0.11)
    r = rects[2]
    rects[2] = Rect((r.center[0], r.center[1], r.center[2] + step), r.e1, r.e2, r.a, r.b, r.obj)
    _, _, d, cloud = _run(rects)
    pairs = occluded_piece_pairs(d.planes, d.relations, d.labels, cloud.xyz, d.support,
                                 flat=True, near=True)
    assert ((1, 2) in pairs) == joined


def test_plane_between_sorts_pixels_against_the_plane():
    # one row: label 0, five pixels between, label 1, on the plane z = 2 seen head-on; the
    # pixels between lie on it, 0.5 m in front of it or 0.5 m behind it (the pixel next to
    # each end left out: 3 counted)
    lab = np.array([[0, -1, -1, -1, -1, -1, 1]])
    for z_mid, front, behind in ((2.0, 0.0, 0.0), (1.5, 1.0, 0.0), (2.5, 0.0, 1.0)):
        z = np.array([[2.0] + [z_mid] * 5 + [2.0]])
        xyz = np.stack([np.zeros_like(z), np.zeros_like(z), z], axis=-1)
        assert plane_between(lab, xyz, 0, 1, (0, 0, 1.0), (0, 0, 2.0)) == (front, behind)
    # the pixels next to the ends only on the plane (an occluder's base): still all in front
    z = np.array([[2.0, 2.0, 1.5, 1.5, 1.5, 2.0, 2.0]])
    xyz = np.stack([np.zeros_like(z), np.zeros_like(z), z], axis=-1)
    assert plane_between(lab, xyz, 0, 1, (0, 0, 1.0), (0, 0, 2.0)) == (1.0, 0.0)
    assert plane_between(lab, xyz, 0, 1, (0, 0, 1.0), (0, 0, 2.0), skip_ends=False) == (0.6, 0.0)
    z = np.array([[2.0] + [np.nan] * 5 + [2.0]])
    xyz = np.stack([np.zeros_like(z), np.zeros_like(z), z], axis=-1)
    assert plane_between(lab, xyz, 0, 1, (0, 0, 1.0), (0, 0, 2.0)) is None


def test_piece_depth_must_not_be_negative():
    with pytest.raises(InputError):
        ProposalParams(piece_depth=-0.01)
