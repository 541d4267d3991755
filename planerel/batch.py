"""Batches of scans: inputs from files, folders and globs; one loop over a pool of workers.

Every command that loops over scenes (``segment``, ``describe``, ``classify``, ``learn``) runs
its per-scene work through :func:`run_batch`:

- the workers are a :class:`concurrent.futures.Executor`: the calling process itself
  (``jobs=1``), a local process pool (``jobs=N``), or a Dask cluster (``scheduler=
  "tcp://host:8786"``, through ``distributed.Client.get_executor``) -- one code path for all;
- at most a few tasks per worker are in flight, and results come back in input order, so a
  caller that writes each result as it arrives keeps memory flat in the number of scenes;
- with ``keep_going`` a failing input is recorded (:class:`Failure`) and the batch goes on;
  without it the first failure stops the batch;
- progress: a bar on a terminal, a log line every ``PLANEREL_PROGRESS_SECONDS`` (default 10)
  seconds otherwise.
"""

from __future__ import annotations

import glob
import os
import sys
import time
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import Executor, Future, ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

from planerel.children import wait_result
from planerel.errors import DependencyError, InputError, PlanerelError

__all__ = ["expand_inputs", "resolve_jobs", "make_executor", "run_batch", "Failure",
           "BatchResult", "write_errors"]

# Files in a folder that are results or ground truth, not scans.
_NOT_SCANS = (".labels.png", ".labels.npy", ".gt.png", ".classified.png", ".explain.png")


def _is_scan(p: Path) -> bool:
    from planerel.io.naming import SCAN_EXTENSIONS

    low = p.name.lower()
    return (p.is_file() and low.endswith(SCAN_EXTENSIONS) and not low.endswith(_NOT_SCANS)
            and not low.startswith("."))


def _colour_image(p: Path) -> bool:
    """True for a file that holds a colour or 8-bit image, no depth: a PNG whose header says
    8 bits or colour, a TIFF whose first page has several samples or 8 bits, a ``uint8``
    ``.npy`` (the ``*_rgb`` files beside depth frames).  Reads the header only."""
    low = p.name.lower()
    try:
        if low.endswith(".png"):
            with open(p, "rb") as fh:
                head = fh.read(26)
            # IHDR: bit depth at byte 24, colour type at byte 25 (0 = grey)
            return (len(head) == 26 and head[:8] == b"\x89PNG\r\n\x1a\n"
                    and (head[24] <= 8 or head[25] != 0))
        if low.endswith((".tif", ".tiff")):
            import tifffile

            with tifffile.TiffFile(p) as tf:
                page = tf.pages[0]
                return page.samplesperpixel > 1 or page.dtype.itemsize == 1
        if low.endswith(".npy"):
            import numpy as np

            return np.load(p, mmap_mode="r", allow_pickle=False).dtype == np.uint8
    except Exception:  # noqa: BLE001 -- an unreadable file is the reader's to report
        return False
    return False


def _folder_scans(p: Path) -> list[Path]:
    """The scans directly inside a folder that is no data set; colour and 8-bit images
    beside the depth frames (``*_rgb.png``) are left out, with a note."""
    found = sorted((q for q in p.iterdir() if _is_scan(q)), key=lambda q: q.name)
    colour = [q for q in found if _colour_image(q)]
    if colour and len(colour) < len(found):
        import warnings

        from planerel.errors import PlanerelWarning

        names = ", ".join(q.name for q in colour[:3]) + (", ..." if len(colour) > 3 else "")
        warnings.warn(PlanerelWarning(
            f"{p}: left out {len(colour)} colour or 8-bit image(s) ({names}): no depth; "
            "name such a file to read it anyway"), stacklevel=3)
        found = [q for q in found if q not in colour]
    return found


def _pattern_scans(pattern: str, found: list) -> list[Path]:
    """The scans among the files a glob pattern matched, as a folder gives them: label and
    result images (``*.gt.png``, ``*.labels.png``), other files (``README.md``) and colour or
    8-bit images are left out with a note (user89: ``"data/test/*.png"`` read a data set's
    label PNGs as depth in millimetres)."""
    scans = [q for q in found if _is_scan(q)]
    colour = {q for q in scans if _colour_image(q)}
    if colour and len(colour) < len(scans):  # as _folder_scans: all colour, all kept
        scans = [q for q in scans if q not in colour]
    kept = set(scans)
    left = [q for q in found if q not in kept]
    if not scans:
        raise InputError(f"{pattern}: the pattern matches no scan ({len(found)} file(s), e.g. "
                         f"{found[0].name}: label, result, colour or other files; name a file "
                         "to read it anyway)")
    if left:
        import warnings

        from planerel.errors import PlanerelWarning

        names = ", ".join(q.name for q in left[:3]) + (", ..." if len(left) > 3 else "")
        warnings.warn(PlanerelWarning(
            f"{pattern}: left out {len(left)} file(s) the pattern matched that are no depth "
            f"scans ({names}: label, result, colour or other files); name such a file to read "
            "it anyway"), stacklevel=3)
    return scans


def expand_inputs(items: Iterable) -> list[Path]:
    """Files, folders and glob patterns -> the list of scan files, in a fixed order.

    Parameters
    ----------
    items : iterable of str or Path
        A file is taken as given (whatever its extension).  A data-set folder (one with a
        ``manifest.csv``) gives its scenes' depth images in manifest order; any other folder
        gives the scan files directly inside it (``.png .tif .tiff .pcd .ply .npy .range``,
        without label and result images such as ``*.gt.png`` / ``*.labels.png``), sorted by
        name; colour and 8-bit images among them (``*_rgb.png`` beside the depth frames)
        are left out with a note.  A pattern with ``* ? [`` that is not an existing path is
        expanded (``**`` recurses), sorted, and its matches filtered as a folder's are
        (the files left out named in a note).

    Raises
    ------
    InputError
        A path that does not exist, a folder with no scan, a pattern that matches nothing.
    """
    out: list[Path] = []
    for item in items:
        p = Path(item)
        if p.is_dir():
            if (p / "manifest.csv").is_file():
                from planerel.features.dataset import load_manifest

                found = [p / r.depth for r in load_manifest(p)]
            else:
                found = _folder_scans(p)
            if not found:
                raise InputError(f"{p}: the folder holds no scan ({', '.join(_exts())})")
            out.extend(found)
        elif p.exists():
            out.append(p)
        elif glob.has_magic(str(item)):
            found = sorted(Path(m) for m in glob.glob(str(item), recursive=True))
            found = [q for q in found if q.is_file()]
            if not found:
                raise InputError(f"{item}: no file matches the pattern")
            out.extend(_pattern_scans(str(item), found))
        else:
            raise InputError(f"{p}: no such file or folder")
    return out


def _exts() -> list[str]:
    from planerel.io.naming import SCAN_EXTENSIONS

    return sorted(SCAN_EXTENSIONS)


def resolve_jobs(jobs: int | None) -> int:
    """``None`` or 0 -> the number of usable cores; a negative number is refused."""
    if jobs is None or jobs == 0:
        try:
            return max(1, len(os.sched_getaffinity(0)))
        except (AttributeError, OSError):
            return os.cpu_count() or 1
    if jobs < 0:
        raise InputError(f"--jobs must be a positive number of workers, got {jobs}")
    return int(jobs)


class _InlineExecutor(Executor):
    """Runs each task at submission in the calling process (``jobs=1``): no pickling, no
    extra process, exceptions keep their traceback."""

    def submit(self, fn, /, *args, **kwargs):
        fut: Future = Future()
        try:
            fut.set_result(fn(*args, **kwargs))
        except BaseException as exc:  # the caller decides what a failure means
            if isinstance(exc, KeyboardInterrupt):
                raise
            fut.set_exception(exc)
        return fut


@dataclass
class _Pool:
    executor: Executor
    workers: int
    client: object = None

    def close(self, cancel: bool = False) -> None:
        if cancel and isinstance(self.executor, ProcessPoolExecutor):
            from planerel.children import stop_pool

            stop_pool(self.executor)  # interrupted: kill the workers, do not wait for them
        elif isinstance(self.executor, (ProcessPoolExecutor, _InlineExecutor)):
            self.executor.shutdown(wait=not cancel, cancel_futures=cancel)
        else:  # Dask's ClientExecutor: shutdown(wait=False) cancels what is pending
            self.executor.shutdown(wait=not cancel)
        if self.client is not None:
            self.client.close()


def make_executor(jobs: int | None = None, scheduler: str | None = None,
                  n_tasks: int | None = None, mp_context: str | None = None) -> _Pool:
    """The workers for a batch.

    Parameters
    ----------
    jobs : int or None
        Local worker processes (None: all cores); 1 runs in the calling process.
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://host:8786``) or a ``distributed.Client``; the
        tasks then run on that cluster's workers and ``jobs`` is ignored.
    n_tasks : int, optional
        The number of tasks, so that no more local processes than tasks are started.
    mp_context : str, optional
        How local workers start (``"fork"``, ``"forkserver"``, ``"spawn"``; default: the
        platform's).  ``"forkserver"`` when this process holds state a child must not
        inherit, such as a running Prolog engine.
    """
    if scheduler is not None:
        try:
            from distributed import Client
        except ImportError:
            raise DependencyError("--scheduler needs Dask's distributed package: "
                                  "pip install 'planerel[dask]'") from None
        own = isinstance(scheduler, str)
        try:
            wait = float(os.environ.get("PLANEREL_DASK_TIMEOUT", "30"))
            client = Client(scheduler, timeout=wait) if own else scheduler
        except (OSError, TimeoutError) as exc:
            raise InputError(f"cannot reach the Dask scheduler {scheduler}: {exc}") from None
        except ValueError as exc:  # an address Dask cannot parse ("missing port number ...")
            raise InputError(f"--scheduler {scheduler}: not a scheduler address ({exc}); give "
                             "one like tcp://HOST:8786") from None
        workers = max(1, sum(client.nthreads().values()))
        return _Pool(client.get_executor(pure=False), workers, client if own else None)
    n = resolve_jobs(jobs)
    if n_tasks is not None:
        n = max(1, min(n, n_tasks))
    if n == 1:
        return _Pool(_InlineExecutor(), 1)
    ctx = None
    if mp_context is not None:
        from multiprocessing import get_context

        ctx = get_context(mp_context)
    from planerel.children import new_pool

    return _Pool(new_pool(n, ctx), n)


@dataclass(frozen=True)
class Failure:
    """One input that failed: its label (usually the path) and a one-sentence reason."""

    input: str
    message: str


@dataclass
class BatchResult:
    """What :func:`run_batch` saw: tasks done, failures, wall time."""

    n_tasks: int = 0
    n_done: int = 0
    failures: list = None
    seconds: float = 0.0

    def __post_init__(self) -> None:
        if self.failures is None:
            self.failures = []


def _reason(exc: BaseException) -> str:
    if isinstance(exc, PlanerelError):
        return str(exc)
    if isinstance(exc, MemoryError):
        return "out of memory"
    return f"{type(exc).__name__}: {exc}"


class _Progress:
    """A tqdm bar on a terminal, else a line on stderr every ``every`` seconds (and at the end
    when the batch took longer than one period)."""

    def __init__(self, total: int, desc: str, enabled: bool | None, every: float | None = None):
        self.total, self.desc = total, desc
        self.t0 = self.last = time.monotonic()
        self.every = every if every is not None else float(
            os.environ.get("PLANEREL_PROGRESS_SECONDS", "10"))
        tty = sys.stderr.isatty()
        self.bar = None
        self.lines = False
        if enabled is None:
            enabled = total > 1
        if enabled and tty:
            from tqdm import tqdm

            self.bar = tqdm(total=total, desc=desc, unit="scene", leave=False)
        elif enabled:
            self.lines = True

    def update(self, done: int, failed: int) -> None:
        if self.bar is not None:
            self.bar.update(1)
            if failed:
                self.bar.set_postfix(failed=failed)
            return
        now = time.monotonic()
        if self.lines and (now - self.last >= self.every):
            self.last = now
            self._line(done, failed, now)

    def _line(self, done, failed, now) -> None:
        rate = done / max(now - self.t0, 1e-9)
        left = (self.total - done) / rate if rate > 0 else float("nan")
        print(f"{self.desc}: {done}/{self.total} scenes ({100 * done / max(self.total, 1):.0f}%), "
              f"{rate:.2f} scenes/s, {failed} failed, ~{left:.0f} s left",
              file=sys.stderr, flush=True)

    def close(self, done: int, failed: int) -> None:
        if self.bar is not None:
            self.bar.close()
        elif self.lines and time.monotonic() - self.t0 >= self.every:
            self._line(done, failed, time.monotonic())


def run_batch(fn: Callable, tasks: Sequence, *, jobs: int | None = None,
              scheduler=None, keep_going: bool = False,
              label: Callable = str, desc: str = "scenes", progress: bool | None = None,
              result: BatchResult | None = None, window: int | None = None,
              mp_context: str | None = None,
              hint: str | None = "--keep-going goes on past bad inputs") -> Iterator:
    """Run ``fn(task)`` for every task on the chosen workers; yield ``(task, value)`` in order.

    Parameters
    ----------
    fn : callable
        A module-level function (it is pickled by reference for other processes).
    tasks : sequence
        Picklable task descriptions.
    jobs, scheduler
        See :func:`make_executor`.
    keep_going : bool
        Record a failing task in ``result.failures`` and go on; otherwise the first failure is
        raised as :class:`InputError` naming the task (after the workers are stopped).
    label : callable
        ``label(task)`` -> the name of the task's input in messages.
    result : BatchResult, optional
        Filled in while the batch runs (counts, failures, seconds).
    window : int, optional
        Tasks in flight at once (default 4 per worker): bounds the results held in memory.
    mp_context : str, optional
        See :func:`make_executor`.
    hint : str, optional
        Added in brackets to the error of a failing task when ``keep_going`` is off (None for
        callers whose command has no ``--keep-going``).

    Yields
    ------
    (task, value)
        For each task that succeeded, in the order of ``tasks``.
    """
    res = result if result is not None else BatchResult()
    res.n_tasks = len(tasks)
    t0 = time.perf_counter()
    pool = make_executor(jobs, scheduler, n_tasks=len(tasks), mp_context=mp_context)
    size = window or max(2, 4 * pool.workers)
    bar = _Progress(len(tasks), desc, progress)
    pending: deque = deque()
    it = iter(tasks)
    ok = False
    try:
        def fill() -> None:
            while len(pending) < size:
                try:
                    task = next(it)
                except StopIteration:
                    return
                pending.append((task, pool.executor.submit(fn, task)))

        fill()
        done = 0
        while pending:
            task, fut = pending.popleft()
            try:
                value = wait_result(fut)
            except Exception as exc:  # noqa: BLE001 - any failure of one input is reported
                reason = _reason(exc)
                name = label(task)
                if not keep_going:
                    tail = f" ({hint})" if hint else ""
                    if isinstance(exc, PlanerelError) and name in reason:
                        raise type(exc)(reason + tail) from None
                    if not isinstance(exc, PlanerelError) and not isinstance(exc, OSError):
                        raise
                    raise InputError(f"{name}: {reason}{tail}") from None
                res.failures.append(Failure(name, reason))
                done += 1
                bar.update(done, len(res.failures))
                fill()
                continue
            done += 1
            res.n_done += 1
            bar.update(done, len(res.failures))
            fill()
            yield task, value
        ok = True
    finally:
        bar.close(res.n_done + len(res.failures), len(res.failures))
        pool.close(cancel=not ok)
        res.seconds = time.perf_counter() - t0


def write_errors(path, failures: Sequence[Failure]) -> Path | None:
    """Write the failures as a tab-separated list ``input<TAB>reason`` (with a header line);
    remove a stale list when there is no failure.  Returns the path written, or None."""
    from planerel.atomic import write_text

    p = Path(path)
    if not failures:
        if p.is_file():
            p.unlink()
        return None
    lines = ["input\treason"] + [f"{f.input}\t{' '.join(f.message.split())}" for f in failures]
    return write_text(p, "\n".join(lines) + "\n")


def report_failures(command: str, failures: Sequence[Failure], errors_file, n_tasks: int) -> int:
    """Print the failures on stderr; the exit status of a ``--keep-going`` batch (1 when any
    input failed, else 0)."""
    if not failures:
        return 0
    for f in failures[:20]:
        # most messages name the input already ("x.png: cannot read the image (...)")
        said = f.message if f.message.startswith(f"{f.input}:") else f"{f.input}: {f.message}"
        print(f"planerel {command}: failed: {said}", file=sys.stderr)
    if len(failures) > 20:
        print(f"planerel {command}: ... and {len(failures) - 20} more", file=sys.stderr)
    where = f"; list in {errors_file}" if errors_file else ""
    print(f"planerel {command}: {len(failures)} of {n_tasks} inputs failed{where}",
          file=sys.stderr)
    return 1
