"""The wall test of the support planes (:mod:`planerel.features.walls`, issue 16).

A solid staircase's side face is a vertical plane as large as a wall (3 m^2 for 10 steps);
taken for a wall it is dropped and cuts the flight apart.  Its top edge follows the steps; a
wall reaches above what stands against it.  Scenes are ray-cast from rectangles
(tests/scenes_analytic.py), labelled with their true planes.
"""

from __future__ import annotations

import numpy as np
from scenes_analytic import Rect, floor, render, stairs, wall

from planerel.features.facts import describe_scene
from planerel.features.relations import ProposalParams
from planerel.features.walls import side_caps

VIEW = dict(pitch=15, cam_height=1.0, width=320, height=240, noise=0.001)
N, RISE, RUN, WIDTH, CX, Y0 = 10, 0.17, 0.28, 1.0, -0.9, 1.6


def _side_face(obj=1):
    """The +x side of the flight of :func:`stairs`: one rectangle per step, floor to tread."""
    x = CX + WIDTH / 2
    return [Rect((x, Y0 + (k + 0.5) * RUN, (k + 1) * RISE / 2), (0, 1, 0), (0, 0, 1),
                 RUN / 2, (k + 1) * RISE / 2, obj) for k in range(N)]


def _scene(extra, **view):
    """Floor, the flight and ``extra`` rectangles; the side rectangles share one label."""
    rects = [floor(size=10.0)] + stairs(CX, Y0, N, RISE, RUN, WIDTH) + extra
    cloud, lab, _up, objs = render(rects, **{**VIEW, **view})
    first = 1 + 2 * N  # the side face's rectangles come right after the flight's
    side = np.isin(lab, range(first, first + len(extra)))
    lab = np.where(side, first, lab)
    _, lab = np.unique(lab, return_inverse=True)
    lab = lab.reshape(side.shape).astype(np.int32) - 1  # -1 stays unassigned
    return cloud, lab, side


def _best_iou(d, truth):
    best = 0.0
    for o in d.objects:
        m = np.isin(d.labels, list(o.planes))
        best = max(best, (m & truth).sum() / max((m | truth).sum(), 1))
    return best


def _label_of(lab, mask):
    vals, counts = np.unique(lab[mask], return_counts=True)
    return int(vals[counts.argmax()])


def test_staircase_side_face_is_no_wall():
    cloud, lab, side = _scene(_side_face())
    face = _label_of(lab, side)
    d = describe_scene(cloud, lab)
    p = next(q for q in d.planes if q.label == face)
    assert p.orientation == "vertical" and p.area >= ProposalParams().support_min_area
    flight = (lab >= 1)  # every plane but the floor (label 0)
    assert face not in d.support
    assert _best_iou(d, flight) >= 0.9
    old = describe_scene(cloud, lab, proposal_params=ProposalParams(wall_test=False))
    assert face in old.support and _best_iou(old, flight) < 0.9


def test_side_face_top_follows_the_steps():
    cloud, lab, side = _scene(_side_face())
    d = describe_scene(cloud, lab)
    face = next(q for q in d.planes if q.label == _label_of(lab, side))
    steps = [q for q in d.planes if q.label not in (0, face.label)]
    caps = [c for c in side_caps(face, steps, d.planes.up, cloud.xyz, d.labels) if c[2]]
    assert len(caps) >= 4
    assert all(above <= 0.10 for above, _top, _ in caps)  # never higher than a step it meets


def test_side_wall_of_a_flight_stays_support():
    # a wall along the flight's far side, 0.9 m above its top tread, touches every step
    x = CX - WIDTH / 2
    h = N * RISE + 0.9
    side_wall = Rect((x, Y0 + N * RUN / 2, h / 2), (0, 1, 0), (0, 0, 1), N * RUN / 2 + 0.2, h / 2)
    cloud, lab, side = _scene([side_wall], pitch=30, cam_height=2.6)
    d = describe_scene(cloud, lab)
    face = next(q for q in d.planes if q.label == _label_of(lab, side))
    steps = [q for q in d.planes if q.label not in (0, face.label)
             and d.relations.get(face.label, q.label).adjacent]
    assert len(steps) >= 10  # every step touches it ...
    # ... but its top is out of view above each of them: undecided, so it stays a wall
    assert not any(c[2] for c in side_caps(face, steps, d.planes.up, cloud.xyz, d.labels))
    assert face.label in d.support


def test_wall_behind_boxes_stays_support():
    # two boxes of different heights against a wall whose top is in view: their faces are
    # two heights 0.3 m apart, but the wall rises 0.4 m above the taller one
    from scenes_analytic import box

    rects = [floor(), wall(y=2.5, h=1.1)] + box(-0.5, 2.25, 0.6, 0.5, 0.4, obj=1) + box(0.5, 2.25, 0.6, 0.5, 0.7, obj=2)
    cloud, lab, _up, objs = render(rects, pitch=20, cam_height=1.2, width=320, height=240, noise=0.001)
    d = describe_scene(cloud, lab)
    w = next(q for q in d.planes if q.label == 1)
    assert w.area >= ProposalParams().support_min_area
    nbrs = [q for q in d.planes if q.label > 1 and d.relations.get(1, q.label).adjacent]
    caps = [c for c in side_caps(w, nbrs, d.planes.up, cloud.xyz, d.labels) if c[2]]
    assert len(caps) >= 2 and min(above for above, _t, _ in caps) > 0.3
    assert 1 in d.support  # the wall
    for obj in (1, 2):
        truth = np.isin(lab, [k for k, o in enumerate(objs) if o == obj])
        assert _best_iou(d, truth) >= 0.9


def _ramp_scene(side_height=None, strips=24, angle=15.0, length=4.5, cx=-1.2, y0=1.4, **view):
    """Floor, a ramp rising away from the camera and its +x side face: vertical strips from
    the floor to the slope (``side_height`` None), or a wall of that height along the side.
    The side's rectangles share one label."""
    from scenes_analytic import ramp

    a = np.radians(angle)
    run, x = length * np.cos(a), cx + 0.5
    if side_height is None:
        dy = run / strips
        side = [Rect((x, y0 + (k + 0.5) * dy, (k + 0.5) * dy * np.tan(a) / 2), (0, 1, 0), (0, 0, 1),
                     dy / 2, (k + 0.5) * dy * np.tan(a) / 2, 1) for k in range(strips)]
    else:
        side = [Rect((x, y0 + run / 2, side_height / 2), (0, 1, 0), (0, 0, 1), run / 2 + 0.2,
                     side_height / 2)]
    rects = [floor(size=12.0)] + ramp(cx, y0, angle, length, 1.0) + side
    cloud, lab, _up, _objs = render(rects, **{**VIEW, "pitch": 20, "cam_height": 1.6, **view})
    first = 2  # floor 0, slope 1, then the side
    is_side = np.isin(lab, range(first, first + len(side)))
    lab = np.where(is_side, first, lab).astype(np.int32)
    return cloud, lab, is_side


def test_ramp_side_face_is_no_wall():
    # a 4.5 m ramp of 15 degrees: its solid side face (2.4 m^2) follows the slope
    cloud, lab, side = _ramp_scene()
    d = describe_scene(cloud, lab)
    face = next(q for q in d.planes if q.label == _label_of(lab, side))
    slope = next(q for q in d.planes if q.label == 1)
    assert face.orientation == "vertical" and face.area >= ProposalParams().support_min_area
    assert slope.orientation == "inclined"
    caps = [c for c in side_caps(face, [slope], d.planes.up, cloud.xyz, d.labels) if c[2]]
    assert len(caps) >= 2 and all(above <= 0.10 for above, _t, _ in caps)
    assert max(t for _a, t, _ in caps) - min(t for _a, t, _ in caps) >= 0.08  # it rises
    assert face.label not in d.support
    ramp_px = lab >= 1
    assert _best_iou(d, ramp_px) >= 0.9
    old = describe_scene(cloud, lab, proposal_params=ProposalParams(wall_test=False,
                                                                    wedge_side_max=0.0))
    assert face.label in old.support and _best_iou(old, ramp_px) < 0.9
    # the wedge-side test (wedge96) alone keeps it too: its top edge rises straight at 15
    # degrees and the face lies under it
    wedge = describe_scene(cloud, lab, proposal_params=ProposalParams(wall_test=False))
    assert face.label not in wedge.support


def test_wall_beside_a_ramp_stays_support():
    # a 1.6 m wall along the ramp's side rises above the slope everywhere
    cloud, lab, side = _ramp_scene(side_height=1.6)
    d = describe_scene(cloud, lab)
    face = next(q for q in d.planes if q.label == _label_of(lab, side))
    assert face.area >= ProposalParams().support_min_area
    assert face.label in d.support
