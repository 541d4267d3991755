"""Work the description's steps shared or did in fewer calls (speed22s, issue 22): each fast
path against the form it replaced, which the tests keep as the reference, on random cases and
on rendered and real scenes; the results must be the same floats, not close ones."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scenes_analytic import box, floor, render

from planerel.features.curved import skirt_faces
from planerel.features.planes import measure_planes
from planerel.features.relations import _horizontal_basis, _tread_depth_axis, relate
from planerel.features.solid import face_profile_of

_DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def _same(a, b) -> bool:
    """The same floats, bit for bit (signed zeros and NaN payloads too)."""
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def _basis_numpy(up):
    """``_horizontal_basis`` as it was: ``np.cross``."""
    e1 = np.cross(up, [1.0, 0.0, 0.0])
    if np.linalg.norm(e1) < 0.1:
        e1 = np.cross(up, [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(up, e1)


def _depth_axis_numpy(H, up):
    """``_tread_depth_axis`` as it was: stacked, rolled, ``np.ptp``."""
    e1, e2 = _basis_numpy(up)
    P = np.stack([H @ e1, H @ e2], 1)
    if len(P) < 3:
        return e1, 0.0
    t = np.roll(P, -1, axis=0) - P
    t = t[np.hypot(t[:, 0], t[:, 1]) > 1e-9]
    if not len(t):
        return e1, 0.0
    t /= np.hypot(t[:, 0], t[:, 1])[:, None]
    n = np.stack([-t[:, 1], t[:, 0]], 1)
    deep = np.ptp(P @ n.T, axis=0)
    k = int(np.argmin(deep))
    if deep[k] <= 0:
        return e1, 0.0
    along = float(np.ptp(P @ t[k]))
    return n[k, 0] * e1 + n[k, 1] * e2, along / float(deep[k])


def _random_ups(rng, n):
    for k in range(n):
        u = rng.normal(size=3)
        if k % 5 == 0:  # near the x axis: the other branch
            u = np.array([np.sign(u[0]) or 1.0, 0.0, 0.0]) + 0.02 * rng.normal(size=3)
        if k % 17 == 0:
            u = np.array([1.0, 0.0, 0.0]) * (1 if k % 2 else -1)
        yield u / np.linalg.norm(u)


def test_horizontal_basis_is_numpys_cross():
    rng = np.random.default_rng(22)
    prev = None
    for up in _random_ups(rng, 3000):
        want = _basis_numpy(up)
        # asked again (the remembered basis), and after another up (computed anew)
        for ask in (up, up, prev, up, list(up)):
            if ask is None:
                continue
            got = _horizontal_basis(ask)
            ref = want if ask is not prev else _basis_numpy(prev)
            assert all(_same(g, w) for g, w in zip(got, ref, strict=True)), up
            assert not any(g.flags.writeable for g in got)
        prev = up
    # -0.0 and 0.0 are different ups to np.cross
    for up in ([0.0, 0.0, 1.0], [-0.0, 0.0, 1.0], [0.0, -0.0, -1.0]):
        got = _horizontal_basis(np.array(up))
        assert all(_same(g, w) for g, w in zip(got, _basis_numpy(np.array(up)), strict=True))
    # float32 and list input as numpy takes them
    up = np.array([0.1, -0.9, -0.3], np.float32)
    assert all(_same(g, w) for g, w in zip(_horizontal_basis(np.asarray(up, float)),
                                           _basis_numpy(np.asarray(up, float)), strict=True))


class _Hull:
    def __init__(self, hull3d):
        self.hull3d = hull3d


def test_tread_depth_axis_is_the_numpy_form_on_random_hulls():
    rng = np.random.default_rng(7)
    ups = list(_random_ups(rng, 400))
    for k in range(6000):
        m = int(rng.integers(0, 16))
        H = rng.normal(size=(m, 3)) * rng.choice([1e-6, 1e-3, 0.1, 1.0, 5.0])
        if m and k % 4 == 0:
            H[rng.integers(0, m)] = H[rng.integers(0, m)]  # a repeated vertex: a zero edge
        if m and k % 13 == 0:
            H[:] = H[0]  # every edge zero
        if m >= 3 and k % 7 == 0:  # a convex polygon, as hull3d is
            a = np.sort(rng.uniform(0, 2 * np.pi, m))
            H = np.c_[np.cos(a), np.sin(a), np.zeros(m)] * rng.uniform(0.05, 2.0)
        up = ups[k % len(ups)]
        (d1, r1), (d0, r0) = _tread_depth_axis(_Hull(H), up), _depth_axis_numpy(H, up)
        assert _same(d1, d0) and _same(r1, r0), (H, up)


@pytest.mark.skipif(not (_DATA / "mosd").is_dir(), reason="needs ../shared/data")
def test_tread_depth_axis_is_the_numpy_form_on_real_planes():
    from planerel.io.readers import read
    from planerel.segment import segment

    n = 0
    for f in sorted((_DATA / "mosd").glob("*.pcd"))[:2]:
        cloud = read(f)
        ps = measure_planes(cloud, segment(cloud).labels)
        for p in ps:
            (d1, r1), (d0, r0) = (_tread_depth_axis(p, ps.up),
                                  _depth_axis_numpy(np.asarray(p.hull3d, float), ps.up))
            assert _same(d1, d0) and _same(r1, r0)
            n += 1
    assert n >= 10


def _scenes():
    """Rendered scenes with skirts: boxes on a floor (one beside another, one on another)."""
    yield [floor()] + box(0.0, 0.8, 0.16, 0.10, 0.08)
    yield [floor()] + box(-0.12, 0.8, 0.14, 0.12, 0.10) + box(0.12, 0.85, 0.12, 0.10, 0.06, 2)
    yield [floor()] + box(0.0, 0.9, 0.30, 0.24, 0.12)


def test_relate_hands_on_the_face_profiles_it_measured():
    for rects in _scenes():
        cloud, lab, _, _ = render(rects, noise=0.0012, pitch=45, cam_height=0.8, width=320,
                                  height=240)
        ps = measure_planes(cloud, lab)
        profiles: dict = {}
        rel = relate(ps, cloud, profiles=profiles)
        # the same relations as without the dict
        assert [repr(r) for r in rel] == [repr(r) for r in relate(ps, cloud)]
        assert any(r.skirt for r in rel) and profiles
        byl = {p.label: p for p in ps}
        for label, prof in profiles.items():
            again = face_profile_of(byl[label], ps.up, ps.labels, cloud.xyz)
            assert all(_same(a, b) for a, b in zip(prof, again, strict=True))
        # the flat faces from the handed-on profiles are those measured anew
        flat = skirt_faces(ps, rel, cloud, profiles=profiles)
        assert flat and flat == skirt_faces(ps, rel, cloud)


def test_skirt_faces_measures_what_it_was_not_handed():
    cloud, lab, _, _ = render([floor()] + box(0.0, 0.8, 0.16, 0.10, 0.08), noise=0.0012,
                              pitch=45, cam_height=0.8, width=320, height=240)
    ps = measure_planes(cloud, lab)
    profiles: dict = {}
    rel = relate(ps, cloud, profiles=profiles)
    want = skirt_faces(ps, rel, cloud)
    assert want
    # a partial dict: the faces missing from it are measured
    some = dict(list(profiles.items())[:1])
    assert skirt_faces(ps, rel, cloud, profiles=some) == want
    assert skirt_faces(ps, rel, cloud, profiles={}) == want
    assert math.isfinite(next(iter(profiles.values())).top)
