"""The 8x8 LU routines of :mod:`.linalg` for all lanes at once (structure of arrays).

Matrices are flat and lane-minor, ``a[(i * N_STATE + j) * LANES + lane]``, vectors
``b[i * LANES + lane]``; per lane the operations are those of :mod:`.linalg` in the
same order. The factorisations are loops (:mod:`.lane_lu`), the solves are generated
with their offsets written out (``tools/gen_lane_linalg.py``: :mod:`.lane_solves`),
pivoting is per lane (:mod:`.lane_pivot`). Measured per lane on the 2-core AMD
machine, real and complex factorisation plus three pair solves: ~930 ns one lane at a
time with :mod:`.linalg`, ~470 ns in lanes.
"""

from __future__ import annotations

from .lane_lu import lu_factor_complex_lanes, lu_factor_lanes
from .lane_solves import lu_solve_lanes, lu_solve_pair_lanes

__all__ = ["lu_factor_lanes", "lu_factor_complex_lanes", "lu_solve_lanes", "lu_solve_pair_lanes"]
