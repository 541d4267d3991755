"""The one exception hierarchy of planerel.

Every error a user can cause is a :class:`PlanerelError`; the CLI prints it as one line and
exits with code 2.  Subclasses say which stage failed:

``InputError``       bad files, shapes, values or parameters (also a ``ValueError``)
``PrologError``      SWI-Prolog missing, a Prolog file that does not load, a failed query
``LearnerError``     a learning run that failed or ran past its time limit
``DependencyError``  an optional component that is not installed; the message says how to install it
"""

from __future__ import annotations

__all__ = ["did_you_mean", "PlanerelError", "InputError", "PrologError", "LearnerError", "DependencyError",
           "user_message", "check_bools", "PlanerelWarning"]


class PlanerelError(Exception):
    """Base class of every error planerel raises on purpose."""


class InputError(PlanerelError, ValueError):
    """A file, array or parameter the user gave is wrong; the message names it."""


class PrologError(PlanerelError):
    """SWI-Prolog is missing, a Prolog text does not load, or a query failed."""


class LearnerError(PlanerelError):
    """A learning run failed, timed out, or produced no usable output."""


class DependencyError(PlanerelError):
    """A needed program or package is missing; the message gives the install command."""


class PlanerelWarning(UserWarning):
    """Something planerel decided in the user's place that the user should know about (a
    camera's intrinsics fitted to points that are no exact pinhole back-projection); the CLI
    prints it as a ``note:`` line, Python code gets a :mod:`warnings` warning."""


def did_you_mean(name: str, choices) -> str:
    """`` (did you mean X?)`` for the closest of ``choices`` to a mistyped ``name`` (difflib's
    ratio 0.75 or more), else ``""``: for the messages that refuse an unknown name."""
    import difflib

    close = difflib.get_close_matches(str(name), [str(c) for c in choices], n=1, cutoff=0.75)
    return f" (did you mean {close[0]}?)" if close else ""


def check_bools(params) -> None:
    """Raise :class:`InputError` when a field of the dataclass ``params`` annotated ``bool``
    holds anything but ``True`` or ``False`` (a switch given as ``"yes"`` or ``1`` from Python;
    the command line's ``--param`` is parsed to a bool before)."""
    import dataclasses

    for f in dataclasses.fields(params):
        if f.type in (bool, "bool"):
            v = getattr(params, f.name)
            if not isinstance(v, bool):
                raise InputError(f"{f.name} must be true or false, got {v!r}")


def user_message(exc: BaseException) -> str | None:
    """One sentence for an error the user can fix, or None for a bug (which keeps its traceback).

    :class:`PlanerelError` keeps its message (squeezed onto one line); ``OSError`` (full disk,
    read-only or missing folder, permissions), ``MemoryError`` and ``UnicodeError`` (a file
    name that is not valid in the file system's encoding) become a sentence that names the
    file and says what to do.
    """
    import errno

    if isinstance(exc, PlanerelError):
        return " ".join(str(exc).split())
    if isinstance(exc, MemoryError):
        return ("out of memory; use smaller inputs (--subsample, --max-points) or fewer parallel "
                "jobs (--jobs)")
    if isinstance(exc, UnicodeError):
        return (f"a file name or text cannot be encoded ({exc.reason}); use file and folder "
                "names in UTF-8")
    if isinstance(exc, OSError):
        where = exc.filename if exc.filename is not None else "a file"
        if exc.filename2 is not None:
            where = f"{where} -> {exc.filename2}"
        what = exc.strerror or str(exc) or type(exc).__name__
        advice = {
            errno.ENOSPC: "free some space or write somewhere else",
            errno.EDQUOT: "free some space or write somewhere else",
            errno.EACCES: "choose a folder you may write to, or fix its permissions",
            errno.EPERM: "choose a folder you may write to, or fix its permissions",
            errno.EROFS: "the file system is read-only: write somewhere else",
            errno.ENOENT: "check the path",
            errno.ENOTDIR: "check the path",
            errno.EISDIR: "give a file, not a folder",
            errno.EMFILE: "too many open files: raise the limit (ulimit -n) or use fewer jobs",
        }.get(exc.errno, "check the path and the disk")
        return " ".join(f"{where}: {what}; {advice}".split())
    return None
