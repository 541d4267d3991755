"""speed22z: the proposal rules' pairs found with fewer Python steps give what the rules gave.

``open_wall_objects`` looks only at the pairs of walls of two proposals whose normals come
within a hair of parallel (one matrix test) and takes each near wall's hull measures once, when
a pair needs them.  The reference below is the rule as it stood before (main 58a44e7), one
wall and one pair at a time; both run on the arguments the real flow gives them
(``describe_scene`` on rendered scenes with open boxes, closed boxes and walls side by side,
near and far, turned, with the rule's thresholds crossed).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scenes_analytic import Rect, box, floor, render

import planerel.features.open_walls as ow
from planerel.features.facts import describe_scene


def _old_open_wall_objects(planes, objects, params, curved_below=0.8, xyz=None):
    """The rule before speed22z (every wall's measures first, then its parallel pairs)."""
    from planerel.features.vectors import cross3

    lab = getattr(planes, "labels", None)
    if (not params.open_walls or xyz is None or len(objects) < 2 or lab is None
            or lab.shape != xyz.shape[:2]):
        return objects
    owner = {x: k for k, o in enumerate(objects) for x in o.planes}
    verts = [p for p in planes if p.orientation == "vertical" and p.label in owner]
    if len(verts) < 2:
        return objects
    up = np.asarray(planes.up, float)
    flats = [p for p in planes if p.orientation == "horizontal"]
    byl = {p.label: p for p in planes}
    cos_par = math.cos(math.radians(params.concave_tol))
    H, W = lab.shape
    seen: dict = {}

    def top_seen(p) -> bool:
        if p.label not in seen:
            r, c = np.nonzero(lab == p.label)
            h = xyz[r, c] @ up
            ok = np.isfinite(h)
            r, c, h = r[ok], c[ok], h[ok]
            if not len(h):
                seen[p.label] = False
            else:
                hi = h >= np.percentile(h, 95.0)
                edge = (r[hi] <= 1) | (r[hi] >= H - 2) | (c[hi] <= 1) | (c[hi] >= W - 2)
                seen[p.label] = float(edge.mean()) <= ow.TOP_CUT
        return seen[p.label]

    normals = np.array([np.asarray(p.normal, float) for p in verts])
    near = normals @ normals.T >= cos_par - 1e-9
    np.fill_diagonal(near, False)
    pairs = []
    for i, a in enumerate(verts):
        if not near[i].any():
            continue
        na = normals[i]
        ha = np.asarray(a.hull3d, float)
        da = abs(float(na @ np.asarray(a.centroid, float)))
        ta = float((ha @ up).max())
        across = cross3(up, na)
        norm = float(np.linalg.norm(across))
        if norm == 0:
            continue
        across = across / norm
        a0, a1 = float((ha @ across).min()), float((ha @ across).max())
        for j in np.flatnonzero(near[i]):
            b = verts[j]
            if owner[a.label] == owner[b.label]:
                continue
            if float(na @ normals[j]) < cos_par:
                continue
            cb = np.asarray(b.centroid, float)
            depth = abs(float(na @ cb)) - da
            if not ow.WALL_DEPTH[0] <= depth <= ow.WALL_DEPTH[1]:
                continue
            hb = np.asarray(b.hull3d, float)
            tol = ow.WALL_LEVEL * max(1.0, float(np.linalg.norm(cb)))
            if abs(ta - float((hb @ up).max())) > tol:
                continue
            b0, b1 = float((hb @ across).min()), float((hb @ across).max())
            inter = min(a1, b1) - max(a0, b0)
            if inter <= 0 or inter / (max(a1, b1) - min(a0, b0)) < ow.WALL_OVERLAP:
                continue
            if any(ow._top_between(f, up, na, da, depth, ta, tol, across, a0, a1) for f in flats):
                continue
            if any(abs(float(np.asarray(byl[x].centroid, float) @ up) - ta) <= tol
                   for x in (*objects[owner[a.label]].planes, *objects[owner[b.label]].planes)
                   if byl[x].orientation == "horizontal"):
                continue
            if not (top_seen(a) and top_seen(b)):
                continue
            pairs.append((owner[a.label], owner[b.label]))
    return ow.join_groups(objects, pairs, curved_below) if pairs else objects


def _key(objs):
    return [(o.planes, None if o.mask is None else o.mask.tobytes(), o.planar_fraction,
             o.curved, o.n_points) for o in objs]


class _Planes(list):
    """The PlaneSet fields the rule reads."""

    def __init__(self, planes, up, labels):
        super().__init__(planes)
        self.up, self.labels = up, labels


def _random_walls(rng):
    """Walls near the rule's thresholds: normals within a few degrees of parallel (some turned
    away), depths about 5 cm and 0.6 m apart, tops about level, extents about half overlapping,
    some flat planes between them, two to four proposals; a label image of blocks, some on
    the image's border."""
    from types import SimpleNamespace

    from planerel.features.curved import CurvedObject

    up = np.array([0.0, -0.8, -0.6])
    H, W = 40, 60
    lab = np.full((H, W), -1, np.int32)
    xyz = rng.normal(size=(H, W, 3))
    n_obj = int(rng.integers(2, 5))
    planes, members = [], [[] for _ in range(n_obj)]
    base = np.array([0.0, 0.6, -0.8])
    for k in range(int(rng.integers(2, 9))):
        vertical = rng.random() < 0.8
        n = base + rng.normal(scale=0.08, size=3) if vertical else up.copy()
        if vertical and rng.random() < 0.1:
            n = -n
        n /= np.linalg.norm(n)
        depth = float(rng.choice([0.05, 0.6, 0.3, 0.02, 0.7])) + rng.normal(scale=0.01)
        c = np.array([rng.normal(scale=0.1), 0.0, 2.0]) - n * depth * (k % 2)
        across = np.cross(up, n)
        across /= np.linalg.norm(across) if np.linalg.norm(across) else 1.0
        w, h = rng.uniform(0.1, 0.4), rng.uniform(0.1, 0.3) + rng.normal(scale=0.03)
        shift = rng.uniform(-0.2, 0.2)
        hull = np.array([c + (shift + sa * w) * across + sb * h * up for sa in (-1, 1) for sb in (-1, 1)])
        label = k + 1
        r0, c0 = int(rng.integers(0, H - 6)), int(rng.integers(0, W - 6))
        lab[r0:r0 + 6, c0:c0 + 6] = label
        planes.append(SimpleNamespace(label=label, orientation="vertical" if vertical else "horizontal",
                                      normal=n, centroid=c, hull3d=hull))
        members[int(rng.integers(0, n_obj))].append(label)
    objects = [CurvedObject(tuple(sorted(m)), None, 1.0, False, 10 * len(m)) for m in members if m]
    return _Planes(planes, up, lab), objects, xyz


def test_open_walls_as_before_on_random_walls():
    from planerel.features.relations import ProposalParams

    params = ProposalParams()
    rng = np.random.default_rng(2211)
    joined = refused = 0
    for _ in range(3000):
        planes, objects, xyz = _random_walls(rng)
        got = ow.open_wall_objects(planes, objects, params, 0.8, xyz)
        want = _old_open_wall_objects(planes, objects, params, 0.8, xyz)
        assert _key(got) == _key(want)
        assert (got is objects) == (want is objects)
        joined += got is not objects
        refused += got is objects and len(objects) > 1
    assert joined > 50 and refused > 50  # both outcomes common


def _wall(cx, cy, h, w, obj, turn=0.0, z0=0.0):
    """A vertical face ``w`` wide and ``h`` high facing the camera, turned ``turn`` degrees."""
    t = math.radians(turn)
    return Rect((cx, cy, z0 + h / 2), (math.cos(t), math.sin(t), 0), (0, 0, 1), w / 2, h / 2, obj)


def _open_box(cx, cy, sx, sy, sz, obj, t=0.01):
    return [Rect((cx, cy - sy / 2, sz / 2), (1, 0, 0), (0, 0, 1), sx / 2, sz / 2, obj),
            Rect((cx, cy + sy / 2 - t, sz / 2), (1, 0, 0), (0, 0, 1), sx / 2 - t, sz / 2, obj),
            Rect((cx, cy, t), (1, 0, 0), (0, 1, 0), sx / 2 - t, sy / 2 - t, obj)]


def _scenes():
    rng = np.random.default_rng(22)
    out = [[*_open_box(-0.5, 2.0, 0.4, 0.3, 0.2, 1), *box(0.4, 1.9, 0.4, 0.2, 0.2, obj=2),
            *box(0.4, 2.2, 0.4, 0.2, 0.2, obj=3)],
           [_wall(0.0, 1.85, 0.2, 0.4, 1), _wall(0.0, 2.14, 0.35, 0.38, 2),
            _wall(0.6, 1.9, 0.2, 0.3, 3), _wall(0.6, 2.3, 0.21, 0.3, 4)],
           # open boxes 7, 7.5 and 5 cm deep side by side; one 0.59 m deep
           [*_open_box(-0.5, 2.0, 0.4, 0.07, 0.2, 1), *_open_box(0.3, 2.0, 0.4, 0.075, 0.2, 2),
            *_open_box(0.0, 2.6, 0.5, 0.05, 0.2, 3)],
           [*_open_box(0.0, 2.0, 0.6, 0.59, 0.25, 1)]]
    for _ in range(6):
        rects = []
        for k in range(int(rng.integers(4, 8))):
            cx, cy = rng.uniform(-1.0, 1.0), rng.uniform(1.6, 2.8)
            h, w = rng.uniform(0.1, 0.4), rng.uniform(0.2, 0.5)
            if rng.random() < 0.3:
                rects += _open_box(cx, cy, w, rng.uniform(0.1, 0.5), h, k + 1)
            else:
                turn = float(rng.choice([0.0, 0.0, rng.uniform(-12, 12), 90.0]))
                rects.append(_wall(cx, cy, h, w, k + 1, turn))
        out.append(rects)
    return out


@pytest.mark.parametrize("k", range(10))
def test_open_walls_as_before_on_rendered_scenes(k, monkeypatch):
    calls = []
    new = ow.open_wall_objects

    def both(planes, objects, params, curved_below=0.8, xyz=None):
        got = new(planes, objects, params, curved_below, xyz)
        want = _old_open_wall_objects(planes, objects, params, curved_below, xyz)
        calls.append((len(objects), len(got)))
        assert _key(got) == _key(want)
        assert (got is objects) == (want is objects)
        return got

    monkeypatch.setattr(ow, "open_wall_objects", both)
    cloud, lab, _up, _objs = render([floor(), *_scenes()[k]], pitch=25, cam_height=1.3,
                                    width=320, height=240, noise=0.001)
    describe_scene(cloud, lab)
    assert calls  # the rule ran


def test_the_scenes_join_open_walls():
    # sensitivity: the scenes hold pairs the rule joins (and pairs it refuses)
    joined = 0
    for rects in _scenes():
        cloud, lab, _up, _objs = render([floor(), *rects], pitch=25, cam_height=1.3,
                                        width=320, height=240, noise=0.001)
        seen = []
        orig = ow.open_wall_objects

        def spy(planes, objects, *a, _orig=orig, _seen=seen):
            got = _orig(planes, objects, *a)
            _seen.append(len(objects) - len(got))
            return got

        ow.open_wall_objects = spy
        try:
            describe_scene(cloud, lab)
        finally:
            ow.open_wall_objects = orig
        joined += sum(seen)
    assert joined >= 2


def test_mask_points_is_nonzero_isfinite_and_the_gather():
    # leg_objects' one pass over a proposal's mask: np.nonzero, the finite flags and the
    # finite points, bit for bit (NaN, infinities, signed zeros; empty rows, first and last
    # rows and columns; sparse and dense masks; a Fortran-ordered mask)
    from planerel.features._curved_kernels import mask_points

    rng = np.random.default_rng(5)
    for t in range(300):
        H, W = int(rng.integers(1, 40)), int(rng.integers(1, 50))
        mask = rng.random((H, W)) < float(rng.choice([0.0, 0.01, 0.2, 0.9]))
        if t % 7 == 0:
            mask[rng.integers(0, H), :] = False
            mask[-1, -1] = True
        xyz = rng.normal(size=(H, W, 3))
        xyz[rng.random((H, W, 3)) < 0.1] = np.nan
        xyz[rng.random((H, W, 3)) < 0.03] = np.inf
        xyz[rng.random((H, W, 3)) < 0.03] = -0.0
        if t % 11 == 0:
            mask = np.asfortranarray(mask)
        rows, cols, fin, pts = mask_points(mask, xyz)
        r0, c0 = np.nonzero(mask)
        assert np.array_equal(rows, r0) and np.array_equal(cols, c0)
        want = np.isfinite(xyz[r0, c0]).all(1)
        assert np.array_equal(fin, want)
        ref = xyz[r0, c0][want]
        assert pts.shape == ref.shape
        assert pts.tobytes() == ref.tobytes()
