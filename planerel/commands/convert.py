"""``planerel convert``: read any supported scan and write it as XYZ ``.npy`` or PLY."""

from __future__ import annotations

from pathlib import Path

from planerel.commands._common import (
    add_input_options,
    check_input_options,
    parse_intrinsics,
    read_input,
)
from planerel.errors import InputError

__all__ = ["register"]


def register(sub) -> None:
    p = sub.add_parser(
        "convert",
        help="convert a scan (depth PNG/TIFF, PCD, PLY, NPY, ABW range) to .npy XYZ, .ply or .pcd",
        description="Read any scan planerel reads and write it as an (H, W, 3) XYZ .npy "
                    "(metres, NaN = invalid), a PLY of its valid points, or a binary PCD "
                    "(organized when the scan is, NaN kept). The input's colours (PCD rgb/rgba, "
                    "PLY red/green/blue) are kept in PLY and PCD.",
    )
    p.add_argument("input", help="the scan to read")
    p.add_argument("-o", "--output", required=True, help="OUT.npy, OUT.ply or OUT.pcd")
    add_input_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    import numpy as np

    from planerel.atomic import atomic_path, check_not_inputs, check_output_file
    from planerel.io.exports import input_colours, write_pcd
    from planerel.io.writers import write_ply

    out = Path(args.output)
    kind = out.suffix.lower()
    if kind not in (".npy", ".ply", ".pcd"):
        raise InputError(f"{out}: output must end in .npy, .ply or .pcd")
    check_input_options(args)
    check_output_file(args.output, "-o")  # the text: Path() drops a trailing slash
    check_not_inputs([out], [args.input])
    cloud = read_input(args.input, args)
    if cloud.n_valid == 0:
        raise InputError(f"{args.input}: has no valid point (every depth is 0 or NaN); "
                         "nothing to convert")
    rgb = input_colours(args.input, cloud.shape, args.subsample or 1,
                        organize=getattr(args, "organize", True),
                        intrinsics=parse_intrinsics(getattr(args, "intrinsics", None)))
    if kind == ".npy":
        with atomic_path(out, suffix=".npy") as tmp:
            np.save(tmp, cloud.xyz, allow_pickle=False)
    elif kind == ".pcd":
        write_pcd(out, cloud.xyz, colours=rgb)
    else:
        write_ply(out, cloud.xyz, colours=rgb)
    h, w = cloud.shape
    print(f"{args.input}: {w}x{h}, {cloud.n_valid} valid points -> {out}")
    return 0
