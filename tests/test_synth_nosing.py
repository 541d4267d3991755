"""Chamfered step nosings in the synthetic stairs (stairs_geometry / descent_geometry ``nosing``,
``WorldRange.nosing``): the strip's place, angle and width, the cut side profile, the upper
floor of a descent, unchanged scenes when off, and that the strip segments as a narrow
inclined plane at subsample 2 (docs/results.md, "Nosings in the varied world")."""

from __future__ import annotations

import hashlib
import math
import re

import numpy as np
import pytest

from planerel.cli import main
from planerel.errors import InputError
from planerel.synth import geometry as sg
from planerel.synth.world import WorldRange, generate_world_scene

UP = np.array([0.0, 0.0, 1.0])


def _pieces(g, role):
    return [p for p in g.polygons if g.planes[p.plane].role == role]


def _incline(poly) -> float:
    return math.degrees(math.acos(min(1.0, abs(float(poly.normal() @ UP)))))


def _area(poly) -> float:
    v = poly.vertices
    return 0.5 * float(np.linalg.norm(np.cross(v - v[0], np.roll(v, -1, axis=0) - v[0]).sum(0)))


@pytest.mark.parametrize("width,deg", [(0.012, 21.0), (0.04, 45.0), (0.03, 60.0)])
def test_the_nosing_lies_between_riser_and_tread_at_its_angle_and_width(width, deg):
    steps, rise, run = 4, 0.17, 0.28
    g = sg.stairs_geometry(steps, rise, run, 1.0, nosing=width, nosing_deg=deg)
    assert [p.role for p in g.planes] == (["riser", "nosing", "tread"] * steps
                                          + ["back", "side", "side"])
    risers, nosings, treads = (_pieces(g, r) for r in ("riser", "nosing", "tread"))
    drop, ahead = width * math.sin(math.radians(deg)), width * math.cos(math.radians(deg))
    for i, (r, n, t) in enumerate(zip(risers, nosings, treads, strict=True)):
        z = (i + 1) * rise
        assert _incline(n) == pytest.approx(deg, abs=1e-9)
        # its lower edge is the riser's top edge, its upper edge the tread's front edge
        low = n.vertices[n.vertices[:, 2] < z - 1e-12]
        high = n.vertices[n.vertices[:, 2] > z - 1e-12]
        assert r.vertices[:, 2].max() == pytest.approx(z - drop, abs=1e-12)
        assert {tuple(v) for v in low} <= {tuple(v) for v in r.vertices}
        assert {tuple(v) for v in high} <= {tuple(v) for v in t.vertices}
        assert t.vertices[:, 0].min() == pytest.approx(r.vertices[0, 0] + ahead, abs=1e-12)
        # the strip is `width` across the edge and the flight's width along it
        assert np.linalg.norm(high.mean(0) - low.mean(0)) == pytest.approx(width, abs=1e-12)
        assert _area(n) == pytest.approx(width * 1.0, abs=1e-12)
        # it faces out of the step: up and against the climb (its normal's x and z have
        # opposite signs whichever the winding)
        nx, _, nz = n.normal()
        assert nx * nz < 0


def test_the_open_side_profile_is_cut_by_the_chamfer():
    steps, rise, run, width, deg = 3, 0.16, 0.3, 0.03, 40.0
    sharp = sg.stairs_geometry(steps, rise, run, 1.0, sides="open")
    cut = sg.stairs_geometry(steps, rise, run, 1.0, sides="open", nosing=width, nosing_deg=deg)
    drop, ahead = width * math.sin(math.radians(deg)), width * math.cos(math.radians(deg))
    sides_sharp, sides_cut = _pieces(sharp, "side"), _pieces(cut, "side")
    assert len(sides_cut) == len(sides_sharp) == 2 * steps
    for a, b in zip(sides_sharp, sides_cut, strict=True):
        # each step's piece loses the corner triangle, and stays convex and planar
        assert _area(a) - _area(b) == pytest.approx(0.5 * drop * ahead, abs=1e-12)
        assert np.allclose((b.vertices - b.vertices[0]) @ b.normal(), 0, atol=1e-12)
    # the profile's cut corner is the nosing's end
    nosing_ends = {tuple(np.round(v, 12)) for n in _pieces(cut, "nosing") for v in n.vertices}
    profile = {tuple(np.round(v, 12)) for s in sides_cut for v in s.vertices}
    assert nosing_ends <= profile
    # closed sides are walls above the nosings: unchanged
    closed = sg.stairs_geometry(steps, rise, run, 1.0, sides="closed", nosing=width)
    closed0 = sg.stairs_geometry(steps, rise, run, 1.0, sides="closed")
    for a, b in zip(_pieces(closed0, "side"), _pieces(closed, "side"), strict=True):
        np.testing.assert_array_equal(a.vertices, b.vertices)


def test_the_descents_upper_floor_stops_short_of_the_top_nosing():
    steps, rise, run, width, w, deg = 4, 0.18, 0.3, 0.04, 1.2, 30.0
    ahead = width * math.cos(math.radians(deg))
    env, flight = sg.descent_geometry(steps, rise, run, w, nosing=width, nosing_deg=deg)
    upper = [p for p in _pieces(env, "floor") if abs(p.vertices[:, 2].max()) < 1e-12]

    def covered(x, y):
        return any(p.vertices[:, 0].min() <= x <= p.vertices[:, 0].max()
                   and p.vertices[:, 1].min() <= y <= p.vertices[:, 1].max() for p in upper)

    # across the flight the floor ends `ahead` before the drop edge (x = 0); beside it, at 0
    assert max(p.vertices[:, 0].max() for p in upper) == pytest.approx(0.0, abs=1e-12)
    assert not covered(-ahead / 2, 0.0) and not covered(-ahead / 2, 0.99 * w / 2)
    assert covered(-ahead * 1.01, 0.0) and covered(-ahead / 2, 1.01 * w / 2)
    assert covered(-ahead / 2, -1.01 * w / 2)
    # the top nosing runs from that floor edge down to the top riser (x = 0)
    nos = _pieces(flight, "nosing")
    assert len(nos) == steps
    top = max(nos, key=lambda p: p.vertices[:, 2].max())
    assert top.vertices[:, 2].max() == pytest.approx(0.0, abs=1e-12)
    assert sorted(np.round(top.vertices[:, 0], 12)) == pytest.approx([-ahead, -ahead, 0, 0],
                                                                      abs=1e-12)
    assert _incline(top) == pytest.approx(deg, abs=1e-9)
    # sharp: one floor rectangle up to the edge, as before
    env0, flight0 = sg.descent_geometry(steps, rise, run, w)
    assert not _pieces(flight0, "nosing")
    assert len([p for p in _pieces(env0, "floor") if abs(p.vertices[:, 2].max()) < 1e-12]) == 1


def test_without_nosing_the_builders_and_scenes_are_unchanged():
    a = sg.stairs_geometry(5, 0.17, 0.28, 1.1, top_depth=0.6)
    b = sg.stairs_geometry(5, 0.17, 0.28, 1.1, top_depth=0.6, nosing=0.0, nosing_deg=30.0)
    assert [p.role for p in a.planes] == [p.role for p in b.planes]
    for p, q in zip(a.polygons, b.polygons, strict=True):
        np.testing.assert_array_equal(p.vertices, q.vertices)
    # hashes taken from main before the option (4b89b2d..: a flight up, 57a2cbe..: down)
    expected = {("stairs", 1, 0.0): "4b89b2d3f97ee57f", ("stairs", 2, 1.0): "57a2cbef44607306",
                ("box", 3, 0.35): "8f3afa14533ec80e", ("ramp", 4, 0.35): "dc20ee70a73eafaa"}
    for (kind, seed, down), digest in expected.items():
        s = generate_world_scene(kind, seed, size=(640, 480), subsample=8,
                                 ranges=WorldRange(descending=down))
        got = hashlib.sha256(s.depth_mm.tobytes() + s.gt_labels.tobytes()
                             + s.gt_objects.tobytes()).hexdigest()[:16]
        assert got == digest, (kind, seed)
        assert "nosing" not in s.objects[1]["params"]


def test_world_nosings_are_drawn_in_range_up_and_down():
    r = WorldRange(nosing=(0.01, 0.04))
    for seed, down in ((1, 0.0), (2, 1.0)):
        s = generate_world_scene("stairs", seed, size=(640, 480), subsample=8,
                                 ranges=WorldRange(**{**r.to_dict(), "descending": down}))
        p = s.objects[1]["params"]
        assert p["direction"] == ("down" if down else "up")
        assert 0.01 <= p["nosing"] <= 0.04 and 20.0 <= p["nosing_deg"] <= 60.0
        planes = [q for q in s.planes if q.role == "nosing"]
        assert len(planes) == p["steps"] and all(q.object_index == 1 for q in planes)
        assert all(q.incline_deg == pytest.approx(p["nosing_deg"], abs=1e-6) for q in planes)


def test_a_nosing_segments_as_a_narrow_inclined_plane_at_subsample_2(tmp_path):
    data, facts = tmp_path / "set", tmp_path / "f.pl"
    assert main(["dataset", "synth", str(data), "--world", "varied", "--n-box", "0",
                 "--n-stairs", "2", "--n-ramp", "0", "--seed", "1", "--subsample", "2",
                 "--range", "nosing=0.03,0.04", "--quiet"]) == 0
    assert main(["describe", str(data / "s0001.depth.png"), "-o", str(facts), "-j", "1"]) == 0
    text = facts.read_text()
    inclined = re.findall(r"^orientation\((\w+), inclined\)\.", text, re.M)
    found = []
    for p in inclined:
        if not re.search(rf"^has_plane\(s0001_o1, {p}\)\.", text, re.M):
            continue
        deg = float(re.search(rf"^incline\({p}, ([-\d.]+)\)\.", text, re.M).group(1))
        wide = float(re.search(rf"^seen_width\({p}, ([-\d.]+)\)\.", text, re.M).group(1))
        found.append((deg, wide))
    # the drawn chamfer is 28 degrees, 3.6 cm; two nosings are in view
    assert len(found) == 2
    assert all(10 < deg < 40 and 0.015 < wide < 0.05 for deg, wide in found), found


@pytest.mark.parametrize("call,match", [
    (lambda: sg.stairs_geometry(3, 0.15, 0.3, 1.0, nosing=-0.01), "nosing must be >= 0"),
    (lambda: sg.stairs_geometry(3, 0.15, 0.3, 1.0, nosing=float("nan")), "nosing must be"),
    (lambda: sg.stairs_geometry(3, 0.15, 0.3, 1.0, nosing=0.2, nosing_deg=60),
     "smaller than a step"),
    (lambda: sg.stairs_geometry(3, 0.15, 0.3, 1.0, nosing="wide"), "nosing must be a number"),
    (lambda: sg.stairs_geometry(3, 0.15, 0.3, 1.0, nosing=0.02, nosing_deg=90),
     "strictly between 0 and 90"),
    (lambda: sg.stairs_geometry(3, 0.15, 0.3, 1.0, nosing=0.02, nosing_deg=0),
     "strictly between 0 and 90"),
    (lambda: sg.descent_geometry(3, 0.15, 0.3, 1.0, nosing=0.02, nosing_deg=-5),
     "strictly between 0 and 90"),
    (lambda: WorldRange(nosing=(0.0, 0.07)), "nosing must lie in 0..0.06"),
    (lambda: WorldRange(nosing=(0.04, 0.01)), "nosing must be a finite"),
])
def test_bad_nosings_raise_input_error(call, match):
    with pytest.raises(InputError, match=match):
        call()


def test_cli_rejects_a_bad_nosing_range(tmp_path, capsys):
    assert main(["dataset", "synth", str(tmp_path / "x"), "--world", "varied", "--n-box", "0",
                 "--n-stairs", "1", "--n-ramp", "0", "--range", "nosing=0,0.1"]) != 0
    assert "nosing must lie in 0..0.06" in capsys.readouterr().err
