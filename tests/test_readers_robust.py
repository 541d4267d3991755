"""Every reader, given anything: a valid result or one InputError sentence naming the file.

Property-based (hypothesis): random bytes, truncated and byte-mutated versions of real files
(Kinect TIFF and PCD, MOSD PCD, SegComp ABW) and of small PNG / PCD / PLY / NPY files made here.
Then the specific failures of issue 18, each with the sentence it must give.
"""

from __future__ import annotations

import json
import struct
import zlib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from planerel.errors import InputError
from planerel.io import readers as io
from planerel.io.cloud import Cloud
from planerel.io.writers import write_depth_png, write_ply

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"

FUZZ = settings(max_examples=30, deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.function_scoped_fixture,
                                       HealthCheck.too_slow])


def _small_files(folder: Path) -> dict[str, bytes]:
    """Valid small files of every format, made here: name -> bytes."""
    folder.mkdir(parents=True, exist_ok=True)
    v, u = np.mgrid[0:12, 0:16]
    depth = (1500 + 10 * v + u).astype(np.uint16)
    write_depth_png(folder / "d.png", depth)
    xyz = np.stack([u * 0.01, v * 0.01, np.full(u.shape, 1.5)], axis=2).reshape(-1, 3)
    write_ply(folder / "p.ply", xyz)
    np.save(folder / "a.npy", xyz.reshape(12, 16, 3))
    header = ("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
              "WIDTH 16\nHEIGHT 12\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 192\nDATA {}\n")
    (folder / "b.pcd").write_bytes(header.format("binary").encode()
                                   + xyz.astype("<f4").tobytes())
    (folder / "t.pcd").write_bytes((header.format("ascii") + "".join(
        f"{x:.3f} {y:.3f} {z:.3f}\n" for x, y, z in xyz)).encode())
    return {p.name: p.read_bytes() for p in folder.iterdir()}


@pytest.fixture(scope="module")
def originals(tmp_path_factory) -> dict[str, bytes]:
    files = _small_files(tmp_path_factory.mktemp("small"))
    if DATA.is_dir():
        for rel in ["kinect/office1.pcd", "mosd/learn0.pcd", "abw/abw.test.6.range",
                    "abw/abw.test.6.gt-seg", "kinect/frame_20121214T142255.814212_depth.tiff"]:
            if (DATA / rel).is_file():
                files[Path(rel).name] = (DATA / rel).read_bytes()
    return files


def _check_one(path: Path, reader) -> str:
    """Run ``reader`` on ``path``; return "ok" or "error"; anything else fails the test."""
    try:
        out = reader(path)
    except InputError as exc:
        msg = str(exc)
        assert "\n" not in msg, msg
        assert path.name in msg, msg
        return "error"
    assert isinstance(out, (Cloud, np.ndarray))
    return "ok"


READERS = {
    "read": lambda p: io.read(p, intrinsics="kinect"),
    "read_label_image": io.read_label_image,
}


def _target(tmp_path: Path, name: str) -> Path:
    return tmp_path / name


@FUZZ
@given(data=st.data())
def test_truncated_files_give_a_result_or_one_sentence(originals, tmp_path, data):
    name = data.draw(st.sampled_from(sorted(originals)))
    blob = originals[name]
    cut = data.draw(st.integers(0, len(blob)))
    path = _target(tmp_path, name)
    path.write_bytes(blob[:cut])
    _check_one(path, READERS["read"])


@FUZZ
@given(data=st.data())
def test_mutated_files_give_a_result_or_one_sentence(originals, tmp_path, data):
    name = data.draw(st.sampled_from(sorted(originals)))
    blob = bytearray(originals[name])
    # mutate mostly the first bytes, where the headers are
    n = data.draw(st.integers(1, 8))
    for _ in range(n):
        where = data.draw(st.one_of(st.integers(0, min(600, len(blob) - 1)),
                                    st.integers(0, len(blob) - 1)))
        blob[where] = data.draw(st.integers(0, 255))
    path = _target(tmp_path, name)
    path.write_bytes(bytes(blob))
    reader = READERS[data.draw(st.sampled_from(sorted(READERS)))]
    _check_one(path, reader)


@FUZZ
@given(data=st.data())
def test_header_numbers_replaced_give_a_result_or_one_sentence(originals, tmp_path, data):
    """Numbers in text headers (PCD, PLY, NPY) replaced by huge, negative or odd values."""
    name = data.draw(st.sampled_from([n for n in sorted(originals)
                                      if n.endswith((".pcd", ".ply", ".npy"))]))
    blob = originals[name]
    head_end = min(len(blob), 400)
    head = blob[:head_end].decode("latin-1")
    import re

    numbers = [m.span() for m in re.finditer(r"-?\d+", head)]
    a, b = data.draw(st.sampled_from(numbers))
    value = data.draw(st.sampled_from(["0", "-1", "3", "8", "99999999999", "100000",
                                       "1e9", "x", ""]))
    path = _target(tmp_path, name)
    path.write_bytes((head[:a] + value + head[b:]).encode("latin-1") + blob[head_end:])
    _check_one(path, READERS["read"])


@FUZZ
@given(blob=st.binary(max_size=2000),
       magic=st.sampled_from([b"", b"\x89PNG\r\n\x1a\n", b"II*\x00", b"\x93NUMPY\x01\x00",
                              b"ply\n", b"# .PCD v0.7\n", struct.pack(">I", 0x59A66A95)]),
       suffix=st.sampled_from([".png", ".tiff", ".npy", ".ply", ".pcd", ".range", ".gt-seg"]))
def test_random_bytes_give_one_sentence(tmp_path, blob, magic, suffix):
    path = tmp_path / f"abw.test.3{suffix}"
    path.write_bytes(magic + blob)
    for reader in READERS.values():
        _check_one(path, reader)


# ----------------------------------------------------------------- the failures of issue 18

PCD_HEAD = ("VERSION 0.7\nFIELDS x y z\nSIZE {size}\nTYPE {type}\nCOUNT 1 1 1\nWIDTH {w}\n"
            "HEIGHT 1\nPOINTS {n}\nDATA {data}\n")


def _raw(tmp_path, blob: bytes) -> Path:
    p = tmp_path / "cloud.pcd"
    p.write_bytes(blob)
    return p


def _pcd(tmp_path, payload=b"", size="4 4 4", type_="F F F", w=2, n=2, data="binary"):
    p = tmp_path / "cloud.pcd"
    p.write_bytes(PCD_HEAD.format(size=size, type=type_, w=w, n=n, data=data).encode() + payload)
    return p


@pytest.mark.parametrize("case, match", [
    ("empty", "the PCD file is empty"),
    ("bad_type", "TYPE of field 'x' must be F, I or U; got 'Q'"),
    ("truncated_header", "header ends before its DATA line"),
    ("negative_width", "WIDTH and HEIGHT must be positive"),
    ("unknown_data", "DATA must be ascii, binary, binary_compressed; got 'zipped'"),
    ("bad_size", "TYPE F with SIZE 3"),
    ("float64_as_f4", "SIZE or TYPE is wrong"),
    ("truncated_data", "truncated"),
])
def test_pcd_errors_are_one_sentence(tmp_path, case, match):
    pts = np.array([[0.1, 0.2, 1.0], [0.3, 0.4, 1.5]])
    f4 = pts.astype("<f4").tobytes()
    path = {
        "empty": lambda: _raw(tmp_path, b""),
        "bad_type": lambda: _pcd(tmp_path, f4, type_="Q F F"),
        "truncated_header": lambda: _raw(tmp_path, PCD_HEAD.format(
            size="4 4 4", type="F F F", w=2, n=2, data="binary")[:40].encode()),
        "negative_width": lambda: _pcd(tmp_path, f4, w=-2),
        "unknown_data": lambda: _pcd(tmp_path, f4, data="zipped"),
        "bad_size": lambda: _pcd(tmp_path, f4, size="3 4 4"),
        "float64_as_f4": lambda: _pcd(tmp_path, pts.astype("<f8").tobytes()),
        "truncated_data": lambda: _pcd(tmp_path, f4[:10]),
    }[case]()
    with pytest.raises(InputError, match=match) as err:
        io.read(path)
    assert "\n" not in str(err.value) and "cloud.pcd" in str(err.value)


def _png_header_only(path: Path, width: int, height: int) -> Path:
    """A PNG whose header declares ``width x height`` 16-bit grey pixels (no real pixel data):
    what a reader sees before it decodes anything."""
    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body
                + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))

    ihdr = struct.pack(">IIBBBBB", width, height, 16, 0, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr)
                     + chunk(b"IDAT", zlib.compress(b"\x00" * 64)) + chunk(b"IEND", b""))
    return path


def test_giant_png_is_refused_before_decoding(tmp_path):
    path = _png_header_only(tmp_path / "giant.png", 12000, 12000)
    with pytest.raises(InputError, match=r"giant\.png: the PNG declares 144,000,000 points, more "
                                         r"than the limit of 20,000,000; raise it with --max-points"):
        io.read(path, intrinsics="kinect")
    # the limit is a parameter: a 640x480 frame passes 307,200 and fails 307,199
    v, u = np.mgrid[0:480, 0:640]
    write_depth_png(tmp_path / "f.png", (1000 + u + v).astype(np.uint16))
    assert io.read(tmp_path / "f.png", intrinsics="kinect", max_points=307_200).shape == (480, 640)
    with pytest.raises(InputError, match="more than the limit of 307,199"):
        io.read(tmp_path / "f.png", intrinsics="kinect", max_points=307_199)


def test_max_points_option_of_the_cli(tmp_path, capsys):
    from planerel.cli import main

    v, u = np.mgrid[0:48, 0:64]
    write_depth_png(tmp_path / "f.png", (1000 + u + v).astype(np.uint16))
    assert main(["segment", str(tmp_path / "f.png"), "--intrinsics", "kinect",
                 "--max-points", "3000", "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "declares 3,072 points, more than the limit of 3,000" in err
    assert err.count("\n") == 1


def test_npy_header_claiming_a_huge_array(tmp_path):
    path = tmp_path / "huge.npy"
    header = "{'descr': '<f8', 'fortran_order': False, 'shape': (100000, 100000, 3), }"
    header += " " * (118 - len(header)) + "\n"
    path.write_bytes(b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode()
                     + b"\x00" * 64)
    with pytest.raises(InputError, match=r"huge\.npy: the \.npy header declares "
                                         r"10,000,000,000 points"):
        io.read(path)
    with pytest.raises(InputError, match=r"declares \(100000, 100000, 3\) float64 "
                                         r"\(240000000000 bytes\) but the file holds 64"):
        io.read(path, max_points=10**11)


@pytest.mark.parametrize("shape", [(1, 1), (1, 40), (40, 1)])
def test_thin_png_is_read_as_an_image(tmp_path, shape):
    write_depth_png(tmp_path / "thin.png", np.full(shape, 1500, np.uint16))
    assert io.read_depth_array(tmp_path / "thin.png").shape == shape
    with pytest.raises(InputError, match=r"thin\.png: no Kinect preset"):  # not 640x480 / k
        io.read(tmp_path / "thin.png", intrinsics="kinect")


def test_sidecar_errors_name_the_json(tmp_path):
    write_depth_png(tmp_path / "s.depth.png", np.full((8, 8), 1500, np.uint16))
    side = tmp_path / "s.json"
    for content, match in [({"intrinsics": {"fx": "a", "fy": 1, "cx": 1, "cy": 1}}, "needs numbers"),
                           ({"intrinsics": [8, 8, 5, 5]}, "6 values"),
                           ({"intrinsics": [8, 8, 5, 5, 4, 4], "depth_scale": -1}, "depth_scale"),
                           ({"intrinsics": [8, 8, 5, 5, 4, 4], "up": [0, 1]}, "'up' must be")]:
        side.write_text(json.dumps(content))
        with pytest.raises(InputError, match=match) as err:
            io.read(tmp_path / "s.depth.png")
        assert str(err.value).startswith(str(side)), err.value


@pytest.mark.skipif(not (DATA / "abw" / "abw.test.6.range").is_file(), reason="no ABW data")
def test_abw_image_number_without_calibration(tmp_path):
    (tmp_path / "abw.test.999.range").write_bytes((DATA / "abw" / "abw.test.6.range").read_bytes())
    with pytest.raises(InputError, match=r"abw\.test\.999\.range: SegComp has no ABW image 999"):
        io.read(tmp_path / "abw.test.999.range")


def test_os_errors_memory_and_encoding_are_one_sentence():
    import errno

    from planerel.errors import user_message

    full = OSError(errno.ENOSPC, "No space left on device", "/out/s0001.depth.png")
    assert user_message(full) == ("/out/s0001.depth.png: No space left on device; free some "
                                  "space or write somewhere else")
    ro = PermissionError(errno.EACCES, "Permission denied", "/ro/model")
    assert user_message(ro).startswith("/ro/model: Permission denied; choose a folder")
    assert user_message(MemoryError()).startswith("out of memory")
    enc = UnicodeEncodeError("utf-8", "\udcff", 0, 1, "surrogates not allowed")
    assert "UTF-8" in user_message(enc)
    assert user_message(ValueError("bug")) is None


def test_unwritable_output_folder_is_one_sentence(tmp_path, capsys):
    """An output "folder" below a file (ENOTDIR; a read-only folder gives EACCES the same way,
    but root, who runs these tests, may write anywhere)."""
    from planerel.cli import main

    v, u = np.mgrid[0:48, 0:64]
    write_depth_png(tmp_path / "f.png", (1000 + u + v).astype(np.uint16))
    (tmp_path / "afile").write_text("x")
    assert main(["segment", str(tmp_path / "f.png"), "--intrinsics", "kinect",
                 "-o", str(tmp_path / "afile" / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err and "afile" in err


def test_pcd_page_padding_is_read(tmp_path):
    """PCL's binary writer maps whole pages, so a real file (Kinect v2 clouds saved by PCL) can
    end in zero bytes after the declared points: read as PCL reads it. Non-zero extra bytes are
    still refused (SIZE or TYPE wrong)."""
    pts = np.array([[0.1, 0.2, 1.0], [0.3, 0.4, 1.5]])
    f4 = pts.astype("<f4").tobytes()
    cloud = io.read(_pcd(tmp_path, f4 + bytes(4096 - 24)))
    assert np.allclose(cloud.xyz.reshape(-1, 3), pts, atol=1e-6)
    with pytest.raises(InputError, match="SIZE or TYPE is wrong"):
        io.read(_pcd(tmp_path, f4 + b"\x01" + bytes(100)))
