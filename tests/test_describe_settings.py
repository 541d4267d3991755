"""``planerel describe --model / --param``: facts made with a model's settings (user89: the
facts of a model learned with ``--param`` could not be exported)."""

from __future__ import annotations

import json
import re

import pytest

from planerel.cli import main


@pytest.fixture(scope="module")
def scan(tmp_path_factory):
    d = tmp_path_factory.mktemp("set")
    assert main(["dataset", "synth", str(d), "--n-box", "1", "--n-stairs", "1", "--n-ramp", "0",
                 "--seed", "7", "--quiet"]) == 0
    return d / "s0001.depth.png"  # the stairs scene


def _model(path, seg_params, **sections):
    from planerel.ilp.model_settings import training_settings

    path.mkdir()
    (path / "rules.pl").write_text("stairs(A) :- has_plane(A, B), parallel(B, C).\n")
    data = training_settings("regiongrow", seg_params)
    for name, values in sections.items():
        data[name].update(values)
    (path / "model.json").write_text(json.dumps(data))
    return path


def _planes(pl) -> list:
    return re.findall(r"^scene_plane\(\w+, (\w+)\)\.", pl.read_text(), re.M)


def test_facts_with_a_models_settings_are_the_ones_classify_reasons_on(scan, tmp_path):
    from planerel.classify.classifier import Classifier
    from planerel.io import readers as io

    model = _model(tmp_path / "m", {"min_region_size": 1500})
    assert main(["describe", str(scan), "-o", str(tmp_path / "default.pl")]) == 0
    assert main(["describe", str(scan), "-o", str(tmp_path / "model.pl"), "--model",
                 str(model)]) == 0
    assert main(["describe", str(scan), "-o", str(tmp_path / "param.pl"), "--param",
                 "min_region_size=1500"]) == 0
    with Classifier(model) as clf:
        ans = clf.classify(io.read(scan), scene_id="s0001")
    by_model = _planes(tmp_path / "model.pl")
    assert by_model == sorted(ans.plane_ids.values())
    assert by_model != _planes(tmp_path / "default.pl")  # the settings made other planes
    body = [ln for ln in (tmp_path / "model.pl").read_text().splitlines()
            if not ln.startswith("%")]
    assert body == [ln for ln in (tmp_path / "param.pl").read_text().splitlines()
                    if not ln.startswith("%")]


def test_a_param_over_a_model_warns_and_a_bad_one_fails_before_any_work(scan, tmp_path,
                                                                           capsys):
    model = _model(tmp_path / "m", {}, relations={"lying_rise": 0.02})
    out = tmp_path / "f.pl"
    assert main(["describe", str(scan), "-o", str(out), "--model", str(model), "--param",
                 "relations.lying_rise=0.03"]) == 0
    assert "lying_rise" in capsys.readouterr().err
    for bad, said in (("thetaa=3", "thetaa"), ("decision.crowd_gate=false", "decision"),
                      ("relations.nope=1", "nope")):
        assert main(["describe", str(scan), "-o", str(tmp_path / "g.pl"), "--param", bad]) == 2
        assert said in capsys.readouterr().err
        assert not (tmp_path / "g.pl").exists()
    assert main(["describe", str(scan), "-o", str(tmp_path / "g.pl"), "--model",
                 str(tmp_path / "none")]) == 2
    assert "no such model" in capsys.readouterr().err
