"""Planes not seen whole (cut by the image border or partly hidden): their sizes are lower
bounds, so ``seen_length`` / ``seen_width`` are written only for planes seen whole."""

from __future__ import annotations

import shutil
import subprocess

import numpy as np
from scenes_analytic import Rect, box, floor, render

from planerel.features.facts import describe_scene, facts_text, truncated_planes

SWIPL = shutil.which("swipl") or "/usr/bin/swipl"


def _panels(pitch=0.0):
    # label 0: a 1 m panel 3 m ahead, in view; label 1: a nearer 0.4 m panel hiding its lower
    # left part; label 2: a panel running out of the image on the right
    back = Rect((0.0, 3.0, 1.2), (1, 0, 0), (0, 0, 1), 0.5, 0.5, 1)
    front = Rect((-0.3, 2.0, 1.0), (1, 0, 0), (0, 0, 1), 0.2, 0.2, 2)
    side = Rect((3.0, 3.0, 1.2), (1, 0, 0), (0, 0, 1), 1.5, 0.3, 3)
    return render([back, front, side], pitch=pitch, cam_height=1.2)


def test_hidden_and_border_planes_are_cut_whole_ones_not():
    cloud, lab, _, _ = _panels()
    assert set(np.unique(lab)) == {-1, 0, 1, 2}
    assert truncated_planes(lab, cloud.xyz) == frozenset({0, 2})
    # nothing hides the back panel once the front one is gone
    lab2 = lab.copy()
    xyz = np.array(cloud.xyz)
    assert truncated_planes(np.where(lab2 == 1, -1, lab2), np.where((lab2 == 1)[..., None], np.nan,
                                                                     xyz)) == frozenset({2})
    # a nearer point of no plane hides as much as a plane does
    assert 0 in truncated_planes(np.where(lab2 == 1, -1, lab2), xyz)
    # the share is a threshold on the hidden outline pixels
    assert truncated_planes(lab, cloud.xyz, share=1.0) == frozenset({2})


def test_a_box_in_view_is_whole_the_floor_is_cut():
    cloud, lab, _, _ = render([floor()] + box(0.0, 2.5, 0.5, 0.5, 0.4), pitch=25)
    cut = truncated_planes(lab, cloud.xyz)
    # the floor reaches the image border; the box's faces meet at shared (convex) edges
    assert 0 in cut
    seen = {int(k) for k in np.unique(lab) if k >= 0}
    assert seen - {0} and not (seen - {0}) & cut


def test_empty_and_unlabelled_images():
    assert truncated_planes(np.zeros((0, 0), int), np.zeros((0, 0, 3))) == frozenset()
    assert truncated_planes(np.full((4, 5), -1), np.ones((4, 5, 3))) == frozenset()


def test_seen_sizes_only_for_planes_seen_whole(tmp_path):
    cloud, lab, _, _ = _panels()
    d = describe_scene(cloud, lab, scene_id="s0003", objects=[[0, 1], [2]])
    assert d.truncated == frozenset({0, 2})
    text = facts_text([d])
    for p in ("s0003_p00", "s0003_p01", "s0003_p02"):
        assert f"plane_width({p}," in text and f"plane_length({p}," in text
    assert "seen_width(s0003_p01," in text and "seen_length(s0003_p01," in text
    for p in ("s0003_p00", "s0003_p02"):
        assert f"seen_width({p}," not in text and f"seen_length({p}," not in text
    # in Prolog: a seen size holds for the whole panel only, and equals its measured size
    path = tmp_path / "f.pl"
    path.write_text(text)
    goal = ("findall(P, (has_plane(_, P), seen_width(P, _)), L), writeln(L), "
            "aggregate_all(count, seen_length(_, _), N), writeln(N), "
            "aggregate_all(count, plane_length(_, _), M), writeln(M), "
            "seen_width(s0003_p01, W), plane_width(s0003_p01, W), writeln(same)")
    proc = subprocess.run([SWIPL, "-q", "-g", goal, "-t", "halt", str(path)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["[s0003_p01]", "1", "3", "same"]


def test_default_task_bounds_sizes_in_the_sound_direction():
    from importlib.resources import files

    task = files("planerel.aleph").joinpath("modes_relational.pl").read_text()
    modes = {ln.strip() for ln in task.splitlines() if ln.startswith(":- modeb(")}
    # a size in view is a lower bound: "at least" on it, "at most" only on a plane seen whole
    assert ":- modeb(1, gteq(+pwidth, #pwidth))." in modes
    assert ":- modeb(1, gteq(+plength, #plength))." in modes
    assert not any("lteq(+pwidth" in m or "lteq(+plength" in m for m in modes)
    assert ":- modeb(1, lteq(+swidth, #swidth))." in modes
    assert ":- modeb(1, lteq(+slength, #slength))." in modes
    assert ":- modeb(1, seen_width(+plane, -swidth))." in modes
