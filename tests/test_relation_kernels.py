"""The compiled passes of planerel.features.relations against the numpy code they replace:
the same floats, bit for bit (the facts of every scene stay byte-identical)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from scenes_analytic import box, floor, render, stairs, wall

from planerel.features.planes import measure_planes
from planerel.features.relations import _gap_matrix, hull_gap

# ---- numpy reference: planerel.features.relations._gap_matrix before the kernel (main 8c18deb)

def _edges(poly: np.ndarray):
    """Start and end points ``(m, 3)`` of a closed polygon (a point gives one zero-length edge)."""
    if poly.shape[0] == 1:
        return poly, poly
    if poly.shape[0] == 2:
        return poly[:1], poly[1:]
    return poly, np.roll(poly, -1, axis=0)


def _segment_distances(p1, q1, p2, q2) -> np.ndarray:
    """Closest distances between segments ``p1q1`` and ``p2q2``, all ``(T, 3)`` -> ``(T,)``."""
    d1 = q1 - p1
    d2 = q2 - p2
    r = p1 - p2
    a = np.einsum("ij,ij->i", d1, d1)
    e = np.einsum("ij,ij->i", d2, d2)
    f = np.einsum("ij,ij->i", d2, r)
    c = np.einsum("ij,ij->i", d1, r)
    b = np.einsum("ij,ij->i", d1, d2)
    eps = 1e-18
    a_ok = a > eps
    e_ok = e > eps
    safe_a = np.where(a_ok, a, 1.0)
    safe_e = np.where(e_ok, e, 1.0)
    denom = a * e - b * b
    s = np.where(denom > eps * np.maximum(a * e, eps), (b * f - c * e) / np.where(denom > 0, denom, 1.0), 0.0)
    s = np.clip(s, 0.0, 1.0)
    t = (b * s + f) / safe_e
    low = t < 0
    high = t > 1
    t = np.clip(t, 0.0, 1.0)
    s = np.where(low, np.clip(-c / safe_a, 0, 1), s)
    s = np.where(high, np.clip((b - c) / safe_a, 0, 1), s)
    # degenerate segments
    s = np.where(~a_ok, 0.0, s)
    t = np.where(~a_ok & e_ok, np.clip(f / safe_e, 0, 1), t)
    t = np.where(~e_ok, 0.0, t)
    s = np.where(~e_ok & a_ok, np.clip(-c / safe_a, 0, 1), s)
    diff = (p1 + d1 * s[:, None]) - (p2 + d2 * t[:, None])
    return np.sqrt(np.einsum("ij,ij->i", diff, diff))


def _gap_matrix_numpy(plist) -> np.ndarray:
    """``(n, n)`` closest hull distances of all plane pairs, vectorized over all edges.

    The distance between two convex planar polygons is the smallest of: the edge-edge segment
    distances, the distance of a vertex of one polygon to the other polygon's face when it
    projects inside it, and 0 when an edge of one pierces the other's face.
    """
    n = len(plist)
    e0s, e1s, eown, vs, vown = [], [], [], [], []
    M = max(p.hull3d.shape[0] for p in plist)
    poly2 = np.zeros((n, M, 2))
    isface = np.zeros(n, dtype=bool)
    C = np.array([p.centroid for p in plist])
    N = np.array([p.normal for p in plist])
    AX = np.array([p.axes for p in plist])  # (n, 2, 3)
    for k, p in enumerate(plist):
        poly = p.hull3d
        a0, a1 = _edges(poly)
        e0s.append(a0)
        e1s.append(a1)
        eown.append(np.full(a0.shape[0], k))
        vs.append(poly)
        vown.append(np.full(poly.shape[0], k))
        if poly.shape[0] >= 3:
            isface[k] = True
            p2 = (poly - p.centroid) @ p.axes.T
            poly2[k, : p2.shape[0]] = p2
            poly2[k, p2.shape[0]:] = p2[-1]
    E0 = np.concatenate(e0s)
    E1 = np.concatenate(e1s)
    eo = np.concatenate(eown)
    V = np.concatenate(vs)
    vo = np.concatenate(vown)
    T = E0.shape[0]
    estart = np.searchsorted(eo, np.arange(n))
    vstart = np.searchsorted(vo, np.arange(n))
    # edge-edge distances over the upper triangle of owners
    ii, jj = np.triu_indices(T, 1)
    cross_owner = eo[ii] != eo[jj]
    ii, jj = ii[cross_owner], jj[cross_owner]
    dee = np.full((T, T), np.inf)
    dee[ii, jj] = _segment_distances(E0[ii], E1[ii], E0[jj], E1[jj])
    dee = np.minimum(dee, dee.T)
    G = np.minimum.reduceat(np.minimum.reduceat(dee, estart, axis=0), estart, axis=1)

    def inside(pts2):  # pts2 (K, n, 2) in each plane's frame -> (K, n) inside that face
        ed = np.roll(poly2, -1, axis=1) - poly2  # (n, M, 2)
        rel = pts2[:, :, None, :] - poly2[None]  # (K, n, M, 2)
        cr = ed[None, :, :, 0] * rel[..., 1] - ed[None, :, :, 1] * rel[..., 0]
        return np.all(cr >= -1e-12, axis=2) & isface[None, :]

    # vertices over faces
    rel = V[:, None, :] - C[None]  # (Nv, n, 3)
    h = np.einsum("knj,nj->kn", rel, N)
    v2 = np.einsum("knj,nij->kni", rel, AX)
    dvf = np.where(inside(v2) & (vo[:, None] != np.arange(n)[None]), np.abs(h), np.inf)
    Gv = np.minimum.reduceat(dvf, vstart, axis=0)
    G = np.minimum(G, np.minimum(Gv, Gv.T))
    # edges piercing faces
    r0 = E0[:, None, :] - C[None]
    r1 = E1[:, None, :] - C[None]
    h0 = np.einsum("knj,nj->kn", r0, N)
    h1 = np.einsum("knj,nj->kn", r1, N)
    crosses = (h0 * h1) < 0
    if crosses.any():
        with np.errstate(divide="ignore", invalid="ignore"):
            tt = np.where(crosses, h0 / np.where(crosses, h0 - h1, 1.0), 0.0)
        pts = r0 + (r1 - r0) * tt[..., None]
        p2 = np.einsum("knj,nij->kni", pts, AX)
        pierce = crosses & inside(p2) & (eo[:, None] != np.arange(n)[None])
        Pm = np.logical_or.reduceat(pierce, estart, axis=0)
        G[Pm | Pm.T] = 0.0
    np.fill_diagonal(G, 0.0)
    return G


# ---- planes to compare on


def _plane(poly, rng=None):
    """A plane-like record with ``hull3d``, ``centroid``, ``normal``, ``axes`` from 3-D
    polygon vertices (counter-clockwise in their own frame)."""
    poly = np.asarray(poly, float)
    c = poly.mean(axis=0)
    if poly.shape[0] >= 3:
        u, s, vt = np.linalg.svd(poly - c)
        n = vt[2]
        ax = vt[:2]
        p2 = (poly - c) @ ax.T
        ang = np.arctan2(p2[:, 1], p2[:, 0])
        poly = poly[np.argsort(ang)]
    else:
        n = np.array([0.0, 0.0, 1.0])
        ax = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    return SimpleNamespace(hull3d=poly, centroid=c, normal=n, axes=ax)


def _random_planes(rng, n):
    out = []
    for _ in range(n):
        k = int(rng.choice([1, 2, 3, 4, 5, 8, 12]))
        centre = rng.normal(size=3) * rng.choice([0.05, 0.3, 1.0])
        normal = rng.normal(size=3)
        normal /= np.linalg.norm(normal)
        a = np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
        a /= np.linalg.norm(a)
        b = np.cross(normal, a)
        t = np.sort(rng.uniform(0, 2 * np.pi, k))
        r = rng.uniform(0.05, 0.6)
        poly = centre + r * (np.cos(t)[:, None] * a + np.sin(t)[:, None] * b)
        out.append(_plane(poly))
    return out


@pytest.fixture(scope="module")
def scene_planes():
    rects = [floor(), wall()] + stairs(0.3, 2.2, 3, rise=0.17, run=0.28) + \
        box(-1.0, 2.5, 0.5, 0.5, 0.4, obj=2) + box(0.2, 1.6, 0.3, 0.3, 0.3, obj=3)
    cloud, lab, _, _ = render(rects, pitch=25, roll=5, noise=0.0012)
    return list(measure_planes(cloud, lab))


def test_gap_matrix_is_the_numpy_reference_on_a_scene(scene_planes):
    a = _gap_matrix(scene_planes)
    b = _gap_matrix_numpy(scene_planes)
    assert len(scene_planes) >= 8
    assert (a == b).all()
    assert np.array_equal(a, a.T) and (np.diag(a) == 0).all()
    assert (a > 0).any() and (a == 0).sum() > len(scene_planes)  # gaps and touching pairs


@pytest.mark.parametrize("seed", range(8))
def test_gap_matrix_is_the_numpy_reference_on_random_polygons(seed):
    rng = np.random.default_rng(seed)
    planes = _random_planes(rng, 12)
    # touching, crossing and degenerate pairs: a copy moved along its own plane, one rotated
    planes.append(_plane(planes[0].hull3d + 0.3 * planes[0].axes[0]))
    planes.append(_plane(planes[3].hull3d[:, [1, 0, 2]]))
    planes.append(_plane(planes[4].hull3d[:1]))
    planes.append(_plane(np.vstack([planes[5].centroid - planes[5].normal,
                                    planes[5].centroid + planes[5].normal])))
    a = _gap_matrix(planes)
    b = _gap_matrix_numpy(planes)
    assert (a == b).all(), np.argwhere(a != b)
    assert (a == 0).sum() > len(planes)  # some pierce or touch


def test_hull_gap_of_two_squares():
    sq = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    p, q = _plane(sq), _plane(sq + [2.5, 0, 0])
    assert hull_gap(p, q) == pytest.approx(1.5)
    assert hull_gap(p, _plane(sq + [0.5, 0.5, 0.2])) == pytest.approx(0.2)
    pierce = _plane(np.array([[0.5, 0.5, -1], [0.5, 0.6, 1], [0.6, 0.6, 1]], float))
    assert hull_gap(p, pierce) == 0.0


def test_relations_built_without_init_equal_the_dataclass():
    from planerel.features.relations import Relation, _relation

    vals = (3, 7, 12.5, False, False, 0.031, True, True, -0.2, True, False, True, False)
    r, q = _relation(*vals), Relation(*vals)
    assert r == q and repr(r) == repr(q) and hash(r) == hash(q)
    with pytest.raises(AttributeError):
        r.a = 4  # still frozen


def test_relations_sorted_by_pair_whatever_the_plane_order(scene_planes):
    from planerel.features.planes import PlaneSet
    from planerel.features.relations import relate

    up = np.array([0.0, 0.0, 1.0])
    ps = PlaneSet(tuple(scene_planes), up, "given", None, 0.0)
    back = PlaneSet(tuple(reversed(scene_planes)), up, "given", None, 0.0)
    a, b = relate(ps), relate(back)
    assert [(r.a, r.b) for r in a] == sorted((r.a, r.b) for r in a)
    assert [(r.a, r.b) for r in b] == [(r.a, r.b) for r in a]
    for r, q in zip(a, b, strict=True):  # floats' last bits follow the order of the planes
        for name, x in vars(r).items():
            y = getattr(q, name)
            assert x == (pytest.approx(y, abs=1e-9) if isinstance(x, float) else y)


def _touch_pairs_python(xyz, lab, rows, cols, g, max_dist, rel_dist, known):
    """touch_pairs written out plainly: every listed pixel against the pixels after it within
    ``g`` rows and columns."""
    H, W = lab.shape
    n = known.shape[0]
    out = np.zeros((n, n), bool)
    for v, u in zip(rows.tolist(), cols.tolist(), strict=True):
        a = int(lab[v, u])
        if a < 0 or a >= n or not known[a]:
            continue
        lim = max(max_dist, rel_dist * abs(float(xyz[v, u, 2])))
        for dv in range(g + 1):
            for du in range(-g, g + 1):
                if dv == 0 and du <= 0:
                    continue
                v2, u2 = v + dv, u + du
                if v2 >= H or u2 < 0 or u2 >= W:
                    continue
                b = int(lab[v2, u2])
                if b < 0 or b == a or b >= n or not known[b]:
                    continue
                e = xyz[v, u] - xyz[v2, u2]
                if float(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) <= lim * lim:
                    out[a, b] = out[b, a] = True
    return out


def test_touch_pairs_kernel_matches_the_plain_definition():
    from planerel.segment._label_kernels import touch_pairs

    rng = np.random.default_rng(7)
    found = 0
    for _ in range(60):
        H, W = (int(v) for v in rng.integers(2, 25, 2))
        lab = rng.integers(-1, 6, (H, W)).astype(np.int32)
        xyz = rng.normal(size=(H, W, 3)) * 0.03 + [0, 0, 2.0]
        xyz[rng.random((H, W)) < 0.1] = np.nan
        known = rng.random(int(lab.max()) + 1) < 0.8
        rows, cols = (a.astype(np.int64) for a in np.nonzero(rng.random((H, W)) < 0.7))
        g = int(rng.integers(1, 4))
        want = _touch_pairs_python(xyz, lab, rows, cols, g, 0.05, 0.02, known)
        found += int(want.sum())
        assert np.array_equal(touch_pairs(xyz, lab, rows, cols, g, 0.05, 0.02, known), want)
    assert found > 100


# ---- planerel.features.solid._cover before its kernels (main 8c18deb)

_DV, _DU = (a.ravel() for a in np.meshgrid([-1, 0, 1], [-1, 0, 1], indexing="ij"))


def _cover_numpy(face, labels, xyz, intr, up, along, levels, t0: float, t1: float,
           samples: int, normals: np.ndarray, cos_par: float) -> float:
    """``cover`` of the module rule: covered / (covered + open) over the sample points.

    ``levels`` are the sample heights (``up . x``), ``[t0, t1]`` the top's extent along
    ``along``; ``intr`` the camera (``fx``, ``fy``, ``cx``, ``cy``); ``normals`` ``(K, 3)``
    the unit normal of each label (NaN where none), ``cos_par`` the cosine of the parallel
    tolerance.
    """
    n = np.asarray(face.normal, float)
    c = np.asarray(face.centroid, float)
    vert = up - (up @ n) * n  # the face's own "up" (the face is vertical within tolerance)
    vert /= max(float(np.linalg.norm(vert)), 1e-12)
    s = np.linspace(t0, t1, samples)
    S, L = np.meshgrid(s, np.asarray(levels, float))
    X = (c + np.multiply.outer(S - c @ along, along)
         + np.multiply.outer((L - c @ up) / (vert @ up), vert)).reshape(-1, 3)
    H, W = labels.shape
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.rint(intr.fx * X[:, 0] / X[:, 2] + intr.cx)
        v = np.rint(intr.fy * X[:, 1] / X[:, 2] + intr.cy)
    inside = (X[:, 2] > 0) & (u >= 0) & (u < W) & (v >= 0) & (v < H)
    u, v, X = u[inside].astype(np.int64), v[inside].astype(np.int64), X[inside]
    if u.size == 0:
        return 0.0
    # a pixel of the face within one pixel (the 3x3 neighbourhood, clipped to the image)
    vv = np.clip(v[None, :] + _DV[:, None], 0, H - 1)
    uu = np.clip(u[None, :] + _DU[:, None], 0, W - 1)
    near = (labels[vv, uu] == face.label).any(axis=0)
    seen = np.asarray(xyz[v, u], float)
    rng_seen = np.linalg.norm(seen, axis=1)
    rng_face = np.linalg.norm(X, axis=1)
    margin = np.maximum(0.03, 0.03 * rng_face)
    hidden = ~np.isfinite(rng_seen) | (rng_seen < rng_face - margin)
    # another piece of the same surface: a plane parallel to the face, its point on the
    # face's plane (a side split in two by an object standing in front of it)
    lab = labels[v, u]
    cos = np.abs(normals[np.clip(lab, 0, None)] @ n)
    with np.errstate(invalid="ignore"):
        near |= (lab >= 0) & (cos >= cos_par) & (np.abs((seen - c) @ n) <= margin)
    covered = int(near.sum())
    open_ = int((~near & ~hidden).sum())
    return covered / (covered + open_) if covered + open_ else 0.0


def test_cover_is_the_numpy_reference():
    """solid._cover with its two kernels gives the numpy code's cover, on random faces seen
    by a pinhole camera over random label images (parallel pieces, hidden and open samples,
    samples off the image).  The kernel sums its two dot products in the plain order, not
    numpy's BLAS order; a count can differ only for a sample within rounding of a limit,
    which none of these is."""
    from planerel.features.solid import _cover

    rng = np.random.default_rng(21)
    intr = SimpleNamespace(fx=300.0, fy=300.0, cx=79.5, cy=59.5)
    H, W = 120, 160
    values = set()
    for _ in range(300):
        n = np.array([rng.normal(), rng.normal(), rng.normal() * 0.1])
        n[2] = -abs(n[2]) - 0.5
        n /= np.linalg.norm(n)
        c = np.array([rng.uniform(-0.5, 0.5), rng.uniform(-0.3, 0.3), rng.uniform(1.0, 3.0)])
        face = SimpleNamespace(normal=n, centroid=c, label=int(rng.integers(0, 4)))
        up = np.array([0.0, -1.0, 0.0]) + rng.normal(size=3) * 0.05
        up /= np.linalg.norm(up)
        along = np.cross(up, n)
        along /= np.linalg.norm(along)
        labels = rng.integers(-1, 5, (H, W)).astype(np.int32)
        labels[labels == face.label] = -1
        r0, c0 = int(rng.integers(0, H)), int(rng.integers(0, W))
        labels[r0:r0 + int(rng.integers(5, H)), c0:c0 + int(rng.integers(5, W))] = face.label
        vv, uu = np.mgrid[0:H, 0:W]
        ray = np.stack([(uu - intr.cx) / intr.fx, (vv - intr.cy) / intr.fy, np.ones((H, W))], -1)
        depth = (c @ n) / (ray @ n) + rng.normal(size=(H, W)) * rng.choice([0.001, 0.05, 0.3])
        xyz = ray * depth[..., None]
        xyz[rng.random((H, W)) < 0.05] = np.nan
        normals = rng.normal(size=(6, 3))
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        normals[face.label] = n
        normals[int(rng.integers(0, 6))] = n * -1 + rng.normal(size=3) * 0.01
        normals[5] = np.nan
        t = c @ along
        t0, t1 = t - rng.uniform(0.05, 1.5), t + rng.uniform(0.05, 1.5)
        top = c @ up + rng.uniform(0, 0.3)
        levels = [top - k * rng.uniform(0.05, 0.4) for k in (0.3, 0.5, 0.7)]
        cos_par = float(np.cos(np.radians(10.0)))
        args = (face, labels, xyz, intr, up, along, levels, t0, t1, 24, normals, cos_par)
        want = _cover_numpy(*args)
        got = _cover(*args)
        assert got == want
        values.add(round(want, 2))
    assert len(values) > 10  # covers across the range, not one constant


def _edge_sums_python(lab, xyz, rows, cols, used, band, depth, n):
    """edge_sums written out plainly, in its order (so its float sums are the same)."""
    H, W = lab.shape
    cnt = np.zeros(n * n)
    lo_acc = np.zeros((n * n, 3))
    hi_acc = np.zeros((n * n, 3))
    for y0, x0 in zip(rows.tolist(), cols.tolist(), strict=True):
        a = int(lab[y0, x0])
        if a < 0 or a >= n or not used[a]:
            continue
        lim = depth * max(1.0, abs(float(xyz[y0, x0, 2])))
        for k in range(1, band + 1):
            for y, x in ((y0, x0 + k), (y0 + k, x0), (y0 + k, x0 + k), (y0 + k, x0 - k)):
                if not (0 <= y < H and 0 <= x < W):
                    continue
                b = int(lab[y, x])
                if b < 0 or b == a or b >= n or not used[b]:
                    continue
                d = xyz[y0, x0] - xyz[y, x]
                if not float(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) <= lim * lim:
                    continue
                code = min(a, b) * n + max(a, b)
                first, second = (xyz[y0, x0], xyz[y, x]) if a < b else (xyz[y, x], xyz[y0, x0])
                for j in range(3):
                    lo_acc[code, j] += first[j]
                    hi_acc[code, j] += second[j]
                cnt[code] += 1.0
    return cnt, lo_acc, hi_acc


def test_edge_sums_kernel_matches_the_plain_definition():
    from planerel.features._relation_kernels import edge_sums

    rng = np.random.default_rng(9)
    counted = 0
    for _ in range(40):
        H, W = (int(v) for v in rng.integers(2, 25, 2))
        lab = rng.integers(-1, 5, (H, W)).astype(np.int32)
        xyz = rng.normal(size=(H, W, 3)) * 0.02 + [0, 0, 1.5]
        xyz[rng.random((H, W)) < 0.1] = np.nan
        n = int(lab.max()) + 1
        used = rng.random(n) < 0.8
        rows, cols = (a.astype(np.int64) for a in np.nonzero(rng.random((H, W)) < 0.7))
        band = int(rng.integers(1, 4))
        want = _edge_sums_python(lab, xyz, rows, cols, used, band, 0.03, n)
        got = edge_sums(lab, xyz, rows, cols, used, band, 0.03, n)
        counted += int(want[0].sum())
        for g, w in zip(got, want, strict=True):
            assert np.array_equal(g, w)
    assert counted > 100


def test_box_points_of_a_label_are_numpys_gather():
    from planerel.features.stepped import _box_points

    rng = np.random.default_rng(13)
    for _ in range(50):
        H, W = (int(v) for v in rng.integers(1, 30, 2))
        lab = rng.integers(-1, 4, (H, W)).astype(np.int32)
        xyz = rng.normal(size=(H, W, 3))
        xyz[rng.random((H, W)) < 0.1] = np.nan
        r0, c0 = int(rng.integers(0, H)), int(rng.integers(0, W))
        for window in ((slice(r0, r0 + int(rng.integers(0, H + 2))), slice(c0, W + 3)),
                    (slice(None), slice(None))):
            want = xyz[window][lab[window] == 2]
            got = _box_points(lab, xyz, 2, window)
            assert got.shape == want.shape and got.flags.c_contiguous
            assert np.array_equal(got, want, equal_nan=True)
            up = rng.normal(size=3)
            assert np.array_equal(got @ up, want @ up, equal_nan=True)


def test_box_profile_is_the_numpy_face_profile_within_rounding():
    """The one-pass face profile (plain-order dot products) against numpy's: the points of
    face_points, their heights by numpy's matrix product, np.percentile; within 1e-12."""
    from planerel.features.solid import face_points, face_profile, face_profile_of

    rects = [floor(), wall()] + stairs(0.3, 2.2, 3, rise=0.17, run=0.28) + \
        box(-1.0, 2.5, 0.5, 0.5, 0.4, obj=2) + box(0.2, 1.6, 0.3, 0.3, 0.3, obj=3)
    cloud, lab, _, _ = render(rects, pitch=25, roll=5, noise=0.0012)
    planes = measure_planes(cloud, lab)
    up = np.asarray(planes.up, float)
    seen = 0
    for p in planes:
        for m in (4000, 50, 2):  # every pixel, every k-th row and column, < 3 points
            pts = face_points(p, planes.labels, cloud.xyz, max_points=m)
            want = face_profile(p, up, pts)
            got = face_profile_of(p, up, planes.labels, cloud.xyz, max_points=m)
            assert np.array_equal(got.along, want.along)
            h, a = pts[0] @ up, pts[0] @ want.along
            for x, y in ((got.bottom, want.bottom), (got.top, want.top), (got.lo, want.lo),
                         (got.hi, want.hi)):
                assert (np.isnan(x) and np.isnan(y)) or x == pytest.approx(y, rel=1e-12,
                                                                           abs=1e-12)
            if len(h) >= 3:
                seen += 1
                assert (want.bottom, want.top) == tuple(np.percentile(h, [2, 98]))
                assert (want.lo, want.hi) == tuple(np.percentile(a, [2, 98]))
    assert seen >= 2 * len(planes)
    # random labels, NaN holes and boxes partly outside the image
    rng = np.random.default_rng(5)
    for _ in range(40):
        H, W = (int(v) for v in rng.integers(3, 40, 2))
        lab = rng.integers(-1, 3, (H, W)).astype(np.int32)
        xyz = rng.normal(size=(H, W, 3))
        xyz[rng.random((H, W)) < 0.1, int(rng.integers(0, 3))] = np.nan
        n = rng.normal(size=3)
        n[2] = 0.1 * n[2]
        face = SimpleNamespace(label=1, normal=n / np.linalg.norm(n), n_points=H * W,
                               bbox=(int(rng.integers(-2, H)), int(rng.integers(-2, W)),
                                     int(rng.integers(0, H + 3)), int(rng.integers(0, W + 3))))
        upv = np.array([0.0, 0.0, 1.0])
        for m in (4000, 20):
            want = face_profile(face, upv, face_points(face, lab, xyz, max_points=m))
            got = face_profile_of(face, upv, lab, xyz, max_points=m)
            assert np.allclose([got.bottom, got.top, got.lo, got.hi],
                               [want.bottom, want.top, want.lo, want.hi], rtol=1e-12,
                               atol=1e-12, equal_nan=True)


def test_box_heights_are_numpys_product_within_rounding():
    """split_stepped's heights in one pass (plain-order dot products) against the numpy gather
    and matrix product, NaN points included, within 1e-12."""
    from planerel.features.stepped import _box_heights, _box_points

    rng = np.random.default_rng(17)
    for _ in range(50):
        H, W = (int(v) for v in rng.integers(1, 30, 2))
        lab = rng.integers(-1, 4, (H, W)).astype(np.int32)
        xyz = rng.normal(size=(H, W, 3)) * rng.choice([0.1, 1.0, 5.0])
        xyz[rng.random((H, W)) < 0.1] = np.nan
        up = rng.normal(size=3)
        up /= np.linalg.norm(up)
        r0, c0 = int(rng.integers(0, H)), int(rng.integers(0, W))
        for window in ((slice(r0, r0 + int(rng.integers(0, H + 2))), slice(c0, W + 3)),
                       (slice(None), slice(None))):
            want = _box_points(lab, xyz, 2, window) @ up
            got = _box_heights(lab, xyz, 2, window, up)
            assert got.shape == want.shape
            assert np.array_equal(np.isnan(got), np.isnan(want))
            assert np.allclose(got, want, rtol=1e-12, atol=1e-12, equal_nan=True)


def test_median_kernel_is_numpys_median():
    """The compiled median against np.median, float for float: odd and even lengths, ties,
    one element, sorted and reversed rows, a NaN."""
    from planerel.features._relation_kernels import median

    rng = np.random.default_rng(29)
    for n in list(range(1, 40)) + [999, 1000, 4001]:
        for x in (rng.normal(size=n), rng.integers(0, 4, n).astype(float),
                  np.sort(rng.random(n)), np.sort(rng.random(n))[::-1].copy(),
                  np.full(n, 0.25)):
            assert median(x) == np.median(x)
        y = rng.normal(size=n)
        y[int(rng.integers(0, n))] = np.nan
        assert np.isnan(median(y)) and np.isnan(np.median(y))


def test_convex_pairs_float_helpers_are_the_numpy_ones_within_rounding():
    """convex_pairs' Python-float products (_dot, _crossing_angle_f, _sanity_limit_f) against
    the numpy helpers they replace, on random normals and offsets."""
    from planerel.features.relations import (
        _crossing_angle,
        _crossing_angle_f,
        _dot,
        _sanity_limit,
        _sanity_limit_f,
        _step_apart,
    )

    rng = np.random.default_rng(31)
    for _ in range(500):
        na, nb = (v / np.linalg.norm(v) for v in rng.normal(size=(2, 3)))
        if rng.random() < 0.2:
            nb = na + rng.normal(size=3) * 1e-4
            nb /= np.linalg.norm(nb)
        xa, xb = rng.normal(size=(2, 3))
        dx = xa - xb
        f = [v.tolist() for v in (na, nb, xa, xb, dx)]
        assert _dot(f[0], f[1]) == pytest.approx(float(na @ nb), rel=1e-12, abs=1e-15)
        assert min(abs(_dot(f[0], f[4])), abs(_dot(f[1], f[4]))) == pytest.approx(
            _step_apart(na, nb, xa, xb), rel=1e-12, abs=1e-15)
        assert _crossing_angle_f(f[0], f[1], f[4]) == pytest.approx(
            _crossing_angle(na, nb, dx), rel=1e-9, abs=1e-6)
        assert _sanity_limit_f(f[0], f[1], 60.0) == pytest.approx(
            _sanity_limit(na, nb, 60.0), rel=1e-9, abs=1e-9)
    assert _crossing_angle_f([0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]) == 90.0


def test_percentiles_from_the_tails_are_numpys_and_fall_back_when_a_tail_is_short():
    """percentiles_2_98 at and above _TAILS_MIN values (the two tails beyond sampled pivots,
    _tails) against np.percentile float for float: random, sorted both ways, sawtooth rows
    (an image's row-major order), ties, outliers; and the cases where a tail holds too few
    (values tied with a pivot), where it selects in the whole array."""
    from planerel.features._relation_kernels import _TAILS_MIN, _tails, percentiles_2_98

    rng = np.random.default_rng(31)
    short = 0
    for n in (_TAILS_MIN, _TAILS_MIN + 1, 777, 1000, 4001, 16384):
        rows = np.tile(np.linspace(-1, 1, 37), n // 37 + 1)[:n] + np.repeat(np.arange(n // 37 + 1), 37)[:n]
        cases = [rng.normal(size=n), np.sort(rng.normal(size=n)), np.sort(rng.normal(size=n))[::-1],
                 rows, rows[::-1], np.round(rng.normal(size=n), 1), rng.integers(0, 3, n).astype(float),
                 np.zeros(n), np.r_[np.zeros(n - 3), 1e9, -1e9, 5.0],
                 np.r_[np.full(n // 2, 0.5), rng.normal(size=n - n // 2)]]
        for x in cases:
            x = np.ascontiguousarray(x, dtype=float)
            assert percentiles_2_98(x).tolist() == np.percentile(x, [2.0, 98.0]).tolist()
            k_lo, k_hi = int(np.floor((n - 1) * 0.02)), int(np.floor((n - 1) * 0.98))
            got = _tails(x.copy(), k_lo, k_hi)
            if got[4]:
                s = np.sort(x)
                assert got[:4] == (s[k_lo], s[k_lo + 1], s[k_hi], s[k_hi + 1])
            else:
                short += 1
    assert short >= 6  # the constant and three-valued arrays at least


def test_linspace_kernel_is_numpys_float_for_float():
    from planerel.features._relation_kernels import linspace

    rng = np.random.default_rng(41)
    for _ in range(3000):
        a, b = (float(v) for v in rng.normal(size=2) * rng.choice([1e-3, 1.0, 1e3]))
        if rng.random() < 0.1:
            b = a
        num = int(rng.integers(0, 40))
        want = np.linspace(a, b, num)
        got = linspace(a, b, num)
        assert got.shape == want.shape and np.array_equal(got.view(np.int64), want.view(np.int64))
    tiny = np.linspace(0.0, 5e-324, 7)  # a zero step (gh-5437's path)
    assert np.array_equal(linspace(0.0, 5e-324, 7), tiny)


def test_window_outlines_are_the_outline_of_the_window_copy():
    from planerel.features._relation_kernels import window_outlines
    from planerel.segment._label_kernels import label_boundary

    rng = np.random.default_rng(31)
    for case in range(300):
        H, W = int(rng.integers(1, 25)), int(rng.integers(1, 25))
        k = int(rng.integers(1, 5))
        lab = rng.integers(-1, k, (H, W)).astype(np.int32)
        if case % 2:  # blocks, as planes are
            lab = np.repeat(np.repeat(lab[: (H + 2) // 3, : (W + 2) // 3], 3, 0), 3, 1)[:H, :W]
            lab = np.ascontiguousarray(lab)
        r0, r1 = sorted(int(v) for v in rng.integers(0, H + 1, 2))
        c0, c1 = sorted(int(v) for v in rng.integers(0, W + 1, 2))
        a, b = int(rng.integers(-1, k)), int(rng.integers(-1, k))
        w = lab[r0:r1, c0:c1]
        pa, pb = window_outlines(lab, r0, c0, r1, c1, a, b)
        if w.size:
            edge = label_boundary(np.ascontiguousarray(w))
            want_a, want_b = np.argwhere(edge & (w == a)), np.argwhere(edge & (w == b))
        else:
            want_a = want_b = np.zeros((0, 2), np.int64)
        assert pa.dtype == np.int64 and pa.shape == want_a.shape and (pa == want_a).all(), case
        assert pb.shape == want_b.shape and (pb == want_b).all(), case


def test_gaps_between_uses_the_window_outlines():
    from planerel.features import gaps

    rng = np.random.default_rng(8)
    for case in range(40):
        H, W = 30, 40
        lab = np.full((H, W), -1, np.int32)
        lab[2:12, 3:15] = 1
        lab[int(rng.integers(14, 20)):28, int(rng.integers(16, 25)):38] = 2
        lab[12:14, 10:30] = 3  # something between them
        gx, gy = np.meshgrid(np.arange(W) * 0.01, np.arange(H) * 0.01)
        xyz = np.dstack([gx, gy, np.ones((H, W))])
        xyz[..., 2] += rng.normal(0, 0.05, (H, W))
        xyz[lab == 3, 2] -= 0.3
        xyz[rng.random((H, W)) < 0.05] = np.nan
        box = (0, 0, 30, 40) if case % 2 else (1, 2, 29, 39)
        got = gaps._between(lab, xyz, 1, 2, 5, 100, box, fast=bool(case % 3))
        want = gaps._between(lab.astype(np.int64), xyz, 1, 2, 5, 100, box, fast=bool(case % 3))
        assert len(got) == len(want)
        for (r, n, f), (r2, n2, f2) in zip(got, want, strict=True):
            assert n == n2 and f == f2 and np.array_equal(r, r2)
        assert gaps.gap_in_front(lab, xyz, 1, 2, window=box) == gaps.gap_in_front(
            lab.astype(np.int64), xyz, 1, 2, window=box)
        assert gaps.gap_behind(lab, xyz, 1, 2) == gaps.gap_behind(lab.astype(np.int64), xyz, 1, 2)


def test_range_at_is_numpys_norm():
    from planerel.features.gaps import _range_at

    rng = np.random.default_rng(2)
    xyz = rng.normal(0, 1, (40, 50, 3)) * 10.0 ** rng.integers(-3, 3, (40, 50, 1))
    xyz[rng.random((40, 50)) < 0.1] = np.nan
    xyz[0, 0, 1] = np.inf
    for r in range(40):
        for c in range(50):
            want = float(np.linalg.norm(np.asarray(xyz[r, c], float), axis=-1))
            got = _range_at(xyz, r, c)
            assert got == want or (np.isnan(got) and np.isnan(want)), (r, c)
    x32 = xyz.astype(np.float32)
    for r in range(40):
        for c in range(50):
            want = float(np.linalg.norm(np.asarray(x32[r, c], float), axis=-1))
            got = _range_at(x32, r, c)
            assert got == want or (np.isnan(got) and np.isnan(want)), (r, c)
