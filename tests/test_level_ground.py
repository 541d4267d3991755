"""A face standing on level ground that no plane took (ground75, docs/objects.md "A box on a
floor no plane took").

A level view of a carton 1-2 m away on a dark or speckled floor: the sensor measures the floor
in front of the carton, but the region grower makes no plane of it, so no horizontal plane is
adjacent to the carton's face and no floor plane exists to extrapolate.  ``tall_face/1`` then
asks :func:`planerel.features.tall_face.level_ground`: the points under the face's foot lie
level with it and reach ``tall_level_ground`` (0.45 m) nearer to the sensor, the face's top is
in view, and the scan has no floor plane at all.

Scenes are ray-cast in code (tests/scenes_analytic.py, 640x480, a camera 0.4 m over the floor
looking level); the floor's pixels are measured but left out of every plane.
"""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import Rect, box, floor, render, wall

from planerel.errors import InputError
from planerel.features.planes import measure_planes
from planerel.features.relations import RelationParams, level_ground, relate, tall_faces
from planerel.features.solid import face_profile_of

VIEW = {"pitch": 0.0, "cam_height": 0.4, "width": 640, "height": 480}
#: the speckle floor off, so that only the new test can ground a face on the unplaned floor
NO_SPECKLE = {"tall_speckle_floor": 0.0}


def _unplaned(rects, keep_floor_within=None):
    """Render ``rects`` (the floor first) and take the floor's pixels out of every plane (all
    of them, or only those farther than ``keep_floor_within`` m)."""
    cloud, lab, _, _ = render(rects, noise=0.0012, **VIEW)
    lab = lab.copy()
    out = lab == 0
    if keep_floor_within is not None:
        out &= np.linalg.norm(np.asarray(cloud.xyz, float), axis=-1) > keep_floor_within
    lab[out] = -1
    return cloud, lab


def _tall(cloud, lab, **params):
    ps = measure_planes(cloud, lab)
    return ps, tall_faces(ps, relate(ps, cloud, RelationParams(**params)), cloud)


def _carton():
    # a carton 0.5 x 0.4 x 0.45 m 1.4 m ahead: its front (label 2) rises 5 cm over the eye
    return [floor()] + box(0.0, 1.6, 0.5, 0.4, 0.45)


def test_a_face_on_a_floor_no_plane_took_is_a_tall_face():
    cloud, lab = _unplaned(_carton())
    ps, tall = _tall(cloud, lab, **NO_SPECKLE)
    assert ps.floor is None and ps.by_label(2).orientation == "vertical"
    assert tall == {2}
    # off (before ground75): it stands on nothing
    assert not _tall(cloud, lab, tall_level_ground=0.0, **NO_SPECKLE)[1]
    # and with the defaults (the speckle floor on) it stands too
    assert _tall(cloud, lab)[1] == {2}


def test_a_face_on_a_ledge_shallower_than_the_reach_stands_on_nothing():
    # the carton's front stands on a ledge 0.3 m deep and 0.17 m high (a tread), the ledge's
    # top no plane: the level ground in front of the face ends after 0.3 m, short of 0.45
    ledge_top = Rect((0.0, 1.25, 0.17), (1, 0, 0), (0, 1, 0), 0.4, 0.15)
    ledge_front = Rect((0.0, 1.1, 0.085), (1, 0, 0), (0, 0, 1), 0.4, 0.085)
    carton = box(0.0, 1.6, 0.5, 0.4, 0.45)
    carton = [Rect((r.center[0], r.center[1], r.center[2] + 0.17), r.e1, r.e2, r.a, r.b, r.obj)
              for r in carton]
    rects = [floor(), *carton, ledge_top, ledge_front]
    cloud, lab = _unplaned(rects)
    lab[lab == 6] = -1  # the ledge's top: no plane
    ps, tall = _tall(cloud, lab, **NO_SPECKLE)
    assert ps.by_label(2).orientation == "vertical"
    assert 2 not in tall
    # a shorter reach takes the ledge for ground
    assert 2 in _tall(cloud, lab, tall_level_ground=0.25, **NO_SPECKLE)[1]


def test_a_panel_over_open_space_stands_on_nothing():
    # a table's apron 0.5 m wide and 0.12 m high, its foot 0.55 m over the floor
    apron = Rect((0.0, 1.5, 0.61), (1, 0, 0), (0, 0, 1), 0.25, 0.06, 1)
    cloud, lab = _unplaned([floor(), apron])
    ps, tall = _tall(cloud, lab, **NO_SPECKLE)
    assert ps.by_label(1).orientation == "vertical" and not tall


def test_a_wall_rising_out_of_view_is_no_tall_face_by_it():
    # a wall 1 m wide 2 m ahead rising 1.5 m: its top is out of the image (which shows 1.2 m
    # up there); without the limit it would stand on the unplaned floor
    cloud, lab = _unplaned([floor(), wall(y=2.0, w=1.0, h=1.5)])
    ps, tall = _tall(cloud, lab, **NO_SPECKLE)
    face = ps.by_label(1)
    assert face.orientation == "vertical" and not tall
    prof = face_profile_of(face, ps.up, ps.labels, cloud.xyz)
    assert not level_ground(face, prof, ps.labels, cloud.xyz, ps.up, RelationParams())


def test_with_a_floor_plane_the_floor_judges_and_not_the_level_ground():
    # the floor's plane ends 1.3 m from the camera; its fit's own test (floor_foot) switched
    # off, the face would stand only on the unplaned floor beyond, which is not asked then
    cloud, lab = _unplaned(_carton(), keep_floor_within=1.3)
    ps, tall = _tall(cloud, lab, tall_floor_fit=0.0, **NO_SPECKLE)
    assert ps.floor == 0 and 2 not in tall
    face = ps.by_label(2)
    prof = face_profile_of(face, ps.up, ps.labels, cloud.xyz)
    assert level_ground(face, prof, ps.labels, cloud.xyz, ps.up, RelationParams())


def test_a_negative_reach_is_refused():
    with pytest.raises(InputError, match="tall_level_ground"):
        RelationParams(tall_level_ground=-0.1)


def _hunt45(name):
    """A hunt45 R200 frame (``$PLANEREL_HUNT_DATA/hunt45/mbot``): ``(cloud, labels, frame)``."""
    import json
    import os
    from pathlib import Path

    import planerel
    from planerel.segment import segment

    folder = Path(os.environ.get("PLANEREL_HUNT_DATA", "/nonexistent")) / "hunt45" / "mbot"
    if not (folder / "labels.json").is_file():
        pytest.skip(f"no frames in {folder} (set PLANEREL_HUNT_DATA)")
    fr = next(f for f in json.loads((folder / "labels.json").read_text())["frames"]
              if f["file"] == name)
    cloud = planerel.read(str(folder / fr["file"]), intrinsics=fr["intrinsics"],
                          depth_scale=fr["depth_scale"])
    return cloud, segment(cloud).labels, fr


def _tall_in(desc, rect):
    """The tall faces of ``desc`` with most of their pixels inside the image rectangle
    ``rect`` ``[c0, r0, c1, r1]``."""
    c0, r0, c1, r1 = rect
    lab = np.asarray(desc.labels)
    inside = np.zeros(lab.shape, bool)
    inside[r0:r1 + 1, c0:c1 + 1] = True
    return {t for t in desc.tall if (inside & (lab == t)).sum() > 0.5 * (lab == t).sum()}


def test_real_r200_carton_on_a_speckled_floor_stands_and_a_wall_over_one_does_not():
    """hunt45's R200 0.3 m over a floor it measures as speckle: the carton under the table
    (r200_dc0_165951, 1.23 m) has no floor plane to stand on, and its face is a tall face on
    the ground in front of it; the wall of r200_mar_145124 rises out of view over such a
    floor and is none."""
    from planerel.features.facts import describe_scene

    cloud, labels, fr = _hunt45("r200_dc0_165951_depth.png")
    rect = fr["objects"][0]["box"]
    desc = describe_scene(cloud, labels)
    assert desc.planes.floor is None
    assert _tall_in(desc, rect)
    off = describe_scene(cloud, labels, relation_params=RelationParams(tall_level_ground=0.0))
    assert not _tall_in(off, rect)
    cloud, labels, _ = _hunt45("r200_mar_145124_depth.png")
    assert not describe_scene(cloud, labels).tall
