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
    # a part from a quarter of near_min_area makes up the area; a speck under it does not
    assert len(_clusters([a, (20, 30, 5, 5, 1.05)])) == 1  # 0.0015 m^2
    assert _clusters([a, (20, 30, 3, 3, 1.05)]) == []  # 0.0005 m^2


def test_a_part_joins_one_kept_cluster_and_kept_clusters_never_join():
    big, part = (20, 10, 12, 12, 1.0), (22, 25, 7, 7, 1.03)
    (m,) = _clusters([big, part])
    assert m[22:29, 25:32].all() and m.sum() == 144 + 49
    (m0,) = _clusters([big, part], nest_depth=0.0)
    assert m0.sum() == 144
    # a part under half of near_min_area does not join a kept cluster (a piece of a neighbour)
    (m1,) = _clusters([big, (22, 25, 5, 5, 1.03)])
    assert m1.sum() == 144
    # a part between two kept clusters joins neither; the two stay apart
    other = (20, 35, 12, 12, 1.0)
    ms = _clusters([big, part, other])
    assert [int(m.sum()) for m in ms] == [144, 144]
    # two kept clusters 3 px apart and 2 cm in depth: not joined by this rule
    ms = _clusters([big, (20, 25, 12, 12, 1.02)])
    assert [int(m.sum()) for m in ms] == [144, 144]


def test_a_part_near_a_small_one_plane_proposal_counts_its_area():
    from collections import namedtuple

    from planerel.features.curved import _clusters

    P = namedtuple("P", "label area")
    # a part of 0.0028 m^2 (under near_min_area) 3 px and 5 cm from a plane of 0.0016 m^2
    # (label 0: a proposal of its own, e.g. a mug's front seen flat)
    cloud, lab = _scene([(20, 20, 7, 7, 1.0), (20, 30, 7, 4, 1.05)])
    lab[20:27, 30:34] = 0
    planes = [P(0, 0.0016)]
    masks, kept_with = _clusters(cloud, lab, planes, params=CurvedParams(), credit={0: 0.0016})
    assert len(masks) == 1 and kept_with == [0] and masks[0][20:27, 20:27].all()
    assert not masks[0][:, 30:].any()  # the plane's pixels stay the plane's
    assert _clusters(cloud, lab, planes, params=CurvedParams())[0] == []  # no credit given
    assert _clusters(cloud, lab, planes, params=CurvedParams(nest_depth=0.0),
                     credit={0: 0.0016})[0] == []
    # a plane too small to make up the area: nothing
    assert _clusters(cloud, lab, planes, params=CurvedParams(), credit={0: 0.0005})[0] == []


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
        nl = int(rng.integers(0, 4))
        lab = rng.integers(-1, nl, (H, W)) if nl else np.full((H, W), -1)
        credit = rng.random(nl) < 0.7
        got = nest_links(rows, cols, ids, near, part, xyz, H, W, g, depth, lab, credit)
        parent = list(range(k + nl))

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
        for s_ in range(n):  # a part's pixel to a credited plane's pixel within g, any side
            a = ids[s_]
            if not (near[a] and part[a]):
                continue
            p = xyz[rows[s_], cols[s_]]
            for r2 in range(max(0, rows[s_] - g), min(H, rows[s_] + g + 1)):
                for c2 in range(max(0, cols[s_] - g), min(W, cols[s_] + g + 1)):
                    x = lab[r2, c2]
                    if x < 0 or not credit[x]:
                        continue
                    if np.linalg.norm(xyz[r2, c2] - p) <= depth * max(1.0, abs(p[2])):
                        u, v = root(a), root(k + x)
                        parent[max(u, v)] = min(u, v)
        want = [root(i) for i in range(k + nl)]
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


def _tabletop(i, seed=11):
    from planerel.segment import segment

    xyz, truth, side = tt.make_scene(i, seed, sensor="mosd")
    k = side["intrinsics"]
    cloud = Cloud(xyz, Intrinsics(k["width"], k["height"], k["fx"], k["fy"], k["cx"], k["cy"]), None,
                  side["scene_id"])
    return cloud, segment(cloud).labels, truth, {o["index"]: o["kind"] for o in side["objects"]}


def _score(cloud, labels, truth, cp):
    from planerel.features.facts import describe_scene
    from planerel.features.object_eval import proposal_image, score_objects

    d = describe_scene(cloud, labels, curved_params=cp)
    img = proposal_image(d.labels, [o.planes for o in d.objects], [o.mask for o in d.objects])
    return score_objects(img, truth)


def test_a_mug_with_a_flat_looking_front_is_found():
    # scene t0013 of the same set: object 2 is a mug whose front the segmentation made a plane
    # of 0.0028 m^2 (a proposal alone) and whose inside and sides are three parts of 0.001-0.002
    # m^2 each: with the plane's area they are kept and join its proposal
    cloud, labels, truth, kinds = _tabletop(13)
    assert kinds[2] == "mug"
    new = _score(cloud, labels, truth, CurvedParams())
    old = _score(cloud, labels, truth, CurvedParams(nest_credit=0.0))
    assert new.best_iou[2] >= 0.8 > 0.5 > old.best_iou[2]
    assert all(new.best_iou[k] >= v - 1e-9 for k, v in old.best_iou.items())
    assert new.false <= old.false


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


def _nest_links_every_near_pixel(rows, cols, ids, near, part, xyz, H, W, g, nest_depth, lab,
                                 credit):
    """nest_links as first written (every near pixel's forward window looked at): the
    reference of the kernel that looks at the parts' windows alone."""
    def root(parent, i):
        while parent[i] != i:
            i = parent[i]
        return i

    k, nl, n = near.shape[0], credit.shape[0], rows.shape[0]
    parent = np.arange(k + nl)
    sel = [t for t in range(n) if near[ids[t]]]
    if not sel:
        return parent
    r0, r1 = min(rows[t] for t in sel), max(rows[t] for t in sel)
    c0, c1 = min(cols[t] for t in sel), max(cols[t] for t in sel)
    img = np.full((r1 - r0 + 1, c1 - c0 + 1), -1, np.int64)
    for t in sel:
        img[rows[t] - r0, cols[t] - c0] = ids[t]
    for t in sel:
        a = ids[t]
        r, c = rows[t], cols[t]
        lim = nest_depth * max(1.0, abs(xyz[r, c, 2]))
        lim2 = lim * lim
        for dr in range(0, g + 1):
            r2 = r + dr
            if r2 > r1:
                break
            for dc in range(-g, g + 1):
                if dr == 0 and dc <= 0:
                    continue
                c2 = c + dc
                if c2 < c0 or c2 > c1:
                    continue
                b = img[r2 - r0, c2 - c0]
                if b < 0 or b == a or not (part[a] or part[b]):
                    continue
                d = xyz[r2, c2] - xyz[r, c]
                if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= lim2:
                    x, y = root(parent, a), root(parent, b)
                    if x != y:
                        parent[max(x, y)] = min(x, y)
        if nl == 0 or not part[a]:
            continue
        for r2 in range(max(0, r - g), min(H, r + g + 1)):
            for c2 in range(max(0, c - g), min(W, c + g + 1)):
                x = lab[r2, c2]
                if x < 0 or x >= nl or not credit[x]:
                    continue
                d = xyz[r2, c2] - xyz[r, c]
                if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= lim2:
                    u, v = root(parent, a), root(parent, k + x)
                    if u != v:
                        parent[max(u, v)] = min(u, v)
    return np.array([root(parent, i) for i in range(k + nl)])


def test_nest_links_parts_windows_as_every_near_pixel():
    from planerel.features._curved_kernels import nest_links

    rng = np.random.default_rng(12)
    for case in range(150):
        H, W, k = int(rng.integers(3, 30)), int(rng.integers(3, 30)), int(rng.integers(1, 9))
        n = int(rng.integers(1, min(H * W, 200) + 1))
        flat = np.sort(rng.choice(H * W, n, replace=False))
        rows, cols = flat // W, flat % W
        ids = rng.integers(0, k, n)
        # depths in steps, some limits met exactly often enough to matter
        xyz = np.round(rng.normal(0, 0.05, (H, W, 3)), 2) + [0, 0, float(rng.choice([0.5, 1.0, 2.0]))]
        near, part = rng.random(k) < 0.8, rng.random(k) < 0.5
        if case % 3 == 0:
            part &= ~near  # parts that are not near: never linked
        g, depth = int(rng.integers(0, 6)), float(rng.choice([0.02, 0.05, 0.1, 0.3]))
        nl = int(rng.integers(0, 4))
        lab = rng.integers(-1, nl, (H, W)) if nl else np.full((1, 1), -1)
        credit = rng.random(nl) < 0.7
        got = nest_links(rows, cols, ids, near, part, xyz, H, W, g, depth, lab, credit)
        want = _nest_links_every_near_pixel(rows, cols, ids, near, part, xyz, H, W, g, depth,
                                            lab, credit)
        assert got.tolist() == want.tolist(), case
