"""``benchmarks/stair_step_why.py`` (step60, docs/objects.md "Why the step test fails a real
flight"): the step test's sub-tests measured pair by pair agree with the step test itself, and
a flight whose steps fail one sub-test is named by it."""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
import independent_scenes as ind  # noqa: E402
import stair_step_why as why  # noqa: E402

from planerel.features.facts import describe_scene  # noqa: E402
from planerel.features.relations import ProposalParams, _step_kind  # noqa: E402
from planerel.features.stair_step import stair_steps  # noqa: E402
from planerel.features.step_geometry import _cut_lengthwise  # noqa: E402
from planerel.io import readers as io  # noqa: E402
from planerel.segment import segment  # noqa: E402


@pytest.fixture(scope="module")
def flights(tmp_path_factory):
    """Described scenes of an independent set of flights: ``[(desc, flight labels)]``."""
    out = tmp_path_factory.mktemp("why")
    ind.make_set(out, 8, 5, (160, 120), kinds=("stairs", "stairs_top"))
    scenes = []
    for p in sorted(out.glob("i[0-9][0-9][0-9][0-9].npy")):
        truth = np.load(p.with_name(p.stem + ".objects.npy"))
        cloud = io.read(p)
        desc = describe_scene(cloud, segment(cloud).labels, scene_id=p.stem)
        lab = np.asarray(desc.labels)
        for k in np.unique(truth[truth > 0]):
            m = truth == k
            labs, n = np.unique(lab[m & (lab >= 0)], return_counts=True)
            size = {L: int((lab == L).sum()) for L in labs.tolist()}
            inside = [L for L, c in zip(labs.tolist(), n.tolist(), strict=True)
                      if c >= 0.5 * size[L] and size[L] >= 50]
            if len(inside) >= 2:
                scenes.append((desc, inside))
    return scenes


def _passing(desc, labels, params):
    planes = desc.planes
    by = {p.label: p for p in planes}
    faces = [by[k] for k in labels if k in by]
    kinds = {q.label: _step_kind(q, params.step_tilt) for q in faces}
    cut = _cut_lengthwise([q for q in faces if kinds[q.label] == "tread"],
                          params.cut_long_side, planes.labels)
    out = set()
    for i, a in enumerate(faces):
        for b in faces[i + 1:]:
            if kinds[a.label] and kinds[a.label] == kinds[b.label] and all(
                    ok for _n, ok, _v in why.pair_tests(planes, a, b, params, cut)):
                lo, hi = (a, b) if a.height <= b.height else (b, a)
                out.add((lo.label, hi.label))
    return out


def test_pairs_passing_every_sub_test_are_the_step_tests_pairs(flights):
    p = ProposalParams()
    seen = 0
    for desc, labels in flights:
        steps = set(stair_steps(desc.planes, labels, p))
        passing = _passing(desc, labels, p)
        # the step test adds only a border-cut top tread's and an open-riser row's steps
        assert passing <= steps
        seen += len(passing)
    assert seen >= 5


def test_a_flight_without_steps_is_named_by_the_sub_test_that_fails(flights):
    p = ProposalParams()
    # an overlap across no two faces reach (interval IoU is at most 1)
    tight = dataclasses.replace(p, step_overlap=1.01)
    named = 0
    for desc, labels in flights:
        if not _passing(desc, labels, p):
            continue
        best = why.closest_pair(desc.planes, labels, p)
        assert best["first"] == "passes all" and not best["fails"]
        named += 1
        worst = why.closest_pair(desc.planes, labels, tight)
        assert not _passing(desc, labels, tight)
        assert "overlap across" in worst["fails"]
        assert worst["values"]["overlap across"] <= 1.0
    assert named >= 3


def test_the_aggregate_counts_each_flight_once_by_its_first_failure():
    rows = [{"stage": "no stair_step", "why": {"first": "rise", "fails": ["rise", "run"]}},
            {"stage": "no stair_step", "why": {"first": "run", "fails": ["run"]}},
            {"stage": "found"},
            {"stage": "no stair_step", "why": None}]
    first, anyf = why.aggregate(rows)
    assert first == {"rise": 1, "run": 1}
    assert anyf == {"rise": 1, "run": 2}


def test_a_missing_folder_or_model_is_a_one_line_error(tmp_path, capsys):
    with pytest.raises(SystemExit):
        why.main([str(tmp_path / "none")])
    assert "no such folder" in capsys.readouterr().err
    assert why.main([str(tmp_path), "--model", str(tmp_path / "nomodel")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("stair_step_why: ") and "Traceback" not in err
