"""The stairfit stage's verdicts for a measuring tool (``_stepped_cluster_labels(why=...)``,
``benchmarks/stairfit_why.py``, wave82): asking for them changes nothing, a kept flight is
``kept`` with its rise, a ramp fails the plane test, a narrow stepped thing ``narrow``, and a
flight whose points the noise scatters beyond the profile fails ``inliers``."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
from scenes_analytic import floor, ramp, render, stairs

from planerel.features.curved import CurvedParams
from planerel.features.facts import describe_scene
from planerel.features.stairfit import StairFitParams, _stepped_cluster_labels

_SPEC = importlib.util.spec_from_file_location(
    "stairfit_why", Path(__file__).resolve().parents[1] / "benchmarks" / "stairfit_why.py")
sw = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(sw)


def _scene(rects, noise=0.003):
    cloud, lab, up, _ = render(rects, width=160, height=120, noise=noise, seed=3, pitch=10.0,
                               cam_height=1.0)
    lab = np.where(lab == 0, 0, -1).astype(np.int32)  # the floor planed, the rest to the fit
    planes = describe_scene(cloud, lab, up=up,
                            curved_params=CurvedParams(stepped_clusters=False)).planes
    return cloud, planes


def _flight(width=1.2, y0=2.6):
    return [floor(size=12.0, y=4.0), *stairs(0.0, y0, n=5, rise=0.17, run=0.29, width=width)]


def _verdicts(cloud, planes, params=None):
    why: dict = {}
    got = _stepped_cluster_labels(cloud, planes, params, why=why)
    plain = _stepped_cluster_labels(cloud, planes, params)
    # asking for the verdicts changes nothing
    assert (got[0] is None) == (plain[0] is None)
    if got[0] is not None:
        np.testing.assert_array_equal(got[0][0], plain[0][0])
        assert got[0][1] == plain[0][1]
    return why


def test_a_kept_flight_is_kept_with_its_rise():
    cloud, planes = _scene(_flight())
    why = _verdicts(cloud, planes)
    tests = [t for t, _m in why["verdicts"].values()]
    assert "kept" in tests
    m = next(m for t, m in why["verdicts"].values() if t == "kept")
    assert abs(m["rise"] - 0.17) <= 0.03 and m["share"] >= 0.8
    rows, cols, ids, n_comp, sizes = why["clusters"]
    assert len(rows) == len(cols) == len(ids) and sizes.sum() == len(ids)


def test_a_ramp_fails_the_plane_test_and_a_narrow_stepped_thing_is_narrow():
    cloud, planes = _scene([floor(size=12.0, y=4.0),
                            *ramp(0.0, 2.6, angle=15.0, length=2.0, width=1.2)])
    tests = {t for t, _m in _verdicts(cloud, planes).get("verdicts", {}).values()}
    assert tests and tests <= {"plane", "slope", "narrow", "inliers", "faces"} and "kept" not in tests
    cloud, planes = _scene(_flight(width=0.3, y0=1.8))
    why = _verdicts(cloud, planes)
    assert {t for t, _m in why["verdicts"].values()} == {"narrow"}


def test_a_flight_scattered_past_its_profile_fails_the_inlier_share():
    # the same flight; the fit asked for nearly every point on the profile within a tight
    # truncation: the share, not the plane or the faces, is what fails
    cloud, planes = _scene(_flight())
    why = _verdicts(cloud, planes, StairFitParams(sigmas=0.5, min_inliers=0.95))
    got = [(t, m) for t, m in why["verdicts"].values() if t not in ("narrow", "slope")]
    assert got and all(t == "inliers" and m["share"] < 0.95 for t, m in got)


def test_the_aggregate_counts_each_flight_once_by_its_largest_cluster():
    rows = [{"stage": "found", "clusters": [{"test": "kept", "share": 0.9}], "wave": 1.2},
            {"stage": "no stair_step", "clusters": [{"test": "inliers", "share": 0.1}],
             "wave": 3.5},
            {"stage": "faces < 2", "clusters": [], "wave": None}]
    verdicts, lost = sw.aggregate(rows)
    assert verdicts == {("found", "kept"): 1, ("lost", "inliers"): 1, ("lost", "no cluster"): 1}
    assert lost == [(3.5, "inliers", 0.1), (None, "no cluster", None)]


def test_the_tool_gives_every_flight_of_a_set_its_clusters(tmp_path, capsys):
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    import independent_scenes as ind

    ind.make_set(tmp_path / "st", 4, 3, (160, 120), kinds=("stairs", "stairs_top"))
    rules = tmp_path / "rules.pl"
    rules.write_text("stairs(A) :- has_plane(A,B), parallel(B,C), stair_step(C,B).\n")
    out = tmp_path / "rows.json"
    assert sw.main([str(tmp_path / "st"), "--model", str(rules), "--json", str(out),
                    "--aggregate"]) == 0
    import json

    rows = json.loads(out.read_text())
    assert rows
    tests = {"narrow", "slope", "taken", "plane", "no fit", "inliers", "faces", "face width",
             "kept", "small"}
    for r in rows:
        assert 0.0 <= r["unassigned"] <= 1.0 and r["wave"] >= 0.0
        assert all(c["test"] in tests and c["pixels"] >= sw.MIN_IN for c in r["clusters"])
    text = capsys.readouterr().out
    assert "largest cluster" in text and "lost (wave, test, share)" in text
    assert "i0000" not in text  # --aggregate names no frame
