"""The part-search and relabelling kernels of the split / merge / absorb steps against the
numpy statements they replaced: bit for bit (same operations in the same order), and the
whole post-processing with the kernels swapped back for those statements gives the same
labels and planes on a floor + ramp scene (a bent region that is split)."""

import numpy as np
import pytest

from planerel.segment import _post_kernels as PK
from planerel.segment import _split_kernels as SK
from planerel.segment import segment
from planerel.segment._kernels import planes_from_sums
from planerel.segment.result import fit_planes
from planerel.synth.generator import generate_scene


def _cost(P, zs, nr, off):
    """The former ``split._cost``: normalised point-to-plane distances, numpy's products."""
    dn = P @ nr
    return np.abs(dn + off) * zs / np.maximum(np.abs(dn), 1e-12)


def _two_planes(m, seed):
    """``m`` points on two planes about 2 m away (a floor and a 10-degree ramp), noisy."""
    rng = np.random.default_rng(seed)
    xy = rng.uniform(-1, 1, size=(m, 2))
    z = 2.0 + 0.2 * xy[:, 1] + np.where(xy[:, 0] > 0.3, 0.18 * (xy[:, 0] - 0.3), 0.0)
    P = np.column_stack([xy, z + rng.normal(size=m) * 2e-3])
    zs = rng.uniform(200, 400, size=m)
    return P, zs


# --- numpy references: the statements of split._split_one before the kernels -------------

def _ref_inliers_fit(P, dn, zs, off, sigmas):
    inl = np.abs(dn + off) * zs / np.maximum(np.abs(dn), 1e-12) <= sigmas
    cnt = int(inl.sum())
    if cnt < 3:
        return inl, cnt, np.zeros(3), 0.0
    n, o = PK.plane_fit(np.ascontiguousarray(P[inl]))
    return inl, cnt, n, o


def _ref_assign_refit(P, DN, zs, offs, assign_sigmas, cut):
    cost = np.stack([np.abs(DN[j] + offs[j]) * zs / np.maximum(np.abs(DN[j]), 1e-12)
                     for j in range(len(DN))], axis=1)
    part = np.argmin(cost, axis=1)
    k = len(DN)
    planes = np.zeros((k, 4))
    done = np.zeros(k, dtype=bool)
    if not cut:
        return part, planes, done
    part[cost[np.arange(len(P)), part] > assign_sigmas] = -1
    for j in range(k):
        mj = part == j
        if mj.sum() >= 3:
            n, o = PK.plane_fit(np.ascontiguousarray(P[mj]))
            planes[j] = [*n, o]
            done[j] = True
    return part, planes, done


def _ref_part_centroids(P, part, k):
    mean = np.zeros((k, 3))
    count = np.zeros(k, dtype=np.int64)
    for j in range(k):
        if np.any(part == j):
            mean[j] = P[part == j].mean(axis=0)
            count[j] = int((part == j).sum())
    return mean, count


def _ref_sample_normals(N, pix, step):
    NQ = np.asarray(N[pix[::step]], dtype=np.float64)
    return NQ, np.all(np.isfinite(NQ), axis=1)


def _ref_relabel_moments(labels, remap, row, pts, nrow):
    from planerel.segment._kernels import region_sums

    out = remap[labels + 1]
    r = row[labels + 1]
    pix = np.flatnonzero(r >= 0)
    sums, ref = region_sums(np.ascontiguousarray(pts[pix], dtype=np.float64),
                            np.ascontiguousarray(r[pix], dtype=np.int32), nrow)
    return out, sums, ref


# --- kernel by kernel ---------------------------------------------------------------------

@pytest.mark.parametrize("seed", range(3))
def test_inliers_fit_is_the_numpy_statement(seed):
    P, zs = _two_planes(5000, seed)
    nr = np.array([0.0, -0.2, 1.0])
    nr /= np.linalg.norm(nr)
    off = -2.0 * nr[2]
    for _ in range(3):  # the refinement loop, both ways
        dn = P @ nr
        inl, cnt, n2, o2 = SK.inliers_fit(P, dn, zs, off, 3.0)
        want = _cost(P, zs, nr, off) <= 3.0
        np.testing.assert_array_equal(inl, want)
        assert cnt == int(want.sum()) and cnt > 100
        wn, wo = PK.plane_fit(np.ascontiguousarray(P[want]))
        assert np.array_equal(n2, wn) and o2 == wo
        nr, off = n2, float(o2)


def test_inliers_fit_with_too_few_inliers():
    P, zs = _two_planes(50, 0)
    nr = np.array([1.0, 0.0, 0.0])  # a plane far from every point
    inl, cnt, n2, o2 = SK.inliers_fit(P, P @ nr, zs, 100.0, 3.0)
    assert cnt == 0 and not inl.any() and not n2.any() and o2 == 0.0


@pytest.mark.parametrize("cut", [True, False])
@pytest.mark.parametrize("seed", range(3))
def test_assign_refit_is_the_numpy_statement(seed, cut):
    P, zs = _two_planes(6000, seed)
    P[::50, 2] += 0.3  # outliers: unassigned
    P = P[::2]  # a strided view, as split's sample is
    zs = zs[::2]
    planes = [(np.array([0.0, -0.2, 1.0]) / np.linalg.norm([0.0, -0.2, 1.0]), None),
              (np.array([-0.18, -0.2, 1.0]) / np.linalg.norm([-0.18, -0.2, 1.0]), None),
              (np.array([1.0, 0.0, 0.0]), None)]  # a third plane no point is near
    planes = [(n, -float(n @ [0.3, 0.0, 2.0])) for n, _ in planes]
    DN = np.stack([P @ n for n, _ in planes])
    offs = np.array([o for _, o in planes])
    got = SK.assign_refit(P, DN, zs, offs, 4.0, cut)
    want = _ref_assign_refit(P, DN, zs, offs, 4.0, cut)
    for g, w in zip(got, want, strict=True):
        np.testing.assert_array_equal(g, w)
    if cut:
        assert got[2][:2].all() and not got[2][2]  # two parts refitted, the far one not
        assert (got[0] == -1).any()


def test_part_centroids_are_numpy_means():
    P, _ = _two_planes(7000, 1)
    part = np.random.default_rng(1).integers(-1, 4, size=len(P))
    part[part == 2] = 3  # part 2 empty
    mean, count = SK.part_centroids(P, part, 4)
    wmean, wcount = _ref_part_centroids(P, part, 4)
    np.testing.assert_array_equal(mean, wmean)
    np.testing.assert_array_equal(count, wcount)
    assert count[2] == 0


def test_sample_normals_gathers_and_flags_unknown():
    rng = np.random.default_rng(2)
    N = rng.normal(size=(500, 3)).astype(np.float32)
    N[rng.random(500) < 0.2, rng.integers(0, 3)] = np.nan
    pix = np.sort(rng.choice(500, size=300, replace=False))
    for step in (1, 3, 7):
        NQ, fin = SK.sample_normals(N, pix, step)
        wNQ, wfin = _ref_sample_normals(N, pix, step)
        np.testing.assert_array_equal(NQ, wNQ)
        np.testing.assert_array_equal(fin, wfin)
        assert NQ.dtype == np.float64 and not fin.all()


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_relabel_moments_equals_fit_planes_of_the_pixels(dtype):
    rng = np.random.default_rng(3)
    n_pix, n = 4000, 6
    labels = rng.integers(-1, n, size=n_pix).astype(np.int32)
    pts = (rng.normal(size=(n_pix, 3)) + [0, 0, 3]).astype(dtype)
    remap = np.array([-1, 0, 0, 1, 2, -1, 3], dtype=np.int32)  # merge 0+1, drop 4
    row = np.array([-1, 0, 0, -1, 1, -1, -1], dtype=np.int64)  # refit 0+1 and 3
    out, sums, ref = PK.relabel_moments(labels, remap, row, pts, 2)
    wout, wsums, wref = _ref_relabel_moments(labels, remap, row, pts, 2)
    np.testing.assert_array_equal(out, wout)
    np.testing.assert_array_equal(sums, wsums)
    np.testing.assert_array_equal(ref, wref)
    # and the planes are fit_planes of those pixels
    sel = row[labels + 1] >= 0
    want = fit_planes(pts[sel], row[labels[sel] + 1].astype(np.int32), 2)
    for g, w in zip(planes_from_sums(sums, ref, 2), want, strict=True):
        np.testing.assert_array_equal(g, w)


def _ref_ransac_hypotheses(Q, tri, N, pick):
    """The former numpy statements of ``split._ransac`` building the hypothesis planes."""
    a, b, c = Q[tri[:, 0]], Q[tri[:, 1]], Q[tri[:, 2]]
    u, v = b - a, c - a
    cr = np.empty_like(u)
    np.multiply(u[:, 1], v[:, 2], out=cr[:, 0])
    cr[:, 0] -= u[:, 2] * v[:, 1]
    np.multiply(u[:, 2], v[:, 0], out=cr[:, 1])
    cr[:, 1] -= u[:, 0] * v[:, 2]
    np.multiply(u[:, 0], v[:, 1], out=cr[:, 2])
    cr[:, 2] -= u[:, 1] * v[:, 0]
    ln = np.linalg.norm(cr, axis=1)
    ok = ln > 1e-12
    hyp_n, hyp_p = [cr[ok] / ln[ok, None]], [a[ok]]
    if len(pick):
        nn = N[pick]
        ln = np.linalg.norm(nn, axis=1)
        ok = ln > 1e-12
        hyp_n.append(nn[ok] / ln[ok, None])
        hyp_p.append(Q[pick[ok]])
    Hn = np.concatenate(hyp_n)
    return Hn, -np.einsum("ij,ij->i", Hn, np.concatenate(hyp_p))


@pytest.mark.parametrize("seed", range(4))
def test_ransac_hypotheses_equal_the_numpy_statements(seed):
    P, _ = _two_planes(3000, seed)
    rng = np.random.default_rng(seed)
    tri = rng.integers(0, len(P), size=(32, 3))
    tri[0] = [5, 5, 7]  # a degenerate triple gives no plane
    N = rng.normal(size=(len(P), 3))
    N[3] = 0.0  # a zero normal gives none
    pick = np.concatenate([[3], rng.integers(0, len(P), size=31)]).astype(np.int64)
    for pk in (pick, np.zeros(0, dtype=np.int64)):
        Hn, Ho = PK.ransac_hypotheses(P, tri, N, pk)
        wHn, wHo = _ref_ransac_hypotheses(P, tri, N, pk)
        np.testing.assert_array_equal(Hn, wHn)
        np.testing.assert_array_equal(Ho, wHo)
    assert len(Hn) == 31


def test_group_moments_and_relabel_equal_relabel_moments():
    rng = np.random.default_rng(4)
    n_pix = 5000
    labels = rng.integers(-1, 5, size=n_pix).astype(np.int32)
    pts = rng.normal(size=(n_pix, 3)) + [0, 0, 3]
    # regions 1 and 3 changed (pixel groups: region 1's pixels, then region 3's and those of
    # region 4 that a later group claims), 2 of its pixels moved to 4 (owned by group 1)
    g0 = np.flatnonzero(labels == 1)
    g1 = np.flatnonzero((labels == 3) | (labels == 4))
    labels[g0[:2]] = 4
    remap = np.array([-1, 0, 1, 2, 3, 4], dtype=np.int32)
    row = np.array([-1, -1, 0, -1, 1, 2], dtype=np.int64)
    owner = np.array([-1, -1, 0, -1, 1, 1], dtype=np.int64)
    g1 = np.union1d(g1, g0[:2])
    sums, ref = np.zeros((3, 10)), np.zeros((3, 3))
    for g, pix in enumerate((g0, g1)):
        PK.group_moments(pts, pix, labels, row, owner, g, sums, ref)
    wout, wsums, wref = _ref_relabel_moments(labels, remap, row, pts, 3)
    np.testing.assert_array_equal(PK.relabel(labels, remap), wout)
    np.testing.assert_array_equal(sums, wsums)
    np.testing.assert_array_equal(ref, wref)


# --- the whole post-processing --------------------------------------------------------------

def _numpy_kernels(monkeypatch):
    """Swap the kernels for the numpy statements they replaced (split imports them inside its
    functions, so the module attributes are what it calls)."""
    monkeypatch.setattr(SK, "inliers_fit", _ref_inliers_fit)
    monkeypatch.setattr(SK, "assign_refit", _ref_assign_refit)
    monkeypatch.setattr(SK, "part_centroids", _ref_part_centroids)
    monkeypatch.setattr(SK, "sample_normals", _ref_sample_normals)
    monkeypatch.setattr(PK, "relabel_moments", _ref_relabel_moments)
    monkeypatch.setattr(PK, "ransac_hypotheses", _ref_ransac_hypotheses)


@pytest.mark.parametrize("adapt", [True, False])
def test_segment_with_kernels_equals_the_numpy_path_on_a_bent_region(monkeypatch, adapt):
    sc = generate_scene("ramp", 0, size=(640, 480), subsample=4, angle_deg=10)
    fast = segment(sc.cloud, adapt=adapt)
    assert fast.info["split_regions"] >= 1  # a region was split: the whole path ran
    with monkeypatch.context() as mp:
        _numpy_kernels(mp)
        ref = segment(sc.cloud, adapt=adapt)
    np.testing.assert_array_equal(fast.labels, ref.labels)
    assert fast.n_planes == ref.n_planes
    for a, b in zip(fast.planes, ref.planes, strict=True):
        assert np.array_equal(a.normal, b.normal) and np.array_equal(a.centroid, b.centroid)
        assert (a.offset, a.rms, a.n_points) == (b.offset, b.rms, b.n_points)
    assert fast.info == ref.info


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("dtype", [np.int32, np.int64])
def test_group_pixels_is_the_stable_sort_it_replaces(seed, dtype):
    rng = np.random.default_rng(seed)
    n = 12
    lab = rng.integers(-1, n, size=5000).astype(dtype)
    sel = np.zeros(n + 1, dtype=bool)
    sel[rng.choice(n, size=5, replace=False) + 1] = True
    sel[0] = bool(seed % 2)  # the unassigned pixels may be selected too
    idx, starts = SK.group_pixels(lab, sel)
    ref = np.flatnonzero(sel[lab + 1])
    ref = ref[np.argsort(lab[ref], kind="stable")]
    assert np.array_equal(idx, ref)
    for r in range(-1, n):
        pix = idx[starts[r + 1]:starts[r + 2]]
        assert np.array_equal(pix, np.flatnonzero(lab == r) if sel[r + 1] else np.empty(0, int))
