"""The model ``make demo`` writes is right on the real frames in ``../shared/data``.

The model is learned exactly as ``examples/demo.py`` learns it (the same training world and
learner settings), once per version of the code that shapes it: it is cached under
``.pytest_cache`` keyed by a hash of the package, the Aleph task files, the Prolog support and
the demo script, so the suite pays the learning time only after such a change.

What each frame shows was checked by looking at it (proposals drawn in colour):

* Kinect ``frame_*_depth.tiff`` (640x480): a cardboard box (image columns ~375-505, rows
  ~175-320) and an open laptop (columns ~120-380, rows ~145-325) on the floor, a piece of
  furniture in the top right corner.  The box must be ``box`` in all three frames; nothing is
  stairs or ramp (the laptop's lid is a 0.38 m plane at ~61 degrees: not a ramp).
* mOSD ``learn0-5.pcd``: boxes on a table (the label field marks each object); every proposal
  that is mostly one labelled box is ``box``; nothing is stairs or ramp.
* mOSD ``test31.pcd``: cylinders: no proposal is box, stairs or ramp (every one is ``other``).

Over training-world seeds (``examples/demo.py --seed 1..5``, docs/results.md "The demo model over
training-world seeds") the Kinect box's ``box``, the mOSD answers and the cylinders' ``other``
held on every seed; "the Kinect box is the only box" and "no stairs in the Kinect frames" held
only on the shipped seed 0 (the corner furniture became ``box`` or ``stairs`` on 5 of 5 others).
"""

from __future__ import annotations

import fcntl
import hashlib
import importlib.util
import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT.parent / "shared" / "data"
KINECT = sorted((DATA / "kinect").glob("frame_*_depth.tiff"))
MOSD_BOXES = [DATA / "mosd" / f"learn{i}.pcd" for i in range(6)]
MOSD_CYLINDERS = DATA / "mosd" / "test31.pcd"
#: The box in the Kinect frames: (column range, row range), full resolution.
KINECT_BOX = ((385, 490), (195, 300))


def _need_data():
    missing = [p for p in [*KINECT, *MOSD_BOXES, MOSD_CYLINDERS] if not p.is_file()]
    if len(KINECT) != 3 or missing:
        pytest.skip(f"the real frames are not at {DATA} (../shared/data/README.md)")


def _demo():
    spec = importlib.util.spec_from_file_location("planerel_demo", ROOT / "examples" / "demo.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _code_hash() -> str:
    h = hashlib.sha256()
    files = sorted([*(ROOT / "planerel").rglob("*.py"), *(ROOT / "planerel").rglob("*.pl"),
                    *(ROOT / "aleph").glob("*.pl"), *(ROOT / "prolog").glob("*.pl"),
                    ROOT / "examples" / "demo.py"])
    for f in files:
        h.update(str(f.relative_to(ROOT)).encode())
        h.update(f.read_bytes())
    return h.hexdigest()[:16]


def test_the_demo_model_fixture_learns_every_part_of_make_demos_world():
    """The fixture below learns what ``make demo`` ships: every part of the training world
    (a part added to the world and to demo.py's flags but not here made the data-gated tests
    check another model: the panel part, 2026-11-30), with demo.py's default counts."""
    import inspect

    from planerel.synth.training_world import generate_training_world

    demo = _demo()
    sig = inspect.signature(generate_training_world).parameters
    # window: the sensor's, not a part (demo.py and the fixture both leave it at KINECT_WINDOW)
    parts = {n for n, p in sig.items() if p.kind == p.KEYWORD_ONLY} - {
        "paper", "room", "seed", "size", "subsample", "ranges", "window"}
    assert set(demo.default_parts()) == parts
    assert demo.default_parts()["panels"] == demo.PANELS > 0


@pytest.fixture(scope="module")
def demo_model(request):
    """The demo's model folder (learned here, or from the cache for this code)."""
    _need_data()

    cache = Path(request.config.cache.mkdir("planerel-demo-model"))
    model = cache / _code_hash()
    # one learner at a time (pytest -n: every worker needs the model; the first learns it,
    # the others wait and read it), into a temporary folder renamed when whole
    with open(cache / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (model / "rules.pl").is_file():
            for old in cache.iterdir():  # models of older code, a broken run's leftovers
                if old.is_dir():
                    shutil.rmtree(old, ignore_errors=True)
            demo = _demo()
            seeds = demo.seeds()  # the shipped model's (make demo, --seed 0)
            tmp = cache / f".learning-{os.getpid()}"
            demo.learn_shipped(cache / "world", tmp, parts=demo.default_parts(),
                               world_seed=seeds["world"], learner_seed=seeds["learner"],
                               engine="builtin", jobs=2, cache="none", log=lambda s: None,
                               progress=False)
            for stage in ("_base", "_products"):   # learn_shipped's first stages
                part = tmp.with_name(tmp.name + stage)
                if part.is_dir():
                    os.replace(part, model.with_name(model.name + stage))
            os.replace(tmp, model)
    return model


@pytest.fixture(scope="module")
def answers(demo_model):
    """``{file name: (SceneAnswer, (H, W) labels)}`` for every real frame."""
    from planerel.classify import Classifier
    from planerel.io import read

    out = {}
    with Classifier(demo_model) as clf:
        for f in [*KINECT, *MOSD_BOXES, MOSD_CYLINDERS]:
            cloud = read(f) if f.suffix == ".pcd" else read(f, intrinsics="kinect")
            out[f.name] = clf.classify(cloud, scene_id=f.stem.replace(".", "_"))
    return out


def _pixels(answer, obj) -> np.ndarray:
    return np.isin(np.asarray(answer.labels), list(obj.labels))


def test_kinect_box_is_box_in_every_frame(answers):
    (c0, c1), (r0, r1) = KINECT_BOX
    for f in KINECT:
        ans = answers[f.name]
        inside = [(_pixels(ans, o)[r0:r1, c0:c1].sum(), o) for o in ans.objects]
        n, box = max(inside, key=lambda t: t[0])
        assert n > 0.5 * (r1 - r0) * (c1 - c0), f"{f.name}: no proposal covers the box"
        assert box.klass == "box", f"{f.name}: the box is {box.klass} ({box.rule})"


def test_kinect_box_is_the_only_box(answers):
    """The furniture in the corner, the laptop and the floor clutter are ``other``."""
    for f in KINECT:
        got = {o.object_id: o.klass for o in answers[f.name].objects}
        assert list(got.values()).count("box") == 1, f"{f.name}: {got}"


def test_kinect_frames_have_no_stairs_or_ramp(answers):
    for f in KINECT:
        got = {o.object_id: o.klass for o in answers[f.name].objects}
        assert not {"stairs", "ramp"} & set(got.values()), f"{f.name}: {got}"


def test_mosd_boxes_are_boxes_and_nothing_is_stairs_or_ramp(answers):
    from planerel.io import read_pcd_field

    for f in MOSD_BOXES:
        ans = answers[f.name]
        truth = read_pcd_field(f, "label").astype(np.int64) // 10  # object = label // 10
        checked = 0
        for o in ans.objects:
            assert o.klass not in ("stairs", "ramp"), f"{f.name}: {o.object_id} is {o.klass}"
            objs = truth[_pixels(ans, o)]
            objs = objs[objs >= 2]  # 0: invalid, 1: table parts
            if objs.size and np.bincount(objs).max() >= 0.8 * objs.size:
                checked += 1  # mostly one box (or boxes merged into one proposal)
                assert o.klass == "box", f"{f.name}: {o.object_id} is {o.klass} ({o.rule})"
        assert checked, f"{f.name}: no proposal lies on a labelled box"


def test_mosd_cylinders_are_none_of_the_classes(answers):
    got = {o.object_id: (o.klass, o.rule) for o in answers[MOSD_CYLINDERS.name].objects}
    assert got and all(k == "other" for k, _ in got.values()), json.dumps(got)


@pytest.mark.parametrize("kind,extra", [("stairs", {"descending": 1.0}), ("ramp", {})])
def test_synthetic_kinect_stairs_from_above_and_ramps_keep_their_class(demo_model, kind, extra):
    """Kinect-like frames (structured light, 640x480) of the varied world's ranges, seeds the
    model never saw: a proposal lying mostly on the primary object has its class in at least
    8 of 10 ramp scenes and 8 of 10 staircases seen from above (going down).  Staircases:
    10 of 10 measured (benchmarks/bench_stairs_from_above.py); before the plane fit in
    disparity space, the stepped split and the step chains of issue 16 the flight came as
    several proposals, most of them single treads or one sloping "ramp" plane, and 5 of 10
    were stairs."""
    from planerel.classify import Classifier
    from planerel.synth.world import WorldRange, generate_world_scene

    ranges = WorldRange(camera_height=(0.8, 1.6), camera_pitch_deg=(25.0, 60.0),
                        object_range=(1.0, 3.0), extra_objects=(0, 1), **extra)
    right, got = 0, []
    with Classifier(demo_model) as clf:
        for seed in range(9000, 9010):
            scene = generate_world_scene(kind, seed, size=(640, 480), subsample=1, ranges=ranges)
            ans = clf.classify(scene.cloud, scene_id=f"k{seed}", up=scene.up)
            mine = scene.gt_objects == 1
            on = [o.klass for o in ans.objects
                  if np.sum(_pixels(ans, o) & mine) > 0.5 * max(1, np.sum(_pixels(ans, o)))]
            got.append(on)
            right += kind in on
    assert right >= 8, got


def test_round_part_cylinders_are_other_and_mostly_curved(tmp_path):
    """The training world's round part: each scene's object 1 is a box and every other object a
    cylinder of class ``other``; described, most cylinders come out curved (facets 360/16 =
    22.5 degrees apart fall in the facet range 5-50 of planerel.curved; far small ones show
    too few facets: 63 of 76 curved in 40 scenes), every box flat."""
    from planerel.ilp.scenes import describe_scenes
    from planerel.synth.training_world import generate_training_world

    world = generate_training_world(tmp_path / "w", paper=(0, 0, 0), room=(0, 0, 0), round_=6,
                                    seed=0)
    info = json.loads((world / "dataset.json").read_text())
    assert info["counts"]["round"] == 6 and info["world"].endswith("+round")
    descs, _ = describe_scenes(world, jobs=1, progress=False)
    boxes = [o for d in descs for o in d.objects if o.klass == "box"]
    cylinders = [o for d in descs for o in d.objects if o.klass == "other"]
    assert boxes and all(not o.curved for o in boxes), [(o.id, o.planar_fraction) for o in boxes]
    assert len(cylinders) >= 6
    assert sum(o.curved for o in cylinders) > 0.5 * len(cylinders), \
        [(o.id, o.planar_fraction) for o in cylinders]
    for d in descs:
        meta = json.loads((world / f"{d.scene_id}.json").read_text())
        kinds = {o["index"]: (o["class"], o["kind"]) for o in meta["objects"]}
        assert kinds[1][0] == "box"
        assert all(c == "other" and "cylinder" in k for i, (c, k) in kinds.items() if i >= 2)


OFFICE = DATA / "kinect" / "office1.pcd"
#: The strip of floor at the bottom of office1.pcd (3.1-3.9 m away): (column range, row range).
OFFICE_FLOOR_STRIP = ((240, 410), (420, 460))


def test_office_floor_strip_is_the_floor_and_no_ramp(demo_model):
    """The PCL office cloud (an office 1.8-5.4 m away: walls, a door, desks, an archive box
    against a cabinet (hunt36's label, :func:`test_office_box_against_a_cabinet_is_a_box`); no
    stairs or ramp).  Its floor shows only as a strip 3.1-3.9 m away that measures 6.2 degrees off the up
    the walls give; it was a ``ramp`` (the inclined-plane rule).  It is the floor now (the
    sensor's depth noise at that range allows the tilt over its width), so it is in no proposal,
    and no proposal of the frame is stairs or ramp."""
    if not OFFICE.is_file():
        pytest.skip(f"the office cloud is not at {OFFICE} (../shared/data/README.md)")
    from planerel.classify import Classifier
    from planerel.io import read

    with Classifier(demo_model) as clf:
        ans = clf.classify(read(OFFICE), scene_id="office1")
    (c0, c1), (r0, r1) = OFFICE_FLOOR_STRIP
    lab = np.asarray(ans.labels)[r0:r1, c0:c1]
    assert np.mean(lab >= 0) > 0.7  # the rest: missing depth, unassigned pixels
    strip = int(np.bincount(lab[lab >= 0]).argmax())
    assert np.mean(lab[lab >= 0] == strip) > 0.9  # one plane covers the strip
    assert not [o.object_id for o in ans.objects if strip in o.labels]
    got = {o.object_id: (o.klass, o.rule) for o in ans.objects}
    assert not {"stairs", "ramp"} & {k for k, _ in got.values()}, got


def test_synthetic_office_floor_strip_and_ramps_without_floor(demo_model):
    """tests/test_sensor_floor.py's scenes classified: the office-like floor strip (tilted 6
    degrees by a depth error across the image, walls dominating the up) is in no proposal and
    nothing is a ramp; ramps whose slope fills the view with no floor in sight, close up and at
    range, stay ``ramp``."""
    from test_sensor_floor import office_like_scene, ramp_scene

    from planerel.classify import Classifier

    with Classifier(demo_model) as clf:
        cloud, strip, _poly = office_like_scene()
        ans = clf.classify(cloud, scene_id="office_like")
        on = [o for o in ans.objects if np.sum(_pixels(ans, o) & strip) > 0.2 * strip.sum()]
        assert not on, [(o.object_id, o.klass) for o in on]
        assert "ramp" not in {o.klass for o in ans.objects}
        for angle, distance in ((9.0, 0.3), (9.0, 2.0), (12.0, 2.0)):
            cloud, up, slope = ramp_scene(angle, distance)
            ans = clf.classify(cloud, scene_id="ramp", up=up)
            on = [o.klass for o in ans.objects
                  if np.sum(_pixels(ans, o) & slope) > 0.5 * slope.sum()]
            assert on == ["ramp"], (angle, distance, [(o.klass, o.rule) for o in ans.objects])


#: Real staircases from public repositories (never copied here; benchmarks/real_stairs.py says
#: where to get them): ``$PLANEREL_STAIRS_DATA/stair-perception`` (Shiaoming/stair-perception
#: ``samples/``: two Kinect v2 frames, 512x424) and ``$PLANEREL_STAIRS_DATA/elmasry``
#: (moatazelmasry2/stair_perception ``pcds/``: two organized 320x240 Kinect clouds).
STAIRS_DATA = Path(os.environ.get("PLANEREL_STAIRS_DATA", "/nonexistent"))


def test_real_staircases_are_one_stairs_answer(demo_model):
    """Each real staircase frame: exactly one proposal answered ``stairs``, holding every tread
    of 0.05 m^2 or more, and nothing answered ``box`` or ``ramp``."""
    frames = [(f, "512,424,365.32,365.32,254.67,208.54")
              for f in sorted((STAIRS_DATA / "stair-perception").glob("*_depth.png"))]
    frames += [(f, None) for f in sorted((STAIRS_DATA / "elmasry").glob("*.pcd"))]
    if not frames:
        pytest.skip(f"no real staircase frames under {STAIRS_DATA} (set PLANEREL_STAIRS_DATA)")
    import planerel
    from planerel.classify import Classifier
    from planerel.features.facts import describe_scene
    from planerel.ilp.scenes import segment_cached

    with Classifier(demo_model) as clf:
        for f, intr in frames:
            cloud = planerel.read(f, intrinsics=intr, depth_scale=1000 if intr else None)
            ans = clf.classify(cloud, scene_id="s")
            classes = [o.klass for o in ans.objects]
            assert classes.count("stairs") == 1, f"{f.name}: {classes}"
            assert "box" not in classes and "ramp" not in classes, f"{f.name}: {classes}"
            labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
            desc = describe_scene(cloud, labels, scene_id="s", **clf.settings.describe_kwargs())
            (flight,) = [o for o in ans.objects if o.klass == "stairs"]
            treads = {p.label for p in desc.planes if p.orientation == "horizontal"
                      and p.area >= 0.05 and p.height >= 0.05}
            assert treads <= set(flight.labels), f"{f.name}: treads {treads - set(flight.labels)} apart"


def _unseen_rows(sets, model, var: str, params=()) -> dict:
    """``{frame: row}`` of benchmarks/real_unseen.py over the labelled set folders ``sets``
    (``Path``s) with ``model`` (and ``--param`` overrides), or a skip naming the variable
    ``var`` that points at them when a set is missing."""
    if not all((s / "labels.json").is_file() for s in sets):
        pytest.skip(f"no labelled frames in {', '.join(str(s) for s in sets)} (set {var}; "
                    "benchmarks/real_unseen.py)")
    import sys

    sys.path.insert(0, str(ROOT / "benchmarks"))
    from real_unseen import run

    return {r["frame"]: r for r in run([str(s) for s in sets], str(model), list(params))}


def _totals(rows: dict) -> dict:
    """benchmarks/real_unseen.py's totals over ``rows`` (:func:`_unseen_rows`)."""
    from real_unseen import totals

    return totals(rows.values())


def test_real_frames_nobody_had_seen(demo_model):
    """hunt25: organized Kinect clouds of PointCloudLibrary/data (``$PLANEREL_STAIRS_DATA/
    pcl-pairwise``: a room with an open-riser flight seen from its side, a desk, a chair;
    ``pcl-tutorials``: a person, a mug on a table, a chair), each with the ``labels.json``
    benchmarks/real_unseen.py reads.  No frame of the room is answered anything but
    ``stairs`` or ``ramp`` where nothing of a class is (the demo's stairs rule 4 proved a room
    wall with a banister's posts, and a desk pedestal's faces, ``stairs`` before the level
    gate, ``decision.level_gate``), and the mug's and the chair's frames have no class answer.
    top25's ``lying/1`` made three inclined patches over the floor (two room frames, the
    tutorial cloud) ``box``; since ``lying_snr`` (their rise over the floor only 2.1-3.6 times
    their own fit's RMS, real books' 9-86 times) none (docs/objects.md, "lying/1 clear of the
    noise").  The flight was missed in all five (docs/objects.md, "Real frames nobody on the
    team had seen"): its treads touch nothing.  Since riser26's open treads
    (``ProposalParams.open_treads``) the treads of 0002-0005 are one proposal and ``stairs``;
    0001 shows two tread levels only (docs/objects.md, "Open-riser flights"); since lead61's
    far planes (``far_theta`` on) its far treads are planes and it is ``stairs`` too
    (docs/segmentation.md "Far planes")."""
    sets = [STAIRS_DATA / "pcl-pairwise", STAIRS_DATA / "pcl-tutorials"]
    rows = _unseen_rows(sets, demo_model, "PLANEREL_STAIRS_DATA")
    assert len(rows) == 8
    false_boxes = 0
    for name in ("capture0001", "capture0002", "capture0003", "capture0004", "capture0005",
                 "table_scene_mug_stereo_textured", "region_growing_rgb_tutorial"):
        assert all(f[0] == "box" for f in rows[name]["false"]), (name, rows[name]["false"])
        false_boxes += len(rows[name]["false"])
    assert rows["table_scene_mug_stereo_textured"]["false"] == []
    t = _totals(rows)
    assert (t["stairs_found"], t["stairs_labelled"], t["false_stairs"]) == (5, 5, 0)
    assert [rows[f"capture000{i}"]["objects"][0]["found"] for i in range(1, 6)] == [
        True, True, True, True, True]
    assert t["false_box"] == false_boxes == 0


def test_a_pallet_of_cartons_is_no_staircase(demo_model):
    """pile26: a RealSense pallet of 13 cartons seen from above (``$PLANEREL_STAIRS_DATA/
    palletizer``, MuhammadUsamaSattar/smart_palletizer), its tops at three heights (0.36,
    0.46, 0.56 m over the floor).  The demo's stairs rules prove the pile and a machine's
    faces; the flight gate (``decision.flight_gate``) refuses them: the pile's steps are
    0.10 and 0.20 m on runs that do not grow with them, the machine's none.  The pile of
    both captures is ``box`` (in the second it was one proposal with the machine, a false
    box, until the floor rule of 2026-11-30 evening took the near floor instead of a piece of
    it 7 cm higher: docs/gravity.md "The floor's level"); the first capture keeps one false
    box (a floor patch beside the tall carton by ``lying/1``, at the pile's edge: 45 % in the
    pile's rectangle as hunt25 drew it, 89 % in the rectangle redrawn after the machine's reset
    of 2026-12-01, whose left edge is 5 px further out; so at most one).  With the gate off, one stairs answer is back (two
    before wavy29's join of the carton tops' wavy pieces, docs/segmentation.md "Wavy sensors"; three
    before the stairs rule was learned on ``stair_step/2``: the pile's 0.10 m step one stair
    rise above and one run beyond the next carton; docs/objects.md, "Carton piles and false
    answers on unseen frames", "A flight's steps as a relation")."""
    sets = [STAIRS_DATA / "palletizer"]
    t = _totals(_unseen_rows(sets, demo_model, "PLANEREL_STAIRS_DATA"))
    assert (t["box_found"], t["box_labelled"], t["false_stairs"]) == (2, 2, 0)
    assert t["false_box"] <= 1
    off = _totals(_unseen_rows(sets, demo_model, "PLANEREL_STAIRS_DATA",
                               ["decision.flight_gate=false"]))
    # (0, 2) before wavy29's join of the RealSense's wavy carton tops (docs/segmentation.md,
    # "Wavy sensors"): the first capture's pile is `box` even without the gate
    assert (off["box_found"], off["false_stairs"]) == (1, 1)


@pytest.mark.parametrize("legs,apron", [(True, 0.0), (False, 0.12), (True, 0.1)])
def test_a_table_standing_in_the_room_is_other_and_the_box_on_it_box(demo_model, legs, apron):
    """table22u: a table seen with its legs or apron is a proposal of its own (its top still
    the ground of what stands on it, ``ProposalParams.table_legs``); the box rules, whose
    ``skirt`` is a face hanging below a top, must not take the top with its apron: the table
    is ``other``, the box on it ``box`` (docs/objects.md, table22u)."""
    from scenes_analytic import box, floor, render
    from test_proposals_table22u import TABLE, VIEW, _on_table, _table

    from planerel.classify import Classifier

    rects = [floor(), *_table(legs=legs, apron=apron),
             *_on_table(box(0.1, 2.0, 0.25, 0.2, 0.15, obj=1))]
    cloud, lab, up, objs = render(rects, **VIEW)
    truth = np.where(lab >= 0, np.asarray(objs)[np.maximum(lab, 0)], -1)
    with Classifier(demo_model) as clf:
        ans = clf.classify(cloud, scene_id="t", up=up)
    held = {}
    for o in ans.objects:
        m = _pixels(ans, o)
        for obj in (1, TABLE):
            held.setdefault(obj, []).append((int((m & (truth == obj)).sum()), o))
    n_table, table = max(held[TABLE], key=lambda t: t[0])
    n_box, box_ = max(held[1], key=lambda t: t[0])
    assert n_table > 0.8 * (truth == TABLE).sum() and table.klass == "other", (table.klass, table.rule)
    assert n_box > 0.8 * (truth == 1).sum() and box_.klass == "box", (box_.klass, box_.rule)
    assert table is not box_
    assert not any(o.klass in ("stairs", "ramp") for o in ans.objects)


#: hunt26's, hunt28's, hunt32's and hunt33's development frames (real frames nobody on the team had made,
#: kept outside the repository: ``$PLANEREL_HUNT_DATA/hidden26``, ``.../hidden28``,
#: ``.../hidden32``, each set folder
#: with the ``labels.json`` benchmarks/real_unseen.py reads)
HUNT_DATA = Path(os.environ.get("PLANEREL_HUNT_DATA", "/nonexistent"))


def test_furniture_longer_than_any_box_is_no_box(demo_model):
    """fbox31: the demo's box rules proved furniture and a door's jamb on real rooms: a
    wardrobe's 1.6 m side and the jamb (NYU basement), an office cabinet's 1.65 m side (SUN
    corridor; ``tall_face``), a dining table's 2.2 m top over its apron (``skirt``).  The size
    gate (``decision.size_gate``) refuses a box proof binding a plane (a face's height, a top's
    length) over 1.2 times the furthest of the training box proofs' (1.23 m).  The sideboard of dining3-5 (its top 0.5-1.2 m, its
    front 0.9 m: box-shaped furniture the labels mark no class) stays a false box
    (docs/objects.md, "False boxes on real rooms").
    The sets as rebuilt from their repositories on 2026-12-06 (session 86; the first copies
    were lost with the machine, and their intrinsics are not known): the rules and gates of
    today no longer prove the wardrobe, the jamb or the cabinet even with the size gate off (the
    last assertion), so the gate's refusals are measured here no more
    (``tests/test_size_gate.py`` tests the gate); what stays is that these rooms' furniture
    gets no box answer but the sideboard."""
    sets = [HUNT_DATA / "hidden26" / "open3d-rgbd", HUNT_DATA / "hidden28" / "nyu-slambook"]
    rows = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA")
    assert len(rows) == 8

    def boxes(row):
        return [f[:2] for f in row["false"] if f[0] == "box"]

    for name in ("nyu_basement_depth", "sun_corridor_depth", "dining1_depth", "dining2_depth"):
        assert boxes(rows[name]) == [], (name, rows[name]["false"])
    for name in ("dining3_depth", "dining4_depth", "dining5_depth"):   # the sideboard
        assert boxes(rows[name]) == [("box", 1)], (name, rows[name]["false"])
    assert boxes(rows["tum_desk_depth"]) == []
    off = _unseen_rows(sets[:1], demo_model, "PLANEREL_HUNT_DATA", ["decision.size_gate=false"])
    for name in ("nyu_basement_depth", "sun_corridor_depth"):
        assert boxes(off[name]) == [], (name, off[name]["false"])


def test_boxes_seen_from_straight_above_lie_on_the_board_around_them(demo_model):
    """lie32: hidden32's pharmacy cartons (``$PLANEREL_HUNT_DATA/hidden32/d435-pharmaboxes``, a
    RealSense 0.5 m over a foam board) and a small box in a tray (``d455-tray``, a D455 0.9 m
    over it): two cartons and the tray's box show their top only, 6-9 cm over what they lie on,
    their sides out of sight, so the top touches nothing and ``lying/1`` (an adjacent ground)
    did not hold.  The board shows around each top across the depth jump, nothing in between
    (``RelationParams.lying_ring``): ``lying``, and the box rule ``lying + oblique_share``
    proves them.  With ``relations.lying_ring=0`` they are missed, as before; no false answer
    is added (docs/objects.md, "Boxes seen from straight above")."""
    sets = [HUNT_DATA / "hidden32" / "d435-pharmaboxes", HUNT_DATA / "hidden32" / "d455-tray"]
    rows = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA")
    off = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA", ["relations.lying_ring=0"])
    found = [o["found"] for o in rows["boxes_depth"]["objects"]]
    assert found == [True, True, True, True]
    assert [o["found"] for o in off["boxes_depth"]["objects"]] == [False, True, False, True]
    assert [o["found"] for o in rows["tray1_depth"]["objects"]] == [True]
    assert [o["found"] for o in off["tray1_depth"]["objects"]] == [False]
    assert _totals(rows)["false_box"] == _totals(off)["false_box"]


def test_boxes_seen_from_above_with_a_smeared_edge_or_a_small_top(demo_model):
    """lying56: hunt55's bin-picking views (``$PLANEREL_HUNT_DATA/hunt55``).  l515-boxes
    pallet2: a carton on the floor seen from above by an L515 0.86 m up; the sensor smears the
    jump from its top to the floor over 4-6 pixels, half lie32's ring "between" the levels, and
    a cable lies beside it.  The ring now starts ``lying_ring_band`` (5) pixels out and allows
    ``lying_ring_between`` 0.1: ``lying``, ``box``.  jh2-suction: a purple pack 12.5 x 4.3 cm,
    3 cm over the table, under ``lying_width``; level, it is ``lying`` as a small top
    (``lying_small_length``): ``box``.  The candy pack beside it (0.036 x 0.108 m) is
    ``lying`` too; the proof gate refused its 0.0038 m^2 top until the training world's small
    flat scenes (small57, ``examples/demo.py`` ``FLAT_SMALL``) took the lying rule's proofs down
    to 0.0052 m^2: ``box`` now.  With lie32's ring and bounds all three are missed; no false
    answer either way."""
    sets = [HUNT_DATA / "hunt55" / "l515-boxes", HUNT_DATA / "hunt55" / "jh2-suction"]
    rows = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA")
    off = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA",
                       ["relations.lying_ring_band=0", "relations.lying_ring_between=0.05",
                        "relations.lying_small_length=0"])
    assert [o["found"] for o in rows["pallet2_depth"]["objects"]] == [False, True]
    assert [o["found"] for o in off["pallet2_depth"]["objects"]] == [False, False]
    assert [o["found"] for o in rows["table_depth"]["objects"]] == [True, True]
    assert [o["found"] for o in off["table_depth"]["objects"]] == [False, False]
    assert _totals(rows)["false_box"] == _totals(off)["false_box"] == 0
    lying_rule = [d for d in json.loads((Path(demo_model) / "model.json").read_text())
                  ["proof_domain"] if d["rule"] == 3]
    assert lying_rule and lying_rule[0]["low"] < 0.006  # main before small57: 0.0102


def test_wooden_cubes_seen_from_above(demo_model):
    """tote67: hunt67's arm-lab boards (``$PLANEREL_HUNT_DATA/hunt67``: 2.5 and 4 cm wooden
    cubes seen from about 1 m above by a Kinect v1 and two RealSense cameras, 114 boxes).  A 4
    cm cube's top measures 4-6.5 cm, under the small-top bounds of small65 (0.05 x 0.03 m);
    at 0.03 x 0.02 m it is ``lying`` and ``box``.  Two boards were read as walls until
    gravity's candidates near the optical axis were scored looking down too.  No false
    answer either way.  (Without the small pass, on for these steep views since small99: its
    test is ``test_the_small_pass_runs_where_the_camera_looks_down``.)"""
    sets = [HUNT_DATA / "hunt67" / n for n in ("armlab-204", "armlab-kinect", "armlab-rs-grid")]
    rows = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA", ["small_scale=0"])
    off = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA",
                       ["relations.lying_small_length=0.05", "relations.lying_small_width=0.03",
                        "relations.lying_tiny_length=0", "small_scale=0"])
    now, before = _totals(rows), _totals(off)
    assert now["box_found"] >= 14 > 3 >= before["box_found"], (now, before)
    assert now["false_box"] == before["false_box"] == 0
    # the shuffled board, read as a wall before: its cubes are found again
    assert any(o["found"] for o in rows["depth_204shuffled"]["objects"])


def test_the_side_test_keeps_small_cube_tops_off_the_board(demo_model):
    """span91: the merge's side test on for small regions (``split.merge_side`` 3 and
    ``merge_side_span`` 0.02 m by default): a cube's top 2-4 cm over the board no longer
    merges into it by the pooled test.  hunt67's boards (2.5 and 4 cm wooden cubes, 114 boxes)
    14 -> 37 found, hunt90's (cubes on tables and boards seen from above by RealSense cameras,
    55 boxes) 4 -> 21; no false box more (hunt90's one is the same).  The demo's rules
    re-learned with it are the rules learned without it.  (Without the small pass, on for
    hunt67's steep views since small99, and without level100's small tops level within their
    noise: what span91 measured.)"""
    sets = ([HUNT_DATA / "hunt67" / n for n in ("armlab-204", "armlab-kinect", "armlab-rs-grid")]
            + [HUNT_DATA / "hunt90" / n for n in ("bg-tabletop", "leob-armlab", "lg-table",
                                                  "lk-armlab")])
    base = ["small_scale=0", "relations.lying_small_noise=0", "relations.lying_tiny_length=0"]
    now = _totals(_unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA", base))
    off = _totals(_unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA",
                               ["split.merge_side=0", *base]))
    # (off 18 before axis102 read lk-armlab stacks' board as the floor: its purple-topped
    # tower is found either way since)
    assert now["box_found"] >= 59 and off["box_found"] <= 19, (now, off)
    assert now["false_box"] <= off["false_box"] <= 1, (now, off)


def test_wooden_cubes_found_by_the_small_pass(demo_model):
    """blocks68: the same cubes with the small pass on at classify time (``small_scale`` 0.35).
    Its tops standing over the board are planes now: the second growing merges with the side
    test, the fit bound is the near pass's, the Kinect frames' unmeasured noise is the sensor
    model's.  Session 67's pass found 15.  With ``split.merge_side`` 3 for every region (the
    small pass's own setting, ``merge_side_span`` 0) the large cubes' tops stay off the board
    too: 49.  No false answer."""
    sets = [HUNT_DATA / "hunt67" / n for n in ("armlab-204", "armlab-kinect", "armlab-rs-grid")]
    small = _totals(_unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA", ["small_scale=0.35"]))
    both = _totals(_unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA",
                                ["small_scale=0.35", "split.merge_side=3"]))
    assert small["box_found"] >= 22 and both["box_found"] >= 45, (small, both)
    assert small["false_box"] == both["false_box"] == 0


def test_the_small_pass_runs_where_the_camera_looks_down(demo_model):
    """small99: the small pass on by default (``small_scale`` 0.35) where the camera looks down
    at least ``small_pitch`` 60 degrees.  hunt67's boards, seen from 77-90 degrees: 37 -> 49
    of 114 cubes found.  hunt90's lk-armlab: its grid board seen from 89 degrees gets small
    planes (more proposals) but no cube more or fewer, in allblocks and in stacks (read level,
    1 degree down, and so given no pass, until axis102).  No false answer either way."""
    steep = [HUNT_DATA / "hunt67" / n for n in ("armlab-204", "armlab-kinect", "armlab-rs-grid")]
    now = _totals(_unseen_rows(steep, demo_model, "PLANEREL_HUNT_DATA"))
    off = _totals(_unseen_rows(steep, demo_model, "PLANEREL_HUNT_DATA", ["small_scale=0"]))
    assert now["box_found"] >= 47 and off["box_found"] <= 39, (now, off)
    assert now["false_box"] == off["false_box"] == 0
    lk = [HUNT_DATA / "hunt90" / "lk-armlab"]
    # (raised102's tops and tiny102's tops off: they find lk-armlab's cubes on the small
    # pass's planes)
    tiny = "relations.lying_tiny_length=0"
    rows = _unseen_rows(lk, demo_model, "PLANEREL_HUNT_DATA", ["raised_min=0", tiny])
    plain = _unseen_rows(lk, demo_model, "PLANEREL_HUNT_DATA", ["small_scale=0", tiny])
    for name in ("allblocks_depth", "stacks_depth"):
        assert rows[name]["objects_proposed"] > plain[name]["objects_proposed"], name
    assert _totals(rows) == _totals(plain)


def test_a_board_under_cube_towers_is_seen_from_above(demo_model):
    """axis102: hunt90's lk-armlab stacks (a RealSense 1 m over a board, four towers of
    cubes 5-11 cm tall, the wall behind the board along the image's top).  The towers' sides
    and the wall strip are upright to the board; with an upright plane in view the board's
    candidate was oriented by the image's top (the camera looking straight up, refused by
    the pose prior) and the image's top won, the wall strip a ceiling over a level camera: 91
    degrees off.  Only an upright plane facing the image's top (a floor strip under a level
    camera facing a wall) keeps that reading now: the up is the board's, the small pass runs,
    and the purple-topped tower of three large cubes is ``box``.  No false answer in the set."""
    from planerel.classify.classifier import Classifier
    from planerel.segment import view_pitch

    lk = HUNT_DATA / "hunt90" / "lk-armlab"
    rows = _unseen_rows([lk], demo_model, "PLANEREL_HUNT_DATA")
    assert [o["found"] for o in rows["stacks_depth"]["objects"]] == [False, False, False, True]
    assert _totals(rows)["false_box"] <= 1      # the set's one false box before axis102
    from real_unseen import describe_frame, read_labels  # on the path: _unseen_rows

    frame = next(f for f in read_labels(str(lk))["frames"] if f["file"].startswith("stacks"))
    with Classifier(demo_model) as clf:
        planes = describe_frame(clf, str(lk), frame)[1].planes
    assert view_pitch(planes.up) > 85.0, planes.up


def test_domed_cube_tops_raised_over_the_board(demo_model):
    """raised102: hunt67/hunt90's cube tops that no growing keeps whole (a RealSense smooths a
    2.5-4 cm top into a dome, its rim 3-9 mm under its centre: the normals turn through the
    rim) are planes from their height over the board (``raised_min`` 0.012 m): the boards'
    169 cubes 78 -> 96 found, no false answer more (hunt90's one is the same); a cup's rim, a
    sphere's cap and the speckle of an R200 stay out (hunt39 sam6d-lm, hunt45 mbot: no false
    box either way)."""
    boards = ([HUNT_DATA / "hunt67" / n for n in ("armlab-204", "armlab-kinect", "armlab-rs-grid")]
              + [HUNT_DATA / "hunt90" / n for n in ("bg-tabletop", "leob-armlab", "lg-table",
                                                    "lk-armlab")])
    tiny = ["relations.lying_tiny_length=0"]     # (tiny102 on top: its own test)
    now = _totals(_unseen_rows(boards, demo_model, "PLANEREL_HUNT_DATA", tiny))
    off = _totals(_unseen_rows(boards, demo_model, "PLANEREL_HUNT_DATA", ["raised_min=0", *tiny]))
    assert now["box_found"] >= 94 and now["box_found"] >= off["box_found"] + 15, (now, off)
    assert now["false_box"] == off["false_box"] <= 1, (now, off)
    others = [HUNT_DATA / "hunt39" / "sam6d-lm", HUNT_DATA / "hunt45" / "mbot"]
    rows = _totals(_unseen_rows(others, demo_model, "PLANEREL_HUNT_DATA"))
    plain = _totals(_unseen_rows(others, demo_model, "PLANEREL_HUNT_DATA", ["raised_min=0"]))
    assert rows["false_box"] == plain["false_box"], (rows, plain)


def test_tiny_squat_cube_tops_lie_on_the_board(demo_model):
    """tiny102: with raised102's planes the boards' 2.5 cm cubes have tops of their own, but
    they measure 2.4-3.3 cm, under ``lying_small_length`` (3 cm); a top down to
    ``lying_tiny_length`` (2.5 cm) that rises at most ``lying_tiny_squat`` (1.5) times its
    length over its ground is ``lying``: the 169 cubes 96 -> 132 found, no false answer more.
    Without the squat test a green cylinder standing 6 cm tall (hunt67 armlab-rs-grid grid1,
    its round top 2.9 x 2.4 cm) was a false box."""
    boards = ([HUNT_DATA / "hunt67" / n for n in ("armlab-204", "armlab-kinect", "armlab-rs-grid")]
              + [HUNT_DATA / "hunt90" / n for n in ("bg-tabletop", "leob-armlab", "lg-table",
                                                    "lk-armlab")])
    now = _totals(_unseen_rows(boards, demo_model, "PLANEREL_HUNT_DATA"))
    off = _totals(_unseen_rows(boards, demo_model, "PLANEREL_HUNT_DATA",
                               ["relations.lying_tiny_length=0"]))
    tall = _totals(_unseen_rows(boards, demo_model, "PLANEREL_HUNT_DATA",
                                ["relations.lying_tiny_squat=100"]))
    assert now["box_found"] >= 128 and now["box_found"] >= off["box_found"] + 30, (now, off)
    assert now["false_box"] == off["false_box"] <= 1, (now, off)
    assert tall["false_box"] == now["false_box"] + 1, (tall, now)


def test_small_tops_level_within_their_own_noise(demo_model):
    """level100: a cube's 2.5-4.6 cm top seen from 1 m measures 3-10 degrees off the board
    (1.5-2.7 mm of RMS, a tilt's rise of 1-4 times that along it), over ``lying_small_tilt``
    5: with ``relations.lying_small_noise`` 3 it is ``lying``.  hunt67's boards 49 -> 55 of
    114 cubes, hunt90 21 -> 22 of 55, no false answer either way."""
    steep = [HUNT_DATA / "hunt67" / n for n in ("armlab-204", "armlab-kinect", "armlab-rs-grid")]
    now = _totals(_unseen_rows(steep, demo_model, "PLANEREL_HUNT_DATA"))
    off = _totals(_unseen_rows(steep, demo_model, "PLANEREL_HUNT_DATA",
                               ["relations.lying_small_noise=0"]))
    assert now["box_found"] >= off["box_found"] + 5 and now["box_found"] >= 53, (now, off)
    assert now["false_box"] == off["false_box"] == 0


def test_realsense_boxes_whose_faces_come_in_pieces(demo_model):
    """frag31: two RealSense boxes nobody on the team had made, lost to a face in pieces.
    hidden26's ycb4 (a Cheez-It box lying under a drill, the wall behind at 1 m): the wall's
    and the box top's pieces tilt 20-31 degrees against each other, beyond the wavy join's 20;
    the wall's fragments then joined the box and the drill through ``open_walls`` (one
    proposal of 41 planes, a false box 28 % in the box).  Small pieces now join up to 30
    degrees (``WAVE_TILT``, docs/segmentation.md "Wavy sensors"): the box is ``box``.
    hidden28's graspnet cracker box: its top and its broad side, a skirt pair, lie 2.5 cm
    apart (the smeared edge's band), beyond ``touch_gap`` (8 px, 0.5 cm there): two
    proposals, neither a box.  On a wavy frame a skirt pair within ``skirt_gap`` stays one
    object: ``box``."""
    ycb, grasp = HUNT_DATA / "hidden26" / "posecnn-ycb", HUNT_DATA / "hidden28" / "graspnet-table"
    rows = _unseen_rows([ycb, grasp], demo_model, "PLANEREL_HUNT_DATA")
    ycb4, box = rows["ycb4-depth"], rows["example_depth"]
    assert [o["found"] for o in ycb4["objects"]] == [True]
    assert [o["found"] for o in box["objects"]] == [True]
    assert not box["false"]


def test_slopes_standing_on_no_floor_are_no_ramps(demo_model):
    """ramp32: the demo's ramp rule ("a plane of 0.53 m^2 or more, at most 28 degrees steep")
    proved four slopes of hunt28's rooms that no floor leads onto: a far shelf (lab060, its low
    end 0.80 m over the floor), a far table top the sensor bends by 27 degrees (dining4, 0.64
    m), the top of a sofa's back (lounge, 0.84 m), each with its low end in plain view, and a
    far floor strip bent through the floor (lab012, 0.11 m under it).  The foot gate
    (``decision.foot_gate``, :func:`planerel.ilp.metrics.foot_refusals`) refuses them; the
    boxes and staircases found stay (docs/results.md, "A ramp stands on the floor").
    The sets as rebuilt from their repositories on 2026-12-06 (session 86: the first copies
    were lost with the machine): aims-lab holds a third frame, lab036 (three far slopes the
    foot gate refuses), and the lounge's sofa back is no ramp with the Kinect v2's usual
    intrinsics (the first copy's are not known).  The slope-parts gate (wave83, later) refuses
    all but lab060's shelf on its own, so the foot gate's share is measured with it off."""
    sets = [HUNT_DATA / "hidden28" / n for n in ("aims-lab", "nyu-slambook", "tuinicr-room")]
    rows = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA")
    off = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA",
                       ["decision.foot_gate=false", "decision.slope_parts_gate=false"])
    parts = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA", ["decision.foot_gate=false"])

    def ramps(rs):
        return sorted(name for name, r in rs.items() for f in r["false"] if f[0] == "ramp")

    assert ramps(off) == ["dining4_depth", "lab012_depth"] + ["lab036_depth"] * 3 \
        + ["lab060_depth"] * 2
    assert ramps(parts) == ["lab060_depth"]
    assert ramps(rows) == []
    on, was = _totals(rows), _totals(off)
    assert {k: v for k, v in on.items() if k != "false_ramp"} == \
        {k: v for k, v in was.items() if k != "false_ramp"}


def test_kinect_v2_cartons_whose_cloud_is_no_exact_pinhole_image(demo_model):
    """hunt33 (``$PLANEREL_HUNT_DATA/hunt33/kinect2box``: niconiconi0808/cv-box-detection's
    three Kinect v2 frames of a carton on a carpet, organized XYZ from the SDK: undistorted
    points on the distorted pixel grid).  The points fit a pinhole to 1.4-1.6 px (median), so
    reading them gave no intrinsics, no skirt could be measured and the carton (its top and a
    side one proposal) was missed in all three.  The fitted intrinsics (``estimate_intrinsics``'s
    approximate fit, with a warning) find it in each, by ``skirt`` (docs/objects.md, "hunt33")."""
    import warnings

    from planerel.errors import PlanerelWarning

    sets = [HUNT_DATA / "hunt33" / "kinect2box"]
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        rows = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA")
    assert len(rows) == 3
    for name, row in rows.items():
        assert [o["found"] for o in row["objects"]] == [True], name
    assert _totals(rows)["false_box"] == 0
    assert sum(issubclass(w.category, PlanerelWarning) and "fitted" in str(w.message)
               for w in seen) >= 3


def test_outdoor_slopes_far_over_the_floor_are_no_ramp(demo_model):
    """hunt35 (``$PLANEREL_HUNT_DATA/hunt35``: outdoor frames, KITTI's and an off-road
    LiDAR's densified depth, RealSense D415 sidewalks): two false ramps stood 1.4-2.6 m over
    the floor with their low end out of sight (a tree's canopy, a far strip at the top of the
    LiDAR band), which the foot gate let pass; ``decision.foot_float`` (1.0 m) refuses them.
    The other false ramps (ground strips beside the floor starting at its level, a parked car
    smeared into a slope) stay (docs/results.md "A ramp stands on the floor"), but the D415
    grass strip by a hedge (gmrpd sample2), which wave50's ``split.wavy_leftover`` makes part
    of the ground's plane (docs/segmentation.md "Large flat areas a wavy sensor leaves
    unassigned"): 7 and 5 before it.
    Measured with the range gate off: it refuses the far ones too
    (:func:`test_outdoor_slopes_farther_than_any_training_ramp_are_no_ramp`).  The slope-parts
    gate (wave83, later) refuses two of the same slopes on its own, so it is off here too."""
    sets = sorted(p.parent for p in (HUNT_DATA / "hunt35").glob("*/labels.json"))
    # the range gate, the side gate (ramp44: one of the far LiDAR strips is seen from below)
    # and the slope-parts gate off: the foot gate's own share
    far = ["decision.range_gate=false", "decision.side_gate=false",
           "decision.slope_parts_gate=false"]
    rows = _unseen_rows(sets or [HUNT_DATA / "hunt35" / "none"], demo_model, "PLANEREL_HUNT_DATA",
                        far)
    off = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA", ["decision.foot_float=0", *far])
    assert (_totals(off)["false_ramp"], _totals(rows)["false_ramp"]) == (6, 4)


def test_outdoor_slopes_farther_than_any_training_ramp_are_no_ramp(demo_model):
    """range40 (``$PLANEREL_HUNT_DATA/hunt35``): of the five false ramps the foot gate leaves,
    four are proved with a plane 10.5-17.4 m from the sensor on KITTI's and an off-road
    LiDAR's densified depth (a kerbed planting bed, a parked car's front, a soil mound, a
    bushy verge); the demo's ramp proofs' planes lie at most 3.54 m away.  The range gate
    (``decision.range_gate``, beyond 1 + ``decision.range_margin`` = 2 times that) refuses
    them (docs/results.md, "Proofs farther away than any training proof"); the fifth, the
    D415 grass strip by a hedge 3.8 m away that the gate let pass, is no ramp since wave50's
    ``split.wavy_leftover`` (the ground's plane takes it: 5 and 1 before).
    The slope-parts gate (wave83, ``decision.slope_parts_gate``: no one flat slope) came later
    and refuses two of the four on its own (uu_000001's, and the second of 1623721492790's):
    the range gate's share is measured with it off, and with it on the range gate's
    absence leaves two."""
    sets = sorted(p.parent for p in (HUNT_DATA / "hunt35").glob("*/labels.json"))
    rows = _unseen_rows(sets or [HUNT_DATA / "hunt35" / "none"], demo_model, "PLANEREL_HUNT_DATA")
    off = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA",
                       ["decision.range_gate=false", "decision.slope_parts_gate=false"])
    assert (_totals(off)["false_ramp"], _totals(rows)["false_ramp"]) == (4, 0)
    assert [n for n, r in rows.items() if r["false"]] == []
    assert sorted(n for n, r in off.items() if r["false"]) == [
        "1623721492790_depth", "uu_000000_depth", "uu_000001_depth"]
    parts = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA", ["decision.range_gate=false"])
    assert _totals(parts)["false_ramp"] == 2


def test_a_box_cut_at_a_registered_depth_images_blank_margin(demo_model):
    """margin36 (``$PLANEREL_HUNT_DATA/hunt33/ucn``: NVlabs/UnseenObjectClustering's RealSense
    frames, depth registered to colour, the first two rows blank).  In 000003 the cracker box
    standing at the back is seen as its front only, cut by the image's top edge at row 3 (the
    first measured row is 2): the top-row test allowed rows 0-2, so its top counted as in
    view and ``tall_face`` did not hold.  Counted from the first measured row
    (``_blank_top_rows``) it is ``box``; the set's other answers are unchanged (the tapered cup
    of 000008 was the one false box until grav53's ``refine_range``; docs/objects.md, "A blank
    margin at the image's top").
    Five boxes of the set are found: bin37's island faces added 000006's food container
    (:func:`test_a_flat_lid_with_a_depth_step_all_round_is_no_facet`)."""
    rows = _unseen_rows([HUNT_DATA / "hunt33" / "ucn"], demo_model, "PLANEREL_HUNT_DATA")
    assert len(rows) == 9
    assert [o["found"] for o in rows["000003-depth"]["objects"]] == [True]
    assert sum(o["found"] for r in rows.values() for o in r["objects"]) == 5
    # 000008's false box (a tapered cup by ``skirt``) held on an up 2.6 degrees off the table;
    # grav53's ``gravity.refine_range`` (near planes set the refinement) levels it: none left
    assert [name for name, r in rows.items() if r["false"]] == []


def test_hunt36_narrow_tops_of_noisy_frames_and_slender_tops(demo_model):
    """hunt36 (``$PLANEREL_HUNT_DATA/hunt36``: a development set of 2026-12-01).  tilt36:
    NVlabs/M2T2's RealSense scene02 shows a fruit-snacks box 1 m away whose 5 cm top strip
    fits at 11 degrees, past ``skirt_top_tilt``'s 10; the allowance its fit's RMS makes
    across the strip (``relations.skirt_top_noise``) lets it be the skirt's top: ``box``.
    slab36: andyzeng/apc-vision-toolbox's bin_b_12 (an F200 frame whose up is read 91 degrees
    off) made a leaning book's long strip a box top; the slenderness gate
    (``decision.slender_gate``) refuses it (docs/objects.md, "A narrow top tilted by the
    sensor's noise", "Thin walls and slabs are no boxes")."""
    m2t2, apc = HUNT_DATA / "hunt36" / "m2t2-real", HUNT_DATA / "hunt36" / "apc-shelf"
    rows = _unseen_rows([m2t2, apc], demo_model, "PLANEREL_HUNT_DATA")
    # face_pair off too (no pair is 91 degrees apart): the fruit-snacks box's two faces make
    # a face_pair, so with it on the box is found without its top (pair41)
    flat = _unseen_rows([m2t2], demo_model, "PLANEREL_HUNT_DATA",
                        ["relations.skirt_top_noise=0", "relations.face_pair_angle=91"])
    # the third box (a red Jell-O box lying on its side) is extend40's (the test below), the
    # fourth pair41's (face_pair: test_a_carton_seen_as_two_upright_faces_is_box)
    assert [o["found"] for o in rows["scene02_depth"]["objects"]] == [False, True, True, True]
    assert [o["found"] for o in flat["scene02_depth"]["objects"]] == [False, False, True, False]
    assert not rows["bin_b_12_depth"]["false"]
    off = _unseen_rows([apc], demo_model, "PLANEREL_HUNT_DATA", ["decision.slender_gate=false"])
    assert [f[0] for f in off["bin_b_12_depth"]["false"]] == ["box"]


def test_top_slope_is_measured_for_a_model_whose_clauses_read_it(demo_model, tmp_path):
    """ramp78: the shipped model's side-view clause reads ``top_slope/2``, so classifying
    measures it; the product stage's model has no such clause, and a comment naming it (a
    clause learning left out) asks for nothing."""
    from planerel.classify.classifier import Classifier

    products = demo_model.with_name(demo_model.name + "_products")
    commented = tmp_path / "commented"
    shutil.copytree(products, commented)
    with open(commented / "rules.pl", "a") as f:
        f.write("% left out: ramp(A) :- has_plane(A,B), top_slope(B,C), gteq(C,5).\n")
    flags = {}
    for name, model in (("shipped", demo_model), ("products", products),
                        ("commented", commented)):
        with Classifier(model) as clf:
            flags[name] = clf._describe_kw["top_slope"]
    assert flags == {"shipped": True, "products": False, "commented": False}


def test_product_boxes_small_faces_are_in_the_extended_models_domain(demo_model):
    """extend40: ``make demo`` learns the world without its product part first
    (``out/model_base``) and extends that theory on the product scenes (``learn_rules``'
    ``prior``): the same rules, whose proofs now reach product-size faces.  Two boxes seen as
    one small face (M2T2 scene02's red Jell-O box lying on its side, 0.0068 m^2; SAM-6D's
    LINEMOD carton, 0.0066 m^2) are ``box`` by the tall-face rule; the base model's proof gate
    refused them (its tall faces started at 0.037 m^2) (docs/objects.md, "Product boxes as an
    extension of the theory") until face52 (2026-12-02: narrow faces flat across are tall
    faces, so the base world's small boxes seen as one face are proved too): the base model
    finds both now.  The extension's ``face_pair`` clause still adds scene02's orange-juice
    carton, which the base model misses."""
    base = demo_model.with_name(demo_model.name + "_base")
    assert (base / "rules.pl").is_file()
    rules = [ln for ln in (demo_model / "rules.pl").read_text().splitlines()
             if ln.startswith(("box(", "stairs(", "ramp("))]
    # the base theory's clauses, kept; the product extension adds one face_pair clause
    # (pair41), the side-view stage one top_slope ramp clause and nothing else (ramp78)
    assert [r for r in rules if "face_pair(" not in r and "top_slope(" not in r] == [
        ln for ln in (base / "rules.pl").read_text().splitlines()
        if ln.startswith(("box(", "stairs(", "ramp("))]
    assert sum("face_pair(" in r for r in rules) == 1
    products = demo_model.with_name(demo_model.name + "_products")
    assert [r for r in rules if "top_slope(" not in r] == [
        ln for ln in (products / "rules.pl").read_text().splitlines()
        if ln.startswith(("box(", "stairs(", "ramp("))]
    assert [r.split(" :- ")[0] for r in rules if "top_slope(" in r] == ["ramp(A)"]
    m2t2 = HUNT_DATA / "hunt36" / "m2t2-real"
    lm = HUNT_DATA / "hunt39" / "sam6d-lm"
    found = {}
    for model in (demo_model, base):
        rows = _unseen_rows([m2t2, lm], model, "PLANEREL_HUNT_DATA")
        assert rows["scene02_depth"]["objects"][2]["found"]
        assert rows["lm_example_depth"]["objects"][0]["found"]
        assert [f[0] for f in rows["lm_example_depth"]["false"]] == ["box"]  # the cup, as before
        found[model] = rows["scene02_depth"]["objects"][3]["found"]       # the gable-top carton
    assert found == {demo_model: True, base: False}


def test_a_carton_seen_as_two_upright_faces_is_box(demo_model):
    """pair41: ryesw's snack carton (``$PLANEREL_HUNT_DATA/hunt39/ryesw-snackbox``, RealSense,
    0.6 m) seen level with its top half shows two upright faces (5.6-6.7 and 11-16 cm wide,
    86.5-88.9 degrees apart), no top and no horizontal plane: no rule of the base theory
    proves it.  The extension learns ``face_pair/2`` (aleph/modes_pair.pl, the extension's
    task only) from the product part's level views: views 1-3 are ``box``, by that clause;
    the base model finds none (docs/objects.md, "Two upright faces of one solid")."""
    sets = [HUNT_DATA / "hunt39" / "ryesw-snackbox"]
    base = demo_model.with_name(demo_model.name + "_base")
    rows = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA")
    old = _unseen_rows(sets, base, "PLANEREL_HUNT_DATA")
    rules = [ln for ln in (demo_model / "rules.pl").read_text().splitlines()
             if ln.startswith(("box(", "stairs(", "ramp("))]
    pair = 1 + next(i for i, r in enumerate(rules) if "face_pair(" in r)
    for view in ("view1_depth", "view2_depth", "view3_depth"):
        assert [tuple(r) for r in rows[view]["right"]] == [("box", pair)]
        assert not rows[view]["false"]
        assert [o["found"] for o in old[view]["objects"]] == [False]


def test_hunt39_a_monitors_round_foot_is_no_flat_box(demo_model):
    """fbox40 (``$PLANEREL_HUNT_DATA/hunt39/tum-fr2desk``: TUM RGB-D fr2/desk frames via
    cggos/rgbdslam_cg, Kinect v1).  In desk1 the monitor's round foot plate, 2.4 cm over the
    desk, was ``lying`` and the box rule ``lying + oblique_share`` proved it: its rise is only
    5.9 times its domed top's fit RMS (4.2 mm), every true lying box's 9.65 times or more.
    ``relations.lying_snr`` 7.5 (5 before) leaves it no ``lying`` top; desk2 keeps its answers
    (docs/objects.md, "A domed plate is no flat thing's top")."""
    sets = [HUNT_DATA / "hunt39" / "tum-fr2desk"]
    rows = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA")
    old = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA", ["relations.lying_snr=5"])
    assert [f[:2] for f in old["desk1_depth"]["false"]] == [("box", 3)]
    assert rows["desk1_depth"]["false"] == []
    assert rows["desk2_depth"]["false"] == old["desk2_depth"]["false"]


#: The archive box on the floor of office1.pcd, ~2 m away, standing against a tall cabinet
#: (hunt36's label): (column range, row range), full resolution.
OFFICE_BOX = ((475, 580), (370, 460))


def test_office_box_against_a_cabinet_is_a_box(demo_model):
    """skirt36: office1.pcd's white archive box stands against a tall cabinet whose front,
    parallel to the box's front, rises 1.2 m from the box's top with no tread on it.  It was
    read as a flight's next riser and denied the box's skirt; a plane rising more than
    ``relations.riser_rise_max`` with nothing at its top edge is no riser now: ``box``
    (docs/objects.md, "A wall behind a box is no next riser")."""
    if not OFFICE.is_file():
        pytest.skip(f"the office cloud is not at {OFFICE} (../shared/data/README.md)")
    from planerel.classify import Classifier
    from planerel.commands.classify import _params
    from planerel.io import read

    (c0, c1), (r0, r1) = OFFICE_BOX
    got = {}
    for name, params in (("now", []), ("off", ["relations.riser_rise_max=0"])):
        with Classifier(demo_model, seg_params=_params(params)) as clf:
            ans = clf.classify(read(OFFICE), scene_id="office1")
        on = [o for o in ans.objects
              if np.sum(_pixels(ans, o)[r0:r1, c0:c1]) > 0.5 * np.sum(_pixels(ans, o))
              and np.sum(_pixels(ans, o)) > 0]
        got[name] = sorted(o.klass for o in on)
        assert not {"stairs", "ramp"} & {o.klass for o in ans.objects}
        assert [o.klass for o in ans.objects].count("box") == len([k for k in got[name] if k == "box"])
    assert got["now"] == ["box"] and got["off"] == ["other"], got


def test_a_flat_lid_with_a_depth_step_all_round_is_no_facet(demo_model):
    """bin37 (``$PLANEREL_HUNT_DATA/hunt33/ucn``: NVlabs/UnseenObjectClustering's RealSense
    table-top frames, a development set of 2026-12-01).  000006's large plastic food container:
    its lid, a flat face wider than ``facet_max_width`` that touches none of the planes the
    facet rule linked it to (a depth step all round), was a strip of a curved surface with them,
    and the container one curved object no rule answered.  As an island it is a flat face
    (``CurvedParams.island_faces``): the container is ``box``; switched off, missed as before;
    no false answer either way (docs/objects.md, "A carton's top on a pile")."""
    sets = [HUNT_DATA / "hunt33" / "ucn"]
    rows = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA")
    off = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA", ["curved.island_faces=false"])
    assert [o["found"] for o in rows["000006-depth"]["objects"]] == [True]
    assert [o["found"] for o in off["000006-depth"]["objects"]] == [False]
    assert _totals(rows)["false_box"] == _totals(off)["false_box"]


def test_a_bin_seen_from_above_stands_on_its_floor(demo_model):
    """bin37 (``$PLANEREL_HUNT_DATA/hunt33/gqcnn``: BerkeleyAutomation/gqcnn's PhoXi frames of a
    tote seen from above, a development set of 2026-12-01).  The camera looks about 8 degrees
    from straight down into the tote, whose walls lean out by their draft, so no wall is
    vertical within 5 degrees; the estimate took the near wall for the floor (up = the camera's
    -y).  The walls facing each other across the tote vote for their mirror axis
    (``GravityParams.mirror_pairs``): phoxi_depth_1's and phoxi_depth_4's up lies within 3
    degrees of the tote floor's normal (-0.13..-0.15, 0, -0.99), with low confidence; switched
    off, the camera's -y as before (docs/gravity.md, "A bin seen from above")."""
    import dataclasses

    import planerel
    from planerel.classify.classifier import Classifier
    from planerel.features.facts import describe_scene
    from planerel.ilp.scenes import segment_cached

    folder = HUNT_DATA / "hunt33" / "gqcnn"
    if not (folder / "labels.json").is_file():
        pytest.skip(f"no labelled frames in {folder} (set PLANEREL_HUNT_DATA)")
    floor = np.array([-0.14, 0.0, -0.99]) / np.linalg.norm([-0.14, 0.0, -0.99])
    with Classifier(demo_model) as clf:
        kw = dict(clf._describe_kw)
        for name in ("phoxi_depth_1.npy", "phoxi_depth_4.npy"):
            cloud = planerel.read(folder / name, intrinsics="516,386,552.5,552.5,255.5,191.75",
                                  depth_scale=1)
            labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
            up = np.asarray(describe_scene(cloud, labels, scene_id="s", **kw).planes.up)
            assert np.degrees(np.arccos(np.clip(up @ floor, -1, 1))) < 3.0, (name, up)
            kw_off = {**kw, "gravity_params": dataclasses.replace(kw["gravity_params"],
                                                                  mirror_pairs=False)}
            up_off = np.asarray(describe_scene(cloud, labels, scene_id="s", **kw_off).planes.up)
            assert up_off @ np.array([0.0, -1.0, 0.0]) > 0.99, (name, up_off)


def test_a_ceiling_seen_from_the_floor_is_no_flight(demo_model):
    """hunt45 (``$PLANEREL_HUNT_DATA/hunt45``: a RealSense D435i on an RC car, 0.10 m over an
    office floor; an R200 and an Xtion 0.15-0.27 m up; a D415 0.52 m up): in donkeycar
    tub3_418 the ceiling, 2.4 m up and seen at grazing incidence, is level strips with steps
    between them (the disparity's terraces), which the demo's stairs clause proved (false
    stairs 1) until the side gate's stairs part refused it (treads all seen from below,
    docs/results.md "A flight's treads seen from below").  Since 65535 is read as no data
    the frame's gravity is another and no flight is proved there with or without the gate;
    no frame of the set may be answered ``stairs``."""
    sets = sorted(p.parent for p in (HUNT_DATA / "hunt45").glob("*/labels.json"))
    rows = _unseen_rows(sets or [HUNT_DATA / "hunt45" / "none"], demo_model,
                        "PLANEREL_HUNT_DATA")
    assert _totals(rows)["false_stairs"] == 0 and len(rows) == 23


def test_a_low_camera_under_an_unsure_up_with_no_floor_proves_no_ramp(demo_model):
    """ramp48 and the lead (``$PLANEREL_HUNT_DATA/hunt45``): in donkeycar tub3_418 (a D435i
    0.10 m over an office floor) the voted up (confidence 0.27, flagged low) is won by the far
    floor the sensor bends, no floor plane is left in view, and the near floor and two other
    planes are "inclined" 23-26 degrees: three false ramps the foot gate cannot check (no
    floor).  Each of two rules takes them alone: the floor under the camera sets a flagged up
    (``gravity.near_floor``, docs/gravity.md "The floor under a low camera"), and
    ``decision.unsure_gate`` refuses ``ramp`` under a low-confidence up with no floor in view.
    xtion_1's false ramp stays with those two (its estimate takes a wall for the floor, so a
    floor is in view: docs/results.md "False ramps on real sensors"); the floor's speckle
    (``gravity.sparse_floor``, sparse49: the Xtion 0.2 m up measures its floor only as
    scattered pixels) rights that up, and the wall is vertical.  The slope-parts gate
    (``decision.slope_parts_gate``, wave83: a ramp's quarters slope alike) is a third defence:
    alone it refuses xtion_1's false ramp and one of tub3_418's; the figures of the two rules
    are measured with it off."""
    sets = sorted(p.parent for p in (HUNT_DATA / "hunt45").glob("*/labels.json"))
    rows = _unseen_rows(sets or [HUNT_DATA / "hunt45" / "none"], demo_model,
                        "PLANEREL_HUNT_DATA")
    off = ["gravity.near_floor=0", "gravity.sparse_floor=0", "decision.slope_parts_gate=false"]
    neither = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA",
                           ["decision.unsure_gate=false", *off])
    gate = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA", off)
    parts = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA", ["decision.unsure_gate=false",
                                                                  *off[:2]])
    # (without either rule tub3_418 had a fourth false ramp from ramp78 to slope80: the
    # side-view stage's top_slope clause on a far face whose edge measured 6-19 degrees under
    # that up; an inclined plane beside it, far steeper than the edge, now takes the fact away)
    assert [_totals(r)["false_ramp"] for r in (neither, gate, parts, rows)] == [4, 1, 2, 0]
    assert [n for n, x in parts.items() if any(f[0] == "ramp" for f in x["false"])] == [
        "tub3_418_depth"]
    assert [n for n, x in gate.items() if any(f[0] == "ramp" for f in x["false"])] == [
        "xtion_1_depth"]
    assert sorted(f[1] for f in neither["tub3_418_depth"]["false"] if f[0] == "ramp") == [
        6, 6, 6]
    assert {k: v for k, v in _totals(neither).items() if k != "false_ramp"} == {
        k: v for k, v in _totals(gate).items() if k != "false_ramp"}


def test_a_ceiling_panel_under_an_upside_down_up_with_no_floor_is_no_ramp(demo_model):
    """up66 (``$PLANEREL_HUNT_DATA/hunt58/am-lab``: a Femto Bolt in a lab whose ceiling panels
    fill the image's top third, no floor in view): the estimate reads the room upside down
    (confidence 0.56, above ``gravity.low_confidence``) and a rough ceiling panel 22 degrees
    off under it is a ``ramp``; ``decision.unsure_upside`` counts the upside-down reading as
    unconfirmed, so the unsure gate refuses it.  Nothing else of the set moves."""
    sets = [HUNT_DATA / "hunt58" / "am-lab"]
    rows = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA")
    off = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA", ["decision.unsure_upside=false"])
    assert [f[0] for f in off["depth"]["false"]] == ["ramp"]
    assert not any(f[0] == "ramp" for r in rows.values() for f in r["false"])
    assert {k: v for k, v in _totals(rows).items() if k != "false_ramp"} == {
        k: v for k, v in _totals(off).items() if k != "false_ramp"}


def test_a_workbench_under_a_speckle_floor_up_with_no_floor_is_no_ramp(demo_model):
    """sparse85 (``$PLANEREL_HUNT_DATA/hunt57/sg-lab-box``: a workbench seen from 0.7 m in a
    397x300 crop, no floor in view): the estimate is decided by a speckle fit of the crop's
    low unassigned points (confidence 0.58, above ``gravity.low_confidence``), 18 degrees
    off, and the bench's top under it is a ``ramp``; ``decision.unsure_sparse`` counts such an
    estimate as unconfirmed with no floor plane in view, so the unsure gate refuses it.  The
    box is found either way, and nothing else of the set moves."""
    sets = [HUNT_DATA / "hunt57" / "sg-lab-box"]
    rows = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA")
    off = _unseen_rows(sets, demo_model, "PLANEREL_HUNT_DATA", ["decision.unsure_sparse=false"])
    assert [f[0] for f in off["bench_scene"]["false"]] == ["ramp"]
    assert not any(f[0] == "ramp" for r in rows.values() for f in r["false"])
    assert all(o["found"] for r in rows.values() for o in r["objects"])
    assert {k: v for k, v in _totals(rows).items() if k != "false_ramp"} == {
        k: v for k, v in _totals(off).items() if k != "false_ramp"}


def test_a_face_on_a_floor_measured_as_speckle_is_a_box(demo_model):
    """sparse49 (``$PLANEREL_HUNT_DATA/hunt45/mbot``: an R200 and an Xtion on a small robot
    0.17-0.24 m over the floor, which they measure only as scattered pixels): r200_dc4's carton
    front, the frame's only large plane, was read as the floor (88 degrees off); the floor's
    speckle rights the up (``gravity.sparse_floor``) and grounds the face (``relations.
    tall_speckle_floor``): the carton is found by ``tall_face``; with that and ground75's level
    ground (``relations.tall_level_ground``) off, it is lost (docs/objects.md "A floor seen only
    as speckle", "A box on a floor no plane took").  In the set as first labelled, xtion_1's wall seen under a
    table's top between its legs was a false box but for ``relations.tall_top_cover``; the set
    rebuilt after the machine's reset of 2026-12-02 (the frame read with the Xtion's standard
    intrinsics, 13 planes where the first build had 11) shows no such face, and the switch moves
    nothing here (its case is made in code in tests/test_speckle_floor.py)."""
    folder = HUNT_DATA / "hunt45" / "mbot"
    rows = _unseen_rows([folder], demo_model, "PLANEREL_HUNT_DATA")
    assert rows["r200_dc4_170421_depth"]["objects"][0]["found"]
    assert _totals(rows)["false_box"] == 0 and _totals(rows)["false_ramp"] == 0
    # the speckle in front of its foot grounds it too (ground75's tall_level_ground): with
    # the speckle floor off it is still found, with both off it is lost
    no_speckle = _unseen_rows([folder], demo_model, "PLANEREL_HUNT_DATA",
                              ["relations.tall_speckle_floor=0"])
    assert no_speckle["r200_dc4_170421_depth"]["objects"][0]["found"]
    no_ground = _unseen_rows([folder], demo_model, "PLANEREL_HUNT_DATA",
                             ["relations.tall_speckle_floor=0", "relations.tall_level_ground=0"])
    assert not no_ground["r200_dc4_170421_depth"]["objects"][0]["found"]
    no_cover = _unseen_rows([folder], demo_model, "PLANEREL_HUNT_DATA",
                            ["relations.tall_top_cover=0"])
    assert _totals(no_cover) == _totals(rows)


def test_cans_seen_as_facets_on_a_realsense_booth_are_no_boxes(demo_model):
    """cube53 (``$PLANEREL_HUNT_DATA/hunt43/rs-booth``: a RealSense D435i 0.57 m over a booth's
    table, one 13-14 cm cube a frame among 6-7 cm cans): the near cans' caps over a facet of
    their side were boxes by ``skirt`` (false box 7).  In 1020_test1 and test15 the facet's
    neighbour meets it at 57.8 and 42.2 degrees, alike in width, and no plane of the can meets
    it at a box's corner: ``decision.facet_gate`` refuses the box; in 1025_test9 a third strip
    meets the face at 85.2 degrees, but the strip between them is a facet of both
    (``decision.facet_bridge``): false box 4; every cube is found as before (docs/objects.md
    "Cans seen as two or three facets")."""
    folder = HUNT_DATA / "hunt43" / "rs-booth"
    rows = _unseen_rows([folder], demo_model, "PLANEREL_HUNT_DATA")
    off = _unseen_rows([folder], demo_model, "PLANEREL_HUNT_DATA", ["decision.facet_gate=false"])

    def false_boxes(r):
        return {n: sum(f[0] == "box" for f in x["false"]) for n, x in r.items()}

    on, was = false_boxes(rows), false_boxes(off)
    cans = {"booth_1020_test1_depth", "booth_test15_depth", "booth_1025_test9_depth"}
    assert {n for n in on if on[n] != was[n]} == cans
    assert all(was[n] - on[n] == 1 for n in cans) and sum(on.values()) == 4
    nobridge = _unseen_rows([folder], demo_model, "PLANEREL_HUNT_DATA",
                            ["decision.facet_bridge=false"])
    assert sum(false_boxes(nobridge).values()) == 5
    # 11: boxrec59's face_pair_graze adds 1021_test1's and 1025_test1's cubes (9 before)
    assert _totals(rows)["box_found"] == _totals(off)["box_found"] == 11


def test_a_cube_whose_side_is_seen_near_edge_on_is_a_face_pair(demo_model):
    """boxrec59 (``$PLANEREL_HUNT_DATA/hunt43/rs-booth``): the D435i smears a 7-10 cm cube's
    edge and turns a side seen 12-16 degrees from edge-on towards the camera, so its corner
    reads 82.3 (1021_test1) and 84.8 degrees (1025_test1); ``relations.face_pair_graze`` takes
    80 degrees there and rule 4 finds both cubes, with no false box added (docs/objects.md
    "Real boxes missed, cause by cause, by range, size and view")."""
    folder = HUNT_DATA / "hunt43" / "rs-booth"
    on = _unseen_rows([folder], demo_model, "PLANEREL_HUNT_DATA")
    off = _unseen_rows([folder], demo_model, "PLANEREL_HUNT_DATA",
                       ["relations.face_pair_graze=0"])
    gained = {n for n in on if [o["found"] for o in on[n]["objects"]]
              != [o["found"] for o in off[n]["objects"]]}
    assert gained == {"booth_1021_test1_depth", "booth_1025_test1_depth"}
    assert _totals(on)["box_found"] == _totals(off)["box_found"] + 2
    assert _totals(on)["false_box"] == _totals(off)["false_box"]


def test_a_ground_in_pieces_as_one_ground_finds_no_box_and_adds_a_false_one(demo_model):
    """ground56 (measured, not kept: ``relations.lying_ground_union`` stays off): hunt56's
    fw-tray tray_upright (``$PLANEREL_HUNT_DATA/hunt56/fw-tray``, a carton standing in a
    cardboard tray seen from 0.95 m above) is found without it: its top lies on the table
    plane that also takes the tray's floor, by lying56's banded ring, and the union changes
    nothing there.  On hunt39's sam6d-lm (a LINEMOD desk) the union of level pieces makes a
    0.09 x 0.16 m patch at the image's corner ``lying`` and rule 3 answers a false box."""
    tray, lm = HUNT_DATA / "hunt56" / "fw-tray", HUNT_DATA / "hunt39" / "sam6d-lm"
    off = _unseen_rows([tray, lm], demo_model, "PLANEREL_HUNT_DATA")
    on = _unseen_rows([tray, lm], demo_model, "PLANEREL_HUNT_DATA",
                      ["relations.lying_ground_union=true"])
    for rows in (off, on):
        assert [o["found"] for o in rows["tray_upright_depth"]["objects"]] == [True]
        assert [o["found"] for o in rows["tray_flat_depth"]["objects"]] == [True]
    assert _totals(on)["false_box"] == _totals(off)["false_box"] + 1
    assert _totals(on)["box_found"] == _totals(off)["box_found"]


def test_a_carpeted_flights_leaning_risers_make_its_steps(demo_model):
    """riser92: hunt92's carpeted flight (BundleFusion's apt0 stairs via fdp0525/G2LTex,
    Structure Sensor) seen close from its foot (depth_21: the lowest tread runs out of the
    image's bottom edge, the top tread is the landing). Its risers measure 11-13 degrees off
    vertical (the carpet runs from the nosing back to the tread below), beyond the treads'
    12-degree tilt: no step was seen.  Within ``proposals.riser_tilt`` (20) they are risers and
    the flight is ``stairs``; the other four frames' answers do not change and no false answer
    appears."""
    g2l = HUNT_DATA / "hunt92" / "g2l-apt0-stairs"
    now = _unseen_rows([g2l], demo_model, "PLANEREL_HUNT_DATA")
    old = _unseen_rows([g2l], demo_model, "PLANEREL_HUNT_DATA", ["proposals.riser_tilt=12"])
    assert [o["found"] for o in now["depth_21"]["objects"]] == [True]
    assert [o["found"] for o in old["depth_21"]["objects"]] == [False]
    for name in ("depth_01", "depth_25", "depth_28"):
        assert [o["found"] for o in now[name]["objects"]] == [True], name
    assert _totals(now)["false_box"] == _totals(old)["false_box"] == 0


def test_an_open_baskets_two_walls_are_no_flight(demo_model):
    """riser92: hidden26's wicker basket (boofcv-kinect, Kinect v1, seen from above its rim)
    was `stairs`: the near wall's outside, its face in pieces, paired its lower strip with the
    far wall's inside one stair rise and run away.  The near wall's surface goes on up to the
    rim the far wall ends at, where a flight's riser ends a rise under the next one's top
    (``proposals.riser_walls``): no false answer, and none with the old behaviour but that."""
    basket = HUNT_DATA / "hidden26" / "boofcv-kinect"
    now = _totals(_unseen_rows([basket], demo_model, "PLANEREL_HUNT_DATA"))
    off = _totals(_unseen_rows([basket], demo_model, "PLANEREL_HUNT_DATA",
                               ["proposals.riser_walls=false"]))
    assert now["false_stairs"] == 0 and off["false_stairs"] == 1, (now, off)
    assert now["false_box"] == off["false_box"] == 0
