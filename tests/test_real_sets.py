"""benchmarks/real_sets.py: a labelled real set captured as a manifest (no data) and rebuilt
bit for bit from the repositories it came from, with real git repositories made here."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

import real_sets  # noqa: E402


def _repo(root: Path, owner: str, name: str, files: dict) -> Path:
    """A clone-layout repository ``root/owner/name`` with ``files`` committed."""
    top = root / owner / name
    top.mkdir(parents=True)
    for rel, data in files.items():
        (top / rel).parent.mkdir(parents=True, exist_ok=True)
        (top / rel).write_bytes(data)
    git = ["git", "-C", str(top), "-c", "user.name=t", "-c", "user.email=t@t"]
    subprocess.run(git[:3] + ["init", "-q"], check=True)
    subprocess.run(git + ["add", "."], check=True)
    subprocess.run(git + ["commit", "-qm", "data"], check=True)
    return top


@pytest.fixture
def world(tmp_path):
    depth = bytes(range(256)) * 40          # binary: not UTF-8
    cloud = b"\x00\x01PCD" * 5000
    mirrors = tmp_path / "mirrors"
    _repo(mirrors, "lab", "frames", {"data/scene0/depth.png": depth, "README": b"hi\n"})
    _repo(mirrors, "other", "clouds", {"pcds/a.pcd": cloud})
    labels = {"set": "s", "frames": [{"file": "depth.png", "objects": [
        {"class": "box", "box": [1, 2, 30, 40], "what": "a carton"}]}]}
    folder = tmp_path / "set"
    (folder / "sub").mkdir(parents=True)
    (folder / "depth.png").write_bytes(depth)
    (folder / "sub" / "a.pcd").write_bytes(cloud)
    (folder / "depth.json").write_text('{"intrinsics": "64,40,50,50,32,20"}\n')
    (folder / "labels.json").write_text(json.dumps(labels))
    (folder / "NOTES.md").write_text("# s\nsource: lab/frames\n")
    return tmp_path, mirrors, folder, labels


def test_a_set_is_captured_by_content_and_rebuilt_bit_for_bit(world):
    tmp, mirrors, folder, labels = world
    doc = real_sets.capture(str(folder), "huntX/s", str(mirrors))
    by_file = {f["file"]: f for f in doc["files"]}
    assert set(by_file) == {"depth.png", "depth.json", "sub/a.pcd"}
    assert by_file["depth.png"]["repo"] == "lab/frames"
    assert by_file["depth.png"]["path"] == "data/scene0/depth.png"
    assert len(by_file["depth.png"]["commit"]) == 40
    assert by_file["sub/a.pcd"]["repo"] == "other/clouds"
    assert by_file["depth.json"]["text"].startswith('{"intrinsics"')   # our sidecar, inline
    assert doc["labels"] == labels and doc["notes"].startswith("# s")
    # no data in the manifest: only ids, paths and our own text
    assert len(json.dumps(doc)) < 2000
    out = Path(real_sets.build(doc, str(tmp / "dest"), real_sets.git_dirs(str(mirrors))))
    assert out == tmp / "dest" / "huntX" / "s"
    for rel in ("depth.png", "sub/a.pcd", "depth.json", "NOTES.md"):
        assert (out / rel).read_bytes() == (folder / rel).read_bytes(), rel
    assert json.loads((out / "labels.json").read_text()) == labels


def test_bare_mirrors_are_read_as_the_fetch_tool_leaves_them(world):
    tmp, mirrors, folder, _ = world
    bare = tmp / "bare"
    bare.mkdir()
    for owner, name in (("lab", "frames"), ("other", "clouds")):
        subprocess.run(["git", "clone", "-q", "--bare", str(mirrors / owner / name),
                        str(bare / f"{owner}+{name}" / "repo")], check=True)
    repos = real_sets.git_dirs(str(bare))
    assert set(repos) == {"lab/frames", "other/clouds"}
    doc = real_sets.capture(str(folder), "huntX/s", str(bare))
    out = Path(real_sets.build(doc, str(tmp / "dest"), repos))
    assert (out / "depth.png").read_bytes() == (folder / "depth.png").read_bytes()


def test_a_converted_data_file_is_refused_at_capture(world):
    tmp, mirrors, folder, _ = world
    (folder / "made.npy").write_bytes(b"\x93NUMPY" + bytes(range(256)) * 10)
    with pytest.raises(real_sets.SetError, match="made.npy"):
        real_sets.capture(str(folder), "huntX/s", str(mirrors))


def test_a_missing_repository_or_blob_is_named_and_the_old_folder_kept(world):
    tmp, mirrors, folder, _ = world
    doc = real_sets.capture(str(folder), "huntX/s", str(mirrors))
    repos = real_sets.git_dirs(str(mirrors))
    out = Path(real_sets.build(doc, str(tmp / "dest"), repos))
    with pytest.raises(real_sets.SetError, match="other/clouds"):
        real_sets.build(doc, str(tmp / "dest"), {"lab/frames": repos["lab/frames"]})
    broken = json.loads(json.dumps(doc))
    next(f for f in broken["files"] if f["file"] == "depth.png")["blob"] = "0" * 40
    with pytest.raises(real_sets.SetError, match="lacks"):
        real_sets.build(broken, str(tmp / "dest"), repos)
    # the folder built before is whole, and no temporary folder is left
    assert (out / "depth.png").read_bytes() == (folder / "depth.png").read_bytes()
    assert sorted(p.name for p in (tmp / "dest" / "huntX").iterdir()) == ["s"]


def test_the_command_line_writes_and_lists_manifests(world, tmp_path, monkeypatch, capsys):
    _, mirrors, folder, _ = world
    monkeypatch.setattr(real_sets, "MANIFESTS", str(tmp_path / "manifests"))
    assert real_sets.main(["capture", str(folder), "huntX/s", "--mirrors", str(mirrors)]) == 0
    assert (tmp_path / "manifests" / "huntX--s.json").exists()
    assert real_sets.main(["list"]) == 0
    assert "huntX/s (development): 3 files from lab/frames, other/clouds" in capsys.readouterr().out
    assert real_sets.main(["build", str(tmp_path / "d"), "--mirrors", str(mirrors)]) == 0
    assert real_sets.main(["build", str(tmp_path / "d"), "--mirrors", str(tmp_path / "none")]) == 1
    assert "no such folder" in capsys.readouterr().err


def test_a_file_a_later_commit_removed_is_found_in_the_commit_that_had_it(world):
    tmp, mirrors, folder, _ = world
    top = mirrors / "lab" / "frames"
    git = ["git", "-C", str(top), "-c", "user.name=t", "-c", "user.email=t@t"]
    old = subprocess.run(git + ["rev-parse", "HEAD"], capture_output=True, text=True,
                         check=True).stdout.strip()
    subprocess.run(git + ["rm", "-q", "data/scene0/depth.png"], check=True)
    subprocess.run(git + ["commit", "-qm", "moved away"], check=True)
    doc = real_sets.capture(str(folder), "huntX/s", str(mirrors))
    f = next(f for f in doc["files"] if f["file"] == "depth.png")
    assert (f["repo"], f["commit"], f["path"]) == ("lab/frames", old, "data/scene0/depth.png")
    out = Path(real_sets.build(doc, str(tmp / "dest"), real_sets.git_dirs(str(mirrors))))
    assert (out / "depth.png").read_bytes() == (folder / "depth.png").read_bytes()


def test_check_says_which_file_of_a_built_set_differs(world):
    tmp, mirrors, folder, _ = world
    (folder / "labels.json").unlink()                 # a set its script scores: no labels
    doc = real_sets.capture(str(folder), "huntX/s", str(mirrors))
    assert doc["labels"] is None
    real_sets.build(doc, str(tmp / "dest"), real_sets.git_dirs(str(mirrors)))
    assert real_sets.check(doc, str(tmp / "dest")) == []
    assert not (tmp / "dest" / "huntX" / "s" / "labels.json").exists()
    (tmp / "dest" / "huntX" / "s" / "sub" / "a.pcd").write_bytes(b"changed")
    (tmp / "dest" / "huntX" / "s" / "depth.json").unlink()
    assert real_sets.check(doc, str(tmp / "dest")) == ["depth.json: missing", "sub/a.pcd: differs"]


def test_a_made_file_is_rebuilt_from_its_source_by_its_converter(tmp_path):
    import io

    import numpy as np

    depth = np.linspace(0.3, 1.2, 64 * 48, dtype=np.float32).reshape(48, 64)
    buf = io.BytesIO()
    np.save(buf, np.array({"depth": depth, "image": np.zeros((48, 64, 3), np.uint8)}),
            allow_pickle=True)
    mirrors = tmp_path / "mirrors"
    _repo(mirrors, "lab", "dicts", {"demo/frame.npy": buf.getvalue()})
    folder = tmp_path / "set"
    folder.mkdir()
    np.save(folder / "frame_depth.npy", depth)
    (folder / "frame_rgb.png").write_bytes(b"\x89PNG not kept")
    (folder / "MADE.json").write_text(json.dumps({
        "frame_depth.npy": {"repo": "lab/dicts", "path": "demo/frame.npy",
                            "convert": "npy_dict:depth"},
        "frame_rgb.png": {"skip": "to look at"}}))
    doc = real_sets.capture(str(folder), "huntX/d", str(mirrors))
    assert [f["file"] for f in doc["files"]] == ["frame_depth.npy"]
    assert doc["files"][0]["convert"] == "npy_dict:depth"
    out = Path(real_sets.build(doc, str(tmp_path / "dest"), real_sets.git_dirs(str(mirrors))))
    assert np.array_equal(np.load(out / "frame_depth.npy"), depth)
    assert real_sets.check(doc, str(tmp_path / "dest")) == []
    # a file the converter does not make from that source is refused at capture
    np.save(folder / "frame_depth.npy", depth + 1)
    with pytest.raises(real_sets.SetError, match="is not npy_dict:depth"):
        real_sets.capture(str(folder), "huntX/d", str(mirrors))


def test_a_pickle_that_asks_for_more_than_arrays_is_refused():
    import pickle

    import numpy as np

    class Boom:
        def __reduce__(self):
            return (print, ("ran",))

    header = b"\x93NUMPY\x01\x00"
    text = "{'descr': '|O', 'fortran_order': False, 'shape': (), }"
    text += " " * (64 - 10 - 1 - len(text)) + "\n"
    data = header + len(text).to_bytes(2, "little") + text.encode() + pickle.dumps(
        np.array(Boom(), dtype=object))
    with pytest.raises(real_sets.SetError, match="refused"):
        real_sets._restricted_npy_object(data)


def test_the_f200_decoding_undoes_the_rotation_and_fills_only_smooth_holes():
    import io

    import numpy as np
    from PIL import Image

    depth = np.full((6, 8), 8000, np.uint16)          # 0.8 m in 0.1 mm
    depth[:, 4:] = 8100
    depth[2, 2] = 0                                     # a grid hole on a smooth surface
    depth[4, 4] = 0                                     # a hole between 0.8 and 0.81 m: filled
    depth[:2, :4] = 3000                                # a step of 0.5 m beside a hole ...
    depth[0, 4] = 3000
    depth[1, 4] = 0                                     # ... bridged neither way
    stored = ((depth << 3) | (depth >> 13)).astype(np.uint16)   # the toolbox's encoding
    buf = io.BytesIO()
    Image.fromarray(stored).save(buf, format="PNG")
    got = np.array(Image.open(io.BytesIO(real_sets._f200_depth(buf.getvalue()))))
    want = depth.copy()
    want[2, 2] = 8000
    want[4, 4] = 8050
    assert want[1, 4] == 0 and np.array_equal(got, want)


def test_the_kinect_raw_disparity_becomes_metres_by_the_repositorys_formula():
    import io

    import numpy as np

    raw = np.array([[2047, 696, 900], [1000, 1084, 300]], np.uint16)
    buf = io.BytesIO()
    np.save(buf, raw)
    got = real_sets._npy(real_sets.convert("kinect_raw_depth", buf.getvalue()))
    cm = np.tan(raw / 1024 + 0.5) * 33.825 + 5.7          # gui/kinect.py's formula
    assert got.dtype == np.float32
    assert got[0, 0] == 0 and got[1, 2] == 0              # no data; nearer than its 80 cm table
    assert cm[1, 1] > 400 and got[1, 1] == 0              # farther than its 4 m table
    assert 0.8 <= cm[0, 1] / 100 and np.isclose(got[0, 1], cm[0, 1] / 100)
    assert np.isclose(got[1, 0], cm[1, 0] / 100) and got[0, 2] > got[0, 1]
    nan = np.array([[np.nan, 1.5]], np.float32)
    buf = io.BytesIO()
    np.save(buf, nan)
    assert real_sets._npy(real_sets.convert("npy_nan_to_zero", buf.getvalue())).tolist() == [[0.0, 1.5]]


def test_a_nyu_raw_pgm_becomes_metres_by_open3ds_formula():
    import numpy as np

    raw = np.array([[0, 600, 1000], [1092, 1093, 2047]], np.uint16)
    pgm = b"P5\n# a comment\n3 2\n65535\n" + raw.astype("<u2").tobytes()   # NYU's byte order
    got = real_sets._npy(real_sets.convert("nyu_pgm", pgm))
    want = 351.3 / (1092.5 - raw.astype(np.float64))      # Open3D's CreateFromNYUFormat
    assert got.dtype == np.float32 and got.shape == (2, 3)
    assert np.isclose(got[0, 1], want[0, 1]) and np.isclose(got[0, 2], want[0, 2])
    assert got[0, 2] > got[0, 1] > got[0, 0] > 0           # larger disparity value, farther
    assert got[1, 0] == 0                                  # 702 m: past the 7 m truncation
    assert got[1, 1] == 0 and got[1, 2] == 0               # past the formula's range: none
    with pytest.raises(real_sets.SetError, match="16-bit binary PGM"):
        real_sets.convert("nyu_pgm", b"P5\n3 2\n255\n" + bytes(6))
    with pytest.raises(real_sets.SetError, match="could not read"):
        real_sets.convert("nyu_pgm", b"P5\n3 2\n65535\n" + bytes(4))   # truncated


def test_a_matlab_cloud_and_a_one_channel_array_are_converted(tmp_path):
    import io

    import numpy as np
    from scipy.io import savemat

    cloud = np.zeros((4, 5, 3))
    cloud[1:, :, 2] = 1.5
    cloud[1:, :, 0] = 0.25
    savemat(tmp_path / "c.mat", {"cloud2": cloud})
    got = real_sets._npy(real_sets.convert("mat_cloud:cloud2", (tmp_path / "c.mat").read_bytes()))
    assert np.isnan(got[0]).all() and np.array_equal(got[1:], cloud[1:])   # (0, 0, 0): no data
    buf = io.BytesIO()
    np.save(buf, np.arange(6, dtype=np.float32).reshape(2, 3, 1))
    assert real_sets._npy(real_sets.convert("npy_squeeze", buf.getvalue())).shape == (2, 3)
    with pytest.raises(real_sets.SetError, match="no converter"):
        real_sets.convert("gzip", b"")


def test_float64_metres_npz_arrays_and_millimetres_are_converted():
    import io

    import numpy as np
    from PIL import Image

    depth = np.array([[0.0, 0.66025], [0.9435, 1.13025]])   # L515 steps of 0.25 mm
    buf = io.BytesIO()
    np.save(buf, depth)
    got = real_sets._npy(real_sets.convert("npy_float32", buf.getvalue()))
    assert got.dtype == np.float32 and np.allclose(got, depth, atol=1e-6)
    buf = io.BytesIO()
    np.savez(buf, depth=depth.astype(np.float32), rgb=np.zeros((2, 2, 3), np.uint8))
    got = real_sets._npy(real_sets.convert("npz_key:depth", buf.getvalue()))
    assert got.dtype == np.float32 and got.shape == (2, 2) and got[1, 1] == np.float32(1.13025)
    with pytest.raises(real_sets.SetError, match="could not read its source"):
        real_sets.convert("npz_key:colour", buf.getvalue())   # no such array: one line
    buf = io.BytesIO()
    Image.fromarray(np.array([[0, 943], [1130, 65000]], np.uint16)).save(buf, format="PNG")
    got = real_sets._npy(real_sets.convert("mm_to_m", buf.getvalue()))
    assert got.dtype == np.float32 and got[0, 0] == 0 and got[0, 1] == np.float32(0.943)
    buf = io.BytesIO()
    np.save(buf, np.array([[500, 0]], np.uint16))
    assert real_sets._npy(real_sets.convert("mm_to_m", buf.getvalue()))[0, 0] == np.float32(0.5)
    buf = io.BytesIO()
    np.save(buf, depth)   # float metres are no millimetres: refused, one line
    with pytest.raises(real_sets.SetError, match="16-bit"):
        real_sets.convert("mm_to_m", buf.getvalue())


def test_matlab_millimetres_and_a_structs_millimetre_cloud_are_converted(tmp_path):
    import numpy as np
    from scipy.io import savemat

    depth = np.array([[0, 943], [1130, 65000]], np.uint16)
    savemat(tmp_path / "d.mat", {"depth_array": depth})
    got = real_sets._npy(real_sets.convert("mat_mm_to_m:depth_array",
                                           (tmp_path / "d.mat").read_bytes()))
    assert got.dtype == np.float32 and got[0, 0] == 0 and got[1, 0] == np.float32(1.13)
    savemat(tmp_path / "f.mat", {"depth_array": depth.astype(np.float64)})
    with pytest.raises(real_sets.SetError, match="16-bit"):   # metres are no millimetres
        real_sets.convert("mat_mm_to_m:depth_array", (tmp_path / "f.mat").read_bytes())
    xyz = np.zeros((2, 2, 3))
    xyz[..., 2] = [[0, 1200], [800, 2500]]
    xyz[..., 0] = 100
    savemat(tmp_path / "s.mat", {"frame": {"xyz": xyz, "depth": xyz[..., 2].astype(np.uint16)}})
    got = real_sets._npy(real_sets.convert("mat_xyz_mm:frame", (tmp_path / "s.mat").read_bytes()))
    assert got.dtype == np.float64 and np.isnan(got[0, 0]).all()   # depth 0: no data
    assert got[1, 1].tolist() == [0.1, 0.0, 2.5] and got[0, 1, 2] == 1.2
    with pytest.raises(real_sets.SetError, match="could not read its source"):
        real_sets.convert("mat_xyz_mm:scene", (tmp_path / "s.mat").read_bytes())   # no such struct


def test_a_depth_csv_becomes_metres_and_a_ragged_one_is_refused():
    import numpy as np

    text = b"0,1500,2796\r\n65535,0,1111\r\n"   # csv.writer's rows of z16 millimetres
    got = real_sets._npy(real_sets.convert("csv_depth", text))
    assert got.dtype == np.float32 and got.shape == (2, 3)
    assert got[0, 0] == 0 and got[0, 1] == np.float32(1.5) and got[1, 2] == np.float32(1.111)
    assert got[1, 0] == 0   # 65535: z16's no-data value, not 65.5 m
    got = real_sets._npy(real_sets.convert("csv_depth:0.0001", b"0 15000\n20000 5\n"))  # 0.1 mm
    assert got[0, 1] == np.float32(1.5) and got[1, 1] == np.float32(0.0005)
    with pytest.raises(real_sets.SetError, match="equal rows"):
        real_sets.convert("csv_depth", b"1,2,3\n4,5\n")
    with pytest.raises(real_sets.SetError, match="could not read its source"):
        real_sets.convert("csv_depth", b"1,2\nx,4\n")   # not a number: one line


def test_a_disparity_png_becomes_metres_by_its_focal_length_and_baseline():
    import io

    import numpy as np
    from PIL import Image

    buf = io.BytesIO()   # 256 per pixel of disparity: 0 (none), 10 px, 40.25 px
    Image.fromarray(np.array([[0, 2560, 10304]], np.uint16)).save(buf, format="PNG")
    got = real_sets._npy(real_sets.convert("disparity_png:400,0.125", buf.getvalue()))
    assert got.dtype == np.float32 and got.shape == (1, 3) and got[0, 0] == 0
    assert got[0, 1] == np.float32(5.0) and np.isclose(got[0, 2], 400 * 0.125 / 40.25)
    got = real_sets._npy(real_sets.convert("disparity_png:400,0.125,16", buf.getvalue()))
    assert got[0, 1] == np.float32(400 * 0.125 / 160)
    with pytest.raises(real_sets.SetError, match="F,B"):
        real_sets.convert("disparity_png:400", buf.getvalue())
    buf = io.BytesIO()
    Image.fromarray(np.zeros((2, 2), np.uint8)).save(buf, format="PNG")
    with pytest.raises(real_sets.SetError, match="16-bit"):   # an 8-bit picture of disparity
        real_sets.convert("disparity_png:400,0.125", buf.getvalue())


def test_a_mirror_fetched_whole_is_read_through_its_git_folder(world):
    tmp, mirrors, folder, _ = world
    whole = tmp / "whole"
    for owner, name in (("lab", "frames"), ("other", "clouds")):
        subprocess.run(["git", "clone", "-q", str(mirrors / owner / name),
                        str(whole / f"{owner}+{name}" / "repo")], check=True)
    repos = real_sets.git_dirs(str(whole))
    assert repos["lab/frames"].endswith("repo/.git")
    doc = real_sets.capture(str(folder), "huntX/s", str(whole))
    out = Path(real_sets.build(doc, str(tmp / "dest"), repos))
    assert (out / "depth.png").read_bytes() == (folder / "depth.png").read_bytes()


def test_a_corrupt_manifest_or_source_is_one_line_and_the_built_set_is_kept(world, tmp_path,
                                                                             monkeypatch, capsys):
    _, mirrors, folder, _ = world
    with pytest.raises(real_sets.SetError, match="could not read its source"):
        real_sets.convert("f200_depth", b"not a PNG")
    manifests = tmp_path / "manifests"
    monkeypatch.setattr(real_sets, "MANIFESTS", str(manifests))
    assert real_sets.main(["capture", str(folder), "huntX/s", "--mirrors", str(mirrors)]) == 0
    assert real_sets.main(["build", str(tmp_path / "d"), "--mirrors", str(mirrors)]) == 0
    built = (tmp_path / "d" / "huntX" / "s" / "depth.png").read_bytes()
    # built again over itself: replaced whole
    assert real_sets.main(["build", str(tmp_path / "d"), "--mirrors", str(mirrors)]) == 0
    assert (tmp_path / "d" / "huntX" / "s" / "depth.png").read_bytes() == built
    assert sorted(p.name for p in (tmp_path / "d" / "huntX").iterdir()) == ["s"]
    capsys.readouterr()
    (manifests / "huntX--s.json").write_text('{"name": "huntX/s", "files": [')
    assert real_sets.main(["list"]) == 1
    assert capsys.readouterr().err.startswith("error: JSONDecodeError")
