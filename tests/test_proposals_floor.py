"""Objects lying on the floor, 1-2 cm up (issue 22): open boxes, plates, laptops' bases.

Scenes are ray-cast from rectangles (tests/scenes_analytic.py).  Two cases of what the
segmentation makes of such an object's low face, both seen in the varied world's cluttered
scenes: a plane of its own at floor level (then :func:`support_planes` must not take it for a
piece of the floor: ``ProposalParams.floor_gap``), or pixels joined to the floor plane (then
:mod:`planerel.features.raised` finds them above it).
"""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import Rect, camera_rotation, floor, render

from planerel.errors import InputError
from planerel.features.facts import describe_scene
from planerel.features.raised import RaisedParams, raised_clusters
from planerel.features.relations import ProposalParams, support_planes
from planerel.io.cloud import Cloud

VIEW = dict(pitch=45, cam_height=1.2, width=320, height=240)


def _open_box(cx=0.0, cy=1.4, sx=0.5, sy=0.4, sz=0.15, bottom=0.01, obj=1):
    """An open box: its bottom ``bottom`` m above the floor and four walls (no lid)."""
    return [
        Rect((cx, cy, bottom), (1, 0, 0), (0, 1, 0), sx / 2, sy / 2, obj),
        Rect((cx, cy - sy / 2, sz / 2), (1, 0, 0), (0, 0, 1), sx / 2, sz / 2, obj),
        Rect((cx, cy + sy / 2, sz / 2), (1, 0, 0), (0, 0, 1), sx / 2, sz / 2, obj),
        Rect((cx - sx / 2, cy, sz / 2), (0, 1, 0), (0, 0, 1), sy / 2, sz / 2, obj),
        Rect((cx + sx / 2, cy, sz / 2), (0, 1, 0), (0, 0, 1), sy / 2, sz / 2, obj),
    ]


def _object_pixels(labels, objs, obj):
    return np.isin(labels, [k for k, o in enumerate(objs) if o == obj])


def _best_iou(d, truth):
    """Best pixel IoU of one of the described objects (planes plus mask) with ``truth``."""
    best = 0.0
    for o in d.objects:
        m = np.isin(d.labels, list(o.planes)) if o.planes else np.zeros_like(truth)
        if o.mask is not None:
            m = m | o.mask
        best = max(best, (m & truth).sum() / max((m | truth).sum(), 1))
    return best


def test_open_box_bottom_above_the_floor_is_no_support():
    # the bottom, 1 cm up, is a plane of its own at floor level: a floor piece lies on the
    # floor's plane, the bottom 1 cm above it, so it is not support and joins the walls
    cloud, lab, _up, objs = render([floor()] + _open_box(), noise=0.001, **VIEW)
    truth = _object_pixels(lab, objs, 1)
    d = describe_scene(cloud, lab)
    assert 1 not in d.support  # label 1: the bottom
    assert _best_iou(d, truth) >= 0.9
    # (open_walls False: synth22y's rule joins the near wall's outside and the far wall's inside)
    old = describe_scene(cloud, lab, proposal_params=ProposalParams(floor_gap=1.0, cavities=False,
                                                                   open_walls=False))
    assert 1 in old.support and _best_iou(old, truth) < 0.5  # the walls alone, cut apart
    # the concave cavities join the inner walls (channels, corners) without the bottom
    walls = describe_scene(cloud, lab, proposal_params=ProposalParams(floor_gap=1.0))
    assert 0.5 < _best_iou(walls, truth) < 0.9


def test_floor_pieces_stay_support():
    # the floor seen in two pieces (one label each, both on its plane) stays support
    rects = [Rect((-1.5, 3.0, 0), (1, 0, 0), (0, 1, 0), 1.5, 3.0), Rect((1.5, 3.0, 0), (1, 0, 0), (0, 1, 0), 1.5, 3.0)]
    cloud, lab, _up, _objs = render(rects, noise=0.001, **VIEW)
    d = describe_scene(cloud, lab)
    assert set(support_planes(d.planes)) == {0, 1}
    assert d.objects == ()


def test_open_box_bottom_in_the_floor_plane_is_found():
    # region growing joined the bottom to the floor: its pixels are found 1 cm above the
    # floor's plane and join the walls they touch
    cloud, lab, _up, objs = render([floor()] + _open_box(), noise=0.001, **VIEW)
    truth = _object_pixels(lab, objs, 1)
    lab = np.where(lab == 1, 0, lab)
    d = describe_scene(cloud, lab)
    assert 0 in d.support
    assert _best_iou(d, truth) >= 0.8
    (box,) = [o for o in d.objects if o.mask is not None]
    assert set(box.planes) == {k for k in np.unique(lab[truth]) if k >= 2}  # all walls seen
    assert not box.curved  # the bottom counts as flat
    old = describe_scene(cloud, lab, proposal_params=ProposalParams(raised_objects=False, cavities=False,
                                                                   open_walls=False))
    assert _best_iou(old, truth) < 0.5


def test_plate_in_the_floor_plane_is_an_object_of_its_own():
    plate = Rect((0.3, 1.6, 0.02), (1, 0, 0), (0, 1, 0), 0.12, 0.12, 1)
    cloud, lab, _up, objs = render([floor(), plate], noise=0.002, **VIEW)
    truth = lab == 1
    lab = np.where(truth, 0, lab)
    d = describe_scene(cloud, lab)
    assert _best_iou(d, truth) >= 0.7
    (obj,) = d.objects
    assert obj.planes == () and obj.planar_fraction == 1.0


def test_a_bend_of_the_floor_is_no_object_a_step_is():
    # a floor bent up 8 mm over half a metre (a sensor's depth distortion) lifts the ring around
    # the raised pixels as much as them: no group; a plate 8 mm high ends at a step: a group
    cloud, lab, up, _objs = render([floor()], noise=0.001, **VIEW)
    d = describe_scene(cloud, lab)
    xyz = np.array(cloud.xyz)
    # world x, y of each point (camera frame -> world: the floor is z = 0)
    world = xyz @ camera_rotation(45, 0).T + np.array([0.0, 0.0, 1.2])
    r2 = (world[..., 0] - 0.2) ** 2 + (world[..., 1] - 1.6) ** 2
    bump = 0.008 * np.exp(-r2 / (2 * 0.25 ** 2))
    bent = Cloud(xyz + bump[..., None] * up, cloud.intrinsics, up, "analytic")
    assert raised_clusters(bent, lab, d.planes, d.support) == []
    step = Cloud(xyz + np.where(r2 < 0.15 ** 2, 0.008, 0.0)[..., None] * up, cloud.intrinsics,
                 up, "analytic")
    groups = raised_clusters(step, lab, d.planes, d.support)
    assert len(groups) == 1
    disc = r2 < 0.15 ** 2
    assert (groups[0] & disc).sum() / (groups[0] | disc).sum() >= 0.7


def test_raised_params_are_checked():
    with pytest.raises(InputError):
        RaisedParams(min_rise=-1)
    with pytest.raises(InputError):
        RaisedParams(smooth_px=1.5)
    with pytest.raises(InputError):
        ProposalParams(floor_gap=-0.1)
