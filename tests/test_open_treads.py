"""riser26: open-riser flights (floating treads, no risers).

The synthetic worlds' open-riser flights (``stairs_geometry(open_risers=True)``, the varied
world's ``open_share``, the demo training world's open part) and the proposal step that joins
an open flight's treads, which touch nothing (``ProposalParams.open_treads``,
:func:`planerel.features.open_treads.open_tread_pairs`).  Scenes are ray-cast
(tests/scenes_analytic.py) and segmented, described and proposed by the real stages.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from planerel.errors import InputError

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scenes_analytic import Rect, box, floor, render, wall  # noqa: E402

RISE, THICK, WIDTH = 0.18, 0.04, 0.9


# ---------------------------------------------------------------------------- geometry


def test_open_flight_geometry_has_slabs_and_no_risers():
    from planerel.synth.geometry import stairs_geometry

    g = stairs_geometry(4, RISE, 0.25, WIDTH, open_risers=True, thickness=THICK, sides="open")
    roles = [p.role for p in g.planes]
    assert "riser" not in roles and "back" not in roles
    assert roles[:12] == ["tread", "nosing", "bottom"] * 4
    assert roles[12:] == ["side", "side"]
    # tread tops at (i + 1) * rise, undersides thickness below, the front edge between them
    by_plane = {}
    for poly in g.polygons:
        by_plane.setdefault(poly.plane, []).append(np.asarray(poly.vertices, float))
    for i in range(4):
        z_top = by_plane[3 * i][0][:, 2]
        z_edge = by_plane[3 * i + 1][0][:, 2]
        z_under = by_plane[3 * i + 2][0][:, 2]
        assert np.allclose(z_top, (i + 1) * RISE)
        assert np.allclose(z_under, (i + 1) * RISE - THICK)
        assert np.isclose(z_edge.min(), (i + 1) * RISE - THICK) and np.isclose(z_edge.max(), (i + 1) * RISE)
        x_top = by_plane[3 * i][0][:, 0]
        assert np.isclose(np.ptp(x_top), 0.25)           # one run deep
        assert np.allclose(by_plane[3 * i + 1][0][:, 0], x_top.min())  # the edge at its front
    # the open sides: one end face per slab on each side
    assert len(by_plane[12]) == len(by_plane[13]) == 4


def test_open_flight_closed_sides_are_stringers_from_the_floor():
    from planerel.synth.geometry import stairs_geometry

    g = stairs_geometry(5, RISE, 0.25, WIDTH, open_risers=True, thickness=THICK,
                        sides="closed", rail=0.3)
    sides = [np.asarray(p.vertices, float) for p in g.polygons
             if g.planes[p.plane].role == "side"]
    assert len(sides) == 2
    for s in sides:
        assert np.isclose(s[:, 2].min(), 0.0)                  # it stands on the floor
        assert np.isclose(s[:, 2].max(), 5 * RISE + 0.3)        # rail above the top nosing


def test_open_flight_thickness_must_be_under_the_rise():
    from planerel.synth.geometry import stairs_geometry

    with pytest.raises(InputError, match="thickness must be smaller than the rise"):
        stairs_geometry(3, RISE, 0.25, WIDTH, open_risers=True, thickness=RISE)
    with pytest.raises(InputError, match="tread thickness"):
        stairs_geometry(3, RISE, 0.25, WIDTH, open_risers=True, thickness=0.0)


def test_varied_world_open_share():
    from planerel.synth.training_world import KINECT_OPEN
    from planerel.synth.world import WorldRange, generate_world_scene

    with pytest.raises(InputError, match="open-riser share"):
        WorldRange(open_share=1.5)
    with pytest.raises(InputError, match="open thickness"):
        WorldRange(open_thickness=(0.03, 0.2))
    scene = generate_world_scene("stairs", 5, (640, 480), 4, ranges=WorldRange(**KINECT_OPEN))
    prim = scene.objects[1]
    assert prim["class"] == "stairs" and prim["params"]["open_risers"] is True
    assert 0.03 <= prim["params"]["thickness"] <= 0.06
    # a world without open flights draws none (and its flights keep their parameters)
    solid = generate_world_scene("stairs", 5, (640, 480), 4)
    assert "open_risers" not in solid.objects[1]["params"]


def test_training_world_open_part(tmp_path):
    import json

    from planerel.synth.training_world import generate_training_world

    out = generate_training_world(tmp_path / "w", paper=(0, 0, 0), room=(0, 0, 0), open_=2,
                                  size=(320, 240), subsample=4)
    info = json.loads((out / "dataset.json").read_text())
    assert info["counts"]["open"] == 2 and info["world"].endswith("+open")
    rows = (out / "manifest.csv").read_text().splitlines()[1:]
    assert len(rows) == 2 and all(",stairs" in r for r in rows)
    with pytest.raises(InputError, match="open scene count"):
        generate_training_world(tmp_path / "x", open_=-1)


# ---------------------------------------------------------------------------- proposals


def _slab(cy, z, run, obj=1, cx=0.0, width=WIDTH, thick=THICK):
    """An open tread: its top at height z, from y = cy to cy + run, and its front edge."""
    return [Rect((cx, cy + run / 2, z), (1, 0, 0), (0, 1, 0), width / 2, run / 2, obj),
            Rect((cx, cy, z - thick / 2), (1, 0, 0), (0, 0, 1), width / 2, thick / 2, obj)]


def _flight(n, run, y0=2.0, rise=RISE, obj=1, depth=0.25):
    """``n`` treads ``depth`` deep, each ``run`` beyond and ``rise`` above the last."""
    return [r for k in range(n) for r in _slab(y0 + k * run, (k + 1) * rise, depth, obj)]


def _describe(rects, open_treads=True, others=True, **view):
    from planerel.features.facts import describe_scene
    from planerel.features.relations import ProposalParams
    from planerel.segment import segment

    kw = dict(pitch=25, cam_height=1.7, width=320, height=240)
    kw.update(view)
    cloud, lab, up, objs = render(rects, **kw)
    desc = describe_scene(cloud, segment(cloud).labels, scene_id="s", up=up,
                          proposal_params=ProposalParams(open_treads=open_treads, step_chains=others,
                                                         stacked_boards=others))
    truth = np.where(lab >= 0, np.asarray(objs)[np.maximum(lab, 0)], -1)
    return desc, truth


def _treads(desc, truth, obj=1):
    """Labels of the segmented horizontal or inclined planes lying mostly on object ``obj``."""
    out = []
    for p in desc.planes:
        m = desc.planes.labels == p.label
        if p.orientation != "vertical" and (truth[m] == obj).mean() > 0.8:
            out.append(p.label)
    return out


def _holding(desc, labels):
    return {i for i, o in enumerate(desc.objects) for k in labels if k in o.planes}


@pytest.mark.parametrize("run", [0.10, 0.25])
def test_an_open_flight_is_one_proposal_by_its_treads_alone(run):
    """Five floating treads 0.25 m deep, 0.18 m apart, each ``run`` beyond the last (0.10: a
    steep open flight, as the real Kinect room's), no riser: no two treads share an edge.
    With the step chains and the shelf boards off (on the real frames they see no row: the
    treads' strips are fitted 25-55 degrees off horizontal, docs/objects.md "Open-riser
    flights"), ``open_treads`` alone makes the treads one proposal; without it each tread is
    one."""
    rects = [floor(), wall()] + _flight(5, run)
    desc, truth = _describe(rects, others=False)
    treads = _treads(desc, truth)
    assert len(treads) == 5
    assert len(_holding(desc, treads)) == 1
    off, truth_off = _describe(rects, open_treads=False, others=False)
    assert len(_holding(off, _treads(off, truth_off))) == 5


def test_open_tread_pairs_need_three_levels_and_shallow_slabs():
    """Two treads are one step, no row: not joined.  A slab one metre deep (a landing, a table
    top) is no tread, and three boxes' tops at regular heights side by side (apart across the
    flight) are no row either."""
    from planerel.features.open_treads import open_tread_pairs

    desc, truth = _describe([floor(), wall()] + _flight(2, 0.10))
    assert open_tread_pairs(desc.planes, [p.label for p in desc.planes
                                          if p.label not in desc.support]) == set()
    # two treads and a deep slab one rise above them
    rects = [floor(), wall()] + _flight(2, 0.10) + _slab(2.2, 3 * RISE, 1.0, obj=2)
    desc, truth = _describe(rects)
    pairs = open_tread_pairs(desc.planes, [p.label for p in desc.planes if p.label not in desc.support])
    assert not any(k in _treads(desc, truth, 2) for pr in pairs for k in pr)
    # three boxes in a row across the view, each one rise higher: tops apart across
    rects = [floor(), wall()] + box(-0.8, 2.2, 0.4, 0.4, RISE, obj=1) + box(
        0.0, 2.2, 0.4, 0.4, 2 * RISE, obj=2) + box(0.8, 2.2, 0.4, 0.4, 3 * RISE, obj=3)
    desc, truth = _describe(rects)
    assert open_tread_pairs(desc.planes, [p.label for p in desc.planes
                                          if p.label not in desc.support]) == set()


def test_slab_level_is_the_top_of_the_hull():
    from planerel.features.open_treads import slab_level

    desc, truth = _describe([floor(), wall()] + _flight(3, 0.25))
    levels = sorted(round(slab_level(desc.planes.by_label(k) if hasattr(desc.planes, "by_label")
                                     else next(p for p in desc.planes if p.label == k),
                                     desc.planes.up), 2) for k in _treads(desc, truth))
    assert levels == pytest.approx([RISE, 2 * RISE, 3 * RISE], abs=0.02)


def test_an_open_row_is_a_flight_for_the_level_gate():
    """``flight_faces`` (the level gate's exception) takes an open row too: the steep flight's
    treads lie 0.10 m beyond each other, under the step chains' least run, so only the open
    treads make them a flight's row."""
    from planerel.features.relations import ProposalParams, flight_faces

    desc, truth = _describe([floor(), wall()] + _flight(5, 0.10))
    treads = _treads(desc, truth)
    assert flight_faces(desc.planes, treads)
    assert not flight_faces(desc.planes, treads, ProposalParams(open_treads=False))


@pytest.mark.parametrize("lift,row", [(0.05, False), (0.18, True)])
def test_a_slab_at_floor_level_is_no_first_tread(lift, row):
    """Three slabs 0.18 m apart whose lowest lies ``lift`` above the floor: at 5 cm it is a
    piece of the floor (a patch beside a carton pile made a row with two carton tops on the
    real pallet_b frame), no first step, and two slabs make no row; at 18 cm, a row."""
    from planerel.features.open_treads import open_tread_pairs

    rects = [floor(), wall()] + [r for k in range(3)
                                 for r in _slab(2.0 + 0.10 * k, lift + k * RISE, 0.25)]
    desc, truth = _describe(rects, others=False)
    pairs = open_tread_pairs(desc.planes, [p.label for p in desc.planes if p.label not in desc.support])
    assert bool(pairs) is row
