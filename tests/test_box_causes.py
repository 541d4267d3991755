"""``benchmarks/box_causes.py`` (boxrec59, docs/objects.md "Real boxes missed, cause by cause,
by range, size and view"): each missed box's cause, its range, size and view, on frames
ray-cast in code (tests/scenes_analytic.py) and written as a labelled set folder; Prolog runs
for real (swipl through pyswip) with a one-rule model (``tall_face/1``)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import box_causes  # noqa: E402
from scenes_analytic import Rect, box, floor, render  # noqa: E402

STATS = [(1, "box", 40, 3)]
RULES = ("box(A) :- has_plane(A,B), nhorizontal(A,0), tall_face(B).\n"
         + "".join(f"planerel_rule_stats({i}, {k}, {tp}, {fp}).\n" for i, k, tp, fp in STATS))


@pytest.mark.parametrize("pitch", [0.0, 30.0, 70.0])
def test_the_camera_pitch_is_the_rendered_one(pitch):
    _, _, up, _ = render([floor()], pitch=pitch, width=32, height=24)
    assert box_causes.camera_pitch(up) == pytest.approx(pitch, abs=1e-6)
    assert box_causes.camera_pitch(-up) == pytest.approx(-pitch, abs=1e-6)


def test_bands_and_causes_of_census_rows():
    assert box_causes.band(0.99, box_causes.RANGES) == "< 1 m"
    assert box_causes.band(4.0, box_causes.RANGES) == ">= 4 m"
    assert box_causes.band(None, box_causes.SIZES) == "?"
    assert box_causes.band(55.0, box_causes.VIEWS) == "above"
    c = box_causes.cause
    assert c({"stage": "found"}, {}) == "found"
    assert c({"stage": "no plane in it"}, {"valid": 0.3, "in_planes": 0.3}) == "no plane: no depth"
    assert c({"stage": "no plane in it"}, {"valid": 0.9, "in_planes": 0.1}) == "no plane: unassigned"
    assert c({"stage": "no plane in it"},
             {"valid": 0.9, "in_planes": 0.8}) == "no plane: in a larger plane"
    assert c({"stage": "merged (other)"}, {"pile": 0.25}) == "merged: pile"
    assert c({"stage": "merged (box)"}, {"pile": 0.05}) == "merged: support"
    assert c({"stage": "gate refused (PlanarRefusal)"}, {}) == "gate refused (PlanarRefusal)"
    assert c({"stage": "no rule fires"},
             {"closest": {"plane": "s_p01", "fails": ["grounded"]},
              "upright": True}) == "rule: tall_face fails grounded"
    assert c({"stage": "no rule fires"}, {"upright": False, "top_sized": False}) == \
        "rule: no upright face, lying fails top size"
    assert c({"stage": "no rule fires"}, {"upright": False, "top_sized": True}) == \
        "rule: no upright face, lying fails ground"
    assert c({"stage": "no rule fires"}, {"upright": False, "tilted": True}) == \
        "rule: no upright face, a face tilted off vertical"


def _model(path: Path) -> Path:
    from planerel.ilp.model_settings import training_settings

    path.mkdir(parents=True, exist_ok=True)
    (path / "rules.pl").write_text(RULES)
    (path / "model.json").write_text(json.dumps(training_settings("regiongrow", {},
                                                                   rule_stats=STATS)))
    return path


def _rect_of(lab, objs, obj):
    ys, xs = np.nonzero(np.isin(lab, [k for k, o in enumerate(objs) if o == obj]))
    return [int(xs.min()), int(ys.min()), int(xs.max()) + 1, int(ys.max()) + 1]


def test_a_box_found_one_floating_and_one_where_nothing_is_seen(tmp_path):
    # a camera 0.2 m over the floor looking level: a box on the floor (found by tall_face),
    # a box 0.4 m up in the air (its face is not grounded), and a rectangle over the empty
    # sky above the scene (no depth)
    floating = [Rect((r.center[0], r.center[1], r.center[2] + 0.4), r.e1, r.e2, r.a, r.b, 2)
                for r in box(0.9, 1.8, 0.5, 0.4, 0.4, obj=2)]
    rects = [floor(), *box(-0.5, 1.5, 0.5, 0.4, 0.5, obj=1), *floating]
    cloud, lab, up, objs = render(rects, pitch=0.0, cam_height=0.2, width=320, height=240,
                                  noise=0.001)
    folder = tmp_path / "set"
    folder.mkdir()
    np.save(folder / "f.npy", cloud.xyz.astype(np.float32))
    i = cloud.intrinsics
    frame = {"file": "f.npy", "intrinsics": f"{i.width},{i.height},{i.fx},{i.fy},{i.cx},{i.cy}",
             "up": [float(x) for x in up],
             "objects": [{"class": "box", "box": _rect_of(lab, objs, 1), "what": "on the floor"},
                         {"class": "box", "box": _rect_of(lab, objs, 2), "what": "in the air"},
                         {"class": "box", "box": [10, 5, 60, 40], "what": "nothing"}]}
    (folder / "labels.json").write_text(json.dumps({"set": "set", "frames": [frame]}))
    rows = {r["what"]: r for r in box_causes.run([str(folder)], str(_model(tmp_path / "m")))}
    assert rows["on the floor"]["cause"] == "found"
    assert rows["in the air"]["cause"].startswith("rule: tall_face fails")
    assert "grounded" in rows["in the air"]["cause"]
    assert rows["nothing"]["cause"] == "no plane: no depth"
    for r in rows.values():
        assert r["view"] == "level" and abs(r["pitch"]) < 0.5
    assert rows["on the floor"]["range_band"] == "1-2 m"
    # its front 0.5 m wide and high (the rectangle also holds its side, seen obliquely)
    assert 0.45 <= rows["on the floor"]["size"] <= 0.75
    assert rows["on the floor"]["size_band"] == ">= 0.4 m"
    text = box_causes.tables(list(rows.values()))
    assert "boxes 3, found 1, missed 2" in text


def test_up_errors_flag_a_wrong_up_and_give_the_view_from_the_truth(tmp_path):
    up_json = tmp_path / "up.json"
    up_json.write_text(json.dumps({"frames": [
        {"frame": "h/s/a.npy", "error_deg": 82.0, "truth": [0.0, -0.1, -0.995]},
        {"frame": "h/s/b.npy", "error_deg": 1.0, "truth": [0.0, -1.0, 0.0]}]}))
    rows = [{"set": "h/s", "file": "a.npy", "pitch": 0.0, "view": "level"},
            {"set": "h/s", "file": "b.npy", "pitch": 1.0, "view": "level"},
            {"set": "h/s", "file": "c.npy", "pitch": 30.0, "view": "oblique"}]
    box_causes.add_up_errors(rows, str(up_json))
    assert rows[0]["up_wrong"] and rows[0]["view"] == "above" and rows[0]["pitch_estimated"] == 0.0
    assert rows[1]["up_wrong"] is False and rows[1]["view"] == "level"
    assert rows[2]["up_error"] is None and rows[2]["view"] == "oblique"
