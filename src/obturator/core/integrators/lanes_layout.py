"""The lane width of the batched integrators and the compile flags of their vector kernels.

Lane arrays are flat and component-major with this compile-time stride
(``x[i * LANES + lane]``): with a constant stride LLVM can prove that rows do not
overlap, so the lane loops vectorise without runtime alias checks (with 2-D
arrays of runtime stride they did not vectorise at all). 16 lanes measured
fastest on the 2-core AVX2 development machine (8: slower; 32: within noise).
"""

from numba.core.options import DefaultOptions

__all__ = ["LANES", "LANE_KERNEL", "NO_REFCOUNT"]

LANES = 16

#: numba's flags for the lane kernels, the functions called once per step (or stage)
#: for all lanes that allocate nothing: FMA contraction, the NumPy error model (a
#: division never raises, so loops vectorise) and, where numba has the option, no
#: reference counting. numba otherwise increments and decrements (atomically) the
#: count of every array passed between such functions on each call; perf put those
#: atomics at ~40 % of the DOP853 lanes' time and ~15 % of the Radau IIA lanes'.
#: ``_nrt`` is numba's own switch for it (``numba.core.options.DefaultOptions``),
#: inherited by callees, so a kernel must not call anything that allocates; where a
#: numba release lacks the switch the kernels are compiled as before (slower, same
#: results).
NO_REFCOUNT: dict[str, object] = {"_nrt": False} if hasattr(DefaultOptions, "_nrt") else {}
LANE_KERNEL: dict[str, object] = {
    "cache": True,
    "fastmath": {"contract"},
    "error_model": "numpy",
    **NO_REFCOUNT,
}
