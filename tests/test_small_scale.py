"""``RegionGrowParams.small_scale`` (small64; on by default since small99, 0.35, but only where
the camera looks down at least ``small_pitch`` 60 degrees, which :mod:`test_small_pitch` tests;
here with ``small_pitch`` 0, on every frame): a second growing with a smaller
minimum region size adds planes only where the first left depth nearer than ``far_depth`` in no
plane, and only those standing parallel over another plane or, with ``small_corners``, meeting
one at a corner; nothing already in a plane changes."""

from __future__ import annotations

import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
import independent_scenes as ind  # noqa: E402

from planerel.errors import InputError  # noqa: E402
from planerel.io.cloud import Cloud  # noqa: E402
from planerel.segment import _noise_sigma, _small_kept, segment  # noqa: E402
from planerel.segment.params import RegionGrowParams  # noqa: E402


@pytest.fixture(scope="module")
def small_boxes():
    """dev_small's scene 6 (``independent_scenes.py dev``): four small boxes (3-12 cm) on a
    table seen by a Kinect-like sensor from under a metre; box 3's thin side face (about 360
    pixels) is too small for the first growing."""
    return _scene(6, 6401, "small_box")


def _scene(index, seed, kind):
    """``independent_scenes.py``'s scene ``index`` of ``seed`` with one ``kind``, seen by the
    Kinect-like sensor at 640x480: ``(cloud, truth (H, W) object ids)``."""
    return _scene_side(index, seed, kind)[:2]


def _scene_side(index, seed, kind, heights=None):
    """:func:`_scene` with the camera's eye ``heights`` (``independent_scenes.camera_pose``)
    and the scene's sidecar (its ``objects`` with their kinds): ``(cloud, truth, side)``."""
    xyz, truth, side, *_ = ind.make_scene(index, seed, (640, 480), kinds=(kind,),
                                          sensor="kinect", heights=heights)
    intr = side["intrinsics"]
    cloud = Cloud(xyz, (intr["width"], intr["height"], intr["fx"], intr["fy"], intr["cx"],
                        intr["cy"]), side["up"])
    return cloud, truth, side


def test_small_scale_needs_the_up_by_default(small_boxes):
    # on by default for steep views only: with no up to judge the view by, no small pass
    cloud, _ = small_boxes
    assert RegionGrowParams().small_scale == 0.35 and RegionGrowParams().small_pitch == 60.0
    seg = segment(cloud)
    assert "small_planes" not in seg.info and seg.info["view_pitch"] is None
    np.testing.assert_array_equal(seg.labels, segment(cloud, small_scale=0.0).labels)


def test_small_planes_fill_only_near_depth_left_in_no_plane(small_boxes):
    cloud, truth = small_boxes
    a = segment(cloud)
    b = segment(cloud, small_scale=0.35, small_corners=True, small_pitch=0.0)
    added = b.info["small_planes"]
    assert added >= 1
    assert len(b.planes) == len(a.planes) + added
    kept = a.labels >= 0
    np.testing.assert_array_equal(b.labels[kept], a.labels[kept])  # nothing planed moves
    new = b.labels >= len(a.planes)
    assert not (new & kept).any()
    z = np.nan_to_num(np.asarray(cloud.xyz[..., 2], float))
    assert (z[new] <= RegionGrowParams().far_depth).all()
    # box 3's side face, in no plane before, is one plane now
    side = (truth == 3) & ~kept
    assert side.sum() > 200
    labs, counts = np.unique(b.labels[side], return_counts=True)
    assert labs[np.argmax(counts)] >= len(a.planes) and counts.max() >= 0.9 * side.sum()


def test_small_planes_are_deterministic(small_boxes):
    cloud, _ = small_boxes
    np.testing.assert_array_equal(segment(cloud, small_scale=0.35, small_pitch=0.0).labels,
                                  segment(cloud, small_scale=0.35, small_pitch=0.0).labels)


def _patch_scene():
    """A floor (plane 0, normal z) and three candidate patches on a 40 x 60 grid: 1 a wall
    standing on the floor's edge (90 degrees), 2 a patch tilted 20 degrees off the floor on
    the same edge (10 rows from the wall), 3 a lone patch touching nothing."""
    h, w = 40, 60
    yy, xx = np.mgrid[0:h, 0:w].astype(float) * 0.01
    xyz = np.zeros((h, w, 3))
    xyz[..., 0], xyz[..., 1] = xx, yy
    out = np.full((h, w), -1, np.int32)
    out[:, :20] = 0
    out[:15, 20:30] = 1
    xyz[:15, 20:30, 2] = (xx[:15, 20:30] - 0.2) * 50  # near vertical
    out[25:, 20:30] = 2
    xyz[25:, 20:30, 2] = (xx[25:, 20:30] - 0.2) * np.tan(np.radians(20))
    out[10:20, 45:55] = 3
    xyz[10:20, 45:55, 2] = (xx[10:20, 45:55]) * 50
    seg = SimpleNamespace(planes=[SimpleNamespace(id=0, normal=np.array([0.0, 0.0, 1.0]),
                                                  centroid=np.array([0.1, 0.2, 0.0]), rms=0.001)],
                          info={})
    return SimpleNamespace(xyz=xyz), seg, out


def test_only_planes_at_a_corner_are_kept():
    cloud, seg, out = _patch_scene()
    lab, kept = _small_kept(cloud, seg, out, 3)
    assert kept == 1
    np.testing.assert_array_equal(lab == 1, out == 1)  # the wall meets the floor at 90 degrees
    assert not np.isin(lab, [2, 3]).any()  # the shallow patch and the lone one are dropped
    assert ((lab == -1) == ((out == -1) | (out >= 2))).all()


def _own_plane(labels, truth):
    """How many objects of ``truth`` (H, W; 0 none) hold a plane of their own: at least 30 %
    of the object's pixels in one plane lying for 80 % or more in it."""
    n = 0
    for t in np.unique(truth[truth > 0]):
        m = truth == t
        labs, counts = np.unique(labels[m], return_counts=True)
        n += any(lab >= 0 and c >= 0.3 * m.sum() and c >= 0.8 * (labels == lab).sum()
                 for lab, c in zip(labs, counts, strict=True))
    return n


def test_block_tops_seen_from_above_get_their_planes():
    # dev_tote's kind: 19 toy blocks and cartons in a tote seen from 0.6-0.9 m above; the
    # small tops the first growing drops, or merges into the block under them, are planes
    cloud, truth = _scene(1, 6801, "tote_blocks")
    a, b = segment(cloud), segment(cloud, small_scale=0.35, small_pitch=0.0)
    assert b.info["small_planes"] >= 3
    assert _own_plane(b.labels, truth) >= _own_plane(a.labels, truth) + 3
    kept = a.labels >= 0
    np.testing.assert_array_equal(b.labels[kept], a.labels[kept])


def test_a_frame_with_no_measured_noise_is_judged_by_the_sensor_model():
    # a Kinect's quantised depth warped onto colour measures no noise (hunt67's armlab
    # frames): with no model every candidate's fit was infinite, so no small plane was added
    from planerel.segment.split import SplitParams

    none = SimpleNamespace(info={"noise_model": {"kind": "none", "const_m": 0.0,
                                                 "quad_per_m": 0.0}})
    assert _noise_sigma(none)(1.0) == 0.0
    sp = SplitParams()
    assert _noise_sigma(none, sp)(1.0) == pytest.approx(float(np.sqrt(sp.depth_sigma2(1.0))))
    measured = SimpleNamespace(info={"noise_model": {"const_m": 0.0003, "quad_per_m": 0.0004}})
    assert _noise_sigma(measured, sp)(2.0) == pytest.approx(float(np.hypot(0.0003, 0.0016)))


@pytest.mark.parametrize("rise, kept", [(0.02, True), (0.0015, False)])
def test_a_small_top_standing_over_a_plane_is_kept(rise, kept):
    # a block's top seen from straight above: parallel to the board, its sides hidden, a
    # ring of edge pixels in no plane between them (hunt67); a patch at the board's level
    # within the noise is no top
    h, w = 40, 40
    yy, xx = np.mgrid[0:h, 0:w].astype(float) * 0.01
    rng = np.random.default_rng(0)
    xyz = np.stack([xx, yy, rng.normal(0, 0.0005, (h, w))], -1)
    out = np.zeros((h, w), np.int32)
    out[14:26, 14:26] = -1                      # the ring
    out[17:23, 17:23] = 1
    xyz[17:23, 17:23, 2] += rise
    seg = SimpleNamespace(planes=[SimpleNamespace(id=0, normal=np.array([0.0, 0.0, 1.0]),
                                                  centroid=np.array([0.2, 0.2, 0.0]),
                                                  rms=0.0005)],
                          info={"settings": {"normal_smooth": 2, "normal_radius": 1}})
    lab, n = _small_kept(SimpleNamespace(xyz=xyz), seg, out, 1)
    assert n == int(kept)
    assert ((lab == 1) == ((out == 1) & kept)).all()


@pytest.mark.parametrize("bad", ["x", 1, None])
def test_small_corners_must_be_a_switch(bad):
    with pytest.raises(InputError, match="small_corners must be true or false"):
        RegionGrowParams(small_corners=bad)


@pytest.mark.parametrize("bad", [-0.1, 1.5, "x", True])
def test_small_scale_must_be_a_factor(bad):
    with pytest.raises(InputError, match="small_scale"):
        RegionGrowParams(small_scale=bad)
