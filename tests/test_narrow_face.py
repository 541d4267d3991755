"""A narrow upright face is a ``tall_face`` when flat across its width (face52,
docs/objects.md "Narrow faces flat across"): :func:`face_bend` tells a box's face from a
cylinder's facet of the same size, and ``tall_narrow_width`` (default 0.06 m; 0: off, as
before face52) admits the flat ones narrower than ``corner_width``."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from scenes_analytic import box, floor
from test_box_tests import _verdicts  # tall_faces' verdict and box_tests' tests, per plane

from planerel.errors import InputError
from planerel.features.relations import RelationParams, face_bend

UP = np.array([0.0, 0.0, 1.0])


def _face(surface, half=0.02, height=0.15, noise=0.0012, seed=0):
    """An organized grid of points ``y = surface(x)`` (x across, z up), all labelled 1, and
    a plane record facing -y."""
    rng = np.random.default_rng(seed)
    x, z = np.meshgrid(np.linspace(-half, half, 24), np.linspace(0.0, height, 60))
    y = surface(x) + rng.normal(0.0, noise, x.shape)
    xyz = np.stack([x, y, z], axis=-1)
    labels = np.ones(x.shape, dtype=np.int32)
    face = SimpleNamespace(label=1, normal=(0.0, -1.0, 0.0), bbox=(0, 0, *x.shape),
                           n_points=x.size)
    return face, labels, xyz


def test_a_flat_face_bends_by_its_noise_and_a_cylinder_facet_by_its_sagitta():
    flat = face_bend(*_face(lambda x: 1.0 + 0.0 * x), UP)
    # a mug's front (radius 4 cm) as a 4 cm strip: 5 mm sagitta against 1.2 mm noise
    r = 0.04
    can = face_bend(*_face(lambda x: 1.0 + r - np.sqrt(r * r - x * x)), UP)
    assert flat < 0.3 < 1.5 < can
    # a tilted flat face (a box turned about the vertical) is flat as well
    assert face_bend(*_face(lambda x: 1.0 + 0.5 * x), UP) < 0.3


def test_a_narrow_flat_box_face_is_tall_only_with_the_narrow_width():
    # a 7 cm wide, 15 cm high product box 1.2 m before a low camera: its front (label 2)
    rects = [floor(), *box(0.0, 1.2, 0.07, 0.07, 0.15)]
    off = _verdicts(rects, RelationParams(tall_narrow_width=0.0), pitch=0.0, cam_height=0.2)
    on = _verdicts(rects, pitch=0.0, cam_height=0.2)  # the default, 0.06
    for v in (off, on):
        assert all(a == b for a, b, _, _ in v.values()), v  # box_tests agrees
    assert off[2][3] < 0.08 and not off[2][0] and off[2][2] == ["shape"]
    assert on[2][0] and on[2][2] == []
    # under the narrow width it stays refused
    under = _verdicts(rects, RelationParams(tall_narrow_width=0.075), pitch=0.0, cam_height=0.2)
    assert not under[2][0] and under[2][2] == ["shape"]


def test_the_narrow_settings_are_checked():
    with pytest.raises(InputError):
        RelationParams(tall_narrow_width=-0.01)
    with pytest.raises(InputError):
        RelationParams(tall_narrow_bend=-1.0)


def test_the_default_admits_the_narrow_flat_faces():
    assert RelationParams().tall_narrow_width == 0.06 and RelationParams().tall_narrow_bend == 0.3


def _face_bend_numpy(face, labels, xyz, up, max_points=4000):
    """face_bend as written with numpy's own calls (face52): the reference its faster form
    (speed58b: cross3, vec_norm, the compiled percentiles) must equal float for float."""
    from planerel.features.solid import face_points

    pts = face_points(face, labels, xyz, max_points)[0]
    if pts.shape[0] < 8:
        return np.inf
    up = np.asarray(up, float)
    n = np.asarray(face.normal, float)
    n = n / np.linalg.norm(n)
    along = np.cross(up, n)
    norm = float(np.linalg.norm(along))
    if not norm > 1e-9:
        return np.inf
    along = along / norm
    c = pts.mean(axis=0)
    d, u, v = (pts - c) @ n, (pts - c) @ along, (pts - c) @ up
    design = np.stack([u * u, u, np.ones_like(u), v], axis=1)
    coef, *_ = np.linalg.lstsq(design, d, rcond=None)
    lo, hi = np.percentile(u, [2, 98])
    res = float(np.sqrt(np.mean((d - design @ coef) ** 2)))
    return abs(float(coef[0])) * ((hi - lo) / 2) ** 2 / max(res, 1e-9)


def test_face_bend_equals_numpy_s_on_random_faces():
    rng = np.random.default_rng(58)
    for seed in range(40):
        r = rng.uniform(0.03, 0.5)
        half = rng.uniform(0.01, 0.2)
        face, labels, xyz = _face(lambda x, r=r: 1.0 + r - np.sqrt(r * r - np.minimum(x * x, r * r)),
                                  half=half, noise=rng.uniform(0.0, 0.004), seed=seed)
        face.normal = tuple(rng.normal(0.0, 0.05, 3) + (0.0, -rng.uniform(0.5, 2.0), 0.0))
        up = UP + rng.normal(0.0, 0.03, 3)
        labels[rng.random(labels.shape) < 0.2] = 2  # other planes' pixels left out
        xyz[rng.random(labels.shape) < 0.05] = np.nan
        got, ref = face_bend(face, labels, xyz, up), _face_bend_numpy(face, labels, xyz, up)
        assert got == ref or (np.isinf(got) and np.isinf(ref))
    face, labels, xyz = _face(lambda x: 1.0 + 0.0 * x)
    assert face_bend(face, labels, xyz, (0.0, -1.0, 0.0)) == np.inf  # up along the normal


def test_face_bend_equals_numpy_s_on_real_frames():
    from pathlib import Path

    from planerel.features.planes import measure_planes
    from planerel.io.readers import read
    from planerel.segment import segment

    files = sorted((Path(__file__).resolve().parents[2] / "shared" / "data" / "kinect")
                   .glob("*_depth.tiff"))
    if not files:
        pytest.skip("no Kinect frames in ../shared/data/kinect")
    n = 0
    for f in files:
        cloud = read(str(f))
        planes = measure_planes(cloud, segment(cloud).labels)
        for q in planes:
            if q.orientation == "vertical":
                got = face_bend(q, planes.labels, cloud.xyz, planes.up)
                assert got == _face_bend_numpy(q, planes.labels, cloud.xyz, planes.up)
                n += 1
    assert n > 0


def _bend_last_holds(planes, cloud, p=None):
    """tall_faces asks a narrow face's bend last (speed59): its answer is the faces it gives
    when every bend passes (``tall_narrow_bend`` 1e300) that pass the full shape test, which is
    what asking the bend first gives when a floor plane grounds the faces (the feet level,
    taken without a floor, reads every shaped face)."""
    from dataclasses import replace

    from planerel.features.relations import relate, tall_faces, tall_shaped

    p = p or RelationParams()
    rel = relate(planes, cloud, p)
    got = tall_faces(planes, rel, cloud)
    loose = tall_faces(planes, relate(planes, cloud, replace(p, tall_narrow_bend=1e300)),
                       cloud)
    by = {q.label: q for q in planes}
    want = {x for x in loose if tall_shaped(by[x], p, planes.labels, cloud.xyz, planes.up)}
    assert got == want
    narrow = [q for q in planes if tall_shaped(q, p, planes.labels, cloud.xyz, planes.up,
                                               bend=False)
              and not q.width >= p.corner_width]
    return got, loose, narrow


def test_the_bend_asked_last_gives_the_faces_asking_it_first_gives_on_rendered_faces():
    from scenes_analytic import render

    from planerel.features.planes import measure_planes

    rects = [floor(), *box(0.0, 1.2, 0.07, 0.07, 0.15)]
    cloud, lab, _, _ = render(rects, noise=0.0012, width=320, height=240, pitch=0.0,
                              cam_height=0.2)
    ps = measure_planes(cloud, lab)
    got, loose, narrow = _bend_last_holds(ps, cloud)
    assert narrow and 2 in got  # the narrow flat front: its bend asked, and passed
    # no bend passes: the front passes every other test, and the bend asked last refuses it
    got, loose, narrow = _bend_last_holds(ps, cloud, RelationParams(tall_narrow_bend=0.0))
    assert 2 in loose and 2 not in got


def test_the_bend_asked_last_gives_the_faces_asking_it_first_gives_on_real_frames():
    from pathlib import Path

    from planerel.features.planes import measure_planes
    from planerel.io.readers import read
    from planerel.segment import segment

    data = Path(__file__).resolve().parents[2] / "shared" / "data"
    files = sorted((data / "kinect").glob("*_depth.tiff")) + sorted((data / "mosd").glob("*.pcd"))
    if not files:
        pytest.skip("no frames in ../shared/data")
    n = 0
    for f in files:
        cloud = read(str(f))
        planes = measure_planes(cloud, segment(cloud).labels)
        if planes.floor is None:
            continue
        n += len(_bend_last_holds(planes, cloud)[2])
    assert n > 0  # narrow faces among them (test31.pcd's three)
