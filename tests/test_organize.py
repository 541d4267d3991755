"""Unorganized clouds put on an image grid (planerel.io.organize): a z-buffer projection from
the sensor's origin, so the whole pipeline runs on them as on a depth frame."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from scenes_analytic import box, floor, render, wall

from planerel.cli import main
from planerel.errors import InputError, PlanerelError, PlanerelWarning
from planerel.io import readers as io
from planerel.io.cloud import Cloud, Intrinsics
from planerel.io.organize import organize, viewpoint_transform
from planerel.io.writers import write_ply

_DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def _scene(width=320, height=240):
    rects = [floor(), wall(), *box(0.0, 2.6, 0.6, 0.5, 0.45)]
    cloud, labels, _up, _obj = render(rects, pitch=25.0, width=width, height=height)
    return cloud, labels


def _unorganized(cloud, seed=0, jitter=0.0005):
    pts = cloud.xyz.reshape(-1, 3)
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    rng = np.random.default_rng(seed)
    return pts[rng.permutation(len(pts))] + rng.normal(0.0, jitter, pts.shape)


def _planes(cloud):
    """(normal, offset) of the segmented planes with >= 300 points, largest first."""
    from planerel.segment import segment

    seg = segment(cloud)
    out = []
    for p in sorted(seg.planes, key=lambda p: -p.n_points):
        if p.n_points >= 300:
            out.append((np.asarray(p.normal), float(p.offset)))
    return out


def test_shuffled_jittered_cloud_comes_back_on_a_grid_with_the_same_planes():
    cloud, _labels = _scene()
    pts = _unorganized(cloud)
    grid = organize(pts)
    intr = grid.intrinsics
    assert grid.xyz.shape == (intr.height, intr.width, 3)
    assert max(intr.width, intr.height) <= 640 and intr.fx == intr.fy
    # about the camera's own pixel (Kinect 525 at 640 -> 262.5 at 320), never finer
    assert 0.4 * 262.5 < intr.fx <= 1.05 * 262.5
    on = np.isfinite(grid.xyz[..., 2])
    assert on.sum() + grid.n_hidden == grid.n_points == len(pts)
    # every point on the grid is an input point, in the pixel its ray falls in
    r, c = np.nonzero(on)
    q = grid.xyz[r, c]
    assert np.all(np.abs(intr.fx * q[:, 0] / q[:, 2] + intr.cx - c) <= 0.5 + 1e-9)
    assert np.all(np.abs(intr.fy * q[:, 1] / q[:, 2] + intr.cy - r) <= 0.5 + 1e-9)
    # the planes found on it are the organized frame's: floor, wall, box top and faces
    got = _planes(Cloud(grid.xyz, intr, cloud.up, "grid"))
    want = _planes(cloud)
    assert len(got) >= 4
    for n, d in want[:4]:
        best = min(got, key=lambda g: 10 * (1 - abs(float(g[0] @ n))) + abs(abs(g[1]) - abs(d)))
        assert abs(float(best[0] @ n)) > np.cos(np.radians(3.0))
        assert abs(abs(best[1]) - abs(d)) < 0.02


def test_order_does_not_matter():
    cloud, _ = _scene(160, 120)
    pts = _unorganized(cloud, seed=1)
    # two points in one pixel at the same depth: the tie goes by x, then y, in any order
    twin = pts[0] * [1.0 + 1e-6, 1.0, 1.0]
    pts = np.vstack([pts, twin, pts[:50]])  # and repeated points
    a = organize(pts)
    for seed in (2, 3):
        b = organize(pts[np.random.default_rng(seed).permutation(len(pts))])
        assert a.intrinsics == b.intrinsics
        assert np.array_equal(a.xyz, b.xyz, equal_nan=True)
    labels = np.arange(len(pts))
    placed = a.place(labels, -1)
    assert np.array_equal(a.xyz[placed >= 0], pts[placed[placed >= 0]])


def test_given_intrinsics_and_points_outside():
    cloud, _ = _scene(160, 120)
    pts = _unorganized(cloud, jitter=0.0)
    intr = Intrinsics.kinect(160, 120)
    grid = organize(pts, intr)
    assert grid.intrinsics == intr and not grid.chosen and grid.n_outside == 0
    # an exact back-projection on its own camera: every pixel gets its own point back
    assert np.allclose(grid.xyz, cloud.xyz, equal_nan=True)
    small = Intrinsics(80, 60, intr.fx, intr.fy, intr.cx, intr.cy)
    part = organize(pts, small)
    assert part.n_outside > 0 and part.xyz.shape == (60, 80, 3)


def test_a_360_degree_cloud_and_points_behind_are_refused_clearly():
    rng = np.random.default_rng(0)
    ang = rng.uniform(-np.pi, np.pi, 5000)
    sweep = np.stack([5 * np.sin(ang), rng.uniform(-1, 1, 5000), 5 * np.cos(ang)], axis=1)
    with pytest.raises(InputError, match="behind the sensor.*--no-organize"):
        organize(sweep, where="lidar.ply")
    # a dome in front of the sensor, 170 degrees wide: no one camera view
    dome = np.stack([np.tan(np.radians(85)) * np.cos(ang), 0.3 * np.sin(ang), np.ones(5000)], axis=1)
    with pytest.raises(InputError, match="degrees.*one view.*--no-organize"):
        organize(dome, where="dome.ply")
    front = np.array([[0.0, 0.0, 1.0]] * 10 + [[0.1, 0.0, -0.5]])
    with pytest.raises(PlanerelError, match="1 of 11 points.*behind"):
        organize(front)


def test_points_at_the_origin_are_invalid_not_behind():
    # exports write an invalid pixel as 0 0 0: left out, like NaN rows, not "behind the sensor"
    cloud, _ = _scene(160, 120)
    pts = _unorganized(cloud, seed=4)
    zeros = np.vstack([np.zeros((40, 3)), pts])
    a, b = organize(pts), organize(zeros)
    assert a.intrinsics == b.intrinsics and a.n_points == b.n_points
    assert np.array_equal(a.xyz, b.xyz, equal_nan=True)
    assert (b.rows[:40] == -1).all()
    with pytest.raises(InputError, match="no valid point"):
        organize(np.zeros((5, 3)))


def test_viewpoint_moves_the_points_into_the_sensor_frame():
    cloud, _ = _scene(160, 120)
    pts = _unorganized(cloud, jitter=0.0)
    # the sensor 1 m along x, turned 90 degrees about y: points given in that other frame
    t = np.array([1.0, 0.0, 0.0])
    h = np.sqrt(0.5)
    vp = (*t, h, 0.0, h, 0.0)
    c, s = 0.0, 1.0
    r = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    world = pts @ r.T + t
    assert np.allclose(viewpoint_transform(world, vp), pts, atol=1e-9)
    a, b = organize(pts), organize(world, viewpoint=vp)
    assert a.intrinsics == b.intrinsics
    assert np.allclose(a.xyz, b.xyz, atol=1e-9, equal_nan=True)


def test_readers_organize_unless_told_not_to(tmp_path):
    import pypcd4

    cloud, _ = _scene(160, 120)
    pts = _unorganized(cloud).astype(np.float32)
    lab = np.arange(len(pts), dtype=np.uint32)
    pc = pypcd4.PointCloud.from_points([pts[:, 0], pts[:, 1], pts[:, 2], lab],
                                       ("x", "y", "z", "label"),
                                       (np.float32, np.float32, np.float32, np.uint32))
    path = tmp_path / "scan.pcd"
    pc.save(path, encoding=pypcd4.Encoding.BINARY)
    with pytest.warns(PlanerelWarning, match="image grid"):
        c = io.read(path)
    assert c.organized and c.intrinsics is not None
    field = io.read_pcd_field(path, "label")
    assert field.shape == c.shape
    hit = field > 0
    assert np.allclose(c.xyz[hit], pts[field[hit]], atol=1e-6)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        raw = io.read(path, organize=False)
    assert not raw.organized and raw.shape == (1, len(pts))
    assert io.read_pcd_field(path, "label", organize=False).shape == (1, len(pts))
    # the user's camera
    with pytest.warns(PlanerelWarning, match="as given"):
        k = io.read(path, intrinsics=(160, 120, 131.25, 131.25, 79.5, 59.5))
    assert k.shape == (120, 160)


def test_ply_round_trip_through_cli_classify(tmp_path, capsys):
    cloud, _ = _scene()
    pts = _unorganized(cloud)
    write_ply(tmp_path / "scene.ply", pts)
    rules = tmp_path / "rules.pl"
    rules.write_text("box(A) :- nvertical(A, B), B >= 1.\n")
    np.save(tmp_path / "organized.npy", cloud.xyz)
    assert main(["classify", str(rules), str(tmp_path / "organized.npy"), "-j", "1"]) == 0
    want = [ln.split(":")[1].split()[0] for ln in capsys.readouterr().out.splitlines()
            if ln.startswith("  organized_o")]
    assert want == ["box"]
    assert main(["classify", str(rules), str(tmp_path / "scene.ply"), "-j", "1"]) == 0
    cap = capsys.readouterr()
    assert "note:" in cap.err and "image grid" in cap.err and "--no-organize" in cap.err
    assert "unorganized cloud (no image grid" not in cap.out
    got = [ln.split(":")[1].split()[0] for ln in cap.out.splitlines() if ln.startswith("  scene_o")]
    assert got == want
    # describe takes it now; --no-organize keeps the old behaviour (and describe refuses it)
    assert main(["describe", str(tmp_path / "scene.ply"), "-o", str(tmp_path / "f.pl")]) == 0
    assert "plane(" in (tmp_path / "f.pl").read_text()
    assert main(["classify", str(rules), str(tmp_path / "scene.ply"), "-j", "1",
                 "--no-organize"]) == 0
    assert "an unorganized cloud (no image grid" in capsys.readouterr().out
    # a cloud that is no one view: one line, exit 2, saying what to do
    write_ply(tmp_path / "around.ply", np.vstack([pts, -pts]))
    assert main(["classify", str(rules), str(tmp_path / "around.ply"), "-j", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "behind the sensor" in err and "--no-organize" in err


@pytest.mark.skipif(not (_DATA / "mosd").is_dir(), reason="needs ../shared/data")
def test_real_learn0_shuffled_answers_box_box(tmp_path):
    import pypcd4

    from planerel.classify.classifier import Classifier

    model = Path(__file__).resolve().parents[1] / "out" / "model"
    if not (model / "rules.pl").is_file():
        model = Path("/work/main/out/model")
    if not (model / "rules.pl").is_file():
        pytest.skip("needs a learned model (make demo)")
    pc = pypcd4.PointCloud.from_path(_DATA / "mosd" / "learn0.pcd")
    xyz = np.asarray(pc.numpy(("x", "y", "z")), dtype=np.float64)
    xyz = xyz[np.all(np.isfinite(xyz), axis=1)]
    rng = np.random.default_rng(0)
    pts = (xyz[rng.permutation(len(xyz))] + rng.normal(0, 0.0005, xyz.shape)).astype(np.float32)
    path = tmp_path / "learn0.pcd"
    pypcd4.PointCloud.from_xyz_points(pts).save(path, encoding=pypcd4.Encoding.BINARY)
    with pytest.warns(PlanerelWarning):
        cloud = io.read(path)
    with Classifier(model) as clf:
        ans = clf.classify(cloud, scene_id="learn0")
    assert [o.klass for o in ans.objects] == ["box", "box"]
