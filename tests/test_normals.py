"""Normals: accuracy on planes, orientation, NaN holes, depth jumps, k-NN PCA."""

import numpy as np
import pytest

from planerel.cloud import Cloud, Intrinsics
from planerel.errors import InputError
from planerel.normals import estimate_normals, knn_normals, organized_normals


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
