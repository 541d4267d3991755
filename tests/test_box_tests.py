"""``benchmarks/box_tests.py`` (rule50, docs/objects.md "Real boxes no box rule proves, test by
test"): ``tall_face/1``'s tests one by one must say what :func:`tall_faces` says, on scenes
ray-cast in code (tests/scenes_analytic.py)."""

from __future__ import annotations

import sys
from pathlib import Path

from scenes_analytic import Rect, box, floor, render, wall

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import box_tests  # noqa: E402

from planerel.features.planes import measure_planes  # noqa: E402
from planerel.features.relations import RelationParams, relate, tall_faces  # noqa: E402


def _verdicts(rects, params=None, **view):
    """``{label: (tall_faces says, every test passes, failed tests, width)}`` of the vertical
    planes."""
    cloud, lab, _, _ = render(rects, noise=0.0012, width=320, height=240, **view)
    ps = measure_planes(cloud, lab)
    rel = relate(ps, cloud, params)
    tall = tall_faces(ps, rel, cloud)
    out = {}
    for q in ps:
        if q.orientation == "vertical":
            tests = box_tests.tall_face_tests(ps, rel, cloud, q.label)
            out[q.label] = (q.label in tall, all(ok for _, ok, _ in tests),
                            [n for n, ok, _ in tests if not ok], q.width)
    return out


def _agree(v):
    assert v and all(a == b for a, b, *_ in v.values()), v


def test_a_box_face_on_the_floor_passes_every_test():
    # a low camera (0.2 m) before a 0.5 m high box 1.5 m away: its front's top over the eye
    v = _verdicts([floor(), *box(0.0, 1.5, 0.5, 0.4, 0.5)], pitch=0.0, cam_height=0.2)
    _agree(v)
    assert v[2][0] and v[2][2] == []


def test_with_no_floor_only_grounded_fails():
    v = _verdicts(box(0.0, 1.5, 0.5, 0.4, 0.5), pitch=0.0, cam_height=0.2)
    _agree(v)
    assert not v[1][0] and v[1][2] == ["grounded"]  # the front (label = rect index)


def test_a_narrow_post_fails_its_shape_and_a_box_seen_from_above_its_top():
    post = Rect((0.6, 1.5, 0.4), (1, 0, 0), (0, 0, 1), 0.025, 0.4, 3)
    rects = [floor(), *box(-0.3, 1.8, 0.5, 0.4, 0.3), post, wall(y=4.0)]
    v = _verdicts(rects, pitch=20.0, cam_height=1.2)
    _agree(v)
    assert "shape" in v[rects.index(post)][2]
    front = v[2]
    assert not front[0] and "top hidden or capped" in front[2]


def test_the_tests_follow_the_settings():
    # (tall_narrow_width 0: a flat face narrower than corner_width passes otherwise, face52)
    off = RelationParams(standing_foot=0.05, corner_width=0.6, tall_narrow_width=0.0)
    v = _verdicts([floor(), *box(0.0, 1.5, 0.5, 0.4, 0.5)], off, pitch=0.0, cam_height=0.2)
    _agree(v)
    assert "shape" in v[2][2]

