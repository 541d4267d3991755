"""Pairwise relations, the scene graph and object proposals."""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import box, floor, render, stairs, wall

from planerel.errors import InputError
from planerel.features.planes import measure_planes
from planerel.features.relations import (
    ProposalParams,
    RelationParams,
    hull_gap,
    objects_from_truth,
    proposal_match,
    propose_objects,
    relate,
    scene_graph,
)


@pytest.fixture(scope="module")
def stair_scene():
    rects = [floor(), wall()] + stairs(0.3, 2.2, 3, rise=0.17, run=0.28) + \
        box(-1.0, 2.5, 0.5, 0.5, 0.4, obj=2)
    cloud, lab, up, objs = render(rects, pitch=25, roll=5, noise=0.0012)
    ps = measure_planes(cloud, lab)
    return cloud, lab, objs, ps, relate(ps, cloud)


def test_stairs_treads_rise_and_relations(stair_scene):
    _, _, _, ps, rel = stair_scene
    treads = [3, 5, 7]  # stairs() alternates riser, tread
    risers = [2, 4, 6]
    for t in treads:
        assert ps.by_label(t).orientation == "horizontal"
    for a, b in zip(treads, treads[1:], strict=False):
        r = rel.get(a, b)
        assert r.rise == pytest.approx(0.17, abs=0.01)
        assert r.parallel and not r.perpendicular
        assert rel.get(b, a).above and not r.above
        assert rel.get(b, a).rise == pytest.approx(-r.rise)
        assert r.gap == pytest.approx(0.17, abs=0.01)  # riser height between the treads
        assert not r.adjacent
    for rs, t in zip(risers, treads, strict=True):
        r = rel.get(rs, t)
        assert r.adjacent and r.touching and r.perpendicular
        assert r.gap < 0.01
    assert rel.get(2, 4).in_front_of and not rel.get(4, 2).in_front_of


def test_relations_are_all_ordered_pairs(stair_scene):
    _, _, _, ps, rel = stair_scene
    n = len(ps)
    assert len(rel) == n * (n - 1)
    keys = [(r.a, r.b) for r in rel]
    assert keys == sorted(keys)
    for r in rel:
        back = rel.get(r.b, r.a)
        assert back.angle == r.angle and back.gap == r.gap and back.adjacent == r.adjacent


def test_occluding_edge_is_not_touching(stair_scene):
    _, _, _, ps, rel = stair_scene
    # the box top (label 8) is seen against the far wall (label 1) but 2+ m in front of it
    r = rel.get(1, 8)
    assert not r.touching and not r.adjacent and r.gap > 1.0


def test_proposals_match_truth(stair_scene):
    cloud, lab, objs, ps, rel = stair_scene
    props = propose_objects(ps, rel)
    truth = objects_from_truth(lab, lab, objs)
    assert props == truth == [(2, 3, 4, 5, 6, 7), (8, 9, 11)]
    obj_img = np.where(lab >= 0, np.array(objs)[np.maximum(lab, 0)], -1)
    m = proposal_match(lab, props, obj_img)
    assert m["n_true"] == 2 and m["matched"] == 2
    g = scene_graph(ps, rel)
    assert set(g.nodes) == {p.label for p in ps}
    assert g.has_edge(2, 3) and not g.has_edge(3, 5)
    assert g.nodes[3]["orientation"] == "horizontal"
    assert scene_graph(ps, rel, edges="all").number_of_edges() == len(ps) * (len(ps) - 1) // 2


def test_synthetic_proposals():
    from planerel.synth.generator import generate_scene

    matched = 0
    for kind, seed in (("box", 1), ("stairs", 1), ("ramp", 1)):
        sc = generate_scene(kind, seed, subsample=4)
        ps = measure_planes(sc.cloud, sc.gt_labels)
        props = propose_objects(ps, relate(ps, sc.cloud))
        truth = np.where(sc.gt_objects == 1, 1, -1)
        matched += proposal_match(sc.gt_labels, props, truth)["matched"]
    assert matched == 3


def test_hull_gap_simple_cases():
    cloud, lab, _, _ = render([floor()] + box(0.0, 2.5, 0.5, 0.5, 0.4), pitch=30)
    ps = measure_planes(cloud, lab)
    top, front = ps.by_label(1), ps.by_label(2)
    # one pixel footprint apart at 160x120 (the edge pixel is shared by neither plane)
    assert hull_gap(top, front) < RelationParams().adjacency_gap
    assert relate(ps, cloud).get(1, 2).adjacent
    assert hull_gap(ps.by_label(0), top) == pytest.approx(0.4, abs=0.01)


def test_zero_and_one_plane():
    cloud, lab, _, _ = render([floor()])
    ps = measure_planes(cloud, lab)
    assert len(ps) == 1 and len(relate(ps, cloud)) == 0
    assert propose_objects(ps, relate(ps, cloud)) == []
    empty = measure_planes(cloud, np.full(lab.shape, -1, np.int32))
    assert len(relate(empty, cloud)) == 0 and propose_objects(empty, relate(empty)) == []


def test_bad_params():
    with pytest.raises(InputError, match="grid_gap"):
        RelationParams(grid_gap=0)
    with pytest.raises(InputError, match="parallel_tol"):
        RelationParams(parallel_tol=60)
    with pytest.raises(InputError, match="support_min_area"):
        ProposalParams(support_min_area=-1)
    with pytest.raises(InputError, match="differ in shape"):
        objects_from_truth(np.zeros((2, 2), int), np.zeros((3, 3), int), [0])


def test_components_are_networkx_connected_components():
    """``Components`` (propose_objects' and facet_planes' union-find) gives networkx's
    components: nodes given first or met in edges, self-loops, repeated edges."""
    import networkx as nx

    from planerel.features.relations import Components

    rng = np.random.default_rng(5)
    for _ in range(200):
        n = int(rng.integers(0, 15))
        nodes = [int(x) for x in rng.permutation(20)[:n]]
        edges = [tuple(int(x) for x in rng.integers(0, 20, 2)) for _ in range(int(rng.integers(0, 25)))]
        g = nx.Graph()
        g.add_nodes_from(nodes)
        c = Components(nodes)
        half = len(edges) // 2
        g.add_edges_from(edges[:half])
        c.add_edges(edges[:half])
        assert set(c.nodes) == set(g.nodes)
        assert sorted(map(sorted, c.groups())) == sorted(map(sorted, nx.connected_components(g)))
        g.add_edges_from(edges[half:])
        c.add_edges(edges[half:])
        assert sorted(map(sorted, c.groups())) == sorted(map(sorted, nx.connected_components(g)))
        assert c.nodes == list(dict.fromkeys(nodes + [x for e in edges for x in e]))


def test_default_parameters_made_once_and_equal_to_new_ones():
    from planerel.features._defaults import defaults

    for cls in (RelationParams, ProposalParams):
        assert defaults(cls) is defaults(cls)
        assert defaults(cls) == cls()


def test_cross3_is_numpys_cross_bit_for_bit():
    from planerel.features.vectors import cross3

    rng = np.random.default_rng(11)
    for _ in range(2000):
        u = rng.normal(size=3) * rng.choice([1e-6, 1.0, 1e4])
        v = rng.normal(size=3)
        if rng.random() < 0.1:
            v = u * 3.0  # parallel: zeros up to rounding
        got, want = cross3(u, v), np.cross(u, v)
        assert got.dtype == want.dtype and np.array_equal(got.view(np.int64), want.view(np.int64))
    assert np.array_equal(cross3([0.0, 0.0, 1.0], [1, 0, 0]), np.cross([0.0, 0.0, 1.0], [1, 0, 0]))


def _cut_lengthwise_numpy(planes) -> set:
    """relations._cut_lengthwise before it read the border through the planes' boxes (main
    19ca73c): every border pixel counted by label."""
    lab = planes.labels
    if lab is None or lab.size == 0 or lab.max() < 0:
        return set()
    edge = np.concatenate([lab[0], lab[-1], lab[1:-1, 0], lab[1:-1, -1]])
    cnt = np.bincount(edge[edge >= 0], minlength=int(lab.max()) + 1)
    out = set()
    for p in planes:
        r0, c0, r1, c1 = p.bbox
        if p.label < cnt.size and cnt[p.label] >= 0.5 * max(r1 - r0, c1 - c0):
            out.add(p.label)
    return out


class _Planes(list):
    """Planes with a label image, as a PlaneSet holds them."""

    def __init__(self, planes, labels):
        super().__init__(planes)
        self.labels = labels


def test_cut_lengthwise_reads_the_border_through_the_boxes_as_numpy_counts_it():
    from types import SimpleNamespace

    from planerel.features.relations import _cut_lengthwise

    rng = np.random.default_rng(21)
    cut = 0
    for _ in range(300):
        H, W = (int(v) for v in rng.integers(1, 14, 2))
        lab = rng.integers(-1, 5, (H, W)).astype(np.int32)
        if rng.random() < 0.5:  # blocks, as planes are
            lab = np.repeat(np.repeat(rng.integers(-1, 4, (H // 3 + 1, W // 3 + 1)), 3, 0), 3, 1)[:H, :W]
            lab = np.ascontiguousarray(lab, dtype=np.int32)
        planes = []
        for k in np.unique(lab[lab >= 0]).tolist():
            r, c = np.nonzero(lab == k)
            planes.append(SimpleNamespace(label=k, bbox=(int(r.min()), int(c.min()),
                                                         int(r.max()) + 1, int(c.max()) + 1)))
        ps = _Planes(planes, lab)
        want = _cut_lengthwise_numpy(ps)
        assert _cut_lengthwise(ps, along_long_side=False) == want
        cut += len(want)
    assert cut > 100


def test_border_pixels_by_side_match_numpy():
    """``_border_pixels``' ``sides`` (the step chains' "cut along the long side") count what
    numpy counts on the image's rows / columns, whatever the label's pixel box."""
    from planerel.features.relations import _border_pixels

    rng = np.random.default_rng(5)
    for shape in [(7, 9), (1, 6), (6, 1), (12, 5)]:
        lab = rng.integers(0, 4, size=shape).astype(np.int32)
        for label in range(4):
            rr, cc = np.nonzero(lab == label)
            if not rr.size:
                continue
            bbox = (rr.min(), cc.min(), rr.max() + 1, cc.max() + 1)
            rows = int(np.count_nonzero(lab[0] == label) + np.count_nonzero(lab[-1] == label))
            cols = int(np.count_nonzero(lab[:, 0] == label) + np.count_nonzero(lab[:, -1] == label))
            every = int(np.count_nonzero(np.concatenate(
                [lab[0], lab[-1], lab[1:-1, 0], lab[1:-1, -1]]) == label))
            assert _border_pixels(lab, label, bbox, "rows") == rows
            assert _border_pixels(lab, label, bbox, "cols") == cols
            assert _border_pixels(lab, label, bbox) == every


def test_get_finds_each_relation_in_every_layout(stair_scene):
    """Relations.get takes a relation from its place among every ordered pair of the sorted
    labels (speed24) and checks it; other layouts (a subset, another order, labels out of
    order) go through the dictionary; a missing pair is a KeyError either way."""
    import random
    from dataclasses import replace as _replace

    from planerel.features.relations import Relations

    _, _, _, _, rel = stair_scene
    want = {(r.a, r.b): r for r in rel}
    rng = random.Random(5)
    shuffled = list(rel.pairs)
    rng.shuffle(shuffled)
    labels = sorted({r.a for r in rel})
    # relabelled so that the runs' first labels are not increasing
    swap = {labels[0]: labels[1], labels[1]: labels[0]}
    odd = [_replace(r, a=swap.get(r.a, r.a), b=swap.get(r.b, r.b)) for r in rel]
    # each run of n - 1 reversed: the runs' first labels still increase, the places do not
    m = len(labels) - 1
    runs = tuple(r for k in range(len(labels)) for r in reversed(rel.pairs[k * m:(k + 1) * m]))
    layouts = [rel, Relations(tuple(shuffled), rel.params), Relations(rel.pairs[:-3], rel.params),
               Relations(runs, rel.params), Relations(tuple(odd), rel.params),
               Relations((), rel.params)]
    for k, rs in enumerate(layouts):
        have = {(r.a, r.b): r for r in rs}
        for a in [*labels, 99]:
            for b in [*labels, 99]:
                if (a, b) in have:
                    assert rs.get(a, b) is have[(a, b)]
                    if k < 4:
                        assert rs.get(a, b) is want[(a, b)]
                else:
                    with pytest.raises(KeyError):
                        rs.get(a, b)
    assert rel._pos and layouts[3]._pos and not layouts[4]._pos


def test_adjacent_only_is_the_adjacent_relations_in_order():
    # speed31: the loops that look at adjacent planes only take the remembered list of their
    # relations; the same relations in the same order as filtering every pair
    from planerel.features.relations import Relation, Relations, adjacent_only

    rng = np.random.default_rng(31)
    pairs = tuple(Relation(a, b, 0.0, False, False, 0.0, False, bool(rng.random() < 0.3), 0.0,
                           False, False, False, False)
                  for a in range(6) for b in range(6) if a != b)
    rel = Relations(pairs, RelationParams())
    want = [r for r in pairs if r.adjacent]
    assert list(adjacent_only(rel)) == want and adjacent_only(rel) is adjacent_only(rel)
    assert list(adjacent_only(list(pairs))) == list(pairs)  # a plain sequence: itself
    assert rel.adjacent_pairs() == [(r.a, r.b) for r in pairs if r.adjacent and r.a < r.b]
