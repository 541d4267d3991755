"""What the far planes' second growing (``far_theta``, docs/segmentation.md "Far planes") costs
a real frame: ``segment()`` with ``far_theta`` on (the default) against ``far_theta=0`` (the
reference), interleaved in one process, per frame the minimum over ``--passes``.

Usage::

    bench_far.py [--passes 3] [--frames DIR ...]

Frames: the shared Kinect frames and office1 (``../shared/data/kinect``), and the first two
labelled frames of each ``--frames`` folder (``labels.json``, as ``real_unseen.py`` reads;
default: hunt57 bf-apt-stairs, hunt36 nvblox-lounge, hunt33 ucn, hunt47 arena-low under
/work, when there).  Prints each frame's times and far planes, the sums and the ratio.
"""

from __future__ import annotations

import argparse
import glob
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

SHARED = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "kinect"
DEFAULT = ["/work/hunt57/bf-apt-stairs", "/work/hunt36/nvblox-lounge", "/work/hunt33/ucn",
           "/work/hunt47/arena-low"]


def clouds(folders) -> list:
    """The benchmark's frames as clouds."""
    from real_unseen import read_frame, read_labels

    from planerel.io import read

    out = [read(f, intrinsics="kinect") for f in sorted(glob.glob(str(SHARED / "*.tiff")))]
    if (SHARED / "office1.pcd").is_file():
        out.append(read(str(SHARED / "office1.pcd")))
    for d in folders:
        if os.path.isfile(os.path.join(d, "labels.json")):
            for fr in read_labels(d)["frames"][:2]:
                out.append(read_frame(d, fr)[0])
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--passes", type=int, default=3)
    ap.add_argument("--frames", nargs="*", default=DEFAULT)
    a = ap.parse_args(argv)
    import warnings

    from planerel.segment import segment

    warnings.simplefilter("ignore")
    frames = clouds(a.frames)
    if not frames:
        print("no frames found")
        return 1
    for c in frames:  # compile and warm
        segment(c)
    on = [float("inf")] * len(frames)
    off = [float("inf")] * len(frames)
    added = [0] * len(frames)
    for _ in range(a.passes):
        for i, c in enumerate(frames):
            t = time.process_time()
            segment(c, far_theta=0.0)
            off[i] = min(off[i], time.process_time() - t)
            t = time.process_time()
            s = segment(c)
            on[i] = min(on[i], time.process_time() - t)
            added[i] = s.info.get("far_planes", 0)
    for c, a_, b, k in zip(frames, off, on, added, strict=True):
        print(f"{Path(c.source).name:55s} {c.shape[1]}x{c.shape[0]}  off {1000 * a_:6.1f} ms  "
              f"on {1000 * b:6.1f} ms  far planes {k}")
    so, sn = sum(off), sum(on)
    print(f"{len(frames)} frames, sums of per-frame minima over {a.passes} passes: "
          f"far_theta=0 {so:.3f} s, default {sn:.3f} s; ratio {sn / so:.3f}; "
          f"the far pass {1000 * (sn - so) / len(frames):.1f} ms a frame")
    return 0


if __name__ == "__main__":
    sys.exit(main())
