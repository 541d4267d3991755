"""benchmarks/round_skirts.py (round44): the measures of a skirt pair's top and face that were
tried as tests of a round thing (a can's cap and a facet of its side) against a box's top and
side.  A measuring tool (docs/objects.md "Cans and cups answered box by the skirt clause:
measured, nothing built (round44)"): no relation of the model reads it.  Points made in code."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import round_skirts  # noqa: E402

UP = np.array([0.0, 0.0, 1.0])


def _grid(n=60):
    u = np.linspace(-1.0, 1.0, n)
    return np.array([(a, b) for a in u for b in u])


def _top(points2d, height=0.1, centre=(0.0, 0.7)):
    """2-D outline points lifted onto a horizontal top ``height`` m up, ``centre`` m ahead of
    a sensor at the origin looking along +y (z up)."""
    return np.c_[points2d[:, 0] + centre[0], points2d[:, 1] + centre[1],
                 np.full(len(points2d), height)]


def test_a_disc_fills_a_quarter_pi_of_its_rectangle_and_fits_a_circle():
    g = _grid(200) * 0.03
    disc = g[np.hypot(g[:, 0], g[:, 1]) <= 0.03]
    m = round_skirts.top_shape(_top(disc), UP)
    assert abs(m["fill"] - math.pi / 4) < 0.02
    assert m["circ_res"] < 0.02
    assert abs(m["radius"] - 0.03) < 0.002


def test_a_square_top_fills_its_rectangle_and_fits_no_circle():
    m = round_skirts.top_shape(_top(_grid() * 0.03), UP)
    assert m["fill"] > 0.98
    assert 0.09 < m["circ_res"] < 0.12
    assert abs(m["sides"][0] - 0.06) < 0.002 and abs(m["sides"][1] - 0.06) < 0.002


def test_a_half_seen_box_top_is_still_no_disc():
    """A box top of which an occluder hides a corner: its hull fills less than a rectangle,
    but its outline is still far from a circle (the measures the skirt would have read)."""
    g = _grid() * 0.05
    half = g[g[:, 0] + g[:, 1] <= 0.03]
    m = round_skirts.top_shape(_top(half), UP)
    assert m["fill"] < 0.95
    assert m["circ_res"] > 0.1


def _cylinder_facet(radius=0.03, half_angle_deg=50.0, centre=(0.0, 0.7), n=40):
    """Points of a can's side between -half_angle_deg and +half_angle_deg around its axis,
    facing a sensor at the origin along -y, 8 cm tall."""
    half = math.radians(half_angle_deg)
    a = np.linspace(-half, half, n)
    z = np.linspace(0.0, 0.08, n)
    aa, zz = np.meshgrid(a, z)
    x = centre[0] + radius * np.sin(aa)
    y = centre[1] - radius * np.cos(aa)
    return np.c_[x.ravel(), y.ravel(), zz.ravel()]


def test_a_can_facet_bends_with_the_cans_radius_towards_the_sensor():
    pts = _cylinder_facet()
    m = round_skirts.face_bend(pts, np.array([0.0, -1.0, 0.0]), UP)
    assert m["bend_radius"] < 0  # bulges towards the sensor
    assert abs(abs(m["bend_radius"]) - 0.03) < 0.008
    assert abs(m["width"] - 2 * 0.03 * math.sin(math.radians(50)) * 0.96) < 0.005


def test_a_flat_box_side_does_not_bend():
    x = np.linspace(-0.03, 0.03, 40)
    z = np.linspace(0.0, 0.08, 40)
    xx, zz = np.meshgrid(x, z)
    pts = np.c_[xx.ravel(), np.full(xx.size, 0.67), zz.ravel()]
    m = round_skirts.face_bend(pts, np.array([0.0, -1.0, 0.0]), UP)
    assert m["bend_radius"] is None or abs(m["bend_radius"]) > 10


def test_a_facet_is_a_chord_of_its_cap_and_a_box_side_spans_its_top():
    g = _grid() * 0.03
    cap = _top(g[np.hypot(g[:, 0], g[:, 1]) <= 0.03], height=0.08)
    can = round_skirts.edge_and_width(cap, _cylinder_facet(), np.array([0.0, -1.0, 0.0]), UP)
    # a +-50 degree facet is 0.77 of the diameter; both widths are 2nd-98th percentiles
    assert 0.7 < can["width_ratio"] < 0.9
    top = _top(g, height=0.08)
    x = np.linspace(-0.03, 0.03, 40)
    zz, xx = np.meshgrid(np.linspace(0.0, 0.08, 40), x)
    side = np.c_[xx.ravel(), np.full(xx.size, 0.67), zz.ravel()]
    box = round_skirts.edge_and_width(top, side, np.array([0.0, -1.0, 0.0]), UP)
    assert abs(box["width_ratio"] - 1.0) < 0.05
    assert abs(box["edge_bow_mm"]) < 0.5


def test_kind_groups_the_truths_the_collectors_write():
    assert round_skirts.kind("round:can") == "round"
    assert round_skirts.kind("box:milk carton") == "box"
    assert round_skirts.kind("touching box") == "box"
    assert round_skirts.kind("false") == "false"
    assert round_skirts.kind("object:mixed").startswith("mosd object")
