"""tread44: a flight going down from the landing the camera stands on, its top tread cut by the
image's bottom edge (``ProposalParams.step_cut_top``; docs/results.md "Stairs from the top: the
cut top tread")."""

from __future__ import annotations

import pytest
from scenes_analytic import Rect, floor, render

from planerel.errors import InputError
from planerel.features.facts import describe_scene
from planerel.features.relations import ProposalParams

#: a landing 0.17 m in front of the camera's feet, eyes 1.2 m over it, pitched 48 degrees:
#: the landing is out of view, the bottom edge cuts the top tread (dev_st i0022's view)
VIEW = dict(pitch=48, cam_height=1.2 + 0.6, width=160, height=120, noise=0.001)


def _level(z, y0, y1, width, obj):
    return Rect((0.0, (y0 + y1) / 2, z), (1, 0, 0), (0, 1, 0), width / 2, (y1 - y0) / 2, obj)


def _face(z0, z1, y, width, obj):
    return Rect((0.0, y, (z0 + z1) / 2), (1, 0, 0), (0, 0, 1), width / 2, (z1 - z0) / 2, obj)


def _descending(rise=0.2, run=0.34, width=1.6, nose=0.17):
    """The landing (support, 3 rises up, ending at ``nose``), two treads (object 1) going down
    away from the camera with their risers (facing away, hidden) and the floor beyond."""
    top = 3 * rise
    rects = [floor(),
             _level(top, -1.0, nose, width + 1.0, -1),
             _level(2 * rise, nose, nose + run, width, 1),
             _level(rise, nose + run, nose + 2 * run, width, 1),
             _face(2 * rise, top, nose, width, 1),
             _face(rise, 2 * rise, nose + run, width, 1),
             _face(0.0, rise, nose + 2 * run, width, 1)]
    return render(rects, **VIEW)


def _treads(d, objs):
    return {p.label for p in d.planes if objs[p.label] == 1 and p.orientation == "horizontal"}


def test_two_treads_seen_from_the_landing_join():
    cloud, lab, _up, objs = _descending()
    treads = _treads(describe_scene(cloud, lab), objs)
    assert len(treads) == 2
    on = describe_scene(cloud, lab)
    assert any(treads <= set(o.planes) for o in on.objects)
    # before: the top tread, cut along its length by the bottom edge, was no member
    off = describe_scene(cloud, lab, proposal_params=ProposalParams(step_cut_top=False))
    assert not any(treads <= set(o.planes) for o in off.objects)


def _boxes(low_h, high_h, width, depth=0.3, gap=0.0, nose=0.17):
    """Two boxes, the higher one nearer the camera (its top cut by the bottom edge), the lower
    one ``gap`` behind it: their tops are level faces one rise apart, one beyond the other."""
    y0, y1 = nose, nose + depth
    y2, y3 = y1 + gap, y1 + gap + depth
    rects = [floor(),
             _level(0.6, -1.0, nose - 0.05, width + 1.0, -1),
             _level(high_h, y0, y1, width, 1), _face(0.0, high_h, y1, width, 1),
             _level(low_h, y2, y3, width, 2), _face(0.0, low_h, y3, width, 2),
             _face(0.0, low_h, y2, width, 2)]
    return render(rects, **VIEW)


@pytest.mark.parametrize("low_h, high_h, width, gap", [
    (0.30, 0.45, 0.9, 0.0),   # the floor two rises under the lower top: no third level
    (0.20, 0.40, 0.40, 0.0),  # cartons no wider than 1.5 times their depth
    (0.20, 0.40, 0.9, 0.35),  # floor seen between them: not edge to edge
])
def test_two_boxes_one_rise_apart_do_not_join(low_h, high_h, width, gap):
    cloud, lab, _up, objs = _boxes(low_h, high_h, width, gap=gap)
    d = describe_scene(cloud, lab)
    assert not any({objs[x] for x in o.planes} >= {1, 2} for o in d.objects)


def test_step_cut_top_validated():
    with pytest.raises(InputError):
        ProposalParams(step_cut_top=1)
