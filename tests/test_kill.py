"""Kill planerel mid-run (SIGTERM and SIGKILL): no child survives, no output is half written.

The process-table walk is planerel.children's (``descendants``, ``pid_alive``): every test first
waits until that walk sees the children it is about to watch, so a walk that saw nothing would
time out there instead of passing.

Each test starts the real CLI in a subprocess, waits until the stage it wants to interrupt is
running (a ``swipl`` learner, pool workers, scenes being written), kills it, and then looks at
every process that descended from it and at the output folder.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from planerel.children import descendants, pid_alive
from planerel.synth.generator import generate_dataset

ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc")


def alive(pids) -> list[int]:
    """The processes of ``pids`` still alive (zombies count as dead)."""
    return [p for p in pids if pid_alive(p)]


def start(args, cwd) -> subprocess.Popen:
    env = dict(os.environ, PLANEREL_CACHE="none", PYTHONPATH=str(ROOT))
    return subprocess.Popen([sys.executable, "-m", "planerel.cli", *args], cwd=cwd, env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)


def wait_for(cond, timeout=60.0, what="the stage to start"):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = cond()
        if value:
            return value
        time.sleep(0.05)
    pytest.fail(f"timed out waiting for {what}")


def kill_and_check(proc, sig, watched) -> None:
    """Send ``sig``; the process ends, and none of ``watched`` (its descendants) survives."""
    proc.send_signal(sig)
    proc.wait(timeout=30)
    end = time.monotonic() + 10
    while alive(watched) and time.monotonic() < end:
        time.sleep(0.05)
    survivors = {p: watched[p] for p in alive(watched)}
    for p in survivors:  # do not leave them running whatever the outcome
        with_kill(p)
    assert not survivors, f"children survived {signal.Signals(sig).name}: {survivors}"


def with_kill(pid):
    try:
        os.kill(pid, signal.SIGKILL)
    except ProcessLookupError:
        pass


@pytest.fixture(scope="module")
def small_set(tmp_path_factory):
    out = tmp_path_factory.mktemp("kill") / "train"
    generate_dataset(out, n_box=4, n_stairs=4, n_ramp=4, seed=3, size=(640, 480), subsample=4)
    return out


def _hidden(folder: Path, name: str) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.startswith(f".{name}."))


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL], ids=["SIGTERM", "SIGKILL"])
def test_kill_learn_during_the_pool(small_set, tmp_path, sig):
    """learn --jobs 2 killed while its two pool workers describe scenes."""
    proc = start(["learn", str(small_set), "-o", str(tmp_path / "model"), "--jobs", "2",
                  "--engine", "builtin"], tmp_path)
    kids = wait_for(lambda: (d := descendants(proc.pid)) and len(d) >= 2 and d,
                    what="the pool workers")
    kill_and_check(proc, sig, kids)
    assert not (tmp_path / "model").exists()
    if sig == signal.SIGTERM:
        err = proc.stderr.read()
        assert proc.returncode == 143 and b"Traceback" not in err, (proc.returncode, err)


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL], ids=["SIGTERM", "SIGKILL"])
def test_kill_learn_while_swipl_runs_keeps_the_old_model(small_set, tmp_path, sig):
    """Killed while the folds' learners (threads, one swipl each) run."""
    model = tmp_path / "model"
    model.mkdir()
    (model / "rules.pl").write_text("% the previous model\n")
    proc = start(["learn", str(small_set), "-o", str(model), "--jobs", "2", "--engine", "builtin",
                  "--folds", "3", "--method", "gt"], tmp_path)
    kids = wait_for(lambda: (d := descendants(proc.pid)) and "swipl" in d.values() and d,
                    what="a swipl learner")
    kill_and_check(proc, sig, kids)
    assert sorted(p.name for p in model.iterdir()) == ["rules.pl"]
    assert (model / "rules.pl").read_text() == "% the previous model\n"
    left = _hidden(tmp_path, "model")
    if sig == signal.SIGTERM:
        assert left == []
    else:  # a SIGKILLed run cannot clean up; the next write of the same model does
        from planerel.atomic import recover_dir

        recover_dir(model)
        assert _hidden(tmp_path, "model") == []
        assert (model / "rules.pl").read_text() == "% the previous model\n"


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL], ids=["SIGTERM", "SIGKILL"])
def test_kill_induce_stops_swipl(tmp_path, sig):
    """A background file that loops for ever (induce runs the .b it is given): the swipl of a
    killed induce must not run on."""
    for ext in ("b", "f", "n"):
        shutil.copy(ROOT / "tests" / "ilp" / f"trains.{ext}", tmp_path / f"spin.{ext}")
    with open(tmp_path / "spin.b", "a") as fh:
        fh.write("\n:- ( between(1, inf, _), fail ; true ).\n")
    proc = start(["induce", str(tmp_path / "spin"), "--timeout", "600"], tmp_path)
    kids = wait_for(lambda: (d := descendants(proc.pid)) and "swipl" in d.values() and d,
                    what="the learner's swipl")
    time.sleep(0.3)
    kill_and_check(proc, sig, kids)


def _digest(folder: Path) -> dict[str, str]:
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.iterdir()) if p.is_file()}


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL], ids=["SIGTERM", "SIGKILL"])
def test_kill_synth_over_an_existing_set_keeps_it_whole(tmp_path, sig):
    ds = tmp_path / "set"
    generate_dataset(ds, n_box=1, n_stairs=1, n_ramp=1, seed=1, size=(640, 480), subsample=8)
    before = _digest(ds)
    proc = start(["dataset", "synth", str(ds), "--n-box", "40", "--n-stairs", "40", "--n-ramp",
                  "40", "--seed", "2", "--quiet"], tmp_path)

    def writing():
        for d in tmp_path.glob(".set.tmp-*"):
            if len(list(d.glob("*.depth.png"))) >= 3:
                return descendants(proc.pid) or {proc.pid: "python"}
        return None

    kids = wait_for(writing, what="scenes being written")
    kids.pop(proc.pid, None)
    kill_and_check(proc, sig, kids)
    assert _digest(ds) == before  # the old set, whole: manifest and scenes agree
    if sig == signal.SIGTERM:
        assert _hidden(tmp_path, "set") == []
    else:
        generate_dataset(ds, n_box=1, n_stairs=1, n_ramp=1, seed=1, size=(640, 480), subsample=8)
        assert _hidden(tmp_path, "set") == [] and _digest(ds) == before


_FORK_SCRIPT = r"""
import ctypes, functools, os, signal, sys, time
libc = ctypes.CDLL(None, use_errno=True)
# registered before logging is imported, so it runs first after a fork in the parent: the
# SIGTERM is pending when logging's own after-fork hook (which releases its lock) starts
os.register_at_fork(after_in_parent=functools.partial(libc.kill, os.getpid(), signal.SIGTERM))
import logging
from planerel import cli
cli._terminate_like_interrupt()
try:
    pid = os.fork()
    if pid == 0:
        os._exit(0)
    os.waitpid(pid, 0)
    time.sleep(5)
    print("not terminated", flush=True)
except cli._Terminated:
    print("terminated", flush=True)
lock = logging._lock
print("logging lock free" if lock.acquire(timeout=2) else "logging lock held", flush=True)
"""


def test_sigterm_during_a_fork_is_not_lost(tmp_path):
    """A SIGTERM that arrives while ``os.fork`` runs logging's after-fork hook ends the run
    (it was dropped there, and logging's lock stayed held, so later forks hung)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run([sys.executable, "-c", _FORK_SCRIPT], env=env, cwd=tmp_path,
                          capture_output=True, text=True, timeout=60)
    assert proc.stdout.split("\n")[:2] == ["terminated", "logging lock free"], (
        proc.stdout, proc.stderr)
    assert "Exception ignored" not in proc.stderr
