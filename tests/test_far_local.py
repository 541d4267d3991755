"""``RegionGrowParams.far_local`` (tof72, on by default at 2): a far candidate that fails ``far_rms`` against the
frame's noise is still a plane when it fits within ``far_local`` times its own patch noise
(:func:`planerel.segment.patch_noise.patch_noise`), a time-of-flight camera's dark risers."""

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
from planerel.segment.params import RegionGrowParams  # noqa: E402
from planerel.segment.patch_noise import patch_noise, patch_size  # noqa: E402


def _grid(h=60, w=80):
    v, u = np.mgrid[0:h, 0:w].astype(float)
    return v, u


def test_patch_noise_measures_a_flat_regions_noise_and_not_its_curvature():
    rng = np.random.default_rng(0)
    v, u = _grid()
    x, y = (u - 40) * 0.004, (v - 30) * 0.004
    flat = np.stack([x, y, 2.0 + 0.1 * x + rng.normal(0, 0.003, x.shape)], -1)
    mask = np.ones(v.shape, bool)
    assert patch_noise(flat, mask, 8) == pytest.approx(0.003, rel=0.2)
    # a cylinder of radius 0.1 m across the region: its patches fit far better than its whole
    curved = np.stack([x, y, 2.0 - np.sqrt(np.maximum(0.1 ** 2 - x ** 2, 0))], -1)
    pts = curved.reshape(-1, 3)
    cen = pts.mean(0)
    whole = np.linalg.svd(pts - cen, compute_uv=False)[-1] / np.sqrt(len(pts))
    assert patch_noise(curved, mask, 8) < 0.25 * whole
    # too few patches in the region: no measure
    small = np.zeros(v.shape, bool)
    small[:10, :10] = True
    assert patch_noise(flat, small, 8) is None
    assert patch_noise(flat, np.zeros(v.shape, bool), 8) is None
    assert patch_size(960) == 12 and patch_size(320) == 6 and patch_size(1920) == 24


@pytest.fixture(scope="module")
def tof_scenes(tmp_path_factory):
    """dev_tof's (seed 7201) scenes 18 (a ramp with a dark box beside it) and 36 (a flight with
    dark risers 2-3 m away), written as ``make_set`` writes them, with their true planes."""
    out = tmp_path_factory.mktemp("tof")
    kinds = ("stairs", "stairs_top", "ramp", "box")
    scenes = []
    for i in (18, 36):
        xyz, _, side, *_, pid = ind.make_scene(i, 7201, (512, 424), kinds=kinds, sensor="tof")
        ind._write_npy(out / f"i{i:04d}.npy", xyz)
        ind._write_json(out / f"i{i:04d}.json", side)
        scenes.append((io.read(out / f"i{i:04d}.npy"), pid))
    return scenes


def test_far_local_makes_planes_of_dark_faces_and_each_lies_on_one_true_plane(tof_scenes):
    added = 0
    for cloud, truth in tof_scenes:
        a = segment(cloud, far_local=0.0)
        b = segment(cloud, far_local=2.0)
        assigned = a.labels >= 0
        np.testing.assert_array_equal(b.labels[assigned], a.labels[assigned])  # kept as grown
        assert "far_local" not in a.info
        n = b.info.get("far_local", 0)
        added += n
        assert len(b.planes) >= len(a.planes) + n
        for q in b.planes[len(a.planes):]:
            on = truth[b.labels == q.id]
            on = on[on >= 0]
            # a plane the pass adds lies on one true face (a riser), not across a nosing
            assert np.bincount(on).max() >= 0.8 * len(on)
    assert added >= 2  # scene 36's two dark risers (measured)


def test_far_local_takes_no_region_rougher_than_its_bound(tof_scenes, monkeypatch):
    import planerel.segment.params as params

    cloud, _ = tof_scenes[1]
    assert segment(cloud, far_local=2.0).info.get("far_local", 0) == 2
    monkeypatch.setattr(params, "FAR_LOCAL_NOISE", 1e-4)  # every dark riser is rougher
    assert segment(cloud, far_local=2.0).info.get("far_local", 0) == 0


def test_far_local_is_on_by_default_at_2_and_checks_its_value(tof_scenes):
    assert RegionGrowParams().far_local == 2.0
    cloud, _ = tof_scenes[1]
    assert segment(cloud).info.get("far_local", 0) == 2
    assert "far_local" not in segment(cloud, far_local=0.0).info
    for bad in (0.5, 11, -1, "x"):
        with pytest.raises(InputError, match="far_local"):
            RegionGrowParams(far_local=bad)


def test_far_local_keeps_nothing_where_the_frame_measured_no_noise(tmp_path):
    # dev_sr i0021 (160x120): no noise measured; the far part of a nine-step flight is a rough
    # surface at the flight's pitch, no plane seen through noise
    xyz, _, side, *_ = ind.make_scene(21, 3203, (160, 120), kinds=("stairs", "ramp", "stairs_top"))
    ind._write_npy(tmp_path / "i0021.npy", xyz)
    ind._write_json(tmp_path / "i0021.json", side)
    seg = segment(io.read(tmp_path / "i0021.npy"), far_local=2.0)
    assert seg.info["noise_model"]["kind"] == "none"
    assert seg.info.get("far_local", 0) == 0
