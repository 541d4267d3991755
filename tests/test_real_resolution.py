"""benchmarks/real_resolution.py: a frame resampled to half (decimated or block median) and double
resolution keeps its geometry (intrinsics scaled so that the points stay on the scene's
surfaces), invalid pixels stay invalid, and the labels' rectangles and the answers' diff follow."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import real_resolution as rr  # noqa: E402

from planerel.errors import InputError  # noqa: E402
from planerel.io.cloud import Cloud, Intrinsics, depth_to_cloud  # noqa: E402


def _tilted_plane(w: int = 64, h: int = 48, hole: bool = True) -> Cloud:
    """A plane ``z = 1.5 + 0.4 x + 0.2 y`` (metres) seen by a pinhole camera, exact depths, with
    an invalid 3x3 hole at rows 10-12, columns 20-22."""
    intr = Intrinsics(w, h, 60.0, 58.0, 31.3, 23.7)
    u, v = np.meshgrid(np.arange(w, dtype=float), np.arange(h, dtype=float))
    rx, ry = (u - intr.cx) / intr.fx, (v - intr.cy) / intr.fy
    z = 1.5 / (1.0 - 0.4 * rx - 0.2 * ry)  # the ray (rx z, ry z, z) meets the plane
    if hole:
        z[10:13, 20:23] = np.nan
    return depth_to_cloud(z, intr, 1.0)


def _on_plane(cloud: Cloud) -> float:
    p = cloud.xyz.reshape(-1, 3)
    p = p[np.isfinite(p[:, 2])]
    return float(np.abs(p[:, 2] - (1.5 + 0.4 * p[:, 0] + 0.2 * p[:, 1])).max())


def test_decimate_keeps_every_second_measurement():
    c = _tilted_plane()
    s = rr.resample(c, "decimate")
    assert s.xyz.shape == (24, 32, 3)
    np.testing.assert_array_equal(s.xyz, c.xyz[::2, ::2])
    assert (s.intrinsics.fx, s.intrinsics.cx) == (30.0, 31.3 / 2)
    assert _on_plane(s) < 1e-9


def test_median_projects_through_the_block_centre_and_keeps_holes():
    c = _tilted_plane()
    s = rr.resample(c, "median")
    k = s.intrinsics
    assert (k.width, k.height, k.fx, k.fy) == (32, 24, 30.0, 29.0)
    assert k.cx == pytest.approx((31.3 + 0.5) / 2 - 0.5) and k.cy == pytest.approx((23.7 + 0.5) / 2 - 0.5)
    # a block touching the hole is invalid; the others valid
    bad = ~np.isfinite(s.xyz[..., 2])
    assert bad[5, 10] and bad[6, 11] and bad.sum() == 4
    # a plane's depth is not linear in the pixel, so the block median is off the plane by a
    # second-order amount only (far under a millimetre here); a wrong principal point would
    # put the points half a pixel off (centimetres at this slope)
    assert _on_plane(s) < 2e-4
    xyz = np.array(s.xyz)
    u, v = np.meshgrid(np.arange(32.0), np.arange(24.0))
    xyz[..., 0] = (u - 31.3 / 2) / 30.0 * xyz[..., 2]  # cx / 2: the decimation's centre
    xyz[..., 1] = (v - 23.7 / 2) / 29.0 * xyz[..., 2]
    assert _on_plane(Cloud(xyz)) > 10 * _on_plane(s)


def test_double_repeats_depths_on_the_new_rays():
    c = _tilted_plane(hole=False)
    d = rr.resample(c, "double")
    k = d.intrinsics
    assert (k.width, k.height, k.fx, k.cx) == (128, 96, 120.0, 2 * 31.3 + 0.5)
    np.testing.assert_array_equal(d.xyz[::2, ::2, 2], c.xyz[..., 2])
    # pixel (2v + 1/2, 2u + 1/2)'s ray is the old pixel's: the block's mean ray
    np.testing.assert_allclose(d.xyz[::2, ::2, :2] + d.xyz[1::2, 1::2, :2], 2 * c.xyz[..., :2],
                               atol=1e-12)


def test_errors_and_scaling():
    c = _tilted_plane()
    with pytest.raises(InputError):
        rr.resample(c, "bicubic")
    with pytest.raises(InputError):
        rr.resample(Cloud(c.xyz), "median")  # no intrinsics
    assert rr.factor("decimate") == rr.factor("median") == 0.5 and rr.factor("double") == 2.0
    fr = {"file": "f.png", "objects": [{"class": "box", "box": [10, 20, 30, 41]}], "unscored": [[0, 0, 4, 4]]}
    half = rr.scaled_frame(fr, 0.5)
    assert half["objects"][0]["box"] == [5, 10, 15, 20.5] and half["unscored"] == [[0, 0, 2, 2]]
    assert fr["objects"][0]["box"] == [10, 20, 30, 41]  # the input is not changed


def test_changes_count_repeated_answers():
    def row(found, false):
        return {"objects": [{"class": "box", "what": "a carton", "found": found,
                             "called": ["box"] if found else []}],
                "false": [("box", r, 0.0) for r in false]}

    assert rr.changes(row(True, [1]), row(True, [1])) == []
    moved = rr.changes(row(True, [1]), row(False, [1, 1, 2]))
    assert moved[0].startswith("box found (called box): a carton  ->  box missed")
    assert moved[1:] == ["false box (rule 1) new", "false box (rule 2) new"]
    assert rr.changes(row(False, [3, 3]), row(False, [])) == ["false box (rule 3) gone"] * 2
