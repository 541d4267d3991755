"""``RegionGrowParams.small_pitch`` (small99; 60 by default, with ``small_scale`` 0.35): the
small pass (``small_scale``) only on a frame
whose camera looks down at least that steeply, by the up the scene is described with
(``segment``'s ``up``, :func:`planerel.features.facts.view_up`)."""

from __future__ import annotations

import numpy as np
import pytest
from test_small_scale import _scene

from planerel.errors import InputError
from planerel.features.facts import view_up
from planerel.io.cloud import Cloud
from planerel.segment import segment, view_pitch
from planerel.segment.params import RegionGrowParams


@pytest.fixture(scope="module")
def tote():
    """dev_tote's kind: toy blocks and cartons in a tote seen from 0.6-0.9 m above (the scene
    of test_small_scale's block tops), with its sidecar up."""
    cloud, truth = _scene(1, 6801, "tote_blocks")
    return cloud, truth


def test_view_pitch_reads_how_far_under_the_horizon_the_camera_looks():
    assert view_pitch((0, -1, 0)) == pytest.approx(0.0)              # level
    assert view_pitch((0, 0, -1)) == pytest.approx(90.0)             # straight down
    assert view_pitch((0, 0, 1)) == pytest.approx(-90.0)             # straight up
    s = np.sin(np.radians(30.0))
    assert view_pitch((0, -np.cos(np.radians(30.0)), -s)) == pytest.approx(30.0)
    assert view_pitch((0, -2, 0)) == pytest.approx(0.0)              # not unit: normalised
    for bad in ((0, 0, 0), (1.0, 2.0), (0, float("nan"), 1), "up"):
        with pytest.raises(InputError, match="up vector"):
            view_pitch(bad)


def test_a_bad_up_given_to_segment_is_the_user_s_mistake(tote):
    cloud, _ = tote
    with pytest.raises(InputError, match="up vector must be 3 finite numbers"):
        segment(cloud, small_pitch=60, up=(1.0, 2.0))


def test_the_small_pass_runs_only_where_the_camera_looks_down_steeply(tote):
    cloud, _ = tote
    pitch = view_pitch(cloud.up)
    assert pitch > 45  # the tote is seen from above
    plain = segment(cloud, small_scale=0.0)
    small = segment(cloud, small_scale=0.35, small_pitch=0.0)
    assert small.info["small_planes"] >= 3
    steep = segment(cloud, small_scale=0.35, small_pitch=pitch - 5, up=view_up(cloud))
    assert steep.info["view_pitch"] == pytest.approx(pitch, abs=0.01)
    np.testing.assert_array_equal(steep.labels, small.labels)
    assert steep.info["small_planes"] == small.info["small_planes"]
    # the same frame judged too shallow for the pass: the plain segmentation
    shallow = segment(cloud, small_scale=0.35, small_pitch=pitch + 5, up=view_up(cloud))
    assert "small_planes" not in shallow.info
    np.testing.assert_array_equal(shallow.labels, plain.labels)
    # the up given as a vector counts as well; no up at all: no pass (nothing to judge by)
    given = segment(cloud, small_scale=0.35, small_pitch=pitch - 5, up=cloud.up)
    np.testing.assert_array_equal(given.labels, small.labels)
    unknown = segment(cloud, small_scale=0.35, small_pitch=pitch - 5)
    assert unknown.info["view_pitch"] is None and "small_planes" not in unknown.info
    # small_pitch 0: the pass on every frame, whatever the up
    level = segment(cloud, small_scale=0.35, small_pitch=0.0, up=(0.0, -1.0, 0.0))
    np.testing.assert_array_equal(level.labels, small.labels)
    # the defaults (0.35, 60 degrees): this tote is seen 59.6 degrees down, just too shallow
    default = segment(cloud, up=view_up(cloud))
    assert default.info["view_pitch"] == pytest.approx(59.57, abs=0.01)
    np.testing.assert_array_equal(default.labels, plain.labels)


def test_the_default_small_pass_runs_on_a_tote_seen_73_degrees_down():
    cloud, _ = _scene(3, 6801, "tote_blocks")
    seg = segment(cloud, up=view_up(cloud))
    assert seg.info["view_pitch"] == pytest.approx(72.94, abs=0.01)
    assert "small_planes" in seg.info
    np.testing.assert_array_equal(seg.labels,
                                  segment(cloud, small_scale=0.35, small_pitch=0.0).labels)
    level = segment(cloud, up=(0.0, -1.0, 0.0))
    assert "small_planes" not in level.info and level.info["view_pitch"] == 0.0


def test_view_up_estimates_the_up_when_the_scan_gives_none(tote):
    cloud, _ = tote
    bare = Cloud(cloud.xyz, cloud.intrinsics)
    assert bare.up is None
    seg = segment(bare)
    est = view_up(bare)(seg)
    assert est.shape == (3,)
    angle = np.degrees(np.arccos(np.clip(float(est @ np.asarray(cloud.up, float)), -1, 1)))
    assert angle < 5.0  # the tote's floor and rims give gravity
    # a given up wins over the scan's own and over the estimate
    assert np.allclose(view_up(cloud, (0.0, -1.0, 0.0))(seg), (0.0, -1.0, 0.0))
    assert np.allclose(view_up(cloud)(seg), np.asarray(cloud.up, float) / np.linalg.norm(cloud.up))


@pytest.mark.parametrize("bad", [-1, 91, "x", True])
def test_small_pitch_must_be_degrees_from_0_to_90(bad):
    with pytest.raises(InputError, match="small_pitch"):
        RegionGrowParams(small_pitch=bad)


def test_the_package_functions_judge_the_view_by_the_scan_s_up():
    import planerel

    cloud, _ = _scene(3, 6801, "tote_blocks")   # 73 degrees down, its sidecar up
    seg = planerel.segment(cloud)
    assert "small_planes" in seg.info
    assert "small_planes" not in planerel.segment(cloud, up=(0.0, -1.0, 0.0)).info
    desc = planerel.describe(cloud)              # segments as planerel.segment does
    assert len(desc.planes) == len(planerel.describe(cloud, seg.labels).planes)
