"""facing(P, Q): two parallel vertical walls of one object, not adjacent, tops level,
overlapping along the walls -- the near and far side of an open box seen without its bottom
(docs/results.md, open16); a staircase's risers, walls of other heights, posts and walls side by
side are not.  The optional task aleph/modes_facing.pl takes it."""

from __future__ import annotations

import re
import shutil
import subprocess

import numpy as np
import pytest
from scenes_analytic import Rect, floor, render, stairs

from planerel.errors import InputError
from planerel.features.facts import describe_scene, facts_text
from planerel.features.planes import measure_planes
from planerel.features.relations import RelationParams, relate
from planerel.features.solid import FaceProfile, is_facing

SWIPL = shutil.which("swipl") or "/usr/bin/swipl"
needs_swipl = pytest.mark.skipif(shutil.which("swipl") is None, reason="SWI-Prolog not installed")


def _wall(cx, cy, half_w, z1, obj=1, along_x=True):
    e1 = (1, 0, 0) if along_x else (0, 1, 0)
    return Rect((cx, cy, z1 / 2), e1, (0, 0, 1), half_w, z1 / 2, obj)


def _open_box(cx=0.0, cy=2.5, sx=0.8, sy=0.5, near=0.3, far=0.3):
    """The near and far side of a box without top or bottom, 0.8 m long, 0.5 m deep (labels 1
    and 2 after the floor); the far side's foot is hidden behind the near side."""
    return [_wall(cx, cy - sy / 2, sx / 2, near), _wall(cx, cy + sy / 2, sx / 2, far)]


def _relate(rects, **kw):
    cloud, lab, _, _ = render(rects, noise=0.0012, **kw)
    ps = measure_planes(cloud, lab)
    return cloud, lab, ps, relate(ps, cloud)


def test_the_two_sides_of_an_open_box_face_each_other():
    _, _, ps, rel = _relate([floor()] + _open_box(), pitch=30)
    assert {1, 2} <= {p.label for p in ps}
    r = rel.get(1, 2)
    assert r.parallel and not r.adjacent
    assert r.facing and rel.get(2, 1).facing
    assert not any(x.facing for x in rel if 0 in (x.a, x.b))


def test_walls_of_other_heights_risers_and_posts_do_not_face():
    # the far side 15 cm higher than the near one: tops not level
    _, _, _, rel = _relate([floor()] + _open_box(far=0.45), pitch=30)
    assert rel.get(1, 2).parallel and not rel.get(1, 2).facing
    # a staircase: parallel risers one rise apart
    _, _, ps, rel = _relate([floor()] + stairs(0.0, 2.2, n=3), pitch=30)
    risers = [p.label for p in ps if p.orientation == "vertical"]
    assert len(risers) >= 2
    assert not any(r.facing for r in rel)
    # two posts 4 cm wide, level tops: narrower than a wall
    posts = [_wall(0.0, 2.25, 0.02, 0.4), _wall(0.0, 2.75, 0.02, 0.4)]
    _, _, ps, rel = _relate([floor()] + posts, pitch=30)
    assert {1, 2} <= {p.label for p in ps}
    assert not rel.get(1, 2).facing
    # two walls side by side, one behind the other's end: no overlap along the walls
    side = [_wall(-0.5, 2.25, 0.3, 0.3), _wall(0.5, 2.75, 0.3, 0.3)]
    _, _, ps, rel = _relate([floor()] + side, pitch=30)
    assert {1, 2} <= {p.label for p in ps}
    assert rel.get(1, 2).parallel and not rel.get(1, 2).facing


def _strip(cx, cy, half_w, z0, z1, obj=1):
    """A wall's part from ``z0`` to ``z1`` (the rest hidden or out of view)."""
    return Rect((cx, cy, (z0 + z1) / 2), (1, 0, 0), (0, 0, 1), half_w, (z1 - z0) / 2, obj)


def test_a_narrow_far_wall_faces_the_near_one_when_its_top_is_level():
    # an open box whose far side shows only a strip 7 cm high above the near side (held16b:
    # the far wall's inner face seen over the near one): the strip's top is the wall's top
    near = _wall(0.0, 2.25, 0.4, 0.3)
    level = _strip(0.0, 2.75, 0.4, 0.23, 0.30)
    cloud, _, ps, rel = _relate([floor(), near, level], pitch=30)
    w = {p.label: p.width for p in ps}
    assert w[2] < RelationParams().corner_width <= w[1]     # narrower than a corner's wall
    assert rel.get(1, 2).facing and rel.get(2, 1).facing
    # the narrow wall asked to be as wide as a corner's (the rule before held16b): not facing
    old = relate(ps, cloud, RelationParams(facing_width=0.08))
    assert old.get(1, 2).parallel and not old.get(1, 2).facing
    # the next riser's foot seen as a strip: its top 7 cm above the lower riser's top, within
    # corner_tol but not within facing_narrow_tol (a strip's top is level or not at all)
    cloud, _, ps, rel = _relate([floor(), near, _strip(0.0, 2.75, 0.4, 0.30, 0.37)], pitch=30)
    assert rel.get(1, 2).parallel and not rel.get(1, 2).facing
    assert relate(ps, cloud, RelationParams(facing_narrow_tol=0.08)).get(1, 2).facing
    with pytest.raises(InputError, match="facing_width"):
        RelationParams(facing_width=-0.01)
    with pytest.raises(InputError, match="facing_narrow_tol"):
        RelationParams(facing_narrow_tol=-0.01)


def test_is_facing_on_profiles():
    along = np.array([1.0, 0.0, 0.0])

    class P:
        width = 0.2

    a = FaceProfile(0.30, 0.0, along, -0.4, 0.4)
    # the other wall seen from its far side: its along direction reversed, lo / hi negated
    b = FaceProfile(0.33, 0.1, -along, -0.3, 0.5)
    assert is_facing(P, P, a, b)
    assert not is_facing(P, P, a, b._replace(top=0.40))                  # 10 cm higher
    assert not is_facing(P, P, a, b._replace(lo=0.35, hi=1.0))           # overlap 0.05 of 0.65
    assert is_facing(P, P, a, b._replace(lo=-0.1, hi=0.6), overlap_min=0.5)  # -0.6..0.1: 0.5 of 0.7

    class Post:
        width = 0.04

    assert not is_facing(Post, P, a, b)
    # a narrow wall faces a wide one when narrow_min allows it and its top is within
    # narrow_tol (both walls narrow: never)
    assert is_facing(Post, P, a, b._replace(top=0.32), narrow_min=0.04, narrow_tol=0.03)
    assert not is_facing(Post, P, a, b._replace(top=0.345), narrow_min=0.04, narrow_tol=0.03)
    assert is_facing(P, P, a, b._replace(top=0.345), narrow_min=0.04, narrow_tol=0.03)
    assert not is_facing(Post, Post, a, b, narrow_min=0.04, narrow_tol=0.03)
    nan = float("nan")
    assert not is_facing(P, P, a, FaceProfile(nan, nan, along, nan, nan))
    with pytest.raises(InputError, match="facing_overlap"):
        RelationParams(facing_overlap=1.5)
    with pytest.raises(InputError, match="facing_overlap"):
        RelationParams(facing_overlap=-0.1)


@needs_swipl
def test_facing_facts_in_prolog(tmp_path):
    cloud, lab, _, _ = render([floor()] + _open_box(), noise=0.0012, pitch=30)
    d = describe_scene(cloud, lab, scene_id="s0003", objects=[[1, 2]])
    text = facts_text([d])
    assert re.findall(r"^facing\((\w+), ?(\w+)\)", text, re.M) == [
        ("s0003_p01", "s0003_p02"), ("s0003_p02", "s0003_p01")]
    path = tmp_path / "f.pl"
    path.write_text(text)
    goal = ("findall(P-Q, (facing(P, Q), parallel(P, Q), \\+ adjacent(P, Q)), L), writeln(L), "
            "findall(P, (has_plane(O, P), facing(P, _)), Ps), length(Ps, N), writeln(N)")
    proc = subprocess.run([SWIPL, "-q", "-g", goal, "-t", "halt", str(path)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    out = proc.stdout.split()
    assert out == ["[s0003_p01-s0003_p02,s0003_p02-s0003_p01]", "2"]


def test_facing_task_is_the_slope_task_and_one_line():
    from planerel.ilp.aleph_export import task_directives

    def modes(name):  # the task's directive lines, its parts expanded (planerel_include)
        return task_directives(name)

    slope, facing, default = modes("modes_slope.pl"), modes("modes_facing.pl"), modes("modes_relational.pl")
    assert [ln for ln in facing if ln not in slope] == [":- modeb(*, facing(+plane, -plane))."]
    assert [ln for ln in facing if ln in slope] == slope
    # not in the default task nor the slope task (openbox16: the demo's world learns it in
    # place of its corner rule and loses boxes of the judge set)
    assert not any("facing" in ln for ln in default + slope)


def test_varied_task_is_the_facing_task_without_incline_thresholds():
    """aleph/modes_varied.pl (the task of --recipe varied): every line of the facing task but
    the two thresholds on incline/2 (docs/results.md, real16b: a bound inside an orientation
    class splits a generated plane's fit noise and rejects real box tops)."""
    from planerel.ilp.aleph_export import task_directives

    def modes(name):  # the task's directive lines, its parts expanded (planerel_include)
        return task_directives(name)

    facing, varied = modes("modes_facing.pl"), modes("modes_varied.pl")
    assert [ln for ln in facing if ln not in varied] == [
        ":- modeb(1, gteq(+incline, #incline)).", ":- modeb(1, lteq(+incline, #incline))."]
    assert [ln for ln in varied if ln not in facing] == [":- modeb(*, over(+plane, -plane))."]
    assert [ln for ln in facing if ln in varied] == [ln for ln in varied if ln in facing]
    # over/2 right after facing/2; nowhere else (the demo's task and the facing task were
    # not measured with it)
    assert varied.index(":- modeb(*, over(+plane, -plane)).") == \
        varied.index(":- modeb(*, facing(+plane, -plane)).") + 1
    for name in ("modes_relational.pl", "modes_slope.pl", "modes_facing.pl"):
        assert not any("over(" in ln for ln in modes(name)), name
    # slope/2 (an inclined plane's incline) keeps its thresholds
    assert ":- modeb(1, lteq(+slope, #slope))." in varied
