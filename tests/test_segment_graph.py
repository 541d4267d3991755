"""The compiled neighbour-graph kernel against a plain numpy statement of its definition.

The kernel streams rows through padded buffers and compares whole rows at a time (for speed);
the reference below computes every edge of every pixel directly, so a buffer, padding or
band mistake in the kernel shows up here bit for bit (delta table and mask).
"""

import math

import numpy as np
import pytest

from planerel.segment._graph_kernels import grid_graph
from planerel.segment._kernels import GRID_DU, GRID_DV
from planerel.segment._scenes import staircase
from planerel.synth.generator import generate_scene

NB = 24


def _shifted(xyz, dv, du):
    """``out[v, u] = xyz[v + dv, u + du]`` (NaN outside the image)."""
    h, w, _ = xyz.shape
    out = np.full_like(xyz, np.nan)
    out[max(0, -dv):h - max(0, dv), max(0, -du):w - max(0, du)] = \
        xyz[max(0, dv):h - max(0, -dv), max(0, du):w - max(0, -du)]
    return out


def _d2(xyz, dv, du):
    """float32 squared length of the edge from each pixel in direction (dv, du); inf where an
    end is invalid or outside the image."""
    with np.errstate(invalid="ignore"):
        d = ((_shifted(xyz, dv, du) - xyz) ** 2).sum(axis=2)
    return np.where(np.isnan(d), np.float32(np.inf), d.astype(np.float32))


def _reference(xyz, factor, fixed, by_depth, row_step):
    h, w, _ = xyz.shape
    z = xyz[:, :, 2]
    rows = np.arange(0, h, row_step)
    zs = z[rows][np.isfinite(z[rows])]
    if zs.size == 0:
        zs = z[np.isfinite(z)]
    zmin, zmax = float(zs.min()), float(zs.max())
    width = (zmax - zmin) / NB
    if not width > 0:
        width = 1.0

    def band(zz):
        return min(NB - 1, max(0, int((zz - zmin) / width)))

    d2 = [_d2(xyz, int(dv), int(du)) for dv, du in zip(GRID_DV, GRID_DU, strict=True)]
    nearest = np.minimum.reduce(d2)
    bsum = [0.0] * NB
    bcnt = [0.0] * NB
    tot = totn = 0.0
    for v in rows:  # row-major, as the kernel sums
        for u in range(w):
            if math.isnan(z[v, u]) or not nearest[v, u] < np.inf:
                continue
            d = math.sqrt(float(nearest[v, u]))
            b = band(z[v, u])
            bsum[b] += d
            bcnt[b] += 1.0
            tot += d
            totn += 1.0
    mean = tot / totn if totn > 0 else 0.0
    if fixed > 0:
        table = [fixed] * NB
    elif not by_depth:
        table = [factor * mean] * NB
    else:
        good = [c >= 20 for c in bcnt]
        table = []
        for b in range(NB):
            if good[b]:
                table.append(factor * bsum[b] / bcnt[b])
            elif not any(good):
                table.append(factor * mean)
            else:
                k = min((k for k in range(NB) if good[k]), key=lambda k: abs(k - b))
                table.append(factor * bsum[k] / bcnt[k])
        for b in range(1, NB):
            table[b] = max(table[b], table[b - 1])
    tab2 = np.array([t * t for t in table], dtype=np.float32)
    bands = np.zeros((h, w), dtype=np.int64)
    ok = np.isfinite(z)
    bands[ok] = [band(zz) for zz in z[ok]]
    mask = np.zeros((h, w), dtype=np.uint8)
    for k, (dv, du) in enumerate(zip(GRID_DV, GRID_DU, strict=True)):
        nb_band = np.zeros((h, w), dtype=np.int64)
        vs = slice(max(0, -dv), h - max(0, dv))
        us = slice(max(0, -du), w - max(0, du))
        nb_band[vs, us] = bands[max(0, dv):h - max(0, -dv), max(0, du):w - max(0, -du)]
        edge = d2[k] < tab2[np.maximum(bands, nb_band)]
        mask |= (edge.astype(np.uint8) << k)
    return np.array(table), zmin, width, mean, mask


def _holed_stairs():
    cloud, *_ = staircase(80, 60, steps=4, seed=5)
    xyz = np.array(cloud.xyz)
    rng = np.random.default_rng(1)
    xyz[rng.random(xyz.shape[:2]) < 0.05] = np.nan  # scattered dropouts
    xyz[10:14, 30:50] = np.nan  # a hole
    return xyz


def _clouds():
    yield "stairs", _holed_stairs()
    yield "generator", np.array(generate_scene("ramp", seed=3, subsample=4).cloud.xyz)
    # 320x240 (a ramp beyond 4 m): once exposed unset padding in the row buffers
    yield "generator 320", np.array(generate_scene("ramp", seed=3, subsample=2).cloud.xyz)
    rng = np.random.default_rng(2)
    pts = rng.normal(size=(9, 13, 3))
    pts[..., 2] = np.abs(pts[..., 2]) + 1.0
    yield "random", pts
    yield "one row", pts[:1]
    yield "one column", pts[:, :1]
    yield "2x2", pts[:2, :2]


@pytest.mark.parametrize("name,xyz", list(_clouds()), ids=[n for n, _ in _clouds()])
@pytest.mark.parametrize("by_depth,fixed,row_step", [(True, -1.0, 1), (True, -1.0, 3),
                                                     (False, -1.0, 2), (True, 0.05, 1)])
def test_graph_kernel_matches_the_definition(name, xyz, by_depth, fixed, row_step):
    xyz = np.ascontiguousarray(xyz)
    mask = np.empty(xyz.shape[:2], dtype=np.uint8)
    table, zmin, width, mean = grid_graph(xyz, 6.0, fixed, by_depth, NB, row_step, mask)
    rtable, rzmin, rwidth, rmean, rmask = _reference(xyz, 6.0, fixed, by_depth, row_step)
    assert (zmin, width, mean) == (rzmin, rwidth, rmean)
    np.testing.assert_array_equal(table, rtable)
    np.testing.assert_array_equal(mask, rmask)
    # the mask is symmetric: bit k at p <=> bit k+4 at the neighbour
    h, w = mask.shape
    for k in range(4):
        fwd = (mask >> k) & 1
        back = (_shifted(((mask >> (k + 4)) & 1)[..., None].astype(float).repeat(3, 2),
                         int(GRID_DV[k]), int(GRID_DU[k]))[..., 0])
        np.testing.assert_array_equal(fwd, np.nan_to_num(back).astype(np.uint8))


def test_graph_kernel_repeats_exactly():
    """Row buffers are scratch of each call: nothing of one image leaks into the next."""
    a = np.ascontiguousarray(_holed_stairs())
    b = np.ascontiguousarray(np.array(generate_scene("box", seed=1, subsample=4).cloud.xyz)[:60, :80])
    first = np.empty(a.shape[:2], dtype=np.uint8)
    grid_graph(a, 6.0, -1.0, True, NB, 1, first)
    other = np.empty(b.shape[:2], dtype=np.uint8)
    grid_graph(b, 6.0, -1.0, True, NB, 1, other)
    again = np.empty(a.shape[:2], dtype=np.uint8)
    grid_graph(a, 6.0, -1.0, True, NB, 1, again)
    np.testing.assert_array_equal(first, again)


@pytest.mark.parametrize("name,xyz", list(_clouds()), ids=[n for n, _ in _clouds()])
def test_graph_in_the_normals_pass_matches_the_definition(name, xyz):
    """Region growing fills the graph inside the normals' pass (each row right after the
    normals read it): the same mask as the definition, and the normals unchanged."""
    from planerel.segment._graph_kernels import graph_table
    from planerel.segment._normal_kernels import no_graph, normals_stream, ring_sizes, with_graph
    from planerel.segment.normals import normal_kernel_args

    xyz = np.ascontiguousarray(xyz)
    h, w, _ = xyz.shape
    args = normal_kernel_args(xyz)
    scratch = []
    for _ in range(2):
        rr, rc, rs = ring_sizes(args[3], args[4])
        scratch.append((np.empty((h, w, 3), np.float32), np.empty((6, rr, w), np.int16),
                        np.empty((rc, w, 4)), np.empty((rs, w, 3), np.float32), np.empty(10)))
    table, tab2, zmin, width, mean = graph_table(xyz, 6.0, -1.0, True, NB, 2)
    mask = np.full((h, w), 255, dtype=np.uint8)
    normals_stream(xyz, *args, *scratch[0], with_graph(tab2, zmin, width, mask))
    normals_stream(xyz, *args, *scratch[1], no_graph())
    rtable, rzmin, rwidth, rmean, rmask = _reference(xyz, 6.0, -1.0, True, 2)
    assert (zmin, width, mean) == (rzmin, rwidth, rmean)
    np.testing.assert_array_equal(table, rtable)
    np.testing.assert_array_equal(mask, rmask)
    np.testing.assert_array_equal(scratch[0][0], scratch[1][0])  # normals, NaN included
    np.testing.assert_array_equal(scratch[0][4], scratch[1][4])  # the degeneracy sample
