"""numba kernels of :mod:`planerel.features.curved` (compiled at first call, cached on disk).

Import this module only from inside functions: numba itself is a heavy import.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from planerel.segment._intrinsics import prefetch

#: How many pixels of a pixel list ahead the list kernels ask for their data
#: (:func:`list_components_spans`, :func:`list_components_pitch`, :func:`open_pixel_list`): the
#: pixels of a list lie scattered over the image, where the hardware's prefetcher does not
#: follow them.  Only when the data arrives changes (C-order arrays assumed for the addresses;
#: any other layout only wastes the hint).
_AHEAD = 32


@njit(cache=True, nogil=True, error_model="numpy")
def _root(parent, i):
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


@njit(cache=True, inline="always", error_model="numpy")
def _compact_ids(parent, n):
    """``(ids, k)``: each of the ``n`` list entries' union-find root numbered 0..k-1 in the
    order the roots are first met (the list components' ids)."""
    ids = np.full(n, -1, np.int64)
    out = np.empty(n, np.int64)
    k = 0
    for t in range(n):
        a = _root(parent, t)
        if ids[a] < 0:
            ids[a] = k
            k += 1
        out[t] = ids[a]
    return out, k


@njit(cache=True, nogil=True, error_model="numpy")
def grid_components(mask, xyz, edge_depth):
    """Connected components of ``mask`` over 4-neighbours whose points lie within
    ``edge_depth * max(1, |z|)`` of each other (``z`` the upper or left pixel's depth).

    Parameters
    ----------
    mask : ndarray, shape (H, W), bool
    xyz : ndarray, shape (H, W, 3), float64
    edge_depth : float

    Returns
    -------
    (ndarray (H, W) int64, int)
        Component ids, -1 outside ``mask``, numbered 0, 1, ... by their first pixel
        (row-major); the number of components.
    """
    H, W = mask.shape
    # the mask's pixels numbered in row-major order (in ``out`` until the last pass): a
    # union-find over them alone; the components, numbered by their first pixel, do not
    # depend on how the union-find joins them
    out = np.full((H, W), -1, np.int64)
    n = 0
    for r in range(H):
        for c in range(W):
            if mask[r, c]:
                out[r, c] = n
                n += 1
    parent = np.arange(n)
    for r in range(H):
        for c in range(W):
            if not mask[r, c]:
                continue
            i = out[r, c]
            lim = edge_depth * max(1.0, abs(xyz[r, c, 2]))
            for dy, dx in ((0, 1), (1, 0)):
                rr, cc = r + dy, c + dx
                if rr >= H or cc >= W or not mask[rr, cc]:
                    continue
                d0 = xyz[rr, cc, 0] - xyz[r, c, 0]
                d1 = xyz[rr, cc, 1] - xyz[r, c, 1]
                d2 = xyz[rr, cc, 2] - xyz[r, c, 2]
                if np.sqrt(d0 * d0 + d1 * d1 + d2 * d2) <= lim:
                    a, b = _root(parent, i), _root(parent, out[rr, cc])
                    if a != b:
                        parent[max(a, b)] = min(a, b)
    ids = np.full(n, -1, np.int64)
    k = 0
    for r in range(H):
        for c in range(W):
            if mask[r, c]:
                a = _root(parent, out[r, c])
                if ids[a] < 0:
                    ids[a] = k
                    k += 1
                out[r, c] = ids[a]
    return out, k


@njit(cache=True, nogil=True, error_model="numpy")
def unexplained_mask(xyz, lab, explained):
    """``(H, W)`` bool: pixels with a finite depth whose label (-1 and other negatives: none)
    is not ``explained`` (``(K,)`` bool; labels ``K`` and above are not explained)."""
    H, W = lab.shape
    K = explained.shape[0]
    out = np.zeros((H, W), np.bool_)
    for r in range(H):
        for c in range(W):
            a = lab[r, c]
            # the label first: the depth (most of the cloud's memory) is read only for
            # pixels that no explained plane holds
            out[r, c] = (a < 0 or a >= K or not explained[a]) and np.isfinite(xyz[r, c, 2])
    return out



@njit(cache=True, inline="always", error_model="numpy")
def _row_any(mask, y, W):
    """Whether row ``y`` of ``mask`` holds a pixel: a branch-free count the compiler
    vectorizes (empty rows are skipped at a byte a pixel instead of a branch a pixel)."""
    s = 0
    for x in range(W):
        s += np.uint8(mask[y, x])
    return s > 0


@njit(cache=True, nogil=True, error_model="numpy")
def touching_counts(mask, lab, xyz, edge_depth, nlab, y0=0, y1=-1):
    """Per label (``(nlab,)`` int64) the number of (pixel of ``mask``, grid neighbour 1 or 2
    steps right, down, left or up of label ``b >= 0``) pairs whose points lie within
    ``edge_depth * max(1, |z|)`` (``z`` the mask pixel's depth) of each other:
    :func:`planerel.features.curved._touching_labels`.  The distance is summed as
    ``np.linalg.norm`` sums it, ``(x^2 + y^2) + z^2``.  ``y0, y1``: only rows ``y0..y1-1``
    of ``mask`` are read (the caller knows the mask holds no pixel outside them; ``y1`` -1:
    ``H``); its pixels' neighbours are read wherever they lie."""
    H, W = mask.shape
    out = np.zeros(nlab, np.int64)
    for y in range(y0, H if y1 < 0 else y1):
        if not _row_any(mask, y, W):
            continue  # a cluster's mask holds a few rows of the image
        for x in range(W):
            if not mask[y, x]:
                continue
            az = abs(xyz[y, x, 2])
            lim = edge_depth * (az if az > 1.0 or az != az else 1.0)  # np.maximum: NaN wins
            for k in range(1, 3):
                for d in range(4):
                    if d == 0:
                        yy, xx = y, x + k
                    elif d == 1:
                        yy, xx = y + k, x
                    elif d == 2:
                        yy, xx = y, x - k
                    else:
                        yy, xx = y - k, x
                    if yy < 0 or yy >= H or xx < 0 or xx >= W:
                        continue
                    b = lab[yy, xx]
                    if b < 0:
                        continue
                    d0 = xyz[yy, xx, 0] - xyz[y, x, 0]
                    d1 = xyz[yy, xx, 1] - xyz[y, x, 1]
                    d2 = xyz[yy, xx, 2] - xyz[y, x, 2]
                    if np.sqrt((d0 * d0 + d1 * d1) + d2 * d2) <= lim:
                        out[b] += 1
    return out


@njit(cache=True, nogil=True, error_model="numpy")
def count_outside(mask, lab, member, skip, y0=0, y1=-1):
    """Pixels of ``mask`` whose label is not a ``member`` (``(K,)`` bool; labels outside
    0..K-1 are no member) and not ``skip``; only rows ``y0..y1-1`` read (``y1`` -1: ``H``)."""
    H, W = mask.shape
    n = 0
    K = member.shape[0]
    for y in range(y0, H if y1 < 0 else y1):
        if not _row_any(mask, y, W):
            continue
        for x in range(W):
            if mask[y, x]:
                a = lab[y, x]
                if a != skip and (a < 0 or a >= K or not member[a]):
                    n += 1
    return n


@njit(cache=True, nogil=True, error_model="numpy")
def pitch_diffs(xyz, rows, cols, axis):
    """The finite ``|x2 / z2 - x / z|`` (``axis`` 1: ``x``, the next pixel along the row;
    ``axis`` 0: ``y``, the next pixel down) of pixels ``(rows, cols)`` whose next pixel lies
    in the image, in their order (the values the curved stage takes the pitches' medians of)."""
    H, W = xyz.shape[0], xyz.shape[1]
    j = 0 if axis == 1 else 1
    out = np.empty(rows.shape[0])
    n = 0
    for t in range(rows.shape[0]):
        r, c = rows[t], cols[t]
        r2, c2 = (r, c + 1) if axis == 1 else (r + 1, c)
        if r2 >= H or c2 >= W:
            continue
        d = abs(xyz[r2, c2, j] / xyz[r2, c2, 2] - xyz[r, c, j] / xyz[r, c, 2])
        if np.isfinite(d):
            out[n] = d
            n += 1
    return out[:n]


@njit(cache=True, nogil=True, error_model="numpy")
def pitch_diffs_both(xyz, rows, cols):
    """``(pitch_diffs(xyz, rows, cols, 1), pitch_diffs(xyz, rows, cols, 0))`` in one pass over
    the pixels (each pixel's point read once for both): the same values in the same order."""
    H, W = xyz.shape[0], xyz.shape[1]
    n = rows.shape[0]
    out1 = np.empty(n)
    out0 = np.empty(n)
    n1 = 0
    n0 = 0
    for t in range(n):
        r, c = rows[t], cols[t]
        z = xyz[r, c, 2]
        if c + 1 < W:
            d = abs(xyz[r, c + 1, 0] / xyz[r, c + 1, 2] - xyz[r, c, 0] / z)
            if np.isfinite(d):
                out1[n1] = d
                n1 += 1
        if r + 1 < H:
            d = abs(xyz[r + 1, c, 1] / xyz[r + 1, c, 2] - xyz[r, c, 1] / z)
            if np.isfinite(d):
                out0[n0] = d
                n0 += 1
    return out1[:n1], out0[:n0]


@njit(cache=True, nogil=True, error_model="numpy")
def mask_values(mask, lab, y0=0, y1=-1):
    """``lab[mask]`` (row-major) reading only the rows of ``mask`` that hold a pixel (a
    cluster's mask holds a few rows of the image), and of those only rows ``y0..y1-1``
    (the caller knows the mask holds no pixel outside them; ``y1`` -1: ``H``)."""
    H, W = mask.shape
    y1 = H if y1 < 0 else y1
    n = 0
    for y in range(y0, y1):
        if not _row_any(mask, y, W):
            continue
        for x in range(W):
            n += mask[y, x]
    out = np.empty(n, lab.dtype)
    k = 0
    for y in range(y0, y1):
        if not _row_any(mask, y, W):
            continue
        for x in range(W):
            if mask[y, x]:
                out[k] = lab[y, x]
                k += 1
    return out


@njit(cache=True, nogil=True, error_model="numpy")
def mask_points(mask, xyz):
    """``(rows, cols, fin, pts)``: ``np.nonzero(mask)`` (int64, row-major), whether each of
    those pixels' three coordinates are finite and the finite pixels' points (``(n, 3)``, in
    that order): ``xyz[rows, cols]`` and its rows where ``np.isfinite(...).all(1)``, reading
    only the rows of ``mask`` that hold a pixel."""
    H, W = mask.shape
    n = 0
    for y in range(H):
        if not _row_any(mask, y, W):
            continue
        for x in range(W):
            n += mask[y, x]
    rows = np.empty(n, np.int64)
    cols = np.empty(n, np.int64)
    fin = np.empty(n, np.bool_)
    pts = np.empty((n, 3), xyz.dtype)
    k = 0
    m = 0
    for y in range(H):
        if not _row_any(mask, y, W):
            continue
        for x in range(W):
            if mask[y, x]:
                rows[k] = y
                cols[k] = x
                a, b, c = xyz[y, x, 0], xyz[y, x, 1], xyz[y, x, 2]
                ok = np.isfinite(a) and np.isfinite(b) and np.isfinite(c)
                fin[k] = ok
                if ok:
                    pts[m, 0] = a
                    pts[m, 1] = b
                    pts[m, 2] = c
                    m += 1
                k += 1
    return rows, cols, fin, pts[:m]


@njit(cache=True, nogil=True, error_model="numpy")
def component_areas(xyz, rows, cols, comp, r0, c0, p0, p1, k):
    """``np.bincount(comp[rows - r0, cols - c0], weights=z^2 p0 p1, minlength=k)`` of
    pixels ``(rows, cols)`` of ``xyz`` (``z`` the depth's magnitude; component ids below
    ``k``): the footprints of :func:`planerel.features.curved._areas_at`, summed per
    component in the pixels' order, as ``bincount`` sums them."""
    out = np.zeros(k)
    for t in range(rows.shape[0]):
        z = abs(xyz[rows[t], cols[t], 2])
        out[comp[rows[t] - r0, cols[t] - c0]] += z * z * p0 * p1
    return out


@njit(cache=True, nogil=True, error_model="numpy")
def _erode_rows(o, m, y, r):
    """``o`` := row ``y`` of ``m`` AND-ed with rows ``y-r..y+r`` (the caller keeps them inside
    ``m``); byte loops over whole rows, which the compiler vectorizes."""
    W = o.shape[0]
    src = m[y]
    for i in range(W):
        o[i] = src[i]
    for k in range(1, r + 1):
        lo = m[y - k]
        hi = m[y + k]
        for i in range(W):
            o[i] &= lo[i] & hi[i]


@njit(cache=True, nogil=True, error_model="numpy")
def _dilate_row(o, row, r):
    """``o`` := ``row`` OR-ed with its copies shifted by -r..r (outside the row counts as
    unset); byte loops over row slices with non-negative indices, which the compiler
    vectorizes."""
    W = row.shape[0]
    for i in range(W):
        o[i] = row[i]
    for k in range(1, min(r, W - 1) + 1):
        a = o[:W - k]
        b = row[k:]
        for i in range(W - k):
            a[i] |= b[i]
        a = o[k:]
        b = row[:W - k]
        for i in range(W - k):
            a[i] |= b[i]


@njit(cache=True, nogil=True, error_model="numpy")
def _shift_pass(mask, r, axis, erode):
    """``mask`` AND-ed (erode) or OR-ed (dilate) with its copies shifted by -r..r along
    ``axis`` (outside the image counts as unset), as
    :func:`planerel.features.curved._shift_all`; row slices with non-negative indices, so the
    inner loops are plain byte loops the compiler vectorizes."""
    H, W = mask.shape
    m = mask.view(np.uint8)
    out = np.zeros((H, W), np.uint8)
    if axis == 1:
        for y in range(H):
            row = m[y]
            o = out[y]
            if erode:
                if W - 2 * r <= 0:
                    continue
                n = W - 2 * r
                oo = o[r:W - r]
                src = row[r:W - r]
                for i in range(n):
                    oo[i] = src[i]
                for k in range(1, r + 1):
                    lo = row[r - k:W - r - k]
                    hi = row[r + k:W - r + k]
                    for i in range(n):
                        oo[i] &= lo[i] & hi[i]
            else:
                _dilate_row(o, row, r)
    else:
        for y in range(H):
            o = out[y]
            if erode:
                if y - r < 0 or y + r >= H:
                    continue
                _erode_rows(o, m, y, r)
            else:
                for yy in range(max(0, y - r), min(H - 1, y + r) + 1):
                    src = m[yy]
                    for i in range(W):
                        o[i] |= src[i]
    return out.view(np.bool_)

@njit(cache=True, nogil=True, error_model="numpy")
def open_mask(mask, r):
    """Morphological opening of ``mask`` (C-contiguous bool) by a ``(2r+1)^2`` square, as
    :func:`planerel.features.curved._open`: erode along rows, then columns; unless nothing is
    left, dilate the same way (``r <= 0``: ``mask`` itself)."""
    if r <= 0:
        return mask
    er = _shift_pass(_shift_pass(mask, r, 1, True), r, 0, True)
    H, W = er.shape
    for y in range(H):
        for x in range(W):
            if er[y, x]:
                return _shift_pass(_shift_pass(er, r, 1, False), r, 0, False)
    return er


@njit(cache=True, nogil=True, error_model="numpy")
def unexplained_valid(valid, lab, explained):
    """:func:`unexplained_mask` from a cloud's valid mask (``(H, W)`` bool: a
    :class:`planerel.io.cloud.Cloud`'s pixel is valid exactly when its depth is finite, the
    invalid ones being all NaN): one byte a pixel read instead of the point."""
    H, W = lab.shape
    K = explained.shape[0]
    out = np.zeros((H, W), np.bool_)
    for r in range(H):
        for c in range(W):
            a = lab[r, c]
            out[r, c] = (a < 0 or a >= K or not explained[a]) and valid[r, c]
    return out


@njit(cache=True, nogil=True, error_model="numpy")
def unexplained_pixels(valid, lab, explained):
    """The rows and columns of :func:`unexplained_valid`'s pixels (``np.nonzero``, row-major)
    without the mask (``unexplained_open(..., 0)``'s pixel list: ``tests/test_curved.py``
    compares).

    With at most 32 labels in ``explained`` (every scene seen so far), the labels that
    explain a pixel are the bits of one word and the test of a pixel is branch-free
    (:func:`_unexplained_flag`): one pass over the image, each row's flags written to a row
    buffer (a loop the compiler vectorizes), counted by its 8-byte words and, when there are
    any, the nonzero words alone looked at; the lists grow by doubling (a few % of the
    pixels: rarely). More labels: one plain pass (:func:`_unexplained_pixels_any`), the
    same list."""
    H, W = lab.shape
    K = explained.shape[0]
    if K > 32:
        return _unexplained_pixels_any(valid, lab, explained)
    bits = np.uint32(0)
    every = True  # every label below K explains its pixels (every call on the real frames)
    for a in range(K):
        if explained[a]:
            bits |= np.uint32(1) << np.uint32(a)
        else:
            every = False
    k32 = np.int32(K)  # (an int32 bound: int32 labels compared in 32-bit lanes)
    cap = max(1024, H * W // 32)
    rows = np.empty(cap, np.int64)
    cols = np.empty(cap, np.int64)
    nw = (W + 7) // 8
    buf = np.zeros(nw * 8, np.uint8)  # one row's flags; the tail past W stays 0
    words = buf.view(np.uint64)
    ones = np.uint64(0x0101010101010101)
    k = 0
    for y in range(H):
        if every:
            # a pixel is unexplained when valid and its label outside [0, K): two compares
            # (the bit test's shift is widened to 64-bit lanes by numba's integer typing:
            # about half the pass's time; the same flags)
            for x in range(W):
                a = lab[y, x]
                buf[x] = np.uint8(valid[y, x]) & np.uint8((a < 0) | (a >= k32))
        else:
            for x in range(W):
                buf[x] = np.uint8(_unexplained_flag(lab[y, x], valid[y, x], bits))
        s = 0
        for w in range(nw):
            # the word's bytes are 0 or 1: their sum is the top byte of the product
            s += (words[w] * ones) >> np.uint64(56)
        if s == 0:
            continue
        if k + s > cap:
            while k + s > cap:
                cap *= 2
            r2, c2 = np.empty(cap, np.int64), np.empty(cap, np.int64)
            r2[:k], c2[:k] = rows[:k], cols[:k]
            rows, cols = r2, c2
        for w in range(nw):
            if words[w] != 0:
                for x in range(8 * w, 8 * w + 8):
                    if buf[x]:
                        rows[k] = y
                        cols[k] = x
                        k += 1
    return rows[:k].copy(), cols[:k].copy()


@njit(cache=True, inline="always", error_model="numpy")
def _unexplained_flag(a, v, bits):
    """1 when a pixel of label ``a`` and validity ``v`` is unexplained: valid, and ``a``
    outside ``[0, 32)`` or its bit in ``bits`` not set; else 0 (no branch)."""
    e = np.uint32((a >= 0) & (a < 32)) & ((bits >> (np.uint32(a) & np.uint32(31))) & np.uint32(1))
    return np.uint32(v) & (e ^ np.uint32(1))


@njit(cache=True, nogil=True, error_model="numpy")
def _unexplained_pixels_any(valid, lab, explained):
    """:func:`unexplained_pixels` for any number of labels, in one pass over the image."""
    H, W = lab.shape
    K = explained.shape[0]
    rows = np.empty(H * W, np.int64)
    cols = np.empty(H * W, np.int64)
    k = 0
    for y in range(H):
        for x in range(W):
            a = lab[y, x]
            if valid[y, x] and (a < 0 or a >= K or not explained[a]):
                rows[k] = y
                cols[k] = x
                k += 1
    return rows[:k].copy(), cols[:k].copy()


@njit(cache=True, nogil=True, error_model="numpy")
def unexplained_open(valid, lab, explained, r):
    """``open_mask(unexplained_valid(valid, lab, explained), r)`` and its pixels' rows and
    columns (``np.nonzero``, row-major) in one pass over the image: the erosion along rows
    is taken from the runs of unexplained pixels as they are found (a run ``[s, e)`` of a row
    keeps ``[s + r, e - r)``), the erosion along columns only on rows whose ``2r + 1``-row
    window holds row-eroded pixels, the dilation and the pixel list only inside the bounding
    box of what the erosion kept (the same pixels: ``tests/test_curved.py`` compares)."""
    H, W = lab.shape
    if r <= 0:
        found = unexplained_valid(valid, lab, explained)
        n = 0
        for y in range(H):
            for x in range(W):
                n += found[y, x]
        rows = np.empty(n, np.int64)
        cols = np.empty(n, np.int64)
        k = 0
        for y in range(H):
            for x in range(W):
                if found[y, x]:
                    rows[k], cols[k] = y, x
                    k += 1
        return found, rows, cols
    span = 2 * r + 1
    K = explained.shape[0]
    e1 = np.zeros((H, W), np.uint8)
    rowany = np.zeros(H, np.bool_)
    for y in range(H):
        run = 0
        for x in range(W):
            a = lab[y, x]
            if valid[y, x] and (a < 0 or a >= K or not explained[a]):
                run += 1
                if run >= span:
                    e1[y, x - r] = 1
                    rowany[y] = True
            else:
                run = 0
    return _open_tail(e1, rowany, H, W, r)


@njit(cache=True, nogil=True, error_model="numpy")
def open_pixels(rows, cols, lab, drop, H, W, r):
    """:func:`unexplained_open` from a row-major pixel list instead of the image: the pixels
    ``(rows, cols)`` (e.g. :func:`unexplained_pixels`' list) less those whose label ``a`` has
    ``drop[a]`` (``0 <= a < len(drop)``), opened with radius ``r``; the same mask and pixel
    list as :func:`unexplained_open` on the image of those pixels (``tests/test_curved.py``
    compares). The row runs of the erosion are read from the list (consecutive columns of
    one row)."""
    K = drop.shape[0]
    if r <= 0:
        found = np.zeros((H, W), np.bool_)
        ro = np.empty(len(rows), np.int64)
        co = np.empty(len(rows), np.int64)
        n = 0
        for i in range(len(rows)):
            y, x = rows[i], cols[i]
            a = lab[y, x]
            if 0 <= a < K and drop[a]:
                continue
            found[y, x] = True
            ro[n], co[n] = y, x
            n += 1
        return found, ro[:n].copy(), co[:n].copy()
    span = 2 * r + 1
    # only the rows that receive an eroded pixel are read after (_open_tail reads a row of
    # e1 only when rowany holds it): each is zeroed when its first pixel comes, the others
    # are left as allocated
    e1 = np.empty((H, W), np.uint8)
    rowany = np.zeros(H, np.bool_)
    run = 0
    py, px = -1, -2
    for i in range(len(rows)):
        y, x = rows[i], cols[i]
        a = lab[y, x]
        if 0 <= a < K and drop[a]:
            continue
        if y == py and x == px + 1:
            run += 1
        else:
            run = 1
        py, px = y, x
        if run >= span:
            if not rowany[y]:
                e1[y, :] = 0
                rowany[y] = True
            e1[y, x - r] = 1
    return _open_tail(e1, rowany, H, W, r)


@njit(cache=True, nogil=True, error_model="numpy")
def open_pixel_list(rows, cols, lab, drop, H, W, r):
    """The pixel list of :func:`open_pixels` (``open_pixels(...)[1:]``: the same pixels,
    row-major) without any ``(H, W)`` array: the opening worked on each row's runs of
    pixels (intervals of columns) instead of on images.  Erosion along a row keeps
    ``[s + r, e - r]`` of a run ``[s, e]`` at least ``2r + 1`` long; along columns, a row's
    intervals intersected with those of the ``r`` rows above and below; dilation along a row
    widens each interval by ``r`` (clipped to the image) and joins those that meet; along
    columns, a row's pixels are the union of the dilated intervals of the rows within ``r``
    of it (``tests/test_small_calls.py`` compares with :func:`open_pixels` and
    :func:`open_mask`)."""
    K = drop.shape[0]
    n = len(rows)
    if r <= 0:
        ro = np.empty(n, np.int64)
        co = np.empty(n, np.int64)
        m = 0
        for i in range(n):
            y, x = rows[i], cols[i]
            a = lab[y, x]
            if 0 <= a < K and drop[a]:
                continue
            ro[m], co[m] = y, x
            m += 1
        return ro[:m].copy(), co[:m].copy()
    span = 2 * r + 1
    # the row-eroded intervals, row-major: row, first and last column
    e_r = np.empty(n + 1, np.int64)
    e_a = np.empty(n + 1, np.int64)
    e_b = np.empty(n + 1, np.int64)
    ne = 0
    py, s, px = -1, 0, -2
    LW = lab.shape[1]
    for i in range(n + 1):
        if i + _AHEAD < n:
            prefetch(lab, rows[i + _AHEAD] * LW + cols[i + _AHEAD])  # scattered pixels' labels
        if i < n:
            y, x = rows[i], cols[i]
            a = lab[y, x]
            if 0 <= a < K and drop[a]:
                continue
            if y == py and x == px + 1:
                px = x
                continue
        # the run [s, px] of row py has ended
        if py >= 0 and px - s + 1 >= span:
            e_r[ne], e_a[ne], e_b[ne] = py, s + r, px - r
            ne += 1
        if i < n:
            py, s, px = y, x, x
    if ne == 0:
        return np.empty(0, np.int64), np.empty(0, np.int64)
    # each row's intervals: [off[y], off[y + 1])
    off = np.zeros(H + 1, np.int64)
    for k in range(ne):
        off[e_r[k] + 1] += 1
    for y in range(H):
        off[y + 1] += off[y]
    # erosion along columns: the rows whose 2r + 1 rows all hold intervals, intersected
    cap = span * ne + 1
    c_r = np.empty(cap, np.int64)
    c_a = np.empty(cap, np.int64)
    c_b = np.empty(cap, np.int64)
    ta = np.empty(cap, np.int64)
    tb = np.empty(cap, np.int64)
    ua = np.empty(cap, np.int64)
    ub = np.empty(cap, np.int64)
    nc = 0
    for y in range(r, H - r):
        ok = True
        for yy in range(y - r, y + r + 1):
            if off[yy + 1] == off[yy]:
                ok = False
                break
        if not ok:
            continue
        m = 0
        for k in range(off[y - r], off[y - r + 1]):
            ta[m], tb[m] = e_a[k], e_b[k]
            m += 1
        for yy in range(y - r + 1, y + r + 1):
            # ta[:m] AND the intervals of row yy, into ua, back to ta
            q = 0
            i = 0
            j = off[yy]
            jend = off[yy + 1]
            while i < m and j < jend:
                lo = max(ta[i], e_a[j])
                hi = min(tb[i], e_b[j])
                if lo <= hi:
                    ua[q], ub[q] = lo, hi
                    q += 1
                if tb[i] < e_b[j]:
                    i += 1
                else:
                    j += 1
            for t in range(q):
                ta[t], tb[t] = ua[t], ub[t]
            m = q
            if m == 0:
                break
        for t in range(m):
            c_r[nc], c_a[nc], c_b[nc] = y, ta[t], tb[t]
            nc += 1
    if nc == 0:
        return np.empty(0, np.int64), np.empty(0, np.int64)
    # dilation along rows: each interval widened by r (clipped), those that meet joined
    d_r = np.empty(nc, np.int64)
    d_a = np.empty(nc, np.int64)
    d_b = np.empty(nc, np.int64)
    nd = 0
    for k in range(nc):
        a, b = max(0, c_a[k] - r), min(W - 1, c_b[k] + r)
        if nd > 0 and d_r[nd - 1] == c_r[k] and a <= d_b[nd - 1] + 1:
            d_b[nd - 1] = max(d_b[nd - 1], b)
        else:
            d_r[nd], d_a[nd], d_b[nd] = c_r[k], a, b
            nd += 1
    doff = np.zeros(H + 1, np.int64)
    for k in range(nd):
        doff[d_r[k] + 1] += 1
    for y in range(H):
        doff[y + 1] += doff[y]
    # dilation along columns: row y's pixels are the union of the rows y - r .. y + r's
    # intervals (merged in order of their first column)
    y0, y1 = d_r[0], d_r[nd - 1]
    o_r = np.empty(span * nd + 1, np.int64)
    o_a = np.empty(span * nd + 1, np.int64)
    o_b = np.empty(span * nd + 1, np.int64)
    no = 0
    total = 0
    for y in range(max(0, y0 - r), min(H - 1, y1 + r) + 1):
        m = 0
        for yy in range(max(0, y - r), min(H - 1, y + r) + 1):
            for k in range(doff[yy], doff[yy + 1]):
                # insertion by first column (a few intervals a row)
                t = m
                while t > 0 and ta[t - 1] > d_a[k]:
                    ta[t], tb[t] = ta[t - 1], tb[t - 1]
                    t -= 1
                ta[t], tb[t] = d_a[k], d_b[k]
                m += 1
        t = 0
        while t < m:
            a, b = ta[t], tb[t]
            t += 1
            while t < m and ta[t] <= b + 1:
                b = max(b, tb[t])
                t += 1
            o_r[no], o_a[no], o_b[no] = y, a, b
            total += b - a + 1
            no += 1
    ro = np.empty(total, np.int64)
    co = np.empty(total, np.int64)
    m = 0
    for k in range(no):
        for x in range(o_a[k], o_b[k] + 1):
            ro[m], co[m] = o_r[k], x
            m += 1
    return ro, co


@njit(cache=True, nogil=True, error_model="numpy")
def _open_tail(e1, rowany, H, W, r):
    """:func:`unexplained_open` after the erosion along rows: the erosion along columns, the
    dilation and the pixel list."""
    # e2 and d1: a row is read only after it is written whole (_erode_rows, _dilate_row),
    # the rows rowe2 holds; the others are left as allocated
    e2 = np.empty((H, W), np.uint8)
    rowe2 = np.zeros(H, np.bool_)
    y0, y1, x0, x1 = H, -1, W, -1
    for y in range(r, H - r):
        ok = True
        for yy in range(y - r, y + r + 1):
            if not rowany[yy]:
                ok = False
                break
        if not ok:
            continue
        o = e2[y]
        _erode_rows(o, e1, y, r)
        s = 0
        for x in range(W):
            s += o[x]
        if s:
            rowe2[y] = True
            if y0 > y:
                y0 = y
            y1 = y
            x = 0
            while not o[x]:
                x += 1
            x0 = min(x0, x)
            x = W - 1
            while not o[x]:
                x -= 1
            x1 = max(x1, x)
    if y1 < 0:
        return np.zeros((H, W), np.bool_), np.empty(0, np.int64), np.empty(0, np.int64)
    # dilation along rows (clipped to the image), then along columns; only rows that hold
    # eroded pixels are read (byte loops over row slices, as in _shift_pass)
    d1 = np.empty((H, W), np.uint8)
    for y in range(y0, y1 + 1):
        if not rowe2[y]:
            continue
        _dilate_row(d1[y], e2[y], r)
    out = np.zeros((H, W), np.uint8)
    per = np.zeros(H, np.int64)
    a0, a1 = max(0, y0 - r), min(H - 1, y1 + r)
    b0, b1 = max(0, x0 - r), min(W - 1, x1 + r)
    n = 0
    for y in range(a0, a1 + 1):
        o = out[y, b0:b1 + 1]
        for yy in range(max(y0, y - r), min(y1, y + r) + 1):
            if not rowe2[yy]:
                continue
            src = d1[yy, b0:b1 + 1]
            for x in range(b1 + 1 - b0):
                o[x] |= src[x]
        s = 0
        for x in range(b1 + 1 - b0):
            s += o[x]
        per[y] = s
        n += s
    rows = np.empty(n, np.int64)
    cols = np.empty(n, np.int64)
    k = 0
    for y in range(a0, a1 + 1):
        left = per[y]
        x = b0
        while left > 0:
            if out[y, x]:
                rows[k], cols[k] = y, x
                k += 1
                left -= 1
            x += 1
    return out.view(np.bool_), rows, cols


@njit(cache=True, nogil=True, error_model="numpy")
def list_components_pitch(rows, cols, xyz, edge_depth, H):
    """``(*list_components(rows, cols, xyz, edge_depth, H), *pitch_diffs_both(xyz, rows,
    cols))`` in one pass over the pixels (both read each pixel's point and its right and
    lower neighbours'): the same components, and the same pitch values in the same order.

    Returns
    -------
    (ndarray (N,) int64, int, ndarray float64, ndarray float64)
    """
    n = rows.shape[0]
    W = xyz.shape[1]
    HX = xyz.shape[0]
    parent = np.arange(n)
    out1 = np.empty(n)
    out0 = np.empty(n)
    n1 = 0
    n0 = 0
    lo = 0  # the first pixel of row r + 1 at or after column c (r, c: the current pixel's)
    for t in range(n):
        if t + _AHEAD < n:
            # the point of a pixel ahead and its lower neighbour's
            q = rows[t + _AHEAD] * W + cols[t + _AHEAD]
            prefetch(xyz, 3 * q)
            prefetch(xyz, 3 * (q + W))
        r, c = rows[t], cols[t]
        z = xyz[r, c, 2]
        # the pitches (pitch_diffs_both)
        if c + 1 < W:
            d = abs(xyz[r, c + 1, 0] / xyz[r, c + 1, 2] - xyz[r, c, 0] / z)
            if np.isfinite(d):
                out1[n1] = d
                n1 += 1
        if r + 1 < HX:
            d = abs(xyz[r + 1, c, 1] / xyz[r + 1, c, 2] - xyz[r, c, 1] / z)
            if np.isfinite(d):
                out0[n0] = d
                n0 += 1
        # the components (list_components)
        lim = edge_depth * max(1.0, abs(z))
        if t + 1 < n and rows[t + 1] == r and cols[t + 1] == c + 1:
            d0 = xyz[r, c + 1, 0] - xyz[r, c, 0]
            d1 = xyz[r, c + 1, 1] - xyz[r, c, 1]
            d2 = xyz[r, c + 1, 2] - xyz[r, c, 2]
            if np.sqrt(d0 * d0 + d1 * d1 + d2 * d2) <= lim:
                a, b = _root(parent, t), _root(parent, t + 1)
                if a != b:
                    parent[max(a, b)] = min(a, b)
        if r + 1 < H:
            if lo <= t:
                lo = t + 1
            while lo < n and (rows[lo] == r or (rows[lo] == r + 1 and cols[lo] < c)):
                lo += 1
            if lo < n and rows[lo] == r + 1 and cols[lo] == c:
                d0 = xyz[r + 1, c, 0] - xyz[r, c, 0]
                d1 = xyz[r + 1, c, 1] - xyz[r, c, 1]
                d2 = xyz[r + 1, c, 2] - xyz[r, c, 2]
                if np.sqrt(d0 * d0 + d1 * d1 + d2 * d2) <= lim:
                    a, b = _root(parent, t), _root(parent, lo)
                    if a != b:
                        parent[max(a, b)] = min(a, b)
    comp, k = _compact_ids(parent, n)
    return comp, k, out1[:n1], out0[:n0]


@njit(cache=True, nogil=True, error_model="numpy")
def list_components_spans(rows, cols, xyz, edge_depth, H, e1, e2):
    """:func:`list_components` and, per component, its points' horizontal reach: ``hypot``
    of the ranges of their coordinates along ``e1`` and ``e2``, NaN when one is not finite
    (:func:`planerel.features._stairfit_kernels.cluster_spans` of the components, from the
    points as they are read: each tree of the union-find keeps its points' bounds at its
    root; a minimum or maximum does not depend on the order its values come in, so the
    same bounds and the same reach).

    Returns
    -------
    (ndarray (N,) int64, int, ndarray (k,) float64)
    """
    n = rows.shape[0]
    parent = np.arange(n)
    lo_u = np.empty(n)
    hi_u = np.empty(n)
    lo_v = np.empty(n)
    hi_v = np.empty(n)
    bad = np.zeros(n, np.bool_)
    W = xyz.shape[1]
    for t in range(n):
        if t + _AHEAD < n:
            prefetch(xyz, 3 * (rows[t + _AHEAD] * W + cols[t + _AHEAD]))
        r, c = rows[t], cols[t]
        x, y, z = xyz[r, c, 0], xyz[r, c, 1], xyz[r, c, 2]
        u = x * e1[0] + y * e1[1] + z * e1[2]
        v = x * e2[0] + y * e2[1] + z * e2[2]
        lo_u[t] = u
        hi_u[t] = u
        lo_v[t] = v
        hi_v[t] = v
        bad[t] = not (math.isfinite(u) and math.isfinite(v))
    lo = 0  # the first pixel of row r + 1 at or after column c (r, c: the current pixel's)
    for t in range(n):
        r, c = rows[t], cols[t]
        lim = edge_depth * max(1.0, abs(xyz[r, c, 2]))
        # right neighbour
        if t + 1 < n and rows[t + 1] == r and cols[t + 1] == c + 1:
            d0 = xyz[r, c + 1, 0] - xyz[r, c, 0]
            d1 = xyz[r, c + 1, 1] - xyz[r, c, 1]
            d2 = xyz[r, c + 1, 2] - xyz[r, c, 2]
            if np.sqrt(d0 * d0 + d1 * d1 + d2 * d2) <= lim:
                a, b = _root(parent, t), _root(parent, t + 1)
                if a != b:
                    _join_bounds(parent, lo_u, hi_u, lo_v, hi_v, bad, a, b)
        # lower neighbour
        if r + 1 < H:
            if lo <= t:
                lo = t + 1
            while lo < n and (rows[lo] == r or (rows[lo] == r + 1 and cols[lo] < c)):
                lo += 1
            if lo < n and rows[lo] == r + 1 and cols[lo] == c:
                d0 = xyz[r + 1, c, 0] - xyz[r, c, 0]
                d1 = xyz[r + 1, c, 1] - xyz[r, c, 1]
                d2 = xyz[r + 1, c, 2] - xyz[r, c, 2]
                if np.sqrt(d0 * d0 + d1 * d1 + d2 * d2) <= lim:
                    a, b = _root(parent, t), _root(parent, lo)
                    if a != b:
                        _join_bounds(parent, lo_u, hi_u, lo_v, hi_v, bad, a, b)
    out, k = _compact_ids(parent, n)
    span = np.zeros(k)
    for t in range(n):
        if parent[t] == t:  # a root (its own id is out[t]): its tree's bounds
            if bad[t]:
                span[out[t]] = np.nan
            else:
                span[out[t]] = math.hypot(hi_u[t] - lo_u[t], hi_v[t] - lo_v[t])
    return out, k, span


@njit(cache=True, inline="always", error_model="numpy")
def _join_bounds(parent, lo_u, hi_u, lo_v, hi_v, bad, a, b):
    """Join the trees of roots ``a`` and ``b`` (the smaller root stays, as
    :func:`list_components` joins them) with their bounds."""
    keep, gone = min(a, b), max(a, b)
    parent[gone] = keep
    lo_u[keep] = min(lo_u[keep], lo_u[gone])
    hi_u[keep] = max(hi_u[keep], hi_u[gone])
    lo_v[keep] = min(lo_v[keep], lo_v[gone])
    hi_v[keep] = max(hi_v[keep], hi_v[gone])
    bad[keep] = bad[keep] or bad[gone]


@njit(cache=True, nogil=True, error_model="numpy")
def list_components(rows, cols, xyz, edge_depth, H):
    """:func:`grid_components` of the mask whose pixels are ``(rows, cols)`` (row-major, as
    ``np.nonzero`` gives them; rows below ``H``), read from the pixel list alone: each
    pixel's right neighbour is the next pixel of the list, its lower neighbour is found by
    a pointer that moves forward through the list (the first pixel of the next row at or
    after the column: it only grows as the list is read; no ``(H, W)`` map is written or
    read).

    Returns
    -------
    (ndarray (N,) int64, int)
        Each pixel's component id (numbered 0, 1, ... by their first pixel, as
        :func:`grid_components`), the number of components.
    """
    n = rows.shape[0]
    parent = np.arange(n)
    lo = 0  # the first pixel of row r + 1 at or after column c (r, c: the current pixel's)
    for t in range(n):
        r, c = rows[t], cols[t]
        lim = edge_depth * max(1.0, abs(xyz[r, c, 2]))
        # right neighbour
        if t + 1 < n and rows[t + 1] == r and cols[t + 1] == c + 1:
            d0 = xyz[r, c + 1, 0] - xyz[r, c, 0]
            d1 = xyz[r, c + 1, 1] - xyz[r, c, 1]
            d2 = xyz[r, c + 1, 2] - xyz[r, c, 2]
            if np.sqrt(d0 * d0 + d1 * d1 + d2 * d2) <= lim:
                a, b = _root(parent, t), _root(parent, t + 1)
                if a != b:
                    parent[max(a, b)] = min(a, b)
        # lower neighbour
        if r + 1 < H:
            if lo <= t:
                lo = t + 1
            while lo < n and (rows[lo] == r or (rows[lo] == r + 1 and cols[lo] < c)):
                lo += 1
            if lo < n and rows[lo] == r + 1 and cols[lo] == c:
                d0 = xyz[r + 1, c, 0] - xyz[r, c, 0]
                d1 = xyz[r + 1, c, 1] - xyz[r, c, 1]
                d2 = xyz[r + 1, c, 2] - xyz[r, c, 2]
                if np.sqrt(d0 * d0 + d1 * d1 + d2 * d2) <= lim:
                    a, b = _root(parent, t), _root(parent, lo)
                    if a != b:
                        parent[max(a, b)] = min(a, b)
    out, k = _compact_ids(parent, n)
    return out, k


@njit(cache=True, nogil=True, error_model="numpy")
def list_areas_depths(xyz, rows, cols, ids, p0, p1, k):
    """``(list_areas(...), np.bincount(ids, weights=xyz[rows, cols, 2], minlength=k),
    np.bincount(ids, minlength=k))`` in one pass over the pixels: the same sums in the same
    order (``bincount`` adds its weights in their order)."""
    out = np.zeros(k)
    zs = np.zeros(k)
    cnt = np.zeros(k, np.int64)
    for t in range(rows.shape[0]):
        zz = xyz[rows[t], cols[t], 2]
        z = abs(zz)
        c = ids[t]
        out[c] += z * z * p0 * p1
        zs[c] += zz
        cnt[c] += 1
    return out, zs, cnt


@njit(cache=True, nogil=True, error_model="numpy")
def list_areas(xyz, rows, cols, ids, p0, p1, k):
    """:func:`component_areas` with each pixel's component id given in a list (``ids``, as
    :func:`list_components` gives them): the same sums in the same order."""
    out = np.zeros(k)
    for t in range(rows.shape[0]):
        z = abs(xyz[rows[t], cols[t], 2])
        out[ids[t]] += z * z * p0 * p1
    return out


@njit(cache=True, nogil=True, error_model="numpy")
def grow_clusters(rows, cols, ids, k, full, xyz, edge_depth, steps, cap):
    """Clusters grown back into the mask before the opening: ``steps`` rounds of
    4-neighbour growth into pixels of ``full`` whose points lie within
    ``edge_depth * max(1, |z|)`` of the growing pixel's (``z`` its depth); two clusters whose
    pixels meet so (growing or grown) become one.

    Parameters
    ----------
    rows, cols, ids : ndarray (N,) int64
        The clusters' pixels (opened) and each one's cluster, ``0 .. k-1``.
    full : ndarray (H, W) bool
        The unexplained pixels before the opening (a superset of the clusters' pixels).
    cap : int
        At least the number of pixels of ``full``.

    Returns
    -------
    (rows, cols, group) : ndarray (M,) int64
        The given pixels, then the grown ones in the order reached; each pixel's group, the
        smallest cluster id among the clusters joined.
    """
    return grow_in_box(rows, cols, ids, k, full, 0, 0, full.shape[0], full.shape[1], xyz,
                       edge_depth, steps, cap)


@njit(cache=True, nogil=True, error_model="numpy")
def grow_in_box(rows, cols, ids, k, full, fy, fx, H, W, xyz, edge_depth, steps, cap):
    """:func:`grow_clusters` with ``full`` given for a part of the ``(H, W)`` image only: its
    pixel ``(i, j)`` is the image's ``(fy + i, fx + j)``, and it covers the box of the given
    pixels grown by ``steps`` (clipped to the image; :func:`grow_box`). The clusters'
    map is kept for that box only, not the image: nothing grows past it (a pixel ``steps``
    4-neighbour steps from every given one is only reached in the last round, which grows
    nothing), so the same pixels, in the same order, and the same groups."""
    n = rows.shape[0]
    y0, y1, x0, x1 = grow_box(rows, cols, H, W, steps)
    # the box's map of cluster ids (-1 none) in int32: half the bytes to fill (the box is
    # most of the image on the real frames); ids below k, taken back as they were
    lab = np.full((y1 - y0, x1 - x0), -1, np.int32)
    parent = np.arange(k)
    R = np.empty(cap, np.int64)
    C = np.empty(cap, np.int64)
    for t in range(n):
        R[t] = rows[t]
        C[t] = cols[t]
        lab[rows[t] - y0, cols[t] - x0] = ids[t]
    m = n
    start, end = 0, n
    for s in range(steps + 1):
        for t in range(start, end):
            r, c = R[t], C[t]
            g = lab[r - y0, c - x0]
            lim = edge_depth * max(1.0, abs(xyz[r, c, 2]))
            for dy, dx in ((-1, 0), (0, -1), (0, 1), (1, 0)):
                rr, cc = r + dy, c + dx
                if rr < y0 or rr >= y1 or cc < x0 or cc >= x1 or not full[rr - fy, cc - fx]:
                    continue
                d0 = xyz[rr, cc, 0] - xyz[r, c, 0]
                d1 = xyz[rr, cc, 1] - xyz[r, c, 1]
                d2 = xyz[rr, cc, 2] - xyz[r, c, 2]
                if not np.sqrt(d0 * d0 + d1 * d1 + d2 * d2) <= lim:
                    continue
                h = lab[rr - y0, cc - x0]
                if h < 0:
                    if s < steps and m < cap:
                        lab[rr - y0, cc - x0] = g
                        R[m] = rr
                        C[m] = cc
                        m += 1
                else:
                    a, b = _root(parent, g), _root(parent, h)
                    if a != b:
                        parent[max(a, b)] = min(a, b)
        start, end = end, m
    G = np.empty(m, np.int64)
    for t in range(m):
        G[t] = _root(parent, lab[R[t] - y0, C[t] - x0])
    return R[:m].copy(), C[:m].copy(), G


@njit(cache=True, nogil=True, error_model="numpy")
def grow_box(rows, cols, H, W, steps):
    """``(y0, y1, x0, x1)``: the box ``[y0, y1) x [x0, x1)`` of the pixels ``(rows, cols)``
    grown by ``steps`` on every side, clipped to the ``(H, W)`` image (empty: no pixel)."""
    if rows.shape[0] == 0:
        return 0, 0, 0, 0
    y0, y1, x0, x1 = H, -1, W, -1
    for t in range(rows.shape[0]):
        y0 = min(y0, rows[t])
        y1 = max(y1, rows[t])
        x0 = min(x0, cols[t])
        x1 = max(x1, cols[t])
    return max(0, y0 - steps), min(H, y1 + 1 + steps), max(0, x0 - steps), min(W, x1 + 1 + steps)


@njit(cache=True, nogil=True, error_model="numpy")
def list_mask(rows, cols, lab, drop, y0, y1, x0, x1):
    """The pixels ``(rows, cols)`` less those whose label ``a`` has ``drop[a]`` (``0 <= a <
    len(drop)``; :func:`open_pixels` with radius 0) as a mask of the box ``[y0, y1) x [x0,
    x1)`` only (pixel ``(i, j)``: the image's ``(y0 + i, x0 + j)``), and how many it holds."""
    K = drop.shape[0]
    out = np.zeros((max(0, y1 - y0), max(0, x1 - x0)), np.bool_)
    n = 0
    for i in range(len(rows)):
        y, x = rows[i], cols[i]
        if y < y0 or y >= y1 or x < x0 or x >= x1:
            continue
        a = lab[y, x]
        if 0 <= a < K and drop[a]:
            continue
        out[y - y0, x - x0] = True
        n += 1
    return out, n


@njit(cache=True, nogil=True, error_model="numpy")
def nest_links(rows, cols, ids, near, part, xyz, H, W, g, nest_depth, lab, credit):
    """Groups of the components of a pixel list linked across small gaps
    (:func:`planerel.features.curved._nested_groups`).

    Two pixels of different ``near`` components link when they lie within ``g`` grid pixels
    (any direction) and within ``nest_depth * max(1, |z|)`` in 3-D (``z`` the earlier pixel's
    depth), and at least one of the two components is a ``part``.  A pixel of a ``part`` also
    links its component to a plane ``x`` with ``credit[x]`` whose pixel (in ``lab``) lies so
    near it: node ``K + x``.

    Parameters
    ----------
    rows, cols, ids : ndarray, shape (N,), int64
        The pixels (row-major) and their component ids (``0 .. K-1``).
    near, part : ndarray, shape (K,), bool
    xyz : ndarray, shape (H, W, 3), float64
    H, W, g : int
    nest_depth : float
    lab : ndarray, shape (H, W), int
        Plane labels (-1: none).
    credit : ndarray, shape (L,), bool
        Planes a part may link to (labels ``0 .. L-1``; none when L is 0).

    Returns
    -------
    ndarray, shape (K + L,), int64
        Each node's group: the smallest node id of its linked group.
    """
    k = near.shape[0]
    nl = credit.shape[0]
    parent = np.arange(k + nl)
    n = rows.shape[0]
    # a component map over the near pixels' bounding box only (-1: none)
    r0, r1, c0, c1 = H, -1, W, -1
    for t in range(n):
        if near[ids[t]]:
            r0 = min(r0, rows[t])
            r1 = max(r1, rows[t])
            c0 = min(c0, cols[t])
            c1 = max(c1, cols[t])
    if r1 < 0:
        return parent
    img = np.full((r1 - r0 + 1, c1 - c0 + 1), -1, np.int32)
    for t in range(n):
        if near[ids[t]]:
            img[rows[t] - r0, cols[t] - c0] = ids[t]
    # a link needs a part on one side: the windows of the parts' pixels alone are looked at,
    # each pair's limit from its earlier pixel (row-major); a pair of two parts is looked at
    # from both sides, with the same limit (each group's root is its smallest node whatever
    # the order of the unions)
    for t in range(n):
        a = ids[t]
        if not (part[a] and near[a]):
            continue
        r, c = rows[t], cols[t]
        za = abs(xyz[r, c, 2])
        for r2 in range(max(r0, r - g), min(r1, r + g) + 1):
            for c2 in range(max(c0, c - g), min(c1, c + g) + 1):
                b = img[r2 - r0, c2 - c0]
                if b < 0 or b == a:
                    continue
                if r2 < r or (r2 == r and c2 < c):
                    lim = nest_depth * max(1.0, abs(xyz[r2, c2, 2]))
                else:
                    lim = nest_depth * max(1.0, za)
                d0 = xyz[r2, c2, 0] - xyz[r, c, 0]
                d1 = xyz[r2, c2, 1] - xyz[r, c, 1]
                d2 = xyz[r2, c2, 2] - xyz[r, c, 2]
                if d0 * d0 + d1 * d1 + d2 * d2 <= lim * lim:
                    x, y = _root(parent, a), _root(parent, b)
                    if x != y:
                        parent[max(x, y)] = min(x, y)
        if nl == 0:
            continue
        lim = nest_depth * max(1.0, za)
        lim2 = lim * lim
        for r2 in range(max(0, r - g), min(H, r + g + 1)):
            for c2 in range(max(0, c - g), min(W, c + g + 1)):
                x = lab[r2, c2]
                if x < 0 or x >= nl or not credit[x]:
                    continue
                d0 = xyz[r2, c2, 0] - xyz[r, c, 0]
                d1 = xyz[r2, c2, 1] - xyz[r, c, 1]
                d2 = xyz[r2, c2, 2] - xyz[r, c, 2]
                if d0 * d0 + d1 * d1 + d2 * d2 <= lim2:
                    u, v = _root(parent, a), _root(parent, k + x)
                    if u != v:
                        parent[max(u, v)] = min(u, v)
    out = np.empty(k + nl, np.int64)
    for i in range(k + nl):
        out[i] = _root(parent, i)
    return out



@njit(cache=True, nogil=True, error_model="numpy")
def join_owners(lab, lut, xyz):
    """:func:`planerel.features.curved.join_parts`' owner map in one pass over the image:
    ``(H, W)`` int32, a labelled pixel's proposal (``lut[label]``, -2 for none), -1 an
    unassigned pixel with a finite depth (-2 without), and those pixels' rows and columns
    (row-major)."""
    H, W = lab.shape
    nl = lut.shape[0]
    own = np.empty((H, W), np.int32)
    rows = np.empty(H * W, np.int64)
    cols = np.empty(H * W, np.int64)
    n = 0
    for y in range(H):
        for x in range(W):
            a = lab[y, x]
            if a >= 0:
                b = lut[a] if a < nl else -1
                own[y, x] = b if b >= 0 else -2
            elif np.isfinite(xyz[y, x, 2]):
                own[y, x] = -1
                rows[n], cols[n] = y, x
                n += 1
            else:
                own[y, x] = -2
    return own, rows[:n].copy(), cols[:n].copy()


@njit(cache=True, nogil=True, error_model="numpy")
def mark_held(mask, own, k):
    """``own[y, x] = k`` where ``own`` is -1 (an unassigned pixel no earlier mask holds) and
    ``mask`` holds the pixel: the first proposal's mask wins; rows without a pixel of
    ``mask`` are skipped at a byte a pixel."""
    H, W = mask.shape
    for y in range(H):
        if not _row_any(mask, y, W):
            continue
        for x in range(W):
            if mask[y, x] and own[y, x] == -1:
                own[y, x] = k


@njit(cache=True, nogil=True, error_model="numpy")
def join_part_targets(rows, cols, own, xyz, edge_depth, npts, min_touch):
    """The proposal each unassigned pixel ``(rows, cols)`` (row-major) joins, for
    :func:`planerel.features.curved.join_parts`, in one pass over the parts' pixels.

    ``own`` (:func:`join_owners`, then :func:`mark_held`): the pixels still -1 form parts
    (:func:`list_components`); each part pixel's grid neighbours 1 or 2 steps right, down,
    left or up are read once: one ``own`` holds for a proposal (``>= 0``) touches it where
    the points lie within ``edge_depth * max(1, |z|)`` (``z`` the part pixel's; the
    distance summed as ``np.linalg.norm`` sums it). A part touching one proposal only, at
    least ``min_touch`` times, and no larger than that proposal's ``npts`` (grown, in part
    order, by the parts joined before) joins it.

    Returns
    -------
    (ndarray (N,) int64, ndarray (M,) int64)
        Per pixel the proposal it joins (-1: none; held pixels are -1), the proposals'
        grown point counts.
    """
    H, W = own.shape
    n = rows.shape[0]
    m = npts.shape[0]
    dest = np.full(n, -1, np.int64)
    out_n = npts.copy()
    kept = 0
    for i in range(n):
        if own[rows[i], cols[i]] == -1:
            kept += 1
    if kept == 0:
        return dest, out_n
    pr = np.empty(kept, np.int64)
    pc = np.empty(kept, np.int64)
    src = np.empty(kept, np.int64)
    j = 0
    for i in range(n):
        if own[rows[i], cols[i]] == -1:
            pr[j], pc[j], src[j] = rows[i], cols[i], i
            j += 1
    pid, np_ = list_components(pr, pc, xyz, edge_depth, H)
    counts = np.zeros((np_, m), np.int64)
    size = np.zeros(np_, np.int64)
    for t in range(kept):
        y, x = pr[t], pc[t]
        p = pid[t]
        size[p] += 1
        az = abs(xyz[y, x, 2])
        lim = edge_depth * (az if az > 1.0 else 1.0)
        for d in range(8):
            if d == 0:
                yy, xx = y, x + 1
            elif d == 1:
                yy, xx = y, x + 2
            elif d == 2:
                yy, xx = y + 1, x
            elif d == 3:
                yy, xx = y + 2, x
            elif d == 4:
                yy, xx = y, x - 1
            elif d == 5:
                yy, xx = y, x - 2
            elif d == 6:
                yy, xx = y - 1, x
            else:
                yy, xx = y - 2, x
            if yy < 0 or yy >= H or xx < 0 or xx >= W:
                continue
            b = own[yy, xx]
            if b < 0:
                continue
            d0 = xyz[y, x, 0] - xyz[yy, xx, 0]
            d1 = xyz[y, x, 1] - xyz[yy, xx, 1]
            d2 = xyz[y, x, 2] - xyz[yy, xx, 2]
            if np.sqrt((d0 * d0 + d1 * d1) + d2 * d2) <= lim:
                counts[p, b] += 1
    target = np.full(np_, -1, np.int64)
    for p in range(np_):
        k = -1
        many = False
        for b in range(m):
            if counts[p, b] > 0:
                if k >= 0:
                    many = True
                    break
                k = b
        if k < 0 or many or counts[p, k] < min_touch or size[p] > out_n[k]:
            continue
        target[p] = k
        out_n[k] += size[p]
    for t in range(kept):
        dest[src[t]] = target[pid[t]]
    return dest, out_n


@njit(cache=True, nogil=True, error_model="numpy")
def group_points(lab, xyz, r0, r1, c0, c1, lut, max_points):
    """The finite points of the pixels of box ``[r0, r1) x [c0, c1)`` whose label ``v`` has
    ``lut[v]`` (labels outside ``0 <= v < len(lut)``: not), every ``k``-th of them in row-major
    order with ``k = max(1, n // max_points)`` for ``n`` such pixels, then those with three
    finite coordinates: ``pts = xyz[box][np.isin(lab[box], comp)]; pts = pts[::k];
    pts[np.isfinite(pts).all(axis=1)]`` (:func:`planerel.features.curved._group_points`
    before) without the box's mask and its gathered copy (the same values in the same
    order).

    Returns
    -------
    ndarray (M, 3) float64
    """
    m = lut.shape[0]
    n = 0
    for y in range(r0, r1):
        for x in range(c0, c1):
            v = lab[y, x]
            if v >= 0 and v < m and lut[v]:
                n += 1
    k = max(1, n // max_points)
    out = np.empty((n // k + 1, 3))
    t = 0
    j = 0
    for y in range(r0, r1):
        for x in range(c0, c1):
            v = lab[y, x]
            if v >= 0 and v < m and lut[v]:
                if t % k == 0:
                    p0 = xyz[y, x, 0]
                    p1 = xyz[y, x, 1]
                    p2 = xyz[y, x, 2]
                    if math.isfinite(p0) and math.isfinite(p1) and math.isfinite(p2):
                        out[j, 0] = p0
                        out[j, 1] = p1
                        out[j, 2] = p2
                        j += 1
                t += 1
    return out[:j]


@njit(cache=True, nogil=True, error_model="numpy")
def center_rows(pts, out):
    """``out[:] = pts - pts.mean(0)`` for C-contiguous ``(N, 3)`` float64 ``pts`` (``N >= 1``):
    numpy's mean over the rows of such an array adds them one after the other (its inner
    loop runs along the three columns) and divides by ``N``; the same sums and the same
    quotient here, then the same differences (:func:`planerel.features.curved.surface_bend`;
    ``tests/test_curved.py`` compares bit for bit)."""
    n = pts.shape[0]
    s0 = 0.0
    s1 = 0.0
    s2 = 0.0
    for i in range(n):
        s0 += pts[i, 0]
        s1 += pts[i, 1]
        s2 += pts[i, 2]
    m0 = s0 / n
    m1 = s1 / n
    m2 = s2 / n
    for i in range(n):
        out[i, 0] = pts[i, 0] - m0
        out[i, 1] = pts[i, 1] - m1
        out[i, 2] = pts[i, 2] - m2


@njit(cache=True, nogil=True, error_model="numpy")
def quadric_terms(loc, out):
    """``out[:] = np.stack([u * u, u * v, v * v, u, v, 1], 1)`` with ``v, u = loc[:, 1],
    loc[:, 2]`` (``out`` ``(N, 6)``): the same products."""
    for i in range(loc.shape[0]):
        v = loc[i, 1]
        u = loc[i, 2]
        out[i, 0] = u * u
        out[i, 1] = u * v
        out[i, 2] = v * v
        out[i, 3] = u
        out[i, 4] = v
        out[i, 5] = 1.0
