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


def test_planes_json_and_facts_header_report_the_noise_model(tmp_path, capsys):
    cloud = staircase(160, 120, seed=0)[0]  # Kinect-like noise 0.0012 z^2
    np.save(tmp_path / "scan.npy", cloud.xyz)
    assert main(["segment", str(tmp_path / "scan.npy"), "-o", str(tmp_path / "o")]) == 0
    info = json.loads((tmp_path / "o" / "scan.planes.json").read_text())["info"]
    assert info["noise_model"]["kind"] == "z2"
    assert abs(info["noise_model"]["quad_per_m"] - 0.0012) < 0.0003
    assert info["settings"]["adapted"] is True
    assert info["settings"]["min_region_size"] == info["min_region_size"]
    # an override and a preset still win
    assert main(["segment", str(tmp_path / "scan.npy"), "-o", str(tmp_path / "p"),
                 "--param", "min_region_size=200", "--param", "preset=kinect"]) == 0
    info = json.loads((tmp_path / "p" / "scan.planes.json").read_text())["info"]
    assert info["min_region_size"] == 200 and info["settings"]["adapted"] is False
    assert main(["describe", str(tmp_path / "scan.npy"), "-o", str(tmp_path / "f.pl")]) == 0
    head = (tmp_path / "f.pl").read_text().splitlines()[:3]
    assert any(line.startswith("% scan: depth noise z2, sigma") and "adapted to it" in line
               for line in head)


def test_segment_cli_split_and_refine_params_as_segment_keywords(tmp_path, capsys):
    """``--param split=...`` / ``refine=...`` do what segment()'s keywords do (split is no
    parameter-class field): same labels, and the post-processing ran (``split_tested`` in the
    planes' info) exactly when asked or by default."""
    from planerel.io.cloud import Cloud
    from planerel.segment import segment

    np.save(tmp_path / "scan.npy", staircase(160, 120, seed=0)[0].xyz)
    cloud = Cloud(np.load(tmp_path / "scan.npy"))
    for name, method, params, kw, post in [
        ("default", "regiongrow", (), {}, True),
        ("nosplit", "regiongrow", ("split=false",), {"split": False}, False),
        ("paper", "regiongrow", ("refine=false", "split=false", "angle_order=paper"),
         {"refine": False, "split": False, "angle_order": "paper"}, False),
        ("paper_split", "regiongrow", ("preset=paper", "split=true"),
         {"preset": "paper", "split": True}, True),
        ("sp_split", "sp", ("split=1",), {"split": True}, True),
    ]:
        args = ["segment", str(tmp_path / "scan.npy"), "-o", str(tmp_path / name), "--method",
                method, "--formats", "npy,json"]
        for p in params:
            args += ["--param", p]
        assert main(args) == 0, name
        info = json.loads((tmp_path / name / "scan.planes.json").read_text())["info"]
        want = segment(cloud, method, **kw)
        assert ("split_tested" in info) is post and ("split_tested" in want.info) is post, name
        np.testing.assert_array_equal(np.load(tmp_path / name / "scan.labels.npy"), want.labels,
                                      err_msg=name)
    capsys.readouterr()
    assert main(["segment", str(tmp_path / "scan.npy"), "-o", str(tmp_path / "bad"),
                 "--param", "split=maybe"]) == 2
    err = capsys.readouterr().err
    assert "split" in err and err.count("\n") == 1
