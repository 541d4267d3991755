"""``RegionGrowParams.far_theta`` (step60; on by default since lead61: 30 degrees beyond
1.5 m, RMS within 2.5 noise sigmas): a second growing with a wider angle adds planes only where
the first left depth beyond ``far_depth`` in no plane; nothing already in a plane changes.  The
far gate (``decision.far_gate``) refuses a box proved through such a plane."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
import independent_scenes as ind  # noqa: E402

from planerel.errors import InputError  # noqa: E402
from planerel.io import readers as io  # noqa: E402
from planerel.segment import segment  # noqa: E402
from planerel.segment.params import FAR_SHARE, RegionGrowParams  # noqa: E402

#: the wide window's fallback off (on by default since up66): these 320x240 stereo flights leave
#: most of their depth in no plane at the narrow window, and the fallback would grow them again
#: before the far pass these tests are about
OFF = {"wide_fallback": 0.0}


@pytest.fixture(scope="module")
def stereo_flights(tmp_path_factory):
    out = tmp_path_factory.mktemp("far")
    ind.make_set(out, 6, 6002, (320, 240), kinds=("stairs",), sensor="stereo")
    return [io.read(p) for p in sorted(out.glob("i[0-9][0-9][0-9][0-9].npy"))]


def test_far_planes_fill_only_far_depth_left_in_no_plane(stereo_flights):
    added = 0
    for cloud in stereo_flights:
        a = segment(cloud, far_theta=0.0, **OFF)
        b = segment(cloud, far_theta=30.0, far_depth=1.5, far_rms=1e9, **OFF)
        assigned = a.labels >= 0
        # what the first growing put in a plane stays in that plane
        np.testing.assert_array_equal(b.labels[assigned], a.labels[assigned])
        new = (b.labels >= 0) & ~assigned
        z = cloud.xyz[..., 2]
        assert (z[new] > 1.5).all()
        assert len(b.planes) == len(a.planes) + b.info["far_planes"]
        assert all(q.id == i for i, q in enumerate(b.planes))
        assert b.info["far_labels"] == list(range(len(a.planes), len(b.planes)))
        added += b.info["far_planes"]
    assert added >= 1  # the wider angle makes planes of some steps the first left


def test_far_theta_is_on_by_default_and_0_turns_it_off(stereo_flights):
    p = RegionGrowParams()
    assert (p.far_theta, p.far_depth, p.far_rms) == (30.0, 1.5, 2.5)
    cloud = stereo_flights[0]
    on = segment(cloud)
    off = segment(cloud, far_theta=0.0)
    assert "far_planes" in on.info and "far_planes" not in off.info
    np.testing.assert_array_equal(on.labels, segment(cloud, far_theta=30.0, far_depth=1.5,
                                                     far_rms=2.5).labels)
    # a preset (adapt off) measures no noise, so no far plane could pass far_rms: none is grown
    assert "far_planes" not in segment(cloud, preset="kinect").info
    assert 0 < FAR_SHARE <= 1


def test_far_theta_out_of_range_is_a_clear_error():
    with pytest.raises(InputError, match="far_theta"):
        RegionGrowParams(far_theta=-1)
    with pytest.raises(InputError, match="far_depth"):
        RegionGrowParams(far_depth=-0.5)


def test_a_far_region_no_plane_fits_at_the_noise_is_not_added(stereo_flights):
    # far_rms: a candidate whose plane RMS exceeds that many noise sigmas stays out (far_local,
    # its own-noise test, off: tests/test_far_local.py)
    seen = kept = 0
    for cloud in stereo_flights:
        b = segment(cloud, far_theta=30.0, far_depth=1.5, far_rms=1e-6, far_local=0.0, **OFF)
        seen += len(b.info["far_fit"])
        kept += b.info["far_planes"]
        c = segment(cloud, far_theta=30.0, far_depth=1.5, far_rms=2.5, far_local=0.0, **OFF)
        assert c.info["far_planes"] == sum(r <= 2.5 for r in c.info["far_fit"])
    assert seen >= 1 and kept == 0


def test_far_wide_grows_again_with_the_wide_window_and_keeps_the_first_planes(stereo_flights):
    # far_wide: the second growing at theta with the 15 px window (noise58's), far depth only
    added = 0
    for cloud in stereo_flights:
        a = segment(cloud, far_theta=0.0, **OFF)
        b = segment(cloud, far_theta=0.0, far_wide=True, far_depth=1.5, far_rms=2.5, **OFF)
        assigned = a.labels >= 0
        np.testing.assert_array_equal(b.labels[assigned], a.labels[assigned])
        assert (cloud.xyz[..., 2][(b.labels >= 0) & ~assigned] > 1.5).all()
        added += b.info["far_planes"]
    assert added >= 1
    with pytest.raises(InputError, match="far_wide"):
        RegionGrowParams(far_wide="maybe")


def test_the_segmentation_cache_keeps_the_far_planes(stereo_flights, tmp_path):
    """``planerel learn``'s describing reads its segmentations from a cache: the far planes'
    labels are kept beside the labels (``KEY.far.npy``), so a training scene's up is read
    without them as classify's is; an entry from before (no such file) is segmented again."""
    from planerel.ilp.scenes import segment_cached, segment_cached_far

    cloud = next(c for c in stereo_flights if segment(c, **OFF).info["far_planes"])
    src = tmp_path / "scene.bin"
    src.write_bytes(b"one scene's files")
    cache = tmp_path / "cache"
    labels, far = segment_cached_far(cloud, params=OFF, files=[src], cache=cache)
    seg = segment(cloud, **OFF)
    np.testing.assert_array_equal(labels, seg.labels)
    assert far == tuple(seg.info["far_labels"]) and far
    stored = sorted(p.name for p in (cache / "seg").iterdir())
    assert len(stored) == 2 and stored[0].endswith(".far.npy")
    # read back; the labels-only call the same
    again = segment_cached_far(cloud, params=OFF, files=[src], cache=cache)
    np.testing.assert_array_equal(again[0], labels)
    assert again[1] == far
    np.testing.assert_array_equal(segment_cached(cloud, params=OFF, files=[src], cache=cache),
                                  labels)
    # an entry without its far file (written before): segmented again, both written
    (cache / "seg" / stored[0]).unlink()
    assert segment_cached_far(cloud, params=OFF, files=[src], cache=cache)[1] == far
    assert (cache / "seg" / stored[0]).is_file()


def test_the_second_growing_on_the_first_ones_normals_is_the_same_growing(stereo_flights):
    """``region_grow(same_window=)`` (the far planes' second growing) takes the first growing's
    float32 normals instead of computing them again: the same regions, bit for bit, as a growing
    that computes its own; a window that differs (``far_wide``) computes its own."""
    import dataclasses

    from planerel.segment import _far_planes, make_params
    from planerel.segment.regiongrow import region_grow

    p = RegionGrowParams()
    wp = dataclasses.replace(p, theta=p.far_theta, far_theta=0.0)
    for cloud in stereo_flights[:3]:
        first = region_grow(cloud, p, split=True)
        own = region_grow(cloud, wp, split=True)
        shared = region_grow(cloud, wp, split=True, same_window=first)
        np.testing.assert_array_equal(shared.labels, own.labels)
        assert shared.normals is first.normals  # not measured again
        np.testing.assert_array_equal(own.normals, first.normals)
    # another cloud's normals (another shape) are refused
    crop = cloud.__class__(cloud.xyz[:100])
    with pytest.raises(InputError, match="same_window"):
        region_grow(cloud, wp, same_window=region_grow(crop, p))
    # the whole far pass: the same planes as a second growing that measures its own normals
    cloud = stereo_flights[0]
    base = segment(cloud, far_theta=0.0, **OFF)
    a = _far_planes(cloud, dataclasses.replace(base, info=dict(base.info)),
                    make_params("regiongrow"), None)
    bare = dataclasses.replace(base, normals=None, info=dict(base.info))
    b = _far_planes(cloud, bare, make_params("regiongrow"), None)
    np.testing.assert_array_equal(a.labels, b.labels)
    assert a.info["far_fit"] == b.info["far_fit"]
