"""The labelled real development sets, rebuilt from their public repositories by one command.

    .venv/bin/python benchmarks/real_sets.py build DEST --mirrors DIR [--only NAME ...]
    .venv/bin/python benchmarks/real_sets.py capture SET_DIR NAME --mirrors DIR [--role R]
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
looked up by its blob id among the repositories of ``DIR``. A file that is in none of them
and is no small text file (a sidecar of ours, kept inline: intrinsics, an up vector) is
listed and the capture refused: a set whose data cannot be fetched
back is not reproducible; convert at read time instead (``planerel.io`` reads PNG/TIFF depth,
PCD, PLY, NPY).

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
OWN = ("labels.json", "NOTES.md")


class SetError(Exception):
    """A manifest that cannot be captured or built (missing repository, blob or file)."""


def blob_id(data: bytes) -> str:
    """The git blob id (SHA-1 of ``b"blob <size>\\0" + data``) of a file's bytes."""
    return hashlib.sha1(b"blob %d\0" % len(data) + data).hexdigest()


def git_dirs(mirrors: str) -> dict:
    """``{"owner/name": git directory}`` of the repositories under ``mirrors``.

    Both layouts are read: ``owner+name/repo`` (bare) and ``owner/name`` (a clone, its
    ``.git``).
    """
    out = {}
    if not os.path.isdir(mirrors):
        raise SetError(f"{mirrors}: no such folder of repositories")
    for entry in sorted(os.listdir(mirrors)):
        top = os.path.join(mirrors, entry)
        if not os.path.isdir(top):
            continue
        if "+" in entry and os.path.isdir(os.path.join(top, "repo")):
            out[entry.replace("+", "/", 1)] = os.path.join(top, "repo")
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


def capture(set_dir: str, name: str, mirrors: str, role: str = "development") -> dict:
    """The manifest of a labelled set folder, each file found by content in ``mirrors``.

    Raises
    ------
    SetError
        No ``labels.json``, or files found in no repository (listed).
    """
    if not os.path.exists(os.path.join(set_dir, "labels.json")):
        raise SetError(f"{set_dir}: no labels.json")
    indexes = {}
    for r, g in git_dirs(mirrors).items():
        try:
            indexes[r] = tree_index(g)
        except SetError as e:   # a snapshot still being copied in: not a repository yet
            print(f"warning: {r} skipped: {e}", file=sys.stderr)
    files, missing = [], []
    for fname in _walk(set_dir):
        path = os.path.join(set_dir, fname)
        if fname in OWN:
            continue
        with open(path, "rb") as fh:
            data = fh.read()
        sha = blob_id(data)
        hit = next(((r, c, idx[sha]) for r, (c, idx) in indexes.items() if sha in idx), None)
        if hit is not None:
            files.append({"file": fname, "repo": hit[0], "commit": hit[1], "path": hit[2],
                          "blob": sha})
            continue
        text = _own_text(data)
        if text is None:
            missing.append(fname)
        else:   # a sidecar written with the labels (intrinsics, an up vector): ours, kept inline
            files.append({"file": fname, "text": text})
    if missing:
        raise SetError(f"{set_dir}: {len(missing)} file(s) in no repository of {mirrors}: "
                       f"{', '.join(missing[:8])}{' ...' if len(missing) > 8 else ''}")
    with open(os.path.join(set_dir, "labels.json")) as fh:
        labels = json.load(fh)
    notes = None
    if os.path.exists(os.path.join(set_dir, "NOTES.md")):
        with open(os.path.join(set_dir, "NOTES.md")) as fh:
            notes = fh.read()
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
            with open(target, "wb") as fh:
                fh.write(res.stdout)
        write_json(os.path.join(tmp, "labels.json"), doc["labels"])
        if doc.get("notes"):
            with open(os.path.join(tmp, "NOTES.md"), "w") as fh:
                fh.write(doc["notes"])
        if os.path.exists(out):
            shutil.rmtree(out)
        os.replace(tmp, out)
    finally:
        if os.path.exists(tmp):
            shutil.rmtree(tmp)
    return out


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
    args = ap.parse_args(argv)
    try:
        if args.cmd == "capture":
            doc = capture(args.set_dir, args.name, args.mirrors, args.role)
            write_json(manifest_path(args.name), doc)
            print(f"{manifest_path(args.name)}: {len(doc['files'])} files, "
                  f"{len(doc['labels'].get('frames', []))} frames")
        elif args.cmd == "list":
            for doc in load_manifests():
                repos = sorted({f["repo"] for f in doc["files"] if "repo" in f})
                print(f"{doc['name']} ({doc['role']}): {len(doc['files'])} files from "
                      f"{', '.join(repos)}")
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
    return 0


if __name__ == "__main__":
    sys.exit(main())
