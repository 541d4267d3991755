"""The cost of the four real-staircase rules (2026-11-29): ``describe_scene`` on the real frames
of ``../shared/data`` (3 Kinect TIFFs, 7 mOSD PCDs) with the rules on (the defaults) and off
(``step_tread_axes``, ``riser_pieces``, ``floor_tread`` False, ``facet_max_width`` 0), the two
alternated 7 times in one process on the same segmentations; prints process time per pass
over the 10 frames and the ratios (minimum and median) on / off.

    nice taskset -c 1 .venv/bin/python benchmarks/ab_real_stairs_rules.py
"""

from __future__ import annotations

import glob
import time
from pathlib import Path

import numpy as np

from planerel.features.curved import CurvedParams
from planerel.features.facts import describe_scene
from planerel.features.relations import ProposalParams
from planerel.io import read
from planerel.segment import segment

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def main() -> None:
    files = (sorted(glob.glob(str(DATA / "kinect" / "frame_*_depth.tiff")))
             + sorted(glob.glob(str(DATA / "mosd" / "*.pcd"))))
    if not files:
        raise SystemExit(f"no real frames under {DATA} (../shared/data/README.md)")
    settings = {
        "on": {"proposal_params": ProposalParams(), "curved_params": CurvedParams()},
        "off": {"proposal_params": ProposalParams(step_tread_axes=False, riser_pieces=False,
                                                  floor_tread=False),
                "curved_params": CurvedParams(facet_max_width=0.0)},
    }
    scenes = []
    for f in files:
        cloud = read(f) if f.endswith(".pcd") else read(f, intrinsics="kinect")
        scenes.append((cloud, segment(cloud).labels))
    for kw in settings.values():  # compile and warm both paths
        for cloud, labels in scenes:
            describe_scene(cloud, labels, **kw)
    times: dict = {"on": [], "off": []}
    for rep in range(7):
        order = ("on", "off") if rep % 2 == 0 else ("off", "on")
        for name in order:
            t = time.process_time()
            for cloud, labels in scenes:
                describe_scene(cloud, labels, **settings[name])
            times[name].append(time.process_time() - t)
    for name, v in times.items():
        print(f"{name}: min {1000 * min(v):.1f} ms, median {1000 * float(np.median(v)):.1f} ms "
              f"a pass over {len(scenes)} frames")
    print(f"on / off: ratio of minima {min(times['on']) / min(times['off']):.3f}, of medians "
          f"{float(np.median(times['on'])) / float(np.median(times['off'])):.3f}")


if __name__ == "__main__":
    main()
