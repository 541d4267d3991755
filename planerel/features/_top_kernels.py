"""numba kernels of two tests on what lies around a plane's top edge (compiled at first call,
cached on disk): the ring of pixels around a ``lying`` top
(:func:`planerel.features.lying._ground_around`) and the level strip on a tall face's top
edge (:func:`planerel.features.tall_face.cap_strip`).  Both read a few thousand pixels of one
plane's pixel box; in numpy each cost 0.1-0.3 ms a call in temporaries (speed32).

Import this module only from inside functions: numba itself is a heavy import.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from planerel.segment._intrinsics import prefetch


@njit(cache=True, error_model="numpy")
def _near_label(labels, r0, r1, c0, c1, label, k):
    """``(r1 - r0, c1 - c0)`` bool: the pixels of ``labels[r0:r1, c0:c1]`` within ``k`` pixels
    (a square neighbourhood) of a pixel labelled ``label``: running windows along the rows,
    then along the columns."""
    h, w = r1 - r0, c1 - c0
    rows = np.zeros((h, w), np.bool_)
    for i in range(h):
        last = -(2 * k + 1)                  # the last column of the label seen
        for j in range(w + k):
            if j < w and labels[r0 + i, c0 + j] == label:
                last = j
            if j >= k and j - last <= 2 * k:  # column j - k's window [j - 2k, j] holds it
                rows[i, j - k] = True
    near = np.zeros((h, w), np.bool_)
    for j in range(w):
        last = -(2 * k + 1)
        for i in range(h + k):
            if i < h and rows[i, j]:
                last = i
            if i >= k and i - last <= 2 * k:
                near[i - k, j] = True
    return near


@njit(cache=True, error_model="numpy")
def _ring_mask(labels, r0, r1, c0, c1, label, k, band):
    """``(r1 - r0, c1 - c0)`` bool: ``_near_label(..., k) & ~_near_label(..., band)`` (``band``
    < 0: nothing left out) from one read of the labels: each pixel's distance along its row
    to the nearest pixel labelled ``label`` (capped at ``k + 1``), then each column's window
    of ``k`` rows (a row within ``k``) and of ``band`` rows (a row within ``band``)."""
    h, w = r1 - r0, c1 - c0
    cap = k + 1
    dh = np.empty((h, w), np.int64)
    for i in range(h):
        d = cap
        for j in range(w):
            if labels[r0 + i, c0 + j] == label:
                d = 0
            elif d < cap:
                d += 1
            dh[i, j] = d
        d = cap
        for j in range(w - 1, -1, -1):
            if dh[i, j] == 0:
                d = 0
            elif d < cap:
                d += 1
            if d < dh[i, j]:
                dh[i, j] = d
    ring = np.zeros((h, w), np.bool_)
    for j in range(w):
        _mark_within(dh, j, k, ring, True)
        if band >= 0:
            _mark_within(dh, j, band, ring, False)
    return ring


@njit(cache=True, error_model="numpy")
def _mark_within(dh, j, k, out, value):
    """Set ``out[i, j] = value`` where a pixel of column ``j`` within ``k`` rows of row ``i``
    has a row distance ``dh`` of at most ``k`` (:func:`_near_label`'s column pass: row
    ``i - k``'s window ``[i - 2k, i]`` holds such a row)."""
    h = dh.shape[0]
    last = -(2 * k + 1)
    for i in range(h + k):
        if i < h and dh[i, j] <= k:
            last = i
        if i >= k and i - last <= 2 * k:
            out[i - k, j] = value


@njit(cache=True, error_model="numpy")
def ring_counts(labels, xyz, r0, r1, c0, c1, label, k, skip, tn, tc, gn, gc, den, rise, tol,
                band=0):
    """The ring around a ``lying`` top read against ``m`` grounds at once: the pixels of
    ``labels[r0:r1, c0:c1]`` within ``k`` pixels (a square neighbourhood) of one labelled
    ``label``, not labelled so themselves nor one of ``skip``, whose point is measured
    (finite z).  ``(m, 3)`` int64 counts of those points, of those at ground ``g``'s
    level (``|h| <= tol[g]``, ``h`` the height over ``g``'s fit along up: ``gn[g] . (p -
    gc[g]) / den[g]``) and of those between (``tol[g] < h < rise[g] + tol[g]``, not within
    ``tol[g]`` of the top's plane ``tn . (p - tc) = 0``).  With ``band`` > 0 the ring is
    the pixels within ``k + band`` of the label but not within ``band``: the band hugging
    the top's outline, where a depth edge's mixed pixels and the top's own side lie, is left
    out (lying56)."""
    ring = _ring_mask(labels, r0, r1, c0, c1, label, k + band, band if band > 0 else -1)
    m = gn.shape[0]
    out = np.zeros((m, 3), np.int64)
    W = labels.shape[1]
    for i in range(r1 - r0):
        if r0 + i + 1 < r1:
            # the next row's points asked for while this one is read (a box's rows are short
            # pieces of the image's rows: the hardware's prefetcher starts each anew)
            for c in range(c0, c1, 2):
                prefetch(xyz, 3 * ((r0 + i + 1) * W + c))
        for j in range(c1 - c0):
            if not ring[i, j]:
                continue
            r, c = r0 + i, c0 + j
            lab = labels[r, c]
            if lab == label:
                continue
            x, y, z = float(xyz[r, c, 0]), float(xyz[r, c, 1]), float(xyz[r, c, 2])
            if not math.isfinite(z):
                continue
            skipped = False
            for s in skip:
                if lab == s:
                    skipped = True
            if skipped:
                continue
            dt = abs((x - tc[0]) * tn[0] + (y - tc[1]) * tn[1] + (z - tc[2]) * tn[2])
            for g in range(m):
                h = ((x - gc[g, 0]) * gn[g, 0] + (y - gc[g, 1]) * gn[g, 1]
                     + (z - gc[g, 2]) * gn[g, 2]) / den[g]
                out[g, 0] += 1
                if abs(h) <= tol[g]:
                    out[g, 1] += 1
                elif dt > tol[g] and tol[g] < h < rise[g] + tol[g]:
                    out[g, 2] += 1
    return out


@njit(cache=True, error_model="numpy")
def cap_columns(labels, xyz, r0, r1, c0, c1, label, k, n, d0, up, top, tol, b0, b1):
    """For each column of ``labels[r0:r1, c0:c1]`` holding ``label``: do the ``k`` pixels above
    its first such pixel hold an unassigned (label < 0), measured point level with ``top``
    (``|up . p - top| <= tol``) and ``b0``-``b1`` behind the plane ``n . p = d0``?  Returns
    (the share of the label's columns that do, 0 without any; the 90th percentile over those
    columns of the farthest such ``n . p - d0``, interpolated as ``np.percentile`` does, 0
    without any)."""
    w = c1 - c0
    far = np.empty(w, np.float64)
    n_cols = 0
    n_hit = 0
    for j in range(w):
        c = c0 + j
        first = -1
        for r in range(r0, r1):
            if labels[r, c] == label:
                first = r
                break
        if first < 0:
            continue
        n_cols += 1
        best = -math.inf
        for r in range(max(first - k, 0), first):
            if labels[r, c] >= 0:
                continue
            x, y, z = float(xyz[r, c, 0]), float(xyz[r, c, 1]), float(xyz[r, c, 2])
            if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z)):
                continue
            beh = x * n[0] + y * n[1] + z * n[2] - d0
            lev = x * up[0] + y * up[1] + z * up[2]
            if abs(lev - top) <= tol and b0 <= beh <= b1 and beh > best:
                best = beh
        if best > -math.inf:
            far[n_hit] = best
            n_hit += 1
    if n_cols == 0 or n_hit == 0:
        return 0.0, 0.0
    v = np.sort(far[:n_hit])
    pos = 0.9 * (n_hit - 1)
    lo = int(math.floor(pos))
    hi = min(lo + 1, n_hit - 1)
    t = pos - lo
    d = v[hi] - v[lo]
    # numpy's linear interpolation: from the nearer end (its _lerp)
    q = v[hi] - d * (1.0 - t) if t >= 0.5 else v[lo] + d * t
    return n_hit / n_cols, q
