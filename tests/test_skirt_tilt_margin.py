"""benchmarks/skirt_tilt_margin.py (tilt45): the (inclined top, face) pairs whose ``skirt``
answer differs between narrow-top allowances are recorded, with the allowance of each, and the
relations themselves are those of the params ``relate`` was given.  Rendered analytic scenes
(as tests/test_top_tilt_noise.py): a box 0.3 m wide, 6 cm deep, 0.3 m high, 1 m away, its top
tilted towards its front, on a noise-free cloud (the noise's allowance is then none)."""

from __future__ import annotations

import math
import sys
from pathlib import Path

from scenes_analytic import Rect, floor, render

from planerel.features.planes import measure_planes
from planerel.features.relations import RelationParams, relate

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import skirt_tilt_margin as stm  # noqa: E402

TOP, FRONT = 1, 2


def _scene(tilt: float):
    a, h, y, depth = math.radians(tilt), 0.3, 1.0, 0.06
    low = h - depth / 2 * math.tan(a)
    top = Rect((0.0, y, h), (1, 0, 0), (0, math.cos(a), math.sin(a)), 0.15,
               depth / 2 / math.cos(a), 1)
    front = Rect((0.0, y - depth / 2, low / 2), (1, 0, 0), (0, 0, 1), 0.15, low / 2, 1)
    cloud, lab, _, _ = render([floor(), top, front], noise=0.0, pitch=35, cam_height=0.9,
                              width=640, height=480)
    return cloud, measure_planes(cloud, lab)


def _recorded(tilt: float, variants: str):
    cloud, ps = _scene(tilt)
    with stm.Recorder(stm._variants(variants)) as rec:
        rel = relate(ps, cloud, RelationParams())
    return rel, {(r["top"], r["face"]): r for r in rec.take()}


def test_a_top_past_the_bound_is_recorded_with_each_variants_answer():
    rel, rows = _recorded(15.0, "10:2,20:2,20:0")
    row = rows[(TOP, FRONT)]
    assert row["skirt"] == [".", "S", "S"]
    assert 14.0 < row["incline"] < 16.0 and row["cam"] > 0.9
    # relate itself ran with the widest allowance (every candidate asked)
    assert any(r.a == TOP and r.b == FRONT and r.skirt for r in rel)


def test_a_pair_every_variant_answers_alike_is_not_recorded():
    _, rows = _recorded(5.0, "10:2,20:2")
    assert rows == {}


def test_the_patch_is_undone():
    from planerel.features import relations

    before = relations._Solid.skirt, relations._Solid.__init__
    with stm.Recorder(stm._variants("10:2,15:2")):
        assert relations._Solid.skirt is not before[0]
    assert (relations._Solid.skirt, relations._Solid.__init__) == before
