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
``patch_radius_mm``      ``patch_radius`` [m] with ``torque_model="coulomb"``
=======================  ======================================================

Physical ranges
---------------
Every :class:`Parameter` carries hard fit ``bounds`` (wide: where the model is
still defined and cheap) and a narrower ``plausible`` range argued from the
rig (thesis chapter III) in its ``justification``. A fitted value outside its
plausible range is reported as such; it is the data asking for more than the
mechanism can physically give.

Spin-rate fluctuation is not a candidate here: it is part of every
candidate's likelihood as an error-in-variables term (see
:mod:`obturator.validation.likelihood`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..model.case import Case
from ..model.cases import TABLE1, rig_case
from ..model.torques import SlipSpeedLaw, hertz_patch_radius

__all__ = [
    "CANDIDATES",
    "DEFAULT_MODELS",
    "HERTZ_PATCH_RADIUS_MM",
    "PARAMETERS",
    "THESIS_MU_S",
    "Candidate",
    "Parameter",
    "get_candidates",
]

#: The thesis's friction coefficient from the starred runs (chapter IV, Eq. 95ff).
THESIS_MU_S = 0.5473
#: Hertz radius of the steel ball in the lucite seat under W (Table 1 rig) [mm].
HERTZ_PATCH_RADIUS_MM = 1e3 * hertz_patch_radius(
    TABLE1["rig_weight"], TABLE1["ball_radius"], TABLE1["gap"], seat_material="lucite"
)


@dataclass(frozen=True)
class Parameter:
    """One fittable model parameter.

    Attributes
    ----------
    name : str
        Key (also the JSON name).
    unit : str
        Unit of the value ("1" for dimensionless).
    nominal : float
        Value when the parameter is not fitted (the thesis's, or "no effect").
    start : float
        Default starting value of a fit.
    bounds : (float, float)
        Hard bounds of the fit.
    plausible : (float, float)
        Physically argued range (see `justification`).
    log : bool
        Fit in log10 (for scale parameters spanning decades).
    scale : float
        Typical size: the optimiser works on value / scale (O(1)).
    justification : str
        Why the plausible range is what it is (one paragraph, with sources).
    """

    name: str
    unit: str
    nominal: float
    start: float
    bounds: tuple[float, float]
    plausible: tuple[float, float]
    log: bool = False
    scale: float = 1.0
    justification: str = ""

    def to_internal(self, value: float) -> float:
        """Value -> optimiser variable (log10 or value/scale)."""
        return math.log10(value) if self.log else value / self.scale

    def from_internal(self, x: float) -> float:
        """Optimiser variable -> value."""
        return 10.0**x if self.log else x * self.scale

    def internal_bounds(self) -> tuple[float, float]:
        """Bounds in optimiser variables."""
        lo, hi = self.bounds
        return (self.to_internal(lo), self.to_internal(hi))

    def is_plausible(self, value: float) -> bool:
        """Whether `value` lies in the plausible range (inclusive)."""
        lo, hi = self.plausible
        return lo <= value <= hi


_RATE_BOUND = 20.0  # rad/s, fit bounds of the release rates

#: The parameters the candidates draw on (fit bounds, physical ranges, sources).
PARAMETERS: dict[str, Parameter] = {
    p.name: p
    for p in (
        Parameter(
            "mu_s",
            "1",
            THESIS_MU_S,
            0.55,
            (0.1, 1.5),
            (0.2, 1.0),
            justification=(
                "Dry sliding of a steel ball on the rig's lucite (PMMA) seat. The thesis "
                "started from 0.35 for laminated plastic on steel (chapter V, ref. [27]) "
                "and fitted 0.5473 (chapter IV); handbook values for PMMA or laminated "
                "plastics on steel span about 0.2-0.8 (static values at the top). "
                "Plausible: 0.2-1.0."
            ),
        ),
        Parameter(
            "theta0_deg",
            "deg",
            TABLE1["theta0_deg"],
            TABLE1["theta0_deg"],
            (80.0, 89.9),
            (86.25, 88.25),
            scale=10.0,
            justification=(
                "Initial nutation set by centring the laser reflection from a polished "
                "spot on the ball (chapter III.B, Figs. 29-31); the thesis states "
                "theta_0 = 87.25 deg 'could only vary by +-1 deg' (chapter IV, p. 97). "
                "Plausible: the stated 86.25-88.25 deg. The reflection measures the "
                "spot's normal, not the hole axis, so a larger offset is conceivable but "
                "undocumented; the fit is allowed 80-89.9 deg to show what the data want."
            ),
        ),
        Parameter(
            "theta_dot0",
            "rad/s",
            0.0,
            -1.0,
            (-_RATE_BOUND, _RATE_BOUND),
            (-1.5, 1.5),
            justification=(
                "Nutation rate at release (negative: towards opening). The holding jet "
                "(chapter III.B, Figs. 26-27) is cut by the retracting plunger; the "
                "plunger never touches the ball. Upper bound: a jet force of about "
                "0.04 N (air at ~100 m/s through a ~2 mm nozzle) acting fully "
                "tangentially at R_s for a 10 ms decay gives "
                "0.04 x 7.9e-3 x 0.01 / A = 14 rad/s (A = 2.2e-7 kg m^2). A jet on a "
                "sphere pushes along the normal, through the centre: only surface shear "
                "and the hole edge give a moment, of order 10 % of that. Plausible: "
                "|theta_dot_0| <= 1.5 rad/s."
            ),
        ),
        Parameter(
            "phi_dot0",
            "rad/s",
            0.0,
            1.0,
            (-_RATE_BOUND, _RATE_BOUND),
            (-1.5, 1.5),
            justification="Spin about the hole axis at release; as theta_dot0.",
        ),
        Parameter(
            "psi_dot0",
            "rad/s",
            0.0,
            1.0,
            (-_RATE_BOUND, _RATE_BOUND),
            (-1.5, 1.5),
            justification=(
                "Precession rate relative to the rig at release, psi_dot_0 - omega_p; "
                "as theta_dot0."
            ),
        ),
        Parameter(
            "release_phase",
            "rad",
            0.0,
            1.0,
            (0.0, math.pi),
            (0.0, math.pi),
            justification=(
                "psi_0, azimuth of the line of nodes relative to gravity (-X) at release. "
                "The switch is thrown at an arbitrary instant (chapter III.B), so psi_0 "
                "is really uniform per run; a single fitted psi_0 tests whether the data "
                "prefer a phase at all. The rig friction depends on (w_X)^2, so psi_0 "
                "and psi_0 + pi are alike: 0-pi covers all phases."
            ),
        ),
        Parameter(
            "speed_ratio",
            "1",
            1.0,
            0.5,
            (0.02, 1.0),
            (0.2, 1.0),
            justification=(
                "r of SlipSpeedLaw: friction at one end of the slip-speed range over "
                "mu_s at the other (weakening: kinetic/static; strengthening: "
                "at-rest/fast). Polymer-on-steel friction changes by up to a factor of "
                "a few over several decades of sliding speed (viscoelastic and "
                "ploughing contributions; Stribeck curves of boundary lubrication "
                "likewise). Plausible: 0.2-1."
            ),
        ),
        Parameter(
            "slip_speed",
            "m/s",
            0.1,
            0.1,
            (1e-3, 5.0),
            (0.01, 1.0),
            log=True,
            justification=(
                "v_s of SlipSpeedLaw, the slip speed of the transition. The rig's slip "
                "speeds R_s |omega_r| run from 0 at stick to about R_s omega_p = "
                "0.6-3.5 m/s (78-446 rad/s); a transition that the data can see lies "
                "inside 0.01-1 m/s. Fitted in log10."
            ),
        ),
        Parameter(
            "patch_radius_mm",
            "mm",
            HERTZ_PATCH_RADIUS_MM,
            HERTZ_PATCH_RADIUS_MM,
            (0.05, 2.0),
            (0.15, 0.6),
            scale=0.1,
            justification=(
                "Radius of the contact patch of the Coulomb model (pivot friction "
                "3 pi a / 16 mu N). Hertz: 0.279 mm for the steel ball in the lucite "
                "seat under W with the Table 1 gap; a ~ (R*/E*)^(1/3) moves by "
                "+-15 % for E(PMMA) 2.4-3.3 GPa and by +-25 % for a gap 50 % off; "
                "roughness and seat out-of-roundness spread it further. Plausible: "
                "0.15-0.6 mm."
            ),
        ),
    )
}


@dataclass(frozen=True)
class Candidate:
    """A named mechanism (or pair): which parameters are fitted, the rest fixed.

    Attributes
    ----------
    name : str
        Registry key (CLI ``--models``).
    description : str
        One line for tables and the report.
    params : tuple of str
        Fitted parameters (keys of :data:`PARAMETERS`), in order.
    fixed : dict of str to float
        Parameter values held fixed (others: their ``nominal``).
    speed_law : {"constant", "weakening", "strengthening"}
        Kind of :class:`~obturator.model.torques.SlipSpeedLaw` used with
        ``speed_ratio`` and ``slip_speed``.
    torque_model : {"thesis", "coulomb"}
        Friction law at the bottom contact.
    mechanisms : tuple of str
        Mechanism labels (for pairs: both).
    """

    name: str
    description: str
    params: tuple[str, ...]
    fixed: Mapping[str, float] = field(default_factory=dict)
    speed_law: str = "constant"
    torque_model: str = "thesis"
    mechanisms: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        for k in (*self.params, *self.fixed):
            if k not in PARAMETERS:
                raise InputError("params", f"{k!r}; allowed: {', '.join(PARAMETERS)}")

    @property
    def n_params(self) -> int:
        """Number of fitted physical parameters (the noise SD is extra)."""
        return len(self.params)

    def values(self, fitted: Sequence[float] | Mapping[str, float]) -> dict[str, float]:
        """All parameter values: nominal, then `fixed`, then the fitted ones."""
        out = {k: p.nominal for k, p in PARAMETERS.items()}
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
            "theta0_deg": v["theta0_deg"],
            "release_rate": (v["theta_dot0"], v["phi_dot0"], v["psi_dot0"]),
            "release_phase": v["release_phase"],
            "torque_model": self.torque_model,
            "t_max": t_max,
        }
        if self.speed_law != "constant":
            kw["speed_law"] = SlipSpeedLaw(self.speed_law, v["speed_ratio"], v["slip_speed"])
        if self.torque_model == "coulomb":
            kw["patch_radius"] = 1e-3 * v["patch_radius_mm"]
        return rig_case(float(spin_rate), v["mu_s"], **kw)

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
            ("mu_s", "patch_radius_mm"),
            torque_model="coulomb",
            mechanisms=("coulomb-patch",),
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
            ("mu_s", "theta0_deg", "patch_radius_mm"),
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
