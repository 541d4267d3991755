"""Robustness audit (issue 18): throw bad input, kills and malicious files at planerel and count
what happens.  Prints the table of docs/robustness.md.

Four parts, all deterministic (seeded):

A. readers, in process: truncated, byte-mutated and header-edited versions of the real files of
   ../shared/data (Kinect TIFF and PCD, MOSD PCD, SegComp ABW range and ground truth) and of
   small PNG/PCD/PLY/NPY files made here, random bytes behind every format's magic, and the
   named failures of issue 18 (giant PNG, .npy header of 100000x100000x3, bad PCD headers...).
   Each input goes through ``planerel.io.readers.read`` and ``read_label_image`` with a 20 s alarm.
   A *clear error* is an InputError of one line that names the file; anything else raised is a
   *traceback*; the alarm is a *hang*.
B. command line, in a subprocess: user mistakes (output below a file, a missing input, a
   non-UTF-8 folder name, --max-points, a class named ``halt``); stderr must be one line with
   no ``Traceback``.
C. kills: ``learn`` (pool workers; fold learners), ``induce`` (a background file that spins)
   and ``dataset synth`` over an existing set, each with SIGTERM and SIGKILL; *orphans* are
   descendants alive 10 s later, a *corrupted output* is an output folder that is neither the
   previous one (byte for byte) nor absent.
D. malicious model files (directives, initialization, shell in a body, a call of a variable,
   a class named shell) through ``planerel classify``, and a TMPDIR that would run a command if
   pasted into a Prolog goal through ``learn --folds``: *ran code* counts marker files created.

Run: ``.venv/bin/python benchmarks/robustness.py`` (about 2 minutes on 2 cores).
"""

from __future__ import annotations

import argparse
import hashlib
import os
import re
import shutil
import signal
import stat
import struct
import subprocess
import sys
import tempfile
import time
import zlib
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT.parent / "shared" / "data"
REAL = ["kinect/office1.pcd", "mosd/learn0.pcd", "abw/abw.test.6.range", "abw/abw.test.6.gt-seg",
        "kinect/frame_20121214T142255.814212_depth.tiff"]


class Tally:
    def __init__(self):
        self.counts: dict[str, dict[str, int]] = {}
        self.notes: list[str] = []

    def add(self, part: str, key: str, n: int = 1) -> None:
        self.counts.setdefault(part, {}).setdefault(key, 0)
        self.counts[part][key] += n


# ----------------------------------------------------------------------------- part A


def _small_files(folder: Path) -> list[Path]:
    from planerel.io.writers import write_depth_png, write_ply

    v, u = np.mgrid[0:12, 0:16]
    write_depth_png(folder / "d.png", (1500 + 10 * v + u).astype(np.uint16))
    xyz = np.stack([u * 0.01, v * 0.01, np.full(u.shape, 1.5)], axis=2).reshape(-1, 3)
    write_ply(folder / "p.ply", xyz)
    np.save(folder / "a.npy", xyz.reshape(12, 16, 3))
    head = ("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
            "WIDTH 16\nHEIGHT 12\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 192\nDATA {}\n")
    (folder / "b.pcd").write_bytes(head.format("binary").encode() + xyz.astype("<f4").tobytes())
    (folder / "t.pcd").write_bytes((head.format("ascii") + "".join(
        f"{x:.3f} {y:.3f} {z:.3f}\n" for x, y, z in xyz)).encode())
    return sorted(folder.iterdir())


def _png_header(width: int, height: int) -> bytes:
    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body
                + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 16, 0,
                                                              0, 0, 0))
            + chunk(b"IDAT", zlib.compress(b"\x00" * 64)) + chunk(b"IEND", b""))


def _named_cases() -> list[tuple[str, bytes]]:
    pcd = ("VERSION 0.7\nFIELDS x y z\nSIZE {s}\nTYPE {t}\nCOUNT 1 1 1\nWIDTH {w}\nHEIGHT 1\n"
           "POINTS 2\nDATA {d}\n")
    f4 = np.array([[0.1, 0.2, 1.0], [0.3, 0.4, 1.5]], "<f4").tobytes()
    f8 = np.array([[0.1, 0.2, 1.0], [0.3, 0.4, 1.5]], "<f8").tobytes()

    def p(s="4 4 4", t="F F F", w=2, d="binary", payload=f4):
        return pcd.format(s=s, t=t, w=w, d=d).encode() + payload

    npy = "{'descr': '<f8', 'fortran_order': False, 'shape': (100000, 100000, 3), }"
    npy += " " * (118 - len(npy)) + "\n"
    return [("empty.pcd", b""), ("badtype.pcd", p(t="Q F F")), ("cuthead.pcd", p()[:40]),
            ("negwidth.pcd", p(w=-2)), ("zipped.pcd", p(d="zipped")), ("size3.pcd", p(s="3 4 4")),
            ("f64asf4.pcd", p(payload=f8)), ("giant.png", _png_header(12000, 12000)),
            ("big.png", _png_header(6000, 6000)),
            ("huge.npy", b"\x93NUMPY\x01\x00" + struct.pack("<H", len(npy)) + npy.encode()
             + b"\x00" * 64)]


def _mutations(blob: bytes, rng) -> list[bytes]:
    out = [blob[: int(len(blob) * f)] for f in (0.0, 0.01, 0.1, 0.3, 0.5, 0.9, 0.999)]
    for _ in range(10):
        b = bytearray(blob)
        for _ in range(int(rng.integers(1, 9))):
            where = int(rng.integers(0, min(len(b), 600))) if rng.random() < 0.7 else \
                int(rng.integers(0, len(b)))
            b[where] = int(rng.integers(0, 256))
        out.append(bytes(b))
    head = blob[:400].decode("latin-1")
    spans = [m.span() for m in re.finditer(r"-?\d+", head)]
    for value in ("0", "-1", "99999999999", "3"):
        if spans:
            a, z = spans[int(rng.integers(0, len(spans)))]
            out.append((head[:a] + value + head[z:]).encode("latin-1") + blob[400:])
    return out


def _alarm(signum, frame):
    raise TimeoutError


def part_a(t: Tally, work: Path) -> None:
    from planerel.errors import InputError
    from planerel.io import readers as io

    rng = np.random.default_rng(18)
    small = work / "small"
    small.mkdir()
    sources = [(p.name, p.read_bytes()) for p in _small_files(small)]
    sources += [(Path(r).name, (DATA / r).read_bytes()) for r in REAL if (DATA / r).is_file()]
    inputs = []
    for name, blob in sources:
        inputs += [(name, b) for b in _mutations(blob, rng)]
    magics = [b"", b"\x89PNG\r\n\x1a\n", b"II*\x00", b"\x93NUMPY\x01\x00", b"ply\n",
              b"# .PCD v0.7\n", struct.pack(">I", 0x59A66A95)]
    for n, (magic, ext) in enumerate(zip(magics, [".dat", ".png", ".tiff", ".npy", ".ply", ".pcd",
                                                  ".range"], strict=True)):
        for _ in range(4):
            inputs.append((f"abw.test.{n}{ext}", magic + rng.bytes(int(rng.integers(0, 3000)))))
    inputs += _named_cases()
    v, u = np.mgrid[0:1, 0:40]
    from planerel.io.writers import write_depth_png

    write_depth_png(small / "thin.png", (1000 + u).astype(np.uint16))
    inputs.append(("thin.png", (small / "thin.png").read_bytes()))
    old = signal.signal(signal.SIGALRM, _alarm)
    folder = work / "a"
    folder.mkdir()
    try:
        for i, (name, blob) in enumerate(inputs):
            path = folder / f"{i:03d}" / name
            path.parent.mkdir()
            path.write_bytes(blob)
            for reader in (lambda p: io.read(p, intrinsics="kinect"), io.read_label_image):
                t.add("A", "inputs tried")
                signal.alarm(20)
                try:
                    reader(path)
                    t.add("A", "valid results")
                except InputError as exc:
                    msg = str(exc)
                    if "\n" not in msg and str(path) in msg:
                        t.add("A", "clear errors")
                    else:
                        t.add("A", "unclear errors")
                        t.notes.append(f"unclear: {msg[:200]!r}")
                except TimeoutError:
                    t.add("A", "hangs")
                    t.notes.append(f"hang: {name}")
                except BaseException as exc:  # noqa: BLE001 - what the audit counts
                    t.add("A", "tracebacks")
                    t.notes.append(f"traceback: {name}: {type(exc).__name__}: {exc}"[:200])
                finally:
                    signal.alarm(0)
    finally:
        signal.signal(signal.SIGALRM, old)


# ----------------------------------------------------------------------------- CLI helpers


def _env(**extra):
    return dict(os.environ, PLANEREL_CACHE="none", PYTHONPATH=str(ROOT), **extra)


def _cli(args, cwd, env=None, timeout=300):
    r = subprocess.run([sys.executable, "-m", "planerel.cli", *args], cwd=cwd, env=env or _env(),
                       capture_output=True, timeout=timeout)
    return r.returncode, r.stderr.decode("utf-8", "replace")


def _judge(t: Tally, part: str, what: str, code: int, err: str, expect_fail=True) -> None:
    t.add(part, "inputs tried")
    if "Traceback" in err:
        t.add(part, "tracebacks")
        t.notes.append(f"traceback in {what}: {err[-300:]!r}")
    elif expect_fail and code == 2 and err.strip().count("\n") == 0:
        t.add(part, "clear errors")
    elif not expect_fail and code == 0:
        t.add(part, "valid results")
    else:
        t.add(part, "unclear errors")
        t.notes.append(f"{what}: exit {code}: {err[-300:]!r}")


# ----------------------------------------------------------------------------- part B


def part_b(t: Tally, work: Path, dataset: Path) -> None:
    scan = dataset / "s0000.depth.png"
    (work / "afile").write_text("x")
    cases = [
        ("output below a file", ["segment", str(scan), "-o", str(work / "afile" / "out")]),
        ("missing input", ["segment", str(work / "nothing.png"), "-o", str(work / "o1")]),
        ("--max-points", ["segment", str(scan), "--max-points", "1000", "-o", str(work / "o2")]),
        ("learn from a file", ["learn", str(scan), "-o", str(work / "m1")]),
        ("learn into a folder of something else", ["learn", str(dataset), "-o", str(work)]),
        ("classify a missing model", ["classify", str(work / "none.pl"), str(scan)]),
    ]
    bad = dataset.parent / "halt_set"
    shutil.copytree(dataset, bad)
    for f in [bad / "manifest.csv", *bad.glob("*.json")]:  # the class is in both
        f.write_text(f.read_text().replace(",ramp,", ",halt,").replace('"class": "ramp"',
                                                                       '"class": "halt"'))
    cases.append(("a class named halt", ["learn", str(bad), "-o", str(work / "m2"), "--method",
                                         "gt"]))
    # outputs onto the inputs, a FIFO, /dev/stdout (user89): refused, the input unchanged
    own = work / "own"
    own.mkdir()
    mine = own / "scan.pcd"
    code, err = _cli(["convert", str(scan), "-o", str(mine)], work)
    _judge(t, "B", "convert a depth PNG to a PCD", code, err, expect_fail=False)
    fifo = work / "fifo"
    os.mkfifo(fifo)
    cases += [
        ("segment into the scan's own folder", ["segment", str(mine), "-o", str(own),
                                                "--formats", "pcd"]),
        ("describe -o the input", ["describe", str(mine), "-o", str(mine)]),
        ("describe -o a FIFO", ["describe", str(mine), "-o", str(fifo)]),
        ("describe -o /dev/stdout", ["describe", str(mine), "-o", "/dev/stdout"]),
    ]
    before = mine.read_bytes()
    for what, args in cases:
        code, err = _cli(args, work)
        _judge(t, "B", what, code, err)
    if mine.read_bytes() != before or not stat.S_ISFIFO(os.stat(fifo).st_mode):
        t.add("B", "unclear errors")
        t.notes.append("an input or the FIFO was written over")
    # a non-UTF-8 folder name: works end to end (or says why in one sentence)
    odd = Path(os.fsdecode(os.fsencode(str(work)) + b"/set\xff"))
    code, err = _cli(["dataset", "synth", str(odd), "--n-box", "2", "--n-stairs", "2",
                      "--n-ramp", "2", "--subsample", "8", "--quiet"], work)
    _judge(t, "B", "synth into a non-UTF-8 folder", code, err, expect_fail=False)
    code, err = _cli(["learn", str(odd), "-o", str(work / "m3"), "--method", "gt", "--folds",
                      "2"], work)
    _judge(t, "B", "learn from a non-UTF-8 folder", code, err, expect_fail=False)


# ----------------------------------------------------------------------------- part C


def _digest(folder: Path):
    if not folder.exists():
        return None
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def _wait(cond, timeout=90.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        v = cond()
        if v:
            return v
        time.sleep(0.05)
    return None


def part_c(t: Tally, work: Path, dataset: Path) -> None:
    from planerel.children import descendants, pid_alive
    from planerel.synth.generator import generate_dataset

    spin = work / "spin"
    spin.mkdir()
    for ext in ("b", "f", "n"):
        shutil.copy(ROOT / "tests" / "ilp" / f"trains.{ext}", spin / f"spin.{ext}")
    with open(spin / "spin.b", "a") as fh:
        fh.write("\n:- ( between(1, inf, _), fail ; true ).\n")

    def learn_pool(d):
        return ["learn", str(dataset), "-o", str(d / "out"), "--jobs", "2"], \
            lambda p: len(descendants(p)) >= 2

    def learn_swipl(d):
        return ["learn", str(dataset), "-o", str(d / "out"), "--jobs", "2", "--folds", "3",
                "--method", "gt"], lambda p: "swipl" in descendants(p).values()

    def induce(d):
        return ["induce", str(spin / "spin"), "--timeout", "600"], \
            lambda p: "swipl" in descendants(p).values()

    def synth(d):
        return ["dataset", "synth", str(d / "out"), "--n-box", "40", "--n-stairs", "40",
                "--n-ramp", "40", "--seed", "2", "--quiet"], \
            lambda p: any(len(list(x.glob("*.depth.png"))) >= 3 for x in d.glob(".out.tmp-*"))

    scenarios = [("learn (pool workers)", learn_pool, "model"),
                 ("learn (fold learners)", learn_swipl, "model"),
                 ("induce (spinning .b)", induce, None),
                 ("dataset synth over a set", synth, "dataset")]
    for n, (what, make, previous) in enumerate(scenarios):
        for sig in (signal.SIGTERM, signal.SIGKILL):
            d = work / f"kill-{n}-{what.split()[0]}-{sig.name}"
            d.mkdir()
            if previous == "model":
                (d / "out").mkdir()
                (d / "out" / "rules.pl").write_text("% previous model\n")
            elif previous == "dataset":
                generate_dataset(d / "out", 1, 1, 1, seed=1, size=(640, 480), subsample=8)
            before = _digest(d / "out")
            args, ready = make(d)
            proc = subprocess.Popen([sys.executable, "-m", "planerel.cli", *args], cwd=d,
                                    env=_env(), stdout=subprocess.DEVNULL,
                                    stderr=subprocess.PIPE)
            t.add("C", "kills")
            if not _wait(lambda p=proc, r=ready: r(p.pid)):
                t.notes.append(f"{what} {sig.name}: stage never reached")
            kids = descendants(proc.pid)
            proc.send_signal(sig)
            try:
                proc.wait(timeout=60)
            except subprocess.TimeoutExpired:
                t.add("C", "hangs")
                proc.kill()
                proc.wait()
            err = proc.stderr.read().decode("utf-8", "replace")
            if "Traceback" in err:
                t.add("C", "tracebacks")
                t.notes.append(f"{what} {sig.name}: {err[-300:]!r}")
            _wait(lambda k=kids: not any(pid_alive(p) and not _zombie(p) for p in k), 10)
            orphans = [p for p in kids if pid_alive(p) and not _zombie(p)]
            t.add("C", "orphans", len(orphans))
            for p in orphans:
                with _quiet():
                    os.kill(p, signal.SIGKILL)
            after = _digest(d / "out")
            if after is not None and after != before:
                t.add("C", "corrupted outputs")
                t.notes.append(f"{what} {sig.name}: output changed")
            else:
                t.add("C", "outputs intact")


class _quiet:
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return exc[0] is not None and issubclass(exc[0], OSError)


def _zombie(pid: int) -> bool:
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return True
    return text[text.rindex(")") + 2:].split()[0] == "Z"


# ----------------------------------------------------------------------------- part D


def part_d(t: Tally, work: Path, dataset: Path) -> None:
    scan = dataset / "s0000.depth.png"
    marker = "pwned"
    any_obj = "nplanes(O, N), gteq(N, 1)"
    models = {
        "directive": f":- shell('touch {marker}').\nbox(O) :- {any_obj}.\n",
        "initialization": f":- initialization(shell('touch {marker}')).\nbox(O) :- {any_obj}.\n",
        "initialization(main)": f":- initialization(shell('touch {marker}'), main).\n",
        "body": f"box(O) :- {any_obj}, shell('touch {marker}').\n",
        "nested body": f"box(O) :- ( {any_obj} ; \\+ shell('touch {marker}') ).\n",
        "call of a variable": f"box(O) :- G = shell('touch {marker}'), call(G).\n",
        "class named shell": f"shell(O) :- {any_obj}.\n",
        "open a file": f"box(O) :- {any_obj}, open('/etc/passwd', read, _).\n",
        "assert": f"box(O) :- {any_obj}, assertz(user:(horizontal(_) :- shell('touch {marker}'))).\n",
    }
    for n, (what, text) in enumerate(models.items()):
        d = work / f"model-{n}"
        d.mkdir()
        (d / "rules.pl").write_text(text)
        code, err = _cli(["classify", str(d / "rules.pl"), str(scan)], d)
        _judge(t, "D", f"model: {what}", code, err)
        if (d / marker).exists():
            t.add("D", "ran code")
            t.notes.append(f"model {what} ran code")
    # a TMPDIR that runs a command when pasted into a goal; learn --folds must not care
    crafted = work / "x'), shell('touch pwned'), ('"
    crafted.mkdir()
    code, err = _cli(["learn", str(dataset), "-o", str(work / "m-tmp"), "--folds", "2",
                      "--method", "gt", "--jobs", "1"], work, env=_env(TMPDIR=str(crafted)))
    _judge(t, "D", "crafted TMPDIR", code, err, expect_fail=False)
    if (work / marker).exists() or (crafted / marker).exists():
        t.add("D", "ran code")


# ----------------------------------------------------------------------------- report


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--keep", action="store_true", help="keep the work folder")
    args = ap.parse_args(argv)
    from planerel.synth.generator import generate_dataset

    t = Tally()
    work = Path(tempfile.mkdtemp(prefix="planerel-robustness-"))
    t0 = time.perf_counter()
    try:
        dataset = work / "set"
        generate_dataset(dataset, n_box=4, n_stairs=4, n_ramp=4, seed=3, size=(640, 480),
                         subsample=4)
        for name, fn in [("A", part_a), ("B", part_b), ("C", part_c), ("D", part_d)]:
            w = work / name.lower()
            w.mkdir(exist_ok=True)
            t1 = time.perf_counter()
            fn(t, w) if name == "A" else fn(t, w, dataset)
            print(f"part {name}: {time.perf_counter() - t1:.1f} s", file=sys.stderr)
    finally:
        if not args.keep:
            shutil.rmtree(work, ignore_errors=True)
    c = t.counts
    a, b, k, d = (c.get(x, {}) for x in "ABCD")
    rows = [
        ("bad inputs tried (readers, in process)", a.get("inputs tried", 0)),
        ("  valid results", a.get("valid results", 0)),
        ("  clear errors (one line, names the file)", a.get("clear errors", 0)),
        ("  unclear errors", a.get("unclear errors", 0)),
        ("  tracebacks", a.get("tracebacks", 0)),
        ("  hangs (> 20 s)", a.get("hangs", 0)),
        ("user mistakes on the command line", b.get("inputs tried", 0)),
        ("  clear errors / ran as expected", b.get("clear errors", 0) + b.get("valid results", 0)),
        ("  tracebacks or unclear errors", b.get("tracebacks", 0) + b.get("unclear errors", 0)),
        ("kills (SIGTERM and SIGKILL, mid-run)", k.get("kills", 0)),
        ("  orphan processes after the kill", k.get("orphans", 0)),
        ("  corrupted outputs", k.get("corrupted outputs", 0)),
        ("  tracebacks or hangs", k.get("tracebacks", 0) + k.get("hangs", 0)),
        ("malicious model files and crafted paths", d.get("inputs tried", 0)),
        ("  refused with a clear error / ran safely",
         d.get("clear errors", 0) + d.get("valid results", 0)),
        ("  ran code", d.get("ran code", 0)),
        ("  tracebacks or unclear errors", d.get("tracebacks", 0) + d.get("unclear errors", 0)),
    ]
    print("| what | count |\n|---|---:|")
    for label, n in rows:
        print(f"| {label.replace('  ', '&nbsp;&nbsp;')} | {n} |")
    print(f"\n({time.perf_counter() - t0:.0f} s)")
    for n in t.notes:
        print("note:", n)
    bad = (a.get("tracebacks", 0) + a.get("hangs", 0) + a.get("unclear errors", 0)
           + b.get("tracebacks", 0) + b.get("unclear errors", 0) + k.get("orphans", 0)
           + k.get("corrupted outputs", 0) + k.get("tracebacks", 0) + k.get("hangs", 0)
           + d.get("ran code", 0) + d.get("tracebacks", 0) + d.get("unclear errors", 0))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
