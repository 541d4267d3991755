"""Folders written in one step (atomic_dir), leftovers of killed runs cleaned or restored."""

from __future__ import annotations

import subprocess
import sys

import pytest

from planerel.atomic import atomic_dir, recover_dir
from planerel.children import clean_stale_temp_dirs, pid_alive
from planerel.errors import InputError


def _dead_pid() -> int:
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    assert not pid_alive(proc.pid)
    return proc.pid


def test_atomic_dir_replaces_whole_or_not_at_all(tmp_path):
    out = tmp_path / "set"
    with atomic_dir(out, markers=("manifest.csv",)) as tmp:
        (tmp / "manifest.csv").write_text("v1")
        (tmp / "a").write_text("a1")
        assert not out.exists()
    assert sorted(p.name for p in out.iterdir()) == ["a", "manifest.csv"]
    with pytest.raises(RuntimeError), atomic_dir(out, markers=("manifest.csv",)) as tmp:
        (tmp / "manifest.csv").write_text("v2")
        raise RuntimeError("killed half-way")
    assert (out / "manifest.csv").read_text() == "v1" and (out / "a").read_text() == "a1"
    with atomic_dir(out, markers=("manifest.csv",)) as tmp:
        (tmp / "manifest.csv").write_text("v3")
    assert sorted(p.name for p in out.iterdir()) == ["manifest.csv"]  # no file of v1 remains
    assert [p.name for p in tmp_path.iterdir()] == ["set"]


def test_atomic_dir_never_deletes_a_folder_of_something_else(tmp_path):
    (tmp_path / "home").mkdir()
    (tmp_path / "home" / "thesis.tex").write_text("years of work")
    with pytest.raises(InputError, match="holds something else"), \
            atomic_dir(tmp_path / "home", markers=("manifest.csv",)):
        pass
    assert (tmp_path / "home" / "thesis.tex").read_text() == "years of work"
    (tmp_path / "f").write_text("x")
    with pytest.raises(InputError, match="not a folder"), atomic_dir(tmp_path / "f"):
        pass


def test_recover_after_a_kill_between_the_two_renames(tmp_path):
    pid = _dead_pid()
    old = tmp_path / f".model.old-{pid}-abc"
    old.mkdir()
    (old / "rules.pl").write_text("previous")
    stale = tmp_path / f".model.tmp-{pid}-def"
    stale.mkdir()
    recover_dir(tmp_path / "model")
    assert (tmp_path / "model" / "rules.pl").read_text() == "previous"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["model"]
    live = tmp_path / f".model.tmp-{__import__('os').getpid()}-xyz"  # a run still going
    live.mkdir()
    recover_dir(tmp_path / "model")
    assert live.exists()


def test_stale_temp_folders_of_dead_processes_are_removed(tmp_path):
    import os

    pid = _dead_pid()
    dead = tmp_path / f"planerel-learn-{pid}-x1"
    dead_file = tmp_path / f"planerel-scene-{pid}-x3.pl"
    mine = tmp_path / f"planerel-learn-{os.getpid()}-x2"
    other = tmp_path / "planerel-notes"
    for d in (dead, mine, other):
        d.mkdir()
    dead_file.write_text("facts")
    assert sorted(clean_stale_temp_dirs(tmp_path)) == sorted([dead, dead_file])
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([mine.name, other.name])
