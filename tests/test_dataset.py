"""The data-set format (planerel.features.dataset) and ``planerel dataset synth`` / ``info``."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from planerel.cli import main
from planerel.errors import InputError
from planerel.features.dataset import (
    MANIFEST,
    ManifestRow,
    iter_scenes,
    load_dataset_info,
    load_manifest,
    load_metadata,
    load_scene,
    write_label_png,
    write_manifest,
    write_scene,
)
from planerel.io import readers as io
from planerel.synth.generator import generate_dataset, generate_scene, scene_seed

SMALL_ARGS = ["--n-box", "1", "--n-stairs", "2", "--n-ramp", "1", "--size", "320x240",
              "--subsample", "4", "--quiet"]


@pytest.fixture(scope="module")
def small_set(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("synth") / "set"
    assert main(["dataset", "synth", str(out), "--seed", "3", *SMALL_ARGS]) == 0
    return out


def _files(folder: Path) -> dict:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def test_cli_writes_a_loadable_data_set(small_set, capsys):
    rows = load_manifest(small_set)
    assert [r.scene_id for r in rows] == ["s0000", "s0001", "s0002", "s0003"]
    assert [r.klass for r in rows] == ["box", "stairs", "stairs", "ramp"]
    assert all((r.width, r.height) == (80, 60) for r in rows)
    names = {p.name for p in small_set.iterdir()}
    assert names == {MANIFEST, "dataset.json"} | {
        f"s000{i}.{ext}" for i in range(4) for ext in ("depth.png", "gt.png", "json")}
    for row, cloud, labels, meta in iter_scenes(small_set):
        assert cloud.shape == (60, 80) and labels.shape == (60, 80) and labels.dtype == np.int32
        assert cloud.intrinsics.fx == pytest.approx(525.0 / 8) and cloud.up is not None
        assert meta["class"] == row.klass and meta["seed"] == row.seed == scene_seed(3, int(row.scene_id[1:]))
        np.testing.assert_array_equal(labels >= 0, cloud.valid)
        # labelled pixels lie on their plane (loose: the noise bound is tested in test_synth)
        for pl in meta["planes"]:
            mask = labels == pl["index"]
            assert mask.sum() == pl["n_pixels"]
            if mask.any():
                res = cloud.xyz[mask] @ np.array(pl["normal"]) + pl["offset"]
                assert np.median(np.abs(res)) < 0.02
        np.testing.assert_allclose(cloud.up, meta["up"])
    info = load_dataset_info(small_set)
    assert info["counts"] == {"box": 1, "stairs": 2, "ramp": 1} and info["seed"] == 3
    assert main(["dataset", "info", str(small_set)]) == 0
    out = capsys.readouterr().out
    assert "4 scenes" in out and "stairs 2" in out


def test_loaded_scene_equals_the_generated_scene(small_set):
    row = load_manifest(small_set)[1]
    scene = generate_scene(row.klass, row.seed, size=(320, 240), subsample=4, scene_id=row.scene_id)
    cloud, labels, meta = load_scene(small_set, row.scene_id)
    np.testing.assert_array_equal(labels, scene.gt_labels)
    np.testing.assert_array_equal(cloud.xyz, scene.cloud.xyz)
    assert meta == json.loads(json.dumps({**scene.metadata(), "files": meta["files"]}))
    # the generic reader finds the sidecar by itself
    plain = io.read(small_set / row.depth)
    assert plain.intrinsics == cloud.intrinsics
    np.testing.assert_array_equal(plain.xyz, cloud.xyz)
    np.testing.assert_allclose(plain.up, scene.up)
    np.testing.assert_array_equal(io.read_label_image(small_set / row.labels), scene.gt_labels)


def test_same_seed_gives_byte_identical_files(tmp_path, small_set):
    again = tmp_path / "again"
    assert main(["dataset", "synth", str(again), "--seed", "3", *SMALL_ARGS]) == 0
    assert _files(again) == _files(small_set)
    other = tmp_path / "other"
    generate_dataset(other, 1, 2, 1, seed=4, size=(320, 240), subsample=4)
    assert _files(other)[MANIFEST] != _files(small_set)[MANIFEST]
    assert not any(p.name.startswith(".") for p in again.iterdir())  # no temp files left


def test_manifest_round_trip(tmp_path):
    rows = [ManifestRow("s0000", "box", 12, 160, 120, "s0000.depth.png", "s0000.gt.png", "s0000.json"),
            ManifestRow("real1", "stairs", None, 640, 480, "x.png", "", "x.json")]
    write_manifest(tmp_path, rows)
    assert load_manifest(tmp_path) == tuple(rows)
    with pytest.raises(InputError, match="duplicate scene ids"):
        write_manifest(tmp_path, rows + rows[:1])


def test_label_png_round_trip(tmp_path):
    lab = np.array([[-1, 0, 1], [300, 2, -1]], dtype=np.int32)
    write_label_png(tmp_path / "l.png", lab)
    np.testing.assert_array_equal(io.read_label_image(tmp_path / "l.png"), lab)
    with pytest.raises(InputError, match="labels must lie in -1..65534"):
        write_label_png(tmp_path / "bad.png", np.array([[-2]]))


def _copy(src: Path, dst: Path) -> Path:
    dst.mkdir()
    for p in src.iterdir():
        (dst / p.name).write_bytes(p.read_bytes())
    return dst


def test_missing_and_corrupt_data_sets_raise_input_error(tmp_path, small_set):
    with pytest.raises(InputError, match="data-set folder does not exist"):
        load_manifest(tmp_path / "nope")
    (tmp_path / "file.txt").write_text("x")
    with pytest.raises(InputError, match="a data set is a folder"):
        load_manifest(tmp_path / "file.txt")
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputError, match="not a data set \\(no manifest.csv\\)"):
        load_manifest(tmp_path / "empty")
    with pytest.raises(InputError, match="no scene 's9999'"):
        load_scene(small_set, "s9999")

    bad = _copy(small_set, tmp_path / "bad_header")
    (bad / MANIFEST).write_text("id,klass\ns0000,box\n")
    with pytest.raises(InputError, match="manifest header must be"):
        load_manifest(bad)

    bad = _copy(small_set, tmp_path / "bad_row")
    text = (bad / MANIFEST).read_text().replace(",80,60,", ",eighty,60,", 1)
    (bad / MANIFEST).write_text(text)
    with pytest.raises(InputError, match="line 2: seed, width and height must be integers"):
        load_manifest(bad)

    bad = _copy(small_set, tmp_path / "no_depth")
    (bad / "s0001.depth.png").unlink()
    with pytest.raises(InputError, match="s0001.depth.png: depth image of scene s0001 is missing"):
        load_scene(bad, "s0001")

    bad = _copy(small_set, tmp_path / "corrupt_depth")
    (bad / "s0001.depth.png").write_bytes(b"\x89PNG\r\n\x1a\n" + b"garbage")
    with pytest.raises(InputError, match="s0001.depth.png: cannot read the image"):
        load_scene(bad, "s0001")

    bad = _copy(small_set, tmp_path / "corrupt_json")
    (bad / "s0002.json").write_text("{not json")
    with pytest.raises(InputError, match="s0002.json: cannot read the scene sidecar"):
        load_metadata(bad, "s0002")

    bad = _copy(small_set, tmp_path / "no_intrinsics")
    meta = json.loads((bad / "s0002.json").read_text())
    del meta["intrinsics"]
    (bad / "s0002.json").write_text(json.dumps(meta))
    with pytest.raises(InputError, match="lacks 'intrinsics'"):
        load_scene(bad, "s0002")

    bad = _copy(small_set, tmp_path / "small_labels")
    write_label_png(bad / "s0003.gt.png", np.zeros((6, 8), dtype=np.int32))
    with pytest.raises(InputError, match="label image is 8x6 but the depth image is 80x60"):
        load_scene(bad, "s0003")


def test_write_scene_then_load(tmp_path):
    scene = generate_scene("ramp", 5, size=(320, 240), subsample=2, scene_id="s0042")
    row = write_scene(tmp_path, scene)
    write_manifest(tmp_path, [row])
    cloud, labels, meta = load_scene(tmp_path, "s0042")
    assert meta["class"] == "ramp" and meta["planes"][0]["id"] == "s0042_p00"
    np.testing.assert_array_equal(labels, scene.gt_labels)
    np.testing.assert_allclose(np.array(meta["pose"]["world_to_camera"]), scene.pose)


@pytest.mark.parametrize("argv,match", [
    (["--size", "640-480"], "--size must look like 640x480"),
    (["--size", "10x10"], r"size 10x10 subsampled by 4 gives 3x3 images; both sides must stay >= 8"),
    (["--n-box", "-1"], "number of box scenes must be a non-negative integer"),
    (["--n-box", "0", "--n-stairs", "0", "--n-ramp", "0"], "at least one scene"),
    (["--camera-height", "1.5"], "--camera-height must be two numbers"),
    (["--camera-distance", "2,1"], "camera distance must be a finite"),
    (["--max-range", "-3"], "sensor max range"),
    (["--sensor", "tof", "--noise", "0.002"], "--noise sets the basic sensor's noise"),
])
def test_cli_bad_options_exit_2_with_one_line(tmp_path, capsys, argv, match):
    assert main(["dataset", "synth", str(tmp_path / "x"), "--quiet", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    import re

    assert re.search(match, err), err


@pytest.mark.parametrize("profile", ["structured-light", "tof"])
def test_cli_sensor_profile_is_used_and_recorded(tmp_path, profile):
    out = tmp_path / profile
    assert main(["dataset", "synth", str(out), "--sensor", profile, "--max-range", "4.0",
                 *SMALL_ARGS]) == 0
    info = load_dataset_info(out)
    assert info["sensor"]["profile"] == {"structured-light": "structured-light",
                                         "tof": "time-of-flight"}[profile]
    assert info["sensor"]["max_range"] == 4.0
    for _row, cloud, labels, meta in iter_scenes(out):
        assert meta["sensor"] == info["sensor"]
        assert np.nanmax(cloud.xyz[..., 2]) <= 4.0
        # flying pixels: valid depth without a plane label
        assert np.all(cloud.valid[labels >= 0])
