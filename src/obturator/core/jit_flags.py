"""numba flags shared by the compiled core, stated on every compiled function.

**No fast-math flag at all** (``fastmath=False`` everywhere, FMA contraction
included). With any of them LLVM may round differently by context: fuse a multiply
into an add once a function is inlined into its caller, or in a vectorised loop but
not in its scalar remainder. A function's bits then depended on where it was compiled:
a caller loaded from numba's cache runs its own linked copy of a callee, a compiling
process binds the callee's library, and a lane's bits on how many lanes were live.
Without them every operation is rounded as written, so freshly compiled, cached and
batched code give the same t_cr bit for bit (``tests/core/test_fresh_compile.py``,
``tests/solve/test_plan.py``). Where a fused multiply-add pays (the LU factorisations
and solves), it is written out, :func:`obturator.core.fma.fma`, which rounds once in
every context.

**Every flag that numba lets a callee inherit is stated explicitly.** numba
compiles a jitted function once per signature, the first time any caller needs
it, and ``fastmath``, ``error_model`` and reference counting (``_nrt``) that the
function does not state itself are taken from *that first caller*
(``numba.core.cpu.CPUTargetOptions.finalize``, ``Flags.inherit_if_not_set``).
A helper shared by the integrators (the right-hand side, the torque law, the
event search) was therefore compiled with one error model or another
depending on which integrator, or which test, happened to compile first. With every decorator in
``core/`` stating all three flags (``tests/core/test_jit_flags.py`` checks it,
and that two opposite compile orders give the same bits), no order can matter.
Functions inlined at numba's IR level (``inline="always"``) take their caller's
flags by construction, which is deterministic.

Reference counting: numba counts references to every array passed between
compiled functions, with atomic increments and decrements around most calls;
its pruning pass removes them only in simple control flow. In the integrators'
hot loops they were most of the time: perf put them at ~60 % of one DOP853
trajectory, ~40 % of the DOP853 lanes and ~15 % of the Radau IIA lanes.
Functions that allocate nothing (the right-hand side, the step and error sums,
the linear algebra) are compiled with numba's own switch for it, ``_nrt=False``
(``numba.core.options.DefaultOptions``): :data:`NO_REFCOUNT`. Functions that
allocate state :data:`REFCOUNT` (on). A function without counting must not call
one that allocates. Where a numba release lacks the switch both are empty and
the code is compiled with counting everywhere (slower, same results).
"""

from __future__ import annotations

from numba.core.options import DefaultOptions

__all__ = ["INHERITED_FLAGS", "NO_REFCOUNT", "REFCOUNT"]

_HAS_NRT_SWITCH = hasattr(DefaultOptions, "_nrt")

#: Extra ``njit`` options of the functions that allocate nothing.
NO_REFCOUNT: dict[str, object] = {"_nrt": False} if _HAS_NRT_SWITCH else {}
#: Extra ``njit`` options of the functions that allocate (counting stated, not inherited).
REFCOUNT: dict[str, object] = {"_nrt": True} if _HAS_NRT_SWITCH else {}
#: The ``njit`` options a callee would otherwise take from its first caller.
INHERITED_FLAGS: tuple[str, ...] = ("fastmath", "error_model") + (
    ("_nrt",) if _HAS_NRT_SWITCH else ()
)
