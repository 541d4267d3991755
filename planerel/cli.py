"""The ``planerel`` command line: one program, one subcommand per job.

Each subcommand lives in a module of :mod:`planerel.commands` that defines ``register(sub)``;
the modules import their heavy dependencies inside the command function, so ``--help`` is fast.
Every :class:`~planerel.errors.PlanerelError` becomes one line on stderr and exit code 2.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from planerel._version import __version__
from planerel.errors import PlanerelError

__all__ = ["main", "build_parser"]

# Order here is the order in ``planerel --help``.
COMMAND_MODULES = [
    "planerel.commands.dataset",
    "planerel.commands.convert",
    "planerel.commands.segment",
    "planerel.commands.induce",
    "planerel.commands.describe",
    "planerel.commands.export_aleph",
    "planerel.commands.learn",
    "planerel.commands.classify",
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
    try:
        result = args.func(args)
    except PlanerelError as exc:
        print(f"planerel {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"planerel {args.command}: interrupted", file=sys.stderr)
        return 130
    return int(result or 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
