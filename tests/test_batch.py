"""Batches: folders and globs as input, --jobs, --keep-going, streamed facts, progress lines."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from planerel.batch import expand_inputs, run_batch
from planerel.cli import main
from planerel.errors import InputError


@pytest.fixture(scope="module")
def scans(tmp_path_factory):
    """A 4-scene synthetic data set at 160x120 (box, stairs, ramp, box)."""
    d = tmp_path_factory.mktemp("set")
    assert main(["dataset", "synth", str(d), "--n-box", "2", "--n-stairs", "1", "--n-ramp", "1",
                 "--seed", "3", "--quiet"]) == 0
    return d


def _square(x):
    if x == 3:
        raise InputError(f"task {x}: three is refused")
    return x * x


def test_expand_inputs_files_folders_globs(scans, tmp_path):
    # a data-set folder gives its depth images in manifest order
    assert [p.name for p in expand_inputs([scans])] == [f"s000{i}.depth.png" for i in range(4)]
    # a plain folder gives its scans, not label / result images, sorted by name
    plain = tmp_path / "plain"
    plain.mkdir()
    for name in ["b.pcd", "a.depth.png", "a.gt.png", "a.labels.png", "a.labels.npy", "notes.txt",
                 "c.range", ".hidden.png"]:
        (plain / name).write_bytes(b"x")
    assert [p.name for p in expand_inputs([plain])] == ["a.depth.png", "b.pcd", "c.range"]
    # globs, sorted; an explicit file is taken whatever its name
    assert [p.name for p in expand_inputs([str(scans / "s000[13].depth.png"),
                                           plain / "notes.txt"])] == [
        "s0001.depth.png", "s0003.depth.png", "notes.txt"]
    with pytest.raises(InputError, match="no file matches"):
        expand_inputs([str(tmp_path / "*.nothing")])
    with pytest.raises(InputError, match="no such file or folder"):
        expand_inputs([tmp_path / "missing.png"])
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputError, match="holds no scan"):
        expand_inputs([tmp_path / "empty"])


def test_a_glob_leaves_out_label_and_other_files_with_a_note(scans, tmp_path):
    """user89: ``classify MODEL "data/test/*.png"`` read the data set's ``*.gt.png`` label
    images as depth in millimetres; a glob's matches are now filtered as a folder's are."""
    from planerel.errors import PlanerelWarning

    with pytest.warns(PlanerelWarning, match=r"left out 4 file\(s\).*s0000\.gt\.png"):
        got = expand_inputs([str(scans / "*.png")])
    assert [p.name for p in got] == [f"s000{i}.depth.png" for i in range(4)]
    notes = tmp_path / "notes"
    notes.mkdir()
    (notes / "README.md").write_text("x")
    with pytest.raises(InputError, match="matches no scan"):
        expand_inputs([str(notes / "*")])
    assert expand_inputs([notes / "README.md"]) == [notes / "README.md"]  # named: taken


@pytest.mark.parametrize("jobs", [1, 2])
def test_run_batch_keeps_order_and_collects_failures(jobs):
    from planerel.batch import BatchResult

    res = BatchResult()
    got = list(run_batch(_square, list(range(7)), jobs=jobs, keep_going=True, result=res,
                         window=2, progress=False))
    assert got == [(x, x * x) for x in range(7) if x != 3]
    assert [(f.input, f.message) for f in res.failures] == [("3", "task 3: three is refused")]
    assert res.n_done == 6 and res.n_tasks == 7
    with pytest.raises(InputError, match="three is refused.*--keep-going"):
        list(run_batch(_square, list(range(7)), jobs=jobs, progress=False))


def test_segment_folder_keep_going_writes_good_results_and_error_list(scans, tmp_path, capsys):
    folder = tmp_path / "in"
    folder.mkdir()
    for i in (0, 2):
        for suffix in (".depth.png", ".json"):
            (folder / f"s000{i}{suffix}").write_bytes((scans / f"s000{i}{suffix}").read_bytes())
    np.save(folder / "broken.npy", np.zeros(5))  # a 1-D array is no scan
    out = tmp_path / "out"
    assert main(["segment", str(folder), "-o", str(out), "--jobs", "2"]) == 2
    err = capsys.readouterr().err
    assert "broken.npy" in err and "--keep-going" in err and err.count("\n") == 1
    assert main(["segment", str(folder), "-o", str(out), "--jobs", "2", "--keep-going"]) == 1
    err = capsys.readouterr().err
    assert "1 of 3 inputs failed" in err
    for i in (0, 2):
        assert np.load(out / f"s000{i}.labels.npy").max() >= 1
        assert json.loads((out / f"s000{i}.planes.json").read_text())["planes"]
    rows = (out / "errors.tsv").read_text().splitlines()
    assert rows[0] == "input\treason" and len(rows) == 2
    assert rows[1].startswith(str(folder / "broken.npy") + "\t")
    # a clean run removes the stale list
    assert main(["segment", str(folder / "s0000.depth.png"), "-o", str(out), "-k"]) == 0
    assert not (out / "errors.tsv").exists()


def test_jobs_do_not_change_results(scans, tmp_path):
    one, two = tmp_path / "one", tmp_path / "two"
    assert main(["segment", str(scans), "-o", str(one), "--jobs", "1"]) == 0
    assert main(["segment", str(scans), "-o", str(two), "--jobs", "2"]) == 0
    for i in range(4):
        a, b = np.load(one / f"s000{i}.labels.npy"), np.load(two / f"s000{i}.labels.npy")
        assert np.array_equal(a, b)
    assert main(["describe", str(scans), "-o", str(one / "f.pl"), "-j", "1"]) == 0
    assert main(["describe", str(scans), "-o", str(two / "f.pl"), "-j", "2"]) == 0
    assert (one / "f.pl").read_bytes() == (two / "f.pl").read_bytes()


def test_streamed_facts_equal_the_whole_text(scans, tmp_path):
    """FactsWriter, one scene at a time, writes what facts_text writes for all at once."""
    from planerel.features.facts import FactParams, FactsWriter, describe_scene, facts_text
    from planerel.io import readers as io
    from planerel.segment import segment

    descs = []
    for i in range(4):
        cloud = io.read(scans / f"s000{i}.depth.png")
        descs.append(describe_scene(cloud, segment(cloud).labels, scene_id=f"s000{i}"))
    for params in (FactParams(), FactParams(pairs="all", planner=False)):
        with FactsWriter(tmp_path / "f.pl", params, header="h") as w:
            for d in descs:
                w.add(d)
        assert (tmp_path / "f.pl").read_text() == facts_text(descs, params, header="h")
    with FactsWriter(tmp_path / "f.pl", header="h") as w:
        w.add(descs[0])
        w.note("s0000: noted")
    assert (tmp_path / "f.pl").read_text() == facts_text(descs[:1], header="h\ns0000: noted")
    with pytest.raises(InputError, match="occurs twice"), FactsWriter(tmp_path / "g.pl") as w:
        w.add(descs[0])
        w.add(descs[0])
    assert not (tmp_path / "g.pl").exists()
    assert [p.name for p in tmp_path.iterdir()] == ["f.pl"]  # no spool left behind


def test_describe_keep_going_and_classify_jobs(scans, tmp_path, capsys):
    bad = tmp_path / "bad.npy"
    np.save(bad, np.zeros(5))
    out = tmp_path / "f.pl"
    assert main(["describe", str(scans / "s0000.depth.png"), str(bad), "-o", str(out), "-k"]) == 1
    text = out.read_text()
    assert "scene(s0000)." in text and "bad" not in text.split("\n", 1)[1]
    assert (tmp_path / "f.pl.errors.tsv").read_text().count("\n") == 2
    capsys.readouterr()
    rules = tmp_path / "rules.pl"
    rules.write_text("box(A) :- nvertical(A, B), B >= 2.\nramp(A) :- ninclined(A, B), B >= 1.\n")
    answers = {}
    for jobs in ("1", "2"):
        assert main(["classify", str(rules), str(scans), "--json", "-j", jobs]) == 0
        answers[jobs] = json.loads(capsys.readouterr().out)
    strip = [{k: v for k, v in a.items() if k != "seconds"} for a in answers["1"]]
    assert strip == [{k: v for k, v in a.items() if k != "seconds"} for a in answers["2"]]
    assert [a["scene"] for a in answers["1"]] == ["s0000", "s0001", "s0002", "s0003"]


def test_progress_lines_when_not_on_a_terminal(scans, tmp_path):
    r = subprocess.run([sys.executable, "-m", "planerel.cli", "segment", str(scans), "-o",
                        str(tmp_path / "o"), "-j", "1"], capture_output=True, text=True,
                       env={**__import__("os").environ, "PLANEREL_PROGRESS_SECONDS": "0"},
                       timeout=120)
    assert r.returncode == 0, r.stderr
    lines = [ln for ln in r.stderr.splitlines() if ln.startswith("segment: ")]
    assert [ln.split(" scenes")[0] for ln in lines[:4]] == [f"segment: {i}/4" for i in range(1, 5)]
