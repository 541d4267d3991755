"""The command line: help, version, and errors as one line with exit code 2."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from planerel import __version__
from planerel.cli import COMMAND_MODULES, build_parser, main


def _run(*args):
    return subprocess.run([sys.executable, "-m", "planerel.cli", *args], capture_output=True,
                          text=True, timeout=120)


def test_version_and_help():
    r = _run("--version")
    assert r.returncode == 0 and r.stdout.strip() == f"planerel {__version__}"
    r = _run("--help")
    assert r.returncode == 0
    for name in ("dataset", "convert"):
        assert name in r.stdout


def test_every_subcommand_explains_itself(capsys):
    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    assert len(sub.choices) >= len(COMMAND_MODULES)
    for name, p in sub.choices.items():
        # a description of its own (argparse would otherwise print only the usage), shown by
        # --help (argparse re-wraps it, also at hyphens: compared without whitespace)
        assert len(p.description or "") >= 40, name
        with pytest.raises(SystemExit) as e:
            main([name, "--help"])
        assert e.value.code == 0
        out = capsys.readouterr().out
        assert out.startswith(f"usage: planerel {name}"), name
        assert "".join(p.description.split()) in "".join(out.split()), name


def test_user_error_is_one_line_exit_2(tmp_path):
    r = _run("convert", str(tmp_path / "missing.pcd"), "-o", str(tmp_path / "x.npy"))
    assert r.returncode == 2
    assert r.stderr.strip().count("\n") == 0
    assert "no such file" in r.stderr and "Traceback" not in r.stderr


def test_convert_npy_to_ply_and_back(tmp_path):
    xyz = np.full((6, 8, 3), np.nan)
    xyz[2:, :, :] = [0.1, 0.2, 1.5]
    np.save(tmp_path / "in.npy", xyz)
    assert main(["convert", str(tmp_path / "in.npy"), "-o", str(tmp_path / "out.ply")]) == 0
    assert main(["convert", str(tmp_path / "out.ply"), "-o", str(tmp_path / "back.npy"),
                 "--no-organize"]) == 0
    back = np.load(tmp_path / "back.npy")
    assert back.shape == (1, 32, 3)
    # put on an image grid (the default): 32 points on one ray are one pixel
    assert main(["convert", str(tmp_path / "out.ply"), "-o", str(tmp_path / "grid.npy")]) == 0
    assert np.load(tmp_path / "grid.npy").shape == (1, 1, 3)


# ------------------------------------------------------------------ option parsing


def test_vector_and_intrinsics_options_parse():
    from planerel.commands._common import parse_intrinsics, parse_vector

    assert parse_vector("0,-1,0") == (0.0, -1.0, 0.0)
    assert parse_vector(" 0.5, 1e-3 ,2") == (0.5, 0.001, 2.0)
    assert parse_intrinsics(None) is None and parse_intrinsics("Kinect") == "Kinect"
    got = parse_intrinsics("640,480,525,526.5,319.5,239.5")
    assert got == (640, 480, 525.0, 526.5, 319.5, 239.5) and isinstance(got[0], int)


@pytest.mark.parametrize("text", ["0,-1", "0,-1,0,1", "0,up,0", "", "0;-1;0"])
def test_bad_vector_is_one_sentence(text):
    from planerel.commands._common import parse_vector
    from planerel.errors import InputError

    with pytest.raises(InputError, match=r"^--up must be three numbers like 0,-1,0; got ") as e:
        parse_vector(text, "--up")
    assert repr(text) in str(e.value)


@pytest.mark.parametrize("text", ["640,480,525,525,319.5", "640,480,525,525,319.5,239.5,1",
                                  "640.5,480,525,525,319.5,239.5", "w,h,fx,fy,cx,cy", "kinect2"])
def test_bad_intrinsics_is_one_sentence(text):
    from planerel.commands._common import parse_intrinsics
    from planerel.errors import InputError

    with pytest.raises(InputError, match=r"^--intrinsics must be 'kinect' or W,H,fx,fy,cx,cy"):
        parse_intrinsics(text)


@pytest.mark.parametrize("value, match", [
    ({"width": 640, "height": 480, "fx": 525, "fy": 525, "cx": 319.5}, "lacks 'cy'"),
    ((640, 480, 525, 525), "need 6 values.*got 4"),
    (42, "cannot read intrinsics from 42"),
    ((640, 0, 525, 525, 319.5, 239.5), "height must be a positive integer"),
    ((640, 480, -525, 525, 319.5, 239.5), "focal lengths must be positive"),
    ((640, 480, 525, "f", 319.5, 239.5), "fy must be a number"),
    ((640, 480, 525, 525, float("inf"), 239.5), "cx must be finite"),
])
def test_bad_intrinsics_values(value, match):
    from planerel.errors import InputError
    from planerel.io.cloud import Intrinsics

    with pytest.raises(InputError, match=match):
        Intrinsics.from_any(value)


@pytest.mark.parametrize("opt, value, phrase", [
    ("--up", "0,1", "--up must be three numbers"),
    ("--intrinsics", "160,120,100", "--intrinsics must be 'kinect' or W,H,fx,fy,cx,cy"),
])
def test_bad_option_on_the_command_line_exits_2_with_one_line(tmp_path, opt, value, phrase):
    xyz = np.zeros((12, 16, 3))
    xyz[..., 2] = 2.0
    xyz[..., 0] = np.arange(16) * 0.01
    xyz[..., 1] = np.arange(12)[:, None] * 0.01
    np.save(tmp_path / "in.npy", xyz)
    r = _run("segment", str(tmp_path / "in.npy"), "-o", str(tmp_path / "out"), f"{opt}={value}")
    assert r.returncode == 2, r.stderr
    assert r.stderr.strip().count("\n") == 0 and phrase in r.stderr
    assert "Traceback" not in r.stderr


def test_fitted_intrinsics_are_one_note_line(tmp_path, capsys):
    # points that are no exact pinhole back-projection (a Kinect v2's undistorted points on
    # its pixel grid): the command goes on with fitted intrinsics and says so in one line
    from test_io import _undistorted_on_distorted_grid

    xyz, *_ = _undistorted_on_distorted_grid()
    np.save(tmp_path / "k2.npy", xyz)
    assert main(["convert", str(tmp_path / "k2.npy"), "-o", str(tmp_path / "k2.pcd")]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("note: ") and "k2.npy" in err[0]
    assert "fitted" in err[0] and "--intrinsics" in err[0]


def test_a_cloud_in_another_frame_is_one_note_line(tmp_path, capsys):
    # an organized cloud turned into a levelled frame (its x axis pointing down, as
    # stair-perception's clouds): no intrinsics, and the note says what is lost and what to give
    from test_io import _plane_depth

    from planerel.io.cloud import depth_to_cloud

    depth, intr = _plane_depth()
    xyz = depth_to_cloud(depth, intr).xyz
    turned = np.stack([xyz[..., 1], -xyz[..., 0], xyz[..., 2]], axis=-1)  # 90 degrees about z
    np.save(tmp_path / "levelled.npy", turned)
    assert main(["convert", str(tmp_path / "levelled.npy"), "-o", str(tmp_path / "l.pcd")]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("note: ") and "no pinhole image" in err[0]
    assert "skirt" in err[0] and "--intrinsics" in err[0]
