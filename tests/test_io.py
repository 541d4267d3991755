"""Readers, writers, Cloud and Intrinsics: real files from ../shared/data and files made here."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from planerel.errors import InputError, PlanerelError, PlanerelWarning
from planerel.io import readers as io
from planerel.io.cloud import KINECT, Cloud, Intrinsics, depth_to_cloud, subsample
from planerel.io.writers import (
    colour_labels,
    write_depth_png,
    write_json,
    write_labels_npy,
    write_labels_png,
    write_ply,
)

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"
needs_data = pytest.mark.skipif(not DATA.is_dir(), reason=f"real data not found at {DATA}")


def _plane_depth(h=48, w=64, z0=1.5):
    """A depth image (mm) of a plane tilted about the x axis, and its intrinsics."""
    intr = Intrinsics(w, h, 60.0, 60.0, (w - 1) / 2, (h - 1) / 2)
    v = np.arange(h)[:, None] * np.ones((1, w))
    z = z0 + 0.004 * (v - h / 2)
    return np.round(z * 1000).astype(np.uint16), intr


# ----------------------------------------------------------------- real files


@needs_data
@pytest.mark.parametrize("name", sorted(p.name for p in (DATA / "kinect").glob("*_depth.tiff")))
def test_kinect_tiff_frames(name):
    cloud = io.read(DATA / "kinect" / name)
    assert cloud.shape == (480, 640)
    assert cloud.intrinsics == Intrinsics(640, 480, 525, 525, 320, 240)  # from the OpenNI XML
    z = cloud.depth[cloud.valid]
    assert 0.66 < z.min() < 0.68 and 1.70 < z.max() < 1.74
    assert 0.80 < cloud.valid.mean() < 0.95  # ~12% invalid
    # back-projection: x = (u - cx) z / fx
    v, u = np.nonzero(cloud.valid)
    i = len(u) // 2
    x, y, zz = cloud.xyz[v[i], u[i]]
    assert x == pytest.approx((u[i] - 320) * zz / 525)
    assert y == pytest.approx((v[i] - 240) * zz / 525)


@needs_data
def test_office_pcd_binary_compressed():
    cloud = io.read(DATA / "kinect" / "office1.pcd")
    assert cloud.organized and cloud.shape == (480, 640)
    z = cloud.depth[cloud.valid]
    assert 1.8 < z.min() < 1.9 and 5.3 < z.max() < 5.4
    intr = cloud.intrinsics
    assert (intr.fx, intr.fy, intr.cx, intr.cy) == pytest.approx((525, 525, 320, 240), abs=1e-3)


@needs_data
@pytest.mark.parametrize("name", ["learn0.pcd", "learn5.pcd", "test31.pcd"])
def test_mosd_pcd_and_labels(name):
    path = DATA / "mosd" / name
    cloud = io.read(path)
    assert cloud.shape == (480, 640)
    intr = cloud.intrinsics
    assert (intr.cx, intr.cy) == pytest.approx((319.5, 239.5), abs=1e-3)
    z = cloud.depth[cloud.valid]
    assert 0.3 < z.min() and z.max() < 3.0
    labels = io.read_pcd_field(path, "label")
    assert labels.shape == (480, 640)
    objects = set(np.unique(labels[labels >= 20]) // 10)
    assert len(objects) >= 1
    # label 0 marks invalid points
    assert not cloud.valid[labels == 0].any()


@needs_data
@pytest.mark.parametrize("n", [0, 3])
def test_abw_range_and_ground_truth(n):
    cloud = io.read(DATA / "abw" / f"abw.test.{n}.range")
    assert cloud.shape == (512, 512)
    frac_invalid = 1 - cloud.valid.mean()
    assert 0.15 < frac_invalid < 0.40  # shadows: 19-37% of pixels
    z = cloud.depth[cloud.valid]
    assert 0.75 < z.min() and z.max() < 1.15  # metres from the sensor
    gt = io.read_abw_gt(DATA / "abw" / f"abw.test.{n}.gt-seg")
    assert gt.shape == (512, 512) and gt.dtype == np.int32
    planes = np.unique(gt[gt >= 0])
    assert planes.min() >= 10 and len(planes) >= 5
    assert io.read_label_image(DATA / "abw" / f"abw.test.{n}.gt-seg").tolist() == gt.tolist()


@needs_data
def test_abw_plane_is_planar():
    """A ground-truth plane of an ABW image back-projects onto a plane (mm-level residual)."""
    cloud = io.read(DATA / "abw" / "abw.test.0.range")
    gt = io.read_abw_gt(DATA / "abw" / "abw.test.0.gt-seg")
    labels, counts = np.unique(gt[(gt >= 0) & cloud.valid], return_counts=True)
    big = labels[np.argmax(counts)]
    pts = cloud.xyz[(gt == big) & cloud.valid]
    centred = pts - pts.mean(axis=0)
    rms = np.linalg.svd(centred, full_matrices=False)[1][-1] / np.sqrt(len(pts))
    assert rms < 0.002


# ----------------------------------------------------------------- files made here


def test_depth_png_with_sidecar_json(tmp_path):
    depth, intr = _plane_depth()
    write_depth_png(tmp_path / "f.depth.png", depth)
    write_json(tmp_path / "f.json", {"intrinsics": intr.to_dict(), "depth_scale": 1000,
                                     "up": [0, -1, 0]})
    cloud = io.read(tmp_path / "f.depth.png")
    assert cloud.intrinsics == intr
    assert cloud.up.tolist() == [0, -1, 0]
    assert np.nanmax(np.abs(cloud.depth - depth / 1000.0)) < 1e-12


def test_depth_png_with_explicit_intrinsics_and_scale(tmp_path):
    depth, intr = _plane_depth()
    write_depth_png(tmp_path / "d.png", depth * 5)  # TUM-style 5000 per metre
    cloud = io.read(tmp_path / "d.png", intrinsics=(intr.width, intr.height, intr.fx, intr.fy,
                                                   intr.cx, intr.cy), depth_scale=5000)
    assert np.nanmax(np.abs(cloud.depth - depth / 1000.0)) < 1e-9


def test_kinect_preset_scales_with_size(tmp_path):
    depth = np.full((120, 160), 1500, np.uint16)
    write_depth_png(tmp_path / "k.png", depth)
    cloud = io.read(tmp_path / "k.png", intrinsics="kinect")
    assert cloud.intrinsics == KINECT.scaled(4)
    assert cloud.intrinsics.fx == pytest.approx(131.25)


def test_tiff_written_by_tifffile(tmp_path):
    import tifffile

    depth, intr = _plane_depth()
    tifffile.imwrite(tmp_path / "t.tiff", depth)  # the real frames cover PackBits
    cloud = io.read(tmp_path / "t.tiff", intrinsics=intr)
    assert cloud.n_valid == depth.size


@pytest.mark.parametrize("encoding", ["ascii", "binary", "binary_compressed"])
@pytest.mark.parametrize("organized", [True, False])
def test_pcd_encodings_round_trip(tmp_path, encoding, organized):
    import pypcd4

    depth, intr = _plane_depth(12, 16)
    cloud = depth_to_cloud(depth, intr)
    pts = cloud.xyz.reshape(-1, 3).astype(np.float32)
    pts[5] = np.nan
    pc = pypcd4.PointCloud.from_xyz_points(pts)
    if organized:
        pc.metadata.width, pc.metadata.height = 16, 12
    path = tmp_path / f"c_{encoding}.pcd"
    pc.save(path, encoding=pypcd4.Encoding(encoding))
    back = io.read_pcd(path, regrid=False)
    assert back.organized == organized
    assert back.shape == ((12, 16) if organized else (1, 192))
    assert back.n_valid == 191
    got = back.xyz.reshape(-1, 3)
    ok = np.isfinite(pts[:, 0])
    assert np.allclose(got[ok], pts[ok], atol=1e-6)
    if organized:
        assert back.intrinsics.fx == pytest.approx(intr.fx, abs=1e-2)


def test_ply_round_trip(tmp_path):
    rng = np.random.default_rng(1)
    pts = rng.normal(size=(50, 3))
    write_ply(tmp_path / "p.ply", pts, colours=np.full((50, 3), 200, np.uint8),
              labels=np.arange(50))
    cloud = io.read(tmp_path / "p.ply", organize=False)  # points all around: no one view
    assert not cloud.organized and cloud.shape == (1, 50)
    assert np.allclose(cloud.points(), pts.astype(np.float32))


def test_npy_xyz_and_depth(tmp_path):
    depth, intr = _plane_depth()
    cloud = depth_to_cloud(depth, intr)
    np.save(tmp_path / "xyz.npy", cloud.xyz)
    back = io.read(tmp_path / "xyz.npy")
    assert back.shape == cloud.shape
    assert back.intrinsics.fx == pytest.approx(intr.fx, abs=1e-3)  # recovered from the points
    np.save(tmp_path / "d.npy", depth.astype(np.float32) / 1000)
    d = io.read(tmp_path / "d.npy", intrinsics=intr)  # float: metres
    assert np.nanmax(np.abs(d.depth - cloud.depth)) < 1e-6


def test_npy_point_list(tmp_path):
    """``np.save(points)`` of an (N, 3) cloud reads as points: a depth frame's valid points go
    back on their pixel grid (as an unorganized PCD does), scattered points go on an image grid
    (planerel.io.organize) or with organize=False stay a list, and an empty list is a clear
    error, never a depth image three pixels wide."""
    depth, intr = _plane_depth()
    cloud = depth_to_cloud(depth, intr)
    pts = cloud.xyz[np.isfinite(cloud.xyz[..., 2])]
    rng = np.random.default_rng(5)
    np.save(tmp_path / "frame.npy", pts[rng.permutation(len(pts))])
    back = io.read(tmp_path / "frame.npy")
    assert back.organized and back.n_valid == len(pts)
    assert back.intrinsics.fx == pytest.approx(intr.fx, abs=1e-2)
    rows = np.flatnonzero(np.isfinite(cloud.xyz[..., 2]).any(axis=1))
    assert np.allclose(back.xyz, cloud.xyz[rows[0]:rows[-1] + 1], atol=1e-6, equal_nan=True)
    scattered = rng.normal(size=(400, 3)) + [0, 0, 4]
    np.save(tmp_path / "scattered.npy", scattered.astype(np.float32))
    s = io.read(tmp_path / "scattered.npy", organize=False)
    assert not s.organized and s.shape == (1, 400)
    with pytest.warns(PlanerelWarning, match="image grid"):
        g = io.read(tmp_path / "scattered.npy")
    assert g.organized and 0 < g.n_valid <= 400 and g.intrinsics is not None
    assert np.allclose(s.points(), scattered.astype(np.float32))
    np.save(tmp_path / "none.npy", np.zeros((0, 3)))
    with pytest.raises(InputError, match="no points"):
        io.read(tmp_path / "none.npy")


def test_read_picks_reader_by_content(tmp_path):
    depth, intr = _plane_depth()
    write_depth_png(tmp_path / "frame.bin", depth)
    assert io.read(tmp_path / "frame.bin", intrinsics=intr).shape == depth.shape


# ----------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    "content, match",
    [
        (b"hello world", "unknown file type"),
        (b"\x89PNG\r\n\x1a\n" + b"\x00" * 20, "cannot read the image"),
        (b"# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\n", "PCD header ends before its DATA line"),
        (b"ply\nformat ascii 1.0\nelement vertex 3\n", "not a PLY file"),
        (b"\x93NUMPY\x01\x00garbage", "not a readable .npy"),
    ],
)
def test_corrupt_files(tmp_path, content, match):
    path = tmp_path / "bad.dat"
    path.write_bytes(content)
    with pytest.raises(InputError, match=match) as err:
        io.read(path, intrinsics="kinect")
    assert "bad.dat" in str(err.value)


@needs_data
def test_truncated_real_files(tmp_path):
    for src in [DATA / "kinect" / "office1.pcd", DATA / "abw" / "abw.test.0.range",
                next((DATA / "kinect").glob("*_depth.tiff"))]:
        cut = tmp_path / src.name
        cut.write_bytes(src.read_bytes()[: src.stat().st_size // 2])
        with pytest.raises(InputError, match=src.name):
            io.read(cut, intrinsics="kinect")


def test_missing_file_and_folder(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        io.read(tmp_path / "nope.pcd")
    with pytest.raises(InputError, match="is a folder"):
        io.read(tmp_path)


def test_depth_image_without_intrinsics(tmp_path):
    depth, _ = _plane_depth()
    write_depth_png(tmp_path / "lonely.png", depth)
    with pytest.raises(InputError, match="no intrinsics"):
        io.read(tmp_path / "lonely.png")


def test_all_invalid_depth(tmp_path):
    write_depth_png(tmp_path / "zero.png", np.zeros((10, 12), np.uint16))
    with pytest.raises(InputError, match="every pixel is invalid"):
        io.read(tmp_path / "zero.png", intrinsics="kinect" if False else (12, 10, 10, 10, 6, 5))


def test_16_bit_no_data_is_invalid(tmp_path):
    """65535 in a 16-bit depth image is the no-data (saturated) value some drivers write, not
    a depth of 65.5 m: invalid, as 0 is; the same value in a float image is a depth."""
    from PIL import Image

    depth = np.full((10, 12), 1500, np.uint16)
    depth[2:4, 3:6] = 65535
    Image.fromarray(depth).save(tmp_path / "gaps.png")  # as a driver wrote it
    cloud = io.read(tmp_path / "gaps.png", intrinsics=(12, 10, 10, 10, 6, 5))
    assert not cloud.valid[2:4, 3:6].any() and cloud.valid.sum() == 120 - 6
    assert np.allclose(cloud.xyz[cloud.valid][:, 2], 1.5)
    Image.fromarray(np.full((10, 12), 65535, np.uint16)).save(tmp_path / "none.png")
    with pytest.raises(InputError, match="every pixel is invalid"):
        io.read(tmp_path / "none.png", intrinsics=(12, 10, 10, 10, 6, 5))
    far = depth_to_cloud(depth.astype(np.float64), (12, 10, 10, 10, 6, 5), 1000)
    assert far.valid.all()
    # planerel never writes the no-data value as a depth
    with pytest.raises(InputError, match="0..65534"):
        write_depth_png(tmp_path / "max.png", depth)


@pytest.mark.parametrize("scale", [0, -1000, float("nan")])
def test_bad_depth_scale(scale):
    depth, intr = _plane_depth()
    with pytest.raises(InputError, match="depth scale"):
        depth_to_cloud(depth, intr, scale)


def test_wrong_shapes_and_dtypes(tmp_path):
    np.save(tmp_path / "four.npy", np.zeros((4, 5, 4)))
    with pytest.raises(InputError, match=r"\(H, W, 3\) XYZ, \(H, W\) depth or \(N, 3\) points"):
        io.read(tmp_path / "four.npy")
    np.save(tmp_path / "str.npy", np.array([["a", "b"]]))
    with pytest.raises(InputError, match="numeric"):
        io.read(tmp_path / "str.npy")
    with pytest.raises(InputError, match=r"shape \(H, W, 3\)"):
        Cloud(np.zeros((4, 4)))
    with pytest.raises(InputError, match="empty"):
        Cloud(np.zeros((0, 4, 3)))
    with pytest.raises(InputError, match="intrinsics are for"):
        depth_to_cloud(np.ones((10, 10)), KINECT)
    with pytest.raises(InputError, match="8-bit"):
        from PIL import Image

        Image.fromarray(np.ones((4, 4), np.uint8)).save(tmp_path / "eight.png")
        io.read(tmp_path / "eight.png", intrinsics=(4, 4, 1, 1, 2, 2))


def test_errors_are_one_hierarchy():
    assert issubclass(InputError, PlanerelError) and issubclass(InputError, ValueError)


# ----------------------------------------------------------------- Cloud and Intrinsics


def test_subsample_scales_intrinsics_exactly():
    depth, intr = _plane_depth(48, 64)
    cloud = depth_to_cloud(depth, intr)
    small = subsample(cloud, 4)
    assert small.shape == (12, 16)
    assert small.intrinsics == Intrinsics(16, 12, 15.0, 15.0, intr.cx / 4, intr.cy / 4)
    again = depth_to_cloud(depth[::4, ::4], small.intrinsics)
    assert np.allclose(again.xyz, small.xyz)


@pytest.mark.parametrize("bad", [0, -2, 1.5, "2"])
def test_subsample_bad_factor(bad):
    depth, intr = _plane_depth()
    with pytest.raises(InputError, match="subsampling factor"):
        subsample(depth_to_cloud(depth, intr), bad)


def test_intrinsics_validation_and_forms():
    assert Intrinsics.kinect() == KINECT
    assert Intrinsics.from_any(KINECT.to_dict()) == KINECT
    assert Intrinsics.from_matrix(KINECT.matrix(), 640, 480) == KINECT
    with pytest.raises(InputError, match="focal lengths"):
        Intrinsics(10, 10, 0, 1, 5, 5)
    with pytest.raises(InputError, match="width"):
        Intrinsics(0, 10, 1, 1, 5, 5)
    # a JSON writer's 160.0 is the size 160; 160.5 is not a size
    assert Intrinsics.from_any({"width": 160.0, "height": 120.0, "fx": 131.25, "fy": 131.25,
                                "cx": 79.5, "cy": 59.5}).width == 160
    with pytest.raises(InputError, match="width"):
        Intrinsics(160.5, 120, 1, 1, 5, 5)
    with pytest.raises(InputError, match="6 values"):
        Intrinsics.from_any([1, 2, 3])
    with pytest.raises(InputError, match="no Kinect preset"):
        Intrinsics.kinect(100, 100)


def test_cloud_is_read_only_and_normalises_up():
    c = Cloud(np.ones((2, 2, 3)), up=[0, -2, 0])
    assert c.up.tolist() == [0, -1, 0]
    with pytest.raises(ValueError):
        c.xyz[0, 0, 0] = 5
    with pytest.raises(InputError, match="up vector"):
        Cloud(np.ones((2, 2, 3)), up=[0, 0, 0])
    with pytest.raises(InputError, match="no valid point"):
        Cloud(np.full((2, 2, 3), np.nan)).require_points()


# ----------------------------------------------------------------- writers


def test_label_writers(tmp_path):
    labels = np.full((6, 8), -1, np.int32)
    labels[:3] = 0
    labels[3:, :4] = 5
    write_labels_npy(tmp_path / "l.npy", labels)
    assert np.array_equal(io.read_label_image(tmp_path / "l.npy"), labels)
    write_labels_png(tmp_path / "l.png", labels, depth=np.linspace(1, 2, 48).reshape(6, 8))
    from PIL import Image

    rgb = np.asarray(Image.open(tmp_path / "l.png"))
    assert rgb.shape == (6, 8, 3)
    assert not np.array_equal(rgb[0, 0], rgb[5, 0])  # labels 0 and 5 differ in colour
    pic = colour_labels(labels)
    assert (pic[3:, 4:] == 128).all()  # unassigned is grey


def test_json_writer_refuses_nan(tmp_path):
    write_json(tmp_path / "ok.json", {"a": np.float64(1.5), "b": np.arange(3)})
    assert json.loads((tmp_path / "ok.json").read_text()) == {"a": 1.5, "b": [0, 1, 2]}
    with pytest.raises(InputError, match="JSON"):
        write_json(tmp_path / "bad.json", {"a": float("nan")})
    assert not (tmp_path / "bad.json").exists()


def test_atomic_write_leaves_nothing_on_failure(tmp_path):
    from planerel.atomic import atomic_path

    target = tmp_path / "out.txt"
    target.write_text("old")
    with pytest.raises(RuntimeError):
        with atomic_path(target) as tmp:
            tmp.write_text("half")
            raise RuntimeError("interrupted")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.txt"]


@pytest.mark.parametrize("encoding", ["ascii", "binary_compressed"])
def test_unorganized_pcd_of_a_depth_frame_is_put_back_on_its_grid(tmp_path, encoding):
    """A depth frame saved without its invalid points (HEIGHT 1, as PCL's tools and three mOSD
    frames do) comes back on its pixel grid with its intrinsics; its fields follow it."""
    import pypcd4

    rng = np.random.default_rng(3)
    h, w = 30, 40
    depth = 1.0 + 0.3 * rng.random((h, w))
    depth[rng.random((h, w)) < 0.3] = 0  # invalid pixels, dropped from the file
    depth[:4] = 0  # a crop: the top rows hold nothing
    intr = Intrinsics(w, h, 525.0, 530.0, 19.5, 14.5)
    cloud = depth_to_cloud(depth, intr, depth_scale=1.0)
    full = cloud.xyz.astype(np.float32)
    keep = np.isfinite(full[..., 2])
    pts = full[keep]
    label = (np.arange(h * w).reshape(h, w)[keep] % 7 + 10).astype(np.uint32)
    order = rng.permutation(len(pts))  # any order of the points
    pc = pypcd4.PointCloud.from_points(
        [pts[order, 0], pts[order, 1], pts[order, 2], label[order]],
        ("x", "y", "z", "label"), (np.float32, np.float32, np.float32, np.uint32))
    path = tmp_path / "frame.pcd"
    pc.save(path, encoding=pypcd4.Encoding(encoding))

    back = io.read(path)
    assert back.organized and back.shape == (h - 4, w)  # the grid starts at the first row in use
    assert back.n_valid == len(pts)
    i = back.intrinsics
    assert (i.width, i.height) == (w, h - 4)
    assert (i.fx, i.fy, i.cx, i.cy) == pytest.approx((525.0, 530.0, 19.5, 10.5), abs=1e-2)
    assert np.allclose(back.xyz, full[4:], atol=1e-6, equal_nan=True)
    lab = io.read_pcd_field(path, "label")
    want = np.where(keep, np.arange(h * w).reshape(h, w) % 7 + 10, 0)[4:]
    assert lab.shape == (h - 4, w) and np.array_equal(lab, want)
    # kept as it is on request
    assert io.read_pcd(path, regrid=False).shape == (1, len(pts))
    assert io.read_pcd_field(path, "label", regrid=False).shape == (1, len(pts))


def test_pinhole_grid_refuses_clouds_off_any_grid():
    rng = np.random.default_rng(4)
    assert io.pinhole_grid(rng.normal(size=(500, 3)) + [0, 0, 5]) is None  # scattered points
    depth, intr = _plane_depth(12, 16)
    pts = depth_to_cloud(depth, intr).xyz.reshape(-1, 3)
    assert io.pinhole_grid(pts) is not None
    jittered = pts + rng.normal(scale=2e-3, size=pts.shape)  # 0.1-1 px off their rays
    assert io.pinhole_grid(jittered) is None
    twice = np.concatenate([pts, pts * 1.01])  # two points on one pixel's ray
    assert io.pinhole_grid(twice) is None
    assert io.pinhole_grid(pts[:50]) is None  # too few points to tell
    assert io.pinhole_grid(np.full((300, 3), np.nan)) is None


def _undistorted_on_distorted_grid(h=120, w=160, k1=0.09):
    """A wall 2 m away as a Kinect v2 SDK saves it: each point is where pixel ``(u, v)``'s ray
    goes once the lens's radial distortion (``k1``) is taken out, kept at ``(u, v)``; so the
    points are no exact pinhole back-projection of their grid (hunt33's kinect2box frames)."""
    f, cx, cy = 0.72 * w, w / 2 - 0.5, h / 2 + 3.0
    v, u = np.mgrid[0:h, 0:w].astype(float)
    a, b = (u - cx) / f, (v - cy) / f
    r2 = a * a + b * b
    a, b = a * (1 + k1 * r2), b * (1 + k1 * r2)
    z = np.full((h, w), 2.0)
    return np.stack([a * z, b * z, z], axis=-1), f, cx, cy


def test_an_approximate_pinhole_cloud_gets_fitted_intrinsics_with_a_warning(tmp_path):
    from planerel.errors import PlanerelWarning

    xyz, f, cx, cy = _undistorted_on_distorted_grid()
    assert io.estimate_intrinsics(xyz) is None  # no exact fit
    with pytest.warns(PlanerelWarning, match=r"scan\.npy: the points are no exact pinhole"):
        intr = io.estimate_intrinsics(xyz, approximate=io.APPROX_FIT_PX, where="scan.npy")
    assert intr.fx == pytest.approx(f, rel=0.05) and intr.cy == pytest.approx(cy, abs=1.0)
    # the readers ask for it: an .npy of such points and an organized PCD of them
    np.save(tmp_path / "k2.npy", xyz)
    with pytest.warns(PlanerelWarning, match="k2.npy"):
        assert io.read(tmp_path / "k2.npy").intrinsics is not None
    # more distortion than a lens gives a pinhole fit: no intrinsics, and a warning that says so
    far, *_ = _undistorted_on_distorted_grid(k1=1.5)
    with pytest.warns(PlanerelWarning, match="no pinhole image of their pixel grid"):
        assert io.estimate_intrinsics(far, approximate=io.APPROX_FIT_PX) is None
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        # an exact back-projection is silent, and so is asking for an exact fit only
        assert io.estimate_intrinsics(far) is None
        depth, intr0 = _plane_depth()
        assert io.estimate_intrinsics(depth_to_cloud(depth, intr0).xyz,
                                      approximate=io.APPROX_FIT_PX).fx == pytest.approx(intr0.fx, abs=1e-3)


def test_a_rotated_cloud_is_no_pinhole_image(tmp_path):
    # an organized cloud turned 30 degrees about the x axis (a levelled frame): x/z and y/z
    # no longer follow the pixel grid; reading it says why its projected measures are missing
    from planerel.errors import PlanerelWarning

    depth, intr = _plane_depth()
    xyz = depth_to_cloud(depth, intr).xyz
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    rot = xyz @ np.array([[1, 0, 0], [0, c, -s], [0, s, c]]).T
    np.save(tmp_path / "levelled.npy", rot)
    with pytest.warns(PlanerelWarning, match=r"levelled\.npy: the points are no pinhole image.*--intrinsics"):
        assert io.read(tmp_path / "levelled.npy").intrinsics is None
