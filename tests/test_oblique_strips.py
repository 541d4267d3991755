"""A strip narrower than ``relations.oblique_min_width`` (2.5 cm) does not count in
``oblique_share``: a real box's rounded edge is no facet of a round object (docs/results.md,
"Rounded box edges and `oblique_share`").
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest

from planerel.errors import InputError
from planerel.features.facts import describe_scene, facts_text, oblique_share
from planerel.features.relations import RelationParams
from planerel.segment import segment

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scenes_analytic import Rect, floor, render  # noqa: E402


def bevelled_box(cx, cy, sx, sy, sz, strip, obj=1):
    """Top and front of a box whose front top edge is cut at 45 degrees by a strip ``strip``
    m wide (the top ends and the front starts ``strip / sqrt 2`` short of the edge)."""
    leg = strip / math.sqrt(2)
    top = Rect((cx, cy + leg / 2, sz), (1, 0, 0), (0, 1, 0), sx / 2, (sy - leg) / 2, obj)
    front = Rect((cx, cy - sy / 2, (sz - leg) / 2), (1, 0, 0), (0, 0, 1), sx / 2,
                 (sz - leg) / 2, obj)
    s = 1 / math.sqrt(2)
    bevel = Rect((cx, cy - sy / 2 + leg / 2, sz - leg / 2), (1, 0, 0), (0, s, s), sx / 2,
                 strip / 2, obj)
    return [top, front, bevel]


def _describe(strip, **kw):
    cloud, _lab, up, _objs = render([floor()] + bevelled_box(0.0, 1.0, 0.4, 0.3, 0.25, strip),
                                    pitch=40, cam_height=0.9, width=640, height=480,
                                    noise=0.0003)
    return describe_scene(cloud, segment(cloud).labels, scene_id="s0001", up=up, **kw)


@pytest.mark.parametrize("strip", [0.02, 0.035])
def test_a_rounded_edge_narrower_than_the_width_does_not_count(strip):
    desc = _describe(strip)
    (obj,) = desc.objects
    by_label = {p.label: p for p in desc.planes}
    widths = sorted(by_label[k].width for k in obj.planes)
    assert len(widths) == 3 and widths[0] < 0.045           # the strip is segmented
    everything = oblique_share(by_label, desc.relations, obj.planes)
    assert everything > 0.02                                # it meets top and front at 45 deg
    narrow = widths[0] < RelationParams().oblique_min_width
    assert narrow == (strip < 0.025)
    default = oblique_share(by_label, desc.relations, obj.planes,
                            RelationParams().oblique_min_width)
    assert default == (0.0 if narrow else everything)
    # the facts use the description's own setting
    text = facts_text([desc])
    assert f"oblique_share(s0001_o1, {round(default, 3)})." in text.replace("'", "")


def test_the_width_is_a_relation_setting():
    desc = _describe(0.02, relation_params=RelationParams(oblique_min_width=0.0))
    assert "oblique_share(s0001_o1, 0.0)." not in facts_text([desc]).replace("'", "")
    with pytest.raises(InputError, match="oblique_min_width must be a non-negative number"):
        RelationParams(oblique_min_width=-0.01)


def test_only_the_smaller_plane_of_an_oblique_pair_counts_by_hand():
    P = {1: SimpleNamespace(area=0.10, width=0.30), 2: SimpleNamespace(area=0.004, width=0.018),
         3: SimpleNamespace(area=0.02, width=0.05)}

    def rel(a, b, *, par=False, perp=False):
        return SimpleNamespace(a=a, b=b, adjacent=True, parallel=par, perpendicular=perp)

    rels = [rel(1, 2), rel(1, 3)]
    assert oblique_share(P, rels, [1, 2, 3]) == pytest.approx(0.024 / 0.124)
    assert oblique_share(P, rels, [1, 2, 3], 0.025) == pytest.approx(0.02 / 0.124)
    assert oblique_share(P, rels, [1, 2, 3], 0.06) == 0.0
    assert oblique_share(P, [rel(1, 3, perp=True)], [1, 3], 0.0) == 0.0
