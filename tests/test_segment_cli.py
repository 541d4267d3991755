"""``planerel segment`` and ``planerel evaluate-seg``."""

import json

import numpy as np

from planerel.cli import main
from planerel.segment._scenes import staircase


def test_segment_and_evaluate_cli(tmp_path, capsys):
    cloud, gt, _, _ = staircase(160, 120, seed=0)
    np.save(tmp_path / "scan.npy", cloud.xyz)
    np.save(tmp_path / "gt.npy", gt)
    out = tmp_path / "out"
    assert main(["segment", str(tmp_path / "scan.npy"), "-o", str(out),
                 "--param", "theta=15"]) == 0
    assert "planes" in capsys.readouterr().out
    lab = np.load(out / "scan.labels.npy")
    assert lab.dtype == np.int32 and lab.shape == (120, 160)
    assert (out / "scan.labels.png").stat().st_size > 0
    meta = json.loads((out / "scan.planes.json").read_text())
    assert len(meta["planes"]) == lab.max() + 1
    first = meta["planes"][0]
    assert {"id", "normal", "offset", "n_points"} <= set(first)
    assert first["n_points"] == int((lab == 0).sum())
    assert main(["evaluate-seg", str(out / "scan.labels.npy"), str(tmp_path / "gt.npy"),
                 "--tolerance", "0.8"]) == 0
    score = json.loads(capsys.readouterr().out)
    assert score["correct"] >= 10 and score["n_gt"] == 11 and score["sparse"] == 0


def test_segment_cli_ransac_and_subsample(tmp_path, capsys):
    cloud = staircase(160, 120, seed=0)[0]
    np.save(tmp_path / "scan.npy", cloud.xyz)
    assert main(["segment", str(tmp_path / "scan.npy"), "-o", str(tmp_path / "o"),
                 "--method", "sp", "--param", "threshold=0.02", "--subsample", "2"]) == 0
    assert np.load(tmp_path / "o" / "scan.labels.npy").shape == (60, 80)


def test_segment_cli_bad_input_is_one_line_and_exit_2(tmp_path, capsys):
    cloud = staircase(80, 60, seed=0)[0]
    np.save(tmp_path / "scan.npy", cloud.xyz)
    assert main(["segment", str(tmp_path / "scan.npy"), "-o", str(tmp_path / "o"),
                 "--param", "theta=95"]) == 2
    err = capsys.readouterr().err
    assert "theta" in err and err.count("\n") == 1
    assert main(["segment", str(tmp_path / "scan.npy"), "-o", str(tmp_path / "o"),
                 "--param", "theta"]) == 2
    assert "name=value" in capsys.readouterr().err
    assert main(["segment", str(tmp_path / "missing.npy"), "-o", str(tmp_path / "o")]) == 2
    assert "no such file" in capsys.readouterr().err
