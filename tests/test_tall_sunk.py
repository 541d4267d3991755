"""A wall's end past a floor's edge is no ``tall_face`` (sunk79, ``tall_sunk``): the end face
of a side wall that goes on down past a landing's edge (a descending flight's side wall seen
from its landing) stands on the landing as a tall box's face would, top out of view, but
the wall's side meeting it at the corner reaches under the landing.  A solid standing on
that ground has its sides' feet there too.

Rendered analytic scenes (640x480, the camera 0.5 m over a landing ending 1.8 m ahead,
pitched 20 degrees down): a wall 0.1 m thick along the view at x 0.4-0.5 m, its end face
(label 1) 1.5 m ahead, its side (label 2) facing the camera's side."""

from __future__ import annotations

import pytest
from scenes_analytic import Rect, render

from planerel.errors import InputError
from planerel.features.planes import measure_planes
from planerel.features.relations import RelationParams, relate, tall_faces

VIEW = {"pitch": 20.0, "cam_height": 0.5, "width": 640, "height": 480}
ON = RelationParams()  # the default: tall_sunk 0.1
OFF = RelationParams(tall_sunk=0.0)


def _wall(bottom: float, top: float = 1.5):
    """The landing (label 0, y -1.0 to 1.8 m), the wall's end face (label 1, from the landing
    to ``top``) and its side (label 2, from ``bottom`` to ``top``, y 1.5-4.0 m)."""
    landing = Rect((0, 0.4, 0), (1, 0, 0), (0, 1, 0), 3.0, 1.4)
    end = Rect((0.45, 1.5, top / 2), (1, 0, 0), (0, 0, 1), 0.05, top / 2, 1)
    side = Rect((0.4, 2.75, (top + bottom) / 2), (0, 1, 0), (0, 0, 1), 1.25, (top - bottom) / 2, 1)
    return [landing, end, side]


def _tall(rects, params):
    cloud, lab, _, _ = render(rects, noise=0.0012, **VIEW)
    ps = measure_planes(cloud, lab)
    return ps, tall_faces(ps, relate(ps, cloud, params), cloud)


def test_a_wall_end_whose_side_goes_down_past_the_landing_is_no_tall_face():
    ps, tall = _tall(_wall(bottom=-1.5), ON)
    assert ps.by_label(1).orientation == "vertical" and ps.by_label(2).orientation == "vertical"
    assert 1 not in tall
    # off, the end face alone looks like a tall box's face standing on the landing
    assert 1 in _tall(_wall(bottom=-1.5), OFF)[1]


def test_a_pillar_whose_sides_stand_on_the_landing_stays_a_tall_face():
    # the same wall ending at the landing's level: its side's foot is the end face's
    ps, tall = _tall(_wall(bottom=0.0), ON)
    assert {1, 2} <= tall
    assert tall == _tall(_wall(bottom=0.0), OFF)[1]


def test_a_parallel_plane_under_the_face_does_not_refuse_it():
    # a box's front (label 3, 0.4 m wide, 0.4-1.4 m: its top over the eye) standing on a
    # shelf (label 1, its top at 0.4 m) 3 cm behind the shelf's lip (label 2, 0.2-0.4 m),
    # which reaches 0.2 m under the front's foot: parallel to it, so no wall's side
    floor = Rect((0, 2.0, 0), (1, 0, 0), (0, 1, 0), 3.0, 3.0)
    shelf = Rect((0, 1.9, 0.4), (1, 0, 0), (0, 1, 0), 1.0, 0.6)
    lip = Rect((0, 1.29, 0.3), (1, 0, 0), (0, 0, 1), 1.0, 0.1)
    front = Rect((0, 1.32, 0.9), (1, 0, 0), (0, 0, 1), 0.2, 0.5, 1)
    cloud, lab, _, _ = render([floor, shelf, lip, front], noise=0.0012, pitch=10.0,
                              cam_height=1.2, width=640, height=480)
    ps = measure_planes(cloud, lab)
    rel = relate(ps, cloud, ON)
    assert any(r.adjacent and {r.a, r.b} == {2, 3} for r in rel.pairs)
    assert 3 in tall_faces(ps, rel, cloud)


def test_the_bound_is_non_negative():
    with pytest.raises(InputError):
        RelationParams(tall_sunk=-0.1)
