"""benchmarks/spurious_answers.py lists the class answers that ``independent_scenes.py score``
counts as matching no object, with the rule and the truth their proof planes lie on."""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

import numpy as np

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"


def _load(name):
    spec = importlib.util.spec_from_file_location(name, BENCH / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    spec.loader.exec_module(mod)
    return mod


ind = _load("independent_scenes")
spur = _load("spurious_answers")


def _write_scene(out: Path, i: int, panel: bool):
    """A 0.6 x 0.4 x 0.5 box (object 1) on the floor seen from 2 m, and with ``panel`` a
    free-standing 1.0 x 0.05 x 0.8 board of the environment (truth 0) beside it."""
    meshes = [(ind._box((30, 30, 0.02), (0, 0, -0.01)), 0), (ind._box((0.6, 0.4, 0.5), (0, 0, 0.25)), 1)]
    if panel:
        meshes.append((ind._box((1.0, 0.05, 0.8), (1.3, 0.3, 0.4)), 0))
    eye = np.array([0.4, -2.2, 1.1])
    f = np.array([0.5, 0.0, 0.3]) - eye
    f /= np.linalg.norm(f)
    r = np.cross(f, [0.0, 0.0, 1.0])
    r /= np.linalg.norm(r)
    R = np.stack([r, np.cross(f, r), f])
    W, H, fx = 160, 120, 140.0
    xyz, truth = ind.render(meshes, eye, R, (W, H, fx, fx, (W - 1) / 2, (H - 1) / 2),
                            np.random.default_rng(i))
    side = {"format": "independent-scene", "version": 1, "scene_id": f"i{i:04d}", "class": "box",
            "intrinsics": {"width": W, "height": H, "fx": fx, "fy": fx, "cx": (W - 1) / 2,
                           "cy": (H - 1) / 2},
            "up": (R @ np.array([0.0, 0.0, 1.0])).tolist(),
            "objects": [{"index": 1, "class": "box", "kind": "box"}], "params": {}}
    np.save(out / f"i{i:04d}.npy", xyz.astype(np.float32))
    np.save(out / f"i{i:04d}.objects.npy", truth.astype(np.int32))
    (out / f"i{i:04d}.json").write_text(json.dumps(side))


def test_the_answers_listed_are_the_ones_score_counts_and_name_the_environment(tmp_path):
    """A rule that calls every upright plane a box answers the environment's board too: that
    answer, and only it, is listed, by rule 1, its proof plane on ``environment``; the box
    itself matches its object and is not listed; the count is ``score``'s."""
    from planerel.classify.classifier import Classifier

    for i, panel in enumerate((True, False)):
        _write_scene(tmp_path, i, panel)
    rules = tmp_path / "rules.pl"
    rules.write_text("box(A) :- has_plane(A,B), orientation(B,vertical).\n")
    with Classifier(rules) as clf:
        rows = spur.set_rows(clf, tmp_path)
    scored = ind.score_set(tmp_path, [rules])[str(rules)]
    assert len(rows) == scored["spurious_class_answers"] >= 1
    assert {r["scene"] for r in rows} == {"i0000"}  # only the scene with the board
    for r in rows:
        assert r["class"] == "box" and r["rule"] == 1
        assert r["proof_planes"] and all(q["lies_on"] == "environment" and q["share"] > 0.9
                                         for q in r["proof_planes"])
    s = spur.summary(rows)
    assert s["answers"] == len(rows) and s["by_truth"] == {"box on environment": len(rows)}


def test_lies_on_names_the_kind_holding_most_of_a_plane():
    truth = np.array([[0, 0, 2], [2, 2, -1]])
    kinds = {2: "chair"}
    assert spur.lies_on(np.array([[1, 1, 1], [1, 1, 0]], bool), truth, kinds) == ("chair", 0.6)
    assert spur.lies_on(np.array([[1, 1, 0], [0, 0, 0]], bool), truth, kinds) == ("environment", 1.0)
    assert spur.lies_on(np.zeros((2, 3), bool), truth, kinds) == ("none", 0.0)
    assert spur._label_of("i0006_p03") == 3 and spur._label_of(7) == 7 and spur._label_of("x") is None


def test_score_takes_the_models_settings_overrides(tmp_path):
    """``independent_scenes.py score --param`` reaches the classifier as ``planerel classify
    --param`` does (real_checks.py passes its ``--param`` to the independent sets): a minimum
    region larger than the image grows no plane, so the box found by default is not; a
    misspelled name is refused with the classifier's message."""
    import pytest

    from planerel.errors import InputError

    _write_scene(tmp_path, 0, False)
    rules = tmp_path / "rules.pl"
    rules.write_text("box(A) :- has_plane(A,B), orientation(B,vertical).\n")

    def preds(params):
        res = ind.score_set(tmp_path, [rules], params=params)[str(rules)]
        return [r["pred"] for r in res["rows"] if r["class"] == "box"]

    assert preds(()) == ["box"]
    assert preds(["min_region_size=100000"]) == ["none"]
    with pytest.raises(InputError):
        ind.score_set(tmp_path, [rules], params=["min_region_sise=10"])
