"""wave83: a ramp is one flat slope, so each of its parts slopes as the whole does
(``decision.slope_parts_gate``; docs/objects.md "A ramp's parts slope alike").

:func:`planerel.features.slope_parts.slope_parts` is checked on made points; the gate on
ray-cast scenes (tests/scenes_analytic.py) described for real, Prolog running for real (swipl
through pyswip), with the demo's ramp clause.  With ``PLANEREL_INDEPENDENT_DATA`` (the folder
``independent_scenes.py dev`` fills) it is checked on the wavy stereo scene it was measured on,
with the demo's model.
"""

from __future__ import annotations

import math
import os
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from planerel.errors import InputError
from planerel.features.slope_parts import slope_parts
from planerel.ilp import metrics as M

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ramp_model import ramp_model  # noqa: E402
from scenes_analytic import Rect, floor, ramp, render  # noqa: E402
from test_real_rules import demo_model  # noqa: E402,F401  (the fixture)

UP = np.array([0.0, -1.0, 0.0])   # the camera's y points down


def _grid(height_of, n=40, seed=0, noise=0.0):
    """Organized points ``(n, n, 3)`` of the surface ``y = -height_of(x, z)`` over 2 x 2 m,
    4-6 m ahead, all labelled 3."""
    x, z = np.meshgrid(np.linspace(-1, 1, n), np.linspace(4, 6, n))
    h = height_of(x, z) + np.random.default_rng(seed).normal(0, noise, x.shape)
    return np.stack([x, -h, z], axis=-1), np.full((n, n), 3)


PLANE = SimpleNamespace(label=3)


def test_a_flat_slope_has_parts_that_slope_alike():
    g = math.tan(math.radians(12))
    xyz, lab = _grid(lambda x, z: g * (z - 4), noise=0.002)
    p = slope_parts(PLANE, UP, xyz, lab)
    assert p.slope == pytest.approx(12, abs=0.3)
    assert len(p.shares) == 4 and p.worst < 0.05


def test_a_bent_surface_does_not():
    """Level for its near metre, 24 degrees for its far one: the whole's fit slopes as a
    compromise, its uphill parts about twice as steeply and its downhill parts nearly level."""
    g = math.tan(math.radians(24))
    xyz, lab = _grid(lambda x, z: g * np.maximum(z - 5, 0))
    p = slope_parts(PLANE, UP, xyz, lab)
    assert 5 < p.slope < 20
    assert p.worst > 0.5
    assert max(p.shares) > 1.5 and min(p.shares) < 0.5


def test_a_slope_tilted_across_its_parts():
    """Parts tilted the other way (a far floor's undulation) give negative shares."""
    g = math.tan(math.radians(10))
    xyz, lab = _grid(lambda x, z: g * (z - 4) - 2.5 * g * np.clip(z - 5, 0, 0.5))
    p = slope_parts(PLANE, UP, xyz, lab)
    assert min(p.shares) < 0 and p.worst > 1


def test_what_is_not_judged():
    g = math.tan(math.radians(12))
    xyz, lab = _grid(lambda x, z: g * (z - 4))
    assert slope_parts(SimpleNamespace(label=4), UP, xyz, lab) is None      # no points
    assert slope_parts(PLANE, UP, xyz[:6, :6], lab[:6, :6]) is None        # too few
    flat, lab2 = _grid(lambda x, z: 0 * x)
    assert slope_parts(PLANE, UP, flat, lab2) is None                       # level
    wall = np.stack([flat[..., 0], -flat[..., 2] + 4, np.full(flat.shape[:2], 5.0)], axis=-1)
    assert slope_parts(PLANE, UP, wall, lab2) is None                       # upright
    holes = xyz.copy()
    holes[::2] = np.nan                                                     # no depth: skipped
    assert slope_parts(PLANE, UP, holes, lab).worst < 0.05


def test_decision_params():
    p = M.DecisionParams()
    assert p.slope_parts_gate is True and p.slope_parts_tol == 0.5
    with pytest.raises(InputError):
        M.DecisionParams(slope_parts_gate="yes")
    with pytest.raises(InputError):
        M.DecisionParams(slope_parts_tol=-0.1)


# --------------------------------------------------------------------------- the decision


def _bent(low_deg=4.0, high_deg=22.0, y0=1.6, half=0.9, width=1.2):
    """Two slopes joined at a crease, rising away from the camera from the floor at ``y0``:
    ``half`` metres at ``low_deg`` then ``half`` at ``high_deg``."""
    (lower,) = ramp(0.0, y0, low_deg, half, width)
    a, b = math.radians(low_deg), math.radians(high_deg)
    y1, z1 = y0 + half * math.cos(a), half * math.sin(a)
    e2 = (0.0, math.cos(b), math.sin(b))
    upper = Rect((0.0, y1 + half / 2 * math.cos(b), z1 + half / 2 * math.sin(b)), (1, 0, 0), e2,
                 width / 2, half / 2, 1)
    return [floor(), lower, upper]


def _answer(model, rects, one_plane=(1, 2), **kw):
    """The scene described from its true planes (the labels of ``one_plane`` joined as one
    plane, as a sensor's undulation or the region grower joins them) and the answer of the
    object holding the slope."""
    from planerel.classify.classifier import Classifier
    from planerel.features.facts import describe_scene

    cloud, lab, up, _objs = render(rects, pitch=30, cam_height=1.4, width=320, height=240,
                                   noise=0.0003)
    lab = np.where(np.isin(lab, one_plane), one_plane[0], lab)
    desc = describe_scene(cloud, lab, scene_id="s", up=up)
    with Classifier(model, **kw) as clf:
        answers = clf.answer_description(desc, xyz=cloud.xyz)
    (o,) = [a for a in answers if one_plane[0] in a.labels]
    return o


def test_a_straight_ramp_stays_a_ramp(tmp_path):
    o = _answer(ramp_model(tmp_path / "m"), [floor()] + ramp(0.0, 1.6, 15.0, 1.8, 1.2),
                one_plane=(1,))
    assert o.klass == "ramp"
    assert not any(isinstance(r, M.SlopePartsRefusal) for r in o.refused)


def test_a_bent_slope_is_no_ramp(tmp_path):
    """The rule holds (one plane of 2 m^2 at about 13 degrees), but its parts slope 4 and 22
    degrees: refused; a ramp with the gate off, or with a bound wider than its parts' spread."""
    o = _answer(ramp_model(tmp_path / "m"), _bent())
    assert o.klass == "other"
    (why,) = [r for r in o.refused if isinstance(r, M.SlopePartsRefusal)]
    assert why.klass == "ramp" and why.rule == 1 and why.bound == 0.5
    assert len(why.planes) == 1 and len(why.shares[0]) == 4
    assert max(abs(s - 1) for s in why.shares[0]) > 0.5
    assert "slope" in why.reason and why.to_dict()["shares"]
    assert _answer(ramp_model(tmp_path / "off", slope_parts_gate=False), _bent()).klass == "ramp"
    assert _answer(ramp_model(tmp_path / "m"), _bent(),
                   seg_params={"decision.slope_parts_tol": "5"}).klass == "ramp"


_DEV = os.environ.get("PLANEREL_INDEPENDENT_DATA")


@pytest.mark.skipif(not _DEV, reason="PLANEREL_INDEPENDENT_DATA not set")
def test_the_wavy_far_floor(demo_model):  # noqa: F811
    """dev_stw i0052 (a flight seen from its landing by the wavy stereo sensor): three of the
    four far floor pieces the demo's rule answered ``ramp`` (10-20 degrees, 3.7-4.8 m away) are
    refused; each refused object lies on the environment (label 0)."""
    from planerel.classify.classifier import Classifier
    from planerel.io import readers as io

    path = Path(_DEV) / "dev_stw" / "i0052.npy"
    if not path.exists():
        pytest.skip(f"{path} missing")
    cloud = io.read(path)
    truth = np.load(path.with_name(path.stem + ".objects.npy"))
    with Classifier(str(demo_model)) as clf:
        ans = clf.classify(cloud, scene_id=path.stem)
    refused = [o for o in ans.objects
               if any(isinstance(r, M.SlopePartsRefusal) for r in o.refused)]
    assert len(refused) >= 3 and all(o.klass == "other" for o in refused)
    for o in refused:
        assert (truth[np.isin(ans.labels, o.labels)] == 0).mean() > 0.95
    assert sum(o.klass == "ramp" for o in ans.objects) <= 1
