"""Candidate mechanisms for the spin-rig opening time: a registry (issue 9, item 2).

Each :class:`Candidate` names a set of fitted parameters (keys of
:data:`PARAMETERS`) and fixed settings, and builds a
:class:`~obturator.model.case.Case` for one spin rate from a parameter vector
(:meth:`Candidate.build`). Every mechanism is also a plain keyword of
:func:`obturator.model.cases.rig_case` (so ``simulate`` and ``sweep`` reach it too):

=======================  ======================================================
parameter                rig_case keyword
=======================  ======================================================
``mu_s``                 ``mu_s``
``theta0_deg``           ``theta0_deg``
``theta_dot0``           ``release_rate[0]``
``phi_dot0``             ``release_rate[1]``
``psi_dot0``             ``release_rate[2]`` (psi_dot_0 - omega_p)
``release_phase``        ``release_phase`` (psi_0)
``speed_ratio``          ``speed_law=SlipSpeedLaw(kind, ratio, speed)``
``slip_speed``           (same)
``patch_radius``         ``patch_radius`` [m] with ``torque_model="coulomb"``
``ageing_rate``          ``ageing=ContactAgeing(rate, cutoff_time)``
``ageing_time``          (same; :mod:`obturator.model.ageing`)
=======================  ======================================================

The ``ageing`` candidate is the one argued from the tribology of the rig's
dry steel-on-PMMA contact rather than fitted for shape: static friction that
grows with the contact's age (Dieterich 1972; Dieterich and Kilgore 1994;
Berthoud et al. 1999), where the age of the lucite seat's asperities is the
time the contact patch takes to pass over them as the seat turns under the
ball, 2 a / (R_s omega_p): longer at low spin (see :mod:`obturator.model.ageing`
for the argument and the references).

Physical ranges
---------------
Every parameter is an entry of the one fit registry
(:data:`obturator.params.FIT_SPECS`, read as
:class:`obturator.fitting.FitParameter`): hard fit ``bounds`` (wide: where
the model is still defined and cheap) and a narrower ``plausible`` range
argued from the rig (thesis chapter III) in its ``reason``. A fitted value
outside its plausible range is reported as such; it is the data asking for
more than the mechanism can physically give.

Spin-rate fluctuation is not a candidate here: it is part of every
candidate's likelihood as an error-in-variables term (see
:mod:`obturator.validation.likelihood`).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._docs import field_docs
from ..calibration.rig_model import apply_run_settings
from ..errors import InputError
from ..fitting import FIT_PARAMETERS, FitParameter
from ..model.ageing import ContactAgeing
from ..model.case import Case
from ..model.cases import TABLE1, rig_case
from ..model.torques import SlipSpeedLaw, hertz_patch_radius

__all__ = [
    "CANDIDATES",
    "DEFAULT_MODELS",
    "HERTZ_PATCH_RADIUS",
    "HERTZ_PATCH_RADIUS_MM",
    "NOMINAL",
    "PARAMETERS",
    "THESIS_MU_S",
    "Candidate",
    "get_candidates",
]

#: The thesis's friction coefficient from the starred runs (chapter IV, Eq. 95ff).
THESIS_MU_S = 0.5473
#: Hertz radius of the steel ball in the lucite seat under W (Table 1 rig) [m].
HERTZ_PATCH_RADIUS = hertz_patch_radius(
    TABLE1["rig_weight"], TABLE1["ball_radius"], TABLE1["gap"], seat_material="lucite"
)
#: The same in mm.
HERTZ_PATCH_RADIUS_MM = 1e3 * HERTZ_PATCH_RADIUS


#: The value of each parameter a candidate does not fit (unless in its ``fixed``): the
#: thesis's, or "no effect" (release rates and phase 0, speed ratio 1), or the Hertz patch.
NOMINAL: dict[str, float] = {
    "mu_s": THESIS_MU_S,
    "theta0_deg": TABLE1["theta0_deg"],
    "theta_dot0": 0.0,
    "phi_dot0": 0.0,
    "psi_dot0": 0.0,
    "release_phase": 0.0,
    "speed_ratio": 1.0,
    "slip_speed": 0.1,
    "patch_radius": HERTZ_PATCH_RADIUS,
    "ageing_rate": 0.0,
    "ageing_time": 1e-4,
}
#: The parameters the candidates draw on: the fit registry's entries (start, bounds,
#: physical range, transform, reason: :data:`obturator.params.FIT_SPECS`).
PARAMETERS: dict[str, FitParameter] = {k: FIT_PARAMETERS[k] for k in NOMINAL}


def __getattr__(name: str) -> object:
    if name == "Parameter":  # the validation's own parameter class until the fit registry
        warnings.warn(
            "obturator.validation.Parameter is obturator.fitting.FitParameter",
            DeprecationWarning,
            stacklevel=2,
        )
        return FitParameter
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


@field_docs
@dataclass(frozen=True)
class Candidate:
    """A named mechanism (or pair): which parameters are fitted, the rest fixed."""

    #: Registry key (CLI ``--models``).
    name: str
    #: One line for tables and the report.
    description: str
    #: Fitted parameters (keys of :data:`PARAMETERS`), in order.
    params: tuple[str, ...]
    #: Parameter values held fixed (others: :data:`NOMINAL`).
    fixed: Mapping[str, float] = field(default_factory=dict)
    #: Kind of :class:`~obturator.model.torques.SlipSpeedLaw` used with ``speed_ratio`` and
    #: ``slip_speed``: "constant", "weakening" or "strengthening".
    speed_law: str = "constant"
    #: Friction law at the bottom contact: "thesis" or "coulomb".
    torque_model: str = "thesis"
    #: Mechanism labels (for pairs: both).
    mechanisms: tuple[str, ...] = ()
    #: Settings of the runs this candidate is evaluated at, where they differ from Table 1 (a data
    #: file's columns, :meth:`~obturator.calibration.data.SpinRigData.run_settings`; applied by
    #: :func:`~obturator.calibration.rig_model.apply_run_settings`: a fitted ``theta0_deg`` is then
    #: an offset from 87.25 deg on the run's own theta_0).
    conditions: tuple[tuple[str, float], ...] = ()

    def __post_init__(self) -> None:
        for k in (*self.params, *self.fixed):
            if k not in PARAMETERS:
                raise InputError("params", f"{k!r}; allowed: {', '.join(PARAMETERS)}")

    @property
    def n_params(self) -> int:
        """Number of fitted physical parameters (the noise SD is extra)."""
        return len(self.params)

    def values(self, fitted: Sequence[float] | Mapping[str, float]) -> dict[str, float]:
        """All parameter values: :data:`NOMINAL`, then `fixed`, then the fitted ones."""
        out = dict(NOMINAL)
        out.update(self.fixed)
        if isinstance(fitted, Mapping):
            out.update({k: float(v) for k, v in fitted.items()})
        else:
            if len(fitted) != len(self.params):
                raise InputError("values", f"expected {len(self.params)} values")
            out.update({k: float(v) for k, v in zip(self.params, fitted, strict=True)})
        return out

    def start(self) -> NDArray[np.float64]:
        """Default starting values of the fitted parameters."""
        return np.array([PARAMETERS[k].start for k in self.params])

    def build(
        self, spin_rate: float, fitted: Sequence[float] | Mapping[str, float], t_max: float
    ) -> Case:
        """The rig :class:`~obturator.model.case.Case` at `spin_rate` [rad/s] for these values.

        Parameters
        ----------
        spin_rate : float
            omega_p [rad/s].
        fitted : sequence or mapping
            Values of :attr:`params` (a mapping may also override others).
        t_max : float
            Integration horizon [s].
        """
        v = self.values(fitted)
        kw: dict[str, Any] = {
            "mu_s": v["mu_s"],
            "theta0_deg": v["theta0_deg"],
            "release_rate": (v["theta_dot0"], v["phi_dot0"], v["psi_dot0"]),
            "release_phase": v["release_phase"],
            "torque_model": self.torque_model,
            "t_max": t_max,
        }
        if self.speed_law != "constant":
            kw["speed_law"] = SlipSpeedLaw(self.speed_law, v["speed_ratio"], v["slip_speed"])
        if self.torque_model == "coulomb":
            kw["patch_radius"] = v["patch_radius"]
        if "ageing_rate" in self.params or "ageing_rate" in self.fixed:
            kw["ageing"] = ContactAgeing(v["ageing_rate"], v["ageing_time"])
        if self.conditions:
            return apply_run_settings(rig_case, float(spin_rate), dict(self.conditions), **kw)
        return rig_case(float(spin_rate), **kw)

    def plausibility(self, fitted: Mapping[str, float]) -> dict[str, bool]:
        """Whether each fitted value lies in its physically argued range."""
        return {k: PARAMETERS[k].is_plausible(float(fitted[k])) for k in self.params}

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready description."""
        return {
            "name": self.name,
            "description": self.description,
            "params": list(self.params),
            "fixed": dict(self.fixed),
            "speed_law": self.speed_law,
            "torque_model": self.torque_model,
        }


def _c(name: str, desc: str, params: Sequence[str], **kw: Any) -> Candidate:
    return Candidate(name, desc, tuple(params), **kw)


#: Every registered candidate, by name.
CANDIDATES: dict[str, Candidate] = {
    c.name: c
    for c in (
        _c(
            "thesis-1980",
            "the thesis's model as published: mu_s = 0.5473, theta_0 = 87.25 deg (no fit)",
            (),
            fixed={"mu_s": THESIS_MU_S},
            mechanisms=("thesis",),
        ),
        _c("mu", "exact thesis friction law, mu_s fitted", ("mu_s",), mechanisms=("thesis",)),
        _c(
            "theta0",
            "theta_0 fitted (alignment worse than +-1 deg)",
            ("mu_s", "theta0_deg"),
            mechanisms=("theta0",),
        ),
        _c(
            "release-rate",
            "release transient: nutation rate theta_dot_0 at release",
            ("mu_s", "theta_dot0"),
            mechanisms=("release-rate",),
        ),
        _c(
            "release-spin-rate",
            "release transient: spin rate phi_dot_0 about the hole axis",
            ("mu_s", "phi_dot0"),
            mechanisms=("release-rate",),
        ),
        _c(
            "release-precession-rate",
            "release transient: precession rate psi_dot_0 - omega_p",
            ("mu_s", "psi_dot0"),
            mechanisms=("release-rate",),
        ),
        _c(
            "release-phase",
            "release phase psi_0 relative to gravity",
            ("mu_s", "release_phase"),
            mechanisms=("release-phase",),
        ),
        _c(
            "stribeck",
            "velocity-weakening (Stribeck) friction mu_s -> r mu_s with slip speed",
            ("mu_s", "speed_ratio", "slip_speed"),
            speed_law="weakening",
            mechanisms=("speed-law",),
        ),
        _c(
            "strengthening",
            "velocity-strengthening friction r mu_s -> mu_s (polymer seat)",
            ("mu_s", "speed_ratio", "slip_speed"),
            speed_law="strengthening",
            mechanisms=("speed-law",),
        ),
        _c(
            "coulomb-patch",
            "exact Coulomb contact with pivot friction of a patch of radius a",
            ("mu_s", "patch_radius"),
            torque_model="coulomb",
            mechanisms=("coulomb-patch",),
        ),
        _c(
            "ageing",
            "contact ageing of the lucite seat: static friction mu_s + b ln(1 + t_d/tau), "
            "t_d = 2a/(R_s omega_p)",
            ("mu_s", "ageing_rate", "ageing_time"),
            mechanisms=("ageing",),
        ),
        _c(
            "theta0+ageing",
            "theta_0 fitted and contact ageing of the lucite seat",
            ("mu_s", "theta0_deg", "ageing_rate", "ageing_time"),
            mechanisms=("theta0", "ageing"),
        ),
        _c(
            "theta0+strengthening",
            "theta_0 fitted and velocity-strengthening friction",
            ("mu_s", "theta0_deg", "speed_ratio", "slip_speed"),
            speed_law="strengthening",
            mechanisms=("theta0", "speed-law"),
        ),
        _c(
            "release-rate+strengthening",
            "release nutation rate and velocity-strengthening friction",
            ("mu_s", "theta_dot0", "speed_ratio", "slip_speed"),
            speed_law="strengthening",
            mechanisms=("release-rate", "speed-law"),
        ),
        _c(
            "theta0+release-rate",
            "theta_0 and release nutation rate (both move the start towards opening)",
            ("mu_s", "theta0_deg", "theta_dot0"),
            mechanisms=("theta0", "release-rate"),
        ),
        _c(
            "theta0+coulomb-patch",
            "theta_0 fitted with the exact Coulomb contact and patch",
            ("mu_s", "theta0_deg", "patch_radius"),
            torque_model="coulomb",
            mechanisms=("theta0", "coulomb-patch"),
        ),
    )
}

#: The default study of ``obturator validate``.
DEFAULT_MODELS: tuple[str, ...] = (
    "thesis-1980",
    "mu",
    "theta0",
    "release-rate",
    "release-phase",
    "stribeck",
    "strengthening",
    "coulomb-patch",
    "ageing",
    "theta0+strengthening",
    "release-rate+strengthening",
    "theta0+release-rate",
)


def get_candidates(names: Sequence[str] | str | None = None) -> list[Candidate]:
    """Candidates by name (comma-separated string or sequence); default :data:`DEFAULT_MODELS`.

    Raises
    ------
    InputError
        ``models`` names an unknown candidate (the message lists the allowed ones).
    """
    if names is None:
        names = DEFAULT_MODELS
    if isinstance(names, str):
        names = [s.strip() for s in names.split(",") if s.strip()]
    if not names:
        raise InputError("models", "empty list; allowed: " + ", ".join(CANDIDATES))
    out = []
    for n in dict.fromkeys(names):
        if n not in CANDIDATES:
            raise InputError(
                "models", f"{n!r} is not a candidate; allowed: {', '.join(CANDIDATES)}"
            )
        out.append(CANDIDATES[n])
    return out
