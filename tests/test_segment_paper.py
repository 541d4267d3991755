"""Region growing as the paper writes it (Farid & Sammut, "Region-Growing Planar Segmentation
for Robot Action Planning", AI 2014, Algorithm 1), against a plain-Python statement of the
pseudo-code, and planerel's variants of it (reversed angle phases, seed test) as named options.

The paper's text is not in this repository.  The acceptance test of each candidate point is
Algorithm 1, lines 16-21, as issue 21 quotes them:

    16-18: if the region is smaller than num_initial_points:
               accept the candidate when current_angle < theta
    19-21: else:
               accept the candidate when current_angle < theta * angle_mf   (angle_mf < 1)

``current_angle`` is the angle between the candidate's normal and the region's base normal.
The rest of the loop follows the paper's parameter list as docs/segmentation.md states it (the
line numbers of those steps are not quoted here): regions start from seeds in row-major order
with no test of their own; a point can join only with at least ``min_neighbour_num`` of its 8
grid neighbours within ``delta``; the region grows breadth-first over those delta edges; the
base normal is the normalised sum of the members' normals, refreshed after each of the first
``num_initial_points`` additions and then every ``base_update_step``; regions smaller than
``min_region_size`` are dropped (their points may join later regions but start none).

The reference below works with angles in degrees, as the paper states the test; the kernel
compares cosines.  Normals and their running sums are float32 as the kernel keeps them (the
paper does not say), so the two agree label for label.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np
import pytest

from planerel.segment import _kernels as K
from planerel.segment import segment
from planerel.segment._graph_kernels import grid_graph
from planerel.segment._scenes import staircase

#: Grid direction k -> (dv, du); the bits of the delta graph's mask (GRID_DV / GRID_DU).
_DIRS = [(0, 1), (1, -1), (1, 0), (1, 1), (0, -1), (-1, 1), (-1, 0), (-1, -1)]


def algorithm1(normals, delta_mask, *, theta, angle_mf, num_initial_points, base_update_step,
               min_neighbour_num, min_region_size):
    """Algorithm 1 on an image grid.

    Parameters
    ----------
    normals : ndarray, shape (H, W, 3), float32
        Unit normals, NaN where unknown.
    delta_mask : ndarray, shape (H, W), uint8
        Bit k set: the neighbour in direction k lies within delta.

    Returns
    -------
    labels : ndarray, shape (H, W)
        Region ids 0..n-1, -1 for points in no region.
    n : int
    """
    h, w, _ = normals.shape
    f32 = np.float32
    known = ~np.isnan(normals.sum(axis=2))

    def delta_neighbours(p):
        m = int(delta_mask[p])
        return [(p[0] + dv, p[1] + du) for k, (dv, du) in enumerate(_DIRS) if (m >> k) & 1]

    def may_join(p):  # a normal, and at least min_neighbour_num neighbours within delta
        return bool(known[p]) and len(delta_neighbours(p)) >= min_neighbour_num

    def angle_deg(n, base):
        c = float(n[0]) * base[0] + float(n[1]) * base[1] + float(n[2]) * base[2]
        return math.degrees(math.acos(max(-1.0, min(1.0, c))))

    labels = np.full((h, w), -1)
    dropped = np.zeros((h, w), dtype=bool)  # points of dropped regions start no region
    n = 0
    for v in range(h):
        for u in range(w):
            seed = (v, u)
            if labels[seed] != -1 or dropped[seed] or not may_join(seed):
                continue
            region = [seed]
            labels[seed] = n
            total = [f32(x) for x in normals[seed]]
            base = [float(x) for x in normals[seed]]
            queue = deque([seed])
            while queue:
                for cand in delta_neighbours(queue.popleft()):
                    if labels[cand] != -1 or not may_join(cand):
                        continue
                    current_angle = angle_deg(normals[cand], base)
                    if len(region) < num_initial_points:       # lines 16-18
                        accept = current_angle < theta
                    else:                                      # lines 19-21
                        accept = current_angle < theta * angle_mf
                    if not accept:
                        continue
                    labels[cand] = n
                    region.append(cand)
                    queue.append(cand)
                    total = [total[i] + normals[cand][i] for i in range(3)]
                    size = len(region)
                    if size <= num_initial_points or size % base_update_step == 0:
                        norm = math.sqrt(sum(float(t) * float(t) for t in total))
                        base = [float(t) / norm for t in total]
            if len(region) >= min_region_size:
                n += 1
            else:
                for p in region:
                    labels[p] = -1
                    dropped[p] = True
    return labels, n


def _scene(kind):
    if kind == "stairs":
        cloud = staircase(80, 60, steps=4, seed=3)[0]
    else:  # a curved, noisy surface with holes: the base normal drifts while a region grows
        rng = np.random.default_rng(0)
        v, u = np.mgrid[0:60, 0:80].astype(float)
        x, y = (u - 40) * 0.02, (v - 30) * 0.02
        z = 2.0 + 0.25 * np.sin(2.5 * x) + 0.15 * np.cos(3 * y) + rng.normal(0, 0.002, x.shape)
        xyz = np.stack([x, y, z], axis=-1)
        xyz[rng.random(x.shape) < 0.03] = np.nan
        from planerel.io.cloud import Cloud

        cloud = Cloud(xyz)
    return cloud


def _mask(cloud, by_depth):
    xyz = np.ascontiguousarray(cloud.xyz, dtype=np.float64)
    mask = np.empty(xyz.shape[:2], dtype=np.uint8)
    grid_graph(xyz, 6.0, -1.0, by_depth, 24, max(1, xyz.shape[0] // 120), mask)
    return mask


@pytest.mark.parametrize("kind", ["stairs", "wavy"])
@pytest.mark.parametrize("extra", [{}, {"theta": 20.0, "num_initial_points": 5},
                                   {"num_initial_points": 1, "base_update_step": 3},
                                   {"angle_mf": 0.8, "min_neighbour_num": 6}])
def test_paper_preset_is_algorithm1_label_for_label(kind, extra):
    cloud = _scene(kind)
    seg = segment(cloud, preset="paper", min_region_size=20, **extra)
    assert seg.info["angle_order"] == "paper" and seg.info["seed_test"] is False
    p = seg.params
    assert (p.refine, p.leftover_planes, p.delta_mode) == (False, False, "image")
    want, n = algorithm1(np.asarray(seg.normals, dtype=np.float32), _mask(cloud, False),
                         theta=p.theta, angle_mf=p.angle_mf,
                         num_initial_points=p.num_initial_points,
                         base_update_step=p.base_update_step,
                         min_neighbour_num=p.min_neighbour_num, min_region_size=20)
    assert seg.n_planes == n >= 3  # the preset also leaves the post-processing off
    np.testing.assert_array_equal(seg.labels, want)


def test_refine_and_split_off_give_algorithm1_with_the_depth_banded_delta():
    cloud = _scene("stairs")
    seg = segment(cloud, refine=False, split=False)
    assert (seg.info["angle_order"], seg.info["seed_test"]) == ("paper", False)
    p = seg.params
    want, n = algorithm1(np.asarray(seg.normals, dtype=np.float32), _mask(cloud, True),
                         theta=p.theta, angle_mf=p.angle_mf,
                         num_initial_points=p.num_initial_points,
                         base_update_step=p.base_update_step,
                         min_neighbour_num=p.min_neighbour_num,
                         min_region_size=seg.info["min_region_size"])
    assert seg.n_planes == n
    np.testing.assert_array_equal(seg.labels, want)
    # planerel's additions on: its own variants unless named
    assert (segment(cloud).info["angle_order"], segment(cloud).info["seed_test"]) == (
        "reversed", True)
    assert segment(cloud, refine=False).info["angle_order"] == "reversed"  # split still on
    named = segment(cloud, refine=False, split=False, angle_order="reversed", seed_test=True)
    assert (named.info["angle_order"], named.info["seed_test"]) == ("reversed", True)
    assert not np.array_equal(named.labels, seg.labels)


# --------------------------------------------------------------------------- by hand
# One image row of 20 pixels (grid neighbours left and right, all within delta), theta 15,
# angle_mf 0.5 (7.5 degrees), num_initial_points 4, base_update_step 8, min_neighbour_num 0,
# min_region_size 1, driven through the kernel with the thresholds region_grow passes.


def _row(tilted):
    """Normals (1, 20, 3): (0, 0, -1), or tilted 10 degrees about y where ``tilted``."""
    t = math.radians(10)
    nrm = np.zeros((1, 20, 3), np.float32)
    nrm[0, :] = [0.0, 0.0, -1.0]
    nrm[0, tilted] = [math.sin(t), 0.0, -math.cos(t)]
    mask = np.full((1, 20), 0b00010001, np.uint8)  # right (bit 0) and left (bit 4)
    mask[0, 0] = 0b00000001
    mask[0, 19] = 0b00010000
    return nrm, mask


def _kernel(nrm, mask, order, seed_test):
    c15, c75 = math.cos(math.radians(15)), math.cos(math.radians(7.5))
    c_init, c_main = (c15, c75) if order == "paper" else (c75, c15)
    n = nrm.shape[1]
    padded, labels = K.padded_labels(1, n)
    K.region_grow_grid_ws(nrm.reshape(-1, 3), np.empty(n, np.bool_), mask.reshape(-1), n, 0,
                          c_init, c_main, c75 if seed_test else -2.0, 4, 8, 1, padded,
                          np.empty(n, np.int32), np.empty(n, np.bool_))
    return np.where(labels < 0, -1, labels).reshape(1, n).tolist()


def test_by_hand_a_late_bend_is_kept_by_the_paper_and_joined_by_the_reversed_order():
    # pixels 0-9 flat, 10-19 tilted 10 degrees.  Paper: pixels 1-3 join (0 deg < 15), the
    # region reaches 4 points, then pixel 10 is 10 deg from the flat base normal > 7.5:
    # rejected; it starts region 1.  Reversed: after 4 points the threshold is 15, so pixel 10
    # joins, and every later one (the base normal only moves towards them).
    nrm, mask = _row(slice(10, 20))
    assert algorithm1(nrm, mask, theta=15, angle_mf=0.5, num_initial_points=4,
                      base_update_step=8, min_neighbour_num=0, min_region_size=1)[0].tolist() \
        == [[0] * 10 + [1] * 10]
    assert _kernel(nrm, mask, "paper", False) == [[0] * 10 + [1] * 10]
    assert _kernel(nrm, mask, "reversed", False) == [[0] * 20]


def test_by_hand_an_early_bend_is_joined_by_the_paper_and_split_by_the_reversed_order():
    # pixel 0 flat, 1-19 tilted.  Paper: pixel 1 is 10 deg < 15 from the one-point region:
    # joins, and so does everything after (base normal between the two).  Reversed: 10 > 7.5,
    # pixel 0 stays alone (min_region_size 1: a region), pixel 1 starts region 1.
    nrm, mask = _row(slice(1, 20))
    assert _kernel(nrm, mask, "paper", False) == [[0] * 20]
    assert _kernel(nrm, mask, "reversed", False) == [[0] + [1] * 19]


def test_by_hand_the_seed_test_leaves_a_crease_pixel_out():
    # pixel 0 flat, 1-19 tilted.  With the seed test (neighbours within 7.5 deg of the seed),
    # pixels 0 and 1 cannot seed (their neighbour differs by 10 deg); pixel 2 seeds, grows
    # over 1..19, and after 4 points (threshold 7.5, paper order) rejects pixel 0.
    nrm, mask = _row(slice(1, 20))
    assert _kernel(nrm, mask, "paper", True) == [[-1] + [0] * 19]
    assert _kernel(nrm, mask, "paper", False) == [[0] * 20]


def test_paper_variant_options_are_validated():
    from planerel.errors import InputError

    cloud = _scene("stairs")
    with pytest.raises(InputError, match="angle_order must be 'auto', 'paper' or 'reversed'"):
        segment(cloud, angle_order="backwards")
    with pytest.raises(InputError, match="seed_test must be true or false"):
        segment(cloud, seed_test=2)
    assert segment(cloud, preset="paper", split=True).info["angle_order"] == "paper"
    # unorganized clouds take the same variants
    u = cloud.__class__(cloud.xyz[cloud.valid][None], organized=False)
    paper = segment(u, preset="paper", min_region_size=30)
    assert (paper.info["angle_order"], paper.info["seed_test"]) == ("paper", False)
    assert paper.n_planes >= 3


def test_paper_rules_without_completion_skip_the_post_processing(tmp_path):
    """preset=paper by keyword, as a params object (what the CLI passes) and on the command
    line: Algorithm 1 alone, the same labels each way."""
    from planerel.cli import main
    from planerel.segment import make_params

    cloud = _scene("stairs")
    by_kw = segment(cloud, preset="paper")
    by_obj = segment(cloud, params=make_params("regiongrow", preset="paper"))
    assert "split_tested" not in by_kw.info and "split_tested" not in by_obj.info
    np.testing.assert_array_equal(by_obj.labels, by_kw.labels)
    with_split = segment(cloud, preset="paper", split=True)
    assert "split_tested" in with_split.info
    np.save(tmp_path / "s.npy", cloud.xyz)
    assert main(["segment", str(tmp_path / "s.npy"), "--param", "preset=paper", "-o",
                 str(tmp_path / "out"), "--formats", "npy"]) == 0
    np.testing.assert_array_equal(np.load(tmp_path / "out" / "s.labels.npy"), by_kw.labels)
