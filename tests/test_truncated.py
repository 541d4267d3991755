"""Planes not seen whole (cut by the image border or partly hidden): their sizes are lower
bounds, so ``seen_length`` / ``seen_width`` are written only for planes seen whole."""

from __future__ import annotations

import shutil
import subprocess

import numpy as np
from scenes_analytic import Rect, box, floor, render

from planerel.features.facts import describe_scene, facts_text, truncated_planes

SWIPL = shutil.which("swipl") or "/usr/bin/swipl"


def _panels(pitch=0.0):
    # label 0: a 1 m panel 3 m ahead, in view; label 1: a nearer 0.4 m panel hiding its lower
    # left part; label 2: a panel running out of the image on the right
    back = Rect((0.0, 3.0, 1.2), (1, 0, 0), (0, 0, 1), 0.5, 0.5, 1)
    front = Rect((-0.3, 2.0, 1.0), (1, 0, 0), (0, 0, 1), 0.2, 0.2, 2)
    side = Rect((3.0, 3.0, 1.2), (1, 0, 0), (0, 0, 1), 1.5, 0.3, 3)
    return render([back, front, side], pitch=pitch, cam_height=1.2)


def test_hidden_and_border_planes_are_cut_whole_ones_not():
    cloud, lab, _, _ = _panels()
    assert set(np.unique(lab)) == {-1, 0, 1, 2}
    assert truncated_planes(lab, cloud.xyz) == frozenset({0, 2})
    # nothing hides the back panel once the front one is gone
    lab2 = lab.copy()
    xyz = np.array(cloud.xyz)
    assert truncated_planes(np.where(lab2 == 1, -1, lab2), np.where((lab2 == 1)[..., None], np.nan,
                                                                     xyz)) == frozenset({2})
    # a nearer point of no plane hides as much as a plane does
    assert 0 in truncated_planes(np.where(lab2 == 1, -1, lab2), xyz)
    # the share is a threshold on the hidden outline pixels
    assert truncated_planes(lab, cloud.xyz, share=1.0) == frozenset({2})


def test_a_box_in_view_is_whole_the_floor_is_cut():
    cloud, lab, _, _ = render([floor()] + box(0.0, 2.5, 0.5, 0.5, 0.4), pitch=25)
    cut = truncated_planes(lab, cloud.xyz)
    # the floor reaches the image border; the box's faces meet at shared (convex) edges
    assert 0 in cut
    seen = {int(k) for k in np.unique(lab) if k >= 0}
    assert seen - {0} and not (seen - {0}) & cut


def test_empty_and_unlabelled_images():
    assert truncated_planes(np.zeros((0, 0), int), np.zeros((0, 0, 3))) == frozenset()
    assert truncated_planes(np.full((4, 5), -1), np.ones((4, 5, 3))) == frozenset()


def test_seen_sizes_only_for_planes_seen_whole(tmp_path):
    cloud, lab, _, _ = _panels()
    d = describe_scene(cloud, lab, scene_id="s0003", objects=[[0, 1], [2]])
    assert d.truncated == frozenset({0, 2})
    text = facts_text([d])
    for p in ("s0003_p00", "s0003_p01", "s0003_p02"):
        assert f"plane_width({p}," in text and f"plane_length({p}," in text
    assert "seen_width(s0003_p01," in text and "seen_length(s0003_p01," in text
    for p in ("s0003_p00", "s0003_p02"):
        assert f"seen_width({p}," not in text and f"seen_length({p}," not in text
    # in Prolog: a seen size holds for the whole panel only, and equals its measured size
    path = tmp_path / "f.pl"
    path.write_text(text)
    goal = ("findall(P, (has_plane(_, P), seen_width(P, _)), L), writeln(L), "
            "aggregate_all(count, seen_length(_, _), N), writeln(N), "
            "aggregate_all(count, plane_length(_, _), M), writeln(M), "
            "seen_width(s0003_p01, W), plane_width(s0003_p01, W), writeln(same)")
    proc = subprocess.run([SWIPL, "-q", "-g", goal, "-t", "halt", str(path)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["[s0003_p01]", "1", "3", "same"]


def test_default_task_bounds_sizes_in_the_sound_direction():
    from planerel.ilp.aleph_export import task_directives

    modes = {ln for ln in task_directives("modes_relational.pl") if ln.startswith(":- modeb(")}
    # a size in view is a lower bound: "at least" on it, "at most" only on a plane seen whole
    assert ":- modeb(1, gteq(+pwidth, #pwidth))." in modes
    assert ":- modeb(1, gteq(+plength, #plength))." in modes
    assert not any("lteq(+pwidth" in m or "lteq(+plength" in m for m in modes)
    assert ":- modeb(1, lteq(+swidth, #swidth))." in modes
    assert ":- modeb(1, lteq(+slength, #slength))." in modes
    assert ":- modeb(1, seen_width(+plane, -swidth))." in modes


def _truncated_reference(lab, xyz, jump=0.05, band=2, share=0.10, border=1):
    """The numpy form of truncated_planes (as first written, before the kernel)."""
    H, W = lab.shape
    rng = np.sqrt((xyz ** 2).sum(-1))
    rng = np.where(np.isfinite(rng) & (rng > 0), rng, np.inf)
    own = lab >= 0
    pad = np.pad(lab, 1, constant_values=-2)
    outline = own & ((pad[:-2, 1:-1] != lab) | (pad[2:, 1:-1] != lab)
                     | (pad[1:-1, :-2] != lab) | (pad[1:-1, 2:] != lab))
    hidden = np.zeros_like(own)
    for k in range(1, band + 1):
        for dr, dc in ((k, 0), (-k, 0), (0, k), (0, -k)):
            src_r = slice(max(dr, 0), H + min(dr, 0))
            dst_r = slice(max(-dr, 0), H + min(-dr, 0))
            src_c = slice(max(dc, 0), W + min(dc, 0))
            dst_c = slice(max(-dc, 0), W + min(-dc, 0))
            nr = rng[src_r, src_c]
            # inf - inf and 0 x inf (a jump of 0 against an empty pixel) are NaN: no hidden pixel
            with np.errstate(invalid="ignore"):
                gap = rng[dst_r, dst_c] - nr
                hidden[dst_r, dst_c] |= ((lab[src_r, src_c] != lab[dst_r, dst_c]) & np.isfinite(nr)
                                         & (gap > jump * np.maximum(1.0, nr)))
    hidden &= outline
    n = int(lab.max()) + 1
    n_out = np.bincount(lab[outline], minlength=n)
    n_hid = np.bincount(lab[hidden], minlength=n)
    edge = np.zeros((H, W), bool)
    edge[:border + 1, :] = edge[H - border - 1:, :] = True
    edge[:, :border + 1] = edge[:, W - border - 1:] = True
    at_edge = np.bincount(lab[edge & own], minlength=n) > 0
    cut = at_edge | ((n_out > 0) & (n_hid >= share * np.maximum(n_out, 1)))
    present = np.bincount(lab[own], minlength=n) > 0
    return frozenset(int(k) for k in np.nonzero(cut & present)[0]), (n_out, n_hid, at_edge, present)


def test_kernel_matches_the_numpy_form_on_random_images():
    from planerel.features._truncated_kernels import truncation_counts

    rs = np.random.default_rng(5)
    for t in range(80):
        H, W = int(rs.integers(3, 40)), int(rs.integers(3, 40 if t < 60 else 200))
        # blocky labels (runs of one label, as planes make) with holes, depths in steps
        lab = np.repeat(np.repeat(rs.integers(-1, 6, (H // 3 + 1, W // 3 + 1)), 3, 0), 3, 1)[:H, :W]
        z = np.repeat(np.repeat(rs.uniform(0.5, 4.0, (H // 3 + 1, W // 3 + 1)), 3, 0), 3, 1)[:H, :W]
        z = z + rs.normal(0, 0.01, (H, W))
        xyz = np.stack([rs.uniform(-1, 1, (H, W)), rs.uniform(-1, 1, (H, W)), z], -1)
        if t % 2:
            # a single odd pixel inside a plane: eight flags of which one is 0
            lab = np.zeros((H, W), int)
            lab[rs.integers(1, H - 1), rs.integers(1, W - 1)] = -1
        xyz[rs.random((H, W)) < 0.05] = np.nan
        xyz[rs.random((H, W)) < 0.02] = 0.0
        kw = dict(jump=float(rs.choice([0.0, 0.05, 0.2])), band=int(rs.integers(0, 4)),
                  share=float(rs.choice([0.0, 0.1, 0.5])), border=int(rs.integers(0, 3)))
        if not (lab >= 0).any():
            continue
        want, counts = _truncated_reference(lab, xyz, **kw)
        assert truncated_planes(lab, xyz, **kw) == want, (t, kw)
        got = truncation_counts(lab.astype(np.int64), np.ascontiguousarray(xyz, float), kw["jump"],
                                kw["band"], kw["border"], int(lab.max()) + 1)
        for a, b in zip(got, counts, strict=True):
            assert np.array_equal(a, b), (t, kw)


def test_points_of_another_shape_are_refused():
    import pytest

    from planerel.errors import InputError

    with pytest.raises(InputError):
        truncated_planes(np.zeros((4, 5), int), np.zeros((5, 4, 3)))


def _outline_pixels(lab):
    from planerel.segment._label_kernels import label_boundary, mask_pixels

    return mask_pixels(label_boundary(np.ascontiguousarray(lab, dtype=np.int32)))


def test_listed_kernel_matches_the_image_kernel_on_random_images():
    """truncated_at (the outline pixels given as measure_planes lists them, each plane's
    tests stopped once its answer is certain) gives the answer of the image kernel's counts
    and of the numpy form."""
    from planerel.features._truncated_kernels import truncated_at, truncation_counts

    rs = np.random.default_rng(11)
    for t in range(160):
        H, W = int(rs.integers(1, 40)), int(rs.integers(1, 40 if t < 120 else 200))
        blk = int(rs.integers(1, 5))
        lab = np.repeat(np.repeat(rs.integers(-1, 7, (H // blk + 1, W // blk + 1)), blk, 0),
                        blk, 1)[:H, :W].astype(np.int32)
        z = np.repeat(np.repeat(rs.uniform(0.3, 5.0, (H // blk + 1, W // blk + 1)), blk, 0),
                      blk, 1)[:H, :W] + rs.normal(0, 0.01, (H, W))
        xyz = np.stack([rs.uniform(-1, 1, (H, W)), rs.uniform(-1, 1, (H, W)), z], -1)
        xyz[rs.random((H, W)) < 0.05] = np.nan
        xyz[rs.random((H, W)) < 0.02] = 0.0
        if not (lab >= 0).any():
            continue
        jump, band, border = float(rs.choice([0.0, 0.05, 0.2])), int(rs.integers(0, 4)), int(rs.integers(0, 3))
        share = float(rs.choice([0.0, 0.02, 0.1, 0.3, 0.5, 1.0, 1.5, np.nan]))
        n = int(lab.max()) + 1
        brow, bcol = _outline_pixels(lab)
        cut, present = truncated_at(lab, xyz, brow, bcol, jump, band, border, share, n)
        n_out, n_hid, at_edge, present_img = truncation_counts(lab, xyz, jump, band, border, n)
        want = at_edge | ((n_out > 0) & (n_hid >= share * np.maximum(n_out, 1)))
        assert np.array_equal(present, present_img), t
        assert np.array_equal(cut & present, want & present_img), (t, jump, band, border, share)
        if min(H, W) > band + 1:  # (the numpy form's shifted slices wrap on a smaller image)
            ref = _truncated_reference(lab, xyz, jump=jump, band=band, share=share, border=border)[0]
            assert frozenset(int(k) for k in np.nonzero(cut & present)[0]) == ref, t


def test_a_plane_sets_labels_take_the_listed_outline_with_the_same_answer():
    """describe_scene's labels (a PlaneSet's, their boundary pixels remembered by
    measure_planes) go through the listed kernel; a writeable copy of the same image through
    the image kernel: the same cut planes, on a rendered scene and on real frames."""
    from pathlib import Path

    import planerel.features.planes as planes_mod
    from planerel.features.planes import measure_planes

    scenes = []
    cloud, lab, _, _ = render([floor()] + box(0.0, 2.5, 0.5, 0.5, 0.4) + box(0.6, 3.2, 0.4, 0.6, 0.5),
                              pitch=25)
    scenes.append((cloud, lab))
    data = Path(__file__).resolve().parents[2] / "shared" / "data"
    frames = sorted((data / "kinect").glob("frame_*_depth.tiff"))[:1] + sorted((data / "mosd").glob("*.pcd"))[:2]
    if frames:
        from planerel.io.readers import read
        from planerel.segment import segment

        for f in frames:
            c = read(f)
            scenes.append((c, segment(c).labels))
    calls = []
    orig = planes_mod._listed_boundary_pixels

    def spy(x):
        r = orig(x)
        calls.append(r is not None)
        return r

    for cloud, lab in scenes:
        ps = measure_planes(cloud, lab)
        xyz = np.asarray(cloud.xyz, float)
        planes_mod._listed_boundary_pixels = spy
        try:
            fast = truncated_planes(ps.labels, xyz)
        finally:
            planes_mod._listed_boundary_pixels = orig
        assert calls[-1], "the PlaneSet's outline was not taken from measure_planes"
        plain = np.array(ps.labels)  # writeable: nothing remembered for it
        assert planes_mod._listed_boundary_pixels(plain) is None
        assert fast == truncated_planes(plain, xyz) == _truncated_reference(plain, xyz)[0]
