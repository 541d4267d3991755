"""A box seen from a camera near the floor (low42, docs/objects.md "A face whose foot the
floor's segmentation does not reach"): the floor, seen at a grazing angle, is segmented only
nearer than the box, so no horizontal plane is adjacent to its face; ``tall_face/1`` then asks
that the face's foot be level with the floor plane's fit (:func:`floor_foot`), the rows under
its lowest pixel show that floor or nothing measured, and its pixels fill its rows (a solid
face).

Rendered analytic scenes (640x480, the camera 0.15 m over the floor looking level); the
floor's pixels farther than ``CUT`` m are taken out of its plane (unlabelled, or not measured
at all) as the region grower leaves the grazing floor."""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import Rect, box, floor, render

from planerel.errors import InputError
from planerel.features.planes import measure_planes
from planerel.features.relations import RelationParams, relate, tall_faces
from planerel.io.cloud import Cloud

#: the camera 0.15 m over the floor, looking level (dev_low's 0.1-0.3 m)
VIEW = {"pitch": 0.0, "cam_height": 0.15, "width": 640, "height": 480}
#: m: the floor's plane ends this far from the camera (the box stands at 2 m)
CUT = 1.5


def _cut_floor(rects, missing=False):
    """Render ``rects`` (the floor first) and take the floor's pixels farther than ``CUT``
    out of its plane: unlabelled, and with ``missing`` not measured either."""
    cloud, lab, _, _ = render(rects, noise=0.0012, **VIEW)
    xyz = np.array(cloud.xyz, float)
    far = (lab == 0) & (np.linalg.norm(xyz, axis=-1) > CUT)
    lab = lab.copy()
    lab[far] = -1
    if missing:
        xyz[far] = np.nan
    return Cloud(xyz, cloud.intrinsics, cloud.up, "analytic"), lab


def _tall(cloud, lab, params=None):
    ps = measure_planes(cloud, lab)
    return ps, tall_faces(ps, relate(ps, cloud, params), cloud)


def _box_front():
    # a 0.6 x 0.4 x 0.5 m box 2 m away: its front (label 2) rises 0.35 m over the eye
    return [floor()] + box(0.0, 2.0, 0.6, 0.4, 0.5)


@pytest.mark.parametrize("missing", [False, True])
def test_a_box_whose_foot_the_floor_plane_does_not_reach_is_a_tall_face(missing):
    cloud, lab = _cut_floor(_box_front(), missing)
    ps, tall = _tall(cloud, lab)
    assert ps.floor == 0 and ps.by_label(2).orientation == "vertical"
    assert tall == {2}
    # without the floor's fit (before low42) it stands on nothing
    assert not _tall(cloud, lab, RelationParams(tall_floor_fit=0.0))[1]


def test_the_uncut_floor_grounds_the_face_as_before():
    cloud, lab, _, _ = render(_box_front(), noise=0.0012, **VIEW)
    ps = measure_planes(cloud, lab)
    assert tall_faces(ps, relate(ps, cloud, RelationParams(tall_floor_fit=0.0)), cloud) == {2}


def test_a_chair_back_over_the_cut_floor_stands_on_nothing():
    # a chair's back 0.45-0.9 m up and its seat behind it: its foot 0.45 m over the floor fit
    back = Rect((0.0, 2.0, 0.675), (1, 0, 0), (0, 0, 1), 0.22, 0.225, 1)
    seat = Rect((0.0, 2.22, 0.45), (1, 0, 0), (0, 1, 0), 0.22, 0.22, 1)
    cloud, lab = _cut_floor([floor(), back, seat])
    ps, tall = _tall(cloud, lab)
    assert ps.by_label(1).orientation == "vertical" and not tall


def test_a_face_that_does_not_fill_its_rows_is_no_tall_face():
    # the box's front cut into 0.05 m bands, every other one unlabelled: a table's legs that
    # the region grower took as one plane fill 0.2 of their rows
    cloud, lab = _cut_floor(_box_front())
    xyz = np.asarray(cloud.xyz)
    bands = (lab == 2) & (np.floor(xyz[..., 0] / 0.05) % 2 == 0)
    lab = lab.copy()
    lab[bands] = -1
    ps, tall = _tall(cloud, lab)
    assert 2 in {p.label for p in ps} and not tall
    assert _tall(cloud, lab, RelationParams(tall_floor_solid=0.0))[1] == {2}


def test_a_face_behind_a_low_block_shows_the_block_under_it():
    # a solid block 0.1 m high right in front of the box, unlabelled (no plane): the box's
    # front shows from 0.1 m up; with the fit's tolerance relaxed to 0.2 m, the rows under
    # its lowest pixel show the block's top 0.1 m over the floor, not the floor
    rects = _box_front()
    block = box(0.0, 1.7, 0.8, 0.2, 0.1, obj=2)
    cloud, lab = _cut_floor(rects + block)
    lab = lab.copy()
    lab[lab >= len(rects)] = -1
    ps, tall = _tall(cloud, lab, RelationParams(tall_floor_fit=0.2))
    assert 2 in {p.label for p in ps} and not tall
    assert _tall(cloud, lab, RelationParams(tall_floor_fit=0.2, tall_floor_share=0.0))[1] == {2}


def test_the_shares_are_shares():
    for name in ("tall_floor_share", "tall_floor_solid"):
        with pytest.raises(InputError):
            RelationParams(**{name: 1.5})
