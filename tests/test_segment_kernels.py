"""Small kernel pieces against their plain statements: the region moments (and each region's
reference point) and the prefetch intrinsic the hot loops use."""

import numpy as np
import pytest
from numba import njit

from planerel.segment import _kernels as K
from planerel.segment._intrinsics import prefetch


@pytest.mark.parametrize("seed", range(3))
def test_region_moments_match_the_definition(seed):
    rng = np.random.default_rng(seed)
    n_pix, nreg = 4000, 7
    pts = rng.normal(size=(n_pix, 3)) + 5.0
    # runs of labels, re-entered in row-major order, with unassigned (-1) and "cannot join" (-2)
    labels = np.repeat(rng.integers(-2, nreg, size=n_pix // 8), 8).astype(np.int32)
    labels[labels == 3] = -1  # one region without points: its row stays zero
    sums = np.full((nreg + 2, 10), np.nan)
    ref = np.full((nreg + 2, 3), np.nan)
    lab = labels.copy()
    K.region_sums_into(pts, lab, nreg, sums, ref, True)
    assert (lab >= -1).all() and np.array_equal(lab[labels >= -1], labels[labels >= -1])
    assert np.isnan(sums[nreg:]).all() and np.isnan(ref[nreg:]).all()
    for r in range(nreg):
        on = np.flatnonzero(labels == r)
        if not len(on):
            np.testing.assert_array_equal(sums[r], 0.0)
            continue
        np.testing.assert_array_equal(ref[r], pts[on[0]])  # the first point in row-major order
        d = pts[on] - pts[on[0]]
        x, y, z = d.T
        want = [len(on), x.sum(), y.sum(), z.sum(), (x * x).sum(), (x * y).sum(), (x * z).sum(),
                (y * y).sum(), (y * z).sum(), (z * z).sum()]
        np.testing.assert_allclose(sums[r], want, rtol=1e-12, atol=1e-9)


@njit(cache=False)
def _sum_with_prefetch(a, idx):
    s = 0.0
    flat = a.reshape(-1)
    for i in range(flat.shape[0]):
        prefetch(a, i + 64)  # past the end near the last elements: harmless
        prefetch(a, idx)
        s += flat[i]
    return s


@pytest.mark.parametrize("dtype", [np.float32, np.float64, np.int32, np.uint8])
@pytest.mark.parametrize("idx", [np.int64(5), np.int32(-100000), np.uint64(3), np.uint64(2 ** 40)])
def test_prefetch_changes_nothing(dtype, idx):
    a = np.arange(60, dtype=dtype).reshape(20, 3)
    assert _sum_with_prefetch(a, idx) == float(a.astype(np.float64).sum())


def test_prefetch_rejects_what_is_not_an_array():
    @njit(cache=False)
    def bad(x):
        prefetch(x, 1)

    with pytest.raises(Exception, match="prefetch"):
        bad(1.0)


def test_diff_row_reads_stay_in_the_ring_for_invalid_points():
    # an invalid pixel (row-run start -1) keeps stale run ends and radius in the rings; the
    # differences must not load outside the smoothed-point ring for it (a read beyond it
    # crashed a process once the memory after the ring was unmapped)
    import numpy as np

    from planerel.segment._normal_kernels import _diff_row

    W, RS = 8, 4
    rsf = np.arange(RS * W * 3, dtype=np.float32)
    rs = np.full(W, 0, dtype=np.int16)
    re = np.full(W, W - 1, dtype=np.int16)
    cs = np.zeros(W, dtype=np.int16)
    ce = np.full(W, 3, dtype=np.int16)
    kr = np.ones(W, dtype=np.int16)
    rs[3], re[3], kr[3] = -1, 30000, 30000  # invalid, stale values
    dif = np.zeros((7, W), dtype=np.float32)
    _diff_row.py_func(rsf, rs, re, cs, ce, kr, 1, RS - 1, dif)  # IndexError before the fix
    assert dif[6, 3] == 0 and dif[6, 4] == 1
    # a valid pixel's horizontal difference: columns u+1 and u-1 of the row, x component
    assert dif[0, 4] == rsf[3 * W + 3 * 5] - rsf[3 * W + 3 * 3]
