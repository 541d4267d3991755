"""Issue 22, eighth pass: a group cut where it is weakest between two planes at a clear
concave edge (docs/objects.md "Eighth pass"; planerel.features.concave_cut)."""

from __future__ import annotations

import itertools
from types import SimpleNamespace as NS

import numpy as np
import pytest

from planerel.features.concave_cut import _min_cut, concave_cos, concave_cuts


def _plane(label, normal, centroid, n_points=500):
    return NS(label=label, normal=np.array(normal, float), centroid=np.array(centroid, float),
              n_points=n_points)


def _boxes():
    """Camera at the origin looking along +z, y down.  Box A: top 1, front 2.  A taller box B
    beside it: left side 3 (facing -x), front 4, top 5.  A's top meets B's left side along a
    concave edge of 200 pixel pairs; it touches B's front only at the corner (10 pairs)."""
    planes = [_plane(1, (0, -1, 0), (0.2, 0.5, 2.0)), _plane(2, (0, 0, -1), (0.2, 0.6, 1.8)),
              _plane(3, (-1, 0, 0), (0.4, 0.4, 2.0)), _plane(4, (0, 0, -1), (0.6, 0.3, 1.8)),
              _plane(5, (0, -1, 0), (0.6, 0.2, 2.0))]
    edges = {(1, 2): ((0.2, 0.5, 1.8), (0.2, 0.52, 1.8), 300),
             (1, 3): ((0.38, 0.5, 2.0), (0.4, 0.48, 2.0), 200),  # A's top left of B's side, below
             (1, 4): ((0.4, 0.5, 1.81), (0.41, 0.49, 1.8), 10),
             (3, 4): ((0.4, 0.4, 1.81), (0.41, 0.4, 1.8), 250),
             (3, 5): ((0.4, 0.21, 2.0), (0.41, 0.2, 2.0), 250),
             (4, 5): ((0.6, 0.21, 1.8), (0.6, 0.2, 1.81), 250)}
    joined = {(1, 2), (1, 4), (3, 4), (3, 5), (4, 5)}
    return planes, edges, joined


def test_the_weak_corner_between_two_boxes_is_cut():
    planes, edges, joined = _boxes()
    assert concave_cos(planes[0], planes[2], edges[(1, 3)]) < -0.99
    assert concave_cuts(planes, joined, [(1, 3)], edges) == {(1, 4)}
    # two weak joins between them, 10 + 15 pixel pairs, together under a quarter of 200: both cut
    edges[(2, 4)] = ((0.4, 0.6, 1.8), (0.41, 0.6, 1.8), 15)
    assert concave_cuts(planes, joined | {(2, 4)}, [(1, 3)], edges) == {(1, 4), (2, 4)}


def test_no_cut_when_the_join_is_strong_or_the_edge_no_evidence():
    planes, edges, joined = _boxes()
    # the corner shares 60 pixel pairs (over a quarter of the concave edge's 200): faces of one
    # object are joined along whole edges, so nothing is cut
    strong = dict(edges)
    strong[(1, 4)] = (edges[(1, 4)][0], edges[(1, 4)][1], 60)
    assert concave_cuts(planes, joined, [(1, 3)], strong) == set()
    assert concave_cuts(planes, joined, [(1, 3)], edges, ratio=0.04) == set()
    # the concave edge in the convexity test's noise band (its points' offset along the edge)
    flat = dict(edges)
    flat[(1, 3)] = ((0.4, 0.5, 1.9), (0.4, 0.5, 2.1), 200)
    assert abs(concave_cos(planes[0], planes[2], flat[(1, 3)])) < 0.1
    assert concave_cuts(planes, joined, [(1, 3)], flat) == set()
    # under 5 edge pixel pairs: no shared edge
    few = dict(edges)
    few[(1, 3)] = (edges[(1, 3)][0], edges[(1, 3)][1], 4)
    assert concave_cuts(planes, joined, [(1, 3)], few) == set()
    # a plane of under min_points = 100 points: its edge's sign is noise
    small = [_plane(1, (0, -1, 0), (0.2, 0.5, 2.0), n_points=60)] + planes[1:]
    assert concave_cuts(small, joined, [(1, 3)], edges) == set()
    assert concave_cuts(small, joined, [(1, 3)], edges, min_points=50) == {(1, 4)}
    # the two planes not joined at all: nothing to cut
    assert concave_cuts(planes, joined - {(1, 4)}, [(1, 3)], edges) == set()
    # planes under 50 degrees apart (facets of a hollow cylinder, or a step between two tops)
    # are no two objects here
    par = [_plane(1, (0, -1, 0), (0.2, 0.5, 2.0)), _plane(3, (0.05, -1, 0), (0.4, 0.3, 2.0))]
    par_edges = {(1, 3): ((0.38, 0.5, 2.0), (0.4, 0.3, 2.0), 200)}
    assert concave_cuts(par, {(1, 3)}, [(1, 3)], par_edges) == set()


def test_a_side_wall_meeting_three_planes_of_the_group_is_not_cut_off():
    # B's side 3 also meets planes 6 and 7 of the group at concave edges (a flight's side wall
    # meets each tread and riser): no cut with wall_members = 3, the cut with 0
    planes, edges, joined = _boxes()
    planes += [_plane(6, (0, -1, 0), (0.2, 0.3, 2.2)), _plane(7, (0, 0, -1), (0.2, 0.4, 2.1))]
    edges[(1, 6)] = ((0.2, 0.5, 2.1), (0.2, 0.4, 2.1), 100)
    edges[(6, 7)] = ((0.2, 0.3, 2.1), (0.2, 0.31, 2.1), 100)
    edges[(3, 6)] = ((0.38, 0.3, 2.2), (0.4, 0.28, 2.2), 50)
    edges[(3, 7)] = ((0.38, 0.4, 2.1), (0.4, 0.4, 2.12), 50)
    joined |= {(1, 6), (6, 7)}
    concave = [(1, 3), (3, 6), (3, 7)]
    assert concave_cuts(planes, joined, concave, edges) == set()
    assert concave_cuts(planes, joined, concave, edges, wall_members=0) == {(1, 4)}


def test_min_cut_against_all_partitions():
    rng = np.random.default_rng(3)
    for _ in range(40):
        n = int(rng.integers(3, 7))
        nodes = list(range(n))
        weight = {}
        for a, b in itertools.combinations(nodes, 2):
            if rng.random() < 0.6:
                weight[(a, b)] = float(rng.integers(1, 20))
        value, cut = _min_cut(nodes, weight, 0, n - 1)
        sides = {}
        for k in range(n - 1):
            for side in itertools.combinations(nodes[1:-1], k):
                s = frozenset({0, *side})
                sides[s] = sum(w for (a, b), w in weight.items() if (a in s) != (b in s))
        best = min(sides.values())
        assert value == pytest.approx(best)
        assert sum(weight[p] for p in cut) == pytest.approx(best)
        # the cut is the one of the smallest side of 0 (every minimum side holds it): one
        # answer whichever maximum flow is found
        smallest = frozenset.intersection(*[s for s, v in sides.items() if v == pytest.approx(best)])
        assert cut == {p for p in weight if (p[0] in smallest) != (p[1] in smallest)}
        # the cut separates them
        g = {k: set() for k in nodes}
        for a, b in weight:
            if (a, b) not in cut:
                g[a].add(b)
                g[b].add(a)
        seen, todo = {0}, [0]
        while todo:
            for v in g[todo.pop()]:
                if v not in seen:
                    seen.add(v)
                    todo.append(v)
        assert n - 1 not in seen


def test_concave_cut_refuses_bad_values():
    from planerel.errors import InputError
    from planerel.features.relations import ProposalParams

    with pytest.raises(InputError):
        ProposalParams(concave_cut=-0.1)
    assert ProposalParams().concave_cut == 0.25


def test_facets_of_a_curved_surface_are_not_cut():
    # the inside of a hollow cylinder: facets 22.5 degrees apart meet at concave edges, and
    # join each other round the rim; no cut with min_angle 50, the cut with 20
    c, s = np.cos(np.radians(22.5)), np.sin(np.radians(22.5))
    planes = [_plane(1, (0, 0, -1), (0.0, 0.5, 2.0)), _plane(2, (-s, 0, -c), (0.1, 0.5, 2.02)),
              _plane(3, (0, -1, 0), (0.05, 0.3, 2.0))]
    # facet 2 lies beside facet 1 and in front of its plane's extension: concave between them
    edges = {(1, 2): ((0.04, 0.5, 2.0), (0.06, 0.5, 1.99), 100),
             (1, 3): ((0.0, 0.32, 2.0), (0.0, 0.3, 2.0), 200),
             (2, 3): ((0.1, 0.32, 2.02), (0.1, 0.3, 2.02), 5)}
    assert concave_cos(planes[0], planes[1], edges[(1, 2)]) < -0.5
    joined = {(1, 3), (2, 3)}
    assert concave_cuts(planes, joined, [(1, 2)], edges) == set()
    assert concave_cuts(planes, joined, [(1, 2)], edges, min_angle=20) == {(2, 3)}


def test_component_is_networkx_connected_component():
    import networkx as nx

    from planerel.features.concave_cut import _component

    rng = np.random.default_rng(5)
    for _ in range(200):
        n = int(rng.integers(1, 12))
        pairs = [tuple(int(v) for v in rng.integers(0, n, 2)) for _ in range(int(rng.integers(0, 15)))]
        a = int(rng.integers(0, n))
        g = nx.Graph(pairs)
        want = nx.node_connected_component(g, a) if a in g else {a}
        assert _component(pairs, a) == want
