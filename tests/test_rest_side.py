"""``benchmarks/rest_side.py`` (grav58, docs/gravity.md "Room frames read upside down: the
clutter's side"): clutter touching a floor rests on it under the true up and hangs under the
opposite one; a bare ceiling carries nothing; a lamp under a ceiling hangs (scenes ray-cast in
code, tests/scenes_analytic.py)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from scenes_analytic import Rect, box, floor, render

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import rest_side  # noqa: E402


def _ceiling(z=2.6):
    return Rect((0, 3.0, z), (1, 0, 0), (0, -1, 0), 3.0, 3.0)


@pytest.mark.parametrize("outline", ["image", "hull"])
def test_box_rests_on_the_floor(outline):
    cloud, lab, up, _ = render([floor()] + box(0.0, 2.5, 0.4, 0.4, 0.4), pitch=35, width=320,
                               height=240, noise=0.001)
    cs = rest_side.clutter_sides(cloud, lab, np.array([up, -up]), outline=outline)
    assert cs[0, 0] > 0.005 and cs[0, 1] == 0.0
    np.testing.assert_allclose(cs[1], cs[0][::-1])  # turned over, the same clutter hangs


def test_bare_ceiling_and_a_lamp():
    bare, lab, up, _ = render([_ceiling()], pitch=-30, width=320, height=240)
    assert rest_side.clutter_sides(bare, lab, up[None]).tolist() == [[0.0, 0.0]]
    lamp = Rect((0.0, 3.0, 2.5), (1, 0, 0), (0, 0, 1), 0.15, 0.1, obj=1)  # hangs 0-0.2 m under it
    cloud, lab, up, _ = render([_ceiling(), lamp], pitch=-30, width=320, height=240)
    cs = rest_side.clutter_sides(cloud, lab, up[None])
    assert cs[0, 0] == 0.0 and cs[0, 1] > 0.0


def test_a_wall_is_no_support():
    cloud, lab, up, _ = render([floor()] + box(0.0, 2.5, 0.4, 0.4, 0.4), pitch=35, width=320,
                               height=240)
    side = np.array([1.0, 0.0, 0.0])  # an up in the floor's plane: no plane is horizontal
    side -= (side @ up) * up
    cs = rest_side.clutter_sides(cloud, lab, (side / np.linalg.norm(side))[None])
    assert cs.tolist() == [[0.0, 0.0]]
