"""numba kernel of the organized-cloud normals (see :mod:`planerel.segment.normals`), compiled once and
cached on disk; import only from inside functions.

The kernel streams the image: three stages run row by row with a lag, through ring buffers of
a few dozen rows, so its scratch is about 1 MB at 640x480 instead of 17 MB of image-sized
arrays (which pushed the cloud and the normals out of the cache before the neighbour graph
and the growing read them):

A. row ``t``: row runs (NaN holes and depth jumps cut them), column-run starts, window sizes,
   horizontal box sums clipped to the run, and the column prefix of those sums; the moments
   of the valid points on every 4th row and column (for the degeneracy check);
B. row ``b = t - L`` (``L = max(smax, rmax)``): the column-run end, capped at ``b + L`` (all a
   window can reach), then the smoothed points (vertical box over the horizontal sums, clipped
   to the column run: :func:`_smooth_row`);
C. row ``c = b - rmax``: central differences of the smoothed points clipped to the runs
   (:func:`_diff_row`, scalar: rows and columns differ per pixel), then the cross product,
   normalised and turned towards the sensor, in a loop LLVM vectorises (:func:`_cross_row`).

The hot loops index with unsigned integers where the index is computed (numba adds
negative-index handling to every load with a signed one), and the kernel prefetches the cloud
two rows ahead (:func:`planerel.segment._intrinsics.prefetch`).

Every value is computed by the same operations in the same order as the earlier full-image
kernel, so the normals are bit-identical to it (tests/test_normals.py checks them against a
plain statement of the definition).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from planerel.segment._graph_kernels import graph_scratch, graph_step
from planerel.segment._intrinsics import prefetch

__all__ = ["normals_stream", "ring_sizes", "with_graph", "no_graph"]


def with_graph(tab2, zmin: float, width: float, mask, scratch=None) -> tuple:
    """The ``graph`` argument of :func:`normals_stream` that fills ``mask`` (H, W) uint8 with
    the neighbour graph of the table ``tab2``, ``zmin``, ``width`` (from
    :func:`planerel.segment._graph_kernels.graph_table`); ``scratch`` from
    :func:`planerel.segment._graph_kernels.graph_scratch` (made when not given)."""
    if scratch is None:
        scratch = graph_scratch(mask.shape[1])
    return (tab2, float(zmin), float(width), *scratch, mask)


_NO_GRAPH = None


def no_graph() -> tuple:
    """The ``graph`` argument of :func:`normals_stream` for normals alone."""
    global _NO_GRAPH
    if _NO_GRAPH is None:  # never written: the kernel skips the graph when mask has no rows
        _NO_GRAPH = with_graph(np.zeros(1, np.float32), 0.0, 1.0, np.zeros((0, 1), np.uint8))
    return _NO_GRAPH


def ring_sizes(smax: int, rmax: int) -> tuple[int, int, int]:
    """Rows of the (int, prefix, smoothed) ring buffers for window limits ``smax``, ``rmax``:
    powers of two larger than the rows each stage keeps alive."""
    lag = max(smax, rmax)

    def pow2_above(n):
        k = 1
        while k <= n:
            k *= 2
        return k

    return pow2_above(lag + rmax + 1), pow2_above(lag + smax + 2), pow2_above(2 * rmax + 1)


@njit(cache=True, nogil=True, inline="always")
def _scale(z, ratio, lo, hi):  # pragma: no cover - compiled
    """round(z * ratio) (ratio = base / zref, or 0 for a fixed size) clipped to [lo, hi]."""
    k = int(z * ratio + 0.5)
    if k < lo:
        return lo
    if k > hi:
        return hi
    return k


@njit(cache=True, nogil=True, error_model="numpy")
def _cross_row(dif, p, o):  # pragma: no cover - compiled
    """Normals of one row: ``o`` (3 W,) float32, the row's normals flattened, from ``dif``
    (7, W) float32 (the row difference x, y, z, the column difference x, y, z, and 1 where the
    pixel has a normal) and ``p`` (3 W,) the row's points flattened: the cross product
    normalised and turned towards the sensor, NaN where there is none.  Flat arrays with
    constant strides: with (W, 3) views the stride is a run-time value and LLVM leaves the
    loop scalar (one square root and three divisions per pixel)."""
    nan = np.float32(np.nan)
    for u in range(dif.shape[1]):
        ax = dif[0, u]
        ay = dif[1, u]
        az = dif[2, u]
        bx = dif[3, u]
        by = dif[4, u]
        bz = dif[5, u]
        nx = ay * bz - az * by
        ny = az * bx - ax * bz
        nz = ax * by - ay * bx
        nn = np.sqrt(nx * nx + ny * ny + nz * nz)
        ok = (dif[6, u] != 0.0) & (nn != 0.0)
        # selects, not branches (the loop must stay branch-free to vectorise)
        nn = -nn if nx * p[3 * u] + ny * p[3 * u + 1] + nz * p[3 * u + 2] > 0.0 else nn
        o[3 * u] = nx / nn if ok else nan
        o[3 * u + 1] = ny / nn if ok else nan
        o[3 * u + 2] = nz / nn if ok else nan


@njit(cache=True, nogil=True, error_model="numpy")
def _smooth_row(rcf, cs, ce, ks, b, MC, sbf):  # pragma: no cover - compiled
    """Stage B's smoothed points of row ``b`` into ``sbf`` (3 W,) float32 (its ring row,
    flattened): the vertical box over the column prefix ``rcf`` (the (RC, W, 4) ring,
    flattened) from row ``max(b - s, cs)`` to ``min(b + s, ce)``; ``cs``, ``ce``, ``ks`` the
    row's column-run start / capped end and window half-sizes (W,) int16; ``MC`` = RC - 1.

    A function of its own with flat arrays and unsigned indices: inside the streaming kernel
    (signed indices into (W, 4) row views) the same loop took ~4 % more of the kernel (more
    register spills, negative-index handling on each load)."""
    W = cs.shape[0]
    RW = 4 * W
    for u in range(W):
        if cs[u] < 0:  # invalid: zeros, so that stage C reads only written values for it
            sbf[3 * u] = 0.0
            sbf[3 * u + 1] = 0.0
            sbf[3 * u + 2] = 0.0
            continue
        s = np.int64(ks[u])
        lo = max(b - s, np.int64(cs[u]))
        hi = min(b + s, np.int64(ce[u]))
        ih = np.uint64(((hi + 1) & MC) * RW + 4 * u)
        il = np.uint64((lo & MC) * RW + 4 * u)
        inv = 1.0 / (rcf[ih + np.uint64(3)] - rcf[il + np.uint64(3)])
        sbf[3 * u] = (rcf[ih] - rcf[il]) * inv
        sbf[3 * u + 1] = (rcf[ih + np.uint64(1)] - rcf[il + np.uint64(1)]) * inv
        sbf[3 * u + 2] = (rcf[ih + np.uint64(2)] - rcf[il + np.uint64(2)]) * inv


@njit(cache=True, nogil=True, error_model="numpy")
def _diff_row(rsf, rs, re, cs, ce, kr, c, MS, dif):  # pragma: no cover - compiled
    """Stage C's differences of row ``c`` into ``dif`` (7, W) (see :func:`_cross_row`): along
    the row between columns ``u -+ r`` clipped to the row run ``rs``, ``re``; along the
    column between rows ``c -+ r`` clipped to the column run ``cs``, ``ce``; ``dif[6]`` 1
    where the pixel is valid and has a neighbour both ways (runs of one pixel have none).
    ``rsf`` the smoothed-point ring (RS, W, 3) flattened, ``MS`` = RS - 1; ``kr`` the
    difference radii.  Scalar (rows and columns differ per pixel); flat arrays and unsigned
    indices as in :func:`_smooth_row`."""
    W = rs.shape[0]
    RW = 3 * W
    row = (c & MS) * RW
    for u in range(W):
        # an invalid point's radius, column run and row-run end are stale ring values (never
        # written for it, or left by an earlier row): it reads only its own smoothed point
        # (zeros, written by stage B), so every load stays inside the ring and reads written
        # values; its result is masked by dif[6].  A valid point's ends lie in [0, W - 1]
        # and in rows stage B has written.
        ok = rs[u] >= 0
        r = np.int64(kr[u])
        ur = min(u + r, np.int64(re[u])) if ok else np.int64(u)
        ul = max(u - r, np.int64(rs[u])) if ok else np.int64(u)
        vd = min(c + r, np.int64(ce[u])) if ok else np.int64(c)
        vu = max(c - r, np.int64(cs[u])) if ok else np.int64(c)
        dif[6, u] = ok & (ur != ul) & (vd != vu)
        ir = np.uint64(row + 3 * ur)
        il = np.uint64(row + 3 * ul)
        idn = np.uint64((vd & MS) * RW + 3 * u)
        iu = np.uint64((vu & MS) * RW + 3 * u)
        one = np.uint64(1)
        two = np.uint64(2)
        dif[0, u] = rsf[ir] - rsf[il]
        dif[1, u] = rsf[ir + one] - rsf[il + one]
        dif[2, u] = rsf[ir + two] - rsf[il + two]
        dif[3, u] = rsf[idn] - rsf[iu]
        dif[4, u] = rsf[idn + one] - rsf[iu + one]
        dif[5, u] = rsf[idn + two] - rsf[iu + two]


@njit(cache=True, nogil=True, error_model="numpy")
def normals_stream(xyz, s0, r0, zref, smax, rmax, jump_per_z, out, ri, rc, rsm, mom,
                   graph):  # pragma: no cover - compiled
    """Depth-aware normals of an organized cloud ``xyz`` (H, W, 3) into ``out`` (H, W, 3)
    float32 (NaN where a point is invalid or has no connected neighbour along its row or its
    column).  Window half-size s and difference radius r grow with depth: round(s0 * z / zref)
    clipped to [s0, smax] (r likewise, >= 1; zref 0 = fixed size).  Ring-buffer scratch (sizes
    from :func:`ring_sizes`): ``ri`` (6, RR, W) int16 (row run start / end, column run start /
    capped end, window half-size, difference radius), ``rc`` (RC, W, 4) float64 (column
    prefix of the horizontal sums x, y, z, count), ``rsm`` (RS, W, 3) float32 (smoothed
    points).  Also fills ``mom`` (10,) with the moments (count, sums and second moments about
    the first one) of the valid points on every 4th row and column, a sample for the
    degeneracy check (accumulating every point cost ~10 % of the kernel).

    ``graph``: :func:`with_graph` to fill the region growing's neighbour graph in the same
    pass, each step right after stage A has read its row (the cloud is then read once; as a
    separate pass it came back from memory, ~0.5 ms more at 640x480); :func:`no_graph` not
    to."""
    H = xyz.shape[0]
    W = xyz.shape[1]
    xflat = xyz.reshape(-1)
    rcf = rc.reshape(-1)  # flat views for the row functions of stages B and C
    rsf = rsm.reshape(-1)
    tab2, gzmin, gwidth, grows, gthr, gband, gedges, mask = graph
    do_graph = mask.shape[0] == H
    # the window grows with depth beyond zref but never shrinks below its nominal size
    smin = int(s0 + 0.5)
    rmin = max(1, int(r0 + 0.5))
    # z * (s0 / zref) instead of s0 * z / zref: one multiplication per pixel, no division
    sratio = s0 / zref if zref > 0.0 else 0.0
    rratio = r0 / zref if zref > 0.0 else 0.0
    same_scale = sratio == rratio and smin == rmin and smax == rmax
    L = max(smax, rmax)
    MI = ri.shape[1] - 1
    MC = rc.shape[0] - 1
    MS = rsm.shape[0] - 1
    rs_ = ri[0]
    re_ = ri[1]
    cs_ = ri[2]
    ce_ = ri[3]
    ks_ = ri[4]
    kr_ = ri[5]
    m0 = m1 = m2 = m3 = m4 = m5 = m6 = m7 = m8 = m9 = 0.0
    refx = np.nan
    refy = 0.0
    refz = 0.0
    for u in range(W):
        for k in range(4):
            rc[0, u, k] = 0.0
    px = np.empty(W + 1)
    py = np.empty(W + 1)
    pz = np.empty(W + 1)
    alive = np.empty(W, dtype=np.bool_)
    dif = np.empty((7, W), dtype=np.float32)
    for t in range(H + L + rmax):
        # ---- A: row t ----------------------------------------------------------------------
        if t < H:
            v = t
            iv = v & MI
            ip = (v - 1) & MI
            rs = rs_[iv]
            re = re_[iv]
            cs = cs_[iv]
            ks = ks_[iv]
            kr = kr_[iv]
            csp = cs_[ip]
            c0 = rc[v & MC]
            c1 = rc[(v + 1) & MC]
            start = 0
            zprev = np.nan
            sample_row = (v & 3) == 0
            px[0] = 0.0
            py[0] = 0.0
            pz[0] = 0.0
            # one pass: runs, column-run starts, window sizes, moments, prefix sums; a run's
            # ends, horizontal box sums and column prefix as soon as it ends
            for u in range(W + 1):
                # the point two rows below towards the cache (the hardware prefetcher alone
                # left this loop waiting for the cloud: ~5 % of the kernel)
                prefetch(xflat, ((v + 2) * W + u) * 3)
                z = xyz[v, u, 2] if u < W else np.nan
                invalid = np.isnan(z)
                if invalid or (u > start and abs(z - zprev) > jump_per_z * min(z, zprev)):
                    if u > start:  # the run [start, u - 1] ends here
                        end = u - 1
                        # unsigned indices: no negative-index handling per load
                        for w in range(start, u):
                            re[w] = end
                            s = ks[w]
                            lo = np.uint64(max(w - s, start))
                            hi = np.uint64(min(w + s, end) + 1)
                            uw = np.uint64(w)
                            c1[uw, 0] = c0[uw, 0] + px[hi] - px[lo]
                            c1[uw, 1] = c0[uw, 1] + py[hi] - py[lo]
                            c1[uw, 2] = c0[uw, 2] + pz[hi] - pz[lo]
                            c1[uw, 3] = c0[uw, 3] + np.float64(hi - lo)
                    start = u + 1 if invalid else u
                if u == W:
                    break
                if invalid:
                    rs[u] = -1
                    re[u] = -1
                    cs[u] = -1
                    px[u + 1] = px[u]
                    py[u + 1] = py[u]
                    pz[u + 1] = pz[u]
                    zprev = np.nan
                    c1[u, 0] = c0[u, 0]
                    c1[u, 1] = c0[u, 1]
                    c1[u, 2] = c0[u, 2]
                    c1[u, 3] = c0[u, 3]
                    continue
                rs[u] = start
                zprev = z
                if v > 0 and csp[u] >= 0:
                    zp = xyz[v - 1, u, 2]
                    if abs(z - zp) > jump_per_z * min(z, zp):
                        cs[u] = v
                    else:
                        cs[u] = csp[u]
                else:
                    cs[u] = v
                ks[u] = _scale(z, sratio, smin, smax)
                kr[u] = ks[u] if same_scale else _scale(z, rratio, rmin, rmax)
                x = xyz[v, u, 0]
                y = xyz[v, u, 1]
                if sample_row and (u & 3) == 0:
                    if np.isnan(refx):
                        refx = x
                        refy = y
                        refz = z
                    mx = x - refx
                    my = y - refy
                    mz = z - refz
                    m0 += 1.0
                    m1 += mx
                    m2 += my
                    m3 += mz
                    m4 += mx * mx
                    m5 += mx * my
                    m6 += mx * mz
                    m7 += my * my
                    m8 += my * mz
                    m9 += mz * mz
                px[u + 1] = px[u] + x
                py[u + 1] = py[u] + y
                pz[u + 1] = pz[u] + z
        if do_graph and t <= H:
            graph_step(xyz, t, tab2, gzmin, gwidth, grows, gthr, gband, gedges, mask)
        # ---- B: row b = t - L --------------------------------------------------------------
        b = t - L
        if 0 <= b < H:
            ib = b & MI
            cs = cs_[ib]
            ce = ce_[ib]
            ks = ks_[ib]
            # column-run end, capped at b + L: the run goes on while the rows below share
            # its start (rows up to min(t, H - 1) are known)
            for u in range(W):
                ce[u] = -1 if cs[u] < 0 else b
                alive[u] = cs[u] >= 0
            for k in range(1, L + 1):
                if b + k >= H:
                    break
                csk = cs_[(b + k) & MI]
                for u in range(W):
                    cont = alive[u] and csk[u] == cs[u]
                    alive[u] = cont
                    if cont:
                        ce[u] = b + k
            _smooth_row(rcf, cs, ce, ks, b, MC, rsm[b & MS].reshape(-1))
        # ---- C: row c = b - rmax -----------------------------------------------------------
        c = b - rmax
        if 0 <= c < H:
            ic = c & MI
            rs = rs_[ic]
            re = re_[ic]
            cs = cs_[ic]
            ce = ce_[ic]
            kr = kr_[ic]
            _diff_row(rsf, rs, re, cs, ce, kr, c, MS, dif)
            _cross_row(dif, xyz[c].reshape(-1), out[c].reshape(-1))
    mom[0] = m0
    mom[1] = m1
    mom[2] = m2
    mom[3] = m3
    mom[4] = m4
    mom[5] = m5
    mom[6] = m6
    mom[7] = m7
    mom[8] = m8
    mom[9] = m9
