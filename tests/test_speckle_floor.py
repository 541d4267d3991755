"""A floor measured only as speckle (sparse49, docs/gravity.md "A floor seen only as speckle",
docs/objects.md "A floor seen only as speckle").

A camera 0.2 m over a floor sees it at grazing incidence: a structured-light or active-stereo
sensor returns a scattered few of its pixels (hunt45's R200 and Xtion robots: 2-30 % of the
image's bottom rows), no region grows over them and the floor is no plane.  The largest plane
is then a carton's face or a far wall, and the estimate takes it for the floor (88 degrees
off).  ``gravity.sparse_floor`` fits a plane to the unassigned points of the image's lower half
and lets it vote; ``relations.tall_speckle_floor`` lets it ground a face no floor plane grounds;
``relations.tall_top_cover`` refuses a face whose top edge a nearer surface covers (a wall's
lower part seen between a table's legs, under its top).

Scenes are ray-cast in code (tests/scenes_analytic.py, 640x480, the camera level 0.2 m over the
floor); the floor is thinned to speckle by dropping 90 % of its pixels (seeded).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scenes_analytic import Rect, box, floor, render, wall

from planerel.errors import InputError
from planerel.features.gravity import GravityParams, speckle_floor, up_from_cloud
from planerel.features.planes import measure_planes
from planerel.features.relations import RelationParams, relate, tall_faces
from planerel.io.cloud import Cloud

VIEW = {"pitch": 0.0, "cam_height": 0.2, "width": 640, "height": 480}


def _deg(a, b) -> float:
    return math.degrees(math.acos(max(-1.0, min(1.0, float(np.dot(a, b))))))


def _speckled(rects, keep=0.1, seed=3):
    """The rendered scene with its floor (rect 0) thinned to ``keep`` of its pixels, left
    unassigned: ``(cloud without up, labels, true up)``."""
    cloud, lab, up, _ = render(rects, noise=0.0012, **VIEW)
    rng = np.random.default_rng(seed)
    on_floor = lab == 0
    drop = on_floor & (rng.random(lab.shape) > keep)
    xyz = cloud.xyz.copy()
    xyz[drop] = np.nan
    lab = lab.copy()
    lab[on_floor] = -1
    return Cloud(xyz, cloud.intrinsics, None, "analytic"), lab, up


def _carton():
    # a carton's front 0.5 m wide and 0.35 m high, 1.2 m ahead (its top over the eye; label
    # 1), a cabinet front 1.6 x 1.2 m 3.5 m ahead (label 2) and the floor: what hunt45's R200 frame dc4 shows
    front = Rect((0.0, 1.2, 0.175), (1, 0, 0), (0, 0, 1), 0.25, 0.175, 1)
    return [floor(), front, wall(y=3.5, w=1.6, h=1.2)]


def test_a_speckle_floor_is_found_under_a_low_camera():
    cloud, lab, up = _speckled(_carton())
    found = speckle_floor(cloud, lab)
    assert found is not None
    normal, area, height, _, _ = found
    assert _deg(normal, up) < 2.0
    assert abs(height - 0.2) < 0.02
    assert area >= GravityParams().sparse_floor_area
    # off: nothing
    assert speckle_floor(cloud, lab, params=GravityParams(sparse_floor=0.0)) is None


def test_the_speckle_floor_rights_an_estimate_won_by_a_face():
    cloud, lab, up = _speckled(_carton())
    before = up_from_cloud(cloud, lab, GravityParams(sparse_floor=0.0))
    after = up_from_cloud(cloud, lab)
    # the face and the wall are the only planes: without the speckle the wall is read as the
    # floor under a camera looking straight down
    assert _deg(before.vector, up) > 60.0
    assert _deg(after.vector, up) < 3.0 and after.sparse_floor and not before.sparse_floor
    assert after.to_dict()["sparse_floor"] is True and "speckle" in after.describe()


def test_a_speckle_floor_the_estimate_agrees_with_changes_nothing():
    # a segmented floor and a wall: the estimate is right; the few unassigned floor points
    # fit the same floor and add nothing
    cloud, lab, up, _ = render([floor(), wall()], noise=0.0012, **VIEW)
    cloud = Cloud(cloud.xyz, cloud.intrinsics, None, "analytic")
    a = up_from_cloud(cloud, lab, GravityParams(sparse_floor=0.0))
    b = up_from_cloud(cloud, lab)
    assert np.allclose(a.vector, b.vector) and not b.sparse_floor


def test_no_speckle_floor_over_a_table_seen_from_above():
    # a camera 1.2 m up, pitched 40 degrees down over a table top at 0.75 m with a box on it:
    # no plane 0.35 m or less under the camera spans a floor's extent
    table = Rect((0.0, 1.5, 0.75), (1, 0, 0), (0, 1, 0), 0.6, 0.4)
    rects = [floor(), table] + box(0.0, 1.5, 0.2, 0.15, 0.1)
    cloud, lab, _, _ = render(rects, pitch=40.0, cam_height=1.2, width=640, height=480, noise=0.0012)
    lab = lab.copy()
    lab[lab == 0] = -1  # the floor unassigned
    assert speckle_floor(cloud, lab) is None


def test_a_face_on_a_speckle_floor_is_a_tall_face():
    cloud, lab, up = _speckled(_carton())
    cloud = Cloud(cloud.xyz, cloud.intrinsics, up, "analytic")
    ps = measure_planes(cloud, lab)
    assert ps.floor is None and ps.by_label(1).orientation == "vertical"
    # the level ground under its foot (ground75's level_ground) off, the speckle floor alone
    on = tall_faces(ps, relate(ps, cloud, RelationParams(tall_level_ground=0.0)), cloud)
    off = tall_faces(ps, relate(ps, cloud, RelationParams(tall_speckle_floor=0.0,
                                                          tall_level_ground=0.0)), cloud)
    assert 1 in on and 1 not in off
    # the speckle reaching in front of its foot grounds it too
    both = tall_faces(ps, relate(ps, cloud, RelationParams(tall_speckle_floor=0.0)), cloud)
    assert 1 in both


def test_a_wall_under_a_table_top_is_no_tall_face():
    # a wall 2 m ahead seen between a table's legs, under its top (0.7 m up, 1.2 m ahead,
    # 0.04 m thick: its front edge and underside, label 2): the wall's visible part is a
    # rectangle standing on the floor whose top the table covers
    top = Rect((0.0, 1.2, 0.7), (1, 0, 0), (0, 1, 0), 0.6, 0.4)
    edge = Rect((0.0, 0.8, 0.68), (1, 0, 0), (0, 0, 1), 0.6, 0.02)
    rects = [floor(), wall(y=2.0, w=1.0, h=2.5), top, edge]
    cloud, lab, up, _ = render(rects, noise=0.0012, **VIEW)
    ps = measure_planes(cloud, lab)
    assert ps.by_label(1).orientation == "vertical"
    on = tall_faces(ps, relate(ps, cloud, RelationParams()), cloud)
    off = tall_faces(ps, relate(ps, cloud, RelationParams(tall_top_cover=0.0)), cloud)
    assert 1 not in on and 1 in off


def test_a_carton_front_with_nothing_over_it_is_not_covered():
    cloud, lab, up, _ = render([floor(), wall(y=4.0)] + box(0.0, 1.4, 0.5, 0.3, 0.35),
                               noise=0.0012, **VIEW)
    ps = measure_planes(cloud, lab)
    assert 3 in tall_faces(ps, relate(ps, cloud, RelationParams()), cloud)


@pytest.mark.parametrize("name,value", [("sparse_floor", -0.1), ("sparse_floor_deg", 95.0),
                                        ("sparse_floor_tol", 0.0), ("sparse_floor_share", 1.5),
                                        ("sparse_floor_min", -0.01), ("sparse_floor_reach", -1.0),
                                        ("sparse_floor_area", -1.0)])
def test_the_gravity_settings_are_checked(name, value):
    with pytest.raises(InputError):
        GravityParams(**{name: value})


@pytest.mark.parametrize("name", ["tall_speckle_floor", "tall_top_cover"])
def test_the_relation_settings_are_checked(name):
    with pytest.raises(InputError):
        RelationParams(**{name: -0.1})


def test_the_gravity_settings_reach_the_speckle_floor_under_a_face():
    # ``--param gravity.sparse_floor_area=...`` bounds the floor that grounds a tall face too
    cloud, lab, up = _speckled(_carton())
    cloud = Cloud(cloud.xyz, cloud.intrinsics, up, "analytic")
    ps = measure_planes(cloud, lab)
    rel = relate(ps, cloud, RelationParams(tall_level_ground=0.0))  # the speckle floor alone
    assert 1 in tall_faces(ps, rel, cloud, gravity_params=GravityParams())
    strict = GravityParams(sparse_floor_area=100.0)  # no floor this large in view
    assert 1 not in tall_faces(ps, rel, cloud, gravity_params=strict)


def _ceiling_over_speckle(stray=0.15):
    """A camera 0.2 m over a floor measured as 5 % speckle plus stray returns 0.1-1 m over it
    (a share of about 0.25 of the lower half's unassigned points on the floor), a low ceiling
    over it, a far wall: the planes' estimate reads the camera upside down (hunt45 xtion_2)."""
    ceiling = Rect((0, 2.0, 1.0), (1, 0, 0), (0, 1, 0), 1.0, 1.5, 3)
    cloud, lab, up, _ = render([floor(), wall(y=5.0, w=6.0, h=2.4), ceiling], noise=0.0012,
                               pitch=0.0, cam_height=0.2, width=320, height=240)
    rng = np.random.default_rng(3)
    on_floor = lab == 0
    drop = on_floor & (rng.random(lab.shape) > 0.05)
    off = drop & (rng.random(lab.shape) < stray)
    xyz = cloud.xyz.copy()
    xyz[off] *= rng.uniform(0.6, 1.0, (int(off.sum()), 1))
    xyz[off, 1] -= rng.uniform(0.1, 1.0, int(off.sum()))
    xyz[drop & ~off] = np.nan
    lab = lab.copy()
    lab[on_floor] = -1
    return Cloud(xyz, cloud.intrinsics, None, "analytic"), lab, up


def test_a_speckle_floor_under_an_upside_down_reading_needs_a_smaller_share():
    cloud, lab, up = _ceiling_over_speckle()
    assert speckle_floor(cloud, lab, params=GravityParams(sparse_floor_share=0.3)) is None
    assert speckle_floor(cloud, lab, params=GravityParams(sparse_floor_share=0.2)) is not None
    assert up_from_cloud(cloud, lab, GravityParams(sparse_floor=0.0)).upside_down
    same = up_from_cloud(cloud, lab, GravityParams(sparse_floor_flip_share=0.3))
    assert same.upside_down and _deg(same.vector, up) > 170
    est = up_from_cloud(cloud, lab, GravityParams())  # the default flip share, 0.2
    assert not est.upside_down and est.sparse_floor and _deg(est.vector, up) < 2


def test_the_flip_share_is_checked():
    with pytest.raises(InputError):
        GravityParams(sparse_floor_flip_share=1.5)
    with pytest.raises(InputError):
        GravityParams(sparse_floor_tries=2)


def test_real_xtion_doorway_is_read_upright():
    """hunt45 mbot xtion_2 (``$PLANEREL_HUNT_DATA/hunt45/mbot``: an Xtion 0.2 m over a
    corridor's floor, a low ceiling seen from below): read upside down with the speckle's
    share bound at 0.3, upright with the flip share (0.2; 1.4 degrees from its floor's up)."""
    import json
    import os
    from pathlib import Path

    import planerel
    from planerel.segment import segment

    folder = Path(os.environ.get("PLANEREL_HUNT_DATA", "/nonexistent")) / "hunt45" / "mbot"
    if not (folder / "labels.json").is_file():
        pytest.skip(f"no frames in {folder} (set PLANEREL_HUNT_DATA)")
    fr = next(f for f in json.loads((folder / "labels.json").read_text())["frames"]
              if f["file"] == "xtion_2_depth.png")
    cloud = planerel.read(str(folder / fr["file"]), intrinsics=fr["intrinsics"],
                          depth_scale=fr["depth_scale"])
    seg = segment(cloud)
    # what describe_scene's up estimate reads: the labels without the far growing's planes
    labels = np.where(np.isin(seg.labels, seg.info.get("far_labels", [])), -1, seg.labels)
    now = up_from_cloud(cloud, labels)
    before = up_from_cloud(cloud, labels, GravityParams(sparse_floor_flip_share=0.3))
    assert before.upside_down and not now.upside_down and now.sparse_floor
    assert _deg(now.vector, before.vector) > 170
