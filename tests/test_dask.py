"""The batch commands on a Dask cluster (a 2-worker LocalCluster): the same code path as the
local pool, the same results."""

from __future__ import annotations

import json

import numpy as np
import pytest

from planerel.cli import main

distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def cluster():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as c:
        yield c


@pytest.fixture(scope="module")
def scans(tmp_path_factory):
    d = tmp_path_factory.mktemp("set")
    assert main(["dataset", "synth", str(d), "--n-box", "1", "--n-stairs", "1", "--n-ramp", "1",
                 "--seed", "4", "--quiet"]) == 0
    return d


@pytest.mark.slow
def test_segment_describe_classify_on_a_local_cluster_match_local_runs(cluster, scans, tmp_path,
                                                                        capsys):
    addr = cluster.scheduler_address
    local, dask = tmp_path / "local", tmp_path / "dask"
    assert main(["segment", str(scans), "-o", str(local), "-j", "1", "--formats", "npy"]) == 0
    assert main(["segment", str(scans), "-o", str(dask), "--scheduler", addr,
                 "--formats", "npy"]) == 0
    for i in range(3):
        assert np.array_equal(np.load(local / f"s000{i}.labels.npy"),
                              np.load(dask / f"s000{i}.labels.npy"))
    assert main(["describe", str(scans), "-o", str(local / "f.pl"), "-j", "1"]) == 0
    assert main(["describe", str(scans), "-o", str(dask / "f.pl"), "--scheduler", addr]) == 0
    assert (local / "f.pl").read_bytes() == (dask / "f.pl").read_bytes()
    rules = tmp_path / "rules.pl"
    rules.write_text("ramp(A) :- has_plane(A, B), orientation(B, inclined).\n")
    capsys.readouterr()
    answers = []
    for extra in (["-j", "1"], ["--scheduler", addr]):
        assert main(["classify", str(rules), str(scans), "--json", *extra]) == 0
        answers.append([{k: v for k, v in a.items() if k != "seconds"}
                        for a in json.loads(capsys.readouterr().out)])
    assert answers[0] == answers[1] and len(answers[0]) == 3


def test_keep_going_on_a_cluster(cluster, scans, tmp_path, capsys):
    bad = tmp_path / "bad.npy"
    np.save(bad, np.zeros(5))
    out = tmp_path / "seg"
    argv = ["segment", str(scans / "s0000.depth.png"), str(bad), "-o", str(out),
            "--scheduler", cluster.scheduler_address, "--formats", "npy"]
    assert main(argv) == 2
    assert "bad.npy" in capsys.readouterr().err
    assert main(argv + ["--keep-going"]) == 1
    assert (out / "s0000.labels.npy").is_file()
    assert (out / "errors.tsv").read_text().splitlines()[1].startswith(str(bad))


def test_unreachable_scheduler_is_one_line(tmp_path, capsys, scans, monkeypatch):
    monkeypatch.setenv("PLANEREL_DASK_TIMEOUT", "2")
    assert main(["segment", str(scans / "s0000.depth.png"), "-o", str(tmp_path),
                 "--scheduler", "tcp://127.0.0.1:9"]) == 2
    err = capsys.readouterr().err
    assert "cannot reach the Dask scheduler tcp://127.0.0.1:9" in err and err.count("\n") == 1
