"""Normals: accuracy on planes, orientation, NaN holes, depth jumps, k-NN PCA."""

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.io.cloud import Cloud, Intrinsics
from planerel.segment.normals import estimate_normals, knn_normals, organized_normals


def _raycast_planes(planes, width=80, height=60, rng=None, noise=0.0):
    """Ray-cast ``planes`` [(normal, offset, column_range)] into an organized (H, W, 3) cloud:
    plane i is seen in the columns of its range."""
    intr = Intrinsics.kinect(width, height)
    v, u = np.mgrid[0:height, 0:width].astype(float)
    d = np.stack([(u - intr.cx) / intr.fx, (v - intr.cy) / intr.fy, np.ones_like(u)], -1)
    xyz = np.full((height, width, 3), np.nan)
    for n, off, cols in planes:
        n = np.asarray(n, float) / np.linalg.norm(n)
        t = -off / (d @ n)
        pts = d * t[..., None]
        sl = slice(*cols)
        xyz[:, sl] = pts[:, sl]
    if noise:
        z = xyz[..., 2]
        xyz *= ((z + rng.standard_normal(z.shape) * noise * z**2) / z)[..., None]
    return Cloud(xyz, intr)


def _angles(n, truth):
    c = np.clip(np.abs(n.reshape(-1, 3) @ truth), 0, 1)
    return np.degrees(np.arccos(c))


def test_tilted_plane_normals_are_accurate_and_face_the_sensor():
    truth = np.array([0.0, 0.6, -0.8])  # floor-like, towards the camera
    cloud = _raycast_planes([(truth, 1.5, (0, 80))])
    n = estimate_normals(cloud)
    ok = np.isfinite(n).all(axis=2)
    assert ok.mean() > 0.99
    assert _angles(n[ok], truth).max() < 0.5
    dots = np.einsum("hwi,hwi->hw", n, cloud.xyz)[ok]
    assert np.all(dots < 0)
    assert np.allclose(np.linalg.norm(n[ok], axis=1), 1.0)


def test_noisy_plane_normals_within_a_few_degrees():
    truth = np.array([0.2, 0.3, -0.93])
    cloud = _raycast_planes([(truth, 2.0, (0, 160))], width=160, height=120,
                            rng=np.random.default_rng(3), noise=0.0012)
    n = organized_normals(cloud.xyz, intrinsics=cloud.intrinsics)
    a = _angles(n[np.isfinite(n).all(axis=2)], truth / np.linalg.norm(truth))
    assert np.median(a) < 4.0
    assert np.percentile(a, 95) < 12.0


def test_step_edge_is_not_averaged_across():
    # two fronto-parallel planes, left half at 1.0 m and right half at 1.6 m: a depth jump
    front = np.array([0.0, 0.0, -1.0])
    cloud = _raycast_planes([(front, 1.0, (0, 40)), (front, 1.6, (40, 80))])
    n = organized_normals(cloud.xyz, smooth=2, radius=2, intrinsics=cloud.intrinsics)
    ok = np.isfinite(n).all(axis=2)
    assert ok[:, 36:44].all(), "pixels next to the jump keep a normal (one-sided differences)"
    assert _angles(n[ok], front).max() < 1e-3


def test_nan_holes_give_nan_normals_and_do_not_spoil_neighbours():
    truth = np.array([0.0, 0.6, -0.8])
    cloud = _raycast_planes([(truth, 1.5, (0, 80))])
    xyz = cloud.xyz.copy()
    xyz[20:25, 30:35] = np.nan
    xyz[::7, ::5] = np.nan
    holey = Cloud(xyz, cloud.intrinsics)
    n = estimate_normals(holey)
    assert np.isnan(n[22, 32]).all()
    ok = np.isfinite(n).all(axis=2)
    assert ok.sum() > 0.9 * holey.n_valid
    assert _angles(n[ok], truth).max() < 0.5


def test_knn_normals_unorganized_plane():
    rng = np.random.default_rng(0)
    pts = np.column_stack([rng.uniform(-1, 1, 500), rng.uniform(-1, 1, 500), np.full(500, 2.0)])
    pts[:, 2] += 0.3 * pts[:, 0]
    truth = np.array([0.3, 0.0, -1.0]) / np.linalg.norm([0.3, 0.0, -1.0])
    n = knn_normals(pts, k=12)
    assert _angles(n, truth).max() < 1e-3
    assert np.all(np.einsum("ij,ij->i", n, pts) < 0)
    cloud = Cloud(pts[None], organized=False)
    assert estimate_normals(cloud, k=8).shape == (1, 500, 3)


def test_bad_normal_inputs_are_named():
    with pytest.raises(InputError, match=r"shape \(H, W, 3\)"):
        organized_normals(np.zeros((4, 4)))
    with pytest.raises(InputError, match="radius"):
        organized_normals(np.zeros((4, 4, 3)), radius=0)
    with pytest.raises(InputError, match="jump_factor"):
        organized_normals(np.zeros((4, 4, 3)), jump_factor=float("nan"))
    with pytest.raises(InputError, match="unknown parameter"):
        estimate_normals(Cloud(np.ones((2, 2, 3))), k=3)


def _reference_normals(xyz, s0, r0, zref, smax, rmax, jpz):
    """The organized normals as docs/segmentation.md defines them, written for reading: runs
    cut at NaN and depth jumps, a depth-scaled box average (rows, then columns) clipped to the
    runs, central differences clipped to the runs, n = t_v x t_u towards the sensor."""
    h, w, _ = xyz.shape
    z = xyz[..., 2]
    ok = ~np.isnan(z)

    def joined(a, b):
        return ok[a] and ok[b] and abs(z[a] - z[b]) <= jpz * min(z[a], z[b])

    def size(zz, base, lo, hi):
        k = int(zz * (base / zref if zref > 0 else 0.0) + 0.5)
        return min(max(k, lo), hi)

    rs = np.full((h, w), -1)
    re = np.full((h, w), -1)
    cs = np.full((h, w), -1)
    ce = np.full((h, w), -1)
    for v in range(h):
        for u in range(w):
            if ok[v, u]:
                rs[v, u] = rs[v, u - 1] if u > 0 and joined((v, u - 1), (v, u)) else u
                cs[v, u] = cs[v - 1, u] if v > 0 and joined((v - 1, u), (v, u)) else v
    for v in range(h - 1, -1, -1):
        for u in range(w - 1, -1, -1):
            if ok[v, u]:
                re[v, u] = re[v, u + 1] if u + 1 < w and joined((v, u + 1), (v, u)) else u
                ce[v, u] = ce[v + 1, u] if v + 1 < h and joined((v + 1, u), (v, u)) else v
    smin, rmin = int(s0 + 0.5), max(1, int(r0 + 0.5))
    hsum = np.zeros((h, w, 4))
    for v in range(h):
        for u in range(w):
            if ok[v, u]:
                s = size(z[v, u], s0, smin, smax)
                lo, hi = max(u - s, rs[v, u]), min(u + s, re[v, u])
                hsum[v, u, :3] = xyz[v, lo:hi + 1].sum(axis=0)
                hsum[v, u, 3] = hi - lo + 1
    sm = np.full((h, w, 3), np.nan)
    for v in range(h):
        for u in range(w):
            if ok[v, u]:
                s = size(z[v, u], s0, smin, smax)
                lo, hi = max(v - s, cs[v, u]), min(v + s, ce[v, u])
                t = hsum[lo:hi + 1, u].sum(axis=0)
                sm[v, u] = t[:3] / t[3]
    out = np.full((h, w, 3), np.nan)
    for v in range(h):
        for u in range(w):
            if not ok[v, u]:
                continue
            r = size(z[v, u], r0, rmin, rmax)
            ur, ul = min(u + r, re[v, u]), max(u - r, rs[v, u])
            vd, vu = min(v + r, ce[v, u]), max(v - r, cs[v, u])
            if ur == ul or vd == vu:
                continue
            n = np.cross(sm[vd, u] - sm[vu, u], sm[v, ur] - sm[v, ul])
            if np.linalg.norm(n) == 0:
                continue
            n /= np.linalg.norm(n)
            out[v, u] = -n if n @ xyz[v, u] > 0 else n
    return out


@pytest.mark.parametrize("radius,reference_depth", [(1, 2.0), (2, 2.0), (1, None)])
def test_streamed_normals_match_the_definition(radius, reference_depth):
    """The compiled kernel (streamed through ring buffers) against the plain statement: steps
    (depth jumps), holes, a far slanted floor (windows grow with depth) and image borders."""
    rng = np.random.default_rng(4)
    cloud = _raycast_planes([((0, 0, -1), 1.6, (0, 20)), ((0, 0, -1), 2.4, (20, 45)),
                             ((0.3, 0.9, -0.4), 2.2, (45, 80))], rng=rng, noise=0.002)
    xyz = np.array(cloud.xyz)
    xyz[rng.random(xyz.shape[:2]) < 0.04] = np.nan
    xyz[20:24, 30:38] = np.nan
    args = dict(smooth=radius, radius=radius, reference_depth=reference_depth)
    got = organized_normals(xyz, intrinsics=cloud.intrinsics, **args)
    from planerel.segment.normals import normal_kernel_args

    s0, r0, zref, smax, rmax, jpz = normal_kernel_args(np.ascontiguousarray(xyz),
                                                       intrinsics=cloud.intrinsics, **args)
    want = _reference_normals(xyz, s0, r0, zref, smax, rmax, jpz)
    np.testing.assert_array_equal(np.isnan(got), np.isnan(want))
    ok = ~np.isnan(want[..., 0])
    assert ok.mean() > 0.8
    np.testing.assert_allclose(got[ok], want[ok], atol=2e-5)
