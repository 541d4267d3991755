"""Every numba kernel of planerel is cached on disk, so a new process loads it instead of
compiling it (benchmarks/bench_first_call.py measures the difference)."""

from __future__ import annotations

import importlib
import pkgutil

import planerel


def test_every_numba_kernel_has_an_on_disk_cache():
    from numba.core.caching import NullCache
    from numba.core.dispatcher import Dispatcher

    kernels, uncached = [], []
    for info in pkgutil.walk_packages(planerel.__path__, "planerel."):
        mod = importlib.import_module(info.name)
        for name, obj in vars(mod).items():
            if isinstance(obj, Dispatcher) and obj.__module__ == info.name:
                kernels.append(f"{info.name}.{name}")
                if isinstance(obj._cache, NullCache):
                    uncached.append(kernels[-1])
    assert len(kernels) >= 20  # the segmentation and feature kernels are found
    assert uncached == []
