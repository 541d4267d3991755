"""``incline/2`` and ``slope/2`` are written in whole degrees: a plane's angle to gravity is
known to about a degree (the estimated up, a small plane's fit), so the learner must not place a
cut-off among its decimals (docs/results.md, cut16: "a facing wall of incline at most 89.8"
left out the walls at 90.0)."""

from __future__ import annotations

import re

from scenes_analytic import floor, ramp, render

from planerel.features.facts import DIGITS_DEG, DIGITS_INCLINE, describe_scene, facts_text


def _facts(angle_a: float, angle_b: float) -> tuple[dict, str]:
    # floor (label 0), two rectangles rising from the floor at the given angles (labels 1, 2)
    rects = [floor()] + ramp(-0.7, 1.8, angle=angle_a, length=1.0, width=0.8, obj=1) \
        + ramp(0.7, 1.8, angle=angle_b, length=0.6, width=0.6, obj=2)
    cloud, lab, _, _ = render(rects, pitch=25)
    d = describe_scene(cloud, lab, scene_id="s0001", objects=[[1], [2]])
    return {p.label: p for p in d.planes}, facts_text([d])


def _values(text: str, name: str) -> dict[str, float]:
    return {m.group(1): float(m.group(2))
            for m in re.finditer(rf"^{name}\((\w+), ([-\d.]+)\)\.$", text, re.M)}


def test_inclines_and_slopes_are_whole_degrees_angles_keep_their_decimals():
    assert DIGITS_INCLINE == 0 and DIGITS_DEG == 2
    by, text = _facts(12.3, 89.7)
    # measured to well under a degree (noise-free render), written to the degree
    assert abs(by[1].incline - 12.3) < 0.05 and by[1].orientation == "inclined"
    assert abs(by[2].incline - 89.7) < 0.05 and by[2].orientation == "vertical"
    inc = _values(text, "incline")
    assert inc == {"s0001_p00": 0.0, "s0001_p01": 12.0, "s0001_p02": 90.0}
    assert _values(text, "slope") == {"s0001_p01": 12.0}
    # a wall leaning 0.3 degrees and an upright one are the same fact
    _, upright = _facts(12.3, 90.0)
    assert _values(upright, "incline") == inc
    # angle/2, between two planes, is not against gravity: its decimals stay
    angles = re.findall(r"^angle\(s0001_p00, s0001_p0([12]), ([-\d.]+)\)\.$", text, re.M)
    assert sorted(angles) == [("1", "12.3"), ("2", "89.7")]
