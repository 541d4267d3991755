"""Work the description skips or narrows where it cannot change the answer (speed23, issue 22):
each changed stage against the work it no longer does, on random cases, rendered scenes and
real frames; the results must be the same values, bit for bit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scenes_analytic import floor, render, stairs

_DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def _same(a, b) -> bool:
    """The same values, bit for bit (signed zeros and NaN payloads too)."""
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


# ---------------------------------------------------------------------------------------------
# raised_noise_pixels: the column sums a few rows behind the grid pass


def _raised_the_old_way(xyz, lab, label, r0, c0, H, W, f, n, d0, min_rise, k_sigma, r, step):
    """raised_noise_pixels as it was: the grid pass, the median, then the tests' own pass over
    the whole grid's row sums (``_raised_rows``, ``_raised_tests``)."""
    from planerel.features._raised_kernels import _raised_rows, _raised_tests
    from planerel.features._relation_kernels import median

    on, h, rs, rc, vals = _raised_rows(xyz, lab, label, r0, c0, H, W, f, n, d0, r, step)
    a = 1.4826 * median(vals) if vals.shape[0] else 0.0
    raw, weak = _raised_tests(xyz, r0, c0, f, on, rs, rc, a, min_rise, k_sigma, r)
    return on, raw, weak, h


def _plane_case(rng, rows, cols, raised_share, lift):
    lab = rng.integers(-1, 3, (rows, cols)).astype(np.int32)
    lab[rng.random((rows, cols)) < 0.7] = 1
    xyz = np.stack(np.meshgrid(np.linspace(-1, 1, cols), np.linspace(-1, 1, rows)), -1)
    z = np.full((rows, cols, 1), float(rng.uniform(0.05, 4.0)))
    xyz = np.concatenate([xyz, z], -1) + rng.normal(size=(rows, cols, 3)) * 0.002
    xyz[rng.random((rows, cols)) < raised_share, 1] += lift
    xyz[rng.random((rows, cols)) < 0.05] = np.nan
    return np.ascontiguousarray(xyz), lab


def test_raised_noise_pixels_with_the_column_sums_behind_the_pass_is_the_old_kernel():
    # grids from 1 x 1 up, windows wider than the grid (r up to 9), and grids whose every
    # window passes the product test (the kept windows' lists grown many times)
    from planerel.features._raised_kernels import raised_noise_pixels

    rng = np.random.default_rng(23)
    grown = raised = 0
    for t in range(240):
        rows, cols = (int(v) for v in rng.integers(1, 90, 2))
        if t % 5 == 0:
            rows, cols = int(rng.integers(1, 6)), int(rng.integers(1, 6))
        share = 1.0 if t % 3 == 0 else float(rng.uniform(0.0, 0.4))
        xyz, lab = _plane_case(rng, rows, cols, share, float(rng.uniform(0.004, 0.05)))
        f = int(rng.integers(1, 4))
        r0, c0 = int(rng.integers(0, min(3, rows))), int(rng.integers(0, min(3, cols)))
        H, W = -(-(rows - r0) // f), -(-(cols - c0) // f)
        n = rng.normal(size=3) * 0.05 + [0.0, 1.0, 0.0]
        n /= np.linalg.norm(n)
        args = (xyz, lab, 1 if rng.random() < 0.9 else 5, r0, c0, H, W, f, n,
                float(rng.normal() * 0.01), float(rng.uniform(0, 0.01)), 2.5,
                int(rng.integers(0, 10)), int(rng.integers(0, 7)))
        got = raised_noise_pixels(*args)
        want = _raised_the_old_way(*args)
        for g, w in zip(got, want, strict=True):
            assert _same(g, w)
        raised += int(want[1].sum())
        grown += int(want[2].sum()) > 8 * W + 64  # more windows kept than the lists' first size
    assert raised > 2000 and grown > 20


@pytest.mark.skipif(not (_DATA / "mosd").is_dir(), reason="needs ../shared/data")
def test_raised_noise_pixels_on_the_real_frames_support_planes_is_the_old_kernel():
    from planerel.features._defaults import defaults
    from planerel.features._raised_kernels import raised_noise_pixels
    from planerel.features.planes import measure_planes
    from planerel.features.raised import RaisedParams
    from planerel.io.readers import read
    from planerel.segment import segment

    rp = defaults(RaisedParams)
    seen = 0
    files = sorted((_DATA / "kinect").glob("*_depth.tiff")) + sorted((_DATA / "mosd").glob("*.pcd"))[:2]
    for path in files:
        cloud = read(path)
        labels = segment(cloud).labels
        planes = measure_planes(cloud, labels)
        xyz = np.ascontiguousarray(cloud.xyz, dtype=np.float64)
        lab = np.ascontiguousarray(labels)
        up = np.asarray(planes.up, float)
        f = max(1, lab.shape[1] // 320)
        for p in planes:
            if p.orientation != "horizontal":
                continue
            n = np.asarray(p.normal, float)
            n = -n if float(n @ up) < 0 else n
            r0, c0, r1, c1 = p.bbox
            for r in (0, 2, 5):  # the real window (2) and others
                args = (xyz, lab, int(p.label), r0, c0, -(-(r1 - r0) // f), -(-(c1 - c0) // f),
                        f, n, float(np.asarray(p.centroid, float) @ n), float(rp.min_rise),
                        float(rp.k_sigma), r, 5)
                got = raised_noise_pixels(*args)
                want = _raised_the_old_way(*args)
                for g, w in zip(got, want, strict=True):
                    assert _same(g, w)
                seen += int(want[1].sum())
    assert seen > 500  # raised pixels among them (the third Kinect frame's floor bend)


def test_the_ring_tests_heights_from_the_groups_widened_box_are_the_whole_grids():
    # raised_clusters' ring test: a group (within its box widened by ring_px) and its ring
    # (within the same box) read from the box give the same heights, in the same order, as
    # from the whole grid, so the same median and percentile
    from planerel.features.curved import _shift_all

    rng = np.random.default_rng(11)
    for _ in range(300):
        H, W = int(rng.integers(1, 60)), int(rng.integers(1, 60))
        h = rng.normal(size=(H, W)).astype(np.float32) * 0.01
        on = rng.random((H, W)) < 0.8
        raw = on & (rng.random((H, W)) < 0.3)
        rows, cols = np.nonzero(raw)
        if not len(rows):
            continue
        sel = rng.random(len(rows)) < 0.5
        sel[0] = True
        ring_px = int(rng.integers(0, 6))
        m = np.zeros((H, W), bool)
        m[rows[sel], cols[sel]] = True
        g0, g1 = max(0, int(rows[sel].min()) - ring_px), int(rows[sel].max()) + ring_px + 1
        h0, h1 = max(0, int(cols[sel].min()) - ring_px), int(cols[sel].max()) + ring_px + 1
        part = m[g0:g1, h0:h1]
        for axis in (0, 1):
            part = _shift_all(part, ring_px, axis, False)
        grown = np.zeros((H, W), bool)
        grown[g0:g1, h0:h1] = part
        ring_old = grown & on & ~raw  # as it was: masks of the whole grid
        box = (slice(g0, g1), slice(h0, h1))
        ring_new = part & on[box] & ~raw[box]
        assert ring_old.any() == ring_new.any()
        assert _same(h[m], h[box][m[box]])
        assert _same(h[ring_old], h[box][ring_new])
        if ring_old.any():
            old = float(np.median(h[m]) - np.percentile(h[ring_old], 10))
            new = float(np.median(h[box][m[box]]) - np.percentile(h[box][ring_new], 10))
            assert _same(old, new)


# ---------------------------------------------------------------------------------------------
# the stairfit stage: only the large clusters the width bound leaves gathered and sloped


def test_a_subset_of_whole_clusters_gathers_and_slopes_as_the_whole_list():
    from planerel.features.stairfit import _gather, _horizontal_axes, _slope_candidates

    rng = np.random.default_rng(7)
    for t in range(200):
        H, W = int(rng.integers(2, 40)), int(rng.integers(2, 40))
        xyz = rng.normal(size=(H, W, 3))
        xyz[..., 2] += 3.0
        if t % 4 == 0:
            xyz[rng.random((H, W)) < 0.05] = np.nan
        n = int(rng.integers(1, min(H * W, 300)))
        rows, cols = np.divmod(np.sort(rng.choice(H * W, n, replace=False)), W)
        k = int(rng.integers(1, 12))
        ids = rng.integers(0, k, n).astype(np.int64)
        up = rng.normal(size=3)
        up /= np.linalg.norm(up)
        e1, e2 = _horizontal_axes(up)
        look = rng.random(k) < 0.5
        at = np.flatnonzero(look[ids])
        pts = _gather(xyz, rows, cols)
        sub = _gather(xyz, rows[at], cols[at])
        for c in np.flatnonzero(look):
            assert _same(sub[ids[at] == c], pts[ids == c])
        want = _slope_candidates(pts, ids, k, e1, e2, up, (0.25, 1.5))
        got = _slope_candidates(sub, ids[at], k, e1, e2, up, (0.25, 1.5))
        assert np.array_equal(got[look], want[look])


def _unassigned_flight(**kw):
    cloud, lab, up, _ = render([floor(size=12.0, y=4.0), *stairs(0.0, 2.6, n=5, rise=0.17,
                                                                 run=0.29, width=1.2)],
                               width=160, height=120, noise=0.003, seed=3, **kw)
    return cloud, np.where(lab == 0, 0, -1).astype(np.int32), up


def _stairfit_cases():
    from planerel.features.curved import CurvedParams
    from planerel.features.facts import describe_scene

    off = CurvedParams(stepped_clusters=False)
    for kw in ({"pitch": 10.0, "cam_height": 1.0}, {"pitch": 25.0, "cam_height": 1.6}):
        cloud, lab, up = _unassigned_flight(**kw)
        yield cloud, describe_scene(cloud, lab, up=up, curved_params=off).planes
        # the flight's pixels as one sloping plane (an inclined candidate among the clusters)
        cloud, full, up, _ = render([floor(size=12.0, y=4.0), *stairs(0.0, 2.0, n=5)],
                                    width=160, height=120, noise=0.003, seed=3, **kw)
        lab = np.where(full == 0, 0, np.where(full > 0, 5, -1)).astype(np.int32)
        yield cloud, describe_scene(cloud, lab, up=up, curved_params=off).planes
    # two flights side by side: two wide clusters, each fitted
    cloud, full, up, _ = render([floor(size=12.0, y=4.0),
                                 *stairs(-1.0, 2.6, n=5, rise=0.17, run=0.29, width=1.2),
                                 *stairs(1.0, 3.2, n=4, rise=0.15, run=0.3, width=1.0)],
                                width=160, height=120, noise=0.003, seed=3, pitch=10.0,
                                cam_height=1.0)
    lab = np.where(full == 0, 0, -1).astype(np.int32)
    yield cloud, describe_scene(cloud, lab, up=up, curved_params=off).planes
    if (_DATA / "kinect").is_dir():
        from planerel.features.planes import measure_planes
        from planerel.io.readers import read
        from planerel.segment import segment

        for path in sorted((_DATA / "kinect").glob("*_depth.tiff")):
            cloud = read(path)
            yield cloud, measure_planes(cloud, segment(cloud).labels)


def test_the_stairfit_stage_is_the_same_whichever_large_clusters_it_gathers(monkeypatch):
    # every cluster's points gathered and sloped (as before), and the width bound off too
    # (every large cluster fitted as far as its own tests go), against the stage as it runs:
    # the same label image, flights, normals and pixels
    import planerel.features.stairfit as S

    fitted = 0
    for cloud, planes in _stairfit_cases():
        got, pixels = S._stepped_cluster_labels(cloud, planes)
        refs = [S._stepped_cluster_labels(cloud, planes, gather_all=True)]
        with monkeypatch.context() as m:
            m.setattr(S, "_narrow_of", lambda span, *a, **k: np.zeros(len(span), bool))
            m.setattr(S, "_narrow_clusters_at", lambda xyz, rows, cols, ids, n, *a, **k:
                      np.zeros(n, bool))
            refs.append(S._stepped_cluster_labels(cloud, planes, gather_all=True))
        for want, wpixels in refs:
            assert (got is None) == (want is None)
            if got is not None:
                assert _same(got[0], want[0]) and got[1] == want[1]
                assert sorted(got[2]) == sorted(want[2])
                assert all(_same(got[2][k], want[2][k]) for k in got[2])
            for g, w in zip(pixels, wpixels, strict=True):
                assert _same(g, w)
        fitted += 0 if got is None else len(got[1])
    assert fitted >= 4


# ---------------------------------------------------------------------------------------------
# leg_objects: a join needs two posts


def test_legs_with_fewer_than_two_possible_posts_read_no_point(monkeypatch):
    # one leg beside a box: one possible post (the box's faces are too wide to be one), so
    # nothing can be joined and no point is read; two legs: their points are read as before
    from scenes_analytic import box
    from test_proposals_synth22y import OFF, _legs, _scene

    import planerel.features.tables as T

    calls = []
    real = T._post

    def counted(*a, **k):
        calls.append(1)
        return real(*a, **k)

    monkeypatch.setattr(T, "_post", counted)
    one = [*_legs(cx=-0.6, cy=2.5, sx=0.12, sy=0.12, obj=3)[:2], *box(0.5, 2.2, 0.3, 0.3, 0.3, obj=2)]
    d, _, _ = _scene(one)
    assert calls == []
    old, _, _ = _scene(one, params=OFF)
    assert [o.planes for o in d.objects] == [o.planes for o in old.objects]
    two = [*_legs(cx=-0.7, cy=2.5, sx=0.12, sy=0.12, obj=3)[:2],
           *_legs(cx=0.7, cy=2.5, sx=0.12, sy=0.12, obj=4)[:2]]
    d, objs, _ = _scene(two)
    assert len(calls) >= 2
    assert len([o for o in d.objects if {objs[x] for x in o.planes} == {3, 4}]) == 1
