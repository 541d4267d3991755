"""planerel's planar post-processing after region growing: planes in unassigned patches
(split.py, ``leftover``) and merging touching coplanar regions (merge.py), and how
:func:`segment` applies them."""

import math

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.io.cloud import Cloud, Intrinsics
from planerel.segment import segment
from planerel.segment.evaluate import evaluate
from planerel.segment.merge import merge_coplanar
from planerel.segment.result import Segmentation, SegPlane, fit_planes
from planerel.segment.split import SplitParams, split_bent_regions
from planerel.synth.generator import CameraRange, generate_scene, scene_seed

# held-out-like stairs: a low camera, the top steps 3 m away and 3-8 pixels high at 160x120
FAR = CameraRange(height=(0.7, 1.7), distance=(1.0, 2.2))


def _far_stairs(i):
    return generate_scene("stairs", scene_seed(1000, i), (640, 480), 4, camera=FAR)


def _with_labels(cloud, labels):
    n = int(labels.max()) + 1
    nrm, off, cnt, cen, rms = fit_planes(cloud.xyz.reshape(-1, 3), labels.reshape(-1), n)
    planes = tuple(SegPlane(i, nrm[i], off[i], int(cnt[i]), cen[i], rms[i]) for i in range(n))
    return Segmentation(labels.astype(np.int32), planes, "regiongrow", None, None,
                        {"min_region_size": 90})


def _check(seg, shape):
    assert seg.labels.dtype == np.int32 and seg.labels.shape == shape
    assert set(np.unique(seg.labels)) - {-1} == set(range(seg.n_planes))
    for i, p in enumerate(seg.planes):
        assert p.id == i and p.n_points == int((seg.labels == i).sum())


@pytest.mark.parametrize("i", [13, 14, 18])
def test_leftover_recovers_far_stair_planes(i):
    sc = _far_stairs(i)
    # the fixed settings (preset kinect): which planes growing misses depends on the minimum
    # region size, and this test is about the leftover step
    off = segment(sc.cloud, split_params=SplitParams(leftover=False), preset="kinect")
    on = segment(sc.cloud, preset="kinect")
    _check(on, sc.cloud.shape)
    assert on.info["leftover_regions"] >= 2
    before = evaluate(off.labels, sc.gt_labels)
    after = evaluate(on.labels, sc.gt_labels)
    # the far risers and treads were missed by region growing; the leftover step finds them
    # and does not make planes across several steps
    assert after.correct >= before.correct + 1
    assert after.missed < before.missed
    assert after.noise <= before.noise + 1
    assert after.under == 0


def test_leftover_leaves_noise_alone():
    # a patch of random points (no plane) next to one grown plane: nothing new is made of it
    rng = np.random.default_rng(0)
    h, w = 120, 160
    intr = Intrinsics.kinect(w, h)
    u, v = np.meshgrid(np.arange(w), np.arange(h))
    z = np.full((h, w), 2.0)
    z[:, 80:] = rng.uniform(1.5, 3.0, size=(h, 80))
    xyz = np.stack([(u - intr.cx) / intr.fx * z, (v - intr.cy) / intr.fy * z, z], axis=2)
    cloud = Cloud(xyz, intr)
    labels = np.full((h, w), -1, dtype=np.int32)
    labels[:, :80] = 0
    out = split_bent_regions(cloud, _with_labels(cloud, labels))
    assert out.info["leftover_patches"] == 1
    assert out.info["leftover_regions"] == 0
    assert out.n_planes == 1 and np.array_equal(out.labels, labels)


def _plane_halves(gap_cols=0, step=0.0, tilt_deg=0.0):
    """A fronto-parallel wall 2 m away (Kinect-like noise) labelled as two regions, left and
    right; the right half moved ``step`` metres back or turned by ``tilt_deg``."""
    rng = np.random.default_rng(1)
    h, w = 120, 160
    intr = Intrinsics.kinect(w, h)
    u, v = np.meshgrid(np.arange(w), np.arange(h))
    x = (u - intr.cx) / intr.fx
    y = (v - intr.cy) / intr.fy
    z = np.full((h, w), 2.0)
    right = u >= 80
    t = math.tan(math.radians(tilt_deg))
    z[right] = 2.0 + step + t * (x[right] * 2.0)
    z = z + rng.normal(0, 0.0012 * z ** 2)
    z = np.round(z, 3)
    xyz = np.stack([x * z, y * z, z], axis=2)
    cloud = Cloud(xyz, intr)
    labels = np.where(right, 1, 0).astype(np.int32)
    if gap_cols:
        labels[:, 80 - gap_cols:80] = -1
    return cloud, labels


def test_merge_joins_two_halves_of_one_plane():
    cloud, labels = _plane_halves(gap_cols=1)  # one unassigned column: 2 pixels apart
    out = merge_coplanar(cloud, _with_labels(cloud, labels))
    _check(out, labels.shape)
    assert out.info["merged"] == 1 and out.n_planes == 1
    assert abs(out.planes[0].normal[2]) > 0.999


@pytest.mark.parametrize("kw", [dict(step=0.08), dict(tilt_deg=20.0)])
def test_merge_keeps_different_planes_apart(kw):
    cloud, labels = _plane_halves(**kw)
    seg = _with_labels(cloud, labels)
    out = merge_coplanar(cloud, seg)
    assert out.info["merged"] == 0 and out.n_planes == 2
    assert np.array_equal(out.labels, labels)


def _board_with_block(h=240, w=320, rise=0.03, side=16):
    """A board 1 m under a camera looking straight down (Kinect-like noise), labelled 0, and a
    ``side`` x ``side`` px block top ``rise`` m nearer in its middle, labelled 1, with one
    unassigned pixel ring between them (the block's edge)."""
    rng = np.random.default_rng(3)
    intr = Intrinsics.kinect(w, h)
    u, v = np.meshgrid(np.arange(w), np.arange(h))
    x = (u - intr.cx) / intr.fx
    y = (v - intr.cy) / intr.fy
    top = (np.abs(u - w // 2) < side // 2) & (np.abs(v - h // 2) < side // 2)
    ring = (np.abs(u - w // 2) <= side // 2) & (np.abs(v - h // 2) <= side // 2) & ~top
    z = np.where(top, 1.0 - rise, 1.0) + rng.normal(0, 0.0012, (h, w))
    cloud = Cloud(np.stack([x * z, y * z, z], axis=2), intr)
    labels = np.where(top, 1, np.where(ring, -1, 0)).astype(np.int32)
    return cloud, labels


def test_merge_keeps_a_small_top_off_the_large_plane_under_it():
    """tote67: a 16 x 16 px block top 3 cm over a large board touches it across its edge; the
    union's RMS is the board's, so the pooled test alone (the default) merges them.  With
    ``merge_side`` each side must fit the union's plane too."""
    cloud, labels = _board_with_block()
    side = SplitParams(merge_side=3.0)
    out = merge_coplanar(cloud, _with_labels(cloud, labels), side)
    assert out.n_planes == 2 and np.array_equal(out.labels, labels)
    pooled = merge_coplanar(cloud, _with_labels(cloud, labels), SplitParams(merge_side=0.0))
    assert pooled.n_planes == 1  # the pooled test alone: the top joins the board
    # the same board with the "top" level with it (one surface cut by a ring) still merges
    flat, lab = _board_with_block(rise=0.0)
    assert merge_coplanar(flat, _with_labels(flat, lab), side).n_planes == 1


def test_the_side_test_holds_for_small_tops_only_with_a_span():
    """span91: with ``merge_side_span`` the side test holds for a pair whose smaller region
    spans at most that (its largest in-plane std): a 6 cm block's top (16 px at 1 m, std
    1.8 cm) stays off the board 3 cm under it; a 19 cm top (a book, a laptop's base: 50 px,
    std 5.5 cm) 1 cm over it merges by the pooled test as without the side test, and with
    span 0 (every pair) it stays apart."""
    span = SplitParams(merge_side=3.0, merge_side_span=0.02)
    cloud, labels = _board_with_block()
    assert merge_coplanar(cloud, _with_labels(cloud, labels), span).n_planes == 2
    cloud, labels = _board_with_block(rise=0.01, side=50)
    pooled = merge_coplanar(cloud, _with_labels(cloud, labels), SplitParams(merge_side=0.0))
    assert pooled.n_planes == 1
    assert merge_coplanar(cloud, _with_labels(cloud, labels), span).n_planes == 1
    every = SplitParams(merge_side=3.0, merge_side_span=0.0)
    assert merge_coplanar(cloud, _with_labels(cloud, labels), every).n_planes == 2
    with pytest.raises(InputError, match="merge_side_span"):
        SplitParams(merge_side_span=-0.01)


def test_merge_needs_regions_to_touch():
    cloud, labels = _plane_halves(gap_cols=4)  # 5 pixels apart: more than merge_gap = 2
    out = merge_coplanar(cloud, _with_labels(cloud, labels))
    assert out.n_planes == 2
    wide = merge_coplanar(cloud, _with_labels(cloud, labels), SplitParams(merge_gap=6))
    assert wide.n_planes == 1
    off = merge_coplanar(cloud, _with_labels(cloud, labels), SplitParams(merge=False, merge_gap=6))
    assert off.n_planes == 2


def test_segment_applies_post_processing_to_regiongrow_only():
    sc = _far_stairs(13)
    plain = segment(sc.cloud, split=False)
    post = segment(sc.cloud)
    assert post.n_planes > plain.n_planes
    assert "leftover_regions" in post.info and "merged" in post.info
    assert "leftover_regions" not in plain.info
    sp = segment(sc.cloud, "sp", threshold=0.03)
    assert "merged" not in sp.info
    assert np.array_equal(segment(sc.cloud, split="false").labels, plain.labels)
    # deterministic
    again = segment(sc.cloud)
    assert np.array_equal(again.labels, post.labels) and again.info == post.info
    with pytest.raises(InputError, match="split must be true or false"):
        segment(sc.cloud, split="maybe")


@pytest.mark.parametrize("kw,match", [
    (dict(merge="yes"), "merge"),
    (dict(merge_angle=-1.0), "merge_angle"),
    (dict(merge_gap=0), "merge_gap"),
    (dict(merge_jump=0.0), "merge_jump"),
    (dict(leftover=1), "leftover"),
])
def test_bad_post_processing_parameters(kw, match):
    with pytest.raises(InputError, match=match):
        SplitParams(**kw)


# the leftover search down to half the minimum region (off by default; docs/objects.md, ninth pass)
HALF = SplitParams(leftover_scale=0.5)


def _wall_with_patch(patch_depth=None, side=8, seed=0):
    """A wall 2 m away (Kinect-like noise) labelled as one region, with a ``side`` x ``side``
    square left unassigned: a small planar box face 1.6 m away, or random depths."""
    rng = np.random.default_rng(seed)
    h, w = 120, 160
    intr = Intrinsics.kinect(w, h)
    u, v = np.meshgrid(np.arange(w), np.arange(h))
    z = np.full((h, w), 2.0)
    sq = (slice(50, 50 + side), slice(70, 70 + side))
    if patch_depth is None:
        z[sq] = rng.uniform(1.2, 1.8, size=(side, side))
    else:
        z[sq] = patch_depth
    z = z + rng.normal(0, 0.0012, size=z.shape) * z ** 2
    xyz = np.stack([(u - intr.cx) / intr.fx * z, (v - intr.cy) / intr.fy * z, z], axis=2)
    cloud = Cloud(xyz, intr)
    labels = np.zeros((h, w), dtype=np.int32)
    labels[sq] = -1
    return cloud, labels, sq


def test_leftover_keeps_small_planar_patch_down_to_half_the_minimum():
    # a 64-pixel face (minimum region 90): under the minimum, but over half of it, and its
    # points fit one plane within the noise: the leftover search makes it a region
    cloud, labels, sq = _wall_with_patch(1.6)
    out = split_bent_regions(cloud, _with_labels(cloud, labels), params=HALF)
    _check(out, labels.shape)
    assert out.info["leftover_patches"] == 1 and out.info["leftover_regions"] == 1
    assert out.n_planes == 2
    assert (out.labels[sq] == 1).mean() >= 0.9
    assert abs(abs(out.planes[1].normal[2]) - 1.0) < 0.02  # fronto-parallel, as built
    # the whole minimum (leftover_scale 1, the default) leaves it unassigned
    full = split_bent_regions(cloud, _with_labels(cloud, labels))
    assert full.info["leftover_patches"] == 0 and full.n_planes == 1
    assert np.array_equal(full.labels, labels)
    # under half the minimum (a 6 x 6 face, 36 pixels) it is not searched
    cloud6, labels6, _ = _wall_with_patch(1.6, side=6)
    small = split_bent_regions(cloud6, _with_labels(cloud6, labels6), params=HALF)
    assert small.info["leftover_patches"] == 0 and np.array_equal(small.labels, labels6)


def test_leftover_small_patch_of_noise_stays_unassigned():
    # the same 64 pixels at random depths: searched, no plane passes the planarity test
    cloud, labels, _ = _wall_with_patch(None)
    out = split_bent_regions(cloud, _with_labels(cloud, labels), params=HALF)
    assert out.info["leftover_patches"] == 1 and out.info["leftover_regions"] == 0
    assert np.array_equal(out.labels, labels)


@pytest.mark.parametrize("bad", [0.0, -0.5, 1.5, "half"])
def test_bad_leftover_scale(bad):
    with pytest.raises(InputError, match="leftover_scale"):
        SplitParams(leftover_scale=bad)


def test_leftover_small_piece_on_a_found_surface_is_dropped():
    # the 64 unassigned pixels lie on the wall's own plane (a bent corner of a real table on
    # mOSD is such a piece): planar, over half the minimum, but not a new surface
    cloud, labels, sq = _wall_with_patch(2.0)
    out = split_bent_regions(cloud, _with_labels(cloud, labels), params=HALF)
    assert out.info["leftover_patches"] == 1 and out.info["leftover_regions"] == 0
    assert np.array_equal(out.labels, labels)
    # 2 cm in front of the wall (1 % of the depth, within parallel_gap 2 %): still the wall's;
    # 10 cm in front: a face of its own
    for z, regions in ((1.98, 0), (1.9, 1)):
        cloud, labels, _ = _wall_with_patch(z)
        out = split_bent_regions(cloud, _with_labels(cloud, labels), params=HALF)
        assert out.info["leftover_regions"] == regions


def _hole_halves(step=0.0, fill_nan=True):
    """:func:`_plane_halves` with 8 columns between the halves: no depth (``fill_nan``) or
    valid points that no region holds."""
    cloud, labels = _plane_halves(gap_cols=8, step=step)
    xyz = cloud.xyz.copy()
    if fill_nan:
        xyz[:, 72:80] = np.nan
    return Cloud(xyz, cloud.intrinsics), labels


def test_hole_pairs_cross_missing_depth_only():
    from planerel.segment.merge import hole_pairs

    cloud, labels = _hole_halves()
    assert hole_pairs(labels, cloud.xyz, 4) == [(0, 1)]  # 8 columns: 4 grown from each side
    assert hole_pairs(labels, cloud.xyz, 3) == []  # too wide for 3
    assert hole_pairs(labels, cloud.xyz, 0) == []
    kept, lab = _hole_halves(fill_nan=False)  # valid unassigned pixels stop the growth
    assert hole_pairs(lab, kept.xyz, 10) == []


def test_hole_bridge_joins_a_plane_a_hole_cuts():
    cloud, labels = _hole_halves()
    seg = _with_labels(cloud, labels)
    assert merge_coplanar(cloud, seg).n_planes == 2  # off by default
    on = merge_coplanar(cloud, seg, SplitParams(hole_bridge=6))
    _check(on, labels.shape)
    assert on.n_planes == 1 and on.info["hole_pairs"] == 1
    # a step of a stair's rise across the hole stays two planes
    far, lab = _hole_halves(step=0.15)
    assert merge_coplanar(far, _with_labels(far, lab), SplitParams(hole_bridge=6)).n_planes == 2


def test_hole_bridge_is_checked():
    with pytest.raises(InputError, match="hole_bridge"):
        SplitParams(hole_bridge=-1)
