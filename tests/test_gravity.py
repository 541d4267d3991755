"""Gravity (up vector) for any camera pitch and roll, its sources and its confidence.

Expected up vectors come from the camera poses the scenes are rendered with (two independent
renderers: tests/scenes_analytic.py and planerel.synth.gravity_scenes on planerel.synth.generator's ray
caster), never from the estimator itself.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from scenes_analytic import box, floor, render, stairs, wall

from planerel.cli import main
from planerel.errors import InputError
from planerel.features.gravity import (
    GravityParams,
    UpEstimate,
    estimate_gravity,
    resolve_up,
    up_from_cloud,
)
from planerel.features.planes import measure_planes
from planerel.io.cloud import Cloud
from planerel.synth.gravity_scenes import posed_scene


def _deg(a, b) -> float:
    """Signed-aware angle: a flipped up vector counts as 180 degrees off."""
    return math.degrees(math.acos(max(-1.0, min(1.0, float(np.dot(a, b))))))


@pytest.mark.parametrize("kind", ["box", "stairs", "ramp"])
def test_pose_grid_with_true_planes(kind):
    # pitch 0..80 (past the old 45-degree cone) and roll -20..20, Kinect-like noise
    errors = []
    for pitch in (0, 25, 50, 65, 80):
        for roll in (-20, 0, 20):
            s = posed_scene(kind, pitch, roll, seed=pitch * 7 + roll + 100, walls=1)
            est = up_from_cloud(s.cloud, s.gt_labels)
            assert est.source == "estimated"
            errors.append(_deg(est.vector, s.up))
    assert max(errors) <= 2.0, errors


def test_rolled_and_steep_analytic_scene():
    # the other renderer: camera pitched 60 degrees down and rolled 20 degrees
    rects = [floor(), wall()] + stairs(0.2, 2.0, 3) + box(-1.2, 2.6, 0.5, 0.5, 0.4, obj=2)
    for pitch, roll in ((60, 20), (75, -20), (10, -20)):
        cloud, lab, up, _ = render(rects, pitch=pitch, roll=roll, noise=0.0012, with_up=False,
                                   cam_height=1.5)
        assert _deg(up_from_cloud(cloud, lab).vector, up) <= 1.0
        assert _deg(up_from_cloud(cloud).vector, up) <= 3.0  # per-pixel normals, no labels


@pytest.mark.parametrize("pitch", [51, 65])
def test_staircase_from_above_segmented_treads_horizontal(pitch):
    # issue 15's case: a staircase seen from above, past the old 45-degree limit; the real
    # segmentation decides the planes, the estimate must land within 2 degrees
    from planerel.segment import segment

    s = posed_scene("stairs_from_above", pitch, 0, seed=3)
    est = up_from_cloud(s.cloud, segment(s.cloud).labels)
    assert _deg(est.vector, s.up) <= 2.0
    # measured with the estimated up, every seen tread is horizontal and measures what it
    # measures with the true up (what is left is the noise of its own plane fit)
    ps = measure_planes(s.cloud, s.gt_labels, up=est.vector)
    truth = measure_planes(s.cloud, s.gt_labels, up=s.up)
    # (slivers cut by the image border, under 10 cm across, have no reliable normal of their own)
    treads = [p for p in ps if s.roles[p.label] == "tread" and p.width >= 0.1]
    assert len(treads) >= 2
    for p in treads:
        assert p.orientation == "horizontal"
        assert abs(p.incline - truth.by_label(p.label).incline) <= 0.5


@pytest.mark.parametrize("pitch", [51, 70])
def test_staircase_from_above_realistic_kinect_one_horizontal_region_per_tread(pitch):
    # issue 15's staircase seen from above (tread normals 51 and 20 degrees from the optical
    # axis) by the realistic structured-light model (projector shadows, flying pixels, z^2
    # disparity quantisation) at the Kinect's native 640x480; seed 1: six steps, the most treads.
    # The truth is the renderer's: its pose (up) and its per-pixel plane labels.
    from planerel.segment import segment
    from planerel.synth.sensor import StructuredLight

    s = posed_scene("stairs_from_above", pitch, 0, seed=1, subsample=1, sensor=StructuredLight())
    seg = segment(s.cloud)
    est = up_from_cloud(s.cloud, seg.labels)
    assert _deg(est.vector, s.up) <= 2.0
    regions = {p.label: p for p in measure_planes(s.cloud, seg.labels, up=est.vector)}
    true = measure_planes(s.cloud, s.gt_labels, up=s.up)
    # treads at least 10 cm across (slivers cut by the image border have no reliable normal)
    treads = [p.label for p in true if s.roles[p.label] == "tread" and p.width >= 0.1]
    assert len(treads) >= 4
    for t in treads:
        m = s.gt_labels == t
        lab, cnt = np.unique(seg.labels[m], return_counts=True)
        cnt, lab = cnt[lab >= 0], lab[lab >= 0]
        main_region = int(lab[np.argmax(cnt)])
        # one region holds the tread: >= 90 % of its pixels, and no other region holds 5 %
        assert cnt.max() >= 0.9 * m.sum()
        assert np.sum(cnt >= 0.05 * m.sum()) == 1
        # ... lies on it (>= 95 % of the region's pixels) and is horizontal under the estimate
        assert cnt.max() >= 0.95 * np.sum(seg.labels == main_region)
        assert regions[main_region].orientation == "horizontal"
        assert regions[main_region].incline <= 3.0


def test_sign_looking_straight_down_and_level():
    for pitch in (0, 85):
        s = posed_scene("box", pitch, 0, seed=5, walls=0)
        est = up_from_cloud(s.cloud, s.gt_labels)
        assert _deg(est.vector, s.up) <= 2.0  # not the flipped vector


@pytest.mark.parametrize("tip", [0.003, -0.003, 0.0])
def test_a_board_seen_from_straight_above_is_the_floor_whichever_way_its_normal_tips(tip):
    """tote67 (hunt67's armlab frames): a board 1 m under a camera looking straight down, two
    pieces of it and a small inclined patch.  The normal's image-up component is a few
    thousandths either way; by its sign the candidate once read the camera as looking
    straight up, the pose prior refused it, and the board became a wall (up = the image's
    top).  Within 12 degrees of the optical axis the axis orients the candidate."""
    board = np.array([0.0, tip, -1.0])
    board /= np.linalg.norm(board)
    patch = np.array([0.0, -0.74, -0.67])
    est = estimate_gravity([board, board, patch / np.linalg.norm(patch)], [1.46, 0.62, 0.035],
                           [1.0, 0.97, 0.47])
    assert _deg(est.vector, board) < 1.0, est


@pytest.mark.parametrize("tip", [0.008, -0.008])
def test_a_board_under_towers_and_a_wall_strip_is_the_floor(tip):
    """hunt90 lk-armlab stacks (measured planes, rounded): a board 1 m under a camera looking
    straight down, the wall behind it along the image's top (its normal towards the image's
    bottom) and the sides of cube towers.  Those planes are upright to the board; they once
    kept the board's candidate oriented by the image's top (looking up, refused by the prior),
    and the image's top won: the wall strip a ceiling 0.3 m over a level camera, 91 degrees
    off.  Only an upright plane facing the image's top (a floor strip under a level camera's
    wall) keeps that reading now."""
    board = np.array([-0.016, tip, -1.0])
    board /= np.linalg.norm(board)
    normals = [board, (-0.003, 0.998, -0.059), (-0.002, 1.0, 0.013), board,
               (0.998, 0.044, -0.052), (0.988, -0.024, -0.15), (0.158, 0.987, 0.004)]
    normals = [np.asarray(n, float) / np.linalg.norm(n) for n in normals]
    areas = [0.65, 0.35, 0.12, 0.076, 0.037, 0.013, 0.013]
    offsets = [0.99, 0.29, 0.30, 1.03, 0.69, 0.68, 0.39]
    est = estimate_gravity(normals, areas, offsets)
    assert _deg(est.vector, board) < 1.0, est
    if tip < 0:
        return  # the candidate already looks down: the image's top never oriented it
    # the same planes with the strip facing the image's top: a floor strip under a level
    # camera facing a wall (the board), read as before
    flipped = [n if i in (0, 3) else n * np.array([1.0, -1.0, 1.0]) for i, n in enumerate(normals)]
    level = estimate_gravity(flipped, areas, offsets)
    assert _deg(level.vector, board) > 80.0, level


def test_confidence_high_for_a_room_low_for_degenerate_scenes():
    rects = [floor(), wall()] + box(-0.5, 2.6, 0.6, 0.5, 0.4)
    cloud, lab, _, _ = render(rects, pitch=30, with_up=False)
    rich = up_from_cloud(cloud, lab)
    assert rich.confidence >= 0.7 and not rich.low_confidence
    # a single plane: a floor or a wall, nothing cross-checks it
    cloud, lab, up, _ = render([floor()], pitch=30, with_up=False)
    single = up_from_cloud(cloud, lab)
    assert single.low_confidence and single.confidence < 0.5
    assert _deg(single.vector, up) <= 1.0  # still the best guess
    # a wall alone, seen head-on, is a floor seen from straight above as far as depth goes
    cloud, lab, _, _ = render([wall(y=2.0)], pitch=0, with_up=False)
    assert up_from_cloud(cloud, lab).low_confidence
    # a wall alone 4.5 m away (too far below a camera to be its floor): up from the roll prior
    cloud, lab, up, _ = render([wall(y=4.5, w=8.0)], pitch=0, cam_height=1.3, with_up=False)
    alone = up_from_cloud(cloud, lab)
    assert alone.confidence <= 0.2 and _deg(alone.vector, up) <= 1.0
    # nothing at all: the default, confidence 0
    empty = up_from_cloud(cloud, np.full(lab.shape, -1, np.int32))
    assert empty.source == "default" and empty.confidence == 0.0
    np.testing.assert_allclose(empty.vector, (0, -1, 0))


def test_far_wall_is_not_taken_for_a_floor():
    # a level camera facing a big wall 4.5 m away with a small table top below it: read
    # as a camera looking straight down at a floor, the "floor" would be 4.5 m below it
    rects = [wall(y=4.5, w=8.0, h=3.0),
             type(floor())((0.0, 2.0, 0.8), (1, 0, 0), (0, 1, 0), 0.5, 0.3)]
    cloud, lab, up, _ = render(rects, pitch=0, cam_height=1.3, with_up=False)
    assert _deg(up_from_cloud(cloud, lab).vector, up) <= 1.0
    near = GravityParams(max_height=10.0)  # without the prior the wall wins by area
    assert _deg(up_from_cloud(cloud, lab, near).vector, up) > 45.0


def test_estimate_gravity_from_normals_directly():
    up = np.array([0.0, -0.6, -0.8])
    wall_n = np.array([0.0, -0.8, 0.6])
    side_n = np.cross(up, wall_n)
    est = estimate_gravity([up, wall_n, side_n], [3.0, 1.0, 1.0], [1.2, 2.0, 1.5])
    assert _deg(est.vector, up) < 1e-6 and est.n_planes == 3
    with pytest.raises(InputError, match="one weight per normal"):
        estimate_gravity([up, wall_n], [1.0])
    with pytest.raises(InputError, match="tol_deg"):
        GravityParams(tol_deg=-1)
    with pytest.raises(InputError, match="source"):
        UpEstimate(up, "guessed", 1.0)


def test_sources_given_file_estimated():
    cloud, lab, up, _ = render([floor(), wall()], pitch=40, with_up=True)
    assert resolve_up(cloud, lab).source == "file"
    given = resolve_up(cloud, lab, up=(0, 0, -3))
    assert given.source == "given" and given.confidence == 1.0
    np.testing.assert_allclose(given.vector, (0, 0, -1))
    est = resolve_up(cloud.with_up(None), lab)
    assert est.source == "estimated" and _deg(est.vector, up) <= 1.0
    ps = measure_planes(cloud.with_up(None), lab)
    assert ps.up_source == "estimated" and ps.up_estimate.to_dict()["source"] == "estimated"


def _write_ascii_pcd(path, xyz):
    h, w = xyz.shape[:2]
    head = (f"# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
            f"WIDTH {w}\nHEIGHT {h}\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {w * h}\nDATA ascii\n")
    rows = "\n".join(" ".join(f"{v:.6f}" if np.isfinite(v) else "nan" for v in p)
                     for p in xyz.reshape(-1, 3))
    path.write_text(head + rows + "\n")


def test_sidecar_up_for_pcd_and_ply(tmp_path):
    from planerel.io import readers as io
    from planerel.io.writers import write_ply

    cloud, _, _, _ = render([floor()], width=16, height=12)
    _write_ascii_pcd(tmp_path / "scan.pcd", cloud.xyz)
    write_ply(tmp_path / "pts.ply", cloud.xyz)
    assert io.read(tmp_path / "scan.pcd").up is None
    (tmp_path / "scan.json").write_text(json.dumps({"up": [0, -2, 0]}))
    (tmp_path / "pts.json").write_text(json.dumps({"up": [0, 0, -1]}))
    np.testing.assert_allclose(io.read(tmp_path / "scan.pcd").up, (0, -1, 0))
    np.testing.assert_allclose(io.read(tmp_path / "pts.ply").up, (0, 0, -1))
    (tmp_path / "pts.json").write_text(json.dumps({"up": [0, 0, 0]}))
    with pytest.raises(InputError, match=r"pts\.json: 'up' must not be the zero vector"):
        io.read(tmp_path / "pts.ply")


def test_cli_reports_up_in_planes_json_and_facts(tmp_path):
    s = posed_scene("box", 60, 10, seed=11, walls=1)
    np.save(tmp_path / "scan.npy", s.cloud.xyz)
    out = tmp_path / "seg"
    assert main(["segment", str(tmp_path / "scan.npy"), "-o", str(out)]) == 0
    up = json.loads((out / "scan.planes.json").read_text())["up"]
    assert up["source"] == "estimated" and 0.0 <= up["confidence"] <= 1.0
    assert _deg(up["vector"], s.up) <= 2.0
    assert main(["segment", str(tmp_path / "scan.npy"), "-o", str(out), "--up", "0,-1,0"]) == 0
    up = json.loads((out / "scan.planes.json").read_text())["up"]
    assert up == {"vector": [0.0, -1.0, 0.0], "source": "given", "confidence": 1.0}
    (tmp_path / "scan.json").write_text(json.dumps({"up": [float(x) for x in s.up]}))
    facts = tmp_path / "f.pl"
    assert main(["describe", str(tmp_path / "scan.npy"), "-o", str(facts), "--ids", "s0001"]) == 0
    line = next(ln for ln in facts.read_text().splitlines() if ln.startswith("% s0001: up ["))
    assert line.endswith("file, confidence 1.00")


@pytest.mark.parametrize("bad,match", [("1,2", "three numbers"), ("0,0,0", "zero vector"),
                                       ("nan,0,1", "finite"), ("a,b,c", "three numbers")])
def test_bad_up_is_one_line_error(tmp_path, bad, match):
    np.save(tmp_path / "scan.npy", np.zeros((4, 4, 3)) + [0.0, 0.0, 1.0])
    r = subprocess.run([sys.executable, "-m", "planerel.cli", "segment", str(tmp_path / "scan.npy"),
                        "-o", str(tmp_path / "o"), f"--up={bad}"], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 2
    assert r.stderr.strip().count("\n") == 0 and "Traceback" not in r.stderr
    assert "--up" in r.stderr and match in r.stderr


def test_deterministic():
    s = posed_scene("stairs", 55, -15, seed=9)
    t = posed_scene("stairs", 55, -15, seed=9)
    assert np.array_equal(s.cloud.xyz, t.cloud.xyz, equal_nan=True)
    a, b = up_from_cloud(s.cloud, s.gt_labels), up_from_cloud(t.cloud, t.gt_labels)
    assert np.array_equal(a.vector, b.vector) and a.confidence == b.confidence
    with pytest.raises(InputError, match="pitch"):
        posed_scene("box", 95, 0)
    assert isinstance(s.cloud, Cloud) and s.cloud.up is None


def test_classify_reports_the_up_source_and_confidence(tmp_path):
    from planerel.classify.classifier import Classifier

    rules = tmp_path / "rules.pl"
    rules.write_text("box(O) :- nplanes(O, N), gteq(N, 1).\n")
    s = posed_scene("box", 55, 5, seed=21, walls=1)
    with Classifier(rules) as clf:
        est = clf.classify(s.cloud, scene_id="s0001").to_dict()
        given = clf.classify(s.cloud, scene_id="s0002", up=s.up).to_dict()
    assert est["up"] == "estimated" and 0.5 <= est["up_confidence"] <= 1.0
    assert given["up"] == "given" and given["up_confidence"] == 1.0
    # the up vector used, and the floor plane the answer stands on
    assert np.allclose(given["up_vector"], s.up / np.linalg.norm(s.up), atol=1e-6)
    assert abs(np.linalg.norm(est["up_vector"]) - 1.0) < 1e-6
    assert np.degrees(np.arccos(np.clip(np.dot(est["up_vector"], given["up_vector"]), -1, 1))) < 5
    for d in (est, given):
        assert d["up_low_confidence"] is False and d["up_upside_down"] is False
        assert d["floor"] is not None and d["floor"].startswith(d["scene"] + "_p")


def test_classify_says_when_no_floor_is_in_view(tmp_path, capsys):
    """A camera near the floor whose floor returns no depth (a Kinect lying on the floor):
    a wall and a box's front, no floor plane, and the answer says what that costs, in the
    JSON and in the text (a note under the scan's line).  The camera's up is given: estimated,
    a level camera facing only upright planes reads the wall as a floor under a camera
    looking straight down (docs/gravity.md)."""
    from planerel.classify.classifier import Classifier

    rules = tmp_path / "rules.pl"
    rules.write_text("box(O) :- nplanes(O, N), gteq(N, 1).\n")
    cloud, _, _, _ = render([wall(y=2.0)] + box(0.0, 1.6, 0.4, 0.3, 0.5), pitch=0,
                            cam_height=0.3, width=320, height=240, with_up=False)
    with Classifier(rules) as clf:
        ans = clf.classify(cloud, scene_id="w", up=np.array([0.0, -1.0, 0.0]))
    d = ans.to_dict()
    assert d["floor"] is None and any("no floor plane" in n for n in ans.notes())
    np.save(tmp_path / "wall.npy", cloud.xyz)
    assert main(["classify", str(rules), str(tmp_path / "wall.npy"), "--up", "0,-1,0"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert "up given" in out[0] and out[0].endswith("no floor plane")
    assert out[1].startswith("  note: no floor plane in view")
    # with a floor under the box there is one, and no note
    cloud, _, _, _ = render([floor(), wall(y=2.0)] + box(0.0, 1.6, 0.4, 0.3, 0.5), pitch=20,
                            cam_height=1.0, width=320, height=240, with_up=False)
    with Classifier(rules) as clf:
        ans = clf.classify(cloud, scene_id="f")
    assert ans.floor is not None and ans.notes() == []
