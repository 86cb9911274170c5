"""Fused multiply-add, ``fma(a, b, c) = a * b + c`` rounded once, as written.

The compiled core runs without fast-math (:mod:`obturator.core.jit_flags`): LLVM's
contraction of ``a * b + c`` into one fused operation depended on the context a function
was compiled in (inlined or not, the vectorised body of a loop or its scalar remainder),
so the same point gave different bits alone and in a batch, from cached and from freshly
compiled code. This function asks for the fusion explicitly instead: it is LLVM's
``llvm.fma.f64`` intrinsic, whose result is defined as the exactly rounded ``a * b + c``
(IEEE 754 fusedMultiplyAdd, C's ``fma``) in every context, scalar or vectorised. On
a CPU with FMA instructions it is one instruction and vectorises; on one without, LLVM
calls the C library's ``fma``: slower, the same bits.

Used where a multiply feeds an add in the integrators' hot arithmetic (the LU
factorisations and solves, DOP853's stage and error sums; scalar and in lanes, in the
same order): one rounding instead of two, one instruction instead of two.
"""

from __future__ import annotations

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

__all__ = ["fma"]


@intrinsic
def fma(typingctx, a, b, c):  # type: ignore[no-untyped-def]
    """``a * b + c`` with one rounding (float64; other real arguments are converted).

    Parameters
    ----------
    a, b, c : float
        Operands (any numba real or integer type, converted to float64 exactly as
        numba converts them in ``a * b + c``).

    Returns
    -------
    float
        The exactly rounded value of ``a * b + c``.
    """
    real = (types.Float, types.Integer)
    if not all(isinstance(x, real) for x in (a, b, c)):
        return None
    sig = types.float64(a, b, c)

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        double = ir.DoubleType()
        ops = [
            context.cast(builder, v, t, types.float64)
            for v, t in zip(args, signature.args, strict=True)
        ]
        fnty = ir.FunctionType(double, [double, double, double])
        fn = cgutils.get_or_insert_function(builder.module, fnty, "llvm.fma.f64")
        return builder.call(fn, ops)

    return sig, codegen
