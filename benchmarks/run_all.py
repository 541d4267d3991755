"""Run every benchmark script in this folder, one after another, on one core when possible."""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
from pathlib import Path

# no options; `--help` says what it does instead of starting every benchmark (minutes)
argparse.ArgumentParser(
    description="Run every benchmark script of this folder (bench_*.py), one after another, "
                "pinned to one core when taskset is installed; `make bench` runs it. Exit "
                "status: non-zero when any script failed. Takes no options.").parse_args()
here = Path(__file__).resolve().parent
prefix = ["taskset", "-c", "0"] if shutil.which("taskset") else []
status = 0
for script in sorted(here.glob("bench_*.py")):
    print(f"==== {script.name}", flush=True)
    status |= subprocess.call(prefix + [sys.executable, str(script)])
sys.exit(status)
