"""A model of several members (``planerel learn --members K``): the partition, learning, the
vote, the command line (real swipl, real learner, real rule queries)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from planerel.cli import main
from planerel.errors import InputError
from planerel.ilp import pipeline as P
from planerel.ilp.members import check_members, member_folders, partition_scenes, vote
from planerel.synth.generator import generate_dataset


@pytest.fixture(scope="module")
def paper_set(tmp_path_factory):
    """6 box, 6 stairs, 6 ramp paper-world scenes at 160x120."""
    out = tmp_path_factory.mktemp("ds") / "train"
    generate_dataset(out, n_box=6, n_stairs=6, n_ramp=6, seed=5, size=(640, 480), subsample=4)
    return out


@pytest.fixture(autouse=True)
def _private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("PLANEREL_CACHE", str(tmp_path / "cache"))


@pytest.fixture(scope="module")
def members_model(paper_set, tmp_path_factory):
    """The paper set learned as 3 members with -j 1 (and its metrics)."""
    out = tmp_path_factory.mktemp("m") / "model3"
    lines: list[str] = []
    m = P.learn_model(paper_set, out, method="gt", jobs=1, engine="builtin", members=3,
                      log=lines.append, cache="none")
    return out, m, lines


# ----------------------------------------------------------------------------- the partition


def test_partition_is_disjoint_stratified_and_deterministic():
    scenes = [(f"s{i:04d}", k) for i, k in enumerate(["box"] * 7 + ["stairs"] * 5 + ["ramp"] * 6)]
    # interleave the classes: the rank counts within a class, whatever the order
    mixed = scenes[::2] + scenes[1::2]
    parts = partition_scenes(mixed, 3)
    assert parts == partition_scenes(mixed, 3)
    assert set(parts) == {s for s, _ in scenes} and set(parts.values()) == {0, 1, 2}
    for k, n in (("box", 7), ("stairs", 5), ("ramp", 6)):
        sizes = [sum(1 for s, c in scenes if c == k and parts[s] == p) for p in range(3)]
        assert sum(sizes) == n and max(sizes) - min(sizes) <= 1, (k, sizes)
    # the rank within a class, mod K, in the order given
    boxes = [s for s, k in mixed if k == "box"]
    assert [parts[s] for s in boxes] == [i % 3 for i in range(len(boxes))]
    assert partition_scenes(mixed, 1) == {s: 0 for s, _ in mixed}
    with pytest.raises(InputError, match="listed twice"):
        partition_scenes([("s1", "box"), ("s1", "box")], 2)


@pytest.mark.parametrize("bad, msg", [(0, "at least 1"), (-2, "at least 1"), (2.5, "whole"),
                                      (True, "whole"), (5, "class stairs has only 4 scene")])
def test_bad_member_counts_are_refused(bad, msg):
    with pytest.raises(InputError, match=msg) as err:
        check_members(bad, {"box": 6, "stairs": 4, "ramp": 5})
    assert "\n" not in str(err.value)
    assert check_members(4, {"box": 6, "stairs": 4}) == 4


def test_bad_members_are_refused_before_any_scene_is_described(paper_set, tmp_path, monkeypatch,
                                                               capsys):
    import planerel.ilp.pipeline as pipeline

    def no(*a, **k):
        raise AssertionError("a scene was described")

    monkeypatch.setattr(pipeline, "describe_scenes", no)
    for k, msg in ((0, "at least 1"), (7, "class box has only 6 scene")):
        with pytest.raises(InputError, match=msg):
            P.learn_model(paper_set, tmp_path / "m", method="gt", jobs=1, members=k)
    with pytest.raises(InputError, match="--folds"):
        P.learn_model(paper_set, tmp_path / "m", method="gt", jobs=1, members=2, folds=3)
    assert main(["learn", str(paper_set), "-o", str(tmp_path / "m"), "--members", "9"]) != 0
    err = capsys.readouterr().err
    assert "--members 9: class box has only 6 scene(s)" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "m").exists()


# ----------------------------------------------------------------------------- the vote


def test_vote_plurality_then_summed_precision_then_other_then_first_member():
    # two of three say stairs: stairs, from the stairs member with the higher precision
    assert vote([("stairs", 0.9), ("box", 0.99), ("stairs", 0.95)]) == ("stairs", 2)
    # a tie of two classes: the larger summed precision wins
    assert vote([("box", 0.9), ("stairs", 0.8), ("stairs", 0.7), ("box", 0.5)]) == ("stairs", 1)
    # an 'other' that no rule answered counts 0 in the sum
    assert vote([("other", None), ("box", 0.6)]) == ("box", 1)
    # an 'other' proved by a rule for other counts its precision
    assert vote([("other", 0.9), ("box", 0.6)]) == ("other", 0)
    # equal sums: 'other' first, else the class of the first member
    assert vote([("box", 0.8), ("other", 0.8)]) == ("other", 1)
    assert vote([("ramp", 0.8), ("box", 0.8)]) == ("ramp", 0)
    # among the winner's members, the first of equal precisions
    assert vote([("box", 0.8), ("box", 0.8), ("ramp", 0.9)]) == ("box", 0)
    assert vote([("box", 0.7)]) == ("box", 0)
    with pytest.raises(InputError):
        vote([])


def test_voted_predictions_take_rule_and_bindings_from_the_winning_member():
    a = P.Prediction("o1", "box", "box(A) :- r1(A).", 1, {"A": "o1", "B": "s_p1"},
                     (("box", 1),), 0.8)
    b = P.Prediction("o1", "ramp", "ramp(A) :- r2(A).", 2, {"A": "o1"}, (("ramp", 2),), 0.9)
    c = P.Prediction("o1", "box", "box(A) :- r3(A).", 1, {"A": "o1", "B": "s_p2"},
                     (("box", 1), ("ramp", 3)), 0.85)
    [v] = P._voted([[a], [b], [c]])
    assert (v.klass, v.member, v.rule, v.bindings, v.precision) == (
        "box", 2, "box(A) :- r3(A).", {"A": "o1", "B": "s_p2"}, 0.85)
    assert v.votes == (a, b, c)
    assert v.fired == (("box", (0, 1)), ("ramp", (1, 2)), ("box", (2, 1)), ("ramp", (2, 3)))


# ----------------------------------------------------------------------------- learning


def test_members_model_folder(members_model, paper_set):
    out, m, lines = members_model
    top = json.loads((out / "model.json").read_text())
    assert top["members"] == ["members/1", "members/2", "members/3"] and "plurality" in top["vote"]
    assert m["members"] == 3 and m["n_scenes"] == 18
    # the whole set's counts are the members' counts summed (each scene in one part)
    assert m["n_examples"] == sum(mm["n_examples"] for mm in m["member_models"]) == 18
    assert m["n_other"] == sum(mm["n_other"] for mm in m["member_models"])
    assert member_folders(out / "rules.pl") == [out / "members" / str(n) for n in (1, 2, 3)]
    manifest = [ln.split(",")[:2] for ln in (paper_set / "manifest.csv").read_text().splitlines()[1:]]
    parts = partition_scenes([(s, k) for s, k in manifest], 3)
    seen = []
    for n in (1, 2, 3):
        folder = out / "members" / str(n)
        for name in ("rules.pl", "model.json", "metrics.json", "aleph/box.b", "aleph/ramp.f"):
            assert (folder / name).is_file(), (n, name)
        mm = json.loads((folder / "metrics.json").read_text())
        # each member learned on its own part: two scenes of each class
        assert mm["scenes"] == [s for s, _ in manifest if parts[s] == n - 1]
        assert mm["n_scenes"] == 6 and mm["n_examples"] == 6
        seen += mm["scenes"]
        assert "planerel_rule_stats(" in (folder / "rules.pl").read_text()
        assert m["member_models"][n - 1]["rules"] == mm["rules"]
    assert sorted(seen) == sorted(s for s, _ in manifest)
    # progress per member on the log
    for n in (1, 2, 3):
        assert f"[member {n}/3] learning on 6 scenes" in lines
        assert any(ln.startswith(f"[member {n}/3] learned ") for ln in lines)
    # the top-level rules.pl: every member's rules under a header, plain clauses
    text = (out / "rules.pl").read_text()
    for n in (1, 2, 3):
        assert f"% ======== member {n} (members/{n}/rules.pl)" in text
        for rules in m["member_models"][n - 1]["rules"].values():
            for r in rules:
                assert r in text
    assert not any(ln.startswith(":-") for ln in text.splitlines())


def test_members_learned_with_two_jobs_are_the_same(members_model, paper_set, tmp_path):
    out, m, _ = members_model
    two = tmp_path / "model3j2"
    m2 = P.learn_model(paper_set, two, method="gt", jobs=2, engine="builtin", members=3,
                       log=lambda s: None, cache="none")
    assert [x["rules"] for x in m2["member_models"]] == [x["rules"] for x in m["member_models"]]
    for n in (1, 2, 3):
        assert (two / "members" / str(n) / "rules.pl").read_text().replace(str(two), "") == \
            (out / "members" / str(n) / "rules.pl").read_text().replace(str(out), "")
    assert (two / "rules.pl").read_text().replace(str(two), "") == \
        (out / "rules.pl").read_text().replace(str(out), "")


def test_the_top_level_rules_read_as_data(members_model, tmp_path):
    """Alone (without its model.json), the top-level rules.pl loads as a plain rules file:
    no directive, only clauses of the classes."""
    from planerel.classify.classifier import Classifier

    out, m, _ = members_model
    alone = tmp_path / "alone"
    alone.mkdir()
    shutil.copy(out / "rules.pl", alone / "rules.pl")
    with Classifier(alone) as clf:
        assert set(clf.classes) == set(m["classes"])
        assert clf.stats == ()


# ----------------------------------------------------------------------------- classifying


def _scans(paper_set):
    scenes = sorted(paper_set.glob("s*.depth.png"))
    return scenes


def test_members_classify_by_vote_with_votes_in_json(members_model, paper_set, capsys):
    from planerel.classify.classifier import Classifier

    out, _, _ = members_model
    scans = _scans(paper_set)[:6]
    assert main(["classify", str(out), *map(str, scans), "--json", "-j", "1"]) == 0
    answers = json.loads(capsys.readouterr().out)
    singles = []
    for n in (1, 2, 3):
        assert main(["classify", str(out / "members" / str(n)), *map(str, scans), "--json",
                     "-j", "1"]) == 0
        singles.append(json.loads(capsys.readouterr().out))
    n_obj = 0
    for i, a in enumerate(answers):
        for j, o in enumerate(a["objects"]):
            n_obj += 1
            own = [s[i]["objects"][j] for s in singles]
            assert [v["class"] for v in o["votes"]] == [x["class"] for x in own]
            assert [v["rule"] for v in o["votes"]] == [x["rule"] for x in own]
            klass, member = vote([(x["class"], x["precision"] if x["rule"] else None)
                                  for x in own])
            assert o["class"] == klass and o["member"] == member + 1
            chosen = own[member]
            for key in ("rule", "rule_index", "precision", "bindings", "proof_planes", "fired",
                        "refused", "planes", "planar_fraction"):
                assert o[key] == chosen[key], key
            assert "votes" not in own[0]
    assert n_obj >= 6
    # the text output names each member's class
    assert main(["classify", str(out), str(scans[0]), "-j", "1"]) == 0
    text = capsys.readouterr().out
    o = answers[0]["objects"][0]
    assert (f"    votes:  {', '.join(v['class'] for v in o['votes'])} (members 1-3; the rule is "
            f"member {o['member']}'s)") in text.splitlines()
    with Classifier(out / "rules.pl") as clf:
        assert len(clf.members) == 3
        ans = clf.classify(scans[0], scene_id=scans[0].name.split(".")[0])
        assert ans.to_dict()["objects"] == answers[0]["objects"]
    assert clf.module is None and all(mm.module is None for mm in clf.members)


def test_a_one_member_model_answers_exactly_as_a_plain_one(paper_set, tmp_path, capsys):
    """--members 1 is today's model: the same files, the same answers, the same JSON."""
    plain, one = tmp_path / "plain", tmp_path / "one"
    P.learn_model(paper_set, plain, method="gt", jobs=1, engine="builtin", log=lambda s: None)
    assert main(["learn", str(paper_set), "-o", str(one), "--method", "gt", "-j", "1",
                 "--engine", "builtin", "--members", "1"]) == 0
    capsys.readouterr()
    assert not (one / "members").exists()
    for name in ("rules.pl", "model.json"):
        assert (one / name).read_text().replace(str(one), "") == \
            (plain / name).read_text().replace(str(plain), ""), name
    scans = list(map(str, _scans(paper_set)[::4]))
    got = []
    for model in (plain, one):
        assert main(["classify", str(model), *scans, "--json", "-j", "1"]) == 0
        got.append([{k: v for k, v in a.items() if k != "seconds"}
                    for a in json.loads(capsys.readouterr().out)])
    assert got[0] == got[1]
    assert all("votes" not in o for a in got[0] for o in a["objects"])


def test_held_out_scores_of_members_are_their_vote(members_model, paper_set, tmp_path):
    held = tmp_path / "held"
    generate_dataset(held, n_box=2, n_stairs=2, n_ramp=2, seed=78, size=(640, 480), subsample=4)
    from planerel.ilp.scenes import describe_scenes

    models = []
    out, _, _ = members_model
    for n in (1, 2, 3):
        models.append(_load(out / "members" / str(n)))
    members = P.Members(tuple(models))
    res = P.held_out_scores(members, held, method="gt", jobs=1, cache="none")
    descs, _ = describe_scenes(held, method="gt", jobs=1, cache="none")
    objs = [o.id for d in descs for o in d.objects if o.klass]
    each = [{p.object_id: p for p in P.prolog_predict(m, descs, objs)} for m in models]
    want = {o: vote([(e[o].klass, e[o].precision if e[o].rule else None) for e in each])[0]
            for o in objs}
    assert res["predictions"] == want and res["n_scenes"] == 6
    assert res["errors"]["n"] == len(objs)


def _load(folder: Path) -> P.Model:
    """A member folder back as a Model (its rules and statistics from metrics.json and
    model.json)."""
    mm = json.loads((folder / "metrics.json").read_text())
    js = json.loads((folder / "model.json").read_text())
    return P.Model(tuple(mm["classes"]), {k: tuple(v) for k, v in mm["rules"].items()},
                   tuple(tuple(s) for s in mm["rule_stats"]),
                   planar_domain=tuple((e["class"], e["low"], e["high"], e["n"])
                                       for e in js["planar_domain"]),
                   proof_domain=tuple((e["rule"], e["class"], e["low"], e["high"], e["n"])
                                      for e in js["proof_domain"]))


def test_a_members_model_warns_once_what_its_members_warn(members_model):
    from planerel.classify.classifier import Classifier

    out, _, _ = members_model
    over = {"decision.planar_margin": "0.5"}
    with Classifier(out / "members" / "1", seg_params=over) as one:
        single = one.warnings
    # learned from ground-truth planes, and an override: each said once, as a member says it
    assert len(single) == 2
    with Classifier(out, seg_params=over) as clf:
        assert clf.warnings == single
