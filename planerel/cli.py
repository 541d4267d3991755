"""The ``planerel`` command line: one program, one subcommand per job.

Each subcommand lives in a module of :mod:`planerel.commands` that defines ``register(sub)``;
the modules import their heavy dependencies inside the command function, so ``--help`` is fast.
Every :class:`~planerel.errors.PlanerelError`, and every ``OSError`` (full disk, read-only folder),
``MemoryError`` and ``UnicodeError``, becomes one sentence on stderr and exit code 2; SIGTERM is
handled like Ctrl-C (children stopped, partial outputs removed), exit code 143; a signal that
comes while an exception would be lost (inside logging's after-fork hook, a ``__del__``) is
taken a moment later instead.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import signal
import sys
import warnings

from planerel._version import __version__
from planerel.errors import PlanerelError, PlanerelWarning, user_message

__all__ = ["main", "build_parser"]

# Order here is the order in ``planerel --help``.
COMMAND_MODULES = [
    "planerel.commands.dataset",
    "planerel.commands.convert",
    "planerel.commands.segment",
    "planerel.commands.induce",
    "planerel.commands.describe",
    "planerel.commands.export_aleph",
    "planerel.commands.export_popper",
    "planerel.commands.learn",
    "planerel.commands.classify",
    "planerel.commands.evaluate_model",
    "planerel.commands.evaluate_objects",
    "planerel.commands.report",
    "planerel.commands.params",
]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="planerel",
        description=(
            "Range images and point clouds to planes, plane relations and Prolog facts; "
            "learn object-class rules with Aleph (or planerel's own learner) and classify "
            "new scenes by logic query."
        ),
        epilog="Run 'planerel COMMAND --help' for the options of one command.",
    )
    parser.add_argument("--version", action="version", version=f"planerel {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMAND_MODULES:
        importlib.import_module(name).register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    previous = _terminate_like_interrupt()
    from planerel.compile_notice import watch

    watch()  # one line on a terminal if numba compiles the kernels (first run after install)
    shown = warnings.showwarning
    warnings.showwarning = _note_or(shown)
    from planerel.atomic import forget_made_folders, record_made_folders, remove_made_folders

    record_made_folders()
    done = False
    try:
        result = args.func(args)
        done = True
    except BrokenPipeError:
        # the reader of stdout is gone (`planerel classify ... --json | head`): stop quietly,
        # as other command-line tools do, not "error: a file: Broken pipe; check the disk"
        _quiet_stdout()
        return 128 + signal.SIGPIPE
    except (PlanerelError, OSError, MemoryError, UnicodeError) as exc:
        message = user_message(exc)
        if message is None:  # pragma: no cover - every instance of these classes has one
            raise
        print(f"planerel {args.command}: error: {message}", file=sys.stderr)
        return 2
    except _Terminated:
        print(f"planerel {args.command}: terminated", file=sys.stderr)
        return 128 + signal.SIGTERM
    except KeyboardInterrupt:
        print(f"planerel {args.command}: interrupted", file=sys.stderr)
        return 130
    finally:
        if done:
            forget_made_folders()
        else:  # a refused or interrupted run leaves no empty output folder it made
            remove_made_folders()
        warnings.showwarning = shown
        for signum, handler in previous.items():
            signal.signal(signum, handler)
    return int(result or 0)


def _quiet_stdout() -> None:
    """Point stdout at /dev/null so that the interpreter's last flush of a closed pipe prints
    nothing either."""
    import os

    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):  # stdout is no file (a test's capture)
        pass


def _note_or(show):
    """A ``warnings.showwarning`` that prints a :class:`PlanerelWarning` as one ``note:`` line
    on stderr (as the CLI's other notes) and hands every other warning to ``show``."""

    def note(message, category, filename, lineno, file=None, line=None):
        if issubclass(category, PlanerelWarning):
            print(f"note: {message}", file=sys.stderr)
        else:
            show(message, category, filename, lineno, file, line)

    return note


class _Terminated(KeyboardInterrupt):
    """SIGTERM, raised like Ctrl-C so that every ``finally`` and ``except BaseException``
    cleans up (child processes killed, temporary folders removed)."""


def _handle_stop(signum, frame):
    """SIGTERM raises :class:`_Terminated`, SIGINT ``KeyboardInterrupt``, unless the signal
    came while code that must not be interrupted runs (:func:`_unsafe_to_raise`): then it is
    sent again a moment later."""
    if _unsafe_to_raise(frame):
        _deferred(signum)
        return
    if signum == signal.SIGTERM:
        raise _Terminated()
    raise KeyboardInterrupt()


def _unsafe_to_raise(frame, depth: int = 8) -> bool:
    """Whether an exception raised in ``frame`` would be lost or break a lock.

    ``os.fork`` runs :mod:`logging`'s after-fork hook, which releases logging's module lock;
    an exception raised inside it is printed as "Exception ignored" and dropped (the signal is
    lost) and the lock stays held, so every later fork in the process waits for it forever.
    Exceptions in ``__del__`` methods are dropped the same way.
    """
    import logging

    logging_file = logging.__file__
    while frame is not None and depth > 0:
        code = frame.f_code
        if code.co_filename == logging_file or code.co_name == "__del__":
            return True
        frame = frame.f_back
        depth -= 1
    return False


def _deferred(signum: int, delay: float = 0.02) -> None:
    """Send ``signum`` to the main thread again after ``delay`` seconds (from a helper thread:
    raising it from inside the handler would run the handler again at once)."""
    import threading

    target = threading.main_thread().ident

    def again() -> None:
        with contextlib.suppress(OSError):  # the thread or process is gone
            signal.pthread_kill(target, signum)

    timer = threading.Timer(delay, again)
    timer.daemon = True
    timer.start()


def _terminate_like_interrupt() -> dict:
    """Handle SIGTERM like SIGINT in the main thread, and both with :func:`_handle_stop`;
    return the previous handlers to restore. A SIGINT handler someone else installed (not
    Python's default) is left alone."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        return {}
    previous = {signal.SIGTERM: signal.signal(signal.SIGTERM, _handle_stop)}
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        previous[signal.SIGINT] = signal.signal(signal.SIGINT, _handle_stop)
    return previous


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
