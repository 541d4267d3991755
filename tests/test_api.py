"""The top-level API: planerel.read / segment / describe / Classifier, string camera presets."""

from __future__ import annotations

import subprocess
import sys
from importlib.resources import files

import numpy as np
import pytest

import planerel
from planerel.errors import InputError


def _depth_mm():
    """A 480x640 depth image in mm: a wall 2 m away, tilted 20 degrees about the x axis."""
    v, u = np.mgrid[0:480, 0:640].astype(float)
    # plane z = 2 + tan(20 deg) * y, y = (v - cy) z / fy  ->  z = 2 / (1 - t (v - cy) / fy)
    t = np.tan(np.radians(20.0))
    z = 2.0 / (1.0 - t * (v - 239.5) / 525.0)
    return np.round(z * 1000).astype(np.uint16)


def test_read_depth_array_with_the_kinect_preset_back_projects_by_hand():
    d = _depth_mm()
    cloud = planerel.read(d, intrinsics="kinect")
    assert cloud.shape == (480, 640) and cloud.organized
    z = d[100, 50] / 1000.0
    # Kinect preset at 640x480: fx = fy = 525, cx = 319.5, cy = 239.5 (docs/formats.md)
    assert np.allclose(cloud.xyz[100, 50], [(50 - 319.5) * z / 525, (100 - 239.5) * z / 525, z])
    same = planerel.read(d, intrinsics="640,480,525,525,319.5,239.5")
    assert np.array_equal(same.xyz, cloud.xyz)
    half = planerel.read(d, intrinsics="Kinect", subsample=2)
    assert np.array_equal(half.xyz, cloud.xyz[::2, ::2])
    metres = planerel.read(d.astype(float) / 1000.0, intrinsics="kinect")  # float = metres
    assert np.allclose(metres.xyz, cloud.xyz, equal_nan=True)


def test_read_xyz_array_path_and_cloud(tmp_path):
    xyz = planerel.read(_depth_mm(), intrinsics="kinect").xyz
    c1 = planerel.read(xyz)
    assert np.array_equal(c1.xyz, xyz, equal_nan=True)
    np.save(tmp_path / "scan.npy", xyz)
    c2 = planerel.read(tmp_path / "scan.npy")
    assert np.array_equal(c2.xyz, xyz, equal_nan=True)
    # the array's intrinsics are recovered from its points, as the file's are
    assert c1.intrinsics == c2.intrinsics and c1.intrinsics.fx == pytest.approx(525, abs=1e-3)
    assert planerel.read(c2) is c2


@pytest.mark.parametrize("bad, match", [
    (np.zeros((4, 4), np.uint16), "needs intrinsics"),
    (np.zeros((4, 4, 2)), "must be \\(H, W\\) depth or \\(H, W, 3\\) XYZ"),
    (np.zeros((4, 4, 3), np.int32), "must hold floats"),
    ([1, 2, 3], "cannot read a scan from a list"),
])
def test_read_refuses_what_it_cannot_read(bad, match):
    with pytest.raises(InputError, match=match):
        planerel.read(bad)
    with pytest.raises(InputError, match="intrinsics must be 'kinect' or W,H"):
        planerel.read(_depth_mm(), intrinsics="kinect2")


def test_segment_and_describe_take_arrays_paths_and_clouds(tmp_path):
    d = _depth_mm()
    cloud = planerel.read(d, intrinsics="kinect", subsample=4)
    np.save(tmp_path / "wall_depth.npy", cloud.xyz)
    a = planerel.segment(cloud)
    b = planerel.segment(tmp_path / "wall_depth.npy")
    c = planerel.segment.segment(cloud)  # the package's own function is still there
    assert np.array_equal(a.labels, b.labels) and np.array_equal(a.labels, c.labels)
    # one plane: the tilted wall covers (nearly) the whole image
    assert len(a.planes) == 1 and np.mean(a.labels == 0) > 0.9
    desc = planerel.describe(tmp_path / "wall_depth.npy")
    assert desc.scene_id == "wall" and len(desc.planes) == 1
    assert planerel.describe(cloud, a.labels, scene_id="w").scene_id == "w"


def test_package_is_typed_and_import_is_light():
    assert files("planerel").joinpath("py.typed").is_file()
    code = ("import sys, planerel; planerel.read; planerel.segment; "
            "print('numba' in sys.modules, 'pyswip' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "False"]
    from planerel.classify.classifier import Classifier

    assert planerel.Classifier is Classifier
    with pytest.raises(AttributeError):
        planerel.no_such_name  # noqa: B018
