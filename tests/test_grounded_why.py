"""``benchmarks/grounded_why.py`` (ground75): what lies under the foot of a face the grounded
test fails, on ray-cast scenes (tests/scenes_analytic.py, the camera 0.4 m over the floor
looking level) whose floor no plane took, or that the sensor did not measure."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scenes_analytic import box, floor, render

from planerel.features.facts import describe_scene
from planerel.features.relations import RelationParams
from planerel.io.cloud import Cloud

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import grounded_why  # noqa: E402

VIEW = {"pitch": 0.0, "cam_height": 0.4, "width": 640, "height": 480}


def _scene(measured=True):
    """A carton 1.4 m ahead (its front label 2) over a floor no plane took; with ``measured``
    False the floor returns no depth at all."""
    cloud, lab, _, _ = render([floor()] + box(0.0, 1.6, 0.5, 0.4, 0.45), noise=0.0012, **VIEW)
    lab = lab.copy()
    xyz = np.array(cloud.xyz, float)
    if not measured:
        xyz[lab == 0] = np.nan
    lab[lab == 0] = -1
    return Cloud(xyz, cloud.intrinsics, cloud.up, "analytic"), lab


def _kind(measured, **params):
    cloud, lab = _scene(measured)
    desc = describe_scene(cloud, lab, relation_params=RelationParams(tall_speckle_floor=0.0,
                                                                     **params))
    face = desc.planes.by_label(2)
    return grounded_why.kind_of(desc, cloud, face)


def test_a_face_on_ground_no_plane_took_is_sorted_by_its_reach():
    kind, reach = _kind(True)
    # the floor is in view from 1.02 m on, the face 1.4 m ahead
    assert kind == "grounded" and 0.45 < reach < 0.6
    kind, reach = _kind(True, tall_level_ground=0.0)
    assert kind == "level ground no plane took, reaching 0.45 m (no floor plane)"
    assert 0.45 < reach < 0.6


def test_a_face_over_nothing_measured_is_sorted_so():
    kind, reach = _kind(False)
    assert kind == "nothing measured under the foot" and np.isnan(reach)


def test_the_aggregate_table_names_no_frame():
    rows = [{"set": "s/a", "frame": "f1", "kind": "k1", "reach": 0.5},
            {"set": "s/a", "frame": "f2", "kind": "k1", "reach": None},
            {"set": "s/b", "frame": "f3", "kind": "k2", "reach": 0.1}]
    out = grounded_why.table(rows)
    assert "| k1 | 2 | 0.50 |" in out and "| k2 | 1 | 0.10 |" in out
    assert "f1" not in out and "s/a" not in out
