"""The ``planerel`` command line: one program, one subcommand per job.

Each subcommand lives in a module of :mod:`planerel.commands` that defines ``register(sub)``;
the modules import their heavy dependencies inside the command function, so ``--help`` is fast.
Every :class:`~planerel.errors.PlanerelError`, and every ``OSError`` (full disk, read-only folder),
``MemoryError`` and ``UnicodeError``, becomes one sentence on stderr and exit code 2; SIGTERM is
handled like Ctrl-C (children stopped, partial outputs removed), exit code 143.
"""

from __future__ import annotations

import argparse
import importlib
import signal
import sys

from planerel._version import __version__
from planerel.errors import PlanerelError, user_message

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
    "planerel.commands.evaluate_objects",
    "planerel.commands.report",
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
    try:
        result = args.func(args)
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
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
    return int(result or 0)


class _Terminated(KeyboardInterrupt):
    """SIGTERM, raised like Ctrl-C so that every ``finally`` and ``except BaseException``
    cleans up (child processes killed, temporary folders removed)."""


def _raise_terminated(signum, frame):
    raise _Terminated()


def _terminate_like_interrupt():
    """Handle SIGTERM like SIGINT in the main thread; return the previous handler."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        return None
    return signal.signal(signal.SIGTERM, _raise_terminated)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
