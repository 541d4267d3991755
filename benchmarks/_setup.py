"""Setup shared by the segmentation benchmarks (bench_segment.py, bench_adapt.py): one core,
the data folder, the speed scenes and the real frames.  Imported by the scripts of this folder
(``python benchmarks/NAME.py`` puts the folder on ``sys.path``)."""

from __future__ import annotations

import glob
import os
from pathlib import Path

#: Speed scenes: the generator's staircase seed 3 (the benchmark's scene since the first
#: revision; 44 % of the pixels invalid at 640x480: background beyond range) and a box scene
#: seed 1 (99 % valid, the density of a real indoor Kinect frame).
SCENES = (("stairs", 3), ("box", 1))


def one_core() -> None:
    """Run this process on one core with single-threaded numba / BLAS (the machine is shared;
    timings then compare like with like)."""
    for var in ("NUMBA_NUM_THREADS", "OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, "1")
    try:
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    except (AttributeError, OSError):
        pass


def data_dir(name: str = "") -> Path:
    """``../shared/data[/name]`` next to the checkout."""
    d = Path(__file__).resolve().parents[2] / "shared" / "data"
    return d / name if name else d


def synth_scene(kind: str, sub: int, cls: str = "stairs", seed: int = 3):
    """``(cloud, gt_labels)`` of a speed scene at 640x480 / ``sub``: the generator's ``cls``
    scene (``kind="synth"``) or the analytic staircase of planerel.segment._scenes."""
    if kind == "synth":
        try:
            from planerel.synth.generator import generate_scene

            sc = generate_scene(cls, seed=seed, subsample=sub)
            return sc.cloud, sc.gt_labels
        except ImportError:
            pass
    from planerel.segment._scenes import staircase

    c, gt, _, _ = staircase(640 // sub, 480 // sub, seed=0)
    return c, gt


def kinect_files(folder=None) -> list[str]:
    """The raw Kinect depth TIFFs (sorted) of ``folder`` (default ``../shared/data/kinect``)."""
    return sorted(glob.glob(os.path.join(str(folder or data_dir("kinect")), "*_depth.tiff")))


def cluttered_set(folder, n: int, seed: int = 22) -> Path:
    """Write ``n`` cluttered varied-world scenes (320x240, 2-3 extra objects; a third each
    stairs and ramp, the rest boxes) into ``folder/synth`` with the CLI and return that
    folder: the synthetic frames of bench_proposals.py and bench_curved.py."""
    from planerel.cli import main as cli

    ds = Path(folder) / "synth"
    cli(["dataset", "synth", str(ds), "--world", "varied", "--n-box", str(n - 2 * (n // 3)),
         "--n-stairs", str(n // 3), "--n-ramp", str(n // 3), "--subsample", "2",
         "--range", "extra_objects=2,3", "--seed", str(seed), "--quiet"])
    return ds
