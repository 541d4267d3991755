"""Full-image passes of the description's kernels done fewer times (speed22t, issue 22): each
fused or narrowed kernel against the calls it replaced, which the tests keep as the reference,
on random cases and on real frames; the results must be the same values, bit for bit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

_DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def _same(a, b) -> bool:
    """The same values, bit for bit (signed zeros and NaN payloads too)."""
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def _real_frames(n: int = 2):
    """``(cloud, labels, planes)`` of the first Kinect frame and of ``n`` mOSD frames."""
    from planerel.features.planes import measure_planes
    from planerel.io.readers import read
    from planerel.segment import segment

    files = sorted((_DATA / "kinect").glob("*_depth.tiff"))[:1]
    files += sorted((_DATA / "mosd").glob("*.pcd"))[:n]
    for f in files:
        cloud = read(f)
        labels = segment(cloud).labels
        yield cloud, labels, measure_planes(cloud, labels)


def _raised_the_old_way(xyz, lab, label, r0, c0, H, W, f, n, d0, min_rise, k_sigma, r, step):
    """``_raised_on`` as it was: the noise values in a pass of their own, their median, then
    ``raised_pixels``."""
    from planerel.features._raised_kernels import raised_pixels
    from planerel.features._relation_kernels import median
    from planerel.features.raised import _noise_values

    vals = _noise_values(xyz, lab, label, (r0, c0, r0 + H * f, c0 + W * f), step * f, n, d0)
    a = 1.4826 * float(median(vals)) if vals.size else 0.0
    return raised_pixels(xyz, lab, label, r0, c0, H, W, f, n, d0, a, min_rise, k_sigma, r)


def test_raised_noise_pixels_is_the_noise_pass_then_raised_pixels():
    from planerel.features._raised_kernels import raised_noise_pixels

    rng = np.random.default_rng(2211)
    raised = 0
    for _ in range(80):
        rows, cols = (int(v) for v in rng.integers(1, 70, 2))
        lab = rng.integers(-1, 3, (rows, cols)).astype(np.int32)
        lab[rng.random((rows, cols)) < 0.6] = 1
        xyz = np.stack(np.meshgrid(np.linspace(-1, 1, cols), np.linspace(-1, 1, rows)), -1)
        z = np.full((rows, cols, 1), float(rng.uniform(0.05, 4.0)))
        xyz = np.concatenate([xyz, z], -1) + rng.normal(size=(rows, cols, 3)) * 0.002
        xyz[rng.random((rows, cols)) < 0.2, 1] += rng.uniform(0.005, 0.05)
        xyz[rng.random((rows, cols)) < 0.05] = np.nan
        f = int(rng.integers(1, 4))
        r0, c0 = int(rng.integers(0, min(3, rows))), int(rng.integers(0, min(3, cols)))
        H, W = -(-(rows - r0) // f), -(-(cols - c0) // f)
        n = rng.normal(size=3) * 0.05 + [0.0, 1.0, 0.0]
        n /= np.linalg.norm(n)
        args = (xyz, lab, 1 if rng.random() < 0.9 else 5, r0, c0, H, W, f, n,
                float(rng.normal() * 0.01), float(rng.uniform(0, 0.01)), 2.5,
                int(rng.integers(0, 6)), int(rng.integers(1, 7)))
        got = raised_noise_pixels(*args)
        want = _raised_the_old_way(*args)
        for g, w in zip(got, want, strict=True):
            assert _same(g, w)
        raised += int(want[1].sum())
    assert raised > 50


@pytest.mark.skipif(not (_DATA / "mosd").is_dir(), reason="needs ../shared/data")
def test_raised_noise_pixels_on_real_support_planes():
    from planerel.features._defaults import defaults
    from planerel.features._raised_kernels import raised_noise_pixels
    from planerel.features.raised import RaisedParams

    rp = defaults(RaisedParams)
    seen = 0
    for cloud, labels, planes in _real_frames():
        xyz = np.ascontiguousarray(cloud.xyz, dtype=np.float64)
        lab = np.ascontiguousarray(labels)
        up = np.asarray(planes.up, float)
        f = max(1, lab.shape[1] // 320)
        for p in planes:
            if p.orientation != "horizontal":
                continue
            n = np.asarray(p.normal, float)
            n = -n if float(n @ up) < 0 else n
            d0 = float(np.asarray(p.centroid, float) @ n)
            r0, c0, r1, c1 = p.bbox
            args = (xyz, lab, int(p.label), r0, c0, -(-(r1 - r0) // f), -(-(c1 - c0) // f), f,
                    n, d0, float(rp.min_rise), float(rp.k_sigma), int(rp.smooth_px), 5)
            got = raised_noise_pixels(*args)
            want = _raised_the_old_way(*args)
            for g, w in zip(got, want, strict=True):
                assert _same(g, w)
            seen += int(want[0].sum())
    assert seen > 50_000


def test_unexplained_pixels_in_one_pass_as_numpy_finds_them():
    """unexplained_pixels (one pass, its lists grown as they fill) against ``np.nonzero`` of
    unexplained_valid's mask: sparse and dense images (the lists' first size is 1/32 of the
    image: denser ones grow them, once or many times), rows of every width modulo 8."""
    from planerel.features._curved_kernels import unexplained_pixels, unexplained_valid

    rng = np.random.default_rng(2212)
    grown = 0
    for _ in range(120):
        H, W = int(rng.integers(1, 200)), int(rng.integers(1, 300))
        valid = rng.random((H, W)) < rng.choice([0.02, 0.5, 1.0])
        lab = rng.integers(-1, 12, (H, W)).astype(np.int32)
        explained = rng.random(int(rng.integers(0, 14))) < rng.choice([0.3, 0.9, 1.0])
        rows, cols = unexplained_pixels(valid, lab, explained)
        wr, wc = np.nonzero(unexplained_valid(valid, lab, explained))
        assert _same(rows, wr.astype(np.int64)) and _same(cols, wc.astype(np.int64))
        grown += len(wr) > max(1024, H * W // 32)
    assert grown > 20


@pytest.mark.skipif(not (_DATA / "mosd").is_dir(), reason="needs ../shared/data")
def test_unexplained_pixels_on_real_frames():
    from planerel.features._curved_kernels import unexplained_pixels, unexplained_valid

    n = 0
    for cloud, labels, planes in _real_frames():
        known = [q.label for q in planes if q.area >= 0.002 and q.label >= 0]
        explained = np.zeros(max(known, default=-1) + 1, bool)
        explained[known] = True
        rows, cols = unexplained_pixels(cloud.valid, labels, explained)
        wr, wc = np.nonzero(unexplained_valid(cloud.valid, labels, explained))
        assert _same(rows, wr.astype(np.int64)) and _same(cols, wc.astype(np.int64))
        n += len(wr)
    assert n > 3000


def test_growth_in_the_clusters_box_is_the_growth_in_the_image():
    """grow_in_box with list_mask's box of the pixels before the opening against
    grow_clusters with open_pixels' whole mask (radius 0), as curved's regrowth called them:
    the same pixels in the same order and the same groups, clusters at the image's border
    and far from it, 0-4 steps."""
    from planerel.features._curved_kernels import (
        grow_box,
        grow_clusters,
        grow_in_box,
        list_mask,
        open_pixels,
    )

    rng = np.random.default_rng(2213)
    grew = 0
    for _ in range(150):
        H, W = (int(v) for v in rng.integers(3, 60, 2))
        lab = rng.integers(-1, 4, (H, W)).astype(np.int32)
        drop = rng.random(int(rng.integers(0, 5))) < 0.5
        pr, pc = np.nonzero(rng.random((H, W)) < rng.uniform(0.2, 0.9))
        xyz = np.zeros((H, W, 3))
        xyz[..., 2] = 1.0 + 0.05 * (rng.random((H, W)) < 0.2)
        full_img = open_pixels(pr, pc, lab, drop, H, W, 0)[0]
        # seeds: some pixels of the mask in a random window (a cluster somewhere)
        wy, wx = int(rng.integers(0, H)), int(rng.integers(0, W))
        win = np.zeros((H, W), bool)
        win[wy:wy + int(rng.integers(1, 12)), wx:wx + int(rng.integers(1, 12))] = True
        sr, sc = np.nonzero(full_img & win & (rng.random((H, W)) < 0.5))
        k = int(rng.integers(1, 4))
        ids = rng.integers(0, k, len(sr)).astype(np.int64)
        steps = int(rng.integers(0, 5))
        want = grow_clusters(sr, sc, ids, k, full_img, xyz, 0.02, steps,
                             int(np.count_nonzero(full_img)))
        y0, y1, x0, x1 = grow_box(sr, sc, H, W, steps)
        full, nf = list_mask(pr, pc, lab, drop, y0, y1, x0, x1)
        assert _same(full, full_img[y0:y1, x0:x1]) and nf == int(full.sum())
        got = grow_in_box(sr, sc, ids, k, full, y0, x0, H, W, xyz, 0.02, steps, nf)
        for g, w in zip(got, want, strict=True):
            assert _same(g, w)
        grew += len(want[0]) > len(sr)
    assert grew > 50


@pytest.mark.skipif(not (_DATA / "mosd").is_dir(), reason="needs ../shared/data")
def test_clusters_from_the_pixel_list_on_real_frames():
    """The curved stage from the stairfit stage's pixel list (the regrowth in the clusters'
    box) against its own scan of the image (the regrowth in the whole image)."""
    from planerel.features._curved_kernels import unexplained_pixels
    from planerel.features.curved import CurvedParams, unexplained_clusters
    from planerel.features.relations import relate, support_planes

    cp = CurvedParams()
    n = 0
    for cloud, labels, planes in _real_frames():
        support = tuple(support_planes(planes, None, relate(planes, cloud), cloud))
        known = [q.label for q in planes if q.area >= cp.tiny_area and q.label >= 0]
        explained = np.zeros(max(known, default=-1) + 1, bool)
        explained[known] = True
        pixels = unexplained_pixels(cloud.valid, labels, explained)
        want = unexplained_clusters(cloud, labels, planes, support, cp)
        got = unexplained_clusters(cloud, labels, planes, support, cp, pixels=pixels)
        assert len(got) == len(want)
        for a, b in zip(got, want, strict=True):
            assert _same(a, b)
        n += sum(int(m.sum()) for m in got)
    assert n > 1000


def _staircase_frames():
    """``(cloud, labels, planes)`` of the real staircase frames of ``$PLANEREL_STAIRS_DATA``
    (tests/test_real_rules.py's), when given."""
    import os

    import planerel
    from planerel.features.planes import measure_planes
    from planerel.segment import segment

    d = Path(os.environ.get("PLANEREL_STAIRS_DATA", "/nonexistent"))
    for f in sorted((d / "stair-perception").glob("*_depth.png")):
        cloud = planerel.read(f, intrinsics="512,424,365.32,365.32,254.67,208.54",
                              depth_scale=1000)
        labels = segment(cloud).labels
        yield cloud, labels, measure_planes(cloud, labels)


@pytest.mark.skipif(not (_DATA / "mosd").is_dir(), reason="needs ../shared/data")
def test_plane_pixels_from_their_boxes_are_the_whole_image_scan():
    """The stairfit stage's inclined-plane pixels (_lut_pixels: from the box of the planes'
    pixel boxes) against the scan of the whole image, for every plane alone, for random sets
    of planes and for the inclined ones, on real frames (and the real staircases when
    $PLANEREL_STAIRS_DATA holds them)."""
    from planerel.features.planes import label_max
    from planerel.features.stairfit import _lut_pixels

    rng = np.random.default_rng(2214)
    n = 0
    for cloud, _labels, planes in [*_real_frames(), *_staircase_frames()]:
        lab = np.asarray(planes.labels)
        byl = {q.label: q for q in planes if q.label >= 0}
        sets = [[x] for x in byl]
        sets += [list(rng.choice(list(byl), int(rng.integers(1, len(byl) + 1)), replace=False))
                 for _ in range(6)]
        sets += [[q.label for q in planes if q.orientation == "inclined"]]
        for chosen in sets:
            if not chosen:
                continue
            lut = np.full(max(label_max(lab), 0) + 1, -1, np.int64)
            lut[chosen] = 7 + np.arange(len(chosen))
            rr, cc, pid = _lut_pixels(lab, cloud.valid, lut, [byl[x].bbox for x in chosen])
            wr, wc = np.nonzero(cloud.valid & (lab >= 0))
            wp = lut[lab[wr, wc]]
            got, want = pid >= 0, wp >= 0
            assert _same(rr[got], wr[want]) and _same(cc[got], wc[want])
            assert _same(pid[got], wp[want])
            n += int(want.sum())
    assert n > 100_000


def _exact_passes_width(P, e1, e2, up, slope, min_width) -> bool:
    """The stairfit loop's slope and width tests as they are: ``np.linalg.lstsq``'s plane."""
    from planerel.features.stairfit import _cross

    h = P @ up
    X = np.c_[P @ e1, P @ e2, np.ones(len(h))]
    coef = np.linalg.lstsq(X, h, rcond=None)[0]
    g = float(np.hypot(coef[0], coef[1]))
    if not slope[0] <= g <= slope[1]:
        return False
    lat = P @ _cross(up, (coef[0] * e1 + coef[1] * e2) / g)
    return not float(lat.max() - lat.min()) < min_width


def test_surely_narrow_never_drops_a_cluster_the_exact_fit_keeps():
    """_surely_narrow (the width test from the normal equations, with a margin) is True only
    for point sets whose exact fit fails the slope or the width test: random tilted strips
    and blobs of widths around min_width, slopes in and out of the range, noise, few points;
    and it does say True for most of the narrow ones."""
    from planerel.features.stairfit import StairFitParams, _horizontal_axes, _surely_narrow

    p = StairFitParams()
    rng = np.random.default_rng(2215)
    said, narrow = 0, 0
    for t in range(600):
        up = rng.normal(size=3) * 0.1 + [0.0, -1.0, 0.0]
        up /= np.linalg.norm(up)
        e1, e2 = _horizontal_axes(up)
        n = int(rng.choice([3, 5, 40, 400, 3000]))
        ang = rng.uniform(0, 2 * np.pi)
        f = np.cos(ang) * e1 + np.sin(ang) * e2
        side = np.cross(up, f)
        width = p.min_width * float(rng.choice([0.3, 0.9, 0.99, 0.999, 1.0, 1.001, 1.2, 2.0]))
        length = float(rng.uniform(0.05, 2.0))
        g = float(rng.choice([0.0, 0.1, 0.24, 0.25, 0.26, 0.7, 1.5, 1.6, 3.0]))
        d = rng.uniform(0, length, n)
        lat = rng.uniform(0, width, n)
        if t % 3 == 0:
            lat[:2] = (0.0, width)  # the width reached exactly
        P = (d[:, None] * f + lat[:, None] * side + (g * d + rng.normal(size=n) * 0.002)[:, None]
             * up + rng.normal(size=3) * 2.0)
        got = _surely_narrow(P, e1, e2, up, p.min_width)
        keep = _exact_passes_width(P, e1, e2, up, p.slope, p.min_width)
        assert not (got and keep), (t, n, width, g)
        said += got
        narrow += not keep
    assert said > 0.5 * narrow > 100


@pytest.mark.skipif(not (_DATA / "kinect").is_dir(), reason="needs ../shared/data")
def test_surely_narrow_on_real_clusters():
    """On the Kinect frames' (and the real staircases') unexplained clusters the stairfit
    stage fits: never True where the exact fit passes the width test; True on the first
    Kinect frame's cluster that the exact fit drops by its width."""
    import planerel.features.stairfit as S

    calls = []
    real = S._surely_narrow

    def spy(P, e1, e2, up, min_width):
        got = real(P, e1, e2, up, min_width)
        calls.append((got, _exact_passes_width(P, e1, e2, up, S.StairFitParams().slope,
                                               min_width)))
        return got

    S._surely_narrow = spy
    try:
        for cloud, _labels, planes in [*_real_frames(0), *_staircase_frames()]:
            S._stepped_cluster_labels(cloud, planes)
    finally:
        S._surely_narrow = real
    assert not any(g and k for g, k in calls)
    assert sum(g for g, _ in calls) >= 1


def test_raised_groups_from_the_pixel_list_are_the_grid_forms():
    """raised_clusters' groups from the raised pixels' list (mask_pixels, list_components,
    list_areas) against the whole grid's (np.nonzero, grid_components, component_areas) on a
    window of a cloud (the strided grid of a plane's box), and a group's ring dilated in its
    box widened by ring_px against the whole grid's dilation: bit for bit."""
    from planerel.features._curved_kernels import component_areas, list_areas, list_components
    from planerel.features.curved import _components, _shift_all
    from planerel.segment._label_kernels import mask_pixels

    rng = np.random.default_rng(2216)
    groups = 0
    for _ in range(120):
        rows_, cols_ = (int(v) for v in rng.integers(2, 90, 2))
        xyz = np.stack(np.meshgrid(np.linspace(-1, 1, cols_), np.linspace(-1, 1, rows_)), -1)
        xyz = np.concatenate([xyz, np.full((rows_, cols_, 1), 1.5)], -1)
        xyz[..., 2] += 0.05 * (rng.random((rows_, cols_)) < 0.1)
        f = int(rng.integers(1, 3))
        r0, c0 = int(rng.integers(0, 2)), int(rng.integers(0, 2))
        bx = xyz[r0::f, c0::f]
        mask = rng.random(bx.shape[:2]) < rng.uniform(0.05, 0.7)
        rr, cc = np.nonzero(mask)
        comp, k = _components(mask, bx, 0.02)
        rows, cols = mask_pixels(mask)
        ids, k2 = list_components(rows, cols, bx, 0.02, mask.shape[0])
        assert _same(rows, rr.astype(np.int64)) and _same(cols, cc.astype(np.int64))
        assert k2 == k and _same(ids, comp[rr, cc])
        want = component_areas(bx, rr, cc, comp, 0, 0, 0.0017, 0.0019, k)
        assert _same(list_areas(bx, rows, cols, ids, 0.0017, 0.0019, k), want)
        for c in range(min(k, 3)):
            sel = ids == c
            m = np.zeros(mask.shape, bool)
            m[rows[sel], cols[sel]] = True
            ring_px = int(rng.integers(0, 5))
            full = m
            for axis in (0, 1):
                full = _shift_all(full, ring_px, axis, False)
            g0, g1 = max(0, int(rows[sel].min()) - ring_px), int(rows[sel].max()) + ring_px + 1
            h0, h1 = max(0, int(cols[sel].min()) - ring_px), int(cols[sel].max()) + ring_px + 1
            grown = np.zeros(mask.shape, bool)
            part = m[g0:g1, h0:h1]
            for axis in (0, 1):
                part = _shift_all(part, ring_px, axis, False)
            grown[g0:g1, h0:h1] = part
            assert _same(grown, full)
            groups += 1
    assert groups > 150


def test_touching_labels_with_the_label_count_given():
    """_touching_labels with ``nlab`` taken once by its caller (any count above the largest
    label) gives what it gives taking ``label_max`` itself."""
    from planerel.features.curved import _touching_labels

    rng = np.random.default_rng(2217)
    seen = 0
    for _ in range(60):
        H, W = (int(v) for v in rng.integers(3, 50, 2))
        lab = rng.integers(-1, int(rng.integers(1, 20)), (H, W)).astype(np.int32)
        xyz = np.concatenate([rng.normal(size=(H, W, 2)) * 0.01,
                              np.full((H, W, 1), 1.0)], -1)
        mask = rng.random((H, W)) < 0.2
        want = _touching_labels(mask, lab, xyz, 0.02)
        for extra in (1, 2, 9):
            assert _touching_labels(mask, lab, xyz, 0.02, int(lab.max()) + extra) == want
        seen += len(want)
    assert seen > 100


def _surely_narrow_numpy(P, e1, e2, up, min_width, margin=1e-3, min_det=1e-3):
    """_surely_narrow as it was in numpy (before width_bound, 2026-12-02): the reference."""
    from planerel.features.stairfit import _cross

    u, v, h = P @ e1, P @ e2, P @ up
    du, dv, dh = u - u.mean(), v - v.mean(), h - h.mean()
    suu, suv, svv = float(du @ du), float(du @ dv), float(dv @ dv)
    suh, svh = float(du @ dh), float(dv @ dh)
    det = suu * svv - suv * suv
    if not (len(P) >= 3 and det > 0 and det >= min_det * suu * svv):
        return False, 0.0, 0.0
    a = (svv * suh - suv * svh) / det
    b = (suu * svh - suv * suh) / det
    g = np.hypot(a, b)
    if not g > 0:
        return False, 0.0, 0.0
    lat = P @ _cross(up, (a * np.asarray(e1) + b * np.asarray(e2)) / g)
    reach = np.hypot(float(np.ptp(u)), float(np.ptp(v)))
    return float(np.ptp(lat)) + margin * reach < min_width, float(np.ptp(lat)), reach


def _width_bound_matches(P, e1, e2, up, min_width, narrow=None):
    from planerel.features._stairfit_kernels import width_bound
    from planerel.features.stairfit import _surely_narrow

    _surely_narrow = narrow or _surely_narrow

    ref, w_ref, r_ref = _surely_narrow_numpy(P, e1, e2, up, min_width)
    ok, w, r = width_bound(np.ascontiguousarray(P, dtype=np.float64), e1, e2, up, 1e-3)
    assert _surely_narrow(P, e1, e2, up, min_width) == ref
    if w_ref or r_ref:
        assert ok and w == pytest.approx(w_ref, rel=1e-9, abs=1e-12)
        assert r == pytest.approx(r_ref, rel=1e-9, abs=1e-12)


def test_width_bound_is_the_numpy_width_test():
    """width_bound (one compiled function) against the numpy _surely_narrow it replaced: the
    same answer, the width and the reach equal to 1e-9, on random strips (as above, and
    degenerate ones: collinear, 2 points, NaN) and on the real frames' clusters."""
    from planerel.features.stairfit import StairFitParams, _horizontal_axes

    p = StairFitParams()
    rng = np.random.default_rng(58)
    for t in range(300):
        up = rng.normal(size=3) * 0.1 + [0.0, -1.0, 0.0]
        up /= np.linalg.norm(up)
        e1, e2 = _horizontal_axes(up)
        n = int(rng.choice([2, 3, 5, 40, 400, 3000]))
        ang = rng.uniform(0, 2 * np.pi)
        f = np.cos(ang) * e1 + np.sin(ang) * e2
        side = np.cross(up, f)
        width = p.min_width * float(rng.choice([0.0, 0.3, 0.99, 1.0, 1.2, 2.0]))
        g = float(rng.choice([0.0, 0.25, 0.7, 1.5]))
        d = rng.uniform(0, float(rng.uniform(0.05, 2.0)), n)
        lat = rng.uniform(0, width, n)
        P = (d[:, None] * f + lat[:, None] * side + (g * d + rng.normal(size=n) * 0.002)[:, None]
             * up + rng.normal(size=3) * 2.0)
        if t % 50 == 7:
            P[0, 1] = np.nan
        _width_bound_matches(P, e1, e2, up, p.min_width)


@pytest.mark.skipif(not (_DATA / "kinect").is_dir(), reason="needs ../shared/data")
def test_width_bound_on_real_clusters():
    import planerel.features.stairfit as S

    seen = []
    real = S._surely_narrow

    def spy(P, e1, e2, up, min_width):
        _width_bound_matches(P, e1, e2, up, min_width, real)
        seen.append(len(P))
        return real(P, e1, e2, up, min_width)

    S._surely_narrow = spy
    try:
        for cloud, _labels, planes in [*_real_frames(2), *_staircase_frames()]:
            S._stepped_cluster_labels(cloud, planes)
    finally:
        S._surely_narrow = real
    assert seen
