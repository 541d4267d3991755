"""Atomic writing of files and folders.

A file is written to a temporary file in the target's folder, then moved onto it with
``os.replace``; a folder (a data set, a model) is built in a hidden sibling ``.NAME.tmp-PID-*`` and swapped with
the old one in one step (``renameat2(RENAME_EXCHANGE)`` on Linux).  A run that is interrupted,
killed or fails leaves the previous state or nothing, never a mix; the leftovers of a SIGKILLed
run are removed (or, for a folder caught between two renames, restored) by the next write of the
same target.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import errno
import os
import re
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

from planerel.errors import InputError

__all__ = ["atomic_path", "atomic_dir", "recover_dir", "write_bytes", "write_text",
           "check_output_file", "check_output_dir", "check_dir_target", "remove_stale_files",
           "stale_files_removed", "check_not_inputs"]


def _file_mode() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


_FILE_MODE = _file_mode()


#: folders made for the outputs of the command line's current command (None: nothing is
#: recorded, as in the Python API, where a long-lived process would only collect them); a
#: command that then fails removes those still empty (:func:`remove_made_folders`), so a
#: refused run leaves no empty output folder behind
_MADE: list[Path] | None = None


def record_made_folders() -> None:
    """Start recording the folders :func:`_make_folder` makes (the command line, before a
    command runs)."""
    global _MADE
    _MADE = []


def remove_made_folders() -> None:
    """Remove the recorded folders that are still empty (deepest first) and stop recording;
    the command line calls it when a command fails or is interrupted."""
    global _MADE
    for folder in sorted(set(_MADE or ()), key=lambda f: len(f.parts), reverse=True):
        with contextlib.suppress(OSError):
            folder.rmdir()  # only an empty folder goes
    _MADE = None


def forget_made_folders() -> None:
    """Keep the folders made so far and stop recording (a command that succeeded)."""
    global _MADE
    _MADE = None


def _make_folder(folder: Path, target: Path) -> None:
    """Create ``folder`` (and its parents) for writing ``target``; a clear error when a file
    stands in the way or the folder cannot be made."""
    missing, f = [], folder.absolute()
    while _MADE is not None and not os.path.lexists(f) and f.parent != f:
        missing.append(f)   # only while a command-line command records them
        f = f.parent
    try:
        folder.mkdir(parents=True, exist_ok=True)
        if _MADE is not None:
            _MADE.extend(missing)
    except FileExistsError:
        raise InputError(f"cannot write {target}: {folder} is a file, not a folder") from None
    except OSError as exc:
        what = "" if folder == target else f" for {target}"
        raise InputError(f"cannot create folder {folder}{what}: {exc.strerror}") from None


def _probe_folder(folder: Path, target: Path) -> None:
    """Create ``folder`` (and its parents) and check that a file can be made in it."""
    _make_folder(folder, target)
    try:
        fd, tmp = tempfile.mkstemp(prefix=".planerel-probe.", dir=folder)
    except OSError as exc:
        raise InputError(f"cannot write in {folder} ({exc.strerror}); choose a folder you may "
                         "write to") from None
    os.close(fd)
    with contextlib.suppress(OSError):
        os.unlink(tmp)


def _refuse_dash(path, option: str, what: str) -> None:
    """No planerel command writes its output file or folder to stdout: ``-`` is refused
    rather than made into a file or folder named ``-`` (``./-`` names one on purpose)."""
    if str(path).strip() == "-":
        raise InputError(f"{option} -: planerel writes no output to stdout with '-'; give a "
                         f"{what} name (./- for a {what} named '-')")


def _special_kind(path: Path) -> str | None:
    """What ``path`` (followed through symbolic links) is when it exists and is neither a
    regular file nor a folder: ``"a FIFO"``, ``"a device"``, ``"a socket"``; else None."""
    import stat

    try:
        mode = os.stat(path).st_mode
    except OSError:
        return None
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return None


#: Paths whose files are a process's open streams (``/dev/stdout -> /proc/self/fd/1``)
_STREAM_PATHS = ("/proc/", "/dev/fd/", "/dev/stdin", "/dev/stdout", "/dev/stderr")


def _via_proc(path: Path) -> bool:
    """True when the chain of symbolic links from ``path`` passes through :data:`_STREAM_PATHS`
    (``/dev/stdout -> /proc/self/fd/1 -> a log file``): the file at its end is a process's
    open stream, which a rename would take from under it."""
    p = os.path.abspath(path)
    for _ in range(40):  # the kernel's own bound on a link chain
        if p.startswith(_STREAM_PATHS):
            return True
        if not os.path.islink(p):
            return False
        p = os.path.normpath(os.path.join(os.path.dirname(p), os.readlink(p)))
    return True


def _write_target(target: Path, option: str | None = None) -> Path:
    """The file an atomic write of ``target`` replaces: ``target`` itself, or the file a
    symbolic link at ``target`` points to (the link is written through and stays a link,
    not replaced by a regular file).  Refuses a target that is a FIFO, a device or a socket,
    or a link to a process's stream (:data:`_STREAM_PATHS`: ``-o /dev/stdout``): a file written whole and then
    renamed cannot go there, and the rename would replace the special file or link itself
    (user89)."""
    where = f"{option} {target}" if option else str(target)
    kind = _special_kind(target)  # followed as the kernel follows it (/dev/stdout: a pipe)
    if kind is None and os.path.islink(target):
        real = os.path.realpath(target)
        if real.startswith(_STREAM_PATHS) or _via_proc(target):
            kind = "a link to a stream or a process's file"  # /proc/self/fd/1 to a log file
        elif not os.path.isdir(os.path.dirname(real)):
            raise InputError(f"{where}: is a link to {real}, whose folder does not exist")
        target = Path(real)
    if kind is not None:
        raise InputError(f"{where}: is {kind}, not a file; planerel writes each output file "
                         "whole and then renames it into place, so give a regular file name")
    return target


def check_output_file(path, option: str = "output") -> Path:
    """Refuse, before any work, an output file that cannot be written: an empty name, a
    folder, a FIFO or device (:func:`_write_target`), a folder that cannot be made or written
    to.  Creates the missing parent folders (as writing would).  Returns ``path`` as a
    :class:`Path`."""
    if path is None or not str(path).strip():
        raise InputError(f"{option} needs a file name")
    _refuse_dash(path, option, "file")
    target = Path(path)
    if target.is_dir():
        raise InputError(f"{option} {target}: is a folder; give a file name")
    if str(path).endswith(("/", os.sep)):
        # Path() drops the slash: "k.pl/" would write the file k.pl, "new/" a file named new
        raise InputError(f"{option} {path}: ends in a slash, as a folder's name does; give a "
                         "file name")
    real = _write_target(target, option)
    _probe_folder(real.parent if str(real.parent) else Path("."), target)
    return target


def check_not_inputs(outputs, inputs, option: str = "-o") -> None:
    """Refuse, before any work, an output file that is one of the inputs (``segment x.pcd -o
    .`` would write ``./x.pcd`` over the scan; ``describe x.pcd -o x.pcd``): the inputs are
    never written (user89).  Paths are compared through links (``os.path.realpath``)."""
    seen = {os.path.realpath(p): p for p in inputs}
    for out in outputs:
        hit = seen.get(os.path.realpath(out))
        if hit is not None:
            raise InputError(f"{option}: the output {out} is the input {hit}; planerel never "
                             "writes over its inputs: give another output name or folder")


def check_output_dir(path, option: str = "output") -> Path:
    """Create the output folder ``path`` (and its parents) before any work and check that files
    can be written in it; refuse an empty name or a path that is a file."""
    if path is None or not str(path).strip():
        raise InputError(f"{option} needs a folder name")
    _refuse_dash(path, option, "folder")
    folder = Path(path)
    if folder.exists() and not folder.is_dir():
        raise InputError(f"{option} {folder}: exists and is not a folder")
    _probe_folder(folder, folder)
    return folder


@contextlib.contextmanager
def atomic_path(path, suffix: str | None = None) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on success rename it onto ``path``.

    ``suffix`` defaults to the target's suffix so that libraries that choose a format by
    extension (Pillow, numpy) still see the right one.
    """
    asked = Path(path)
    folder = asked.parent if str(asked.parent) else Path(".")
    _make_folder(folder, asked)
    if asked.is_dir():  # the rename would fail after all the work, naming the temporary file
        raise InputError(f"{asked}: is a folder; give a file name")
    target = _write_target(asked)  # through a symbolic link; never onto a FIFO or device
    folder = target.parent
    try:
        # the pid in the name lets remove_stale_files tell a killed writer's file
        fd, tmp = tempfile.mkstemp(
            prefix=f".{target.name}.tmp-{os.getpid()}-",
            suffix=suffix if suffix is not None else target.suffix, dir=folder,
        )
    except OSError as exc:  # name the file asked for, not the temporary one
        raise InputError(f"cannot write {target}: {exc.strerror}") from None
    os.close(fd)
    tmp_path = Path(tmp)
    os.chmod(tmp_path, _FILE_MODE)  # mkstemp makes 0600; results are ordinary files
    try:
        yield tmp_path
        try:
            os.replace(tmp_path, target)
        except IsADirectoryError:
            raise InputError(f"{target}: is a folder; give a file name") from None
    except BaseException:
        with contextlib.suppress(OSError):
            tmp_path.unlink()
        raise


def write_bytes(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically; return the path."""
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
    return Path(path)


def write_text(path, text: str) -> Path:
    """Write UTF-8 ``text`` to ``path`` atomically; return the path."""
    return write_bytes(path, text.encode("utf-8"))


_RENAME_EXCHANGE = 2
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Swap two paths in one step (Linux renameat2); False when the system cannot."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):
        return False
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    if fn(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP):
        return False
    raise OSError(err, os.strerror(err), str(b))


def _pid_alive(pid: int) -> bool:
    from planerel.children import pid_alive

    return pid_alive(pid)


def recover_dir(path) -> None:
    """Clean up after a killed folder write of ``path``: remove ``.NAME.tmp-PID-*`` siblings of
    processes that are gone; an ``.NAME.old-PID-*`` sibling is moved back to ``NAME`` when the
    kill came between the two renames (``NAME`` missing), else removed."""
    target = Path(path)
    pat = re.compile(rf"\.{re.escape(target.name)}\.(tmp|old)-(\d+)-")
    try:
        entries = sorted(os.scandir(target.parent if str(target.parent) else "."),
                         key=lambda e: e.name)
    except OSError:
        return
    for entry in entries:
        m = pat.match(entry.name)
        if not m or _pid_alive(int(m.group(2))):
            continue
        if m.group(1) == "old" and not target.exists():
            with contextlib.suppress(OSError):
                os.replace(entry.path, target)
                continue
        shutil.rmtree(entry.path, ignore_errors=True)


_STALE_FILE = re.compile(r"\..+\.tmp-(\d+)-")


@contextlib.contextmanager
def stale_files_removed(folder) -> Iterator[None]:
    """Remove the temporary files killed writers left in ``folder`` (:func:`remove_stale_files`)
    before the block and again after it, however it ends: workers stopped by Ctrl-C in the
    middle of a write leave theirs behind.  ``folder`` None: nothing to do."""
    if folder is not None:
        remove_stale_files(folder)
    try:
        yield
    finally:
        if folder is not None:
            remove_stale_files(folder)


def remove_stale_files(folder) -> int:
    """Remove the temporary files (``.NAME.tmp-PID-*``) that :func:`atomic_path` writers left in
    ``folder`` when they were killed (a worker process stopped by Ctrl-C in the middle of a
    write); files of live processes are kept.  Returns how many were removed."""
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return 0
    n = 0
    for entry in entries:
        m = _STALE_FILE.match(entry.name)
        if not m or not entry.is_file(follow_symlinks=False) or _pid_alive(int(m.group(1))):
            continue
        with contextlib.suppress(OSError):
            os.unlink(entry.path)
            n += 1
    return n


def _looks_like(folder: Path, markers) -> bool:
    try:
        names = set(os.listdir(folder))
    except OSError:
        return False
    return not names or any(m in names for m in markers)


def _dir_target(path, markers) -> tuple[Path, Path]:
    """The checks of :func:`atomic_dir` before its temporary folder: ``(target, parent)``."""
    target = Path(path)
    if not str(path).strip():
        raise InputError("the output folder needs a name")
    folder = target.parent if str(target.parent) else Path(".")
    _make_folder(folder, target)
    recover_dir(target)
    if target.exists():
        if not target.is_dir():
            raise InputError(f"{target}: exists and is not a folder")
        if markers and not _looks_like(target, markers):
            raise InputError(f"{target}: exists and holds something else (none of "
                             f"{', '.join(markers)}); choose a new folder or empty it")
    return target, folder


def check_dir_target(path, *, markers=()) -> Path:
    """Refuse, before any work, a folder :func:`atomic_dir` would refuse at the end (a file, a
    folder of something else, a parent that cannot be made or written to)."""
    target, folder = _dir_target(path, markers)
    _probe_folder(folder, target)
    return target


@contextlib.contextmanager
def atomic_dir(path, *, markers=()) -> Iterator[Path]:
    """Yield an empty hidden folder next to ``path``; when the block ends normally it replaces
    ``path`` in one step; on any exception (Ctrl-C and SIGTERM too) it is removed and ``path``
    is untouched.

    Parameters
    ----------
    path : path
        The folder to (re)create.
    markers : sequence of str
        File names of which an existing, non-empty ``path`` must hold one to be replaced
        (e.g. ``manifest.csv`` for a data set): a folder of something else is never deleted.

    Raises
    ------
    InputError
        ``path`` is a file, or a non-empty folder without any of ``markers``, or its parent
        cannot be created.
    """
    target, folder = _dir_target(path, markers)
    try:
        tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.tmp-{os.getpid()}-", dir=folder))
    except OSError as exc:  # name the folder asked for, not the temporary one
        raise InputError(f"cannot write {target}: {exc.strerror}") from None
    os.chmod(tmp, 0o777 & ~_umask())
    try:
        yield tmp
        _swap_in(tmp, target)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _swap_in(tmp: Path, target: Path) -> None:
    if not target.exists():
        os.replace(tmp, target)
        return
    if _exchange(tmp, target):
        shutil.rmtree(tmp, ignore_errors=True)  # now the old folder
        return
    old = Path(tempfile.mkdtemp(prefix=f".{target.name}.old-{os.getpid()}-", dir=target.parent))
    os.replace(target, old)  # replaces the empty placeholder
    os.replace(tmp, target)
    shutil.rmtree(old, ignore_errors=True)
