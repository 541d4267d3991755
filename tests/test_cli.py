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
        assert p.description or p.format_help(), name
        with pytest.raises(SystemExit) as e:
            main([name, "--help"])
        assert e.value.code == 0
        assert "usage: planerel" in capsys.readouterr().out


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
    assert main(["convert", str(tmp_path / "out.ply"), "-o", str(tmp_path / "back.npy")]) == 0
    back = np.load(tmp_path / "back.npy")
    assert back.shape == (1, 32, 3)
