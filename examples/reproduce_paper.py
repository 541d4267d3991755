"""Reproduce the paper's comparison (region growing vs SP / SNP RANSAC) on the paper-sized
synthetic set, and check the page in headless Chromium.

    python examples/reproduce_paper.py [OUT_DIR] [--quick] [--no-learning] [--jobs N]

1. generates the paper-sized data set (12 box, 15 stairs, 18 ramp scenes at 160x120, seed 0)
   into OUT_DIR/dataset unless it is already there;
2. runs ``planerel report OUT_DIR/dataset -o OUT_DIR/report`` (the same code path as the
   command line) with the paper's methods, the real data from ../shared/data when present,
   the learning comparison and timing at 160x120 and 640x480;
3. takes a screenshot of OUT_DIR/report/index.html with headless Chromium when it is installed
   (``apt-get install -y chromium``) and writes OUT_DIR/report/screenshot.png.

``--quick`` makes a small version in a minute (3 scenes per class, three methods, timing at
160x120 only, no learning) in OUT_DIR/report-quick instead of OUT_DIR/report.  Default
OUT_DIR: ``out/paper``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?", default="out/paper", help="output folder (out/paper)")
    ap.add_argument("--quick", action="store_true", help="small version (about a minute)")
    ap.add_argument("--no-learning", action="store_true", help="skip the learning comparison")
    ap.add_argument("--jobs", type=int, default=0, help="worker processes (0 = all cores)")
    args = ap.parse_args(argv)

    from planerel.cli import main as planerel
    from planerel.features.dataset import MANIFEST
    from planerel.report.browser import find_chromium, screenshot

    out = Path(args.out)
    n = (3, 3, 3) if args.quick else (12, 15, 18)
    data = out / ("dataset-quick" if args.quick else "dataset")
    if not (data / MANIFEST).is_file():
        rc = planerel(["dataset", "synth", str(data), "--n-box", str(n[0]), "--n-stairs",
                       str(n[1]), "--n-ramp", str(n[2]), "--seed", "0", "--size", "640x480",
                       "--subsample", "4", "--quiet"])
        if rc:
            return rc
    report = out / ("report-quick" if args.quick else "report")
    cmd = ["report", str(data), "-o", str(report), "--jobs", str(args.jobs)]
    if args.quick:
        cmd += ["--methods", "sp:0.03,snp:0.05,regiongrow", "--sizes", "160x120",
                "--no-learning"]
    elif args.no_learning:
        cmd.append("--no-learning")
    rc = planerel(cmd)
    if rc:
        return rc
    if find_chromium() is None:
        print("Chromium not found (apt-get install -y chromium): no screenshot taken",
              file=sys.stderr)
    else:
        shot = screenshot(report / "index.html", report / "screenshot.png", size=(1200, 3000))
        print(f"screenshot of the page: {shot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
