"""numba kernel of the region-growing neighbour graph (compiled once, cached on disk).

The graph joins 8-adjacent grid pixels whose points are closer than delta (the paper's
distance threshold); ``"auto"`` delta comes from the mean nearest-neighbour distance per
depth band (docs/segmentation.md).  Two parts: :func:`graph_table` (the delta per depth band,
from a sample of rows) and :func:`graph_step` (one row of the bit mask from two row buffers,
in per-row loops simple enough for LLVM to vectorise); :func:`grid_graph` runs both, region
growing runs the steps inside the normals' pass, while each row of the cloud is in the cache.
Nothing image-sized is written but the (H, W) bit mask.  Import this module only from inside
functions (numba is a heavy import).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["grid_graph"]


@njit(cache=True, nogil=True, error_model="numpy")
def _deinterleave(a, x, y, z):  # pragma: no cover - compiled
    """``x``, ``y``, ``z`` (n,) from the flat (n, 3) points ``a`` (3 n,): constant strides,
    which LLVM vectorises (a (n, 3) view's stride is a run-time value)."""
    for u in range(x.shape[0]):
        x[u] = a[3 * u]
        y[u] = a[3 * u + 1]
        z[u] = a[3 * u + 2]


@njit(cache=True, nogil=True, error_model="numpy")
def _load_row(xyz, v, r):  # pragma: no cover - compiled
    """Row ``v`` of ``xyz`` into ``r`` (3, W + 2): x, y, z at columns 1..W; all NaN when ``v``
    lies outside the image.  Columns 0 and W + 1 are padding and must hold NaN."""
    H = xyz.shape[0]
    W = xyz.shape[1]
    if 0 <= v < H:
        _deinterleave(xyz[v].reshape(-1), r[0, 1:W + 1], r[1, 1:W + 1], r[2, 1:W + 1])
    else:
        for u in range(W + 2):
            r[0, u] = np.nan
            r[1, u] = np.nan
            r[2, u] = np.nan


@njit(cache=True, nogil=True, error_model="numpy")
def _d2_row(a, b, shift, out):  # pragma: no cover - compiled
    """``out[u]``: float32 squared distance between column ``u + 1`` of row buffer ``a`` and
    column ``u + 1 + shift`` of row buffer ``b`` (inf where either point is NaN)."""
    n = out.shape[0]
    ax = a[0, 1:n + 1]
    ay = a[1, 1:n + 1]
    az = a[2, 1:n + 1]
    bx = b[0, 1 + shift:n + 1 + shift]
    by = b[1, 1 + shift:n + 1 + shift]
    bz = b[2, 1 + shift:n + 1 + shift]
    inf = np.float32(np.inf)
    for i in range(n):
        dx = bx[i] - ax[i]
        dy = by[i] - ay[i]
        dz = bz[i] - az[i]
        d = np.float32(dx * dx + dy * dy + dz * dz)
        out[i] = d if d < inf else inf


@njit(cache=True, nogil=True, error_model="numpy")
def _nearest_row(d, z, zmin, width, nbands, near, band):  # pragma: no cover - compiled
    """``near[u]``: distance from column ``u + 1`` of a row to its nearest of the 8 adjacent
    points (-1 where the point is NaN or has no valid neighbour), ``band[u]`` its depth band;
    ``d`` (7, W + 2) the padded float32 squared lengths of the table pass, ``z`` the padded
    row's depths.  Branch-free, so that LLVM vectorises it."""
    inf = np.float32(np.inf)
    top = nbands - 1
    for u in range(near.shape[0]):
        z0 = z[u + 1]
        # right, left, below-left, below, below-right, above-right, above, above-left
        m = min(min(min(d[0, u + 1], d[0, u]), min(d[4, u + 1], d[5, u + 1])),
                min(min(d[6, u + 1], d[1, u + 2]), min(d[2, u + 1], d[3, u])))
        ok = not np.isnan(z0) and m < inf
        near[u] = np.sqrt(np.float64(m)) if ok else -1.0
        b = (z0 - zmin) / width if ok else 0.0
        b = b if b > 0.0 else 0.0
        band[u] = np.int32(b if b < top else top)


def grid_graph(xyz, delta_factor, delta_fixed, by_depth, nbands, row_step, mask):
    """Fill ``mask`` (H, W) uint8 with the grid neighbours within delta (bit k: direction k of
    ``planerel.segment._kernels.GRID_DV`` / ``GRID_DU``): :func:`graph_table`, then
    :func:`graph_step` for every row.  Returns what :func:`graph_table` returns but ``tab2``.

    (Region growing runs the steps inside the normals' pass instead, while each row of the
    cloud is in the cache: :func:`planerel.segment._normal_kernels.normals_stream`.)"""
    table, tab2, zmin, width, mean = graph_table(xyz, delta_factor, delta_fixed, by_depth,
                                                 nbands, row_step)
    gs = graph_scratch(xyz.shape[1])
    _all_steps(xyz, tab2, zmin, width, *gs, mask)
    return table, zmin, width, mean


def graph_scratch(w: int) -> tuple:
    """Scratch of :func:`graph_step` for rows ``w`` pixels wide: ``rows`` (2, 3, W + 2) float64,
    ``thr`` (2, W + 2) float32, ``band`` (W,) int32, ``edges`` (8, W) uint8."""
    rows = np.full((2, 3, w + 2), np.nan)  # the padding columns stay NaN
    return rows, np.zeros((2, w + 2), np.float32), np.empty(w, np.int32), np.zeros((8, w), np.uint8)


@njit(cache=True, nogil=True, error_model="numpy")
def _all_steps(xyz, tab2, zmin, width, rows, thr, band, edges, mask):  # pragma: no cover
    for t in range(xyz.shape[0] + 1):
        graph_step(xyz, t, tab2, zmin, width, rows, thr, band, edges, mask)


@njit(cache=True, nogil=True, error_model="numpy")
def graph_table(xyz, delta_factor, delta_fixed, by_depth, nbands,
                row_step):  # pragma: no cover - compiled
    """The delta table of the grid graph of ``xyz`` (H, W, 3) float64, NaN = invalid.

    delta: ``delta_fixed`` when > 0; else ``delta_factor`` x the mean over points of the
    distance to the nearest of the 8 adjacent neighbours, estimated on every ``row_step``-th
    row; with ``by_depth`` that mean is taken per depth band (``nbands`` equal bands between
    the smallest and largest depth of those rows) and an edge uses the band of its farther
    point.  An edge exists when its float32 squared length is below the float32 squared
    delta.

    Returns (delta table (nbands,), its float32 squares ``tab2``, band zmin, band width,
    global mean nearest-neighbour distance).
    """
    H = xyz.shape[0]
    W = xyz.shape[1]
    zmin = np.inf
    zmax = -np.inf
    for v in range(0, H, row_step):
        for u in range(W):
            z = xyz[v, u, 2]
            if not np.isnan(z):
                if z < zmin:
                    zmin = z
                if z > zmax:
                    zmax = z
    if not zmin < np.inf:
        for v in range(H):
            for u in range(W):
                z = xyz[v, u, 2]
                if not np.isnan(z):
                    zmin = min(zmin, z)
                    zmax = max(zmax, z)
    width = (zmax - zmin) / nbands
    if not width > 0:
        width = 1.0

    # --- mean nearest-neighbour distance per band, on every row_step-th row -------------
    r0 = np.full((3, W + 2), np.nan)  # padding columns stay NaN
    r1 = np.full((3, W + 2), np.nan)
    r2 = np.full((3, W + 2), np.nan)
    inf = np.float32(np.inf)
    # padded squared lengths: 0 right edges of row v; 1-3 the down edges of row v - 1 (shift
    # -1, 0, +1); 4-6 the down edges of row v
    d = np.full((7, W + 2), inf, dtype=np.float32)
    bsum = np.zeros(nbands)
    bcnt = np.zeros(nbands)
    near = np.empty(W)
    band = np.empty(W, dtype=np.int32)
    tot = 0.0
    totn = 0.0
    prev = -2
    for v in range(0, H, row_step):
        if v == prev + 1:  # consecutive rows: reuse the rows and row v - 1's down edges
            r0, r1, r2 = r1, r2, r0
            _load_row(xyz, v + 1, r2)
            for k in range(3):
                for u in range(W + 2):
                    d[1 + k, u] = d[4 + k, u]
        else:
            _load_row(xyz, v - 1, r0)
            _load_row(xyz, v, r1)
            _load_row(xyz, v + 1, r2)
            for k in range(3):
                _d2_row(r0, r1, k - 1, d[1 + k, 1:W + 1])
        prev = v
        _d2_row(r1, r1, 1, d[0, 1:W + 1])
        for k in range(3):
            _d2_row(r1, r2, k - 1, d[4 + k, 1:W + 1])
        _nearest_row(d, r1[2], zmin, width, nbands, near, band)
        for u in range(W):  # in column order (the sums' rounding stays the same)
            dd = near[u]
            if not dd >= 0.0:
                continue
            b = band[u]
            bsum[b] += dd
            bcnt[b] += 1.0
            tot += dd
            totn += 1.0
    mean = tot / totn if totn > 0 else 0.0

    # --- delta per band ------------------------------------------------------------------
    table = np.empty(nbands)
    if delta_fixed > 0:
        for b in range(nbands):
            table[b] = delta_fixed
    elif not by_depth:
        for b in range(nbands):
            table[b] = delta_factor * mean
    else:
        # band means; bands with few samples take the nearest well-sampled band's value
        good = np.zeros(nbands, dtype=np.bool_)
        for b in range(nbands):
            good[b] = bcnt[b] >= 20
        anygood = False
        for b in range(nbands):
            anygood = anygood or good[b]
        for b in range(nbands):
            if good[b]:
                table[b] = delta_factor * bsum[b] / bcnt[b]
            elif not anygood:
                table[b] = delta_factor * mean
            else:
                best = -1
                for k in range(nbands):
                    if good[k] and (best < 0 or abs(k - b) < abs(best - b)):
                        best = k
                table[b] = delta_factor * bsum[best] / bcnt[best]
        # monotone in depth, so that the band of an edge's farther point is its larger delta
        for b in range(1, nbands):
            if table[b] < table[b - 1]:
                table[b] = table[b - 1]
    tab2 = np.empty(nbands, dtype=np.float32)
    for b in range(nbands):
        tab2[b] = table[b] * table[b]

    return table, tab2, zmin, width, mean


@njit(cache=True, nogil=True, error_model="numpy")
def graph_step(xyz, t, tab2, zmin, width, rows, thr, band, edges,
               mask):  # pragma: no cover - compiled
    """Step ``t`` (0..H) of the graph: load row ``t`` of ``xyz`` (all NaN for t = H) into the
    row buffers and, for t >= 1, fill ``mask[t - 1]`` from rows t - 1 and t.  The 4 forward
    edges of a row are computed once; its 4 backward bits are the previous row's forward
    edges.  ``tab2``, ``zmin``, ``width`` from :func:`graph_table`; scratch from
    :func:`graph_scratch` (rows, thresholds and edges alternate by the parity of the row; the
    table is monotone, so ``tab2`` of the farther point's band is the larger of the two ends'
    squared deltas)."""
    W = xyz.shape[1]
    top = tab2.shape[0] - 1
    pb = t & 1
    _load_row(xyz, t, rows[pb])
    for u in range(W):  # band of each point (NaN: band 0, its edges fail anyway)
        b = (rows[pb, 2, u + 1] - zmin) / width
        b = b if b > 0.0 else 0.0
        b = b if b < top else top
        band[u] = np.int32(b)
    for u in range(W):
        thr[pb, u + 1] = tab2[band[u]]
    if t == 0:
        return
    v = t - 1
    pa = v & 1
    c0 = 0 if v % 2 == 0 else 4  # this row's forward edges: edges[c0:c0 + 4]
    p0 = 4 - c0  # the previous row's (zero before row 0)
    if v == 0:
        edges[:, :] = 0
    # the 4 forward edges (right, below-left, below, below-right) in one loop without calls
    # (array arguments cost a reference-count round trip per call)
    for u in range(W):
        ax = rows[pa, 0, u + 1]
        ay = rows[pa, 1, u + 1]
        az = rows[pa, 2, u + 1]
        at = thr[pa, u + 1]
        dx = rows[pa, 0, u + 2] - ax
        dy = rows[pa, 1, u + 2] - ay
        dz = rows[pa, 2, u + 2] - az
        edges[c0, u] = np.float32(dx * dx + dy * dy + dz * dz) < max(at, thr[pa, u + 2])
        dx = rows[pb, 0, u] - ax
        dy = rows[pb, 1, u] - ay
        dz = rows[pb, 2, u] - az
        edges[c0 + 1, u] = np.float32(dx * dx + dy * dy + dz * dz) < max(at, thr[pb, u])
        dx = rows[pb, 0, u + 1] - ax
        dy = rows[pb, 1, u + 1] - ay
        dz = rows[pb, 2, u + 1] - az
        edges[c0 + 2, u] = np.float32(dx * dx + dy * dy + dz * dz) < max(at, thr[pb, u + 1])
        dx = rows[pb, 0, u + 2] - ax
        dy = rows[pb, 1, u + 2] - ay
        dz = rows[pb, 2, u + 2] - az
        edges[c0 + 3, u] = np.float32(dx * dx + dy * dy + dz * dz) < max(at, thr[pb, u + 2])
    mr = mask[v]
    if W == 1:
        mr[0] = (edges[c0 + 2, 0] << 2) | (edges[p0 + 2, 0] << 6)
    else:
        mr[0] = (edges[c0, 0] | (edges[c0 + 2, 0] << 2) | (edges[c0 + 3, 0] << 3)
                 | (edges[p0 + 1, 1] << 5) | (edges[p0 + 2, 0] << 6))
        for u in range(1, W - 1):
            mr[u] = (edges[c0, u] | (edges[c0 + 1, u] << 1) | (edges[c0 + 2, u] << 2)
                     | (edges[c0 + 3, u] << 3) | (edges[c0, u - 1] << 4)
                     | (edges[p0 + 1, u + 1] << 5) | (edges[p0 + 2, u] << 6)
                     | (edges[p0 + 3, u - 1] << 7))
        u = W - 1
        mr[u] = ((edges[c0 + 1, u] << 1) | (edges[c0 + 2, u] << 2) | (edges[c0, u - 1] << 4)
                 | (edges[p0 + 2, u] << 6) | (edges[p0 + 3, u - 1] << 7))
