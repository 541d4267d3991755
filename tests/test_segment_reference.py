"""The compiled growing kernel against a plain-Python statement of planerel's variant of
Algorithm 1 (reversed angle phases and the seed test, as docs/segmentation.md states them; the
kernel receives its thresholds, so the same code runs the paper's order, which
tests/test_segment_paper.py checks against the paper's pseudo-code), and the fast paths around
it (plane construction, parameter cache).

The kernel is tuned for speed (label test first, no integer division in the base-normal
schedule, moments gathered while growing); the reference below is written for reading, so any
speed change that alters which pixel joins which region shows up here, label for label.
"""

import math
from collections import deque

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.segment import SegPlane, make_params, segment
from planerel.segment import _kernels as K
from planerel.segment._graph_kernels import grid_graph
from planerel.segment._scenes import staircase
from planerel.segment.normals import organized_normals

_DIRS = [(0, 1), (1, -1), (1, 0), (1, 1), (0, -1), (-1, 1), (-1, 0), (-1, -1)]


def _reference_grow(nrm, mask, min_nb, cos_init, cos_main, num_init, step, min_size):
    """planerel's growing on the image grid, as docs/segmentation.md states it: ``cos_init``
    while the region is small and for the seed test, ``cos_main`` after (float32 normals and
    running normal sums, float64 base normal, as the kernel keeps them)."""
    h, w, _ = nrm.shape
    f32 = np.float32
    nvalid = ~np.isnan(nrm.sum(axis=2))
    labels = np.where(nvalid & (K.POPCOUNT[mask] >= min_nb), -1, -2)
    seedable = np.ones((h, w), dtype=bool)

    def neighbours(v, u):
        m = int(mask[v, u])
        return [(v + dv, u + du) for k, (dv, du) in enumerate(_DIRS) if (m >> k) & 1]

    nreg = 0
    for v in range(h):
        for u in range(w):
            if labels[v, u] != -1 or not seedable[v, u]:
                continue
            n0 = nrm[v, u]
            if any(not nvalid[q] or f32(n0[0] * nrm[q][0] + n0[1] * nrm[q][1]
                                        + n0[2] * nrm[q][2]) < cos_init
                   for q in neighbours(v, u)):
                seedable[v, u] = False
                continue
            labels[v, u] = nreg
            members = [(v, u)]
            queue = deque(members)
            s = [f32(n0[0]), f32(n0[1]), f32(n0[2])]
            base = [float(x) for x in n0]
            count = 1
            thr = cos_init if num_init > 1 else cos_main
            while queue:
                for q in neighbours(*queue.popleft()):
                    if labels[q] != -1:
                        continue
                    nq = nrm[q]
                    if (float(nq[0]) * base[0] + float(nq[1]) * base[1]
                            + float(nq[2]) * base[2]) < thr:
                        continue
                    labels[q] = nreg
                    members.append(q)
                    queue.append(q)
                    s = [s[0] + nq[0], s[1] + nq[1], s[2] + nq[2]]
                    count += 1
                    if count <= num_init or count % step == 0:
                        inv = 1.0 / float(np.sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]))
                        base = [float(x) * inv for x in s]
                        if count >= num_init:
                            thr = cos_main
            if count >= min_size:
                nreg += 1
            else:
                for q in members:
                    labels[q] = -1
                    seedable[q] = False
    return labels, nreg


def _graph(xyz):
    h, w, _ = xyz.shape
    mask = np.empty((h, w), dtype=np.uint8)
    grid_graph(xyz, 6.0, -1.0, True, 24, 1, mask)
    return mask


def _stairs():
    cloud, *_ = staircase(80, 60, steps=4, seed=3)
    xyz = np.ascontiguousarray(cloud.xyz)
    return xyz, organized_normals(xyz).astype(np.float32), _graph(xyz)


def _wavy():
    """A curved, noisy surface with holes: the base normal drifts while a region grows, so the
    refresh schedule and the visiting order decide which pixels join."""
    rng = np.random.default_rng(0)
    v, u = np.mgrid[0:60, 0:80].astype(float)
    x, y = (u - 40) * 0.02, (v - 30) * 0.02
    z = 2.0 + 0.25 * np.sin(2.5 * x) + 0.15 * np.cos(3 * y) + rng.normal(0, 0.002, x.shape)
    xyz = np.ascontiguousarray(np.stack([x, y, z], axis=-1))
    xyz[rng.random(x.shape) < 0.03] = np.nan
    nrm = organized_normals(xyz, smooth=1, radius=1, reference_depth=None)
    return xyz, nrm.astype(np.float32), _graph(xyz)


@pytest.fixture(scope="module", params=["stairs", "wavy"])
def small_scene(request):
    return _stairs() if request.param == "stairs" else _wavy()


@pytest.mark.parametrize("num_init,step,theta", [(16, 8, 15.0), (5, 8, 15.0), (8, 8, 12.0),
                                                  (1, 3, 15.0), (7, 3, 20.0)])
def test_kernel_matches_the_reference_algorithm(small_scene, num_init, step, theta):
    xyz, nrm, mask = small_scene
    h, w, _ = xyz.shape
    n = h * w
    cos_main = math.cos(math.radians(theta))
    cos_init = math.cos(math.radians(theta * 0.5))
    min_size = 20
    want, want_n = _reference_grow(nrm, mask, 4, cos_init, cos_main, num_init, step, min_size)
    padded, labels = K.padded_labels(h, w)
    got_n = K.region_grow_grid_ws(nrm.reshape(-1, 3), np.empty(n, np.bool_), mask.reshape(-1), w,
                                  4, cos_init, cos_main, cos_init, num_init, step, min_size,
                                  padded, np.empty(n, np.int32), np.empty(n, np.bool_))
    assert got_n == want_n >= 3
    np.testing.assert_array_equal(labels.reshape(h, w), want)
    # the padding is read, never written
    assert (padded[:w + 1] == -2).all() and (padded[w + 1 + n:] == -2).all()


def test_planes_from_fits_validate_once_and_are_read_only():
    nrm = np.array([[0.0, 0.0, -1.0], [0.6, 0.0, -0.8]])
    planes = SegPlane.from_fits(nrm, [1.0, 2.0], np.array([10, 20]), [[0, 0, 1], [1, 0, 2]],
                                [0.001, 0.002])
    assert [p.id for p in planes] == [0, 1]
    assert planes[1].n_points == 20 and isinstance(planes[1].n_points, int)
    assert planes[1].offset == 2.0 and planes[0].rms == 0.001
    with pytest.raises(ValueError):
        planes[0].normal[0] = 1.0  # read-only, as the constructor makes them
    nrm[0, 2] = -1.0  # the input may change afterwards
    assert planes[0].normal[2] == -1.0
    assert SegPlane.from_fits(np.zeros((0, 3)), [], [], np.zeros((0, 3)), []) == ()
    with pytest.raises(InputError, match="unit length"):
        SegPlane.from_fits([[0, 0, -2.0]], [1.0], [5], [[0, 0, 1]], [0.0])
    with pytest.raises(InputError, match="n_points"):
        SegPlane.from_fits([[0, 0, -1.0]], [1.0], [0], [[0, 0, 1]], [0.0])
    with pytest.raises(InputError, match="differ in length"):
        SegPlane.from_fits([[0, 0, -1.0]], [1.0, 2.0], [5], [[0, 0, 1]], [0.0])


def test_parameter_cache_shares_validated_instances_only_for_equal_values():
    a = make_params("regiongrow", theta=12, refine=False)
    assert make_params("regiongrow", refine=False, theta=12) is a
    assert make_params("regiongrow", theta=12.5, refine=False) is not a
    assert make_params("regiongrow", theta=12.0, refine=False).theta == 12.0
    # equal but differently typed values are validated on their own
    assert make_params("sp", threshold=1) is not make_params("sp", threshold=1.0)
    for _ in range(2):  # a failure is not cached
        with pytest.raises(InputError, match="theta"):
            make_params("regiongrow", theta=95)
    with pytest.raises(InputError):
        make_params("regiongrow", theta=[15])  # unhashable: validated without the cache


def test_segmentation_unchanged_by_the_cache():
    cloud, *_ = staircase(80, 60, steps=4, seed=3)
    first = segment(cloud, refine=False, split=False)
    again = segment(cloud, refine=False, split=False)
    np.testing.assert_array_equal(first.labels, again.labels)
    assert first.params is again.params


def test_residual_kernel_matches_a_numpy_statement():
    from planerel.segment._split_kernels import residual_stats_grid
    from planerel.segment.split import SplitParams, expected_sigma

    rng = np.random.default_rng(1)
    h, w, n = 30, 40, 3
    X = np.stack([rng.uniform(-1, 1, (h, w)), rng.uniform(-1, 1, (h, w)),
                  rng.uniform(1, 4, (h, w))], axis=-1)
    L = rng.integers(-1, n, (h, w)).astype(np.int32)
    L[:, :20] = 0  # a block where second differences exist
    pn = rng.normal(size=(n, 3))
    pn /= np.linalg.norm(pn, axis=1, keepdims=True)
    po = rng.uniform(0.5, 2, n)
    p = SplitParams()
    q = p.disparity_step / (p.focal_px * p.baseline)
    rms, exp_rms, local = residual_stats_grid(X, L, pn, po, n, p.noise, q, p.depth_unit, True)
    on = L >= 0
    lab, P = L[on], X[on]
    d = np.einsum("ij,ij->i", P, pn[lab]) + po[lab]
    c = np.bincount(lab, minlength=n)
    np.testing.assert_allclose(rms, np.sqrt(np.bincount(lab, d * d, minlength=n) / c), rtol=1e-12)
    sig = expected_sigma(P, pn[lab], p)
    np.testing.assert_allclose(exp_rms, np.sqrt(np.bincount(lab, sig * sig, minlength=n) / c),
                               rtol=1e-12)
    D = np.zeros((h, w))
    D[on] = d
    dd = D[:, :-2] - 2 * D[:, 1:-1] + D[:, 2:]
    ok = (L[:, 1:-1] == 0) & (L[:, :-2] == 0) & (L[:, 2:] == 0)
    ddc = D[:-2] - 2 * D[1:-1] + D[2:]
    okc = (L[1:-1] == 0) & (L[:-2] == 0) & (L[2:] == 0)
    want0 = np.sqrt(((dd[ok] ** 2).sum() + (ddc[okc] ** 2).sum()) / (ok.sum() + okc.sum()) / 6)
    assert local[0] == pytest.approx(want0, rel=1e-12)
    assert np.isnan(residual_stats_grid(X, L, pn, po, n, p.noise, q, p.depth_unit, False)[2]).all()


def test_completion_queue_grows_without_changing_the_result():
    xyz, nrm, mask = _stairs()
    h, w, _ = xyz.shape
    n = h * w
    pts = xyz.reshape(-1, 3)
    cos_main, cos_init = math.cos(math.radians(15)), math.cos(math.radians(7.5))
    padded, labels = K.padded_labels(h, w)
    nreg = K.region_grow_grid_ws(nrm.reshape(-1, 3), np.empty(n, np.bool_), mask.reshape(-1), w, 4,
                                 cos_init, cos_main, cos_init, 16, 8, 20, padded,
                                 np.empty(n, np.int32), np.empty(n, np.bool_))
    sums = np.full((n // 20 + 2, 10), np.nan)  # rows past nreg: left alone by region_sums_into
    ref = np.full((n // 20 + 2, 3), np.nan)
    K.region_sums_into(pts, labels, nreg, sums, ref, False)
    np.testing.assert_array_equal(np.column_stack(K.region_sums(pts, labels, nreg)),
                                  np.column_stack([sums[:nreg], ref[:nreg]]))
    assert np.isnan(sums[nreg:]).all() and np.isnan(ref[nreg:]).all()
    pn, po, _, _, prms = K.planes_from_sums(sums, ref, nreg)
    planes = np.ascontiguousarray(np.column_stack([pn, po]))
    thr = 3.0 * np.maximum(prms, 1e-6)
    out = []
    for cap in (1, n):  # a one-entry queue must grow many times
        lab, sm = labels.copy(), sums.copy()
        added, _ = K.refine_grid_ws(pts, mask.reshape(-1), w, lab, planes, thr, 6,
                                    np.empty(n, np.uint8), np.empty(n, np.uint8),
                                    np.empty((cap, 3), np.int32), sm, ref)
        out.append((added, lab, sm))
    assert out[0][0] == out[1][0] > 0
    np.testing.assert_array_equal(out[0][1], out[1][1])
    np.testing.assert_array_equal(out[0][2], out[1][2])
    # the moments kept up to date while completing are those of the final labels
    lab = out[0][1]
    np.testing.assert_array_equal(out[0][2][:nreg, 0], np.bincount(lab[lab >= 0], minlength=nreg))
