"""Model opening times for a candidate at given spins, cached per parameter vector.

A fit evaluates the same parameter vector at the same spin rates more than once
(the optimiser's accepted point, the Jacobian's base point, the slope runs of
the error-in-variables term, the out-of-band prediction): :class:`ModelEvaluator`
keeps every t_cr it has computed, keyed by (parameter vector, spin).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._docs import field_docs
from ..solve import SolverOptions, opening_times
from ..status import Status
from .candidates import Candidate
from .floor import SPIN_REGULATION

__all__ = ["DEFAULT_T_MAX", "VALIDATION_OPTIONS", "ModelEvaluator"]

#: Integration horizon [s]: 30 times the slowest measured opening (0.658 s).
DEFAULT_T_MAX = 20.0
#: Solver settings of the study: rtol 1e-9 (package default 1e-8), width 1e-7. At the
#: fitted parameters of the candidates, the package defaults fail the 1e-3 threshold of
#: :func:`obturator.solve.convergence_check` on some runs (DOP853 reports stiffness and
#: the Radau rerun works at 0.1 rtol^(2/3)); at rtol 1e-9 every run passes, for about
#: the same cost (the figures per candidate: ``docs/benchmarks.md``, history).
VALIDATION_OPTIONS = SolverOptions(rtol=1e-9, atol=1e-11)


@field_docs
@dataclass
class ModelEvaluator:
    """Exact-model t_cr of one candidate, cached."""

    #: The candidate whose t_cr is computed.
    candidate: Candidate
    #: Horizon [s]; a run not opened by then is censored (NaN).
    t_max: float = DEFAULT_T_MAX
    #: Solver settings (None: :data:`VALIDATION_OPTIONS`).
    options: SolverOptions | None = None
    #: Trajectories actually integrated (cache misses).
    n_integrations: int = 0
    #: Integrations that failed or hit the step limit (counted as censored).
    n_failed: int = 0
    #: Cache: t_cr [s] (NaN: censored) of each (parameter values, spin rate [rad/s]) integrated.
    _cache: dict[tuple[tuple[float, ...], float], float] = field(default_factory=dict, repr=False)

    def opening_times(self, values: Sequence[float], spin_rate: ArrayLike) -> NDArray[np.float64]:
        """t_cr [s] at each spin [rad/s] (NaN: not opened by ``t_max``).

        Parameters
        ----------
        values : sequence of float
            Values of ``candidate.params`` (physical units).
        spin_rate : array_like
            omega_p [rad/s].
        """
        return self.opening_times_of([values], spin_rate)[0]

    def opening_times_of(
        self, values: Sequence[Sequence[float]], spin_rate: ArrayLike
    ) -> NDArray[np.float64]:
        """t_cr [s] of several parameter vectors at each spin, shape (len(values), n_spins).

        Every (vector, spin) not yet in the cache goes through one call of
        :func:`obturator.solve.opening_times` (lanes where the options allow: the more
        points a call has, the fuller the lanes; a finite-difference Jacobian asks for
        all its columns at once).
        """
        keys = [tuple(float(v) for v in vals) for vals in values]
        w = [float(x) for x in np.asarray(spin_rate, dtype=float).reshape(-1)]
        missing = list(dict.fromkeys((k, x) for k in keys for x in w if (k, x) not in self._cache))
        if missing:
            cases = [self.candidate.build(x, k, self.t_max) for k, x in missing]
            t, status, _ = opening_times(cases, self.options or VALIDATION_OPTIONS)
            self.n_integrations += len(missing)
            self.n_failed += int(np.isin(status, (Status.FAILED, Status.STEP_LIMIT)).sum())
            self._cache.update(zip(missing, t.tolist(), strict=True))
        return np.array([[self._cache[(k, x)] for x in w] for k in keys]).reshape(len(keys), -1)

    def slopes(
        self, values: Sequence[float], spin_rate: ArrayLike, half_width: float = SPIN_REGULATION
    ) -> NDArray[np.float64]:
        """Secant dt_cr/domega_p [s^2] over w +- `half_width` (NaN if either end is censored)."""
        w = np.asarray(spin_rate, dtype=float).reshape(-1)
        lo = np.maximum(w - half_width, 1e-3)
        both = self.opening_times_of([values], np.concatenate((w + half_width, lo)))[0]
        return (both[: w.size] - both[w.size :]) / (w + half_width - lo)
