"""The box profile's row prefetch (speed22y): the next row of the face's box asked for while
one is read.  A prefetch changes when data arrives, never a value: the kernel's answers on
C-ordered, Fortran-ordered and strided inputs, and on boxes at the image's last rows and
columns, are those of a plain numpy computation of the same order statistics."""

from __future__ import annotations

import numpy as np


def _profile_numpy(lab, xyz, label, r0, c0, r1, c1, k, up, along):
    """box_profile by numpy: the box's every k-th pixel of ``label`` with finite coordinates,
    np.percentile 2 and 98 of the plain-order dot products."""
    rows, cols = np.meshgrid(np.arange(r0, r1, k), np.arange(c0, c1, k), indexing="ij")
    rows, cols = rows.ravel(), cols.ravel()
    p = xyz[rows, cols]
    ok = (lab[rows, cols] == label) & np.isfinite(p).all(axis=1)
    p = p[ok]
    if len(p) < 3:
        return np.full(4, np.nan)
    hu = p[:, 0] * up[0] + p[:, 1] * up[1] + p[:, 2] * up[2]
    ha = p[:, 0] * along[0] + p[:, 1] * along[1] + p[:, 2] * along[2]
    return np.array([*np.percentile(hu, [2, 98]), *np.percentile(ha, [2, 98])])


def test_box_profile_with_row_prefetch_on_any_layout_and_at_the_edges():
    from planerel.features._relation_kernels import box_profile

    rng = np.random.default_rng(2222)
    seen = 0
    for _ in range(150):
        H, W = (int(v) for v in rng.integers(2, 60, 2))
        lab = rng.integers(-1, 3, (H, W)).astype(np.int32)
        lab[rng.random((H, W)) < 0.5] = 1
        xyz = rng.normal(size=(H, W, 3))
        xyz[rng.random((H, W)) < 0.05] = np.nan
        xyz[rng.random((H, W)) < 0.01, 0] = np.inf
        # boxes reaching the last row and column (the prefetch's row past the box's end is
        # past the image too), and inner ones
        r0, c0 = int(rng.integers(0, H)), int(rng.integers(0, W))
        r1 = H if rng.random() < 0.5 else int(rng.integers(r0, H + 1))
        c1 = W if rng.random() < 0.5 else int(rng.integers(c0, W + 1))
        k = int(rng.integers(1, 4))
        up = rng.normal(size=3)
        up /= np.linalg.norm(up)
        along = rng.normal(size=3)
        want = _profile_numpy(lab, xyz, 1, r0, c0, r1, c1, k, up, along)
        strided = (np.pad(lab, ((0, 0), (0, 3)))[:, :W],
                   np.pad(xyz, ((0, 0), (0, 2), (0, 1)))[:, :W, :3])
        for L, X in ((lab, xyz), (np.asfortranarray(lab), np.asfortranarray(xyz)), strided):
            got = box_profile(L, X, 1, r0, c0, r1, c1, k, up, along)
            assert np.array_equal(got, want, equal_nan=True)
        seen += int(np.isfinite(want).all())
    assert seen > 60


def _same(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def test_outline_kernels_with_prefetch_ahead_answer_as_their_references():
    """The touch test, the edge sums and truncated_at ask for the data of the boundary pixel
    64 places on: on whole synthetic scenes (thousands of boundary pixels, some on the last
    rows, whose row below is past the image) the same answers as the kernels without it
    (segment's touch_pairs, the dense edge_sums, truncation_counts), bit for bit."""
    from planerel.features._relation_kernels import (
        _AHEAD,
        edge_sums,
        edge_sums_pairs_with_tiles,
        touch_pairs_with_tiles,
    )
    from planerel.features._truncated_kernels import truncated_at, truncation_counts
    from planerel.features.planes import _boundary_pixels, _boundary_tiles, measure_planes
    from planerel.segment._label_kernels import touch_pairs
    from planerel.synth.generator import generate_scene

    touching = sums = 0
    for kind, seed in (("box", 3), ("stairs", 4), ("ramp", 5)):
        sc = generate_scene(kind, seed=seed, subsample=1)
        planes = measure_planes(sc.cloud, np.asarray(sc.gt_labels))
        lab = planes.labels
        xyz = np.ascontiguousarray(sc.cloud.xyz, dtype=np.float64)
        brow, bcol = _boundary_pixels(lab)
        H = lab.shape[0]
        assert len(brow) > 20 * _AHEAD and (brow >= H - 2).any()
        n = int(lab.max()) + 1
        known = np.ones(n, bool)
        got = touch_pairs_with_tiles(xyz, lab, brow, bcol, _boundary_tiles(lab), 2, 0.02, 0.05,
                                     known)
        assert _same(got, touch_pairs(xyz, lab, brow, bcol, 2, 0.02, 0.05, known))
        touching += int(got.sum())
        partner = np.ones((n, n), bool)
        got = edge_sums_pairs_with_tiles(lab, xyz, brow, bcol, _boundary_tiles(lab), partner, 2,
                                         0.03)
        want = edge_sums(lab, xyz, brow, bcol, known, 2, 0.03, n)
        for g, w in zip(got, want, strict=True):
            assert _same(g, w)
        sums += int(got[0].sum())
        ints = np.ascontiguousarray(lab, dtype=np.int64)
        for share in (0.0, 0.1, 0.5):
            cut, present = truncated_at(ints, xyz, brow, bcol, 0.05, 2, 1, share, n)
            n_out, n_hid, at_edge, present_img = truncation_counts(ints, xyz, 0.05, 2, 1, n)
            want = at_edge | ((n_out > 0) & (n_hid >= share * np.maximum(n_out, 1)))
            assert _same(present, present_img) and _same(cut & present, want & present_img)
    assert touching > 10 and sums > 1000
