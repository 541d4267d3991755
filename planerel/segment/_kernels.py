"""numba kernels of normals and region growing (compiled once, cached on disk).

Importing this module compiles nothing: numba compiles each kernel at its first call, or loads
the machine code from its on-disk cache (``cache=True``, next to this file in ``__pycache__``).
Import it only from inside functions (numba itself is a heavy import).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = [
    "organized_normals_kernel",
    "grid_graph",
    "region_grow_grid",
    "region_grow_list",
    "refine_grid",
    "region_sums",
    "POPCOUNT",
    "GRID_DV",
    "GRID_DU",
]

#: The 8 grid directions; direction k and k + 4 are opposite.
GRID_DV = np.array([0, 1, 1, 1, 0, -1, -1, -1], dtype=np.int64)
GRID_DU = np.array([1, -1, 0, 1, -1, 1, 0, -1], dtype=np.int64)
#: Number of set bits of each byte.
POPCOUNT = np.array([bin(i).count("1") for i in range(256)], dtype=np.int64)


@njit(cache=True, nogil=True, inline="always")
def _scale(z, base, zref, lo, hi):
    if zref <= 0.0:
        k = int(base + 0.5)
    else:
        k = int(base * z / zref + 0.5)
    if k < lo:
        return lo
    if k > hi:
        return hi
    return k


@njit(cache=True, nogil=True)
def organized_normals_kernel(xyz, s0, r0, zref, smax, rmax, jump_per_z, out):  # pragma: no cover
    """Depth-aware normals; see planerel.normals.  Window half-size s and difference radius r
    grow with depth: round(s0 * z / zref) clipped to [min(1, s0), smax] (r likewise, >= 1)."""
    H = xyz.shape[0]
    W = xyz.shape[1]
    smin = 1 if s0 > 0 else 0
    rs = np.empty((H, W), dtype=np.int16)
    re = np.empty((H, W), dtype=np.int16)
    cs = np.empty((H, W), dtype=np.int16)
    ce = np.empty((H, W), dtype=np.int16)
    colp = np.empty((H + 1, W, 4))
    for u in range(W):
        for c in range(4):
            colp[0, u, c] = 0.0
    px = np.empty(W + 1)
    py = np.empty(W + 1)
    pz = np.empty(W + 1)
    # rows: runs, horizontal box sums (clipped to the run), column prefix of those sums
    for v in range(H):
        start = 0
        zprev = np.nan
        px[0] = 0.0
        py[0] = 0.0
        pz[0] = 0.0
        for u in range(W):
            z = xyz[v, u, 2]
            if np.isnan(z):
                rs[v, u] = -1
                start = u + 1
                px[u + 1] = px[u]
                py[u + 1] = py[u]
                pz[u + 1] = pz[u]
                zprev = np.nan
                continue
            if u > start and abs(z - zprev) > jump_per_z * min(z, zprev):
                start = u
            rs[v, u] = start
            zprev = z
            px[u + 1] = px[u] + xyz[v, u, 0]
            py[u + 1] = py[u] + xyz[v, u, 1]
            pz[u + 1] = pz[u] + z
        end = W - 1
        znext = np.nan
        for u in range(W - 1, -1, -1):
            z = xyz[v, u, 2]
            if np.isnan(z):
                re[v, u] = -1
                end = u - 1
                znext = np.nan
                continue
            if u < end and abs(z - znext) > jump_per_z * min(z, znext):
                end = u
            re[v, u] = end
            znext = z
        for u in range(W):
            z = xyz[v, u, 2]
            if np.isnan(z):
                colp[v + 1, u, 0] = colp[v, u, 0]
                colp[v + 1, u, 1] = colp[v, u, 1]
                colp[v + 1, u, 2] = colp[v, u, 2]
                colp[v + 1, u, 3] = colp[v, u, 3]
                continue
            s = _scale(z, s0, zref, smin, smax)
            lo = max(u - s, rs[v, u])
            hi = min(u + s, re[v, u])
            colp[v + 1, u, 0] = colp[v, u, 0] + px[hi + 1] - px[lo]
            colp[v + 1, u, 1] = colp[v, u, 1] + py[hi + 1] - py[lo]
            colp[v + 1, u, 2] = colp[v, u, 2] + pz[hi + 1] - pz[lo]
            colp[v + 1, u, 3] = colp[v, u, 3] + (hi - lo + 1)
    # column runs
    for v in range(H):
        for u in range(W):
            z = xyz[v, u, 2]
            if np.isnan(z):
                cs[v, u] = -1
            elif v > 0 and cs[v - 1, u] >= 0:
                zp = xyz[v - 1, u, 2]
                if abs(z - zp) > jump_per_z * min(z, zp):
                    cs[v, u] = v
                else:
                    cs[v, u] = cs[v - 1, u]
            else:
                cs[v, u] = v
    for v in range(H - 1, -1, -1):
        for u in range(W):
            z = xyz[v, u, 2]
            if np.isnan(z):
                ce[v, u] = -1
            elif v < H - 1 and ce[v + 1, u] >= 0:
                zn = xyz[v + 1, u, 2]
                if abs(z - zn) > jump_per_z * min(z, zn):
                    ce[v, u] = v
                else:
                    ce[v, u] = ce[v + 1, u]
            else:
                ce[v, u] = v
    # smoothed points (vertical box over the horizontal sums), stored in out temporarily
    sm = np.empty((H, W, 3), dtype=np.float32)
    for v in range(H):
        for u in range(W):
            z = xyz[v, u, 2]
            if np.isnan(z):
                continue
            s = _scale(z, s0, zref, smin, smax)
            lo = max(v - s, cs[v, u])
            hi = min(v + s, ce[v, u])
            n = colp[hi + 1, u, 3] - colp[lo, u, 3]
            sm[v, u, 0] = (colp[hi + 1, u, 0] - colp[lo, u, 0]) / n
            sm[v, u, 1] = (colp[hi + 1, u, 1] - colp[lo, u, 1]) / n
            sm[v, u, 2] = (colp[hi + 1, u, 2] - colp[lo, u, 2]) / n
    for v in range(H):
        for u in range(W):
            z = xyz[v, u, 2]
            if np.isnan(z):
                out[v, u, 0] = np.nan
                out[v, u, 1] = np.nan
                out[v, u, 2] = np.nan
                continue
            r = _scale(z, r0, zref, 1, rmax)
            ur = min(u + r, re[v, u])
            ul = max(u - r, rs[v, u])
            vd = min(v + r, ce[v, u])
            vu = max(v - r, cs[v, u])
            if ur == ul or vd == vu:
                out[v, u, 0] = np.nan
                out[v, u, 1] = np.nan
                out[v, u, 2] = np.nan
                continue
            ax = sm[v, ur, 0] - sm[v, ul, 0]
            ay = sm[v, ur, 1] - sm[v, ul, 1]
            az = sm[v, ur, 2] - sm[v, ul, 2]
            bx = sm[vd, u, 0] - sm[vu, u, 0]
            by = sm[vd, u, 1] - sm[vu, u, 1]
            bz = sm[vd, u, 2] - sm[vu, u, 2]
            nx = ay * bz - az * by
            ny = az * bx - ax * bz
            nz = ax * by - ay * bx
            nn = np.sqrt(nx * nx + ny * ny + nz * nz)
            if nn == 0.0:
                out[v, u, 0] = np.nan
                out[v, u, 1] = np.nan
                out[v, u, 2] = np.nan
                continue
            if nx * xyz[v, u, 0] + ny * xyz[v, u, 1] + nz * z > 0.0:
                nn = -nn
            out[v, u, 0] = nx / nn
            out[v, u, 1] = ny / nn
            out[v, u, 2] = nz / nn


@njit(cache=True, nogil=True)
def grid_graph(xyz, delta_factor, delta_fixed, by_depth, nbands, row_step, mask):  # pragma: no cover
    """Fill ``mask`` (H, W) uint8 with the grid neighbours within delta.

    delta: ``delta_fixed`` when > 0; else ``delta_factor`` x the mean over points of the distance
    to the nearest of the 8 adjacent neighbours, estimated on every ``row_step``-th row; with
    ``by_depth`` that mean is taken per depth band (``nbands`` bands) and an edge uses the band
    of its farther point.  Returns (delta table (nbands,), band zmin, band width, global mean).
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
    bsum = np.zeros(nbands)
    bcnt = np.zeros(nbands)
    tot = 0.0
    totn = 0.0
    for v in range(0, H, row_step):
        for u in range(W):
            x0 = xyz[v, u, 0]
            if np.isnan(x0):
                continue
            y0 = xyz[v, u, 1]
            z0 = xyz[v, u, 2]
            best = np.inf
            for dv in range(-1, 2):
                vv = v + dv
                if vv < 0 or vv >= H:
                    continue
                for du in range(-1, 2):
                    uu = u + du
                    if (dv == 0 and du == 0) or uu < 0 or uu >= W:
                        continue
                    x1 = xyz[vv, uu, 0]
                    if np.isnan(x1):
                        continue
                    dx = x1 - x0
                    dy = xyz[vv, uu, 1] - y0
                    dz = xyz[vv, uu, 2] - z0
                    d = dx * dx + dy * dy + dz * dz
                    if d < best:
                        best = d
            if best < np.inf:
                d = np.sqrt(best)
                b = min(nbands - 1, max(0, int((z0 - zmin) / width)))
                bsum[b] += d
                bcnt[b] += 1.0
                tot += d
                totn += 1.0
    mean = tot / totn if totn > 0 else 0.0
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
        # never below the image-wide value scaled to this depth's nearest band: keep it monotone
        for b in range(1, nbands):
            if table[b] < table[b - 1]:
                table[b] = table[b - 1]
    tab2 = table * table
    for v in range(H):
        for u in range(W):
            mask[v, u] = 0
    for v in range(H):
        for u in range(W):
            x0 = xyz[v, u, 0]
            if np.isnan(x0):
                continue
            y0 = xyz[v, u, 1]
            z0 = xyz[v, u, 2]
            for k in range(4):
                if k == 0:
                    vv = v
                    uu = u + 1
                elif k == 1:
                    vv = v + 1
                    uu = u - 1
                elif k == 2:
                    vv = v + 1
                    uu = u
                else:
                    vv = v + 1
                    uu = u + 1
                if vv >= H or uu < 0 or uu >= W:
                    continue
                x1 = xyz[vv, uu, 0]
                if np.isnan(x1):
                    continue
                z1 = xyz[vv, uu, 2]
                dx = x1 - x0
                dy = xyz[vv, uu, 1] - y0
                dz = z1 - z0
                zf = z1 if z1 > z0 else z0
                b = min(nbands - 1, max(0, int((zf - zmin) / width)))
                if dx * dx + dy * dy + dz * dz < tab2[b]:
                    mask[v, u] |= np.uint8(1 << k)
                    mask[vv, uu] |= np.uint8(1 << (k + 4))
    return table, zmin, width, mean


@njit(cache=True, nogil=True)
def region_grow_grid(nrm, nvalid, mask, W, min_nb, cos_init, cos_main, cos_seed,
                     num_init, update_step, min_size, labels, queue):  # pragma: no cover
    """The paper's Algorithm 1 on the 8-neighbour image grid (flat arrays).

    nrm (N, 3) unit normals; nvalid (N,) bool; mask (N,) uint8 neighbour bits; labels (N,) int32
    receives region ids (-1 = could join but did not, -2 = cannot join: no normal or fewer than
    ``min_nb`` delta-neighbours); queue (N,) int32 scratch.  Returns the region count.
    """
    N = nrm.shape[0]
    offs = np.empty(8, dtype=np.int64)
    dv = (0, 1, 1, 1, 0, -1, -1, -1)
    du = (1, -1, 0, 1, -1, 1, 0, -1)
    for k in range(8):
        offs[k] = dv[k] * W + du[k]
    popc = np.zeros(256, dtype=np.int64)
    for i in range(256):
        c = 0
        x = i
        while x:
            c += x & 1
            x >>= 1
        popc[i] = c
    seedable = np.ones(N, dtype=np.bool_)
    for p in range(N):
        nvalid[p] = not np.isnan(nrm[p, 0] + nrm[p, 1] + nrm[p, 2])
        labels[p] = -1 if (nvalid[p] and popc[mask[p]] >= min_nb) else -2
    nreg = 0
    for p in range(N):
        if labels[p] != -1 or not seedable[p]:
            continue
        m = mask[p]
        # a seed must lie inside a smooth patch: every neighbour's normal close to its own
        n0x = nrm[p, 0]
        n0y = nrm[p, 1]
        n0z = nrm[p, 2]
        smooth = True
        for k in range(8):
            if (m >> k) & 1:
                q = p + offs[k]
                if not nvalid[q] or n0x * nrm[q, 0] + n0y * nrm[q, 1] + n0z * nrm[q, 2] < cos_seed:
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
        thr = cos_init if num_init > 1 else cos_main
        while head < tail:
            c = queue[head]
            head += 1
            mc = mask[c]
            for k in range(8):
                if not (mc >> k) & 1:
                    continue
                q = c + offs[k]
                if labels[q] != -1:
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
                if count <= num_init or count % update_step == 0:
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


@njit(cache=True, nogil=True)
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
        smooth = True
        for k in range(K):
            q = nbr[p, k]
            if q >= 0:
                if not nvalid[q] or n0x * nrm[q, 0] + n0y * nrm[q, 1] + n0z * nrm[q, 2] < cos_seed:
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
                if count <= num_init or count % update_step == 0:
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


@njit(cache=True, nogil=True)
def _grow(arr, n):  # pragma: no cover - compiled
    out = np.empty(max(2 * arr.shape[0], n + 1), dtype=arr.dtype)
    out[: arr.shape[0]] = arr
    return out


@njit(cache=True, nogil=True)
def refine_grid(pts, mask, W, labels, planes, thr, rounds):  # pragma: no cover - compiled
    """Boundary completion by priority flood: unassigned valid pixels (label < 0) join a
    neighbouring region (over a delta edge) whose fitted plane is within the region's threshold,
    nearest plane first (16 distance levels per threshold, FIFO within a level), at most
    ``rounds`` pixels away from the grown region.  Returns pixels assigned."""
    N = pts.shape[0]
    NB = 16
    offs = np.empty(8, dtype=np.int64)
    dv = (0, 1, 1, 1, 0, -1, -1, -1)
    du = (1, -1, 0, 1, -1, 1, 0, -1)
    for k in range(8):
        offs[k] = dv[k] * W + du[k]
    depth = np.zeros(N, dtype=np.int32)
    cap = 1024
    ip = np.empty(cap, dtype=np.int32)
    il = np.empty(cap, dtype=np.int32)
    nx = np.empty(cap, dtype=np.int32)
    head = np.full(NB, -1, dtype=np.int32)
    tail = np.full(NB, -1, dtype=np.int32)
    n = 0
    cur = NB
    for p in range(N):
        if labels[p] >= 0:
            continue
        m = mask[p]
        if m == 0:
            continue
        px = pts[p, 0]
        py = pts[p, 1]
        pz = pts[p, 2]
        for k in range(8):
            if (m >> k) & 1:
                lab = labels[p + offs[k]]
                if lab >= 0:
                    d = abs(planes[lab, 0] * px + planes[lab, 1] * py + planes[lab, 2] * pz + planes[lab, 3])
                    if d < thr[lab]:
                        lev = min(NB - 1, int(NB * d / thr[lab]))
                        if n == cap:
                            ip = _grow(ip, n)
                            il = _grow(il, n)
                            nx = _grow(nx, n)
                            cap = ip.shape[0]
                        ip[n] = p
                        il[n] = lab
                        nx[n] = -1
                        if tail[lev] >= 0:
                            nx[tail[lev]] = n
                        else:
                            head[lev] = n
                        tail[lev] = n
                        n += 1
                        if lev < cur:
                            cur = lev
    total = 0
    while cur < NB:
        it = head[cur]
        if it < 0:
            cur += 1
            continue
        head[cur] = nx[it]
        if head[cur] < 0:
            tail[cur] = -1
        p = ip[it]
        lab = il[it]
        if labels[p] >= 0:
            continue
        labels[p] = lab
        total += 1
        m = mask[p]
        best = rounds + 1
        for k in range(8):
            if (m >> k) & 1:
                q = p + offs[k]
                if labels[q] == lab and depth[q] + 1 < best:
                    best = depth[q] + 1
        depth[p] = best
        if best >= rounds:
            continue
        for k in range(8):
            if (m >> k) & 1:
                q = p + offs[k]
                if labels[q] < 0:
                    dq = abs(planes[lab, 0] * pts[q, 0] + planes[lab, 1] * pts[q, 1]
                             + planes[lab, 2] * pts[q, 2] + planes[lab, 3])
                    if dq < thr[lab]:
                        lev = min(NB - 1, int(NB * dq / thr[lab]))
                        if n == cap:
                            ip = _grow(ip, n)
                            il = _grow(il, n)
                            nx = _grow(nx, n)
                            cap = ip.shape[0]
                        ip[n] = q
                        il[n] = lab
                        nx[n] = -1
                        if tail[lev] >= 0:
                            nx[tail[lev]] = n
                        else:
                            head[lev] = n
                        tail[lev] = n
                        n += 1
                        if lev < cur:
                            cur = lev
    return total


@njit(cache=True, nogil=True)
def region_sums(pts, labels, nreg):  # pragma: no cover - compiled
    """Per-region moments: (nreg, 10) = n, sx, sy, sz, sxx, sxy, sxz, syy, syz, szz, about each
    region's first point (for numerical stability), and (nreg, 3) those reference points."""
    out = np.zeros((nreg, 10))
    ref = np.zeros((nreg, 3))
    seen = np.zeros(nreg, dtype=np.bool_)
    N = pts.shape[0]
    for p in range(N):
        lab = labels[p]
        if lab < 0:
            continue
        if not seen[lab]:
            seen[lab] = True
            ref[lab, 0] = pts[p, 0]
            ref[lab, 1] = pts[p, 1]
            ref[lab, 2] = pts[p, 2]
        x = pts[p, 0] - ref[lab, 0]
        y = pts[p, 1] - ref[lab, 1]
        z = pts[p, 2] - ref[lab, 2]
        o = out[lab]
        o[0] += 1.0
        o[1] += x
        o[2] += y
        o[3] += z
        o[4] += x * x
        o[5] += x * y
        o[6] += x * z
        o[7] += y * y
        o[8] += y * z
        o[9] += z * z
    return out, ref
