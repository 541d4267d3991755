"""One line on a terminal when numba compiles planerel's kernels, so a first run does not look hung.

planerel's numeric kernels are compiled by numba the first time they run after an install or an
upgrade (about a minute of CPU for the kernels of one ``planerel classify`` on the 2-core machine
of docs/benchmarks.md) and then cached next to their modules (``cache=True``): later runs load
them in milliseconds. Without a word, that first minute looks like a hang. :func:`watch` prints
:data:`MESSAGE` once per process, when numba actually starts compiling (a kernel loaded from the
cache says nothing), and only when the stream is a terminal: a pipe, a log file or a test that
reads stderr sees nothing new.
"""

from __future__ import annotations

import contextlib
import sys
from typing import TextIO

__all__ = ["MESSAGE", "watch", "unwatch"]

MESSAGE = ("planerel: compiling its numeric kernels for this machine (once after an install or an "
           "upgrade, about a minute; cached afterwards)")

# The listener registered in this process (None: not watching). A forked worker inherits it.
_LISTENER = None


def watch(stream: TextIO | None = None):
    """Print :data:`MESSAGE` on ``stream`` (default ``sys.stderr``) the first time numba starts
    compiling in this process, if ``stream`` is a terminal.

    Returns the listener (pass it to :func:`unwatch`), or None when nothing is watched: the
    stream is not a terminal, numba is missing, or this process already watches.
    """
    global _LISTENER
    stream = sys.stderr if stream is None else stream
    if _LISTENER is not None:
        return None
    try:
        if not stream.isatty():
            return None
        from numba.core import event
    except (AttributeError, ValueError, ImportError):  # a closed or odd stream; no numba
        return None

    class _Notice(event.Listener):
        told = False

        def on_start(self, ev) -> None:
            if not self.told:
                self.told = True
                # "\r": a progress bar may be drawn on this line; it redraws on its next update.
                # A stream closed since must not fail the compile.
                with contextlib.suppress(ValueError, OSError):
                    print("\r" + MESSAGE, file=stream, flush=True)

        def on_end(self, ev) -> None:
            pass

    _LISTENER = _Notice()
    event.register("numba:compile", _LISTENER)
    return _LISTENER


def unwatch(listener) -> None:
    """Stop the listener :func:`watch` returned (None: nothing to do)."""
    global _LISTENER
    if listener is None:
        return
    from numba.core import event

    event.unregister("numba:compile", listener)
    if _LISTENER is listener:
        _LISTENER = None
