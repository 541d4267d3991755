"""How a setting moves the real development frames' ``box`` answers, frame by frame, split by how
steeply the camera looks down (small99, docs/objects.md "Session 99").  A measuring tool: no
relation or gate of the model reads it.

Usage::

    answers_by_pitch.py BEFORE.jsonl AFTER.jsonl [--split 60]

``BEFORE`` and ``AFTER`` are :mod:`box_answers` ``--jsonl`` outputs over the same frames (the
model as it is, and with the setting measured, e.g. ``--param small_scale=0.35``).  Each frame
whose count of ``right``, ``false`` or ``unscored`` answers differs is listed with the camera's
pitch (degrees under the horizon by the frame's up: :func:`planerel.segment.view_pitch`, read
from the rows), and the differences are summed in two bands: pitch at least ``--split`` (a camera looking
down on a table or a bin) and under it.  A frame with no box answer in either file cannot move
and is not listed; its pitch is unknown to the rows.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter, defaultdict
from pathlib import Path

#: the answer statuses compared (``box_answers``' ``thing`` rows, OSD's untyped objects, are
#: neither right nor false and are left out)
STATUSES = ("right", "false", "unscored")


def read_rows(path) -> list:
    """The JSON lines of a :mod:`box_answers` ``--jsonl`` file."""
    with open(path, encoding="utf-8") as fh:
        return [json.loads(line) for line in fh if line.strip()]


def frame_counts(rows) -> tuple[dict, dict]:
    """``({(set, frame): Counter of statuses}, {(set, frame): pitch or None})``."""
    counts: dict = defaultdict(Counter)
    pitch: dict = {}
    for r in rows:
        key = (r["set"], r["frame"])
        counts[key][r["status"]] += 1
        if r.get("pitch") is not None:
            pitch.setdefault(key, float(r["pitch"]))
    return counts, pitch


def compare(before, after, split: float = 60.0) -> tuple[list, dict]:
    """Frame-by-frame differences of ``after`` against ``before`` (lists of rows).

    Returns
    -------
    (list, dict)
        ``[(set, frame, pitch, {status: change})]`` for the frames that move (sorted by set
        and frame), and ``{(band, status): summed change}`` with band ``">= split"``, ``"<
        split"`` or ``"unknown"`` (no pitch in the rows).
    """
    cb, pb = frame_counts(before)
    ca, pa = frame_counts(after)
    moved, totals = [], Counter()
    for key in sorted(set(cb) | set(ca)):
        change = {s: ca[key][s] - cb[key][s] for s in STATUSES}
        if not any(change.values()):
            continue
        p = pa.get(key, pb.get(key))
        band = "unknown" if p is None else (f">= {split:g}" if p >= split else f"< {split:g}")
        for s, v in change.items():
            totals[(band, s)] += v
        moved.append((key[0], key[1], p, change))
    return moved, dict(totals)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("before", type=Path)
    ap.add_argument("after", type=Path)
    ap.add_argument("--split", type=float, default=60.0,
                    help="degrees under the horizon that part the two bands (default 60)")
    a = ap.parse_args(argv)
    moved, totals = compare(read_rows(a.before), read_rows(a.after), a.split)
    for s, f, p, change in moved:
        ps = "?" if p is None else f"{p:.1f}"
        print(f"{s:20s} {f:34s} pitch {ps:>5s}  "
              + "  ".join(f"{k} {v:+d}" for k, v in change.items()))
    for band in (f">= {a.split:g}", f"< {a.split:g}", "unknown"):
        row = {s: totals.get((band, s), 0) for s in STATUSES}
        if any(row.values()) or band != "unknown":
            print(f"pitch {band}: " + ", ".join(f"{k} {v:+d}" for k, v in row.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
