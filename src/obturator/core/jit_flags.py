"""numba flags shared by the compiled core: reference counting off where nothing allocates.

numba counts references to every array passed between compiled functions, with
atomic increments and decrements around most calls; its pruning pass removes
them only in simple control flow. In the integrators' hot loops they were most of
the time: perf put them at ~60 % of one DOP853 trajectory, ~40 % of the DOP853
lanes and ~15 % of the Radau IIA lanes. Functions that allocate nothing (the
right-hand side, the step and error sums, the linear algebra) are compiled with
numba's own switch for it, ``_nrt=False`` (``numba.core.options.DefaultOptions``),
which callees inherit: such a function must not call one that allocates. Where a
numba release lacks the switch the flags are empty and the code is compiled as
before (slower, same results).
"""

from __future__ import annotations

from numba.core.options import DefaultOptions

__all__ = ["NO_REFCOUNT"]

#: Extra ``njit`` options of the functions that allocate nothing.
NO_REFCOUNT: dict[str, object] = {"_nrt": False} if hasattr(DefaultOptions, "_nrt") else {}
