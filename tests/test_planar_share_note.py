"""A scan whose depth lies mostly in no plane (up66): ``classify`` reports the share of its
valid points in a plane (``planar_share``); the default ``wide_fallback`` grows such a scan
again with a wider window, and with it off a note under ``LOW_PLANAR_SHARE`` names it (an
R200's speckled, rippled depth: hunt45's frames hold 0-6 % at the adapted window)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
from test_real_rules import demo_model  # noqa: E402,F401  (the fixture)
from test_segment_noise import _noisy_slope  # noqa: E402

from planerel.classify.classifier import LOW_PLANAR_SHARE, Classifier, SceneAnswer  # noqa: E402
from planerel.io.cloud import Cloud  # noqa: E402
from planerel.segment import planar_share  # noqa: E402


def _answer(**extra):
    kw = dict(source="x", scene_id="s", labels=np.zeros((2, 2), np.int32),
              plane_ids={0: "s_p00"}, objects=(), up_source="given", seconds=0.0, floor="s_p00")
    return SceneAnswer(**{**kw, **extra})


def test_the_note_speaks_only_under_the_share_and_without_the_fallback():
    low, high = _answer(planar_share=0.02), _answer(planar_share=LOW_PLANAR_SHARE + 0.01)
    assert any("wide_fallback" in n and "2 %" in n for n in low.notes())
    assert not any("wide_fallback" in n for n in high.notes())
    assert not any("wide_fallback" in n for n in _answer().notes())   # not recorded
    grown = _answer(planar_share=0.02, wide_fallback=True)
    assert not any("wide_fallback" in n for n in grown.notes())
    assert low.to_dict()["planar_share"] == 0.02
    assert "planar_share" not in _answer().to_dict()


def test_the_share_counts_valid_points_in_a_plane():
    xyz = np.zeros((2, 3, 3))
    xyz[..., 2] = 1.0
    xyz[0, 0] = np.nan
    cloud = Cloud(xyz, (3, 2, 1.0, 1.0, 1.0, 0.5))
    labels = np.array([[5, -1, 0], [0, -1, -1]], np.int32)
    assert planar_share(cloud, labels) == 2 / 5   # the NaN pixel's label does not count
    assert planar_share(Cloud(np.full((2, 3, 3), np.nan), (3, 2, 1.0, 1.0, 1.0, 0.5)),
                         labels) is None


def test_classify_reports_the_share_and_the_fallback_raises_it(demo_model):  # noqa: F811
    # a slope with correlated noise and a row and a column without depth every 14 px (no 15 px
    # patch for the wide noise estimate): the adapted window plans little of it, the fallback
    # with the widest window nearly all
    noisy = _noisy_slope(0.005, seed=2)
    xyz = np.array(noisy.xyz)
    xyz[::14, :] = np.nan
    xyz[:, ::14] = np.nan
    cloud = Cloud(xyz, noisy.intrinsics)
    with Classifier(str(demo_model), seg_params={"wide_fallback": 0.0}) as clf:
        plain = clf.classify(cloud)
    with Classifier(str(demo_model)) as clf:   # the default: on at LOW_PLANAR_SHARE
        grown = clf.classify(cloud)
    assert plain.planar_share < LOW_PLANAR_SHARE and not plain.wide_fallback
    assert any("wide_fallback" in n for n in plain.notes())
    assert grown.wide_fallback and grown.planar_share > 0.9
    assert not any("wide_fallback" in n for n in grown.notes())
