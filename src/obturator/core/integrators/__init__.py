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
``"auto"`` is DOP853 with the whole run repeated by Radau IIA when DOP853
reports stiffness (nfev then counts both runs). The method modules (and numba)
are imported on first use.
"""

from __future__ import annotations

import importlib

from .contract import Controls, Problem, RawSolution, Status

__all__ = ["Controls", "Problem", "RawSolution", "Status", "integrate", "method_module"]

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
    rad = method_module("radau").integrate(problem, controls)
    return rad._replace(nfev=rad.nfev + out.nfev)
