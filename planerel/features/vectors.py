"""Small vector helpers of the relation and proposal stages: numpy's results for one 3-vector
or one short array, without numpy's per-call overhead (these run thousands of times a frame).

Each gives bit for bit what the numpy expression in its docstring gives (tests/test_small_calls.py).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["cross3", "lo_hi", "vec_norm"]


def cross3(u, v) -> np.ndarray:
    """``np.cross(u, v)`` of two 3-vectors of floats: the same products and differences in
    Python floats (``a1 b2 - a2 b1``, ...; the floats numpy's cross gives) without its
    overhead (about 15 us a call).  A float64 array's values are taken by ``tolist`` (the same
    Python floats as ``float`` of each, without a generator: 2.1 -> 0.85 us a call)."""
    u0, u1, u2 = u.tolist() if type(u) is np.ndarray and u.dtype == np.float64 else (float(x) for x in u)
    v0, v1, v2 = v.tolist() if type(v) is np.ndarray and v.dtype == np.float64 else (float(x) for x in v)
    return np.array([u1 * v2 - u2 * v1, u2 * v0 - u0 * v2, u0 * v1 - u1 * v0])


def vec_norm(x) -> float:
    """``float(np.linalg.norm(x))`` of a 1-D float64 array: numpy's own computation for it
    (``sqrt(x.dot(x))`` of ``x.ravel(order="K")``: the same BLAS dot product, and a
    correctly rounded square root either way) without the function's argument handling
    (about 3.2 -> 0.7 us a call)."""
    v = x.ravel(order="K")
    return math.sqrt(v.dot(v))


def lo_hi(a) -> tuple[float, float]:
    """``(float(a.min()), float(a.max()))`` of a 1-D float array from its Python list (about
    5 -> 1 us on a hull's vertices); numpy's reductions themselves when the list's sum is NaN
    (a NaN, or infinities of both signs), when a bound is a zero (numpy's choice between
    ``0.0`` and ``-0.0`` is kept) and for an empty array (numpy's error)."""
    v = a.tolist()
    if v:
        s = sum(v)
        if s == s:
            lo, hi = min(v), max(v)
            if lo != 0.0 and hi != 0.0:
                return lo, hi
    return float(a.min()), float(a.max())
