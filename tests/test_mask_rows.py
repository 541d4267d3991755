"""The cluster-mask kernels read only the rows the caller says the mask holds (the twentieth
speed pass): ``touching_counts``, ``count_outside`` and ``mask_values`` given a mask's row
bounds count what they counted over the whole image, and ``_clusters`` gives each mask's true
row bounds."""

from __future__ import annotations

import numpy as np

from planerel.features.curved import CurvedParams, _clusters, _span_union
from planerel.io.cloud import Cloud


def _rows_of(m):
    r = np.nonzero(m.any(axis=1))[0]
    return int(r[0]), int(r[-1]) + 1


def _random_case(rng):
    H, W = int(rng.integers(1, 70)), int(rng.integers(1, 90))
    mask = np.zeros((H, W), bool)
    for _ in range(int(rng.integers(1, 4))):  # a few blobs on a few rows
        r0, c0 = int(rng.integers(0, H)), int(rng.integers(0, W))
        mask[r0:r0 + int(rng.integers(1, 8)), c0:c0 + int(rng.integers(1, 12))] = True
    if rng.random() < 0.15:
        mask[[0, H - 1], int(rng.integers(0, W))] = True  # the first and the last row
    lab = rng.integers(-2, 7, (H, W)).astype(rng.choice([np.int32, np.int64]))
    xyz = rng.normal(size=(H, W, 3)) * 0.02 + [0, 0, 1.5]
    xyz[rng.random((H, W)) < 0.1] = np.nan
    return mask, lab, xyz


def test_kernels_with_row_bounds_match_the_whole_image_scan():
    """On 600 random sparse masks: the counts and values with the mask's exact row bounds, and
    with looser bounds, equal the whole-image scan (the code before) bit for bit; bounds one
    row too tight lose the mask's edge rows (the test can tell)."""
    from planerel.features._curved_kernels import count_outside, mask_values, touching_counts

    rng = np.random.default_rng(2220)
    tight = 0
    for _ in range(600):
        mask, lab, xyz = _random_case(rng)
        H = mask.shape[0]
        y0, y1 = _rows_of(mask)
        edge = float(rng.choice([0.005, 0.02, 0.05]))
        nlab = int(lab.max()) + 1
        g = sorted({int(x) for x in rng.integers(0, 7, int(rng.integers(0, 4)))})
        member = np.zeros(max([-1, *g]) + 1, bool)
        member[g] = True
        skip = -(1 << 40) if g else -2
        want_t = touching_counts(mask, lab, xyz, edge, nlab)
        want_o = count_outside(mask, lab, member, skip)
        want_v = mask_values(mask, lab)
        assert np.array_equal(want_v, lab[mask]) and want_v.dtype == lab.dtype
        assert want_o == int((mask & ~np.isin(lab, g if g else [-2])).sum())
        a, b = int(rng.integers(0, y0 + 1)), int(rng.integers(y1, H + 1))
        for lo, hi in ((y0, y1), (a, b), (0, H), (0, -1)):
            got_t = touching_counts(mask, lab, xyz, edge, nlab, lo, hi)
            assert got_t.dtype == np.int64 and np.array_equal(got_t, want_t)
            assert count_outside(mask, lab, member, skip, lo, hi) == want_o
            got_v = mask_values(mask, lab, lo, hi)
            assert got_v.dtype == want_v.dtype and np.array_equal(got_v, want_v)
        if y1 - y0 >= 2:
            # a row short at either end: the first and the last row's pixels go
            n_first, n_last = int(mask[y0].sum()), int(mask[y1 - 1].sum())
            assert len(mask_values(mask, lab, y0 + 1, y1)) == len(want_v) - n_first
            assert len(mask_values(mask, lab, y0, y1 - 1)) == len(want_v) - n_last
            tight += 1
    assert tight > 200


def test_span_union():
    assert _span_union(None, (3, 5)) == (3, 5)
    assert _span_union((3, 5), None) == (3, 5)
    assert _span_union((3, 5), (1, 4)) == (1, 5)
    assert _span_union((3, 5), (6, 9)) == (3, 9)


def _cloud(f=500.0, z=1.0, size=(200, 200)):
    h, w = size
    v, u = np.mgrid[0:h, 0:w].astype(float)
    cx, cy = (w - 1) / 2, (h - 1) / 2
    return np.stack([(u - cx) * z / f, (v - cy) * z / f, np.full((h, w), z)], axis=2)


def test_clusters_give_each_masks_true_row_bounds():
    """``_clusters(..., bounds=[])`` appends each mask's first row and one past its last, with
    and without the regrowth and the opening, and the masks are those given without it."""
    xyz = _cloud()
    xyz[60:64, 25:45] = np.nan  # invalid pixels across a patch
    xyz[20:50, 35:50, 2] += 0.3  # a depth jump
    cloud = Cloud(xyz)
    labels = np.zeros((200, 200), np.int64)  # 0: support
    labels[20:50, 20:50] = -1
    labels[55:90, 20:50] = -1
    labels[100:140, 150:180] = -1
    labels[0:16, 176:200] = -1  # the first rows
    labels[185:200, 0:30] = -1  # the last rows
    n = 0
    for cp in (CurvedParams(min_area=0.001), CurvedParams(min_area=0.001, regrow_px=0),
               CurvedParams(min_area=0.001, open_px=0)):
        bounds: list = []
        masks, kept = _clusters(cloud, labels, [], (0,), cp, bounds=bounds)
        want, want_kept = _clusters(cloud, labels, [], (0,), cp)
        assert len(masks) == len(want) == len(bounds) and kept == want_kept
        for m, w, b in zip(masks, want, bounds, strict=True):
            assert np.array_equal(m, w)
            assert b == _rows_of(m)
            n += 1
        assert any(b[0] == 0 for b in bounds)
        assert any(b[1] == 200 for b in bounds)
    assert n >= 12
