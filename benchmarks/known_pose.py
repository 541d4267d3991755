"""Real labelled frames answered with and without their camera's known height (eye62,
docs/objects.md "A known camera height").  A measuring tool.

Usage::

    known_pose.py SET=HEIGHT[:UP] [SET=HEIGHT[:UP] ...] [--model out/model] [--json F]

``SET`` is a folder of labelled frames (``labels.json``, as ``real_unseen.py`` reads),
``HEIGHT`` the camera's height over the floor in metres and ``UP`` (``x,y,z``, optional) its
gravity-up in the camera frame (else each frame's own ``up``, else estimated).  Each frame is
classified three ways: as is, with ``UP`` only (when given), and with ``UP`` and ``HEIGHT``;
per set the labelled objects found and the false answers, scored as ``real_unseen.py``
scores them, and the frames whose answers differ.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def parse_spec(text: str):
    """``SET=HEIGHT[:UP]`` -> ``(folder, height, up or None)``."""
    folder, sep, rest = text.partition("=")
    if not sep:
        raise SystemExit(f"{text!r}: give SET=HEIGHT[:UP]")
    height, _, up = rest.partition(":")
    vec = None
    if up:
        vec = np.array([float(v) for v in up.split(",")])
        vec = vec / np.linalg.norm(vec)
    return folder, float(height), vec


def run(specs, model: str) -> list:
    """One row per set: ``{set, height, up, ways: {way: totals}, changed: [frame, ...]}``."""
    from real_unseen import read_labels, score_frame, totals

    import planerel
    from planerel.classify.classifier import Classifier

    out = []
    with Classifier(model) as clf:
        for folder, height, up in specs:
            doc = read_labels(folder)
            ways = {"as is": (None, None)}
            if up is not None:
                ways["up given"] = (up, None)
            ways["up and height given" if up is not None else "height given"] = (up, height)
            rows = {w: [] for w in ways}
            changed = []
            for fr in doc["frames"]:
                cloud = planerel.read(os.path.join(folder, fr["file"]),
                                      intrinsics=fr.get("intrinsics"),
                                      depth_scale=fr.get("depth_scale"))
                own = None if fr.get("up") is None else np.asarray(fr["up"], float)
                got = {}
                for w, (u, h) in ways.items():
                    ans = clf.classify(cloud, scene_id="s", up=u if u is not None else own,
                                       camera_height=h)
                    got[w] = score_frame(ans, fr)
                    rows[w].append(got[w])
                if len({json.dumps(g, sort_keys=True) for g in got.values()}) > 1:
                    changed.append(fr["file"])
            out.append({"set": folder, "height": height,
                        "up": None if up is None else [round(float(v), 4) for v in up],
                        "ways": {w: totals(r) for w, r in rows.items()}, "changed": changed})
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("specs", nargs="+", metavar="SET=HEIGHT[:UP]")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    rows = run([parse_spec(s) for s in a.specs], a.model)
    for r in rows:
        print(f"== {r['set']} (camera {r['height']} m over the floor"
              f"{'' if r['up'] is None else ', up ' + ','.join(map(str, r['up']))})")
        for w, t in r["ways"].items():
            print(f"   {w:20s} found: " + ", ".join(
                f"{k} {t[f'{k}_found']}/{t[f'{k}_labelled']}" for k in ("box", "stairs", "ramp"))
                + "; false: " + ", ".join(f"{k} {t[f'false_{k}']}"
                                          for k in ("box", "stairs", "ramp")))
        print(f"   frames whose answers differ: {len(r['changed'])}"
              + (f" ({', '.join(r['changed'])})" if r["changed"] else ""))
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
