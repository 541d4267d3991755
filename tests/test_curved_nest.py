"""Parts of one round object apart across a depth jump (CurvedParams.nest_depth / nest_px):
the outside of a mug and its inside seen over the rim, each under ``near_min_area``."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.features.curved import CurvedParams, pixel_areas, unexplained_clusters
from planerel.io.cloud import Cloud, Intrinsics

FX = 131.25  # a 160 x 120 Kinect-like camera: a pixel covers 5.8 cm^2 at 1 m


def _cloud(z):
    """An organized cloud from a depth image (NaN = no depth)."""
    H, W = z.shape
    r, c = np.mgrid[0:H, 0:W]
    xyz = np.stack([(c - (W - 1) / 2) * z / FX, (r - (H - 1) / 2) * z / FX, z], -1)
    return Cloud(xyz.astype(np.float32), Intrinsics(W, H, FX, FX, (W - 1) / 2, (H - 1) / 2), None, "t")


def _scene(patches, shape=(60, 80)):
    """Patches ``(row0, col0, rows, cols, depth)`` of points no plane explains, the rest no
    depth: returns the cloud and the labels (all -1)."""
    z = np.full(shape, np.nan)
    for r0, c0, h, w, d in patches:
        z[r0:r0 + h, c0:c0 + w] = d
    return _cloud(z), np.full(shape, -1, np.int32)


def _clusters(patches, **kw):
    cloud, lab = _scene(patches)
    return unexplained_clusters(cloud, lab, [], params=CurvedParams(**kw))


def test_two_parts_across_a_narrow_band_are_one_cluster():
    # 7 x 7 px at 1 m: 0.0028 m^2 each (under near_min_area 0.004), 0.0057 together; 3 px of
    # no depth between them and a 5 cm depth jump (the rim hiding the inside's foot)
    a, b = (20, 20, 7, 7, 1.0), (20, 30, 7, 7, 1.05)
    cloud, lab = _scene([a, b])
    areas = pixel_areas(cloud.xyz)
    assert 0.002 < np.nansum(areas[20:27, 20:27]) < 0.004
    (m,) = _clusters([a, b])
    assert m[20:27, 20:27].all() and m[20:27, 30:37].all() and m.sum() == 98
    assert _clusters([a, b], nest_depth=0.0) == []  # off: each part alone is too small
    assert _clusters([a, (20, 30, 7, 7, 1.15)]) == []  # 15 cm behind: another surface
    assert _clusters([a, (20, 32, 7, 7, 1.05)]) == []  # 5 px of no depth: 6 px apart, over nest_px 4
    assert len(_clusters([a, (20, 32, 7, 7, 1.05)], nest_px=6)) == 1
    # a speck (under half of near_min_area) does not make up the area
    assert _clusters([a, (20, 30, 5, 5, 1.05)]) == []


def test_a_part_joins_one_kept_cluster_and_kept_clusters_never_join():
    big, part = (20, 10, 12, 12, 1.0), (22, 25, 7, 7, 1.03)
    (m,) = _clusters([big, part])
    assert m[22:29, 25:32].all() and m.sum() == 144 + 49
    (m0,) = _clusters([big, part], nest_depth=0.0)
    assert m0.sum() == 144
    # a part between two kept clusters joins neither; the two stay apart
    other = (20, 35, 12, 12, 1.0)
    ms = _clusters([big, part, other])
    assert [int(m.sum()) for m in ms] == [144, 144]
    # two kept clusters 3 px apart and 2 cm in depth: not joined by this rule
    ms = _clusters([big, (20, 25, 12, 12, 1.02)])
    assert [int(m.sum()) for m in ms] == [144, 144]


def test_far_parts_are_not_joined():
    # beyond near_depth (1.5 m) the limit is min_area (0.01) and no part is joined: 5 x 5 px
    # at 2 m are 0.0058 m^2 each, 0.0117 together
    a, b = (20, 20, 5, 5, 2.0), (20, 28, 5, 5, 2.05)
    assert _clusters([a, b]) == []
    assert len(_clusters([a, b], near_depth=2.5, near_min_area=0.01)) == 1


def test_nest_links_against_a_plain_reference():
    from planerel.features._curved_kernels import nest_links

    rng = np.random.default_rng(4)
    for _ in range(30):
        H, W, k = 20, 24, int(rng.integers(2, 7))
        n = int(rng.integers(5, 120))
        flat = np.sort(rng.choice(H * W, n, replace=False))
        rows, cols = flat // W, flat % W
        ids = rng.integers(0, k, n)
        ids[:k] = np.arange(k) if n >= k else ids[:k]
        xyz = rng.normal(0, 0.05, (H, W, 3)) + [0, 0, 1.0]
        near, part = rng.random(k) < 0.8, rng.random(k) < 0.6
        g, depth = int(rng.integers(1, 5)), float(rng.uniform(0.02, 0.2))
        got = nest_links(rows, cols, ids, near, part, xyz, H, W, g, depth)
        parent = list(range(k))

        def root(i, parent=parent):
            while parent[i] != i:
                i = parent[i]
            return i

        for s in range(n):
            for t in range(n):
                a, b = ids[s], ids[t]
                if a == b or not (near[a] and near[b]) or not (part[a] or part[b]):
                    continue
                dr, dc = rows[t] - rows[s], cols[t] - cols[s]
                if not (0 <= dr <= g and abs(dc) <= g) or (dr == 0 and dc <= 0):
                    continue
                p, q = xyz[rows[s], cols[s]], xyz[rows[t], cols[t]]
                if np.linalg.norm(q - p) <= depth * max(1.0, abs(p[2])):
                    x, y = root(a), root(b)
                    parent[max(x, y)] = min(x, y)
        want = [root(i) for i in range(k)]
        assert got.tolist() == want


def test_bad_values_are_refused():
    with pytest.raises(InputError, match="nest_depth"):
        CurvedParams(nest_depth=-0.1)
    with pytest.raises(InputError, match="nest_px"):
        CurvedParams(nest_px=0)


_SPEC = importlib.util.spec_from_file_location(
    "tabletop_scenes", Path(__file__).resolve().parents[1] / "benchmarks" / "tabletop_scenes.py")
tt = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(tt)


def test_a_mug_seen_over_its_rim_is_found():
    # scene t0000 of the table-top judge set's seed 11 with the sensor fitted to the real mOSD
    # frames (benchmarks/tabletop_scenes.py --sensor mosd): object 3 is a mug at 0.96 m whose
    # inside and outside lie apart across the band of no depth at the rim (0.0064 m^2 in view)
    from planerel.features.facts import describe_scene
    from planerel.features.object_eval import proposal_image, score_objects
    from planerel.segment import segment

    xyz, truth, side = tt.make_scene(0, 11, sensor="mosd")
    assert {o["index"]: o["kind"] for o in side["objects"]}[3] == "mug"
    i = side["intrinsics"]
    cloud = Cloud(xyz, Intrinsics(i["width"], i["height"], i["fx"], i["fy"], i["cx"], i["cy"]), None, "t0000")
    labels = segment(cloud).labels

    def score(cp):
        d = describe_scene(cloud, labels, curved_params=cp)
        img = proposal_image(d.labels, [o.planes for o in d.objects], [o.mask for o in d.objects])
        return score_objects(img, truth)

    new, old = score(CurvedParams()), score(CurvedParams(nest_depth=0.0))
    assert new.best_iou[3] >= 0.9 and old.best_iou.get(3, 0.0) < 0.5
    # no other object loses (a bowl's inside and outside join too: object 6, 0.80 -> 0.96),
    # and no false proposal is added
    assert all(new.best_iou[k] >= v for k, v in old.best_iou.items())
    assert new.best_iou[6] > 0.9 > old.best_iou[6]
    assert new.false <= old.false
