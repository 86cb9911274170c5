"""The 8x8 LU routines of :mod:`.linalg` for all lanes at once (structure of arrays).

Matrices are flat and lane-minor, ``a[(i * N_STATE + j) * LANES + lane]``, vectors
``b[i * LANES + lane]``. The routines are generated with their offsets written out
(``tools/gen_lane_linalg.py``: :mod:`.lane_lu_real`, :mod:`.lane_lu_complex`,
:mod:`.lane_solve_pair`), pivoting is per lane (:mod:`.lane_pivot`); per lane the
operations are those of :mod:`.linalg` in the same order. Measured per lane on the
2-core AMD machine, real and complex factorisation plus three pair solves: 930 ns
one lane at a time with :mod:`.linalg`, 500 ns in lanes with loops over rows and
columns (LLVM left those 16-lane loops scalar), and see ``benchmarks`` for the
generated form.
"""

from __future__ import annotations

from .lane_lu_complex import lu_factor_complex_lanes
from .lane_lu_real import lu_factor_lanes, lu_solve_lanes
from .lane_solve_pair import lu_solve_pair_lanes

__all__ = ["lu_factor_lanes", "lu_factor_complex_lanes", "lu_solve_lanes", "lu_solve_pair_lanes"]
