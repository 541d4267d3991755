"""Low-level helpers for the numba kernels.

:func:`prefetch` asks the CPU to bring an array element's cache line closer while the kernel
works on something else.  It never changes a result (a prefetch of any address, even outside
the array, does not fault), only when the data arrives.

numba's on-disk cache of a kernel does not notice edits to this module: after changing it,
delete the ``__pycache__/*.nbi`` / ``*.nbc`` files next to the kernels that use it.
"""

from __future__ import annotations

from llvmlite import ir
from numba import types
from numba.core import cgutils, config
from numba.extending import intrinsic

__all__ = ["prefetch"]


@intrinsic
def prefetch(typingctx, arr, index):
    """Prefetch ``arr.reshape(-1)[index]`` for reading (``arr`` contiguous, ``index`` an
    integer; out-of-range indices are harmless)."""
    if not isinstance(arr, types.Array) or not isinstance(index, types.Integer):
        return None
    sig = types.void(arr, index)

    def codegen(context, builder, signature, args):
        aryty = signature.args[0]
        ary = context.make_array(aryty)(context, builder, args[0])
        i64 = ir.IntType(64)
        i32 = ir.IntType(32)
        idx = args[1]
        if idx.type.width < 64:
            idx = builder.sext(idx, i64) if signature.args[1].signed else builder.zext(idx, i64)
        off = builder.mul(idx, i64(context.get_abi_sizeof(context.get_data_type(aryty.dtype))))
        ptr = builder.gep(builder.bitcast(ary.data, ir.IntType(8).as_pointer()), [off])
        fnty = ir.FunctionType(ir.VoidType(), [ir.IntType(8).as_pointer(), i32, i32, i32])
        fn = cgutils.get_or_insert_function(builder.module, fnty, "llvm.prefetch.p0i8")
        # read, high temporal locality, data cache
        builder.call(fn, [ptr, i32(0), i32(3), i32(1)])
        return context.get_dummy_value()

    return sig, codegen


if config.DISABLE_JIT:  # the kernels run as plain Python (coverage runs): nothing to prefetch
    def prefetch(arr, index):  # noqa: F811
        """No-op stand-in for the intrinsic when numba's JIT is disabled."""
        return None
