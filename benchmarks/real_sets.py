"""The labelled real development sets, rebuilt from their public repositories by one command.

    .venv/bin/python benchmarks/real_sets.py build DEST --mirrors DIR [--only NAME ...]
    .venv/bin/python benchmarks/real_sets.py capture SET_DIR NAME --mirrors DIR [--role R]
    .venv/bin/python benchmarks/real_sets.py check DEST
    .venv/bin/python benchmarks/real_sets.py list

The real frames planerel is checked on (``real_unseen.py``'s hunts, ``real_tabletop.py``'s and
``real_stairs.py``'s sets) come from public repositories and are never copied into planerel;
the labels drawn on them are ours. A *manifest* (``benchmarks/real_sets/*.json``, one a set
folder) keeps everything but the data: for each file of the folder the repository it came
from, the path and commit it was read at, and its git blob id (the content's hash, so the
file is fetched by content and checked bit for bit); the folder's ``labels.json`` and
``NOTES.md`` as they were. The data itself stays in the repositories.

``build DEST --mirrors DIR`` writes every manifest's folder under ``DEST`` (``DEST/hunt36/
m2t2-real/...``): ``DIR`` holds the repositories, either as ``DIR/owner+name/repo`` (a bare
git directory, as the session's fetch tool leaves them) or ``DIR/owner/name`` (a clone, e.g.
``git clone https://github.com/owner/name DIR/owner/name``). A repository that is missing or
lacks a blob is named in the error, with the path to get; nothing is written for that set
(files are written to a temporary folder that replaces the set's only when all are there).

``capture SET_DIR NAME`` writes the manifest of a labelled folder made by hand: each file is
looked up by its blob id among the repositories of ``DIR`` (in ``HEAD``'s tree, else in the
commit that added it). A file made from a repository's file is named in the folder's
``MADE.json`` (``{"FILE": {"repo": "owner/name", "path": P, "convert": C}}``, with an optional
``"commit"`` when the path held other data at other commits; ``C`` one of ``CONVERTERS``: a dict
pickled in a ``.npy`` reduced to its depth array, RealSense F200 depth decoded, float64 metres
as float32, an ``.npz``'s named array, 16-bit millimetres (a ``.npy``, a PNG or a MATLAB variable) as float32
metres, a MATLAB struct's millimetre cloud as float64 metres, a depth grid kept as CSV/TXT, a
stereo disparity PNG with its focal length and baseline;
``{"FILE": {"skip": "why"}}`` leaves a file out): the capture makes it again and checks it. A file that is in no repository, not made, and no small text file (a sidecar of
ours, kept inline: intrinsics, an up vector) is listed and the capture refused: a set whose
data cannot be fetched back is not reproducible.

``check DEST`` says which sets under ``DEST`` are not bit for bit their manifest's (a file
missing or changed, the labels redrawn).

Why: the machine these sets lived on was reset twice, and each time the sets (frames, labels,
notes) had to be found and labelled again by hand, hours of work, with figures that moved
because the rectangles were redrawn (docs/status.md "Real frames, set by set").
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
MANIFESTS = os.path.join(HERE, "real_sets")
#: files of a set folder that are ours, kept in the manifest itself
OWN = ("labels.json", "NOTES.md", "MADE.json")


class SetError(Exception):
    """A manifest that cannot be captured or built (missing repository, blob or file)."""


def blob_id(data: bytes) -> str:
    """The git blob id (SHA-1 of ``b"blob <size>\\0" + data``) of a file's bytes."""
    return hashlib.sha1(b"blob %d\0" % len(data) + data).hexdigest()


def git_dirs(mirrors: str) -> dict:
    """``{"owner/name": git directory}`` of the repositories under ``mirrors``.

    Both layouts are read: ``owner+name/repo`` (bare, or a clone whose ``.git`` is there) and
    ``owner/name`` (a clone, its ``.git``).
    """
    out = {}
    if not os.path.isdir(mirrors):
        raise SetError(f"{mirrors}: no such folder of repositories")
    for entry in sorted(os.listdir(mirrors)):
        top = os.path.join(mirrors, entry)
        if not os.path.isdir(top):
            continue
        if "+" in entry and os.path.isdir(os.path.join(top, "repo")):
            repo = os.path.join(top, "repo")   # bare, or (fetched whole) a clone with its .git
            out[entry.replace("+", "/", 1)] = (os.path.join(repo, ".git")
                                               if os.path.isdir(os.path.join(repo, ".git")) else repo)
            continue
        for name in sorted(os.listdir(top)):
            git = os.path.join(top, name, ".git")
            if os.path.isdir(git):
                out[f"{entry}/{name}"] = git
    return out


def _git(git_dir: str, *args: str, binary: bool = False):
    res = subprocess.run(["git", f"--git-dir={git_dir}", *args], capture_output=True)
    if res.returncode != 0:
        raise SetError(f"git {' '.join(args)} in {git_dir}: "
                       f"{res.stderr.decode(errors='replace').strip()}")
    return res.stdout if binary else res.stdout.decode()


def tree_index(git_dir: str) -> tuple[str, dict]:
    """The commit of ``HEAD`` and ``{blob id: path}`` of every file in its tree."""
    commit = _git(git_dir, "rev-parse", "HEAD").strip()
    index = {}
    for line in _git(git_dir, "ls-tree", "-r", "-z", "HEAD").split("\0"):
        if not line:
            continue
        meta, path = line.split("\t", 1)
        mode, kind, sha = meta.split()
        if kind == "blob":
            index.setdefault(sha, path)
    return commit, index


def _scan_commits(git_dir: str, sha: str):
    """``(commit, path)`` of the newest commit whose tree holds blob ``sha``, trees read one
    by one (those that cannot be read skipped), or None."""
    for commit in _git(git_dir, "rev-list", "--all").split():
        res = subprocess.run(["git", f"--git-dir={git_dir}", "ls-tree", "-r", "-z", commit],
                             capture_output=True, text=True)
        for line in res.stdout.split("\0"):
            if "\t" in line and line.split("\t", 1)[0].split()[2] == sha:
                return commit, line.split("\t", 1)[1]
    return None


def _find_blobs(shas: set, repos: dict) -> dict:
    """``{blob id: (repo, commit, path)}`` for the blobs found in ``repos``: in the tree of
    ``HEAD`` first, else in any commit that added it (a file a later commit removed)."""
    found = {}
    for repo, git_dir in repos.items():
        left = sorted(shas - set(found))
        if not left:
            break
        try:
            commit, index = tree_index(git_dir)
        except SetError as e:   # a snapshot still being copied in: not a repository yet
            print(f"warning: {repo} skipped: {e}", file=sys.stderr)
            continue
        for sha in left:
            if sha in index:
                found[sha] = (repo, commit, index[sha])
        left = [sha for sha in left if sha not in found]
        if not left:
            continue
        res = subprocess.run(["git", f"--git-dir={git_dir}", "cat-file", "--batch-check"],
                             input="\n".join(left) + "\n", capture_output=True, text=True)
        for line in res.stdout.splitlines():
            sha, kind = (line.split() + ["", ""])[:2]
            if kind != "blob":
                continue
            try:
                log = _git(git_dir, "log", "--all", "--format=commit %H", "--raw",
                           "--no-abbrev", f"--find-object={sha}")
            except SetError:   # a snapshot lacking some objects (files of 4 MiB and more)
                hit = _scan_commits(git_dir, sha)
                if hit:
                    found[sha] = (repo, *hit)
                continue
            commit = None
            for ln in log.splitlines():
                if ln.startswith("commit "):
                    commit = ln.split()[1]
                elif ln.startswith(":") and "\t" in ln:
                    meta, path = ln.split("\t", 1)
                    if meta.split()[3] == sha:   # the commit that added it (its new side)
                        found[sha] = (repo, commit, path)
                        break
    return found


def _restricted_npy_object(data: bytes):
    """The object of a pickled ``.npy`` (``np.save`` of a dict), unpickled with numpy's array
    classes only: a repository's file is data, and a pickle could run anything."""
    import io
    import pickle

    import numpy as np
    from numpy.lib import format as npf

    class Arrays(pickle.Unpickler):
        def find_class(self, module, name):
            if module.split(".")[0] == "numpy" and name in (
                    "_reconstruct", "ndarray", "dtype", "scalar", "_frombuffer"):
                if module.startswith("numpy.core") and hasattr(np, "_core"):
                    module = "numpy._core" + module[len("numpy.core"):]   # numpy 2's name
                return super().find_class(module, name)
            raise SetError(f"a pickled .npy asks for {module}.{name}: refused")

    f = io.BytesIO(data)
    version = npf.read_magic(f)
    header = npf.read_array_header_1_0 if version == (1, 0) else npf.read_array_header_2_0
    shape, _, dtype = header(f)
    if dtype != np.dtype(object):
        raise SetError("not a pickled .npy")
    arr = Arrays(f, encoding="latin1").load()
    return arr.item() if shape == () else arr


def _npy_bytes(arr) -> bytes:
    import io

    import numpy as np

    buf = io.BytesIO()
    np.save(buf, np.asarray(arr))
    return buf.getvalue()


def _png_uint16(img) -> bytes:
    import io

    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(img).save(buf, format="PNG")
    return buf.getvalue()


def _f200_depth(data: bytes) -> bytes:
    """andyzeng/apc-vision-toolbox's RealSense F200 depth PNG as 16-bit depth (0.1 mm): the
    toolbox's encoding (a circular 3-bit left shift) undone, and the one-pixel holes of the
    depth-to-colour registration grid filled (a hole between two valid pixels within 3 % of
    each other, along the row then the column, two passes; 26 % of the pixels valid before,
    44-46 % after). Unfilled, no plane grows on these frames (docs/objects.md, hunt36)."""
    import io

    import numpy as np
    from PIL import Image

    raw = np.array(Image.open(io.BytesIO(data))).astype(np.uint16)
    d = ((raw >> 3) | (raw << 13)).astype(np.float64)
    for _ in range(2):
        out = d.copy()
        left, right, up, down = (np.zeros_like(d) for _ in range(4))
        left[:, 1:], right[:, :-1] = d[:, :-1], d[:, 1:]
        up[1:, :], down[:-1, :] = d[:-1, :], d[1:, :]
        hole = d <= 0
        row = hole & (left > 0) & (right > 0) & (np.abs(left - right) < 0.03 * np.maximum(left, right))
        out[row] = (left[row] + right[row]) / 2
        col = hole & ~row & (up > 0) & (down > 0) & (np.abs(up - down) < 0.03 * np.maximum(up, down))
        out[col] = (up[col] + down[col]) / 2
        d = out
    return _png_uint16(np.round(d).astype(np.uint16))


def _npy(data: bytes):
    import io

    import numpy as np

    return np.load(io.BytesIO(data), allow_pickle=False)


def _mm_array(data: bytes):
    """A 16-bit depth image in millimetres, from a ``.npy`` or a PNG."""
    import io

    import numpy as np
    from PIL import Image

    arr = _npy(data) if data[:6] == b"\x93NUMPY" else np.array(Image.open(io.BytesIO(data)))
    if arr.dtype != np.uint16:
        raise SetError(f"millimetre depth must be 16-bit, not {arr.dtype}")
    return arr


def _kinect_raw_depth(data: bytes) -> bytes:
    """A Kinect v1's raw 11-bit disparity (``uint16``, 2047 = none) as metres (``float32``, 0 =
    none), by PascalLeMerrer/Bug-Arena's own formula (``gui/kinect.py``: cm = tan(raw / 1024 +
    0.5) * 33.825 + 5.7, kept within its 80-400 cm table)."""
    import numpy as np

    raw = _npy(data)
    cm = np.tan(raw.astype(np.float64) / 1024 + 0.5) * 33.825 + 5.7
    keep = (raw != 2047) & (cm >= 80) & (cm <= 400)
    return _npy_bytes(np.where(keep, cm / 100, 0).astype(np.float32))


def _nyu_pgm(data: bytes) -> bytes:
    """A NYU Depth v2 raw depth frame (a binary PGM, ``P5``, of 16-bit values: the Kinect v1's
    raw disparity, 2047 = none) as float32 metres, 0 = none: ``351.3 / (1092.5 - raw)``, the
    conversion Open3D applies (``RGBDImage::CreateFromNYUFormat``), kept within its 7 m
    truncation; a raw value at or over 1092.5 (no depth, or beyond the formula's range) is 0.
    The values are stored little-endian, against the PGM convention (Open3D's example reads
    them big-endian and its C++ swaps the bytes back): read big-endian, a frame's values
    spread over 4-65287 instead of 839-2047.

    Returns
    -------
    bytes
        A ``.npy`` of the image's shape ``(H, W)``.
    """
    import re

    import numpy as np

    head = re.match(rb"P5\s+(?:#[^\n]*\n\s*)*(\d+)\s+(?:#[^\n]*\n\s*)*(\d+)\s+"
                    rb"(?:#[^\n]*\n\s*)*(\d+)\s", data)
    if head is None or int(head.group(3)) < 256:
        raise SetError("a NYU raw depth frame must be a 16-bit binary PGM (P5, maxval >= 256)")
    w, h = int(head.group(1)), int(head.group(2))
    raw = np.frombuffer(data, dtype="<u2", count=w * h, offset=head.end()).reshape(h, w)
    raw = raw.astype(np.float64)
    depth = np.zeros_like(raw)
    ok = raw < 1092.5
    depth[ok] = 351.3 / (1092.5 - raw[ok])
    depth[depth > 7.0] = 0.0
    return _npy_bytes(depth.astype(np.float32))


def _mat_cloud(data: bytes, var: str) -> bytes:
    """An organized cloud stored as a MATLAB variable ``var`` (``(H, W, 3)`` metres; points at
    the origin mean no data) as a float64 ``.npy`` with NaN for no data."""
    import numpy as np

    cloud = np.asarray(_mat_var(data, var), dtype=np.float64)
    cloud[~(cloud[..., 2] > 0)] = np.nan
    return _npy_bytes(cloud)


def _mat_var(data: bytes, var: str):
    """The MATLAB variable ``var`` of a ``.mat`` file; ``STRUCT.FIELD`` reads a struct's field."""
    import io

    from scipy.io import loadmat

    name, _, field = var.partition(".")
    value = loadmat(io.BytesIO(data))[name]
    return value[field][0, 0] if field else value


def _mat_xyz_mm(data: bytes, struct: str) -> bytes:
    """An organized cloud in a MATLAB struct (``STRUCT.xyz``: ``(H, W, 3)`` millimetres,
    ``STRUCT.depth`` 0 where there is no data; ai4ce/peac's ``frame.mat``) as float64 metres with
    NaN for no data."""
    import numpy as np

    cloud = np.asarray(_mat_var(data, struct + ".xyz"), dtype=np.float64) / 1000
    cloud[_mat_var(data, struct + ".depth") == 0] = np.nan
    return _npy_bytes(cloud)


def _mat_mm_to_m(data: bytes, var: str) -> bytes:
    """A MATLAB variable of 16-bit millimetres as float32 metres (0 = no depth)."""
    arr = _mat_var(data, var)
    if arr.dtype != "uint16":
        raise SetError(f"millimetre depth must be 16-bit, not {arr.dtype}")
    return _npy_bytes(arr.astype("float32") / 1000)


def _csv_depth(data: bytes, unit: str) -> bytes:
    """A depth grid kept as text (one image row a line, values split by commas or blanks; e.g.
    a RealSense ``z16`` frame written with ``csv.writer``) as float32 metres: each value times
    ``unit`` metres (default 0.001, millimetres); 0 and 65535 (``z16``'s no-data / saturated value,
    as :func:`planerel.io.cloud.depth_to_cloud` reads a 16-bit image) are no depth (0).

    Returns
    -------
    bytes
        A ``.npy`` of shape ``(rows, columns)``.
    """
    import numpy as np

    rows = [line.replace(",", " ").split() for line in data.decode("ascii").splitlines()]
    rows = [r for r in rows if r]
    if not rows or len({len(r) for r in rows}) != 1:
        raise SetError("a depth CSV must be a non-empty grid of equal rows")
    raw = np.array(rows, dtype=np.float64)
    grid = raw * float(unit or 0.001)
    keep = np.isfinite(grid) & (grid > 0) & (raw != 65535)
    return _npy_bytes(np.where(keep, grid, 0).astype(np.float32))


def _disparity_png(data: bytes, arg: str) -> bytes:
    """A 16-bit disparity PNG (disparity in pixels = value / ``SCALE``) of a rectified stereo
    pair as float32 metres: ``depth = F * B / disparity`` with ``arg`` = ``"F,B[,SCALE]"`` (focal
    length in pixels, baseline in metres, ``SCALE`` 256 by default, the KITTI-style encoding);
    no disparity (0) is no depth (0).

    Returns
    -------
    bytes
        A ``.npy`` of the image's shape ``(H, W)``.
    """
    import io

    import numpy as np
    from PIL import Image

    parts = [float(x) for x in arg.split(",")]
    if len(parts) not in (2, 3) or min(parts) <= 0:
        raise SetError(f"disparity_png needs F,B[,SCALE] > 0, not {arg!r}")
    focal, base, scale = (parts + [256.0])[:3]
    raw = np.array(Image.open(io.BytesIO(data)))
    if raw.dtype != np.uint16 or raw.ndim != 2:
        raise SetError(f"a disparity PNG must be one 16-bit channel, not {raw.dtype} {raw.shape}")
    disp = raw.astype(np.float64) / scale
    depth = np.where(disp > 0, focal * base / np.where(disp > 0, disp, 1), 0)
    return _npy_bytes(depth.astype(np.float32))


#: how a file of a set is made from a repository's file (``MADE.json``'s ``convert``:
#: ``NAME`` or ``NAME:ARGUMENT``)
CONVERTERS = {
    "npy_dict": lambda data, key: _npy_bytes(_restricted_npy_object(data)[key]),
    "npy_nan_to_zero": lambda data, _: _npy_bytes(__import__("numpy").nan_to_num(_npy(data), nan=0.0)),
    "npy_squeeze": lambda data, _: _npy_bytes(_npy(data)[..., 0]),
    "mat_cloud": _mat_cloud,
    "kinect_raw_depth": lambda data, _: _kinect_raw_depth(data),
    "nyu_pgm": lambda data, _: _nyu_pgm(data),   # NYU Depth v2 raw disparity PGM as metres
    "f200_depth": lambda data, _: _f200_depth(data),
    # float64 metres stored as float32 (the sensor's steps are coarser than float32's)
    "npy_float32": lambda data, _: _npy_bytes(_npy(data).astype("float32")),
    "npz_key": lambda data, key: _npy_bytes(_npy(data)[key]),   # np.load reads an .npz too
    # 16-bit millimetres (a .npy or a PNG) as float32 metres, 0 = no depth
    "mm_to_m": lambda data, _: _npy_bytes(_mm_array(data).astype("float32") / 1000),
    "mat_mm_to_m": _mat_mm_to_m,   # the same, from a MATLAB variable
    "mat_xyz_mm": _mat_xyz_mm,
    "csv_depth": _csv_depth,   # a text grid of depth values times UNIT metres (0.001)
    "disparity_png": _disparity_png,   # stereo disparity (PNG / SCALE px) as F * B / d metres
}


def convert(name: str, data: bytes) -> bytes:
    """``data`` made into a set's file by the converter ``name`` (``NAME[:ARGUMENT]``)."""
    base, _, arg = name.partition(":")
    if base not in CONVERTERS:
        raise SetError(f"no converter {base!r} (known: {', '.join(CONVERTERS)})")
    try:
        return CONVERTERS[base](data, arg)
    except SetError:
        raise
    except Exception as exc:   # a source file the converter cannot read: say which, no traceback
        raise SetError(f"converter {name!r} could not read its source: "
                       f"{type(exc).__name__}: {exc}") from None


def _digest(data: bytes, fname: str) -> str:
    """SHA-1 of a made file's decoded array (a PNG's pixels or a ``.npy``'s values with shape
    and dtype), so a PNG written by another Pillow version still checks."""
    import io

    import numpy as np

    if fname.endswith(".npy"):
        arr = np.load(io.BytesIO(data), allow_pickle=False)
    else:
        from PIL import Image

        arr = np.array(Image.open(io.BytesIO(data)))
    return hashlib.sha1(f"{arr.dtype.str}{arr.shape}".encode() + arr.tobytes()).hexdigest()


def _made_files(set_dir: str, repos: dict) -> dict:
    """``{file: manifest entry or None}`` for the files ``MADE.json`` says were made from a
    repository's file (``{"file": {"repo": R, "path": P, "convert": NAME}}``, checked by
    making them again here) or are left out (``{"file": {"skip": "why"}}``: an image kept
    only to look at)."""
    path = os.path.join(set_dir, "MADE.json")
    if not os.path.exists(path):
        return {}
    with open(path) as fh:
        spec = json.load(fh)
    out = {}
    for fname, how in sorted(spec.items()):
        if how.get("skip"):
            out[fname] = None
            continue
        if str(how.get("convert")).partition(":")[0] not in CONVERTERS or how.get("repo") not in repos:
            raise SetError(f"{path}: {fname}: needs a 'convert' of {', '.join(CONVERTERS)} "
                           f"and a 'repo' among the mirrors")
        git_dir = repos[how["repo"]]
        commit = how.get("commit") or _git(git_dir, "rev-parse", "HEAD").strip()
        src = _git(git_dir, "show", f"{commit}:{how['path']}", binary=True)
        with open(os.path.join(set_dir, fname), "rb") as fh:
            have = fh.read()
        made = convert(how["convert"], src)
        if _digest(made, fname) != _digest(have, fname):
            raise SetError(f"{set_dir}: {fname} is not {how['convert']} of {how['path']}")
        out[fname] = {"file": fname, "repo": how["repo"], "commit": commit,
                      "path": how["path"], "blob": blob_id(src), "convert": how["convert"],
                      "digest": _digest(made, fname)}
    return out


def capture(set_dir: str, name: str, mirrors: str, role: str = "development") -> dict:
    """The manifest of a labelled set folder, each file found by content in ``mirrors``.

    Raises
    ------
    SetError
        No such folder, or data files found in no repository (listed).
    """
    if not os.path.isdir(set_dir):
        raise SetError(f"{set_dir}: no such folder")
    repos = git_dirs(mirrors)
    made = _made_files(set_dir, repos)
    shas = {}
    for fname in _walk(set_dir):
        if fname not in OWN and fname not in made:
            with open(os.path.join(set_dir, fname), "rb") as fh:
                data = fh.read()
            shas[fname] = (blob_id(data), _own_text(data))
    where = _find_blobs({sha for sha, _ in shas.values()}, repos)
    files, missing = [f for f in made.values() if f is not None], []
    for fname, (sha, text) in shas.items():
        if sha in where:
            repo, commit, path = where[sha]
            files.append({"file": fname, "repo": repo, "commit": commit, "path": path,
                          "blob": sha})
        elif text is not None:   # a sidecar written with the labels (intrinsics, an up): ours
            files.append({"file": fname, "text": text})
        else:
            missing.append(fname)
    if missing:
        raise SetError(f"{set_dir}: {len(missing)} file(s) in no repository of {mirrors}: "
                       f"{', '.join(missing[:8])}{' ...' if len(missing) > 8 else ''}")
    labels = None   # a set scored by its script's own truth (real_tabletop.py, real_mosd.py)
    if os.path.exists(os.path.join(set_dir, "labels.json")):
        with open(os.path.join(set_dir, "labels.json")) as fh:
            labels = json.load(fh)
    notes = None
    if os.path.exists(os.path.join(set_dir, "NOTES.md")):
        with open(os.path.join(set_dir, "NOTES.md")) as fh:
            notes = fh.read()
    files.sort(key=lambda f: f["file"])
    return {"name": name, "role": role, "files": files, "labels": labels, "notes": notes}


def _walk(top: str) -> list:
    """Every file under ``top``, as sorted paths relative to it (hidden files left out)."""
    out = []
    for root, dirs, names in os.walk(top):
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))
        out += [os.path.relpath(os.path.join(root, n), top) for n in names
                if not n.startswith(".")]
    return sorted(out)


def _own_text(data: bytes, limit: int = 65536):
    """``data`` as text when it is a small UTF-8 file (a sidecar of ours), else None."""
    if len(data) > limit:
        return None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return None


def manifest_path(name: str) -> str:
    return os.path.join(MANIFESTS, name.replace("/", "--") + ".json")


def write_json(path: str, doc) -> None:
    """``doc`` as indented JSON, written atomically (a temporary file renamed)."""
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(path) or ".", suffix=".tmp")
    with os.fdopen(fd, "w") as fh:
        json.dump(doc, fh, indent=1)
        fh.write("\n")
    os.replace(tmp, path)


def load_manifests(only=()) -> list:
    """Every manifest of ``benchmarks/real_sets`` (or those whose name starts with one of
    ``only``), sorted by name."""
    docs = []
    for fname in sorted(os.listdir(MANIFESTS)) if os.path.isdir(MANIFESTS) else []:
        if fname.endswith(".json"):
            with open(os.path.join(MANIFESTS, fname)) as fh:
                doc = json.load(fh)
            if not only or any(doc["name"].startswith(o) for o in only):
                docs.append(doc)
    return docs


def build(doc: dict, dest: str, repos: dict) -> str:
    """Write one manifest's folder ``dest/<name>``; returns its path.

    Every file is read by its blob id and checked; the folder is replaced only when all are.

    Raises
    ------
    SetError
        A repository not in ``repos`` or a blob it lacks (the path and commit to get named).
    """
    need = sorted({f["repo"] for f in doc["files"] if "repo" in f} - set(repos))
    if need:
        raise SetError(f"{doc['name']}: repositories not found: {', '.join(need)} "
                       f"(fetch them, or git clone https://github.com/OWNER/NAME DIR/OWNER/NAME)")
    out = os.path.join(dest, doc["name"])
    os.makedirs(os.path.dirname(out), exist_ok=True)
    tmp = tempfile.mkdtemp(dir=os.path.dirname(out), prefix=".building-")
    try:
        for f in doc["files"]:
            target = os.path.join(tmp, f["file"])
            os.makedirs(os.path.dirname(target), exist_ok=True)
            if "text" in f:
                with open(target, "w") as fh:
                    fh.write(f["text"])
                continue
            res = subprocess.run(["git", f"--git-dir={repos[f['repo']]}", "cat-file", "blob",
                                  f["blob"]], capture_output=True)
            if res.returncode != 0 or blob_id(res.stdout) != f["blob"]:
                raise SetError(f"{doc['name']}: {f['repo']} lacks {f['path']} (blob {f['blob'][:10]},"
                               f" commit {f['commit'][:10]}); a newer snapshot may have moved it")
            data = res.stdout
            if "convert" in f:
                data = convert(f["convert"], data)
                if _digest(data, f["file"]) != f["digest"]:
                    raise SetError(f"{doc['name']}: {f['file']} made by {f['convert']} "
                                   f"differs from the captured one")
            with open(target, "wb") as fh:
                fh.write(data)
        if doc.get("labels") is not None:
            write_json(os.path.join(tmp, "labels.json"), doc["labels"])
        if doc.get("notes"):
            with open(os.path.join(tmp, "NOTES.md"), "w") as fh:
                fh.write(doc["notes"])
        old = None
        if os.path.exists(out):   # swapped, not deleted first: the set is never missing
            old = tempfile.mkdtemp(dir=os.path.dirname(out), prefix=".replaced-")
            os.replace(out, os.path.join(old, "set"))
        os.replace(tmp, out)
        if old is not None:
            shutil.rmtree(old)
    finally:
        if os.path.exists(tmp):
            shutil.rmtree(tmp)
    return out


def check(doc: dict, dest: str) -> list:
    """What differs between a manifest and its folder under ``dest``: files missing or not
    bit for bit the manifest's (``[]`` when the folder is the set as captured)."""
    out = os.path.join(dest, doc["name"])
    bad = []
    for f in doc["files"]:
        path = os.path.join(out, f["file"])
        if not os.path.isfile(path):
            bad.append(f"{f['file']}: missing")
            continue
        with open(path, "rb") as fh:
            data = fh.read()
        if "text" in f:
            same = data.decode("utf-8", "replace") == f["text"]
        elif "convert" in f:
            same = _digest(data, f["file"]) == f["digest"]
        else:
            same = blob_id(data) == f["blob"]
        if not same:
            bad.append(f"{f['file']}: differs")
    if doc.get("labels") is not None:
        try:
            with open(os.path.join(out, "labels.json")) as fh:
                if json.load(fh) != doc["labels"]:
                    bad.append("labels.json: differs")
        except (OSError, ValueError):
            bad.append("labels.json: missing or not JSON")
    return bad


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    b = sub.add_parser("build", help="write the sets' folders from the repositories")
    b.add_argument("dest")
    b.add_argument("--mirrors", required=True)
    b.add_argument("--only", nargs="*", default=())
    c = sub.add_parser("capture", help="write the manifest of a labelled folder")
    c.add_argument("set_dir")
    c.add_argument("name", help="the folder's name under DEST, e.g. hunt36/m2t2-real")
    c.add_argument("--mirrors", required=True)
    c.add_argument("--role", default="development")
    sub.add_parser("list", help="the manifests and the repositories each needs")
    k = sub.add_parser("check", help="is every set under DEST the manifest's, bit for bit")
    k.add_argument("dest")
    k.add_argument("--only", nargs="*", default=())
    args = ap.parse_args(argv)
    try:
        if args.cmd == "capture":
            doc = capture(args.set_dir, args.name, args.mirrors, args.role)
            write_json(manifest_path(args.name), doc)
            print(f"{manifest_path(args.name)}: {len(doc['files'])} files, "
                  f"{len((doc['labels'] or {}).get('frames', []))} labelled frames")
        elif args.cmd == "list":
            for doc in load_manifests():
                repos = sorted({f["repo"] for f in doc["files"] if "repo" in f})
                print(f"{doc['name']} ({doc['role']}): {len(doc['files'])} files from "
                      f"{', '.join(repos)}")
        elif args.cmd == "check":
            bad = 0
            for doc in load_manifests(args.only):
                diff = check(doc, args.dest)
                bad += bool(diff)
                print(f"{doc['name']}: " + ("ok" if not diff else "; ".join(diff[:5])))
            return 1 if bad else 0
        else:
            repos = git_dirs(args.mirrors)
            docs = load_manifests(args.only)
            if not docs:
                raise SetError("no manifest matches")
            failed = 0
            for doc in docs:
                try:
                    print(f"{build(doc, args.dest, repos)}: {len(doc['files'])} files")
                except SetError as e:
                    failed += 1
                    print(f"error: {e}", file=sys.stderr)
            return 1 if failed else 0
    except SetError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    except (OSError, ValueError) as e:   # an unreadable or corrupt manifest, MADE.json, folder
        print(f"error: {type(e).__name__}: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
