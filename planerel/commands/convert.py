"""``planerel convert``: read any supported scan and write it as XYZ ``.npy`` or PLY."""

from __future__ import annotations

from pathlib import Path

from planerel.commands._common import add_input_options, read_input
from planerel.errors import InputError

__all__ = ["register"]


def register(sub) -> None:
    p = sub.add_parser(
        "convert",
        help="convert a scan (depth PNG/TIFF, PCD, PLY, NPY, ABW range) to .npy XYZ or .ply",
        description="Read any scan planerel reads and write it as an (H, W, 3) XYZ .npy "
                    "(metres, NaN = invalid) or a PLY of its valid points.",
    )
    p.add_argument("input", help="the scan to read")
    p.add_argument("-o", "--output", required=True, help="OUT.npy or OUT.ply")
    add_input_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    import numpy as np

    from planerel.atomic import atomic_path
    from planerel.writers import write_ply

    out = Path(args.output)
    if out.suffix.lower() not in (".npy", ".ply"):
        raise InputError(f"{out}: output must end in .npy or .ply")
    cloud = read_input(args.input, args)
    if out.suffix.lower() == ".npy":
        with atomic_path(out, suffix=".npy") as tmp:
            np.save(tmp, cloud.xyz, allow_pickle=False)
    else:
        write_ply(out, cloud.xyz)
    h, w = cloud.shape
    print(f"{args.input}: {w}x{h}, {cloud.n_valid} valid points -> {out}")
    return 0
