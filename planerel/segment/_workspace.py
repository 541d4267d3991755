"""Per-thread scratch arrays of the organized pipeline (normals and region growing), reused
between calls of the same image size.  Its own module so that :mod:`planerel.segment.normals`
and :mod:`planerel.segment.regiongrow` both use it without importing each other."""

from __future__ import annotations

import sys
import threading

import numpy as np


class _Workspace:
    """Scratch arrays of one image size, reused between calls.

    Fresh memory costs a page fault per 4 KiB page on first touch (about 3 ms for 10 MB on the
    reference VM, as much as the whole growing step), so the organized pipeline keeps its
    scratch (~5 MB at 640x480) for the most recent image sizes (:data:`_WS_KEEP`) per thread.
    """

    def __init__(self, h: int, w: int) -> None:
        from planerel.segment._graph_kernels import graph_scratch

        n = h * w
        self.w = w
        self.rings = None  # the normals' ring buffers, see normal_rings()
        self.graph = graph_scratch(w)  # the neighbour graph's row buffers
        self.mom = np.empty(10)
        self.mask = np.empty((h, w), dtype=np.uint8)
        self.nvalid = np.empty(n, dtype=np.bool_)
        self.queue = np.empty(n, dtype=np.int32)
        self.seedable = np.empty(n, dtype=np.bool_)
        self.depth = np.empty(n, dtype=np.uint8)
        self.qlev = np.empty(n, dtype=np.uint8)
        self.comp = np.empty(n, dtype=np.int32)
        # output arrays handed to a Segmentation; reused only once no one refers to them
        self.out_normals = None
        self.out_labels = None
        self.entries = np.empty((max(16, n // 4), 3), dtype=np.int32)


def normal_rings(ws: _Workspace, smax: int, rmax: int) -> tuple:
    """The normals kernel's ring buffers ``(ri, rc, rsm)`` for window limits ``smax``,
    ``rmax`` (kept in the workspace; about 1 MB at 640x480)."""
    from planerel.segment._normal_kernels import ring_sizes

    sizes = ring_sizes(smax, rmax)
    if ws.rings is None or ws.rings[0] != sizes:
        rr, rc, rs = sizes
        ws.rings = (sizes, (np.empty((6, rr, ws.w), dtype=np.int16),
                            np.empty((rc, ws.w, 4)), np.empty((rs, ws.w, 3), dtype=np.float32)))
    return ws.rings[1]


def _padded_labels(ws: _Workspace, h: int, w: int) -> tuple:
    """The growing's label buffer (``padded`` with -2 around ``labels`` (h*w,), see
    :func:`planerel.segment._kernels.padded_labels`), reused as :func:`_output` reuses."""
    from planerel.segment._kernels import padded_labels

    arr = _reusable(ws, "out_labels", lambda: padded_labels(h, w)[0])
    return arr, arr[w + 1:w + 1 + h * w]


def _output(ws: _Workspace, name: str, shape: tuple, dtype) -> np.ndarray:
    """The workspace's output array ``name`` (see :func:`_reusable`), else a new one."""
    return _reusable(ws, name, lambda: np.empty(shape, dtype=dtype))


def _reusable(ws: _Workspace, name: str, make) -> np.ndarray:
    """The workspace's output array ``name`` when nothing outside the workspace refers to it any
    more (the Segmentation that received it, and every view of it, is gone), else ``make()``,
    kept for next time.

    Reusing returned arrays this way avoids the page faults of fresh memory (CPython reference
    counts are exact, so an array still held by a caller is never overwritten)."""
    arr = getattr(ws, name)
    # references: the workspace attribute, ``arr`` and getrefcount's argument; views add more
    if arr is None or sys.getrefcount(arr) > 3:
        arr = make()
        setattr(ws, name, arr)
    return arr


#: Image sizes whose scratch is kept per thread.
_WS_KEEP = 2
_WS_LOCAL = threading.local()


def _workspace(h: int, w: int) -> _Workspace:
    cache = getattr(_WS_LOCAL, "cache", None)
    if cache is None:
        cache = _WS_LOCAL.cache = {}
    ws = cache.pop((h, w), None)
    if ws is None:
        ws = _Workspace(h, w)
    cache[(h, w)] = ws  # most recent last
    while len(cache) > _WS_KEEP:
        cache.pop(next(iter(cache)))
    return ws
