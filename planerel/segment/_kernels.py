"""numba kernels of region growing, boundary completion and plane fits (compiled once, cached
on disk).

Importing this module compiles nothing: numba compiles each kernel at its first call, or loads
the machine code from its on-disk cache (``cache=True``, next to this file in ``__pycache__``).
Import it only from inside functions (numba itself is a heavy import).
"""

from __future__ import annotations

import numpy as np
from numba import config, njit
from numba.cpython.unsafe.numbers import trailing_zeros

from planerel.segment._intrinsics import prefetch

if config.DISABLE_JIT:  # the kernels run as plain Python (coverage runs)
    def trailing_zeros(x):  # noqa: F811
        """Index of the lowest set bit of ``x`` (> 0), as numba's intrinsic."""
        x = int(x)
        return (x & -x).bit_length() - 1

__all__ = [
    "region_grow_list",
    "refine_grid_ws",
    "region_grow_grid_ws",
    "padded_labels",
    "region_sums",
    "region_sums_into",
    "add_region_moments",
    "fit_planes_kernel",
    "planes_from_sums",
    "spread_of_moments",
    "leftover_components",
    "POPCOUNT",
    "GRID_DV",
    "GRID_DU",
]

#: The 8 grid directions; direction k and k + 4 are opposite.
GRID_DV = np.array([0, 1, 1, 1, 0, -1, -1, -1], dtype=np.int64)
GRID_DU = np.array([1, -1, 0, 1, -1, 1, 0, -1], dtype=np.int64)
#: Number of set bits of each byte.
POPCOUNT = np.array([bin(i).count("1") for i in range(256)], dtype=np.int64)


@njit(cache=True, nogil=True, error_model="numpy")
def _valid_normals(n3, nvalid):  # pragma: no cover - compiled
    """``nvalid[p]``: the normal ``n3[3p:3p + 3]`` (flattened (N, 3)) has no NaN."""
    for p in range(nvalid.shape[0]):
        nvalid[p] = not np.isnan(n3[3 * p] + n3[3 * p + 1] + n3[3 * p + 2])


@njit(cache=True, nogil=True, error_model="numpy")
def _free_or_not(nvalid, mask, min_nb, lab):  # pragma: no cover - compiled
    """``lab[p]`` = -1 (free) where ``nvalid[p]`` and ``mask[p]`` has at least ``min_nb`` set
    bits, else -2 (cannot join)."""
    for p in range(lab.shape[0]):
        x = np.int32(mask[p])
        x = x - ((x >> 1) & 0x55)
        x = (x & 0x33) + ((x >> 2) & 0x33)
        x = (x + (x >> 4)) & 0x0F
        lab[p] = np.int32(-1) if (nvalid[p] and x >= min_nb) else np.int32(-2)


@njit(cache=True, nogil=True, error_model="numpy")
def region_grow_grid_ws(nrm, nvalid, mask, W, min_nb, cos_init, cos_main, cos_seed,
                        num_init, update_step, min_size, padded, queue,
                        seedable):  # pragma: no cover
    """Algorithm 1 on the 8-neighbour image grid (flat arrays).

    A candidate joins when its normal's cosine with the base normal is at least ``cos_init``
    while the region has fewer than ``num_init`` points, ``cos_main`` after (the paper:
    cos theta, then cos(theta * angle_mf); planerel's reversed order swaps them).  A seed
    needs every delta-neighbour's normal within ``cos_seed`` of its own (planerel's seed
    test); ``cos_seed < -1`` turns the test off (the paper).

    nrm (N, 3) unit normals; nvalid (N,) bool; mask (N,) uint8 neighbour bits; ``padded``
    (N + 2W + 2,) int32 holds the labels at ``[W + 1, W + 1 + N)`` (see :func:`padded_labels`)
    between padding that must be -2 (read, never written, so that the eight neighbour labels
    of any pixel are read without bounds tests).  The labels receive region ids (-1 = could
    join but did not, -2 = cannot join: no normal or fewer than ``min_nb`` delta-neighbours);
    queue (N,) int32 and seedable (N,) bool scratch.  Returns the region count.  The regions'
    moments come afterwards from one row-major pass (:func:`region_sums_into`): accumulating
    them here, in growing order, cost more than the pass (each joined point's coordinates are
    a cache miss on the growing's critical path)."""
    N = nrm.shape[0]
    B = W + 1
    offs = np.empty(8, dtype=np.int64)
    dv = (0, 1, 1, 1, 0, -1, -1, -1)
    du = (1, -1, 0, 1, -1, 1, 0, -1)
    for k in range(8):
        offs[k] = dv[k] * W + du[k]
    # unsigned copies for the growing loop: numba handles a negative index on every load
    # with a signed one (three more operations on the critical path); the offsets wrap
    # modulo 2^64, so c + uoffs[k] is the neighbour's index
    uoffs = np.empty(8, dtype=np.uint64)
    for k in range(8):
        uoffs[k] = np.uint64(offs[k])
    uB = np.uint64(B)
    nf = nrm.reshape(-1)  # flat: a constant stride instead of a multiplication by shape[1]
    # three loops LLVM vectorises (flat normals: constant stride; popcount by bit arithmetic)
    seedable[:] = True
    _valid_normals(nf, nvalid)
    _free_or_not(nvalid, mask, min_nb, padded[B:B + N])
    one = np.uint64(1)
    o1 = np.uint64(W - 1)
    o2 = np.uint64(W)
    o3 = np.uint64(W + 1)
    nreg = 0
    for p in range(N):
        if padded[np.uint64(p) + uB] != -1 or not seedable[p]:
            continue
        m = mask[p]
        n0x = nrm[p, 0]
        n0y = nrm[p, 1]
        n0z = nrm[p, 2]
        if cos_seed >= -1.0:
            # planerel's seed test: a seed must lie inside a smooth patch, every neighbour's
            # normal close to its own (cos_seed < -1: no test, as in the paper)
            smooth = True
            for k in range(8):
                if (m >> k) & 1:
                    q = p + offs[k]
                    if (not nvalid[q]
                            or n0x * nrm[q, 0] + n0y * nrm[q, 1] + n0z * nrm[q, 2] < cos_seed):
                        smooth = False
                        break
            if not smooth:
                seedable[p] = False
                continue
        rid = nreg
        padded[p + B] = rid
        queue[0] = p
        head = 0
        tail = 1
        sx = n0x
        sy = n0y
        sz = n0z
        bx = n0x
        by = n0y
        bz = n0z
        count = 1
        # refresh the base normal at counts 1..num_init and then at every multiple of
        # update_step (a running target instead of count % update_step: no integer division)
        next_update = update_step * (num_init // update_step + 1)
        thr = cos_init if num_init > 1 else cos_main
        while head < tail:
            c = np.uint64(queue[head])
            head += 1
            # the free neighbours over delta edges as a bit set in direction order, without
            # a branch per neighbour (which neighbours are free is unpredictable on noisy
            # data)
            i = c + uB
            f = (np.uint32(padded[i + one] == -1) | (np.uint32(padded[i + o1] == -1) << 1)
                 | (np.uint32(padded[i + o2] == -1) << 2)
                 | (np.uint32(padded[i + o3] == -1) << 3)
                 | (np.uint32(padded[i - one] == -1) << 4)
                 | (np.uint32(padded[i - o1] == -1) << 5)
                 | (np.uint32(padded[i - o2] == -1) << 6)
                 | (np.uint32(padded[i - o3] == -1) << 7)) & np.uint32(mask[c])
            # in direction order, as a loop over the eight would visit them; joining one
            # neighbour does not change whether another is free
            while f != 0:
                k = trailing_zeros(f)
                f &= f - np.uint32(1)
                q = c + uoffs[k]
                uq = np.uint64(3) * q
                qx = nf[uq]
                qy = nf[uq + one]
                qz = nf[uq + np.uint64(2)]
                if qx * bx + qy * by + qz * bz < thr:
                    continue
                padded[q + uB] = rid
                # the normal and label one more step in this direction, which the next
                # breadth-first level reads: their cache lines are often not yet near
                # (~10 % of the growing)
                prefetch(nf, np.uint64(3) * (q + q - c))
                prefetch(padded, q + q - c + uB)
                queue[tail] = np.int32(q)
                tail += 1
                sx += qx
                sy += qy
                sz += qz
                count += 1
                if count <= num_init or count == next_update:
                    if count == next_update:
                        next_update += update_step
                    inv = 1.0 / np.sqrt(sx * sx + sy * sy + sz * sz)
                    bx = sx * inv
                    by = sy * inv
                    bz = sz * inv
                    if count >= num_init:
                        thr = cos_main
        if count >= min_size:
            nreg += 1
        else:
            for t in range(tail):
                padded[queue[t] + B] = -1
                seedable[queue[t]] = False
    return nreg


def padded_labels(h: int, w: int) -> tuple:
    """A label buffer for :func:`region_grow_grid_ws`: ``(padded (h*w + 2w + 2,) int32 with
    -2 padding, labels (h*w,) view of its middle)``."""
    padded = np.full(h * w + 2 * w + 2, -2, dtype=np.int32)
    return padded, padded[w + 1:w + 1 + h * w]


@njit(cache=True, nogil=True, error_model="numpy")
def region_grow_list(nrm, nvalid, nbr, min_nb, cos_init, cos_main, cos_seed,
                     num_init, update_step, min_size, labels, queue):  # pragma: no cover
    """Algorithm 1 on a neighbour list ``nbr`` (N, K) int32 (-1 = none), for unorganized clouds."""
    N = nrm.shape[0]
    K = nbr.shape[1]
    nbcount = np.zeros(N, dtype=np.int64)
    for p in range(N):
        c = 0
        for k in range(K):
            if nbr[p, k] >= 0:
                c += 1
        nbcount[p] = c
    seedable = np.ones(N, dtype=np.bool_)
    for p in range(N):
        nvalid[p] = not np.isnan(nrm[p, 0] + nrm[p, 1] + nrm[p, 2])
        labels[p] = -1 if (nvalid[p] and nbcount[p] >= min_nb) else -2
    nreg = 0
    for p in range(N):
        if labels[p] != -1 or not seedable[p]:
            continue
        n0x = nrm[p, 0]
        n0y = nrm[p, 1]
        n0z = nrm[p, 2]
        if cos_seed >= -1.0:  # planerel's seed test (see region_grow_grid_ws)
            smooth = True
            for k in range(K):
                q = nbr[p, k]
                if q >= 0:
                    if (not nvalid[q]
                            or n0x * nrm[q, 0] + n0y * nrm[q, 1] + n0z * nrm[q, 2] < cos_seed):
                        smooth = False
                        break
            if not smooth:
                seedable[p] = False
                continue
        rid = nreg
        labels[p] = rid
        queue[0] = p
        head = 0
        tail = 1
        sx = n0x
        sy = n0y
        sz = n0z
        bx = n0x
        by = n0y
        bz = n0z
        count = 1
        # refresh the base normal at counts 1..num_init and then at every multiple of
        # update_step (a running target instead of count % update_step: no integer division)
        next_update = update_step * (num_init // update_step + 1)
        thr = cos_init if num_init > 1 else cos_main
        while head < tail:
            c = queue[head]
            head += 1
            for k in range(K):
                q = nbr[c, k]
                if q < 0 or labels[q] != -1:
                    continue
                qx = nrm[q, 0]
                qy = nrm[q, 1]
                qz = nrm[q, 2]
                if qx * bx + qy * by + qz * bz < thr:
                    continue
                labels[q] = rid
                queue[tail] = q
                tail += 1
                sx += qx
                sy += qy
                sz += qz
                count += 1
                if count <= num_init or count == next_update:
                    if count == next_update:
                        next_update += update_step
                    inv = 1.0 / np.sqrt(sx * sx + sy * sy + sz * sz)
                    bx = sx * inv
                    by = sy * inv
                    bz = sz * inv
                    if count >= num_init:
                        thr = cos_main
        if count >= min_size:
            nreg += 1
        else:
            for i in range(tail):
                labels[queue[i]] = -1
                seedable[queue[i]] = False
    return nreg


#: Distance levels of the completion queue (per region threshold).
_NB = 16


@njit(cache=True, nogil=True, error_model="numpy")
def _refine_scan(pts, mask, W, labels, planes, thr, p0, qlev, ent, state,
                 head, tail):  # pragma: no cover - compiled
    """The completion's frontier from pixel ``p0`` on: each unassigned pixel next to a region
    (over a delta edge) is queued once, with its nearest neighbouring plane (within that
    region's threshold).  Stops early when ``ent`` is full; returns the next pixel to scan
    (N when done).  Queue state: ``state`` [entries used, lowest non-empty level, assigned]."""
    N = pts.shape[0]
    NB = _NB
    dv = (0, 1, 1, 1, 0, -1, -1, -1)
    du = (1, -1, 0, 1, -1, 1, 0, -1)
    n = state[0]
    cur = state[1]
    cap = ent.shape[0]
    for p in range(p0, N):
        m = mask[p]
        if not ((labels[p] < 0) & (m != 0)):
            continue
        if n == cap:
            state[0] = n
            state[1] = cur
            return p
        bestl = -1
        bestd = 1.0
        for k in range(8):
            if (m >> k) & 1:
                lab = labels[p + dv[k] * W + du[k]]
                if lab >= 0 and lab != bestl:
                    d = abs(planes[lab, 0] * pts[p, 0] + planes[lab, 1] * pts[p, 1]
                            + planes[lab, 2] * pts[p, 2] + planes[lab, 3]) / thr[lab]
                    if d < bestd:
                        bestd = d
                        bestl = lab
        if bestl >= 0:
            lev = min(NB - 1, int(NB * bestd))
            qlev[p] = lev
            # FIFO per level: entries (pixel, region, next entry of the level); written out
            # here and in _refine_flood: a shared helper taking the queue arrays measured 16 %
            # slower (a reference-count round trip per call)
            ent[n, 0] = p
            ent[n, 1] = bestl
            ent[n, 2] = -1
            if tail[lev] >= 0:
                ent[tail[lev], 2] = n
            else:
                head[lev] = n
            tail[lev] = n
            n += 1
            cur = min(cur, lev)
    state[0] = n
    state[1] = cur
    return N


@njit(cache=True, nogil=True, error_model="numpy")
def _refine_flood(pts, mask, W, labels, planes, thr, rounds, depth, qlev, ent, state, head,
                  tail, sums, ref):  # pragma: no cover - compiled
    """The completion's priority flood (see :func:`refine_grid_ws`) until the queue is empty
    (returns True) or ``ent`` is full (returns False; call again with a larger copy)."""
    NB = _NB
    dv = (0, 1, 1, 1, 0, -1, -1, -1)
    du = (1, -1, 0, 1, -1, 1, 0, -1)
    n = state[0]
    cur = state[1]
    total = state[2]
    cap = ent.shape[0]
    while cur < NB:
        it = head[cur]
        if it < 0:
            cur += 1
            continue
        if n + 8 > cap:  # a pixel queues at most 8 entries: stop before taking it
            state[0] = n
            state[1] = cur
            state[2] = total
            return False
        head[cur] = ent[it, 2]
        if head[cur] < 0:
            tail[cur] = -1
        p = ent[it, 0]
        lab = ent[it, 1]
        if labels[p] < 0:
            m = mask[p]
            labels[p] = lab
            total += 1
            # moments of the region (written out: an inlined helper taking the arrays costs a
            # reference-count round trip per call)
            x = pts[p, 0] - ref[lab, 0]
            y = pts[p, 1] - ref[lab, 1]
            z = pts[p, 2] - ref[lab, 2]
            sums[lab, 0] += 1.0
            sums[lab, 1] += x
            sums[lab, 2] += y
            sums[lab, 3] += z
            sums[lab, 4] += x * x
            sums[lab, 5] += x * y
            sums[lab, 6] += x * z
            sums[lab, 7] += y * y
            sums[lab, 8] += y * z
            sums[lab, 9] += z * z
            best = rounds + 1
            for k in range(8):
                if (m >> k) & 1:
                    q = p + dv[k] * W + du[k]
                    if labels[q] == lab and depth[q] + 1 < best:
                        best = depth[q] + 1
            depth[p] = min(best, 255)
            if best < rounds:
                a0 = planes[lab, 0]
                a1 = planes[lab, 1]
                a2 = planes[lab, 2]
                a3 = planes[lab, 3]
                t = thr[lab]
                for k in range(8):
                    if (m >> k) & 1:
                        q = p + dv[k] * W + du[k]
                        if labels[q] < 0:
                            dq = abs(a0 * pts[q, 0] + a1 * pts[q, 1] + a2 * pts[q, 2] + a3) / t
                            if dq < 1.0:
                                lev = min(NB - 1, int(NB * dq))
                                # an entry at a level no lower than one queued before pops
                                # after it, when q is taken already: not queued
                                if lev < qlev[q]:
                                    qlev[q] = lev
                                    ent[n, 0] = q
                                    ent[n, 1] = lab
                                    ent[n, 2] = -1
                                    if tail[lev] >= 0:
                                        ent[tail[lev], 2] = n
                                    else:
                                        head[lev] = n
                                    tail[lev] = n
                                    n += 1
                                    cur = min(cur, lev)
    state[0] = n
    state[1] = cur
    state[2] = total
    return True


@njit(cache=True, nogil=True)
def _grown(ent):  # pragma: no cover - compiled
    e2 = np.empty((2 * ent.shape[0], 3), dtype=np.int32)
    e2[:ent.shape[0]] = ent
    return e2


@njit(cache=True, nogil=True, error_model="numpy")
def refine_grid_ws(pts, mask, W, labels, planes, thr, rounds, depth, qlev, ent, sums,
                   ref):  # pragma: no cover
    """Boundary completion by priority flood: unassigned valid pixels (label < 0) join a
    neighbouring region (over a delta edge) whose fitted plane is within the region's threshold,
    nearest plane first (16 distance levels per threshold, FIFO within a level), at most
    ``rounds`` pixels away from the grown region.  The flood starts from the frontier only (each
    unassigned pixel next to a region, queued once with its nearest neighbouring plane).
    Scratch: ``depth``, ``qlev`` (N,) uint8; ``ent`` (M, 3) int32 queue entries (pixel, region,
    next), copied to a larger array when full.  Each assigned pixel's moments are added to
    ``sums`` / ``ref`` (see :func:`region_sums`).  Returns (pixels assigned, the entries array
    used: ``ent`` or its larger copy)."""
    N = pts.shape[0]
    for p in range(N):
        depth[p] = 0
        qlev[p] = 255
    head = np.full(_NB, -1, dtype=np.int64)
    tail = np.full(_NB, -1, dtype=np.int64)
    state = np.zeros(3, dtype=np.int64)
    state[1] = _NB
    p = 0
    while True:
        p = _refine_scan(pts, mask, W, labels, planes, thr, p, qlev, ent, state, head, tail)
        if p == N:
            break
        ent = _grown(ent)
    while not _refine_flood(pts, mask, W, labels, planes, thr, rounds, depth, qlev, ent, state,
                            head, tail, sums, ref):
        ent = _grown(ent)
    return state[2], ent


#: Moment sums of no point: ``(n, sx, sy, sz, sxx, sxy, sxz, syy, syz, szz)``.
NO_MOMENTS = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@njit(inline="always", cache=True)
def moments_load(sums, r):  # pragma: no cover - compiled
    """Row ``r`` of ``sums`` (nrow, 10) as a tuple (kept in registers by the callers' loops)."""
    return (sums[r, 0], sums[r, 1], sums[r, 2], sums[r, 3], sums[r, 4], sums[r, 5],
            sums[r, 6], sums[r, 7], sums[r, 8], sums[r, 9])


@njit(inline="always", cache=True)
def moments_store(sums, r, m):  # pragma: no cover - compiled
    """Write the moments tuple ``m`` to row ``r`` of ``sums``."""
    sums[r, 0] = m[0]
    sums[r, 1] = m[1]
    sums[r, 2] = m[2]
    sums[r, 3] = m[3]
    sums[r, 4] = m[4]
    sums[r, 5] = m[5]
    sums[r, 6] = m[6]
    sums[r, 7] = m[7]
    sums[r, 8] = m[8]
    sums[r, 9] = m[9]


@njit(inline="always", cache=True)
def moments_add(m, x, y, z):  # pragma: no cover - compiled
    """The moments ``m`` plus one point ``(x, y, z)`` (relative to the row's reference): the
    one accumulation every moment kernel shares (the same additions in the same order)."""
    return (m[0] + 1.0, m[1] + x, m[2] + y, m[3] + z, m[4] + x * x, m[5] + x * y,
            m[6] + x * z, m[7] + y * y, m[8] + y * z, m[9] + z * z)


@njit(inline="always", cache=True)
def moments_enter(sums, ref, cur, m, r, pts, p, take_ref):  # pragma: no cover - compiled
    """Close the running row ``cur`` (store ``m``; none when ``cur < 0``) and open row ``r`` at
    point ``p``: with ``take_ref`` a row whose count is still 0 takes ``pts[p]`` as its
    reference.  Returns row ``r``'s moments and its reference ``(m, rx, ry, rz)``."""
    if cur >= 0:
        moments_store(sums, cur, m)
    if take_ref and sums[r, 0] == 0.0:
        ref[r, 0] = pts[p, 0]
        ref[r, 1] = pts[p, 1]
        ref[r, 2] = pts[p, 2]
    return moments_load(sums, r), ref[r, 0], ref[r, 1], ref[r, 2]


@njit(inline="always", cache=True)
def plane_from_scatter(sxx, sxy, sxz, syy, syz, szz, cx, cy, cz):  # pragma: no cover - compiled
    """Unit normal (3,) and offset of the plane through ``(cx, cy, cz)`` whose scatter about
    that point has these entries: the smallest-eigenvalue eigenvector."""
    cov = np.empty((3, 3))
    cov[0, 0] = sxx
    cov[0, 1] = cov[1, 0] = sxy
    cov[0, 2] = cov[2, 0] = sxz
    cov[1, 1] = syy
    cov[1, 2] = cov[2, 1] = syz
    cov[2, 2] = szz
    _, vec = np.linalg.eigh(cov)
    n = vec[:, 0].copy()
    return n, -(n[0] * cx + n[1] * cy + n[2] * cz)


@njit(cache=True, nogil=True, error_model="numpy")
def add_region_moments(pts, labels, lo, hi, sums, ref, clamp,
                       first_ref=False):  # pragma: no cover - compiled
    """Add the moments of every point whose label lies in ``[lo, hi)`` to ``sums`` (about
    ``ref``; see :func:`region_sums`), in row-major order.  The current region's totals stay in
    registers until the label changes: the same additions in the same order as updating
    ``sums`` point by point, without a load and store of ten totals per point.  With ``clamp``
    labels below -1 are set to -1 on the way (the growing's "cannot join" mark).  With
    ``first_ref`` a region whose count in ``sums`` is still 0 takes the point where it is met
    first as its ``ref`` (for fresh sums: each region's first point in row-major order)."""
    N = pts.shape[0]
    cur = -1
    m = NO_MOMENTS
    rx = ry = rz = 0.0
    for p in range(N):
        lab = labels[p]
        if lab < lo or lab >= hi:
            if clamp and lab < -1:
                labels[p] = -1
            continue
        if lab != cur:
            m, rx, ry, rz = moments_enter(sums, ref, cur, m, lab, pts, p, first_ref)
            cur = lab
        m = moments_add(m, pts[p, 0] - rx, pts[p, 1] - ry, pts[p, 2] - rz)
    if cur >= 0:
        moments_store(sums, cur, m)


@njit(cache=True, nogil=True, error_model="numpy")
def region_sums(pts, labels, nreg):  # pragma: no cover - compiled
    """Per-region moments: (nreg, 10) = n, sx, sy, sz, sxx, sxy, sxz, syy, syz, szz, about each
    region's first point (for numerical stability), and (nreg, 3) those reference points."""
    out = np.empty((nreg, 10))
    ref = np.empty((nreg, 3))
    region_sums_into(pts, labels, nreg, out, ref, False)
    return out, ref


@njit(cache=True, nogil=True, error_model="numpy")
def region_sums_into(pts, labels, nreg, out, ref, clamp):  # pragma: no cover - compiled
    """:func:`region_sums` into the first ``nreg`` rows of ``out`` (>= nreg, 10) and ``ref``
    (>= nreg, 3) (other rows untouched); ``clamp``: labels below -1 become -1 (see
    :func:`add_region_moments`)."""
    for i in range(nreg):
        for k in range(10):
            out[i, k] = 0.0
        for k in range(3):
            ref[i, k] = 0.0
    # each region's reference point (its first in row-major order) is set in the same pass
    add_region_moments(pts, labels, 0, nreg, out, ref, clamp, True)


@njit(cache=True, nogil=True, error_model="numpy")
def leftover_components(mask, labels, W, min_size, comp, queue):  # pragma: no cover - compiled
    """Connected components (over delta edges) of the unassigned valid pixels (label < 0 with at
    least one delta edge) with at least ``min_size`` pixels: ``comp`` (N,) int32 receives the
    component id (0..n-1), or a negative value for every other pixel.  ``queue`` (N,) int32
    scratch.  Returns n."""
    N = labels.shape[0]
    offs = np.empty(8, dtype=np.int64)
    dv = (0, 1, 1, 1, 0, -1, -1, -1)
    du = (1, -1, 0, 1, -1, 1, 0, -1)
    for k in range(8):
        offs[k] = dv[k] * W + du[k]
    for p in range(N):
        comp[p] = -1 if (labels[p] < 0 and mask[p] != 0) else -2
    n = 0
    for p in range(N):
        if comp[p] != -1:
            continue
        comp[p] = n
        queue[0] = p
        head = 0
        tail = 1
        while head < tail:
            c = queue[head]
            head += 1
            m = mask[c]
            for k in range(8):
                if (m >> k) & 1:
                    q = c + offs[k]
                    if comp[q] == -1:
                        comp[q] = n
                        queue[tail] = q
                        tail += 1
        if tail >= min_size:
            n += 1
        else:
            for i in range(tail):
                comp[queue[i]] = -3
    return n


@njit(cache=True, nogil=True, error_model="numpy")
def fit_planes_kernel(pts, labels, nreg):  # pragma: no cover - compiled
    """Least-squares (PCA) planes of the labelled points: per region the smallest-eigenvalue
    eigenvector of the scatter matrix, turned towards the sensor.  Returns normals (nreg, 3),
    offsets (nreg,), counts (nreg,) int64, centroids (nreg, 3), rms (nreg,)."""
    sums, ref = region_sums(pts, labels, nreg)
    return planes_from_sums(sums, ref, nreg)


@njit(cache=True, nogil=True, error_model="numpy")
def planes_from_sums(sums, ref, nreg):  # pragma: no cover - compiled
    """:func:`fit_planes_kernel` from the moments (see :func:`region_sums`) of the first
    ``nreg`` rows of ``sums`` / ``ref``."""
    normals = np.zeros((nreg, 3))
    offsets = np.zeros(nreg)
    counts = np.zeros(nreg, dtype=np.int64)
    cents = np.zeros((nreg, 3))
    rms = np.zeros(nreg)
    cov = np.empty((3, 3))
    for i in range(nreg):
        n = sums[i, 0]
        counts[i] = int(n)
        if n <= 0:
            normals[i, 2] = -1.0
            continue
        mx = sums[i, 1] / n
        my = sums[i, 2] / n
        mz = sums[i, 3] / n
        cov[0, 0] = sums[i, 4] / n - mx * mx
        cov[0, 1] = sums[i, 5] / n - mx * my
        cov[0, 2] = sums[i, 6] / n - mx * mz
        cov[1, 1] = sums[i, 7] / n - my * my
        cov[1, 2] = sums[i, 8] / n - my * mz
        cov[2, 2] = sums[i, 9] / n - mz * mz
        cov[1, 0] = cov[0, 1]
        cov[2, 0] = cov[0, 2]
        cov[2, 1] = cov[1, 2]
        w, vec = np.linalg.eigh(cov)
        nx = vec[0, 0]
        ny = vec[1, 0]
        nz = vec[2, 0]
        cx = mx + ref[i, 0]
        cy = my + ref[i, 1]
        cz = mz + ref[i, 2]
        if nx * cx + ny * cy + nz * cz > 0:
            nx = -nx
            ny = -ny
            nz = -nz
        normals[i, 0] = nx
        normals[i, 1] = ny
        normals[i, 2] = nz
        cents[i, 0] = cx
        cents[i, 1] = cy
        cents[i, 2] = cz
        offsets[i] = -(nx * cx + ny * cy + nz * cz)
        rms[i] = np.sqrt(max(w[0], 0.0))
    return normals, offsets, counts, cents, rms


@njit(cache=True, nogil=True, error_model="numpy")
def spread_of_moments(mom):  # pragma: no cover - compiled
    """Eigenvalues (ascending) of the covariance of points with moments ``mom`` (10,) (count,
    sums, second moments; see
    :func:`planerel.segment._normal_kernels.normals_stream`)."""
    n = mom[0]
    cov = np.empty((3, 3))
    if n <= 0:
        return np.zeros(3)
    mx = mom[1] / n
    my = mom[2] / n
    mz = mom[3] / n
    cov[0, 0] = mom[4] / n - mx * mx
    cov[0, 1] = mom[5] / n - mx * my
    cov[0, 2] = mom[6] / n - mx * mz
    cov[1, 1] = mom[7] / n - my * my
    cov[1, 2] = mom[8] / n - my * mz
    cov[2, 2] = mom[9] / n - mz * mz
    cov[1, 0] = cov[0, 1]
    cov[2, 0] = cov[0, 2]
    cov[2, 1] = cov[1, 2]
    return np.linalg.eigvalsh(cov)

