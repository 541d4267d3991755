"""``benchmarks/no_plane_why.py --small-pass`` (docs/segmentation.md "The judge's blocks, stage
by stage"): the stage it names for a box is what the small pass itself does with it, and the
aggregate lines name no frame."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.insert(0, str(ROOT / "tests"))
import no_plane_why as why  # noqa: E402
from test_small_scale import _scene  # noqa: E402

from planerel.segment import segment  # noqa: E402


@pytest.fixture(scope="module")
def tote():
    """dev_tote's kind (toy blocks and cartons in a tote seen from above), the first growing,
    the small pass's result and each object's bounding rectangle."""
    cloud, truth = _scene(1, 6801, "tote_blocks")
    first, small = segment(cloud), segment(cloud, small_scale=0.35, small_pitch=0.0)
    rects = {}
    for t in np.unique(truth[truth > 0]).tolist():
        ys, xs = np.nonzero(truth == t)
        rects[t] = (int(xs.min()), int(ys.min()), int(xs.max()) + 1, int(ys.max()) + 1)
    return cloud, truth, first, small, rects


def test_a_box_staged_kept_holds_a_plane_of_the_small_pass(tote):
    cloud, truth, first, small, rects = tote
    n = len(first.planes)
    stages = {t: why.small_stage(cloud, r, seg=first) for t, r in rects.items()}
    assert {s for s, _ in stages.values()} <= set(why.SMALL_STAGES)
    kept = [t for t, (s, _) in stages.items() if s == "kept"]
    assert kept, stages  # the scene's tops standing over the tote floor or a block
    for t in kept:
        # the small pass added a plane lying half or more in the box's rectangle
        x0, y0, x1, y1 = rects[t]
        new = small.labels[y0:y1, x0:x1]
        labs, counts = np.unique(new[new >= n], return_counts=True)
        assert any(c >= 0.5 * (small.labels == lab).sum()
                   for lab, c in zip(labs.tolist(), counts.tolist(), strict=True)), t
    # no more boxes kept than planes the pass added
    assert len(kept) <= small.info["small_planes"]


def test_a_rectangle_over_planed_depth_has_no_free_region(tote):
    cloud, truth, first, small, rects = tote
    # the tote's floor or a wall: the largest plane of the first growing, wholly planed
    lab = first.labels
    big = int(np.bincount(lab[lab >= 0]).argmax())
    ys, xs = np.nonzero(lab == big)
    cy, cx = int(np.median(ys)), int(np.median(xs))
    stage, _ = why.small_stage(cloud, (cx - 3, cy - 3, cx + 4, cy + 4), seg=first)
    assert stage in ("no region", "not free")


def test_the_aggregate_names_no_frame():
    rows = [{"name": "secret/frame box [1, 2, 3, 4]", "px": 100, "valid": 1.0, "z": 0.9,
             "unassigned": 1.0, "rms5": 0.2, "rms9": 0.4, "rms15": 1.0, "normals_off": "16.0/20.0",
             "few_neighbours": 0.0, "seedable": 0.5, "model": "wave sigma 0.23 mm, wave 1.0",
             "window/min/delta": "3/3 1080 10 mm",
             "planes_in_rect": {name: "0.60/0.50" for name, _ in why.VARIANTS}}]
    text = "\n".join(why.aggregate(rows))
    assert "secret" not in text and "frame" not in text
    assert "targets 1" in text
    assert "main: in planes >= 0.5 for 1 of 1" in text
