"""One naming rule for scene ids and output names across segment, describe and classify."""

from __future__ import annotations

import numpy as np
import pytest

from planerel.cli import main
from planerel.errors import InputError
from planerel.io.naming import scene_name, scene_names


@pytest.mark.parametrize("path, name", [
    ("data/s0003.depth.png", "s0003"),
    ("kinect/frame_20121214T142256.068683_depth.tiff", "frame_20121214T142256.068683"),
    ("frame_20121214T142256.332395_depth.TIFF", "frame_20121214T142256.332395"),
    ("abw/abw.test.12.range", "abw.test.12"),
    ("office1.pcd", "office1"),
    ("scan-depth.npy", "scan"),
    ("cloud.v2.ply", "cloud.v2"),
    ("notes.txt", "notes.txt"),          # unknown extension: kept whole
    (".depth.png", ".depth.png"),        # nothing left: the whole file name
])
def test_scene_name_is_the_full_stem_minus_known_suffixes(path, name):
    assert scene_name(path) == name


def test_frames_that_share_text_before_the_first_dot_get_distinct_names():
    a = "k/frame_20121214T142256.068683_depth.tiff"
    b = "k/frame_20121214T142256.332395_depth.tiff"
    assert scene_names([a, b]) == ["frame_20121214T142256.068683", "frame_20121214T142256.332395"]


def test_collisions_are_refused_naming_both_inputs():
    with pytest.raises(InputError, match=r"a/s1.depth.png and b/s1.npy have the same scene name 's1'"):
        scene_names(["a/s1.depth.png", "b/s1.npy"])
    with pytest.raises(InputError, match="same scene name"):
        scene_names(["a/Scan.png", "b/scan.png"])  # equal on a case-insensitive file system
    with pytest.raises(InputError, match="same scene id"):
        scene_names(["a.png", "b.png"], ids=["x", "x"])
    with pytest.raises(InputError, match="one id per input"):
        scene_names(["a.png", "b.png"], ids=["x"])


def _xyz_scan(path):
    """A 24x32 organized cloud: a floor plane 1 m below a pinhole camera (y down)."""
    h, w = 24, 32
    v, u = np.mgrid[0:h, 0:w].astype(float)
    f = 30.0
    ray = np.stack([(u - w / 2 + 0.5) / f, (v - h / 2 + 0.5) / f, np.ones_like(u)], axis=-1)
    ray[ray[..., 1] <= 0.05] = np.nan  # only rays that hit the floor
    t = 1.0 / ray[..., 1]
    np.save(path, ray * t[..., None])
    return path


@pytest.mark.parametrize("command", ["segment", "describe", "classify"])
def test_commands_refuse_colliding_inputs_before_writing(tmp_path, capsys, command):
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    x = _xyz_scan(tmp_path / "a" / "scan.npy")
    y = _xyz_scan(tmp_path / "b" / "scan_depth.npy")
    out = tmp_path / "out"
    if command == "segment":
        argv = ["segment", str(x), str(y), "-o", str(out)]
    elif command == "describe":
        argv = ["describe", str(x), str(y), "-o", str(out / "f.pl")]
    else:
        rules = tmp_path / "rules.pl"
        rules.write_text("box(A) :- nplanes(A, 1).\n")
        argv = ["classify", str(rules), str(x), str(y), "-o", str(out)]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "same scene name 'scan'" in err and err.count("\n") == 1
    assert not out.exists()


def test_segment_describe_classify_use_the_same_name(tmp_path, capsys):
    scan = _xyz_scan(tmp_path / "frame_1.5_depth.npy")
    out = tmp_path / "out"
    assert main(["segment", str(scan), "-o", str(out)]) == 0
    assert (out / "frame_1.5.labels.npy").is_file() and (out / "frame_1.5.planes.json").is_file()
    assert main(["describe", str(scan), "-o", str(out / "f.pl")]) == 0
    assert "scene('frame_1.5')." in (out / "f.pl").read_text()
