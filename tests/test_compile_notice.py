"""The one-line notice when numba compiles planerel's kernels (planerel.compile_notice).

Real numba compiles real functions here: in this process for the terminal / not-a-terminal
cases, and in child processes on a pseudo-terminal for the cache (a kernel loaded from numba's
cache says nothing; the CLI watches).
"""

from __future__ import annotations

import io
import os
import pty
import select
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from planerel import compile_notice
from planerel.compile_notice import MESSAGE, unwatch, watch

numba = pytest.importorskip("numba")


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        if self.closed:  # as a real file does
            raise ValueError("I/O operation on closed file")
        return True


@pytest.fixture(autouse=True)
def _no_watch_left():
    # the CLI tests of this process may have left a listener (stderr is not a terminal under
    # pytest, so they do not); make sure each test starts and ends without one
    before = compile_notice._LISTENER
    compile_notice._LISTENER = None
    yield
    compile_notice._LISTENER = before


def _fresh_kernel(k: int):
    # a new function object each call: numba compiles it (no cache)
    @numba.njit
    def add(x):
        return x + k

    return add


def test_terminal_hears_once_when_numba_compiles():
    out = _Terminal()
    listener = watch(out)
    try:
        assert listener is not None
        assert watch(out) is None  # one listener per process
        assert _fresh_kernel(1)(1) == 2
        assert _fresh_kernel(2)(1) == 3
    finally:
        unwatch(listener)
    assert out.getvalue() == "\r" + MESSAGE + "\n"
    assert compile_notice._LISTENER is None


def test_not_a_terminal_hears_nothing():
    out = io.StringIO()
    assert watch(out) is None
    assert _fresh_kernel(3)(1) == 4
    assert out.getvalue() == ""
    closed = _Terminal()
    closed.close()
    assert watch(closed) is None  # a closed stream is not an error


def test_stream_closed_later_does_not_fail_the_compile():
    out = _Terminal()
    listener = watch(out)
    out.close()
    try:
        assert _fresh_kernel(5)(1) == 6
    finally:
        unwatch(listener)


def test_nothing_without_compiling():
    out = _Terminal()
    listener = watch(out)
    try:
        kernel = _fresh_kernel(4)
        kernel(1)
        out.truncate(0)
        out.seek(0)
        kernel(2)  # already compiled for this type: no compile, no word
    finally:
        unwatch(listener)
    assert out.getvalue() == ""


def _run_on_terminal(code: str, cwd: Path) -> str:
    """Run ``python -c code`` with stderr on a pseudo-terminal; return what it printed there."""
    master, slave = pty.openpty()
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(cwd), *sys.path]))
    env.pop("NUMBA_DISABLE_JIT", None)
    proc = subprocess.Popen([sys.executable, "-c", code], cwd=cwd, stderr=slave,
                            stdout=subprocess.DEVNULL, env=env)
    os.close(slave)
    chunks = []
    try:
        while True:
            ready, _, _ = select.select([master], [], [], 120)
            if not ready:
                break
            try:
                data = os.read(master, 4096)
            except OSError:  # the child closed the terminal
                break
            if not data:
                break
            chunks.append(data)
    finally:
        os.close(master)
        assert proc.wait(timeout=120) == 0
    return b"".join(chunks).decode().replace("\r\n", "\n")


def test_cached_kernel_says_nothing(tmp_path):
    (tmp_path / "notice_kernel.py").write_text(textwrap.dedent("""
        from numba import njit

        @njit(cache=True)
        def twice(x):
            return 2 * x
    """))
    code = ("from planerel.compile_notice import watch; watch(); "
            "import notice_kernel; assert notice_kernel.twice(3) == 6")
    first = _run_on_terminal(code, tmp_path)
    assert first.count(MESSAGE) == 1, first
    second = _run_on_terminal(code, tmp_path)  # loaded from numba's cache
    assert MESSAGE not in second, second


def test_cli_watches_on_a_terminal(tmp_path):
    # the CLI registers the notice before running a command: a probe command added to its
    # parser compiles a fresh kernel
    (tmp_path / "notice_kernel2.py").write_text(textwrap.dedent("""
        from numba import njit

        @njit
        def thrice(x):
            return 3 * x
    """))
    code = textwrap.dedent("""
        import sys
        import planerel.cli as cli
        def run(args):
            import notice_kernel2
            return 0 if notice_kernel2.thrice(2) == 6 else 1
        parser = cli.build_parser
        def build():
            p = parser()
            sub = [a for a in p._actions if a.__class__.__name__ == '_SubParsersAction'][0]
            sub.add_parser('probe').set_defaults(func=run)
            return p
        cli.build_parser = build
        sys.exit(cli.main(['probe']))
    """)
    printed = _run_on_terminal(code, tmp_path)
    assert printed.count(MESSAGE) == 1, printed
