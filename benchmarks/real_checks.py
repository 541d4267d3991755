"""Every real-data check that can run here, for one model: the summary lines, saved and compared.

    .venv/bin/python benchmarks/real_checks.py [--model out/model] [--param NAME=VALUE ...]
        [--tabletop DIR] [--stairs DIR] [--hunts DIR ...] [--independent DIR ...]
        [--save F.json] [--compare F.json]

What a change must not break (or must measure) on data nobody on the team made, in one run
instead of six commands: the shared frames (``../shared/data``: the Kinect TIFFs, office1, the
mOSD PCDs: every class answer), the whole mOSD set, the OSD + UOIS table-tops
(``real_mosd.py``, ``real_tabletop.py``: ``--tabletop``, default ``$PLANEREL_TABLETOP_DATA``,
holding ``mosd/``, ``osd/``, ``uois/``), the real staircases (``real_stairs.py``: ``--stairs``,
default ``$PLANEREL_STAIRS_DATA``, holding ``stair-perception/``, ``elmasry/``), hunt25's
labelled sets (``pcl-pairwise/``, ``pcl-tutorials/``, ``palletizer/`` under the table-top
folder) and any other folders of labelled sets (``--hunts``: each a folder of set folders with
a ``labels.json``, ``real_unseen.py``), and sets of the independent generator (``--independent``:
``independent_scenes.py score``).  A set whose folder is missing is skipped and said so.
``--param`` reaches every script, the independent sets' included (since session 90; before,
those were skipped with a parameter).

Each script runs as its own process; this one keeps the lines that say what was found (a
script's totals, every class answer of the shared frames), without timings, so that two runs
of identical answers print identical lines.  ``--save F`` writes them as JSON; ``--compare F``
prints each line that differs from F's (exit status 1 when any does): the check that a speed
change is exact, or the measure of what a behaviour change moved.
"""

from __future__ import annotations

import argparse
import glob
import json
import os
import re
import subprocess
import sys
from pathlib import Path

from _setup import data_dir

HERE = Path(__file__).resolve().parent

#: lines kept from each script's output (everything else is per-frame detail or timing)
KEEP = {
    "shared": re.compile(r"^\s+\S+_o\d+: (box|stairs|ramp)\b"),
    "mosd": re.compile(r"^(learn|test|all|rest):"),
    "tabletop": re.compile(r"^all:"),
    "stairs": re.compile(r"^frames whose flight"),
    "unseen": re.compile(r"^found:|false answers"),
    "independent": re.compile(r"^object accuracy|^\s+of those, on labelled objects|^\s+(box|stairs|ramp|other)\s+\d+/|^\s+by kind:"),
}
#: timings a kept line may carry
TIMING = re.compile(r"\s*[\[(]?\d+(\.\d+)? ?(ms|s)\b(/scene)?( classify| per scene)?[\])]?")


def _run(name: str, args: list[str], cwd: Path) -> list[str]:
    """The kept lines of one script's output (or of ``planerel`` with ``args[0] == '-m'``)."""
    proc = subprocess.run([sys.executable, *args], cwd=cwd, capture_output=True, text=True)
    if proc.returncode != 0:
        tail = (proc.stderr.strip().splitlines() or ["(no message)"])[-1]
        return [f"FAILED (exit {proc.returncode}): {tail}"]
    keep = KEEP[name]
    return [TIMING.sub("", line).rstrip() for line in proc.stdout.splitlines() if keep.search(line)]


def checks(model: str, params: list[str], tabletop: Path | None, stairs: Path | None,
           hunts: list[Path], independent: list[Path]) -> dict[str, list[str]]:
    """``{check: kept lines}`` of every check whose data is here; a missing set's entry says
    ``skipped``."""
    root = HERE.parent
    par = [a for p in params for a in ("--param", p)]
    out: dict[str, list[str]] = {}
    shared = data_dir()
    frames = sorted(glob.glob(str(shared / "kinect" / "frame_*_depth.tiff")))
    frames += sorted(glob.glob(str(shared / "kinect" / "office1.pcd")))
    frames += sorted(glob.glob(str(shared / "mosd" / "*.pcd")))
    if frames:
        out["shared frames"] = _run("shared", ["-m", "planerel", "classify", model, *frames, *par], root)
    else:
        out["shared frames"] = [f"skipped: no frames under {shared}"]

    def script(key, name, args, needs):
        missing = [str(n) for n in needs if not Path(n).exists()]
        out[key] = ([f"skipped: no {', '.join(missing)}"] if missing else
                    _run(name, [str(HERE / args[0]), *args[1:], "--model", model, *par], root))

    if tabletop is not None:
        script("whole mOSD", "mosd", ["real_mosd.py", str(tabletop / "mosd")], [tabletop / "mosd"])
        script("table-tops", "tabletop", ["real_tabletop.py", "--osd", str(tabletop / "osd"),
                                          "--uois", str(tabletop / "uois")],
               [tabletop / "osd", tabletop / "uois"])
        h25 = [tabletop / n for n in ("pcl-pairwise", "pcl-tutorials", "palletizer")]
        script("hunt25", "unseen", ["real_unseen.py", *map(str, h25)],
               [h / "labels.json" for h in h25])
    if stairs is not None:
        clouds = sorted(glob.glob(str(stairs / "elmasry" / "*.pcd")))
        script("staircases", "stairs", ["real_stairs.py", str(stairs / "stair-perception"),
                                        *(["--clouds", *clouds] if clouds else [])],
               [stairs / "stair-perception"])
    for h in hunts:
        sets = sorted(str(p.parent) for p in Path(h).glob("*/labels.json"))
        if not sets:
            out[f"labelled {h}"] = [f"skipped: no labelled set (*/labels.json) under {h}"]
            continue
        script(f"labelled {h}", "unseen", ["real_unseen.py", *sets], [])
    for d in independent:
        key = f"independent {d}"
        if not Path(d).is_dir():
            out[key] = [f"skipped: no {d}"]
        else:
            out[key] = _run("independent", [str(HERE / "independent_scenes.py"), "score", str(d),
                                            model, *par], root)
    return out


def compare(now: dict, before: dict) -> list[str]:
    """Lines of ``now`` that differ from ``before``, as ``check: - old / + new``."""
    diff = []
    for key in sorted(set(now) | set(before)):
        a, b = before.get(key, []), now.get(key, [])
        if a != b:
            diff += [f"{key}: - {line}" for line in a if line not in b]
            diff += [f"{key}: + {line}" for line in b if line not in a]
    return diff


def main(argv=None) -> int:
    env = os.environ.get
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--tabletop", default=env("PLANEREL_TABLETOP_DATA"),
                    help="folder with mosd/, osd/, uois/ and hunt25's sets")
    ap.add_argument("--stairs", default=env("PLANEREL_STAIRS_DATA"),
                    help="folder with stair-perception/ and elmasry/")
    ap.add_argument("--hunts", nargs="*", default=[], metavar="DIR",
                    help="folders of labelled set folders (real_unseen.py)")
    ap.add_argument("--independent", nargs="*", default=[], metavar="DIR",
                    help="sets made by independent_scenes.py make")
    ap.add_argument("--save", help="write the lines here (JSON)")
    ap.add_argument("--compare", help="print the lines that differ from this saved run")
    a = ap.parse_args(argv)
    model = str(Path(a.model).resolve())
    res = checks(model, a.param, Path(a.tabletop) if a.tabletop else None,
                 Path(a.stairs) if a.stairs else None, [Path(h) for h in a.hunts],
                 [Path(d) for d in a.independent])
    for key, lines in res.items():
        print(f"== {key}")
        for line in lines:
            print(f"   {line.strip()}")
    if a.save:
        from planerel.atomic import write_text

        write_text(a.save, json.dumps(res, indent=1) + "\n")
    if a.compare:
        before = json.loads(Path(a.compare).read_text())
        diff = compare(res, before)
        print(f"== against {a.compare}: " + ("identical" if not diff else f"{len(diff)} lines differ"))
        for line in diff:
            print(f"   {line}")
        return 1 if diff else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
