"""Profile segment() with perf, naming the numba kernels (this VM has no hardware counters, so
sample the CPU clock).

    perf record -e cpu-clock -F 20000 -o /tmp/perf.data -- \\
        .venv/bin/python benchmarks/profile_kernels.py --scene box --seed 1 --calls 300
    perf report -i /tmp/perf.data --sort sym

numba's machine code has no symbols; this script writes ``/tmp/perf-PID.map`` (perf's map for
JIT code) with the address of every compiled planerel kernel, so ``perf report`` shows
``normals_stream``, ``region_grow_grid_ws`` ... instead of bare addresses.  With ``--dump DIR``
it also saves each kernel's machine code (``DIR/NAME.bin`` and its address in ``NAME.addr``)
for an instruction-level view::

    objdump -D -b binary -m i386:x86-64 --adjust-vma=0x$(cat DIR/NAME.addr) DIR/NAME.bin

against ``perf script -F ip,sym`` sample addresses.  A kernel's extent is taken as the gap to
the next kernel's address (at most 256 KiB), so samples in code numba placed after a kernel may
be attributed to it.
"""

from __future__ import annotations

import argparse
import ctypes
import os
import sys


def kernel_entries() -> list[tuple[int, str]]:
    """(address, name) of every compiled planerel kernel in this process, by address."""
    from planerel.segment import (
        _graph_kernels,
        _kernels,
        _normal_kernels,
        _post_kernels,
        _split_kernels,
    )
    from planerel.segment import _label_kernels as _feature_kernels

    out = set()
    for mod in (_kernels, _graph_kernels, _normal_kernels, _post_kernels, _split_kernels,
                _feature_kernels):
        for name in dir(mod):
            fn = getattr(mod, name)
            for cres in getattr(fn, "overloads", {}).values():
                try:
                    addr = cres.library.get_pointer_to_function(cres.fndesc.llvm_func_name)
                except Exception:  # noqa: BLE001 - a helper without a standalone symbol
                    continue
                if addr:
                    out.add((addr, name))
    return sorted(out)


def write_perf_map(entries, dump: str | None = None) -> str:
    """Write ``/tmp/perf-PID.map`` (and the code of each kernel into ``dump``)."""
    path = f"/tmp/perf-{os.getpid()}.map"
    with open(path, "w") as fh:
        for i, (addr, name) in enumerate(entries):
            size = min((entries[i + 1][0] - addr) if i + 1 < len(entries) else 1 << 16, 1 << 18)
            fh.write(f"{addr:x} {size:x} {name}\n")
            if dump:
                os.makedirs(dump, exist_ok=True)
                with open(os.path.join(dump, f"{name}.bin"), "wb") as code:
                    code.write(ctypes.string_at(addr, size))
                with open(os.path.join(dump, f"{name}.addr"), "w") as a:
                    a.write(f"{addr:x}\n")
    return path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="box", help="planerel.synth.generator class (box, stairs, ramp) or "
                    "a file any planerel reader takes")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--subsample", type=int, default=1)
    ap.add_argument("--calls", type=int, default=300)
    ap.add_argument("--paper", action="store_true", help="refine=False, split=False")
    ap.add_argument("--dump", default=None, metavar="DIR", help="save each kernel's machine code")
    a = ap.parse_args(argv)
    from planerel.segment import segment

    if a.scene in ("box", "stairs", "ramp"):
        from planerel.synth.generator import generate_scene

        cloud = generate_scene(a.scene, seed=a.seed, subsample=a.subsample).cloud
    else:
        from planerel.io.readers import read

        cloud = read(a.scene)
    kw = dict(refine=False, split=False) if a.paper else {}
    segment(cloud, **kw)  # compile or load every kernel the call uses
    path = write_perf_map(kernel_entries(), a.dump)
    print(f"perf map: {path}", file=sys.stderr)
    for _ in range(a.calls):
        segment(cloud, **kw)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
