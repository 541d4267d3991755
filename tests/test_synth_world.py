"""The varied synthetic world (planerel.synth.world): ranges, object ground truth, the data-set
files it writes, and multi-object learning examples (``other`` = negatives for every class)."""

from __future__ import annotations

import hashlib
import math

import numpy as np
import pytest

from planerel.cli import main
from planerel.errors import InputError
from planerel.features.dataset import (
    describe_truth_scene,
    iter_scenes,
    load_dataset_info,
    load_object_labels,
    object_classes,
)
from planerel.synth import geometry as sg
from planerel.synth.generator import generate_scene
from planerel.synth.world import CLUTTER, WorldRange, generate_world_scene

SMALL = dict(size=(640, 480), subsample=8)  # 80x60: enough for geometry checks


@pytest.fixture(scope="module")
def scenes():
    out = {}
    for kind in ("box", "stairs", "ramp"):
        out[kind] = [generate_world_scene(kind, seed, **SMALL) for seed in range(14)]
    return out


def test_paper_world_scenes_are_unchanged():
    """The default scenes are those of the code before the varied world (hashes taken from
    that code)."""
    expected = {("box", 1): "58d42ab3c171d292", ("stairs", 2): "a8d864bcea3e5626",
                ("ramp", 3): "b3c8a9314480ad51"}
    for (kind, seed), digest in expected.items():
        s = generate_scene(kind, seed, subsample=4)
        got = hashlib.sha256(s.depth_mm.tobytes() + s.gt_labels.tobytes()).hexdigest()[:16]
        assert got == digest, kind
        assert "world" not in s.metadata()


def test_same_seed_same_scene():
    a = generate_world_scene("stairs", 5, **SMALL)
    b = generate_world_scene("stairs", 5, **SMALL)
    c = generate_world_scene("stairs", 6, **SMALL)
    np.testing.assert_array_equal(a.depth_mm, b.depth_mm)
    np.testing.assert_array_equal(a.gt_objects, b.gt_objects)
    assert a.metadata() == b.metadata()
    assert not np.array_equal(a.depth_mm, c.depth_mm)


def test_camera_and_object_parameters_stay_in_their_ranges(scenes):
    r = WorldRange()
    for kind, ss in scenes.items():
        for s in ss:
            cam = s.params["camera"]
            assert r.camera_height[0] <= cam["height"] <= r.camera_height[1]
            assert r.camera_pitch_deg[0] <= cam["pitch_deg"] <= r.camera_pitch_deg[1]
            assert abs(cam["roll_deg"]) <= r.camera_roll_deg
            # the pose agrees: the camera centre is `height` above the floor, the optical axis
            # points `pitch` below the horizon
            rot = s.pose[:3, :3]
            eye = -rot.T @ s.pose[:3, 3]
            assert eye[2] == pytest.approx(cam["height"], abs=1e-9)
            assert math.degrees(math.asin(-rot[2, 2])) == pytest.approx(cam["pitch_deg"], abs=1e-6)
            primary = s.objects[1]
            assert primary["class"] == kind and primary["index"] == 1
            p = primary["params"]
            if kind == "stairs":
                assert r.steps[0] <= p["steps"] <= r.steps[1]
                assert r.rise[0] <= p["rise"] <= r.rise[1] and r.run[0] <= p["run"] <= r.run[1]
            elif kind == "ramp":
                assert r.ramp_angle_deg[0] <= p["angle_deg"] <= r.ramp_angle_deg[1]
                assert r.ramp_length[0] <= p["length"] <= r.ramp_length[1]
            else:
                assert all(r.box_size[0] <= p[k] <= r.box_size[1] for k in ("length", "width"))
                assert r.box_height[0] <= p["height"] <= r.box_height[1]


def test_object_ground_truth_is_consistent(scenes):
    classes = set()
    for ss in scenes.values():
        for s in ss:
            obj_of_plane = np.array([p.object_index for p in s.planes])
            lab = s.gt_labels
            np.testing.assert_array_equal(
                s.gt_objects, np.where(lab >= 0, obj_of_plane[np.maximum(lab, 0)], -1))
            objs = s.objects
            assert [o["index"] for o in objs] == list(range(len(objs)))
            assert objs[0]["class"] == "environment"
            for o in objs:
                assert o["n_pixels"] == int((s.gt_objects == o["index"]).sum())
                assert o["id"] == f"{s.scene_id}_o{o['index']}"
                classes.add(o["class"])
            assert set(obj_of_plane) <= {o["index"] for o in objs}
            # the primary object is seen
            assert objs[1]["n_pixels"] >= 0.03 * lab.size * 0.5
    assert classes == {"environment", "box", "stairs", "ramp", "other"}


def test_stairs_and_ramps_have_their_exact_geometry(scenes):
    for s in scenes["stairs"]:
        p = s.objects[1]["params"]
        treads = [pl for pl in s.planes if pl.object_index == 1 and pl.role == "tread"]
        heights = sorted(pl.height for pl in treads)
        if p["direction"] == "up":
            expected = [(i + 1) * p["rise"] for i in range(p["steps"])]
        else:  # below the floor the camera stands on, the top step being that floor
            expected = [-(p["steps"] - 1 - i) * p["rise"] for i in range(p["steps"] - 1)]
        np.testing.assert_allclose(heights, expected, atol=1e-9)
        assert all(pl.incline_deg == pytest.approx(0.0, abs=1e-6) for pl in treads)
    for s in scenes["ramp"]:
        slope = next(pl for pl in s.planes if pl.object_index == 1 and pl.role == "slope")
        assert slope.incline_deg == pytest.approx(s.objects[1]["params"]["angle_deg"], abs=1e-6)


def test_descending_stairs_are_seen_from_the_upper_floor():
    r = WorldRange(descending=1.0)
    s = generate_world_scene("stairs", 3, **SMALL, ranges=r)
    p = s.objects[1]["params"]
    assert p["direction"] == "down"
    floors = sorted(pl.height for pl in s.planes if pl.role == "floor")
    assert floors == pytest.approx([-p["steps"] * p["rise"], 0.0], abs=1e-9)
    # treads are seen from above: their normal points to the camera and up
    for pl in s.planes:
        if pl.role == "tread" and pl.n_pixels:
            assert float(np.dot(pl.normal, s.up)) == pytest.approx(1.0, abs=1e-9)
    assert any(pl.role == "tread" and pl.n_pixels for pl in s.planes)


def test_touching_boxes_share_a_face_plane_and_boxes_sit_on_tables():
    touching = on_table = 0
    for seed in range(60):
        s = generate_world_scene("box", seed, **SMALL)
        box = s.objects[1]["params"]
        if box.get("touching") == "box":
            other = next(o for o in s.objects[2:] if o["params"].get("touching") == "box")
            fa = [pl for pl in s.planes if pl.object_index == 1 and pl.role == "face"]
            fb = [pl for pl in s.planes if pl.object_index == other["index"] and pl.role == "face"]
            shared = [(a, b) for a in fa for b in fb
                      if np.allclose(a.normal, b.normal, atol=1e-9) and abs(a.offset - b.offset) < 1e-9]
            assert len(shared) == 1
            touching += 1
        if box.get("on") == "table":
            table = next(o for o in s.objects if o.get("kind") == "table")
            top = next(pl for pl in s.planes if pl.object_index == 1 and pl.role == "top") \
                if box["top"] else None
            if top is not None:
                assert top.height == pytest.approx(table["params"]["height"] + box["height"])
            on_table += 1
    assert touching >= 5 and on_table >= 3


def test_clutter_of_every_kind_is_class_other():
    kinds = {}
    for seed in range(40):
        s = generate_world_scene("ramp", seed, **SMALL)
        for o in s.objects[2:]:
            if o["class"] == "other":
                kinds[o["kind"]] = kinds.get(o["kind"], 0) + 1
            else:
                assert o["class"] in ("box", "stairs", "ramp")
    assert set(kinds) == set(CLUTTER)


def test_plate_share_makes_the_clutter_plates():
    # plate_share 1: every further clutter object is a plate (boxes, ramps, stairs as before
    # the pick); 0 (the default): no draw, the scenes of the default world
    kinds = {}
    for seed in range(12):
        s = generate_world_scene("ramp", seed, **SMALL, ranges=WorldRange(plate_share=1.0))
        for o in s.objects[2:]:
            kinds[o["kind"]] = kinds.get(o["kind"], 0) + 1
            if o["class"] == "other":
                assert o["kind"] == "plate" and 8.0 <= o["params"]["tilt_deg"] <= 70.0
    assert kinds.get("plate", 0) >= 4 and not set(kinds) & (set(CLUTTER) - {"plate"})
    for seed in (3, 7):
        a = generate_world_scene("box", seed, **SMALL, ranges=WorldRange(plate_share=0.0))
        b = generate_world_scene("box", seed, **SMALL)
        assert [o.get("params") for o in a.objects] == [o.get("params") for o in b.objects]
        np.testing.assert_array_equal(a.depth_mm, b.depth_mm)


def test_clutter_builders():
    g = sg.laptop_geometry(0.3, 0.2, 90.0)
    lid = next(p for p in g.polygons if g.planes[p.plane].role == "lid")
    assert abs(lid.normal()[2]) == pytest.approx(0.0, abs=1e-12)  # upright lid
    g = sg.plate_geometry(0.5, 0.4, 30.0)
    n = g.polygons[0].normal()
    assert math.degrees(math.acos(abs(n[2]))) == pytest.approx(30.0)
    g = sg.shelf_geometry(1.0, 0.3, 1.5, 3)
    assert sorted(p.vertices[0, 2] for p in g.polygons if g.planes[p.plane].role == "shelf") == \
        pytest.approx([0.5, 1.0, 1.5])
    g = sg.table_geometry(1.2, 0.8, 0.75)
    assert max(p.vertices[:, 2].max() for p in g.polygons) == pytest.approx(0.75)
    assert sum(sp.role == "leg" for sp in g.planes) == 16
    assert len(sg.cylinder_geometry(0.2, 1.0, facets=12).planes) == 13
    g = sg.box_geometry(1, 1, 0.05, top=False)  # an open box: its bottom inside, no top
    assert [p.role for p in g.planes] == ["bottom"] + ["face"] * 4
    assert g.polygons[0].vertices[:, 2] == pytest.approx([0.005] * 4)  # a tenth of 5 cm
    assert sg.box_geometry(1, 1, 0.5, top=False).polygons[0].vertices[:, 2] == \
        pytest.approx([0.01] * 4)


def test_tilted_boxes_lean_by_the_drawn_angle_and_rest_on_the_floor():
    """``box_tilt_deg``: the top leans by the drawn tilt, the faces by the same from vertical,
    the lowest corner stays on the floor; level worlds draw nothing (their scenes stay)."""
    seen = 0
    for seed in range(6):
        s = generate_world_scene("box", seed, **SMALL, ranges=WorldRange(box_tilt_deg=(2.5, 2.5)))
        p = s.objects[1]["params"]
        assert p["tip_deg"] == 2.5 and 0 <= p["tip_azimuth_deg"] < 360
        for pl in s.planes:
            if pl.object_index != 1 or not pl.n_pixels:
                continue
            incline = math.degrees(math.acos(min(1.0, abs(float(np.dot(pl.normal, s.up))))))
            if pl.role in ("top", "bottom"):
                assert incline == pytest.approx(2.5, abs=1e-6)
                seen += 1
            else:  # a face leans by up to the tilt (none when its normal is the tilt's axis)
                assert 87.5 - 1e-6 <= incline <= 90 + 1e-6
        level = generate_world_scene("box", seed, **SMALL)
        assert "tip_deg" not in level.objects[1]["params"]
    assert seen >= 4
    # clutter tips too when asked (a plate keeps its own tilt_deg, the slope it was made with)
    tipped_clutter = 0
    for seed in range(6):
        s = generate_world_scene("box", seed, **SMALL,
                                 ranges=WorldRange(clutter_tilt_deg=(1.0, 1.0), extra_objects=(3, 3)))
        for o in s.objects[2:]:
            if o["class"] == "other" and o["kind"] != "table":
                assert o["params"]["tip_deg"] == 1.0
                tipped_clutter += 1
    assert tipped_clutter
    # ascending staircases too: treads lean by the tilt, risers by up to it; a descending
    # flight (cut into the floor) stays level
    treads = 0
    for seed in range(8):
        s = generate_world_scene("stairs", seed, **SMALL,
                                 ranges=WorldRange(stairs_tilt_deg=(3.0, 3.0)))
        o = s.objects[1]
        if o["kind"] == "stairs down":
            assert "tip_deg" not in o["params"]
            continue
        assert o["params"]["tip_deg"] == 3.0
        for pl in s.planes:
            if pl.object_index != 1 or not pl.n_pixels:
                continue
            incline = math.degrees(math.acos(min(1.0, abs(float(np.dot(pl.normal, s.up))))))
            if pl.role == "tread":
                assert incline == pytest.approx(3.0, abs=1e-6)
                treads += 1
            elif pl.role == "riser":
                assert 87.0 - 1e-6 <= incline <= 90 + 1e-6
        assert "tip_deg" not in generate_world_scene("stairs", seed, **SMALL).objects[1]["params"]
    assert treads >= 4
    # level_share: that share of the tipped kinds stands level (tip_deg 0), the rest tip
    tips = [generate_world_scene("box", seed, **SMALL,
                                 ranges=WorldRange(box_tilt_deg=(2.0, 4.0), level_share=0.5)
                                 ).objects[1]["params"]["tip_deg"] for seed in range(12)]
    assert 0 < tips.count(0.0) < len(tips) and all(t == 0.0 or 2.0 <= t <= 4.0 for t in tips)
    assert [o.get("params") for o in generate_world_scene("box", 3, **SMALL, ranges=WorldRange(
        level_share=0.5)).objects] == [o.get("params") for o in generate_world_scene(
            "box", 3, **SMALL).objects]  # no tilt range on: no draw
    box = sg.box_geometry(0.4, 0.3, 0.2)
    tipped = sg.tilt(box, 4.0, 30.0)
    assert tipped.vertices()[:, 2].min() == pytest.approx(0.0, abs=1e-12)
    assert np.allclose(sg.tilt(box, 0.0, 30.0).vertices(), box.vertices())


@pytest.mark.parametrize("call,match", [
    (lambda: WorldRange(box_tilt_deg=(0, 12)), "box tilt must lie in 0..10"),
    (lambda: WorldRange(clutter_tilt_deg=(-1, 2)), "clutter tilt must be a finite"),
    (lambda: WorldRange(stairs_tilt_deg=(0, 11)), "stairs tilt must lie in 0..10"),
    (lambda: WorldRange(level_share=1.5), "level share must be one number in 0..1"),
    (lambda: WorldRange(plate_share=-0.1), "plate share must be one number in 0..1"),
    (lambda: WorldRange(descending=(0.0, 0.0)), "descending share must be one number in 0..1"),
    (lambda: WorldRange(camera_roll_deg=(0, 10)), "camera roll must be one number in 0..45"),
    (lambda: WorldRange(descending=True), "descending share must be one number"),
    (lambda: WorldRange(camera_pitch_deg=(0, 95)), "camera pitch must lie in 0..85"),
    (lambda: WorldRange(steps=(1, 4)), "steps must be integers with 2 <= min"),
    (lambda: WorldRange(rise=(0.2, 0.1)), "rise must be a finite"),
    (lambda: WorldRange(ramp_angle_deg=(0, 10)), "ramp angle must lie in"),
    (lambda: generate_world_scene("table", 0), "unknown scene class 'table'"),
    (lambda: generate_world_scene("box", 0, ranges={"steps": 3}), "ranges must be a WorldRange"),
])
def test_bad_world_parameters_raise_input_error(call, match):
    with pytest.raises(InputError, match=match):
        call()


# ------------------------------------------------------------------ data set and learning


@pytest.fixture(scope="module")
def varied_set(tmp_path_factory):
    out = tmp_path_factory.mktemp("varied") / "set"
    assert main(["dataset", "synth", str(out), "--world", "varied", "--n-box", "3",
                 "--n-stairs", "3", "--n-ramp", "3", "--subsample", "8", "--seed", "2",
                 "--quiet"]) == 0
    return out


def test_varied_data_set_files_and_object_labels(varied_set):
    info = load_dataset_info(varied_set)
    assert info["world"] == "varied" and info["sensor"]["profile"] == "structured-light"
    assert info["world_ranges"]["steps"] == [2, 10]
    for row, _cloud, labels, meta in iter_scenes(varied_set):
        assert meta["world"] == "varied" and (varied_set / meta["files"]["objects"]).is_file()
        objects = load_object_labels(varied_set, row.scene_id)
        obj_of_plane = np.array([p["object_index"] for p in meta["planes"]])
        np.testing.assert_array_equal(
            objects, np.where(labels >= 0, obj_of_plane[np.maximum(labels, 0)], -1))
        classes = object_classes(meta)
        assert classes[1] == row.klass
        assert set(classes) == {o["index"] for o in meta["objects"][1:]}


def test_object_labels_of_a_paper_set_come_from_the_planes(tmp_path):
    out = tmp_path / "paper"
    assert main(["dataset", "synth", str(out), "--n-box", "1", "--n-stairs", "0", "--n-ramp", "0",
                 "--subsample", "8", "--quiet"]) == 0
    _row, _cloud, labels, meta = next(iter_scenes(out))
    objects = load_object_labels(out, "s0000")
    assert set(np.unique(objects)) <= {-1, 0, 1} and (objects == 1).any()
    np.testing.assert_array_equal(objects >= 0, labels >= 0)
    assert object_classes(meta) == {1: "box"}


def test_every_object_is_an_example_with_its_class(varied_set, tmp_path):
    from planerel.ilp.aleph_export import export_aleph

    descs = []
    truth = {}
    for row, cloud, labels, meta in iter_scenes(varied_set):
        d = describe_truth_scene(cloud, labels, labels, meta, row.scene_id, row.klass)
        descs.append(d)
        seen = {o["index"]: o["class"] for o in meta["objects"][1:] if o["n_pixels"] > 0}
        # one object per seen object (ground-truth planes), in object order, with its class,
        # unless it is no fair example (then no class, and listed with the reason)
        left_out = {oid: (k, why) for oid, k, why in d.excluded}
        assert [o.klass or left_out[o.id][0] for o in d.objects] == [seen[k] for k in sorted(seen)]
        assert all(o.klass is None for o in d.objects if o.id in left_out)
        truth.update({o.id: o.klass for o in d.objects if o.klass})
    assert "other" in truth.values()
    res = export_aleph(descs, tmp_path / "aleph", "all")
    assert res.stems == ("box", "ramp", "stairs")
    for c in ("box", "stairs", "ramp"):
        pos = (tmp_path / "aleph" / f"{c}.f").read_text().split()
        neg = (tmp_path / "aleph" / f"{c}.n").read_text().split()
        n = len(c) + 1  # the facts are c(ID).
        assert {f[n:-2] for f in pos} == {o for o, k in truth.items() if k == c}
        assert {f[n:-2] for f in neg} == {o for o, k in truth.items() if k != c}  # `other` included


def test_cross_validation_tests_other_objects_apart(varied_set):
    from planerel.ilp.pipeline import cross_validate
    from planerel.ilp.scenes import describe_scenes

    descs, _ = describe_scenes(varied_set, method="gt", cache="none", progress=False)
    truth = {o.id: o.klass for d in descs for o in d.objects if o.klass}  # fair examples
    n_other = sum(k == "other" for k in truth.values())
    assert n_other >= 2
    cv = cross_validate(descs, ("box", "stairs", "ramp"), folds=2, progress=False)
    # every object, `other` included, is tested once; accuracy counts the class objects only
    assert sorted(o for f in cv["folds"] for o in f["test"]) == sorted(truth)
    assert cv["n_examples"] == len(truth) - n_other
    assert sum(map(sum, cv["confusion"])) == cv["n_examples"]
    got = [cv["predictions"][o] for o, k in truth.items() if k == "other"]
    assert cv["other"]["n"] == n_other and sum(cv["other"]["predicted"].values()) == n_other
    assert cv["other"]["rejected"] == pytest.approx(got.count("other") / n_other)
    right = sum(cv["predictions"][o] == k for o, k in truth.items())
    assert cv["open_set_accuracy"] == pytest.approx(right / len(truth))


def test_cli_range_option_shifts_the_world(tmp_path, capsys):
    out = tmp_path / "shifted"
    assert main(["dataset", "synth", str(out), "--world", "varied", "--n-box", "0",
                 "--n-stairs", "3", "--n-ramp", "0", "--subsample", "8", "--quiet",
                 "--range", "steps=11,12", "--range", "camera_pitch_deg=30,40",
                 "--range", "descending=0"]) == 0
    assert load_dataset_info(out)["world_ranges"]["steps"] == [11, 12]
    for _row, _cloud, _labels, meta in iter_scenes(out):
        p = meta["objects"][1]["params"]
        assert p["direction"] == "up" and 11 <= p["steps"] <= 12
        assert 30 <= meta["params"]["camera"]["pitch_deg"] <= 40
    capsys.readouterr()
    assert main(["dataset", "info", str(out)]) == 0
    assert "stairs (stairs up) 3" in capsys.readouterr().out
    for argv, match in ((["--range", "steps=3,4"], "add --world varied"),
                        (["--world", "varied", "--range", "stepz=3,4"], "NAME=MIN,MAX"),
                        (["--world", "varied", "--range", "steps=2.5,4"], "whole numbers"),
                        # a share is one number (nose16: a pair gave a TypeError traceback)
                        (["--world", "varied", "--range", "descending=0,0"],
                         "descending share must be one number in 0..1")):
        assert main(["dataset", "synth", str(tmp_path / "x"), "--quiet", *argv]) == 2
        assert match in capsys.readouterr().err


def test_objects_record_the_pixels_they_would_cover_alone_in_an_unbounded_view(scenes):
    """n_pixels_full >= n_pixels always; a lone box wholly inside the image is seen on all of
    them but the sensor's losses at its edges (flying pixels, dropouts: < 30 %)."""
    for ss in scenes.values():
        for s in ss:
            for o in s.objects[1:]:
                assert o["n_pixels"] <= o["n_pixels_full"], (s.scene_id, o["kind"])
    checked = 0
    for seed in range(12):
        s = generate_world_scene("box", seed, **SMALL, ranges=WorldRange(extra_objects=(0, 0)))
        if len(s.objects) != 2 or s.objects[1]["params"].get("on"):
            continue
        on = s.gt_objects == 1
        if on[[0, -1], :].any() or on[:, [0, -1]].any():  # touches the image border
            continue
        o = s.objects[1]
        assert 0.7 * o["n_pixels_full"] <= o["n_pixels"] <= o["n_pixels_full"]
        checked += 1
    assert checked >= 2
