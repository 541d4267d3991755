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
