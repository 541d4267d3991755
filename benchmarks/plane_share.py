"""The share of each real frame's valid pixels the segmentation puts in a plane, with the
narrow normal window and with the wide one (srob59, docs/segmentation.md "Staircases under
correlated noise and holes").  A measuring tool: which real frames ``wide_fallback`` would
segment again, and what the wide window makes of them.

Usage::

    plane_share.py DIR [DIR ...] [--stairs DIR] [--below F] [--json F]

``DIR`` is a labelled set folder (``labels.json``, :mod:`real_unseen`) or a folder of them;
``--stairs`` stair-perception's samples (:mod:`stairs_robust`).  Per frame: the noise kind,
``wave`` and the 5 px / 15 px noise (mm at the median depth), the share of valid pixels in a
plane with the segmentation's defaults (``narrow``) and, when that share is under ``--below``
(0.5; 1 for every frame), with ``wide_noise_window`` (``wide``).
"""

from __future__ import annotations

import argparse
import glob
import json
import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))


def assigned_share(seg, cloud) -> float:
    """Share of ``cloud``'s valid pixels that ``seg`` (a Segmentation) puts in a plane (0 with
    none valid)."""
    from planerel.segment import planar_share

    return planar_share(cloud, seg.labels) or 0.0


def frame_row(name: str, cloud, below: float = 0.5) -> dict:
    """One frame's row: noise figures, the narrow share and (under ``below``) the wide one."""
    from planerel.segment import segment
    from planerel.segment.noise import WIDE_PATCH, estimate_noise

    m5 = estimate_noise(cloud, waviness=True)
    m15 = estimate_noise(cloud, patch=WIDE_PATCH)
    z = m5.z_median
    row = {"frame": name, "kind": m5.kind, "wave": round(float(m5.wave), 2),
           "z": round(float(z), 2) if z else None,
           "s5_mm": round(1000 * float(m5.sigma(z)), 2) if z else None,
           "s15_mm": round(1000 * float(m15.sigma(z)), 2) if z and m15.reliable else None,
           # the narrow window alone: the fallback (on by default since up66) off
           "narrow": round(assigned_share(segment(cloud, wide_fallback=0.0), cloud), 3)}
    if row["narrow"] < below:
        row["wide"] = round(assigned_share(segment(cloud, wide_noise_window=True), cloud), 3)
    return row


def frames(dirs=(), stairs_dir=None):
    """``(name, cloud)`` of every frame of the set folders ``dirs`` and of ``stairs_dir``."""
    from real_census import set_folders
    from real_unseen import read_frame, read_labels

    if stairs_dir:
        from real_stairs import INTRINSICS

        import planerel

        for p in sorted(glob.glob(os.path.join(stairs_dir, "*_depth.png"))):
            yield (f"stair-perception/{Path(p).stem}",
                   planerel.read(p, intrinsics=INTRINSICS, depth_scale=1000))
    for folder in set_folders(dirs):
        doc = read_labels(str(folder))
        for fr in doc["frames"]:
            cloud, _up = read_frame(str(folder), fr)
            yield f"{folder.name}/{Path(fr['file']).stem}", cloud


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dirs", nargs="*", metavar="DIR")
    ap.add_argument("--stairs", help="stair-perception's samples folder")
    ap.add_argument("--below", type=float, default=0.5)
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    rows = []
    for name, cloud in frames(a.dirs, a.stairs):
        r = frame_row(name, cloud, a.below)
        rows.append(r)
        wide = f" -> wide {r['wide']:.3f}" if "wide" in r else ""
        print(f"{name:48s} {r['kind']:7s} wave {r['wave']:5.2f} z {r['z']} s5 {r['s5_mm']} "
              f"s15 {r['s15_mm']} mm  narrow {r['narrow']:.3f}{wide}", flush=True)
    low = [r for r in rows if "wide" in r]
    print(f"{len(low)} of {len(rows)} frames under {a.below}: "
          + ", ".join(r["frame"] for r in low))
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
