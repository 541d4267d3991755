"""benchmarks/top_ring.py: the ring around a product box's top seen from above (top53,
docs/objects.md "Boxes seen only by their top, packed side by side")."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from scenes_analytic import Rect, floor, render

from planerel.features.planes import measure_planes
from planerel.features.relations import RelationParams

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import top_ring  # noqa: E402

#: a camera 0.8 m over a board at 0.75 m, looking 80 degrees down
VIEW = {"pitch": 80.0, "cam_height": 1.55, "width": 640, "height": 480}
BOARD_Z = 0.75


def _board():
    return Rect((0.0, 0.15, BOARD_Z), (1, 0, 0), (0, 1, 0), 0.6, 0.45)


def _top(x, rise=0.08, sx=0.16, sy=0.10, obj=1):
    """A carton's top ``rise`` over the board, its sides left out (hidden)."""
    return Rect((x, 0.15, BOARD_Z + rise), (1, 0, 0), (0, 1, 0), sx / 2, sy / 2, obj)


def _shares(rects, label):
    cloud, lab, _, _ = render(rects, noise=0.001, **VIEW)
    ps = measure_planes(cloud, lab)
    t = ps.by_label(label)
    assert top_ring.top_like(t, ps.floor)
    return top_ring.ring_shares(ps, RelationParams(), cloud.xyz, t)


def test_a_carton_top_alone_on_a_board_drops_all_round():
    s = _shares([floor(), _board(), _top(0.0)], 2)
    assert s["drop"] > 0.8 and s["above"] == 0.0
    assert s["step"] == pytest.approx(0.08, abs=0.01)
    assert s["fill"] > 0.9
    assert top_ring.passes({**s})


def test_packed_tops_level_neighbours_are_left_out_higher_ones_are_above():
    # three cartons side by side, 2 mm apart.  Neighbours at the top's level are its "own
    # pieces" for the lying ring (within skirt_tilted and lying_rise of it), so they are left
    # out: the middle top reads as a lone one, the board seen through the seams
    level = [floor(), _board(), _top(-0.162, obj=1), _top(0.0, obj=2), _top(0.162, obj=3)]
    s = _shares(level, 3)
    assert s["level"] == 0.0 and s["drop"] > 0.8 and top_ring.passes(s)
    # neighbours 3 cm higher are not its pieces: the ring's sides toward them are above it
    # (its two short sides: 0.14 of the ring, under the default bound 0.15, so it passes)
    higher = [floor(), _board(), _top(-0.162, rise=0.11, obj=1), _top(0.0, obj=2),
              _top(0.162, rise=0.11, obj=3)]
    s = _shares(higher, 3)
    assert 0.1 < s["above"] < 0.2 and s["drop"] > 0.8
    assert top_ring.passes(s) and not top_ring.passes(s, above=0.1)
