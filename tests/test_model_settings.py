"""The model carries its settings: learn writes model.json, classify reuses it (issue 16, 4)."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from planerel.cli import main
from planerel.errors import InputError
from planerel.ilp import pipeline as P
from planerel.synth.generator import generate_dataset, generate_scene


@pytest.fixture(scope="module")
def model_dir(tmp_path_factory):
    """A model learned from region-growing planes with theta=12 (not the default 15)."""
    base = tmp_path_factory.mktemp("settings")
    ds = base / "train"
    generate_dataset(ds, n_box=3, n_stairs=0, n_ramp=3, seed=5, size=(640, 480), subsample=4)
    P.learn_model(ds, base / "model", engine="builtin", jobs=1, seg_params={"theta": "12"},
                  cache="none", log=lambda s: None)
    return base / "model"


def test_learn_writes_the_settings_it_learned_with(model_dir):
    from planerel.features.gravity import GravityParams
    from planerel.features.planes import PlaneParams
    from planerel.features.relations import ProposalParams, RelationParams

    data = json.loads((model_dir / "model.json").read_text())
    seg = data["segmentation"]
    assert seg["method"] == "regiongrow" and seg["params"] == {"theta": "12"}
    assert seg["resolved"]["theta"] == 12.0
    assert seg["resolved"]["adapt"] is True  # the sensor-adaptive settings are on by default
    assert data["gravity"] == dataclasses.asdict(GravityParams())
    assert data["planes"] == dataclasses.asdict(PlaneParams())
    assert data["relations"] == dataclasses.asdict(RelationParams())
    assert data["proposals"] == dataclasses.asdict(ProposalParams())
    stats = json.loads((model_dir / "metrics.json").read_text())["rule_stats"]
    assert [[r["index"], r["class"], r["tp"], r["fp"]] for r in data["rule_precision"]] == stats
    for r in data["rule_precision"]:
        assert r["laplace"] == pytest.approx((r["tp"] + 1) / (r["tp"] + r["fp"] + 2), abs=1e-6)
    # gate22: the least and most planar training positive of each class, and the decision's
    # settings (the gate off by default)
    from planerel.ilp.metrics import DecisionParams
    from planerel.ilp.scenes import describe_scenes

    assert data["decision"] == dataclasses.asdict(DecisionParams())
    descs, _ = describe_scenes(model_dir.parent / "train", jobs=1, seg_params={"theta": "12"},
                               cache="none", progress=False)
    want = {}
    for d in descs:
        for o in d.objects:
            if o.klass in ("box", "ramp"):
                want.setdefault(o.klass, []).append(o.planar_fraction)
    got = {e["class"]: e for e in data["planar_domain"]}
    assert set(got) == set(want) == {"box", "ramp"}
    for k, v in want.items():
        assert (got[k]["low"], got[k]["high"], got[k]["n"]) == (
            pytest.approx(min(v), abs=1e-4), pytest.approx(max(v), abs=1e-4), len(v))


def test_classify_segments_with_the_model_settings(model_dir):
    from planerel.classify.classifier import Classifier
    from planerel.segment import segment

    scene = generate_scene("box", seed=21, size=(640, 480), subsample=4)
    with Classifier(model_dir / "rules.pl") as clf:
        assert clf.warnings == ()
        assert (clf.method, clf.seg_params) == ("regiongrow", {"theta": "12"})
        ans = clf.classify(scene.cloud, scene_id="s0001")
    want = segment(scene.cloud, "regiongrow", theta=12.0).labels
    default = segment(scene.cloud, "regiongrow").labels
    assert np.array_equal(ans.labels, want)
    assert not np.array_equal(want, default)  # so the test can tell the settings apart


@pytest.mark.parametrize("overrides, method, warned", [
    ({"theta": "12"}, None, []),                       # the training value: nothing to say
    ({"theta": "15"}, None, ["theta=15.0", "12.0"]),
    ({"gravity.tol_deg": "4"}, None, ["gravity.tol_deg=4.0", "5.0"]),
    ({}, "sp", ["method sp", "regiongrow"]),
])
def test_overrides_differing_from_training_are_warned(model_dir, overrides, method, warned):
    from planerel.classify.classifier import Classifier

    with Classifier(model_dir / "rules.pl", method=method, seg_params=overrides) as clf:
        text = " | ".join(clf.warnings)
        assert len(clf.warnings) == (1 if warned else 0), text
        for part in warned:
            assert part in text
        if "gravity.tol_deg" in overrides:
            assert clf._describe_kw["gravity_params"].tol_deg == 4.0


@pytest.mark.parametrize("overrides, match", [
    ({"gravity.nope": "1"}, "gravity has no parameter 'nope'"),
    ({"colour.x": "1"}, "unknown section 'colour'"),
    ({"planes.min_points": "many"}, "expected a int"),
])
def test_bad_overrides_are_refused(model_dir, overrides, match):
    from planerel.classify.classifier import Classifier

    with pytest.raises(InputError, match=match):
        Classifier(model_dir / "rules.pl", seg_params=overrides)


def test_rules_without_settings_use_the_defaults(tmp_path):
    from planerel.classify.classifier import Classifier

    (tmp_path / "rules.pl").write_text("box(A) :- nplanes(A, 2).\n")
    with Classifier(tmp_path / "rules.pl", seg_params={"theta": "12"}) as clf:
        assert clf.warnings == () and clf.trained is None
        assert (clf.method, clf.seg_params) == ("regiongrow", {"theta": "12"})


def test_cli_warns_about_an_override(model_dir, tmp_path, capsys):
    scene = generate_scene("box", seed=21, size=(640, 480), subsample=4)
    np.save(tmp_path / "box.npy", scene.cloud.xyz)
    assert main(["classify", str(model_dir / "rules.pl"), str(tmp_path / "box.npy"),
                 "--param", "theta=14"]) == 0
    err = capsys.readouterr().err
    assert "warning: segmentation theta=14.0 differs from the model's training value 12.0" in err


def test_split_fields_are_settings_of_the_model(model_dir, tmp_path, capsys):
    """``split.NAME`` sets a field of the segmentation's post-processing: kept in the model's
    resolved settings, overridable in classify with a warning, and used when segmenting."""
    from planerel.classify.classifier import Classifier
    from planerel.segment import segment
    from planerel.segment.split import SplitParams

    resolved = json.loads((model_dir / "model.json").read_text())["segmentation"]["resolved"]
    assert {k: resolved["split." + k] for k in ("small_faces", "merge", "leftover_scale")} == {
        "small_faces": 0, "merge": True, "leftover_scale": 1.0}
    scene = generate_scene("stairs", seed=2, size=(640, 480), subsample=4)
    with Classifier(model_dir / "rules.pl", seg_params={"split.merge": "false"}) as clf:
        assert clf.warnings == ("segmentation split.merge=False differs from the model's "
                                "training value True",)
        ans = clf.classify(scene.cloud, scene_id="s0001")
    want = segment(scene.cloud, "regiongrow", theta=12.0,
                   split_params=SplitParams(merge=False)).labels
    assert np.array_equal(ans.labels, want)
    assert not np.array_equal(want, segment(scene.cloud, "regiongrow", theta=12.0).labels)
    np.save(tmp_path / "st.npy", scene.cloud.xyz)
    assert main(["classify", str(model_dir / "rules.pl"), str(tmp_path / "st.npy"),
                 "--param", "split.smal_faces=150"]) == 2
    # the closest known name is offered (user89), in the user's spelling, with no class name
    # (usab90: "for SplitParams" was the message's end before)
    assert ("unknown parameter(s) split.smal_faces (did you mean split.small_faces?): split has "
            "no parameter 'smal_faces'; 'planerel params split' lists its"
            in capsys.readouterr().err)


@pytest.mark.parametrize("given,said", [
    # usab90: the suggestion in the user's spelling (was "'lying_ris' (did you mean
    # lying_rise?)"), and where the names are listed instead of them all (was "(it has ...")
    ({"relations.lying_ris": "0.02"}, "relations.lying_ris (did you mean relations.lying_rise?)"),
    ({"relation.lying_rise": "0.02"}, "'relation' (did you mean relations?)"),
    ({"gravity.nope": "1"}, "gravity has no parameter 'nope'; 'planerel params gravity'"),
])
def test_a_mistyped_name_is_offered_the_closest_one(given, said):
    from planerel.ilp.model_settings import with_overrides

    with pytest.raises(InputError) as err:
        with_overrides(None, overrides=given)
    assert said in str(err.value)


def test_a_setting_the_model_predates_is_not_called_a_training_value(model_dir, tmp_path):
    """A model written before a setting existed does not record it: it runs at today's
    default, and an override is warned about as differing from that default, not from a
    training value the model never had."""
    import shutil

    from planerel.classify.classifier import Classifier

    old = tmp_path / "old"
    shutil.copytree(model_dir, old)
    data = json.loads((old / "model.json").read_text())
    del data["segmentation"]["resolved"]["split.piece_offset"]
    del data["relations"]["profile_points"]
    (old / "model.json").write_text(json.dumps(data))
    over = {"split.piece_offset": "0", "relations.profile_points": "1000"}
    with Classifier(old / "rules.pl", seg_params=over) as clf:
        w = "\n".join(clf.warnings)
    assert "relations.profile_points=1000 differs from the default 4000 (the model does not " \
           "record relations.profile_points" in w
    assert "segmentation split.piece_offset=0.0 differs from the default 0.005 (the model does " \
           "not record split.piece_offset" in w
    assert "training value" not in w
    # the model as written records both: the same overrides are training-value warnings
    with Classifier(model_dir / "rules.pl", seg_params=over) as clf:
        w = "\n".join(clf.warnings)
    assert "relations.profile_points=1000 differs from the model's training value 4000" in w
    assert "segmentation split.piece_offset=0.0 differs from the model's training value 0.005" in w
