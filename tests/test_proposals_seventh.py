"""Issue 22, seventh pass: rules for the objects missed in the cluttered synthetic scenes
(docs/objects.md "Seventh pass")."""

from __future__ import annotations

import numpy as np

from planerel.features.curved import CurvedParams, curved_objects, unexplained_clusters
from planerel.io.cloud import Cloud


def _flat_cloud(f=500.0, z=1.0, size=(200, 200)):
    """A fronto-parallel plane at depth z: every pixel covers (z / f)^2 m^2 (4e-6 at 1 m)."""
    h, w = size
    v, u = np.mgrid[0:h, 0:w].astype(float)
    cx, cy = (w - 1) / 2, (h - 1) / 2
    return Cloud(np.stack([(u - cx) * z / f, (v - cy) * z / f, np.full((h, w), z)], axis=2))


def _two_faces_and_a_strip():
    """Two 30 x 30 unexplained patches (a box's top and front) with a two-pixel column of
    support between them, joined only by a strip two pixels high below both (the pixels that
    connect the faces of a far box lie at its outline, and the opening removes them), a
    two-pixel tail hanging from the strip, two 20 x 20 pieces joined the same way and a lone
    3 x 3 speck; label 0 is support."""
    labels = np.zeros((200, 200), np.int64)
    labels[20:50, 20:50] = -1
    labels[20:50, 52:82] = -1  # columns 50-51 stay support
    labels[50:52, 20:82] = -1  # the strip below both
    labels[52:70, 30:32] = -1  # the tail
    labels[110:130, 20:40] = -1  # two pieces of 0.0016 m^2 (400 px) and their strip
    labels[110:130, 42:62] = -1
    labels[130:132, 20:62] = -1
    labels[160:163, 160:163] = -1  # a speck
    return labels


def test_clusters_cut_apart_by_the_opening_are_one_grown_back():
    labels = _two_faces_and_a_strip()
    cloud = _flat_cloud()
    cp = CurvedParams(min_area=0.002)
    masks = unexplained_clusters(cloud, labels, [], support=(0,), params=cp)
    assert len(masks) == 1
    m = masks[0]
    # both faces, the strip and the tail: every pixel of the component before the opening
    assert m.sum() == 900 + 900 + 2 * 62 + 2 * 18
    assert np.array_equal(m[:100], labels[:100] == -1)
    # the two pieces: each under min_area when opened (together they would not be): none;
    # nor the speck
    assert not m[100:].any()
    # before the seventh pass: the opened faces, two clusters, neither reaching the other
    old = unexplained_clusters(cloud, labels, [], support=(0,),
                               params=CurvedParams(min_area=0.002, reconnect=False))
    assert len(old) == 2
    assert not any(x[:, 50:52].any() or x[55:].any() for x in old)


def test_grown_back_clusters_keep_the_depth_rule_and_the_area_of_the_opened_pixels():
    labels = _two_faces_and_a_strip()
    xyz = _flat_cloud().xyz.copy()
    xyz[:100, 51:, 2] += 0.3  # the second face and its part of the strip 30 cm farther away
    masks = unexplained_clusters(Cloud(xyz), labels, [], support=(0,),
                                 params=CurvedParams(min_area=0.002))
    assert sorted(int(m.sum()) for m in masks) == [900 + 2 * 31, 900 + 2 * 31 + 2 * 18]
    # the near face opened weighs 0.0036-0.0039 m^2, the far one (1.3 m) 1.69 times as much:
    # with min_area 0.005 the near one is no cluster, its tail and strip do not make it one
    far = unexplained_clusters(Cloud(xyz), labels, [], support=(0,),
                               params=CurvedParams(min_area=0.005))
    assert len(far) == 1 and far[0][:, 52:82].any() and not far[0][:, :50].any()


def test_a_box_cut_in_two_by_the_opening_is_one_proposal():
    labels = _two_faces_and_a_strip()
    cloud = _flat_cloud()
    objs = curved_objects([], [], [], cloud, labels, support=(0,), params=CurvedParams(min_area=0.002))
    assert len(objs) == 1 and objs[0].n_points == 1960 and objs[0].planar_fraction == 0.0
    old = curved_objects([], [], [], cloud, labels, support=(0,),
                         params=CurvedParams(min_area=0.002, reconnect=False))
    assert len(old) == 2
