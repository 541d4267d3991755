"""Face profiles on a strided sample of ``RelationParams.profile_points`` points (speed22v,
issue 22): 4000 by default, 1000 one setting away (a fifth of the reads on large faces).  Not
exact: a profile's percentiles move by the sample; the tests check that the relations and
objects of the real frames are the same at both settings, and that every step that measures a
profile takes the setting."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scenes_analytic import box, floor, render

from planerel.errors import InputError
from planerel.features.curved import skirt_faces
from planerel.features.planes import measure_planes
from planerel.features.relations import RelationParams, relate
from planerel.features.solid import PROFILE_POINTS, face_points, face_profile_of

_DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def _real_frames():
    files = sorted((_DATA / "kinect").glob("*_depth.tiff")) + sorted((_DATA / "mosd").glob("*.pcd"))
    if not files:
        pytest.skip(f"no real frames under {_DATA}")
    return files


@pytest.mark.parametrize("bad", [0, -5, True, 2.5, "1000", None])
def test_profile_points_must_be_a_positive_integer(bad):
    with pytest.raises(InputError, match="profile_points"):
        RelationParams(profile_points=bad)


def test_the_default_sample_and_the_old_one():
    assert PROFILE_POINTS == RelationParams().profile_points == 4000
    assert RelationParams(profile_points=1000).profile_points == 1000


def test_relate_measures_its_profiles_on_the_relations_sample():
    """The profiles relate hands on are face_profile_of's at ``profile_points``; a face of
    more than ``4 * profile_points`` points is read on every k-th row and column (k >= 2)."""
    cloud, lab, _, _ = render([floor()] + box(0.0, 0.8, 0.30, 0.24, 0.12), noise=0.0012,
                              pitch=45, cam_height=0.8, width=320, height=240)
    ps = measure_planes(cloud, lab)
    byl = {p.label: p for p in ps}
    strided = 0
    for pts in (4000, 1000, 60):
        profiles: dict = {}
        rel = relate(ps, cloud, RelationParams(profile_points=pts), profiles)
        assert any(r.skirt for r in rel) and profiles
        for label, prof in profiles.items():
            want = face_profile_of(byl[label], ps.up, ps.labels, cloud.xyz, pts)
            assert all(np.array_equal(a, b, equal_nan=True) for a, b in zip(prof, want, strict=True))
            n = len(face_points(byl[label], ps.labels, cloud.xyz, pts)[0])
            if byl[label].n_points >= 4 * pts:
                strided += 1
                assert n <= byl[label].n_points / 3
        # the flat faces: relate's profiles, or measured anew on the same sample
        assert skirt_faces(ps, rel, cloud, profiles=profiles) == skirt_faces(ps, rel, cloud)
    assert strided >= 1


def test_skirt_faces_measures_on_the_relations_sample(monkeypatch):
    """skirt_faces measures the faces it was not handed with the relations' setting (a spy
    around the real face_profile_of records the sample asked)."""
    import planerel.features.solid as solid

    cloud, lab, _, _ = render([floor()] + box(0.0, 0.8, 0.16, 0.10, 0.08), noise=0.0012,
                              pitch=45, cam_height=0.8, width=320, height=240)
    ps = measure_planes(cloud, lab)
    real = solid.face_profile_of
    asked = []

    def spy(face, up, labels, xyz, max_points=PROFILE_POINTS):
        asked.append(max_points)
        return real(face, up, labels, xyz, max_points)

    rel = relate(ps, cloud, RelationParams(profile_points=77))
    monkeypatch.setattr(solid, "face_profile_of", spy)
    assert skirt_faces(ps, rel, cloud, profiles={})
    assert asked and set(asked) == {77}


def test_real_frames_relate_and_propose_the_same_at_the_old_sample():
    """On the shared real frames (three Kinect frames, seven mOSD frames) the relations (every
    field, skirt steps too) and the objects are the same with 1000 and with 4000 points, while
    the large faces are read on a sparser grid."""
    from planerel.features.facts import describe_scene
    from planerel.io.readers import read
    from planerel.segment import segment

    sparser = 0
    for f in _real_frames():
        cloud = read(f)
        labels = segment(cloud).labels
        new = describe_scene(cloud, labels, relation_params=RelationParams(profile_points=1000))
        old = describe_scene(cloud, labels)
        assert [repr(r) for r in new.relations] == [repr(r) for r in old.relations], f.name
        assert new.relations.skirt_steps == old.relations.skirt_steps
        assert [(o.planes, o.curved, o.planar_fraction) for o in new.objects] == \
            [(o.planes, o.curved, o.planar_fraction) for o in old.objects], f.name
        sparser += sum(1 for p in new.planes if p.orientation == "vertical" and p.n_points >= 4000)
    assert sparser >= 5
