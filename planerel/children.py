"""Child processes that die with their parent, and temporary folders that do not outlive it.

* :func:`die_with_parent` asks Linux to SIGKILL the calling process when its parent dies
  (``PR_SET_PDEATHSIG``), even when the parent is SIGKILLed and runs no cleanup;
* :func:`child_preexec` does that for a ``swipl`` started by :mod:`subprocess`, and gives it its
  own time limit (a kernel CPU-time limit a little above the parent's timeout), so that even an
  orphan cannot run on for ever;
* :func:`new_pool` makes a ``ProcessPoolExecutor`` whose workers die with the parent, and
  :func:`stop_pool` kills them (instead of waiting for their work) when a batch is interrupted
  (Ctrl-C, SIGTERM; :mod:`planerel.batch` uses both), even a worker forked an instant before
  the interruption and not yet recorded by the executor;
* :func:`wait_result` waits for a future in short slices, so that a Ctrl-C or SIGTERM reaches
  the waiting thread within a fraction of a second;
* :func:`temp_dir` makes ``planerel-KIND-PID-*`` folders and first removes those whose process
  is gone (left by a run that was SIGKILLed).

On systems without ``prctl`` (not Linux) the parent-death signal is skipped; the rest works.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import math
import os
import re
import shutil
import signal
import tempfile
import threading
from collections.abc import Callable
from pathlib import Path

__all__ = ["die_with_parent", "child_preexec", "pool_worker_init", "pool_options", "new_pool",
           "stop_pool", "wait_result",
           "register_child", "unregister_child", "stop_children", "temp_dir", "temp_prefix",
           "pid_alive",
           "descendants",
           "clean_stale_temp_dirs"]

_PR_SET_PDEATHSIG = 1


_LIBC = None


def _libc():
    global _LIBC
    if _LIBC is None:
        try:
            _LIBC = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        except OSError:
            _LIBC = False
    return _LIBC


def die_with_parent(parent_pid: int | None = None) -> None:
    """Have the kernel SIGKILL this process when its parent dies (Linux; no-op elsewhere).

    ``parent_pid`` is the parent this process was started by: if it is already gone (it died
    between the fork and this call), exit at once.
    """
    libc = _libc()
    if libc and hasattr(libc, "prctl"):
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    if parent_pid is not None and os.getppid() != parent_pid:
        os._exit(1)


def child_preexec(timeout: float | None = None) -> Callable[[], None]:
    """A ``preexec_fn`` for :class:`subprocess.Popen`: the child dies with this process and,
    with ``timeout``, may use at most ``timeout + 5`` CPU seconds (SIGXCPU, then SIGKILL 5 s
    later): its own limit, which holds even if nothing is left to enforce the parent's."""
    parent = os.getpid()
    limit = None if timeout is None else int(math.ceil(timeout)) + 5

    def preexec() -> None:
        die_with_parent(parent)
        if limit is not None:
            import resource

            with contextlib.suppress(ValueError, OSError):
                resource.setrlimit(resource.RLIMIT_CPU, (limit, limit + 5))

    return preexec


def pool_worker_init(parent_pid: int) -> None:
    """Initializer of pool workers: die with the parent; SIGTERM ends the worker quietly and
    Ctrl-C is left to the parent (which stops its workers), so neither prints a traceback;
    on a terminal, a worker that compiles numba kernels says so (:mod:`planerel.compile_notice`)."""
    die_with_parent()  # the parent: this process, or its forkserver (which exits with it)
    if not pid_alive(parent_pid):
        os._exit(1)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    from planerel.compile_notice import watch

    watch()  # a worker compiles its own kernels: the same one line on a terminal


def pool_options() -> dict:
    """Keyword arguments for ``ProcessPoolExecutor`` whose workers die with this process."""
    return {"initializer": pool_worker_init, "initargs": (os.getpid(),)}


def new_pool(max_workers: int, mp_context=None):
    """A ``ProcessPoolExecutor`` whose workers die with this process (:func:`pool_options`) and
    that :func:`stop_pool` can stop completely.

    The executor records a worker only after its fork returns; an interruption between the two
    would leave a worker nobody kills (and an interpreter that waits for it at exit). So the
    children this process has before the pool is made are remembered, and :func:`stop_pool`
    also kills every child started after them.
    """
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    before = set(multiprocessing.active_children())
    executor = ProcessPoolExecutor(max_workers=max_workers, mp_context=mp_context,
                                   **pool_options())
    executor._planerel_children_before = before
    return executor


def stop_pool(executor) -> None:
    """Stop a ``ProcessPoolExecutor`` now: queued work cancelled, workers killed, not awaited
    (SIGKILL: a worker just forked may still run the parent's signal handlers). A pool made by
    :func:`new_pool` also loses the workers it had started but not yet recorded."""
    procs = list((getattr(executor, "_processes", None) or {}).values())
    before = getattr(executor, "_planerel_children_before", None)
    if before is not None:
        import multiprocessing

        known = {id(p) for p in procs}
        procs += [p for p in multiprocessing.active_children()
                  if p not in before and id(p) not in known]
    executor.shutdown(wait=False, cancel_futures=True)
    for proc in procs:
        with contextlib.suppress(Exception):
            proc.kill()
    for proc in procs:
        with contextlib.suppress(Exception):
            proc.join(timeout=5)


def wait_result(future, poll: float = 0.2):
    """``future.result()``, waited for in slices of ``poll`` seconds.

    An untimed ``result()`` blocks the main thread in one lock acquisition that a signal
    interrupts only if the kernel delivers it to that thread; in slices, Python's handler for a
    Ctrl-C or SIGTERM runs within ``poll`` seconds whichever thread the signal was given to.
    """
    from concurrent.futures import TimeoutError as FutureTimeout

    while True:
        try:
            return future.result(timeout=poll)
        except FutureTimeout:
            if future.done():  # finished between the timeout and here
                return future.result()


_RUNNING: set = set()
_LOCK = threading.Lock()
_STOPPING = threading.Event()


def register_child(proc) -> None:
    """Note a running child (started in its own session) so :func:`stop_children` can kill it.

    Raises ``KeyboardInterrupt`` at once (killing it) while :func:`stop_children` is in force, so
    that no thread starts new work during an interruption."""
    with _LOCK:
        _RUNNING.add(proc.pid)
    if _STOPPING.is_set():
        _kill_group(proc.pid)
        raise KeyboardInterrupt


def unregister_child(proc) -> None:
    with _LOCK:
        _RUNNING.discard(proc.pid)


def _kill_group(pid: int) -> None:
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(pid, signal.SIGKILL)


@contextlib.contextmanager
def stop_children():
    """Kill every registered child's process group, and keep killing new ones until the block
    ends (use it around the wait for worker threads after an interruption)."""
    _STOPPING.set()
    try:
        with _LOCK:
            pids = list(_RUNNING)
        for pid in pids:
            _kill_group(pid)
        yield
    finally:
        _STOPPING.clear()


def descendants(pid: int) -> dict[int, str]:
    """``{pid: command name}`` of every living (not zombie) descendant of ``pid``, read from
    ``/proc`` (empty where there is none)."""
    table = {}
    try:
        entries = [e for e in os.listdir("/proc") if e.isdigit()]
    except OSError:
        return {}
    for entry in entries:
        try:
            text = Path(f"/proc/{entry}/stat").read_text()
        except OSError:
            continue
        fields = text[text.rindex(")") + 2:].split()
        table[int(entry)] = (int(fields[1]), fields[0], text[text.index("(") + 1:text.rindex(")")])
    out: dict[int, str] = {}
    frontier = [pid]
    while frontier:
        parent = frontier.pop()
        for child, (ppid, state, name) in table.items():
            if ppid == parent and child not in out and state != "Z":
                out[child] = name
                frontier.append(child)
    return out


def pid_alive(pid: int) -> bool:
    """Whether a process with this id exists and is not a zombie (dead, not yet reaped)."""
    if pid <= 0:
        return False
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
        return text[text.rindex(")") + 2:].split()[0] not in ("Z", "X")
    except (OSError, ValueError, IndexError):
        pass
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


_TEMP = re.compile(r"planerel-[a-z]+-(\d+)-")


def clean_stale_temp_dirs(folder=None) -> list[Path]:
    """Remove ``planerel-KIND-PID-*`` folders and files of ``folder`` (default: the temporary
    folder) whose process is gone; return what was removed."""
    base = Path(folder or tempfile.gettempdir())
    removed = []
    try:
        entries = list(os.scandir(base))
    except OSError:
        return removed
    for entry in entries:
        m = _TEMP.match(entry.name)
        if not m or pid_alive(int(m.group(1))):
            continue
        if entry.is_dir(follow_symlinks=False):
            shutil.rmtree(entry.path, ignore_errors=True)
        else:
            with contextlib.suppress(OSError):
                os.unlink(entry.path)
        removed.append(Path(entry.path))
    return removed


_CLEANED = False


def temp_prefix(kind: str) -> str:
    """``planerel-KIND-PID-``, the prefix of this process's temporary files and folders; the
    first call of a process also removes those left by processes that are gone."""
    global _CLEANED
    if not _CLEANED:
        _CLEANED = True
        clean_stale_temp_dirs()
    return f"planerel-{kind}-{os.getpid()}-"


def temp_dir(kind: str) -> tempfile.TemporaryDirectory:
    """``tempfile.TemporaryDirectory`` named ``planerel-KIND-PID-*`` (see :func:`temp_prefix`)."""
    return tempfile.TemporaryDirectory(prefix=temp_prefix(kind))
