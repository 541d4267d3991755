"""Run every benchmark script in this folder, one after another, on one core when possible."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

here = Path(__file__).resolve().parent
prefix = ["taskset", "-c", "0"] if shutil.which("taskset") else []
status = 0
for script in sorted(here.glob("bench_*.py")):
    print(f"==== {script.name}", flush=True)
    status |= subprocess.call(prefix + [sys.executable, str(script)])
sys.exit(status)
