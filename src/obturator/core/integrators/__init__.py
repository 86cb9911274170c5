"""The compiled integrators, one module per method, all keeping one contract.

:mod:`.contract` says what an integrator takes (:class:`Problem`,
:class:`Controls`) and returns (:class:`RawSolution`, with a
:class:`~obturator.status.Status`); :mod:`.common` and :mod:`.linalg` hold
what they share. Methods:

* :mod:`.dop853`: explicit Dormand-Prince 8(5,3), no Jacobian; reports
  ``STIFF`` in sticking phases;
* :mod:`.radau`: fifth-order Radau IIA collocation (simplified Newton);
* :mod:`.rosenbrock`: Shampine's L-stable Rosenbrock pair (ode23s).

:func:`integrate` dispatches on the method name of :data:`obturator.vocab.METHODS`;
``"auto"`` is DOP853 handing the run over to Radau IIA in flight when DOP853
reports stiffness: Radau continues from DOP853's last accepted state and time
(counters add up; outputs join). The method modules (and numba) are imported on
first use.
"""

from __future__ import annotations

import importlib

import numpy as np

from .contract import Controls, Problem, RawSolution, Status

__all__ = [
    "AUTO_RADAU_TOL_FACTOR",
    "auto_radau_tolerances",
    "Controls",
    "Problem",
    "RawSolution",
    "Status",
    "integrate",
    "method_module",
]

#: ``auto`` runs Radau IIA at this fraction of the requested tolerances. The stiff
#: stretches are near-stick, where t_cr amplifies local errors (stick-slip twice per
#: revolution): on 1,786 near-stick rig points (100-207 rad/s) Radau at rtol 1e-8 left
#: t_cr errors up to 9.7e-5, at 3.3e-9 at most 8e-8, for ~13 % more Radau work.
AUTO_RADAU_TOL_FACTOR = 1.0 / 3.0


def auto_radau_tolerances(rtol: float, atol: float) -> tuple[float, float]:
    """(rtol, atol) of ``auto``'s Radau IIA stretches for requested (rtol, atol): both
    times :data:`AUTO_RADAU_TOL_FACTOR`. Used by the scalar hand-over and the Radau lanes."""
    return rtol * AUTO_RADAU_TOL_FACTOR, atol * AUTO_RADAU_TOL_FACTOR


#: Method name -> module defining ``integrate(problem, controls)``.
_MODULES = {"dop853": "dop853", "radau": "radau", "rosenbrock": "rosenbrock"}


def method_module(name: str):
    """The module of one compiled method (``"dop853"``, ``"radau"``, ``"rosenbrock"``)."""
    return importlib.import_module(f".{_MODULES[name]}", __name__)


def integrate(method: str, problem: Problem, controls: Controls) -> RawSolution:
    """Run the compiled integrator `method` (``"auto"``, ``"radau"`` or ``"rosenbrock"``)."""
    if method != "auto":
        return method_module(method).integrate(problem, controls)
    out = method_module("dop853").integrate(problem, controls)
    if out.status != Status.STIFF:
        return out
    return _hand_over(out, problem, controls)


def _hand_over(dop: RawSolution, problem: Problem, controls: Controls) -> RawSolution:
    """Continue a run DOP853 stopped as stiff with Radau IIA from its last accepted state.

    Restarting from t = 0 (as before) repeated the whole non-stiff stretch with the
    costlier implicit method; the hand-over state is an accepted DOP853 step, as
    accurate as any other. A non-finite state (DOP853 diverged) restarts from t0.
    Radau IIA runs at :data:`AUTO_RADAU_TOL_FACTOR` of the tolerances.
    """
    radau = method_module("radau").integrate
    rtol, atol = auto_radau_tolerances(controls.rtol, controls.atol)
    controls = controls._replace(rtol=rtol, atol=atol)
    if not (np.all(np.isfinite(dop.y_end)) and dop.t_end > problem.t0):
        rad = radau(problem, controls)
        return rad._replace(nfev=rad.nfev + dop.nfev, n_rejected=rad.n_rejected + dop.n_rejected)
    t_eval = controls.t_eval[controls.t_eval > dop.t_end]
    rest = controls._replace(t_eval=t_eval, max_steps=max(controls.max_steps - dop.n_steps, 1))
    rad = radau(problem._replace(y0=dop.y_end, t0=dop.t_end), rest)
    # recorded rows: DOP853's end state is Radau's first row
    if controls.record and controls.t_eval.shape[0] == 0:
        t = np.concatenate((dop.t, rad.t[1:]))
        y = np.concatenate((dop.y, rad.y[1:]))
    else:
        t = np.concatenate((dop.t, rad.t))
        y = np.concatenate((dop.y, rad.y))
    if dop.t_event == dop.t_event:  # found before the hand-over (non-terminal runs)
        rad = rad._replace(t_event=dop.t_event, y_event=dop.y_event)
    return rad._replace(
        t=t,
        y=y,
        nfev=rad.nfev + dop.nfev,
        n_steps=rad.n_steps + dop.n_steps,
        n_rejected=rad.n_rejected + dop.n_rejected,
    )
