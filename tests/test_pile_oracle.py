"""``benchmarks/pile_oracle.py`` (pile56, docs/objects.md "Packed and stacked boxes: seams,
oracle planes and oracle proposals"): seams found in a plane's depth, planes cut along labelled
rectangles, one proposal per rectangle; and on a real frame (``$PLANEREL_HUNT_DATA``) the 2x2
block of cartons packed in a bin that no box proof reaches even cut and proposed one by one."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
import pile_oracle  # noqa: E402
from test_real_rules import demo_model  # noqa: E402,F401  (the fixture)

HUNT_DATA = Path(os.environ.get("PLANEREL_HUNT_DATA", "/nonexistent"))


def _tops(seam=None, depth=0.66, w=120, h=80, f=600.0):
    """Two carton tops 0.66 m under a camera looking straight down, flush side by side (one
    label); ``seam``: None, ``"gap"`` (a column without depth between them) or ``"dip"`` (a
    column 8 mm deeper: past the 4 mm tolerance by ten times the noise)."""
    v, u = np.mgrid[:h, :w].astype(float)
    z = np.full((h, w), depth) + np.random.default_rng(0).normal(0, 0.0008, (h, w))
    valid = np.ones((h, w), bool)
    mid = w // 2
    if seam == "gap":
        valid[:, mid] = False
    elif seam == "dip":
        z[:, mid] += 0.008
    xyz = np.stack([(u - w / 2) * z / f, (v - h / 2) * z / f, z], axis=-1)
    xyz[~valid] = np.nan
    lab = np.zeros((h, w), int)
    lab[~valid] = -1
    return lab, xyz, valid


@pytest.mark.parametrize("seam, parts", [(None, 1), ("gap", 2), ("dip", 2)])
def test_a_plane_falls_apart_only_along_a_seam_the_depth_shows(seam, parts):
    lab, xyz, valid = _tops(seam)
    found = pile_oracle.seam_parts(lab, xyz, valid, 0)
    assert len(found) == parts
    if parts == 2:   # the two tops, each about half
        assert all(0.4 < p.sum() / (lab == 0).sum() < 0.6 for p in found)


def test_a_plane_spanning_two_rectangles_is_cut_along_them_and_proposed_apart():
    lab = np.full((40, 60), -1)
    lab[5:35, 5:55] = 0          # one plane over two boxes
    lab[5:35, 56:58] = 1         # a strip inside the right box only
    rects = [(0, 0, 30, 40), (28, 0, 60, 40)]   # overlapping by two columns
    masks = [np.zeros(lab.shape, bool) for _ in rects]
    for m, (x0, y0, x1, y1) in zip(masks, rects, strict=True):
        m[y0:y1, x0:x1] = True
    span = pile_oracle.spanning(lab, masks)
    assert list(span) == [0]
    cut = pile_oracle.cut_along_rects(lab, rects, span)
    left, right = np.unique(cut[5:35, 5:28]), np.unique(cut[5:35, 31:55])
    assert len(left) == 1 and len(right) == 1 and left[0] != right[0] != 0
    # the overlap (columns 28-29) goes to the nearer centre: the left box's (15, not 44)
    assert cut[10, 28] == cut[10, 29] == left[0] and cut[10, 30] == right[0]
    own = pile_oracle.own_proposals(cut, masks)
    assert own == [[int(left[0])], sorted([1, int(right[0])])]


def test_the_packed_block_of_cartons_has_no_box_proof_even_cut_and_proposed_apart(demo_model):  # noqa: F811
    """hunt55 l515-boxes tote4 (``$PLANEREL_HUNT_DATA/hunt55/l515-boxes``): four carton tops
    packed 2x2 in a bin, seen from 0.66 m above (RealSense L515).  The segmentation bridges
    them into one plane (the seam between the two upper tops is not in the depth); cut along
    the labelled rectangles and proposed one by one, with the up of their tops given, no box
    rule fires on any (no ground plane under them, no side in view)."""
    folder = HUNT_DATA / "hunt55" / "l515-boxes"
    if not (folder / "labels.json").is_file():
        pytest.skip(f"no labelled frames in {folder} (set PLANEREL_HUNT_DATA)")
    from real_unseen import read_labels

    from planerel.classify.classifier import Classifier

    frame = next(f for f in read_labels(str(folder))["frames"] if f["file"].startswith("tote4"))
    with Classifier(str(demo_model)) as clf:
        rows = pile_oracle.frame_rows(clf, str(folder), frame, up_given=(0.023, 0.008, -1.0))
    assert len(rows) == 4
    assert all(r["shared_planes"] >= 1 for r in rows)       # one plane spans the block
    assert not any(r[k] for r in rows for k in ("as is", "cut", "cut+own", "cut+own+up"))
