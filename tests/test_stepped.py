"""Treads joined into one sloping "plane" come apart (planerel.features.stepped).

Scenes are ray cast from rectangles (tests/scenes_analytic.py) with depth noise along the ray;
the segmentation that joined the treads is imitated by giving all of them one label, so the
test is of the split and the proposal, not of region growing (the Kinect-like frames where
region growing does join them are in benchmarks/bench_stairs_from_above.py).
"""

from __future__ import annotations

import numpy as np
from scenes_analytic import Rect, floor, ramp, render

from planerel.features.curved import CurvedParams
from planerel.features.facts import describe_scene
from planerel.features.relations import ProposalParams
from planerel.features.stepped import stepped_levels


def _flight_as_one_plane(n=6, rise=0.15, run=0.30, y0=1.0):
    # treads only (a flight seen from above going down: the risers face away), all one label
    rects = [floor()] + [Rect((0.0, y0 + (k + 0.5) * run, (n - k) * rise), (1, 0, 0), (0, 1, 0),
                              0.45, run / 2 - 0.01, 1) for k in range(n)]
    cloud, lab, up, objs = render(rects, pitch=40, cam_height=n * rise + 1.6, width=320,
                                  height=240, noise=0.0015, seed=4)
    lab = np.where(lab > 1, 1, lab).astype(np.int32)
    return cloud, lab, up


def test_levels_of_treads_and_not_of_a_slope():
    rng = np.random.default_rng(0)
    treads = np.concatenate([rng.normal(k * 0.17, 0.006, 300 - 30 * k) for k in range(5)])
    treads = np.concatenate([treads, rng.uniform(0, 0.68, 20)])  # a few flying pixels between
    levels = stepped_levels(treads)
    assert len(levels) == 5
    assert np.allclose([0.5 * (a + b) for a, b in levels], np.arange(5) * 0.17, atol=0.015)
    assert stepped_levels(rng.uniform(0, 0.6, 2000)) == []  # a slope fills its heights
    assert stepped_levels(rng.normal(0, 0.006, 500)) == []  # one tread
    # levels too far apart for a rise (0.45 m): shelves, not treads
    assert stepped_levels(np.concatenate([rng.normal(0, 0.006, 300), rng.normal(0.45, 0.006, 300)])) == []


def test_treads_joined_into_one_sloping_plane_become_one_staircase():
    cloud, lab, up = _flight_as_one_plane()
    # (the stepped profile fit of sloping planes, planerel.features.stairfit, off too: it would
    # take the same plane)
    off = describe_scene(cloud, lab, up=up, proposal_params=ProposalParams(split_stepped=False),
                         curved_params=CurvedParams(stepped_clusters=False))
    assert [p.orientation for p in off.planes if p.label == 1] == ["inclined"]  # a "ramp"
    d = describe_scene(cloud, lab, up=up)
    treads = [p for p in d.planes if not p.is_floor]
    assert len(treads) == 6 and all(p.orientation == "horizontal" for p in treads)
    # one proposal holds them all; the label image the planes refer to has them apart
    assert [set(o.planes) for o in d.objects] == [{p.label for p in treads}]
    assert {int(x) for x in np.unique(d.labels)} == {-1, 0} | {p.label for p in treads}


def test_a_ramp_is_not_split():
    cloud, lab, up, _ = render([floor(), *ramp(0.0, 2.0, angle=12.0, length=2.5)], pitch=35,
                               cam_height=1.5, width=320, height=240, noise=0.0015, seed=2)
    d = describe_scene(cloud, lab, up=up)
    assert len(d.planes) == len(np.unique(lab[lab >= 0]))
    assert np.array_equal(d.labels[lab >= 0], lab[lab >= 0])


def _stepped_levels_numpy(heights, rise=(0.08, 0.30), bin_size=0.01, dense=0.2,
                          max_thickness=0.08, min_share=0.85, margin=0.02, min_level=0.01):
    """stepped_levels before its kernels (main 19ca73c): numpy's filter, ptp, bincount and
    padded sliding maximum."""
    h = np.asarray(heights, float)
    h = h[np.isfinite(h)]
    if h.size < 20 or np.ptp(h) < rise[0]:
        return []
    lo = float(h.min())
    nb = int(np.ptp(h) / bin_size) + 1
    counts = np.bincount(np.minimum(((h - lo) / bin_size).astype(np.int64), nb - 1), minlength=nb)
    w = int(0.5 * rise[1] / bin_size) + 1
    pad = np.pad(counts, w)
    local = np.lib.stride_tricks.sliding_window_view(pad, 2 * w + 1).max(axis=1)
    pop = (counts >= 3) & (counts >= dense * local)
    runs = []
    k = 0
    while k < nb:
        if not pop[k]:
            k += 1
            continue
        j = k
        while j + 1 < nb and pop[j + 1]:
            j += 1
        runs.append((k, j))
        k = j + 1
    merged = []
    for a, b in runs:
        if counts[a:b + 1].sum() < max(5, min_level * h.size):
            continue
        if merged and a - merged[-1][1] - 1 < 0.5 * rise[0] / bin_size:
            merged[-1] = (merged[-1][0], b)
        else:
            merged.append((a, b))
    runs = merged
    if len(runs) < 2:
        return []
    levels = [(lo + a * bin_size, lo + (b + 1) * bin_size) for a, b in runs]
    if any(b - a > max_thickness for a, b in levels):
        return []
    near = np.zeros(h.size, bool)
    for a, b in levels:
        near |= (h >= a - margin) & (h <= b + margin)
    if near.mean() < min_share:
        return []
    mids = [0.5 * (a + b) for a, b in levels]
    if not all(rise[0] <= s <= rise[1] for s in np.diff(mids)):
        return []
    return levels


def test_stepped_levels_and_its_kernels_are_the_numpy_code():
    """stepped_levels (finite_range, level_bins compiled) against its numpy version, level
    for level: treads, slopes, NaN heights, few points, flat sets, another bin size; and the
    kernels against numpy's min / max and bincount + sliding maximum."""
    from planerel.features._relation_kernels import finite_range, level_bins

    rng = np.random.default_rng(3)
    cases = [np.zeros(0), np.full(30, np.nan), np.full(25, 0.3), rng.normal(0, 0.006, 19)]
    for _ in range(150):
        n_lev = int(rng.integers(1, 6))
        rise = float(rng.uniform(0.05, 0.35))
        h = np.concatenate([rng.normal(k * rise, rng.uniform(0.002, 0.03), int(rng.integers(3, 400)))
                            for k in range(n_lev)] + [rng.uniform(-0.1, n_lev * rise, int(rng.integers(0, 60)))])
        h[rng.random(h.size) < 0.05] = rng.choice([np.nan, np.inf, -np.inf])
        cases.append(rng.permutation(h))
    found = 0
    for h in cases:
        for kw in ({}, {"bin_size": 0.013, "dense": 0.35}):
            want = _stepped_levels_numpy(h, **kw)
            assert stepped_levels(h, **kw) == want
            found += len(want) > 0
        f = h[np.isfinite(h)]
        n, lo, hi = finite_range(h)
        assert n == f.size
        if f.size:
            assert (lo, hi) == (f.min(), f.max())
            nb = int(np.ptp(f) / 0.01) + 1
            counts = np.bincount(np.minimum(((f - lo) / 0.01).astype(np.int64), nb - 1), minlength=nb)
            local = np.lib.stride_tricks.sliding_window_view(np.pad(counts, 16), 33).max(axis=1)
            got_c, got_p = level_bins(f, lo, 0.01, nb, 16, 0.2)
            assert np.array_equal(got_c, counts)
            assert np.array_equal(got_p, (counts >= 3) & (counts >= 0.2 * local))
        else:
            assert np.isnan(lo) and np.isnan(hi)
    assert found > 20


# ---------------------------------------------------------------------------------------------
# The RMS gate (SPLIT_MIN_RMS, speed24): only planes as rough as treads grown into one are
# looked at.  Not an exact bound: the tests pin what it keeps and what it gives up.


def _slope_in_bands(gap=0.15, band=0.03):
    # a ramp (25 degrees, on its plane within the sensor's noise, 2-3 mm) of which only horizontal
    # bands one gap apart are labelled, all one label: its points lie on levels
    cloud, lab, up, _ = render([floor(), *ramp(0.0, 1.6, angle=25.0, length=1.6, width=1.2)],
                               pitch=35, cam_height=1.6, width=320, height=240, noise=0.0004,
                               seed=3)
    h = np.asarray(cloud.xyz) @ up
    h = h - np.nanmin(np.where(lab == 1, h, np.nan))
    on = (lab == 1) & (np.mod(h, gap) < band)
    out = np.where(lab == 1, -1, lab)
    out[on] = 1
    return cloud, out.astype(np.int32), up


def test_the_rms_gate_keeps_treads_and_leaves_a_slope_seen_in_bands():
    from planerel.features.planes import measure_planes
    from planerel.features.stepped import SPLIT_MIN_RMS, split_stepped

    cloud, lab, up = _flight_as_one_plane()
    planes = measure_planes(cloud, lab, up)
    steps = [p for p in planes if p.label == 1]
    # treads grown into one plane: a sawtooth a rise high, far above the gate
    assert steps[0].orientation == "inclined" and steps[0].rms > 3 * SPLIT_MIN_RMS
    assert split_stepped(cloud.xyz, planes.labels, planes) is not None
    # a slope seen in bands lies on levels too, but on its plane: split without the gate
    # (as before it), left whole with it
    cloud, lab, up = _slope_in_bands()
    planes = measure_planes(cloud, lab, up)
    slope = [p for p in planes if p.label == 1][0]
    assert slope.orientation == "inclined" and slope.rms < SPLIT_MIN_RMS
    assert split_stepped(cloud.xyz, planes.labels, planes, min_rms=0.0) is not None
    assert split_stepped(cloud.xyz, planes.labels, planes) is None


def test_the_rms_gate_changes_nothing_on_the_real_frames(monkeypatch):
    """The shared real frames (three Kinect frames with a 36 000-point plane at 61 degrees the
    level test read in full, seven mOSD frames) describe the same with and without it."""
    from pathlib import Path

    import pytest

    from planerel.features import stepped
    from planerel.io.readers import read
    from planerel.segment import segment

    data = Path(__file__).resolve().parents[2] / "shared" / "data"
    files = sorted((data / "kinect").glob("*_depth.tiff")) + sorted((data / "mosd").glob("*.pcd"))
    if not files:
        pytest.skip(f"no real frames under {data}")
    real = stepped.split_stepped

    def ungated(*a, **k):
        return real(*a, **{**k, "min_rms": 0.0})

    gated = 0
    for f in files:
        cloud = read(f)
        labels = segment(cloud).labels
        new = describe_scene(cloud, labels)
        gated += sum(1 for p in new.planes if p.orientation == "inclined" and not p.is_floor
                     and p.rms < stepped.SPLIT_MIN_RMS)
        monkeypatch.setattr(stepped, "split_stepped", ungated)
        old = describe_scene(cloud, labels)
        monkeypatch.setattr(stepped, "split_stepped", real)
        assert [repr(r) for r in new.relations] == [repr(r) for r in old.relations], f.name
        assert [(o.planes, o.curved, o.planar_fraction) for o in new.objects] == \
            [(o.planes, o.curved, o.planar_fraction) for o in old.objects], f.name
        assert np.array_equal(new.labels, old.labels)
    assert gated >= 10  # 18 of the 20 inclined planes (0.8-3.4 mm)
