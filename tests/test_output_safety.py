"""Outputs never write over inputs, through links, or onto streams (user89's new-user pass).

- ``segment x.npy -o .`` would write ``./x.npy``'s labels next to it, but ``segment x.pcd -o .``
  wrote the labelled cloud over the scan, and ``describe x.pcd -o x.pcd`` Prolog text over it;
- ``-o link`` replaced the link with a regular file (as root, ``-o /dev/stdout`` replaced the
  system's ``/dev/stdout`` link);
- ``-o fifo`` replaced the FIFO, and a reader on it got nothing.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

import numpy as np
import pytest

from planerel.atomic import atomic_path, check_not_inputs, check_output_file, write_text
from planerel.cli import main
from planerel.errors import InputError
from planerel.io.exports import write_pcd
from planerel.segment._scenes import staircase


def _digest(path) -> str:
    return hashlib.sha256(open(path, "rb").read()).hexdigest()


@pytest.fixture
def scan(tmp_path):
    cloud, _, _, _ = staircase(160, 120, seed=0)
    path = tmp_path / "scan.pcd"
    write_pcd(path, cloud.xyz)
    return path


def test_segment_into_the_scans_folder_refuses_and_keeps_the_scan(scan, capsys):
    before = _digest(scan)
    assert main(["segment", str(scan), "-o", str(scan.parent)]) == 2
    err = capsys.readouterr().err
    assert "is the input" in err and "scan.pcd" in err
    assert _digest(scan) == before
    # the formats that do not collide are written as before
    assert main(["segment", str(scan), "-o", str(scan.parent), "--formats", "npy,json"]) == 0
    assert (scan.parent / "scan.labels.npy").exists() and _digest(scan) == before


@pytest.mark.parametrize("command", [["describe"], ["convert"]])
def test_output_named_as_the_input_is_refused(scan, command, capsys):
    before = _digest(scan)
    assert main([*command, str(scan), "-o", str(scan)]) == 2
    assert "is the input" in capsys.readouterr().err
    assert _digest(scan) == before


def test_a_link_to_the_input_is_the_input(scan, tmp_path):
    link = tmp_path / "other.pcd"
    link.symlink_to(scan)
    with pytest.raises(InputError, match="is the input"):
        check_not_inputs([link], [scan])
    check_not_inputs([tmp_path / "new.pcd"], [scan])  # any other name passes


def test_an_output_link_is_written_through_and_stays_a_link(tmp_path, scan):
    target = tmp_path / "facts_target.pl"
    target.write_text("old\n")
    link = tmp_path / "facts.pl"
    link.symlink_to(target.name)
    assert main(["describe", str(scan), "-o", str(link)]) == 0
    assert link.is_symlink() and os.readlink(link) == target.name
    assert target.read_text().startswith("% planerel describe")
    write_text(link, "again\n")  # the library's writers too
    assert link.is_symlink() and target.read_text() == "again\n"


def test_a_fifo_is_refused_before_any_work_and_left_a_fifo(tmp_path, scan, capsys):
    fifo = tmp_path / "ff"
    os.mkfifo(fifo)
    assert main(["describe", str(scan), "-o", str(fifo)]) == 2
    assert "FIFO" in capsys.readouterr().err
    assert fifo.exists() and not fifo.is_file()
    with pytest.raises(InputError, match="FIFO"):
        with atomic_path(fifo):
            pass


def test_links_into_proc_and_dev_are_refused(tmp_path):
    # /dev/stdout -> /proc/self/fd/1 -> whatever stdout is: a rename would replace the link
    # or take the file from under the process writing to it
    link = tmp_path / "out.pl"
    link.symlink_to("/proc/self/fd/1")
    with pytest.raises(InputError, match="stream|FIFO|device"):
        check_output_file(link, "-o")
    with pytest.raises(InputError, match="device"):
        check_output_file("/dev/null", "-o")
    assert os.path.islink(link)


def test_a_dangling_link_into_a_missing_folder_names_the_folder(tmp_path):
    link = tmp_path / "d.pl"
    link.symlink_to(tmp_path / "nowhere" / "x.pl")
    with pytest.raises(InputError, match="whose folder does not exist"):
        check_output_file(link, "-o")


def test_a_regular_output_is_still_replaced_whole(tmp_path):
    out = tmp_path / "a.txt"
    out.write_text("old")
    write_text(out, "new")
    assert out.read_text() == "new" and not out.is_symlink()
    np.save(tmp_path / "x.npy", np.zeros(3))  # nothing else in the folder is touched
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "x.npy"]


def test_a_link_to_a_plain_file_under_dev_is_written_through(tmp_path):
    """Only a process's streams are refused (``/proc``, ``/dev/fd``, ``/dev/stdout``): a link
    to a file on ``/dev/shm`` is a file like any other."""
    shm = Path("/dev/shm")
    if not (shm.is_dir() and os.access(shm, os.W_OK)):
        pytest.skip("no writable /dev/shm")
    target = shm / f"planerel-test-{os.getpid()}.txt"
    link = tmp_path / "out.txt"
    link.symlink_to(target)
    try:
        write_text(link, "ok\n")
        assert target.read_text() == "ok\n" and link.is_symlink()
    finally:
        target.unlink(missing_ok=True)
