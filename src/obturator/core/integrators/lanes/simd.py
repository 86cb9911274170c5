"""The lane width of the batched integrators and the compile flags of their vector kernels.

Lane arrays are flat and component-major with this compile-time stride
(``x[i * LANES + lane]``): with a constant stride LLVM can prove that rows do not
overlap, so the lane loops vectorise without runtime alias checks (with 2-D
arrays of runtime stride they did not vectorise at all). 16 lanes measured
fastest on the 2-core AVX2 development machine (8: slower; 32: within noise).
"""

from ...jit_flags import NO_REFCOUNT, REFCOUNT

__all__ = ["LANES", "LANE_KERNEL", "DRIVER_PHASE", "NO_REFCOUNT", "REFCOUNT"]

LANES = 16

#: numba's flags for the lane kernels, the functions called once per step (or stage)
#: for all lanes that allocate nothing: no fast-math, the NumPy error model (a
#: division never raises, so loops vectorise) and no reference counting
#: (:data:`obturator.core.jit_flags.NO_REFCOUNT`).
LANE_KERNEL: dict[str, object] = {
    "cache": True,
    "fastmath": False,
    "error_model": "numpy",
    **NO_REFCOUNT,
}

#: numba's flags for the phases of the lane drivers' loops: compiled into the loop
#: (numba inlines them), as it is compiled (no fast-math, the NumPy error model, no
#: reference counting), so each driver's loop is one function with no reference counts.
DRIVER_PHASE: dict[str, object] = {**LANE_KERNEL, "inline": "always"}
