"""Gravity for a tote or bin seen from above: drafted walls facing each other vote for their
mirror axis (docs/gravity.md, "A bin seen from above").

The planes are made in code: a tote whose walls lean out by a draft angle, seen by a camera
0.8 m above its floor, looking 82 degrees down; clutter lying tilted on the floor.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.features.gravity import GravityParams, estimate_gravity, up_from_cloud
from planerel.synth.gravity_scenes import posed_scene


def _deg(a, b) -> float:
    return math.degrees(math.acos(max(-1.0, min(1.0, float(np.dot(a, b))))))


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


def _tote(tilt_deg=8.0, draft_b=8.0, draft_a=25.0, floor_area=0.037, clutter=True):
    """``(normals, areas, offsets, ranges, centroids, up)`` of a tote seen from above (its floor
    first).

    The camera looks ``90 - tilt_deg`` degrees down (no roll); up is ``(0, -sin t, -cos t)``.
    The tote's floor is 0.8 m below the camera; its walls across the image's columns lean out
    by ``draft_a``, those across its rows by ``draft_b``; the wall at the image's bottom is
    the largest plane in view (it faces the camera's -y: the level reading's floor).  Clutter
    lies tilted on the floor, each piece more than 5 degrees off level and at right angles to
    that wall (vertical under the level reading)."""
    t = math.radians(tilt_deg)
    up = np.array([0.0, -math.sin(t), -math.cos(t)])
    a = np.array([1.0, 0.0, 0.0])
    b = _unit(np.cross(up, a))  # horizontal, towards the image's top
    floor_c = -0.8 * up
    planes = [(up, floor_area, floor_c)]
    for s, e, d, area in ((b, 0.18, draft_b, 0.019), (-b, 0.18, draft_b, 0.056),
                          (a, 0.25, draft_a, 0.014), (-a, 0.25, draft_a, 0.0125)):
        d = math.radians(d)
        planes.append((math.cos(d) * -s + math.sin(d) * up, area, floor_c + e * s + 0.1 * up))
    if clutter:
        wall = planes[2][0]  # the bottom wall: the level reading's floor
        m = _unit(up - (up @ wall) * wall)
        for k, phi in enumerate((0.0, 16.0, 24.0, -20.0, -45.0)):
            p = math.radians(phi)
            c = floor_c + 0.05 * up + 0.04 * (k - 2) * a
            planes.append((_unit(math.cos(p) * m + math.sin(p) * a), 0.022, c))
    normals = np.array([p[0] for p in planes])
    cents = np.array([p[2] for p in planes])
    assert (np.einsum("ij,ij->i", normals, cents) < 0).all()  # facing the sensor
    offsets = -np.einsum("ij,ij->i", normals, cents)
    return (normals, np.array([p[1] for p in planes]), offsets, np.linalg.norm(cents, axis=1),
            cents, up)


def test_tote_from_above_mirror_axis_is_up():
    n, w, d, r, c, up = _tote()
    on = estimate_gravity(n, w, d, ranges=r, centroids=c)
    assert _deg(on.vector, up) <= 1.0
    # before (and without centroids): the bottom wall is the floor, the clutter its walls
    off = estimate_gravity(n, w, d, GravityParams(mirror_pairs=False), ranges=r, centroids=c)
    assert _deg(off.vector, up) >= 45.0
    assert _deg(off.vector, (0.0, -1.0, 0.0)) <= 2.0
    bare = estimate_gravity(n, w, d, ranges=r)
    np.testing.assert_array_equal(bare.vector, off.vector)


@pytest.mark.parametrize("draft", [6.0, 12.0, 20.0])
def test_tote_drafts(draft):
    n, w, d, r, c, up = _tote(draft_b=draft, draft_a=draft)
    assert _deg(estimate_gravity(n, w, d, ranges=r, centroids=c).vector, up) <= 1.0


def test_drafted_walls_without_a_floor_below_do_not_vote():
    # the tote's floor covered (or out of view): no plane is level w.r.t. the walls' mirror
    # axis below them, so nothing says the cavity opens upwards (a shelf's cubby seen from the
    # front has the same walls), and the estimate is the one before
    n, w, d, r, c, up = _tote()
    keep = np.arange(len(w)) != 0
    on = estimate_gravity(n[keep], w[keep], d[keep], ranges=r[keep], centroids=c[keep])
    off = estimate_gravity(n[keep], w[keep], d[keep], GravityParams(mirror_pairs=False),
                           ranges=r[keep])
    np.testing.assert_array_equal(on.vector, off.vector)
    assert on.confidence == off.confidence
    # a level plane above the walls' middles (nearer the camera) is no floor either
    c2 = c.copy()
    c2[0] = c[0] + 0.3 * up
    on = estimate_gravity(n, w, -np.einsum("ij,ij->i", n, c2), ranges=r, centroids=c2)
    off = estimate_gravity(n, w, -np.einsum("ij,ij->i", n, c2), GravityParams(mirror_pairs=False),
                           ranges=r)
    np.testing.assert_array_equal(on.vector, off.vector)


def test_a_ridge_seen_from_outside_does_not_vote():
    # two faces of a gable (a convex ridge) leaning 20 degrees from vertical, 1 m below a level
    # camera: their normals are 140 degrees apart, as a drafted pair's, but each points away
    # from the other plane; plus the floor and a far wall
    up = np.array([0.0, -1.0, 0.0])
    tilt = math.radians(20.0)
    left = _unit(np.array([-math.cos(tilt), -math.sin(tilt), 0.0]))
    right = _unit(np.array([math.cos(tilt), -math.sin(tilt), 0.0]))
    normals = [up, left, right, (0.0, 0.0, -1.0)]
    cents = np.array([(0.0, 1.5, 2.5), (-0.1, 1.2, 2.0), (0.1, 1.2, 2.0), (0.0, 0.5, 4.0)])
    for n, c in zip(normals, cents, strict=True):
        assert np.dot(n, c) < 0
    w = [0.5, 0.4, 0.4, 1.0]
    d = [-float(np.dot(n, c)) for n, c in zip(normals, cents, strict=True)]
    on = estimate_gravity(normals, w, d, centroids=cents)
    off = estimate_gravity(normals, w, d, GravityParams(mirror_pairs=False))
    np.testing.assert_array_equal(on.vector, off.vector)
    assert on.confidence == off.confidence


def test_posed_scenes_unchanged():
    """Scenes with square walls (the pose sweep's: box, stairs, ramp, floor and walls) keep
    their estimate exactly, vector and confidence."""
    for kind in ("box", "stairs", "ramp"):
        for pitch in (0, 40, 80):
            s = posed_scene(kind, pitch, 10, seed=pitch + 3, walls=2)
            on = up_from_cloud(s.cloud, s.gt_labels)
            off = up_from_cloud(s.cloud, s.gt_labels, GravityParams(mirror_pairs=False))
            np.testing.assert_array_equal(on.vector, off.vector)
            assert on.confidence == off.confidence
            assert _deg(on.vector, s.up) <= 2.0


def test_bad_parameters():
    with pytest.raises(InputError, match="mirror_pairs"):
        GravityParams(mirror_pairs=1)
    with pytest.raises(InputError, match="max_draft_deg"):
        GravityParams(max_draft_deg=60.0)
    with pytest.raises(InputError, match="centroid"):
        estimate_gravity([(0, 1, 0), (1, 0, 0)], [1.0, 1.0], [0.5, 0.5], centroids=[(0, 0, 1)])
