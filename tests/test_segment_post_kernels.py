"""The post-processing kernels against the numpy / scipy statements they replaced.

Each kernel must give exactly what the plain statement gives (same counts, same component
numbering by first pixel, same assignments), so the split and merge results do not depend on
which one runs."""

import numpy as np
import pytest
from scipy import ndimage

from planerel.segment import _post_kernels as PK
from planerel.segment.split import SplitParams

EIGHT = np.ones((3, 3), dtype=bool)


def _random_labels(h, w, n, seed, holes=0.2):
    rng = np.random.default_rng(seed)
    # blobs: a coarse random label image upsampled, with scattered unassigned pixels
    coarse = rng.integers(-1, n, size=(h // 4 + 1, w // 4 + 1))
    lab = np.kron(coarse, np.ones((4, 4), dtype=np.int64))[:h, :w].astype(np.int32)
    lab[rng.random((h, w)) < holes] = -1
    valid = rng.random((h, w)) > 0.1
    lab[~valid] = -1
    return lab, valid


@pytest.mark.parametrize("seed", range(4))
def test_label_counts_and_checks(seed):
    lab, valid = _random_labels(37, 53, 6, seed)
    cnt, status = PK.label_counts(lab.reshape(-1), valid.reshape(-1), 6)
    assert status == 0
    np.testing.assert_array_equal(cnt, np.bincount(lab[lab >= 0], minlength=6))
    bad = lab.copy()
    bad[3, 4] = 6
    assert PK.label_counts(bad.reshape(-1), valid.reshape(-1), 6)[1] == 1
    bad[3, 4] = -2
    assert PK.label_counts(bad.reshape(-1), valid.reshape(-1), 6)[1] == 1
    inval = valid.copy()
    inval[lab >= 0] = False
    assert PK.label_counts(lab.reshape(-1), inval.reshape(-1), 6)[1] == (2 if (lab >= 0).any() else 0)


def _scipy_patches(lab, valid, min_size):
    comp, nc = ndimage.label(valid & (lab < 0), structure=EIGHT)
    flat = comp.reshape(-1)
    out = []
    for c in range(1, nc + 1):
        pix = np.flatnonzero(flat == c)
        if len(pix) >= min_size:
            out.append(pix)
    return out


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("min_size", [1, 5, 40])
def test_free_patches_match_scipy_labelling(seed, min_size):
    lab, valid = _random_labels(41, 67, 4, seed, holes=0.35)
    order, starts = PK.free_patches(lab.reshape(-1), valid.reshape(-1), 67, min_size)
    got = [order[starts[i]:starts[i + 1]] for i in range(len(starts) - 1)]
    want = _scipy_patches(lab, valid, min_size)
    assert len(got) == len(want)
    for g, wnt in zip(got, want, strict=True):
        np.testing.assert_array_equal(g, wnt)


def _scipy_pieces(pix, w, part, k, min_size):
    """split._pieces as it was written with scipy (per part, components on the bounding box)."""
    rr, cc = np.divmod(pix, w)
    rr, cc = rr - rr.min(), cc - cc.min()
    shape = (rr.max() + 1, cc.max() + 1)
    piece = np.full(len(part), -1, dtype=np.int64)
    planes = []
    for j in range(k):
        on = part == j
        if not on.any():
            continue
        mask = np.zeros(shape, dtype=bool)
        mask[rr[on], cc[on]] = True
        comp, nc = ndimage.label(mask, structure=EIGHT)
        cl = comp[rr[on], cc[on]]
        sizes = np.bincount(cl, minlength=nc + 1)
        big = np.flatnonzero(sizes >= min_size)
        big = big[big > 0]
        lut = np.full(nc + 1, -2, dtype=np.int64)
        lut[big] = len(planes) + np.arange(len(big))
        planes.extend([j] * len(big))
        piece[on] = lut[cl]
    return piece, np.array(planes, dtype=np.int64)


def _region(seed, h=45, w=60):
    rng = np.random.default_rng(seed)
    inside = rng.random((h, w)) < 0.8
    pix = np.flatnonzero(inside)
    coarse = rng.integers(-1, 3, size=(h // 5 + 1, w // 5 + 1))
    part = np.kron(coarse, np.ones((5, 5), dtype=np.int64))[:h, :w].reshape(-1)[pix]
    return pix, w, part, h * w


@pytest.mark.parametrize("seed", range(5))
@pytest.mark.parametrize("min_size", [1, 8, 30])
def test_part_pieces_match_scipy(seed, min_size):
    pix, w, part, n = _region(seed)
    piece, planes = PK.part_pieces(pix, w, part, 3, min_size)
    want_piece, want_planes = _scipy_pieces(pix, w, part, 3, min_size)
    np.testing.assert_array_equal(piece, want_piece)
    np.testing.assert_array_equal(planes, want_planes)


def _numpy_absorb(pix, w, piece, piece_plane, cost, sig):
    """split._absorb as it was written with scipy."""
    rr, cc = np.divmod(pix, w)
    rr, cc = rr - rr.min(), cc - cc.min()
    hh, ww = rr.max() + 1, cc.max() + 1
    piece = piece.copy()
    small = np.flatnonzero(piece == -2)
    cs = cost[small][:, piece_plane]
    kept = np.full((hh + 2, ww + 2), -1, dtype=np.int64)
    ok = piece >= 0
    kept[rr[ok] + 1, cc[ok] + 1] = piece[ok]
    rs, cs_ = rr[small], cc[small]
    r0, c0 = rs.min(), cs_.min()
    smallmask = np.zeros((rs.max() - r0 + 1, cs_.max() - c0 + 1), dtype=bool)
    smallmask[rs - r0, cs_ - c0] = True
    comp, nc = ndimage.label(smallmask, structure=EIGHT)
    comp_of = comp[rs - r0, cs_ - c0]
    adj = np.zeros((nc + 1, len(piece_plane)), dtype=bool)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            if dy or dx:
                nb = kept[rs + 1 + dy, cs_ + 1 + dx]
                mk = nb >= 0
                adj[comp_of[mk], nb[mk]] = True
    cs = np.where(adj[comp_of], cs, np.inf)
    best = np.argmin(cs, axis=1)
    cb = cs[np.arange(len(small)), best]
    piece[small] = np.where(cb <= sig, best, -1)
    return piece


@pytest.mark.parametrize("seed", range(5))
def test_absorb_small_matches_the_numpy_statement(seed):
    pix, w, part, n = _region(seed)
    cellmap = np.full(n, -1, dtype=np.int32)
    piece, planes = PK.part_pieces(pix, w, part, 3, 12)
    assert (piece == -2).any() and len(planes) >= 2
    rng = np.random.default_rng(seed)
    cost = rng.random((len(pix), 3)) * 6.0
    got = PK.absorb_small(pix, w, piece, planes, cost, 3.0, cellmap)
    np.testing.assert_array_equal(got, _numpy_absorb(pix, w, piece, planes, cost, 3.0))
    assert (cellmap == -1).all()


def test_assignment_and_depth_scales_match_numpy():
    rng = np.random.default_rng(0)
    P = rng.normal(size=(500, 3)) + [0.0, 0.0, 3.0]
    p = SplitParams()
    q = p.disparity_step / (p.focal_px * p.baseline)
    zs = PK.depth_scales(np.ascontiguousarray(P[:, 2]), 1.3, p.noise, q, p.depth_unit)
    np.testing.assert_array_equal(zs, P[:, 2] / (1.3 * np.sqrt(p.depth_sigma2(P[:, 2]))))
    planes = np.array([[0.0, 0.0, -1.0, 3.0], [0.6, 0.0, -0.8, 2.0], [0.0, 0.6, -0.8, 2.5]])
    cost, part = PK.assign_parts(P, zs, planes, 3.0)
    dn = P @ planes[:, :3].T
    want = np.abs(dn + planes[:, 3]) * zs[:, None] / np.maximum(np.abs(dn), 1e-12)
    np.testing.assert_allclose(cost, want, rtol=1e-12)
    best = np.argmin(cost, axis=1)
    np.testing.assert_array_equal(part, np.where(cost[np.arange(500), best] <= 3.0, best, -1))


def test_merge_stats_match_the_bincount_statement():
    rng = np.random.default_rng(3)
    X = rng.normal(size=(800, 3)) + [0.0, 0.0, 2.5]
    L = rng.integers(-1, 5, size=800).astype(np.int32)
    pn = rng.normal(size=(5, 3))
    pn /= np.linalg.norm(pn, axis=1, keepdims=True)
    p = SplitParams()
    q = p.disparity_step / (p.focal_px * p.baseline)
    cnt, s1, s2, sv = PK.merge_stats(X, L, pn, 5, p.noise, q, p.depth_unit, 1.7 ** 2)
    on = L >= 0
    P, lab = X[on], L[on]
    np.testing.assert_array_equal(cnt, np.bincount(lab, minlength=5))
    for k in range(3):
        np.testing.assert_array_equal(s1[:, k], np.bincount(lab, P[:, k], minlength=5))
        for j in range(3):
            np.testing.assert_array_equal(s2[:, k, j], np.bincount(lab, P[:, k] * P[:, j], minlength=5))
    z = P[:, 2]
    proj = np.abs(np.einsum("ij,ij->i", P, pn[lab])) / z
    want = np.bincount(lab, p.depth_sigma2(z) * proj * proj * 1.7 ** 2, minlength=5)
    np.testing.assert_allclose(sv, want, rtol=1e-13)


@pytest.mark.parametrize("seed", range(6))
def test_part_pieces_on_speckle_match_scipy(seed):
    """Single-pixel speckle: diagonal contacts, U shapes closing rows later, runs of one pixel
    (the run-length labelling's hard cases)."""
    rng = np.random.default_rng(100 + seed)
    h, w = 23, 31
    inside = rng.random((h, w)) < 0.9
    pix = np.flatnonzero(inside)
    part = rng.integers(-1, 2, size=len(pix))
    piece, planes = PK.part_pieces(pix, w, part, 2, 1)
    want_piece, want_planes = _scipy_pieces(pix, w, part, 2, 1)
    np.testing.assert_array_equal(piece, want_piece)
    np.testing.assert_array_equal(planes, want_planes)


def test_ransac_scores_match_the_numpy_statement():
    """Inlier counts per hypothesis; the numpy statement's dot products go through BLAS, whose
    rounding may differ in the last bit, so a count may differ by a point on the boundary."""
    rng = np.random.default_rng(7)
    S = rng.normal(size=(1000, 3)) * [1.0, 1.0, 0.05] + [0.0, 0.0, 2.0]
    Sz = rng.random(1000) * 300 + 100
    Hn = rng.normal(size=(64, 3)) * [0.05, 0.05, 1.0]
    Hn /= np.linalg.norm(Hn, axis=1, keepdims=True)
    Ho = -(Hn @ np.array([0.0, 0.0, 2.0]))
    got = PK.ransac_scores(S, Sz, Hn, Ho, 3.0)
    dn = S @ Hn.T
    want = (np.abs(dn + Ho) * Sz[:, None] <= 3.0 * np.abs(dn)).sum(axis=0)
    assert np.abs(got - want).max() <= 1
    assert (got == want).mean() > 0.9
    assert want.max() > 50  # the test has real inliers


def test_plane_fit_matches_the_numpy_pca():
    rng = np.random.default_rng(11)
    n_true = np.array([0.2, -0.3, -0.93])
    n_true /= np.linalg.norm(n_true)
    basis = np.linalg.svd(n_true[None])[2][1:]  # two directions in the plane
    P = rng.normal(size=(3000, 2)) @ basis + 2.0 * -n_true + rng.normal(size=(3000, 1)) * 1e-3 * n_true
    nr, off = PK.plane_fit(P)
    c = P.mean(axis=0)
    q = P - c
    want = np.linalg.eigh(q.T @ q)[1][:, 0]
    s = np.sign(nr @ want)  # an eigenvector's sign is arbitrary
    np.testing.assert_allclose(s * nr, want, atol=1e-10)
    np.testing.assert_allclose(s * off, -(want @ c), atol=1e-10)
    assert abs(abs(nr @ n_true) - 1.0) < 1e-4
