"""The compiled integrators, one module per method, all keeping one contract.

:mod:`.contract` says what an integrator takes (:class:`Problem`,
:class:`Controls`) and returns (:class:`RawSolution`, with a
:class:`~obturator.status.Status`); :mod:`.common` and :mod:`.linalg` hold
what they share. Methods:

* :mod:`.dop853`: explicit Dormand-Prince 8(5,3), no Jacobian; reports
  ``HandOff.STIFF`` in sticking phases;
* :mod:`.radau`: fifth-order Radau IIA collocation (simplified Newton); under
  ``auto`` reports ``HandOff.NONSTIFF`` once sliding has resumed;
* :mod:`.stick_slip`: the set-valued (width-free) law, event-driven: exact stick and
  slip modes (:mod:`.stick_slip_modes`, the admissible set of
  :mod:`obturator.core.friction_sets`), slips by the phases of :mod:`.radau` and
  stretches of :mod:`.dop853`;
* :mod:`.moreau_jean`: the same law by time-stepping (Moreau-Jean), first order, a
  cross-check;
* :mod:`.rosenbrock`: Shampine's L-stable Rosenbrock pair (ode23s).

:func:`integrate` dispatches on the method name of :data:`obturator.vocab.METHODS`;
``"auto"`` is DOP853 handing the run over to Radau IIA in flight when DOP853
reports stiffness, and back when sliding has resumed (one switch policy for every
driver: :mod:`.switching`): each continues from the
other's last accepted state and time (counters add up; outputs join). The method
modules (and numba) are imported on first use.
"""

from __future__ import annotations

import importlib

import numpy as np

from .contract import Controls, Problem, RawSolution, Status
from .switching import SWITCH, HandOff

__all__ = [
    "AUTO_HAND_BACKS",
    "AUTO_RADAU_TOL_FACTOR",
    "CORE_METHODS",
    "auto_radau_tolerances",
    "continue_auto",
    "Controls",
    "HandOff",
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
_MODULES = {
    "dop853": "dop853",
    "radau": "radau",
    "rosenbrock": "rosenbrock",
    "set-valued": "stick_slip",
    "moreau-jean": "moreau_jean",
}


#: Every method :func:`integrate` runs: ``"auto"`` (the regularised law, DOP853 and
#: Radau IIA switching) and the one-module methods above.
CORE_METHODS: tuple[str, ...] = ("auto", *_MODULES)


def method_module(name: str):
    """The module of one compiled method (``"dop853"``, ``"radau"``, ``"rosenbrock"``)."""
    return importlib.import_module(f".{_MODULES[name]}", __name__)


#: Largest number of times one ``auto`` run goes back from Radau IIA to DOP853
#: (:data:`.switching.SWITCH`).
AUTO_HAND_BACKS = SWITCH.auto_hand_backs


def integrate(method: str, problem: Problem, controls: Controls) -> RawSolution:
    """Run the compiled integrator `method` (``"auto"``, ``"radau"`` or ``"rosenbrock"``).

    ``"auto"``: DOP853, then :func:`continue_auto` where it reports ``STIFF``.
    """
    if method != "auto":
        return method_module(method).integrate(problem, controls)
    return continue_auto(method_module("dop853").integrate(problem, controls), problem, controls)


def continue_auto(
    out: RawSolution, problem: Problem, controls: Controls, hand_backs: int = 0
) -> RawSolution:
    """Finish an ``auto`` run whose last stretch, DOP853's, ended as `out`.

    Where DOP853 reports ``STIFF``, Radau IIA continues from its last accepted state
    (:func:`_hand_over`); where sliding then resumes for half a revolution (status
    ``NONSTIFF``, :func:`.switching.sliding_resumed`), DOP853 again, and so on,
    at most :data:`AUTO_HAND_BACKS` times in all (`hand_backs` already done). On the
    rig the stiff stretch is the stick-slip phase after release; the sliding that
    follows costs DOP853 far less than Radau IIA. The batched lanes
    (:mod:`obturator.solve.many`) switch at the same points.
    """
    dop853 = method_module("dop853").integrate
    while out.status == HandOff.STIFF:
        out = _hand_over(out, problem, controls, hand_backs < AUTO_HAND_BACKS)
        if out.status != HandOff.NONSTIFF:
            break
        hand_backs += 1
        out = _continue(out, dop853, problem, controls)
    return out


def _hand_over(
    dop: RawSolution, problem: Problem, controls: Controls, hand_back: bool = False
) -> RawSolution:
    """Continue a run DOP853 stopped as stiff with Radau IIA from its last accepted state.

    Restarting from t = 0 (as before) repeated the whole non-stiff stretch with the
    costlier implicit method; the hand-over state is an accepted DOP853 step, as
    accurate as any other. A non-finite state (DOP853 diverged) restarts from t0.
    Radau IIA runs at :data:`AUTO_RADAU_TOL_FACTOR` of the tolerances; with
    `hand_back` it stops with ``NONSTIFF`` once sliding has resumed.
    """
    radau = method_module("radau").integrate
    rtol, atol = auto_radau_tolerances(controls.rtol, controls.atol)
    stiff = controls._replace(rtol=rtol, atol=atol, stop_when_sliding=hand_back)
    if not (np.all(np.isfinite(dop.y_end)) and dop.t_end > problem.t0):
        rad = radau(problem, stiff)
        return rad._replace(nfev=rad.nfev + dop.nfev, n_rejected=rad.n_rejected + dop.n_rejected)
    return _continue(dop, radau, problem, stiff)


def _continue(prev: RawSolution, run, problem: Problem, controls: Controls) -> RawSolution:
    """`run` (a compiled integrator) from the end of `prev`, with the steps left; the
    outputs joined and the counters added up."""
    t_eval = controls.t_eval[controls.t_eval > prev.t_end]
    rest = controls._replace(t_eval=t_eval, max_steps=max(controls.max_steps - prev.n_steps, 1))
    nxt = run(problem._replace(y0=prev.y_end, t0=prev.t_end), rest)
    # recorded rows: the previous end state is the next run's first row
    if controls.record and controls.t_eval.shape[0] == 0:
        t = np.concatenate((prev.t, nxt.t[1:]))
        y = np.concatenate((prev.y, nxt.y[1:]))
    else:
        t = np.concatenate((prev.t, nxt.t))
        y = np.concatenate((prev.y, nxt.y))
    if prev.t_event == prev.t_event:  # found before the switch (non-terminal runs)
        nxt = nxt._replace(t_event=prev.t_event, y_event=prev.y_event)
    return nxt._replace(
        t=t,
        y=y,
        nfev=nxt.nfev + prev.nfev,
        njev=nxt.njev + prev.njev,
        n_steps=nxt.n_steps + prev.n_steps,
        n_rejected=nxt.n_rejected + prev.n_rejected,
    )


def __getattr__(name: str):
    """The batched integrators (:mod:`.lanes`), loaded on first use like the methods."""
    if name in ("integrate_lanes", "integrate_radau_lanes"):
        return getattr(importlib.import_module(".lanes", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
