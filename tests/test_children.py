"""planerel.children: pools that can be stopped whole, waits that signals reach."""

from __future__ import annotations

import multiprocessing
import signal
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import pytest

from planerel.batch import make_executor
from planerel.children import wait_result

pytestmark = pytest.mark.skipif(not hasattr(signal, "pthread_kill"), reason="needs pthread_kill")


def _nothing():
    return None


class _InterruptAfterFork:
    """A multiprocessing context whose ``n``-th process start raises ``KeyboardInterrupt``
    right after the fork, before the executor can record the new worker."""

    def __init__(self, real, n):
        self._real, self._n, self._started = real, n, 0

    def __getattr__(self, name):
        return getattr(self._real, name)

    def Process(self, *args, **kwargs):  # noqa: N802 - the context's own name
        proc = self._real.Process(*args, **kwargs)
        start = proc.start

        def start_then_interrupt():
            start()
            self._started += 1
            if self._started == self._n:
                raise KeyboardInterrupt

        proc.start = start_then_interrupt
        return proc


def test_interrupt_between_fork_and_record_does_not_hang():
    before = set(multiprocessing.active_children())
    pool = make_executor(jobs=2, mp_context="fork")
    executor = pool.executor
    executor._mp_context = _InterruptAfterFork(executor._mp_context, 2)
    with pytest.raises(KeyboardInterrupt):
        executor.submit(_nothing)            # forks both workers: the 2nd start is interrupted
    unrecorded = [p for p in multiprocessing.active_children()
                  if p not in before and p.pid not in executor._processes]
    assert len(unrecorded) == 1              # the worker the executor never recorded
    pool.close(cancel=True)
    end = time.monotonic() + 10
    while time.monotonic() < end and any(p.is_alive() for p in unrecorded):
        time.sleep(0.05)
    assert not [p for p in multiprocessing.active_children() if p not in before]


class _Boom(Exception):
    pass


def _raise_boom(signum, frame):
    raise _Boom


def test_signal_taken_by_another_thread_interrupts_the_wait():
    """A signal the kernel gives to a worker thread runs Python's handler in the main thread
    only when that thread next runs bytecode: an untimed ``result()`` would wait for the task."""
    release = threading.Event()
    idents = []

    def task():
        idents.append(threading.get_ident())
        release.wait(20)
        return "done"

    previous = signal.signal(signal.SIGUSR1, _raise_boom)
    pool = ThreadPoolExecutor(1)
    try:
        fut = pool.submit(task)
        while not idents:
            time.sleep(0.01)
        threading.Timer(0.3, signal.pthread_kill, (idents[0], signal.SIGUSR1)).start()
        t0 = time.monotonic()
        with pytest.raises(_Boom):
            wait_result(fut)
        assert time.monotonic() - t0 < 5
    finally:
        release.set()
        pool.shutdown()
        signal.signal(signal.SIGUSR1, previous)
