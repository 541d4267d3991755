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
