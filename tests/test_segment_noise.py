"""The depth-noise estimator and the settings derived from it, on synthetic planes whose noise
model is known by construction."""

import math

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.io.cloud import Cloud, Intrinsics
from planerel.segment import make_params, segment
from planerel.segment.adapt import FLOOR_SCALE, MIN_SIDE_SIGMAS, adapt_params
from planerel.segment.noise import QUANTILE, NoiseModel, estimate_noise
from planerel.segment.params import scaled_min_region_size

W, H = 320, 240
INTR = Intrinsics.kinect(W, H)
F_NATIVE, BASELINE, STEP = 525.0, 0.075, 0.125  # a Kinect's disparity: f (px), b (m), 1/8 px


def _planes(depths=(1.0, 2.0, 3.0), tilt_deg=50.0):
    """True depth (H, W): one plane per vertical strip of the image, strip k at ``depths[k]``
    along the optical axis, turned by ``tilt_deg`` about the vertical axis (alternating sign)."""
    u, v = np.meshgrid(np.arange(W, dtype=float), np.arange(H, dtype=float))
    rx, ry = (u - INTR.cx) / INTR.fx, (v - INTR.cy) / INTR.fy
    z = np.empty((H, W))
    edges = np.linspace(0, W, len(depths) + 1).astype(int)
    for k, d in enumerate(depths):
        t = math.radians(tilt_deg) * (1 if k % 2 == 0 else -1)
        n = np.array([math.sin(t), 0.0, -math.cos(t)])  # n . X + off = 0 through (0, 0, d)
        off = n[2] * -d
        sl = slice(edges[k], edges[k + 1])
        z[:, sl] = -off / (n[0] * rx[:, sl] + n[1] * ry[:, sl] + n[2])
    return z


def _cloud(z):
    u, v = np.meshgrid(np.arange(W, dtype=float), np.arange(H, dtype=float))
    xyz = np.stack([(u - INTR.cx) / INTR.fx * z, (v - INTR.cy) / INTR.fy * z, z], axis=2)
    return Cloud(xyz, INTR)


def _disparity_quantised(z):
    """Depth measured through a disparity quantised to STEP px: z = f b / round(f b / z)."""
    fb = F_NATIVE * BASELINE
    d = np.round(fb / z / STEP) * STEP
    return fb / d


def test_structured_light_quantisation_at_several_depths():
    # disparity steps give depth steps q z^2 with q = STEP / (f b), uniform within a step:
    # std q z^2 / sqrt(12).  A little Gaussian dither (0.0003 z^2) keeps the steps from
    # lining up with the patches; it adds to the quadratic term in quadrature.
    rng = np.random.default_rng(0)
    zt = _planes((1.0, 1.8, 2.6, 3.4))
    q = STEP / (F_NATIVE * BASELINE)
    zm = _disparity_quantised(zt + 0.0003 * zt ** 2 * rng.standard_normal(zt.shape))
    m = estimate_noise(_cloud(zm))
    expected = math.sqrt((q / math.sqrt(12)) ** 2 + 0.0003 ** 2)
    assert m.kind == "z2"
    assert m.reliable
    assert m.quad == pytest.approx(expected, rel=0.15)
    for z in (1.0, 2.0, 3.0):  # the whole model, at several depths
        assert float(m.sigma(z)) == pytest.approx(expected * z * z, rel=0.15)
    # the bands themselves grow as z^2: std / z^2 the same within 25 % from 1 m to 3.4 m
    ratio = [s / (z * z) for z, s in m.bands]
    assert max(ratio) / min(ratio) < 1.25


def test_kinect_like_gaussian_and_quantisation():
    rng = np.random.default_rng(1)
    zt = _planes((1.2, 2.2, 3.2))
    q = STEP / (F_NATIVE * BASELINE)
    zm = _disparity_quantised(zt + 0.0012 * zt ** 2 * rng.standard_normal(zt.shape))
    m = estimate_noise(_cloud(zm))
    assert m.kind == "z2"
    assert m.quad == pytest.approx(math.sqrt(0.0012 ** 2 + q * q / 12), rel=0.1)


@pytest.mark.parametrize("sigma", [0.0005, 0.002])
def test_uniform_gaussian_noise(sigma):
    rng = np.random.default_rng(2)
    zt = _planes((0.9, 1.5, 2.5))
    m = estimate_noise(_cloud(zt + sigma * rng.standard_normal(zt.shape)))
    assert m.kind == "uniform"
    for z in (0.9, 1.5, 2.5):  # constant in depth
        assert float(m.sigma(z)) == pytest.approx(sigma, rel=0.12)
    assert m.pixels(1.5) == pytest.approx(sigma / (1.5 / INTR.fx), rel=0.12)


def test_noise_free_planes():
    m = estimate_noise(_cloud(_planes()))
    assert m.kind == "none"
    assert float(m.sigma(2.0)) < 1e-9
    assert m.reliable


def test_edges_and_holes_do_not_raise_the_estimate():
    # a quarter of the patches cross a depth step or hold a hole: the robust band statistic
    # still gives the noise of the planes
    rng = np.random.default_rng(3)
    zt = _planes((1.0, 1.4, 1.8, 2.2, 2.6, 3.0, 3.4, 3.8))
    zm = zt + 0.001 * rng.standard_normal(zt.shape)
    zm[::17, :] += 0.2  # thin ridges: every patch row crossing them has an edge
    zm[rng.random(zm.shape) < 0.01] = np.nan
    m = estimate_noise(_cloud(zm))
    assert float(m.sigma(2.0)) == pytest.approx(0.001, rel=0.2)


def test_too_few_patches_and_bad_input():
    z = np.full((H, W), np.nan)
    z[:4, :4] = 1.0  # a few valid pixels: no complete patch
    m = estimate_noise(_cloud(z))
    assert m.n_patches == 0 and not m.reliable and m.kind == "none"
    flat = Cloud(np.random.default_rng(0).random((1, 50, 3)), None, organized=False)
    with pytest.raises(InputError, match="organized cloud"):
        estimate_noise(flat)
    with pytest.raises(InputError, match="patch must be an integer >= 3"):
        estimate_noise(_cloud(_planes()), patch=2)
    with pytest.raises(InputError, match="max_patches must be a positive integer"):
        estimate_noise(_cloud(_planes()), max_patches=0)


def _model(kind, sigma, z=1.0, fx=INTR.fx):
    return NoiseModel(kind, sigma if kind == "uniform" else 0.0,
                      sigma / z ** 2 if kind == "z2" else 0.0, z, z, z, 1.0 / fx, 1000)


def test_settings_follow_the_noise_in_pixels():
    p = make_params("regiongrow")
    floor = scaled_min_region_size(W * H, FLOOR_SCALE)
    # uniform noise of 1.5 pixel footprints: window round(sqrt(12) * 1.5) = 5 px at every
    # depth, min region (20 * 1.5)^2 = 900 px
    foot = 1.0 / INTR.fx
    out, info = adapt_params(p, _model("uniform", 1.5 * foot), (H, W))
    assert out.normal_smooth == out.normal_radius == round(math.sqrt(12) * 1.5)
    assert out.reference_depth is None
    assert out.min_region_size == round((MIN_SIDE_SIGMAS * 1.5) ** 2) == 900
    assert info["adapted"] and info["min_region_area_m2"] == pytest.approx(900 * foot ** 2, rel=1e-4)
    # disparity-type noise: the window keeps growing with depth beyond 2 m; low noise hits
    # the resolution floor
    out, info = adapt_params(p, _model("z2", 0.2 * foot), (H, W))
    assert out.normal_smooth == "auto" and out.reference_depth == 2.0
    assert out.min_region_size == floor
    # explicit values and min_region_scale are kept / applied
    q = make_params("regiongrow", normal_smooth=1, min_region_scale=0.5)
    out, _ = adapt_params(q, _model("uniform", 1.5 * foot), (H, W))
    assert out.normal_smooth == 1 and out.normal_radius == 5
    assert out.min_region_size == 450
    # no noise measured, or adaptation off: the fixed defaults
    for prm, mdl in ((p, _model("none", 0.0)), (p, None),
                     (make_params("regiongrow", preset="kinect"), _model("uniform", 1.5 * foot))):
        out, info = adapt_params(prm, mdl, (H, W))
        assert not info["adapted"]
        assert out.min_region_size == "auto" and out.normal_smooth == "auto"
        assert out.reference_depth == 2.0


def test_segmentation_reports_model_and_settings():
    rng = np.random.default_rng(4)
    zt = _planes((0.9, 1.5, 2.5))
    cloud = _cloud(zt + 0.0015 * rng.standard_normal(zt.shape))
    seg = segment(cloud)
    nm, st = seg.info["noise_model"], seg.info["settings"]
    assert nm["kind"] == "uniform" and nm["sigma_median_m"] == pytest.approx(0.0015, rel=0.12)
    assert st["adapted"] and st["min_region_size"] == seg.info["min_region_size"]
    assert st["reference_depth"] is None
    # the three planes come out
    assert seg.n_planes == 3
    fixed = segment(cloud, preset="kinect")
    assert fixed.info["settings"]["adapted"] is False
    assert fixed.info["min_region_size"] == scaled_min_region_size(W * H)


def _bent_floor(sag):
    """A floor seen from 1 m height, pitched 45 degrees down, bent by ``sag`` metres at its
    far corners (a paraboloid, as a Kinect's depth distortion bends real floors), with
    Kinect-like noise and disparity steps."""
    rng = np.random.default_rng(5)
    u, v = np.meshgrid(np.arange(W, dtype=float), np.arange(H, dtype=float))
    ray = np.stack([(u - INTR.cx) / INTR.fx, (v - INTR.cy) / INTR.fy, np.ones_like(u)], axis=2)
    c, s = math.cos(math.radians(45)), math.sin(math.radians(45))
    up = np.array([0.0, -c, -s])  # world up in the camera frame
    t = 1.0 / np.maximum(-(ray @ up), 1e-9)  # ray hits the flat floor 1 m below the camera
    p = ray * t[..., None]
    fwd = np.array([0.0, s, -c])
    side, ahead = p[..., 0], p @ fwd
    bump = sag * ((side / 1.0) ** 2 + ((ahead - 1.2) / 1.0) ** 2)
    t = t * (1.0 - bump / 1.0)  # raise the floor by `bump` along up (approximately)
    z = t
    z = np.where((z > 0.3) & (z < 4.0), z, np.nan)
    zn = _disparity_quantised(z + 0.0012 * z ** 2 * rng.standard_normal(z.shape))
    return _cloud(zn)


def test_a_slightly_bent_floor_stays_one_region():
    # a real floor is not planar within the sensor noise (here 12 mm of sag at the far
    # corners); the split step cut it into parallel slabs and the merge step kept them apart
    cloud = _bent_floor(0.012)
    from planerel.segment.split import SplitParams

    seg = segment(cloud)
    largest = max(p.n_points for p in seg.planes)
    assert largest >= 0.95 * cloud.n_valid
    old = segment(cloud, split_params=SplitParams(min_split_angle=0, absorb=False))
    assert max(p.n_points for p in old.planes) < 0.6 * cloud.n_valid


@pytest.mark.parametrize("sensor", ["structured-light", "laser"])
def test_the_synthetic_worlds_sensor_models_are_recognised(sensor):
    # planerel.synth.sensor's documented noise: structured light sigma_z = z^2 / (f b) *
    # sqrt(sigma_d^2 + step^2 / 12) = 1.43e-3 z^2; the laser a constant 10 mm
    from planerel.synth.generator import generate_scene
    from planerel.synth.sensor import StructuredLight, TimeOfFlight

    sen = StructuredLight() if sensor == "structured-light" else TimeOfFlight.laser()
    m = estimate_noise(generate_scene("box", 1, subsample=2, sensor=sen).cloud)
    if sensor == "structured-light":
        fb = sen.focal_px * abs(sen.baseline)
        quad = math.sqrt(sen.disparity_noise ** 2 + sen.disparity_step ** 2 / 12) / fb
        assert m.kind == "z2" and m.quad == pytest.approx(quad, rel=0.08)
    else:
        assert m.kind == "uniform" and float(m.sigma(2.0)) == pytest.approx(0.010, rel=0.08)


def test_band_statistics_kernels_equal_numpy():
    """The compiled band medians and quantiles of the estimate equal ``np.median`` /
    ``np.quantile`` of the former statements, bit for bit."""
    from planerel.segment._noise_kernels import band_quantiles, sorted_median

    rng = np.random.default_rng(7)
    for nb, size in ((1, 60), (3, 61), (8, 517)):
        zc = np.sort(rng.uniform(0.4, 6.0, nb * size))
        sd = rng.gamma(2.0, 1e-3, nb * size)
        bz = np.median(zc.reshape(nb, size), axis=1)
        np.testing.assert_array_equal(
            [sorted_median(zc, b * size, (b + 1) * size) for b in range(nb)], bz)
        assert sorted_median(zc, 0, len(zc)) == np.median(zc)
        band = np.repeat(np.arange(nb), size)
        for const, quad in ((1.0, 0.0), (2e-3, 1.5e-3), (0.0, 3e-3)):
            shape = np.sqrt(const ** 2 + (quad * bz[band] ** 2) ** 2) / np.sqrt(
                const ** 2 + (quad * zc * zc) ** 2)
            want = np.quantile((sd * shape).reshape(nb, size), QUANTILE, axis=1) * 1.0614
            got = band_quantiles(zc, sd, bz, nb, size, const ** 2, quad, QUANTILE, 1.0614)
            np.testing.assert_array_equal(got, want)


def test_wide_noise_window_is_off_by_default_and_widens_for_correlated_noise():
    # noise58: a z2 frame whose 5 px noise is small (nominal window) but whose 15 px noise is
    # 2 pixel footprints: with the switch the window is round(sqrt(12) * 2 * 1.0186 / 1.0614)
    # = 7 px; off (the default) the wide estimate is ignored; explicit values are kept
    from planerel.segment.noise import QUANTILE_TO_MEDIAN, WIDE_QUANTILE_TO_MEDIAN

    foot = 1.0 / INTR.fx
    small, wide = _model("z2", 0.2 * foot), _model("z2", 2.0 * foot)
    p = make_params("regiongrow")
    assert p.wide_noise_window is False
    out, info = adapt_params(p, small, (H, W), wide=wide)
    assert out.normal_smooth == "auto" and "wide_noise_pixels" not in info
    on = make_params("regiongrow", wide_noise_window=True)
    out, info = adapt_params(on, small, (H, W), wide=wide)
    want = round(math.sqrt(12) * 2.0 * WIDE_QUANTILE_TO_MEDIAN / QUANTILE_TO_MEDIAN)
    assert out.normal_smooth == out.normal_radius == want == 7
    assert out.reference_depth == 2.0
    out, _ = adapt_params(on, small, (H, W), wide=_model("z2", 0.2 * foot))
    assert out.normal_smooth == "auto"  # no wider than the nominal window: unchanged
    out, _ = adapt_params(make_params("regiongrow", wide_noise_window=True, normal_radius=2),
                          small, (H, W), wide=wide)
    assert out.normal_smooth == 7 and out.normal_radius == 2
    with pytest.raises(InputError):
        make_params("regiongrow", wide_noise_window="maybe")


def test_wide_noise_window_sees_smoothed_noise_in_a_segmentation():
    # a plane at 1.5 m with noise smoothed over 2 px: the 5 px estimate misses most of it, the
    # switch widens the window (segmentation info), off keeps the nominal window
    from scipy.ndimage import gaussian_filter

    rng = np.random.default_rng(5)
    z = _planes((1.5,), tilt_deg=20.0)
    n = gaussian_filter(rng.standard_normal(z.shape), 2.0)
    c = _cloud(z + 0.012 * n / n.std())
    off = segment(c, method="regiongrow")
    on = segment(c, method="regiongrow", params=make_params("regiongrow", wide_noise_window=True))
    assert off.info["settings"]["normal_smooth"] == "auto" or off.info["settings"]["normal_smooth"] <= 2
    assert on.info["settings"]["wide_noise_pixels"] > 1.0
    assert on.info["settings"]["normal_smooth"] > 2


def _noisy_slope(k, seed=0, w=320, h=240):
    """A sloping plane 2-2.5 m away with ``k z^2`` depth noise smoothed over 2 px (a stereo
    sensor's correlated error)."""
    from scipy.ndimage import gaussian_filter

    intr = Intrinsics.kinect(w, h)
    u, v = np.meshgrid(np.arange(w), np.arange(h))
    x, y = (u - intr.cx) / intr.fx, (v - intr.cy) / intr.fy
    z = 2.0 + 0.5 * y
    if k:
        n = gaussian_filter(np.random.default_rng(seed).standard_normal((h, w)), 2.0)
        z = z + k * z ** 2 * n / n.std()
    return Cloud(np.stack([x * z, y * z, z], axis=2), intr)


def test_wide_fallback_only_where_the_narrow_window_fails():
    assert make_params("regiongrow").wide_fallback == 0.15  # on by default since up66
    clean = _noisy_slope(0.0)
    a, b = segment(clean, wide_fallback=0), segment(clean, wide_fallback=0.5)
    assert np.array_equal(a.labels, b.labels) and "wide_fallback" not in b.info
    noisy = _noisy_slope(0.005)
    valid = np.asarray(noisy.valid)
    off = segment(noisy, wide_fallback=0)
    on = segment(noisy, wide_fallback=0.5)
    assert (off.labels[valid] >= 0).mean() < 0.5  # the 2 px window: normals of noise
    share, wide = on.info["wide_fallback"]
    assert share < 0.5 and wide > 0.9
    assert (on.labels[valid] >= 0).mean() == pytest.approx(wide, abs=1e-3)
    with pytest.raises(InputError, match="wide_fallback"):
        make_params("regiongrow", wide_fallback=1.5)


def test_the_estimate_is_measured_once_a_cloud():
    """estimate_noise remembers its model per cloud (read-only points): a second call returns
    the same model; without waviness after a call with it, the same model with ``wave`` 0,
    what a fresh cloud of the same points measures (eye62)."""
    rng = np.random.default_rng(3)
    z = _planes() + rng.normal(0, 0.002, (H, W))
    a, b = _cloud(z), _cloud(z)
    wavy = estimate_noise(a, waviness=True)
    assert estimate_noise(a, waviness=True) is wavy
    plain = estimate_noise(a)
    assert plain == estimate_noise(b)  # another cloud object: measured afresh
    assert plain.wave == 0 and plain.wave_window == 0
    assert (plain.const, plain.quad, plain.bands) == (wavy.const, wavy.quad, wavy.bands)
    assert estimate_noise(b, waviness=True) == wavy
    # other arguments are other measurements
    seven = estimate_noise(a, patch=7)
    assert seven is not plain and seven == estimate_noise(b, patch=7)


def test_wide_fallback_takes_the_widest_window_where_no_wide_patch_can_be_measured():
    # up66: an R200's speckled depth (holes everywhere) leaves no 15 x 15 px patch for the wide
    # noise estimate, so the fallback's own window would be the narrow one again; it then grows
    # with MAX_WINDOW
    from planerel.segment.adapt import MAX_WINDOW
    from planerel.segment.noise import WIDE_PATCH, estimate_noise

    noisy = _noisy_slope(0.005, seed=2)
    xyz = np.array(noisy.xyz)
    xyz[::14, :] = np.nan   # a row and a column without depth every 14 px: no 15 px patch
    xyz[:, ::14] = np.nan
    speckled = Cloud(xyz, noisy.intrinsics)
    assert not estimate_noise(speckled, patch=WIDE_PATCH).reliable
    valid = np.asarray(speckled.valid)
    off = segment(speckled, wide_fallback=0)
    on = segment(speckled, wide_fallback=0.5)
    share, wide = on.info["wide_fallback"]
    assert share == pytest.approx(float((off.labels[valid] >= 0).mean()), abs=1e-3) and share < 0.5
    assert on.info["settings"]["normal_smooth"] == on.info["settings"]["normal_radius"] == MAX_WINDOW
    assert share < 0.1 and wide > 0.9
    assert (on.labels[valid] >= 0).mean() == pytest.approx(wide, abs=1e-3)
    # a window the caller set is not widened
    mine = segment(speckled, wide_fallback=0.5, normal_smooth=1, normal_radius=1)
    assert mine.info["settings"]["normal_smooth"] == mine.info["settings"]["normal_radius"] == 1
