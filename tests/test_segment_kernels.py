"""Small kernel pieces against their plain statements: the region moments (and each region's
reference point) and the prefetch intrinsic the hot loops use."""

import numpy as np
import pytest
from numba import njit
from numba.core import config as numba_config

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


@pytest.mark.skipif(numba_config.DISABLE_JIT, reason="NUMBA_DISABLE_JIT: prefetch is a no-op "
                    "plain-Python stand-in, numba's typing (what rejects it) does not run")
def test_prefetch_rejects_what_is_not_an_array():
    @njit(cache=False)
    def bad(x):
        prefetch(x, 1)

    with pytest.raises(Exception, match="prefetch"):
        bad(1.0)


def _plain(kernel):
    """The kernel's plain-Python function (the function itself when numba's JIT is disabled,
    as in `make coverage`'s second run): Python checks every index."""
    return getattr(kernel, "py_func", kernel)


def test_diff_row_reads_stay_in_the_ring_for_invalid_points():
    # an invalid pixel (row-run start -1) keeps stale run ends and radius in the rings; the
    # differences must not load outside the smoothed-point ring for it (a read beyond it
    # crashed a process once the memory after the ring was unmapped)
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
    _plain(_diff_row)(rsf, rs, re, cs, ce, kr, 1, RS - 1, dif)  # IndexError before e06532f
    assert dif[6, 3] == 0 and dif[6, 4] == 1
    # a valid pixel's horizontal difference: columns u+1 and u-1 of the row, x component
    assert dif[0, 4] == rsf[3 * W + 3 * 5] - rsf[3 * W + 3 * 3]


@pytest.mark.parametrize("stale", [(-1, -1, 5), (-1, 7, -32768), (-1, -1, 32767)])
def test_diff_row_reads_only_written_rows_for_invalid_points(stale):
    # stage B writes ring rows c - rmax .. c + rmax; an invalid pixel's stale column run and
    # radius (cs = ce = -1 as stage A/B leave them, kr never written) pointed at row -1 & MS,
    # not written for this row: NaN here (garbage in the kernel's np.empty ring)
    from planerel.segment._normal_kernels import _diff_row

    W, RS, c, rmax = 6, 8, 3, 2
    rsf = np.full((RS, W, 3), np.nan, dtype=np.float32)
    rng = np.random.default_rng(0)
    rsf[c - rmax:c + rmax + 1] = rng.normal(size=(2 * rmax + 1, W, 3))
    ce_s, re_s, kr_s = stale
    rs = np.zeros(W, np.int16)
    re = np.full(W, W - 1, np.int16)
    cs = np.full(W, c - rmax, np.int16)
    ce = np.full(W, c + rmax, np.int16)
    kr = np.full(W, rmax, np.int16)
    rs[2], re[2], cs[2], ce[2], kr[2] = -1, re_s, -1, ce_s, kr_s
    rsf[c, 2] = 0.0  # stage B's zeros for the invalid pixel
    dif = np.full((7, W), np.nan, dtype=np.float32)
    _plain(_diff_row)(rsf.reshape(-1), rs, re, cs, ce, kr, c, RS - 1, dif)
    assert np.isfinite(dif).all()
    assert dif[6, 2] == 0 and (dif[6, [0, 1, 3, 4, 5]] == 1).all()
    # valid pixels, by the definition: rows c -+ rmax of their column, columns u -+ rmax
    # clipped to the row [0, W - 1]
    for u in (0, 1, 3, 4, 5):
        np.testing.assert_array_equal(dif[3:6, u], rsf[c + rmax, u] - rsf[c - rmax, u])
        np.testing.assert_array_equal(dif[0:3, u], rsf[c, min(u + rmax, W - 1)]
                                      - rsf[c, max(u - rmax, 0)])


def test_smooth_row_writes_every_column():
    # stage C reads an invalid pixel's own smoothed point: stage B must write it (zeros)
    from planerel.segment._normal_kernels import _smooth_row

    W, RC, b = 5, 4, 1
    rcf = np.zeros((RC, W, 4))
    rcf[:, :, 3] = np.arange(RC)[:, None]  # counts: one point per row
    rcf[:, :, :3] = 2.0 * np.arange(RC)[:, None, None]  # each point (2, 2, 2)
    cs = np.array([0, -1, 0, -1, 0], np.int16)
    ce = np.array([2, -1, 2, -1, 2], np.int16)
    ks = np.ones(W, np.int16)
    sbf = np.full(3 * W, np.nan, dtype=np.float32)
    _plain(_smooth_row)(rcf.reshape(-1), cs, ce, ks, b, RC - 1, sbf)
    got = sbf.reshape(W, 3)
    np.testing.assert_array_equal(got[[1, 3]], 0.0)
    np.testing.assert_array_equal(got[[0, 2, 4]], 2.0)  # mean of rows 0..2 of (2, 2, 2)
