"""A face cut by the image's top edge when the depth image starts with a blank margin (margin36).

A RealSense's depth registered to its colour camera leaves the first rows blank (two on hunt33's
UnseenObjectClustering frames and UOIS's).  A box's front cut there by the image's top edge has
its top out of view as much as one cut at row 0, and ``tall_face/1`` takes it so: the top-row
test counts from the first row the sensor measures (:func:`planerel.features.tall_face._blank_top_rows`).
Rows that fill in gradually are the scene out of range, not a margin.  Rendered analytic scenes:
a camera 1.2 m up looking 60 degrees down at a 0.6 x 0.4 x 0.6 m box 1.1 m away, its front cut
by the image's top edge, its top out of view (docs/objects.md, "A blank margin at the image's top").
"""

from __future__ import annotations

import numpy as np
import pytest
from scenes_analytic import box, floor, render

from planerel.features.planes import measure_planes
from planerel.features.relations import _blank_top_rows, relate, tall_faces
from planerel.io.cloud import Cloud

VIEW = {"pitch": 60.0, "cam_height": 1.2, "width": 640, "height": 480}
FRONT = 2  # floor 0, top 1, front 2 (box()'s order)


@pytest.fixture(scope="module")
def scene():
    cloud, lab, _, _ = render([floor()] + box(0.0, 1.1, 0.6, 0.4, 0.6), noise=0.0012, **VIEW)
    rows = np.flatnonzero((lab == FRONT).any(axis=1))
    assert rows[0] == 0 and not (lab == 1).any()  # the front reaches row 0, the top unseen
    return cloud, lab


def _blanked(scene, blank: int, ragged: int | None = None):
    """The scene with its first ``blank`` rows unmeasured, and row ``ragged`` (if given)
    measured at every fifth pixel only."""
    cloud, lab = scene
    xyz, lab = np.array(cloud.xyz, float), lab.copy()
    xyz[:blank], lab[:blank] = np.nan, -1
    if ragged is not None:
        drop = np.ones(xyz.shape[1], bool)
        drop[::5] = False
        xyz[ragged, drop], lab[ragged, drop] = np.nan, -1
    return Cloud(xyz, cloud.intrinsics, cloud.up, "analytic"), lab


def _tall(cloud, lab):
    ps = measure_planes(cloud, lab)
    return tall_faces(ps, relate(ps, cloud), cloud)


@pytest.mark.parametrize("blank", [0, 2, 3, 6])
def test_a_face_cut_at_a_blank_margin_is_cut_by_the_border(scene, blank):
    cloud, lab = _blanked(scene, blank)
    assert _blank_top_rows(cloud.xyz) == blank
    assert _tall(cloud, lab) == {FRONT}


def test_rows_that_fill_in_gradually_are_no_margin(scene):
    # three blank rows, then a row measured at a fifth of its pixels: the scene going out of
    # range, not a registration margin; the face starts at row 3, its top counts as in view
    cloud, lab = _blanked(scene, 3, ragged=3)
    assert _blank_top_rows(cloud.xyz) == 0
    assert _tall(cloud, lab) == frozenset()


def test_a_margin_deeper_than_the_bound_is_none(scene):
    from planerel.features.relations import BLANK_MARGIN_MAX

    cloud, _ = _blanked(scene, BLANK_MARGIN_MAX + 1)
    assert _blank_top_rows(cloud.xyz) == 0
    # a sparse first row (a ragged edge a pixel deep) still ends a margin at the next full row
    xyz = np.array(cloud.xyz, float)
    xyz[:] = scene[0].xyz
    xyz[0] = np.nan
    xyz[1, 1:] = np.nan   # one pixel measured of 640
    assert _blank_top_rows(xyz) == 2
