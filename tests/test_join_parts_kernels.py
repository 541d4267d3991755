"""join22: :func:`planerel.features.curved.join_parts` in compiled passes
(``join_owners``, ``mark_held``, ``join_part_targets``) gives exactly what its numpy version
(synth22q, kept below as the reference) gave: the same proposals, point counts and joined
pixels, on random scenes, a rendered chair and real frames (docs/objects.md, "join_parts
compiled (join22)")."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scenes_analytic import Rect, floor, render

import planerel.features.curved as curved_mod
from planerel.features.curved import CurvedObject, CurvedParams, join_parts
from planerel.features.facts import describe_scene

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def reference_join_parts(cobjs, xyz, labels, edge_depth=0.02, min_touch=3):
    """The numpy join_parts of synth22q (commit d24f008), the reference."""
    from planerel.features._curved_kernels import list_components, unexplained_open

    lab = np.asarray(labels)
    xyz = np.asarray(xyz, float)
    if not cobjs or lab.shape != xyz.shape[:2]:
        return list(cobjs)
    H, W = lab.shape
    nl = max(int(lab.max()) + 1, 1)
    lut = np.full(nl + 1, -1, np.int64)
    for k, c in enumerate(cobjs):
        for x in c.planes:
            if 0 <= int(x) < nl:
                lut[int(x)] = k
    _un, rows, cols = unexplained_open(np.isfinite(xyz[..., 2]), lab, np.ones(nl, np.bool_), 0)
    if not len(rows):
        return list(cobjs)
    held = np.full(len(rows), -1, np.int64)
    for k, c in enumerate(cobjs):
        if c.mask is not None:
            inm = np.asarray(c.mask, bool)[rows, cols] & (held < 0)
            held[inm] = k
    keep = held < 0
    mo = np.full((H, W), -1, np.int64)
    mo[rows[~keep], cols[~keep]] = held[~keep]
    rows, cols = rows[keep], cols[keep]
    if not len(rows):
        return list(cobjs)
    pid, n = list_components(rows, cols, xyz, float(edge_depth), H)
    pts = xyz[rows, cols]
    z = np.abs(pts[:, 2])
    lim = edge_depth * np.where(z > 1.0, z, 1.0)
    m = len(cobjs)
    counts = np.zeros(n * m, np.int64)
    for dy, dx in ((0, 1), (0, 2), (1, 0), (2, 0), (0, -1), (0, -2), (-1, 0), (-2, 0)):
        r2, c2 = rows + dy, cols + dx
        ok = np.nonzero((r2 >= 0) & (r2 < H) & (c2 >= 0) & (c2 < W))[0]
        r2, c2 = r2[ok], c2[ok]
        lb = lab[r2, c2]
        b = np.where(lb >= 0, lut[np.clip(lb, 0, nl)], mo[r2, c2])
        hit = b >= 0
        ok, b, r2, c2 = ok[hit], b[hit], r2[hit], c2[hit]
        if not len(ok):
            continue
        d = np.linalg.norm(pts[ok] - xyz[r2, c2], axis=1)
        near = d <= lim[ok]
        counts += np.bincount(pid[ok[near]] * m + b[near], minlength=n * m)
    counts = counts.reshape(n, m)
    size = np.bincount(pid, minlength=n)
    out = list(cobjs)
    order = np.argsort(pid, kind="stable")
    start = np.searchsorted(pid[order], np.arange(n + 1))
    grown: dict = {}
    for part in np.nonzero((counts > 0).sum(axis=1) == 1)[0]:
        k = int(np.argmax(counts[part]))
        if counts[part, k] < min_touch or size[part] > out[k].n_points:
            continue
        if k not in grown:
            grown[k] = (np.zeros((H, W), bool) if out[k].mask is None
                        else np.array(out[k].mask, dtype=bool))
        sel = order[start[part]:start[part + 1]]
        grown[k][rows[sel], cols[sel]] = True
        c = out[k]
        out[k] = CurvedObject(c.planes, c.mask, c.planar_fraction, c.curved,
                              int(c.n_points + size[part]))
    for k, g in grown.items():
        c = out[k]
        out[k] = CurvedObject(c.planes, g, c.planar_fraction, c.curved, c.n_points)
    return out


_masks_before: list = []


def assert_same(got, want, given):
    assert len(got) == len(want)
    for g, w in zip(got, want, strict=True):
        assert (g.planes, g.planar_fraction, g.curved, g.n_points) == \
            (w.planes, w.planar_fraction, w.curved, w.n_points)
        assert (g.mask is None) == (w.mask is None)
        if w.mask is not None:
            assert np.array_equal(np.asarray(g.mask, bool), np.asarray(w.mask, bool))
    # the given proposals' masks are left as they were (a grown mask is a new array)
    for c, before in zip(given, _masks_before, strict=True):
        assert (c.mask is None) == (before is None)
        if before is not None:
            assert np.array_equal(c.mask, before)


def _random_scene(seed: int):
    """Random plane blobs, unassigned parts between them, holes without depth, and masks
    that overlap (the first mask holds the shared pixels)."""
    rng = np.random.default_rng(seed)
    h, w = 48, 64
    yy, xx = np.mgrid[0:h, 0:w]
    z = 1.0 + 0.8 * rng.random() + 0.004 * rng.standard_normal((h, w))
    z = np.where(rng.random((h, w)) < 0.05, z + 0.3, z)  # depth jumps: parts apart
    xyz = np.stack([xx * 0.01 * z, yy * 0.01 * z, z], axis=-1)
    lab = np.full((h, w), -1, np.int32)
    nlab = int(rng.integers(2, 9))
    for a in range(nlab):
        r0, c0 = int(rng.integers(0, h - 6)), int(rng.integers(0, w - 6))
        lab[r0:r0 + int(rng.integers(3, 14)), c0:c0 + int(rng.integers(3, 20))] = a
    lab[rng.random((h, w)) < 0.03] = -1
    xyz[rng.random((h, w)) < 0.04] = np.nan
    cobjs = []
    for _ in range(int(rng.integers(1, 6))):
        planes = tuple(int(x) for x in rng.choice(nlab, size=int(rng.integers(0, 3)),
                                                  replace=False))
        mask = None
        if rng.random() < 0.5:
            mask = np.zeros((h, w), bool)
            r0, c0 = int(rng.integers(0, h - 8)), int(rng.integers(0, w - 8))
            mask[r0:r0 + 8, c0:c0 + int(rng.integers(2, 12))] = True
        npts = int(rng.integers(0, 300))
        cobjs.append(CurvedObject(planes, mask, float(rng.random()), bool(rng.random() < .5),
                                  npts))
    return cobjs, xyz, lab


@pytest.mark.parametrize("seed", range(40))
def test_compiled_join_parts_equals_numpy_reference_on_random_scenes(seed):
    cobjs, xyz, lab = _random_scene(seed)
    _masks_before[:] = [None if c.mask is None else c.mask.copy() for c in cobjs]
    for edge, touch in ((0.02, 3), (0.05, 1)):
        assert_same(join_parts(cobjs, xyz, lab, edge, touch),
                    reference_join_parts(cobjs, xyz, lab, edge, touch), cobjs)


def test_random_scenes_exercise_joins_and_refusals():
    # the random scenes are no empty comparison: parts join, and some are refused
    joined = refused = 0
    for seed in range(40):
        cobjs, xyz, lab = _random_scene(seed)
        out = join_parts(cobjs, xyz, lab)
        joined += sum(o.n_points > c.n_points for o, c in zip(out, cobjs, strict=True))
        refused += sum(o.n_points == c.n_points for o, c in zip(out, cobjs, strict=True))
    assert joined >= 20 and refused >= 20


def _captured(monkeypatch, cloud, labels):
    """The proposals describe_scene hands join_parts (join_parts on) for ``cloud``."""
    seen = []
    orig = curved_mod.join_parts

    def rec(cobjs, xyz, lab, *a, **k):
        seen.append((list(cobjs), np.array(xyz), np.array(lab), a, k))
        return orig(cobjs, xyz, lab, *a, **k)

    monkeypatch.setattr(curved_mod, "join_parts", rec)
    describe_scene(cloud, labels, curved_params=CurvedParams(join_parts=True))
    monkeypatch.undo()
    assert len(seen) == 1
    return seen[0]


def test_compiled_join_parts_equals_reference_on_a_rendered_chair(monkeypatch):
    seat = Rect((0.0, 2.0, 0.45), (1, 0, 0), (0, 1, 0), 0.22, 0.22, 1)
    legs = [Rect((sx * 0.2, 2.0 - 0.2, 0.225), (1, 0, 0), (0, 0, 1), 0.015, 0.225, 1)
            for sx in (-1, 1)]
    cloud, lab, _up, _objs = render([floor(), seat] + legs, pitch=20, cam_height=1.2,
                                    width=320, height=240, noise=0.001)
    lab = lab.copy()
    lab[lab >= 2] = -1
    cobjs, xyz, lab2, a, k = _captured(monkeypatch, cloud, lab)
    _masks_before[:] = [None if c.mask is None else np.array(c.mask) for c in cobjs]
    got = join_parts(cobjs, xyz, lab2, *a, **k)
    assert_same(got, reference_join_parts(cobjs, xyz, lab2, *a, **k), cobjs)
    assert any(g.n_points > c.n_points for g, c in zip(got, cobjs, strict=True))  # the legs joined


@pytest.mark.skipif(not (DATA / "mosd" / "test31.pcd").is_file()
                    or not (DATA / "kinect").is_dir(), reason="shared real frames absent")
@pytest.mark.parametrize("name", ["mosd/test31.pcd", "mosd/learn1.pcd", "kinect/first-tiff"])
def test_compiled_join_parts_equals_reference_on_real_frames(monkeypatch, name):
    from planerel.io import readers as io
    from planerel.segment import segment

    path = (sorted((DATA / "kinect").glob("*_depth.tiff"))[0] if name == "kinect/first-tiff"
            else DATA / name)
    cloud = io.read(path)
    cobjs, xyz, lab, a, k = _captured(monkeypatch, cloud, segment(cloud).labels)
    _masks_before[:] = [None if c.mask is None else np.array(c.mask) for c in cobjs]
    got = join_parts(cobjs, xyz, lab, *a, **k)
    assert_same(got, reference_join_parts(cobjs, xyz, lab, *a, **k), cobjs)
    assert any(g.n_points > c.n_points for g, c in zip(got, cobjs, strict=True))


@pytest.mark.parametrize("npts,joins", [(16, True), (15, False)])
def test_a_part_as_large_as_its_proposal_joins_a_larger_one_does_not(npts, joins):
    h, w = 12, 8
    yy, xx = np.mgrid[0:h, 0:w]
    xyz = np.stack([xx * 0.01, yy * 0.01, np.full((h, w), 1.0)], axis=-1)
    lab = np.full((h, w), -1, np.int32)
    lab[0:4, 0:8] = 0
    valid = lab >= 0
    valid[4:12, 3:5] = True  # a leg of 16 pixels under the plane
    xyz[~valid] = np.nan
    objs = [CurvedObject((0,), None, 1.0, False, npts)]
    _masks_before[:] = [None]
    out = join_parts(objs, xyz, lab)
    assert_same(out, reference_join_parts(objs, xyz, lab), objs)
    assert out[0].n_points == (npts + 16 if joins else npts)
    assert (out[0].mask is not None) == joins
