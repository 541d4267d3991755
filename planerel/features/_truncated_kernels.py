"""numba kernel of :func:`planerel.features.facts.truncated_planes` (compiled at first call,
cached on disk).

Import this module only from inside functions: numba itself is a heavy import.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from planerel.segment._intrinsics import prefetch

#: How many outline pixels ahead :func:`truncated_at` asks for data (speed22y: 64 and 128
#: measured alike, 16 and 32 less).
_AHEAD = 64

#: Eight flags of 1 read as one word (unsigned: compared with a signed literal, numba would
#: go through float64, whose 53 bits cannot tell it from a word with its lowest flag 0).
_ALL_SAME = np.uint64(0x0101010101010101)


@njit(cache=True, inline="always", error_model="numpy")
def _range(xyz, r, c):
    """The point's distance from the sensor; inf when the point is invalid (NaN or 0)."""
    x, y, z = xyz[r, c, 0], xyz[r, c, 1], xyz[r, c, 2]
    d = math.sqrt(x * x + y * y + z * z)
    if math.isfinite(d) and d > 0:
        return d
    return math.inf


@njit(cache=True, inline="always", error_model="numpy")
def _range_at(X, p):
    """:func:`_range` of the point at flat pixel index ``p`` of the flat points ``X``."""
    x, y, z = X[3 * p], X[3 * p + 1], X[3 * p + 2]
    d = math.sqrt(x * x + y * y + z * z)
    if math.isfinite(d) and d > 0:
        return d
    return math.inf


@njit(cache=True, nogil=True, error_model="numpy")
def truncation_counts(lab, xyz, jump, band, border, n):
    """Per plane label ``0..n-1``: outline pixels, hidden outline pixels, whether a pixel lies
    within ``border`` pixels of the image border, whether the label has a pixel at all.

    An outline pixel has a 4-neighbour of another label or lies on the image border; it is
    hidden when a pixel of another label (or none) within ``band`` pixels along its row or
    column is valid and nearer to the sensor by more than ``jump * max(1, range)`` of that
    pixel's range.  Only outline pixels are tested (the one pass of the image reads the
    neighbours of those only).

    Parameters
    ----------
    lab : ndarray, shape (H, W), int
        Plane labels, negative unassigned.
    xyz : ndarray, shape (H, W, 3), float64
    jump, band, border, n
        As :func:`planerel.features.facts.truncated_planes`; ``n`` = largest label + 1.

    Returns
    -------
    n_out, n_hid : ndarray, shape (n,), int64
    at_edge, present : ndarray, shape (n,), bool
    """
    H, W = lab.shape
    n_out = np.zeros(n, np.int64)
    n_hid = np.zeros(n, np.int64)
    at_edge = np.zeros(n, np.bool_)
    # the strips within ``border`` of the image border
    b = min(border + 1, H, W)
    for r in range(H):
        if r < b or r >= H - b:
            for c in range(W):
                if lab[r, c] >= 0:
                    at_edge[lab[r, c]] = True
        else:
            for c in range(b):
                if lab[r, c] >= 0:
                    at_edge[lab[r, c]] = True
                if lab[r, W - 1 - c] >= 0:
                    at_edge[lab[r, W - 1 - c]] = True
    nw = (W + 7) // 8
    same = np.zeros(8 * nw, np.uint8)
    words = same.view(np.uint64)
    for r in range(H):
        # most pixels lie inside their plane (or their hole): four equal neighbours, nothing
        # to test; the row's flags in a branch-free loop first, which the compiler vectorises
        # (the image's first and last rows and columns keep 0: they are outline), then the
        # flags read eight at a time
        if 0 < r < H - 1:
            up, row, dn = lab[r - 1], lab[r], lab[r + 1]
            for c in range(W - 2):
                lv = row[c + 1]
                same[c + 1] = ((row[c] == lv) & (row[c + 2] == lv) & (up[c + 1] == lv)
                               & (dn[c + 1] == lv))
        elif r == H - 1:
            same[:] = 0
        for w in range(nw):
            if words[w] == _ALL_SAME:
                continue
            for c in range(8 * w, min(8 * w + 8, W)):
                if same[c]:
                    continue
                lv = lab[r, c]
                if lv < 0:
                    continue
                n_out[lv] += 1
                here = _range(xyz, r, c)
                hid = False
                for k in range(1, band + 1):
                    for d in range(4):
                        rr = r + k if d == 0 else (r - k if d == 1 else r)
                        cc = c + k if d == 2 else (c - k if d == 3 else c)
                        if rr < 0 or rr >= H or cc < 0 or cc >= W or lab[rr, cc] == lv:
                            continue
                        nr = _range(xyz, rr, cc)
                        if nr != math.inf and here - nr > jump * max(1.0, nr):
                            hid = True
                            break
                    if hid:
                        break
                if hid:
                    n_hid[lv] += 1
    # every label with a pixel has an outline pixel (its first pixel in row order has none
    # of its label above it or lies on the top row)
    return n_out, n_hid, at_edge, n_out > 0


@njit(cache=True, nogil=True, error_model="numpy")
def truncated_at(lab, xyz, brow, bcol, jump, band, border, share, n):
    """:func:`planerel.features.facts.truncated_planes`' answer from the label image's outline
    pixels already listed (``brow``, ``bcol``: every labelled pixel with a 4-neighbour of
    another label or on the image border, as :func:`planerel.features.planes._boundary_pixels`
    lists them), so the image is not scanned for them again.

    Per label ``0..n-1``: cut (within ``border`` of the image border, or at least ``share`` of
    its outline pixels hidden: :func:`truncation_counts`' counts, ``n_hid >= share *
    max(n_out, 1)``) and present.  Only the outline pixels whose answer is still open are
    tested: none of a plane at the border (cut whatever is hidden), and a plane's no more
    once its hidden pixels reach the share (cut) or cannot reach it with the pixels left (not
    cut); each plane's outline pixels are counted first.  The same answer as the counts give
    (a test compares).  ``lab`` and ``xyz`` C-contiguous (read through flat views).

    Returns
    -------
    cut, present : ndarray, shape (n,), bool
    """
    H, W = lab.shape
    cut = np.zeros(n, np.bool_)
    b = min(border + 1, H, W)
    for r in range(H):
        if r < b or r >= H - b:
            for c in range(W):
                if lab[r, c] >= 0:
                    cut[lab[r, c]] = True
        else:
            for c in range(b):
                if lab[r, c] >= 0:
                    cut[lab[r, c]] = True
                if lab[r, W - 1 - c] >= 0:
                    cut[lab[r, W - 1 - c]] = True
    L = lab.ravel()
    X = xyz.ravel()
    n_out = np.zeros(n, np.int64)
    nb = brow.shape[0]
    # the outline pixels are read in row order but far apart: each loop asks for the data of
    # the pixel _AHEAD places on (its label; its point and the row band rows below it, the
    # newest its band's box reads) while it works on this one (only when data arrives changes)
    for i in range(nb):
        if i + _AHEAD < nb:
            prefetch(L, brow[i + _AHEAD] * W + bcol[i + _AHEAD])
        lv = L[brow[i] * W + bcol[i]]
        if lv >= 0:
            n_out[lv] += 1
    # per label: its share of hidden pixels (as truncated_planes computes it), the hidden
    # pixels found and the outline pixels left to test; open: neither answer certain yet
    need = np.empty(n)
    n_hid = np.zeros(n, np.int64)
    left = n_out.copy()
    open_ = np.zeros(n, np.bool_)
    for lv in range(n):
        need[lv] = share * max(n_out[lv], 1)
        if n_out[lv] > 0 and not cut[lv]:
            if 0 >= need[lv]:
                cut[lv] = True
            elif not n_out[lv] < need[lv]:
                open_[lv] = True
    for i in range(nb):
        if i + _AHEAD < nb:
            ra = brow[i + _AHEAD]
            pa = ra * W + bcol[i + _AHEAD]
            prefetch(X, 3 * pa)
            if ra + band < H:
                prefetch(L, pa + band * W)
                prefetch(X, 3 * (pa + band * W))
        r = brow[i]
        c = bcol[i]
        p = r * W + c
        lv = L[p]
        if lv < 0 or not open_[lv]:
            continue
        here = math.nan  # the pixel's range, computed at its first neighbour of another label
        hid = False
        for k in range(1, band + 1):
            for d in range(4):
                rr = r + k if d == 0 else (r - k if d == 1 else r)
                cc = c + k if d == 2 else (c - k if d == 3 else c)
                if rr < 0 or rr >= H or cc < 0 or cc >= W:
                    continue
                q = rr * W + cc
                if L[q] == lv:
                    continue
                if here != here:
                    here = _range_at(X, p)
                nr = _range_at(X, q)
                if nr != math.inf and here - nr > jump * max(1.0, nr):
                    hid = True
                    break
            if hid:
                break
        left[lv] -= 1
        if hid:
            n_hid[lv] += 1
            if n_hid[lv] >= need[lv]:
                cut[lv] = True
                open_[lv] = False
        elif n_hid[lv] + left[lv] < need[lv]:
            open_[lv] = False
    return cut, n_out > 0
