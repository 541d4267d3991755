"""A narrow box top tilted by the sensor's noise is still a skirt's top (tilt36).

``skirt/2`` takes a narrow top inclined at most ``skirt_top_tilt`` (10) degrees towards its
face (the rounded edge tilts its fit).  On hunt36's RealSense frames a product box's 5 cm top
strip 1 m away fitted at 11-13 degrees.  The allowance now grows by the tilt that
``skirt_top_noise`` (2) times the top's fit RMS across its width makes (at most
``skirt_top_tilt`` more), as the floor's rule allows a noisy narrow floor
(docs/objects.md, "A narrow top tilted by the sensor's noise").  Rendered analytic scenes: a
box 0.3 m wide, 6 cm deep, 0.3 m high, 1 m away, its top tilted towards its front.
"""

from __future__ import annotations

import math

import pytest
from scenes_analytic import Rect, floor, render

from planerel.features.planes import measure_planes
from planerel.features.relations import RelationParams, relate

TOP, FRONT = 1, 2


def _skirts(tilt: float, noise: float, k: float) -> tuple:
    a, h, y, depth = math.radians(tilt), 0.3, 1.0, 0.06
    low = h - depth / 2 * math.tan(a)        # the front's top edge, under the top's near edge
    top = Rect((0.0, y, h), (1, 0, 0), (0, math.cos(a), math.sin(a)), 0.15,
               depth / 2 / math.cos(a), 1)
    front = Rect((0.0, y - depth / 2, low / 2), (1, 0, 0), (0, 0, 1), 0.15, low / 2, 1)
    cloud, lab, _, _ = render([floor(), top, front], noise=noise, pitch=35, cam_height=0.9,
                              width=640, height=480)
    ps = measure_planes(cloud, lab)
    rel = relate(ps, cloud, RelationParams(skirt_top_noise=k))
    return ps.by_label(TOP), {(r.a, r.b) for r in rel if r.skirt}


@pytest.mark.parametrize("tilt", [12.0, 14.0])
def test_a_narrow_top_tilted_past_the_bound_on_a_noisy_cloud_is_a_skirts_top(tilt):
    top, skirts = _skirts(tilt, 0.003, 2.0)
    assert top.orientation == "inclined" and top.incline > 10.0
    assert skirts == {(TOP, FRONT)}
    # without the noise's allowance the bound is skirt_top_tilt's 10 degrees
    assert _skirts(tilt, 0.003, 0.0)[1] == set()


def test_a_noise_free_cloud_gets_no_allowance():
    # a fit with no residual: the bound stays 10 degrees
    top, skirts = _skirts(12.0, 0.0, 2.0)
    assert top.incline > 10.0 and skirts == set()
    assert _skirts(8.0, 0.0, 2.0)[1] == {(TOP, FRONT)}


def test_the_allowance_is_bounded():
    # at most skirt_top_tilt more: a top tilted 25 degrees is no narrow top at any noise
    assert _skirts(25.0, 0.003, 2.0)[1] == set()


def test_a_negative_setting_is_refused():
    from planerel.errors import InputError

    with pytest.raises(InputError):
        RelationParams(skirt_top_noise=-1.0)
