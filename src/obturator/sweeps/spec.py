"""A parameter study: :class:`SweepSpec` (case, swept axes, fixed values, models, solver).

A spec is immutable and validated eagerly: every corner of the grid is built
into a case before any integration. :meth:`SweepSpec.identity` (and its
SHA-256, :meth:`SweepSpec.digest`) is everything that determines the results;
the resume store refuses partial results of a different study by it.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from .._provenance import package_version
from ..errors import InputError, check_range
from ..model.case import Case
from ..model.cases import case_from_settings
from ..params import SWEEP_PARAMS
from ..reference import TABLE1
from ..runs.digest import study_digest
from ..solve import SolverOptions
from ..vocab import CASE_NAMES, SPEED_LAWS, SPIN_MODES, TORQUE_MODELS, check_choice
from .grid import MAX_POINTS, as_axis

__all__ = ["SweepSpec"]

#: Case settings a study holds fixed outside its parameters (its base case).
_BASE_FIELDS = (
    "ball_radius",
    "viscosity",
    "weight",
    "patch_radius",
    "p1",
    "n_contacts",
    "bore_radius",
)


def _json_float(x: float) -> float | str:
    return x if math.isfinite(x) else repr(x)


@dataclass(frozen=True, eq=False)
class SweepSpec:
    """A parameter study: case, swept axes, fixed values, models, solver settings.

    Parameters
    ----------
    case : {"spin-rig", "flight"}
        Thesis Table 1 column; the grid points are built with
        :func:`obturator.model.cases.rig_case` or :func:`obturator.model.cases.flight_case`.
    axes : mapping of str to array_like
        Swept parameters, in dimension order: name -> 1-D values (distinct,
        finite). Allowed names and units (:data:`SWEEP_PARAMS`): ``spin_rate``
        [rad/s], ``mu_s`` [-], ``theta0_deg`` [deg], ``density`` [kg/m^3],
        ``hole_radius`` [m], ``gap`` [m], and for the flight case only
        ``mach`` [-] and ``altitude_m`` [m].
    fixed : mapping of str to float
        Values held fixed (same names and units). Anything neither swept nor
        fixed takes the case factory's Table 1 default (spin_rate 200 rad/s on
        the rig and 12042 rad/s in flight, mu_s 0.35, theta_0 87.25 deg,
        rho 7669.6 kg/m^3, r_s 4.72 mm, h 50.8 um, M_1 = 3, P_1 = 0.099 MPa).
    torque_model : {"thesis", "coulomb"}
    spin_mode : {"constant", "free", "thesis-energy"}
    options : SolverOptions
        Default: the defaults with ``shared_maps=True`` (a sweep's cases that differ in
        spin alone reuse their spin band's return map; :mod:`obturator.solve.plan`).
    t_max : float or None
        Give-up time [s]; None keeps the factory default (100 s rig, 0.5 s flight).
    check_convergence : bool
        Re-run every opened point with the tolerances divided by 10, with the
        friction width divided by 10 and with another regularisation family
        (four times the cost) and mark points whose t_cr moves by more than
        1e-3 with status ``Status.UNCONVERGED`` (typical at low spin, where
        long near-stick phases need a small width).
    speed_law : {"constant", "weakening", "strengthening"}
        Slip-speed law of the rig friction (:class:`~obturator.model.torques.SlipSpeedLaw`);
        its ``speed_ratio`` and ``slip_speed``, the release transient ``theta_dot0``
        and the release phase ``release_phase`` are sweep parameters (spin rig only;
        the mechanisms of :mod:`obturator.validation`).
    base : mapping of str to object
        The base case's other settings, as a config file gives them to ``simulate``
        (:func:`obturator.model.cases.case_from_settings`): ``ball_radius`` [m],
        ``viscosity`` [Pa s], ``weight`` [N] (rig), ``patch_radius`` [m] (Coulomb),
        ``p1`` [Pa], ``n_contacts``, ``bore_radius`` [m] (flight). Not swept; empty by
        default (then the identity is that of a study without it).

    Notes
    -----
    The ball is :func:`obturator.model.cases.table1_ball` with the given density and
    hole radius. On the rig the normal load is Table 1's *measured*
    W = 0.07987 N unless ``density`` or ``hole_radius`` is swept or fixed; then
    the weight follows the ball (``weight=None``, W = rho g V), as in the
    thesis's geometry studies (Figs. 16-17). In flight a different hole radius
    changes the ball only; the bore radius r_p that sets the pressure force
    and the contact angle stays Table 1's 4.72 mm. With ``altitude_m`` the
    free-stream pressure comes from the 1976 standard atmosphere instead of
    P_1 = 0.099 MPa.

    Validation is eager: names, models, and every corner of the grid (each
    axis at its smallest and largest value) are built into cases, which
    catches out-of-range values before any integration.
    """

    case: str = "spin-rig"
    axes: Mapping[str, Any] = field(default_factory=dict)
    fixed: Mapping[str, float] = field(default_factory=dict)
    torque_model: str = "thesis"
    spin_mode: str = "constant"
    options: SolverOptions = field(default_factory=lambda: SolverOptions(shared_maps=True))
    t_max: float | None = None
    check_convergence: bool = False
    speed_law: str = "constant"
    base: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        check_choice("case", self.case, CASE_NAMES)
        check_choice("speed_law", self.speed_law, SPEED_LAWS)
        if self.speed_law != "constant" and self.case != "spin-rig":
            raise InputError("speed_law", "applies to --case spin-rig only")
        check_choice("torque_model", self.torque_model, TORQUE_MODELS)
        check_choice("spin_mode", self.spin_mode, SPIN_MODES)
        if not isinstance(self.options, SolverOptions):
            raise InputError("options", "expected a SolverOptions")
        axes: dict[str, np.ndarray] = {}
        for name, values in dict(self.axes).items():
            self._check_name(name)
            axes[name] = as_axis(name, values)
        fixed: dict[str, float] = {}
        for name, value in dict(self.fixed).items():
            self._check_name(name)
            if name in axes:
                raise InputError(name, "is both swept and fixed")
            fixed[name] = check_range(name, value)
        base = dict(self.base)
        for name in base:
            if name in SWEEP_PARAMS or name not in _BASE_FIELDS:
                raise InputError(
                    name, f"is not a base-case setting; allowed: {', '.join(_BASE_FIELDS)}"
                )
        object.__setattr__(self, "base", base)
        object.__setattr__(self, "axes", axes)
        object.__setattr__(self, "fixed", fixed)
        if self.t_max is not None:
            object.__setattr__(
                self, "t_max", check_range("t_max", self.t_max, 0.0, lo_open=True, unit="s")
            )
        if self.n_points > MAX_POINTS:
            raise InputError("axes", f"{self.n_points} grid points exceed the limit {MAX_POINTS}")
        self._check_corners()

    def _check_name(self, name: str) -> None:
        if name not in SWEEP_PARAMS:
            raise InputError(
                "parameter", f"unknown parameter {name!r}; allowed: {', '.join(SWEEP_PARAMS)}"
            )
        if SWEEP_PARAMS[name].flight_only and self.case != "flight":
            raise InputError(name, "applies to the flight case only")

    def _check_corners(self) -> None:
        names = list(self.axes)
        if not names:
            self.build_case({})
            return
        ends = [sorted({float(a.min()), float(a.max())}) for a in self.axes.values()]
        for corner in itertools.product(*ends):
            self.build_case(dict(zip(names, corner, strict=True)))

    # -- shape of the grid
    @property
    def dims(self) -> tuple[str, ...]:
        """Swept parameter names, in dimension order."""
        return tuple(self.axes)

    @property
    def shape(self) -> tuple[int, ...]:
        """Grid shape (one entry per swept parameter)."""
        return tuple(len(a) for a in self.axes.values())

    @property
    def n_points(self) -> int:
        """Number of grid points (1 when nothing is swept)."""
        return int(math.prod(self.shape))

    def rows(self, indices: np.ndarray) -> np.ndarray:
        """Swept values at flat (C-order) grid indices, shape (len(indices), len(dims))."""
        idx = np.asarray(indices, dtype=np.int64)
        if not self.axes:
            return np.empty((idx.size, 0))
        multi = np.unravel_index(idx, self.shape)
        return np.column_stack([a[m] for a, m in zip(self.axes.values(), multi, strict=True)])

    # -- building cases
    @property
    def weight_from_ball(self) -> bool:
        """True when the rig load is the ball's computed weight (geometry varied)."""
        if "weight" in self.base:
            return False
        varied = set(self.axes) | set(self.fixed) | set(self.base)
        return self.case == "spin-rig" and bool(varied & {"density", "hole_radius", "ball_radius"})

    @property
    def weight_model(self) -> str:
        """How the normal load is set (text stored in the results)."""
        if self.case == "flight":
            return "flight: pressure force behind the normal bow shock (Eqs. 1, 3, 43)"
        if self.weight_from_ball:
            return "spin-rig: weight W = rho g V computed from the (modified) ball"
        if "weight" in self.base:
            return f"spin-rig: weight W = {self.base['weight']:g} N (given)"
        return f"spin-rig: Table 1 measured weight W = {TABLE1['rig_weight']} N"

    def resolved(self) -> dict[str, float | None]:
        """Every parameter's value when not swept: fixed, else the factory default."""
        defaults: dict[str, float | None] = {
            "spin_rate": TABLE1["rig_spin_rate" if self.case == "spin-rig" else "flight_spin_rate"],
            "mu_s": TABLE1["mu_s"],
            "theta0_deg": TABLE1["theta0_deg"],
            "density": TABLE1["density"],
            "hole_radius": TABLE1["hole_radius"],
            "gap": TABLE1["gap"],
        }
        if self.case == "flight":
            defaults["mach"] = TABLE1["mach"]
            defaults["altitude_m"] = None
        defaults.update(self.fixed)
        return defaults

    def build_case(self, values: Mapping[str, float]) -> Case:
        """The :class:`~obturator.model.case.Case` at one grid point.

        Parameters
        ----------
        values : mapping of str to float
            Values of (some of) the swept parameters; everything else is taken
            from ``fixed`` or the factory defaults. Units as in :data:`SWEEP_PARAMS`.
            Built by :func:`obturator.model.cases.case_from_settings`, as
            ``simulate`` builds its case.
        """
        settings: dict[str, Any] = {
            "case": self.case,
            "torque_model": self.torque_model,
            "spin_mode": self.spin_mode,
            **self.base,
            **self.fixed,
            **{k: float(x) for k, x in values.items()},
        }
        if self.t_max is not None:
            settings["t_max"] = self.t_max
        if self.speed_law != "constant":
            settings["speed_law"] = self.speed_law
        return case_from_settings(settings)

    # -- identity
    def identity(self) -> dict[str, Any]:
        """JSON-ready description of everything that determines the results."""
        opts = {
            k: (_json_float(x) if isinstance(x, float) else x)
            for k, x in asdict(self.options).items()
        } | self.options.digest_extra()
        return {
            "case": self.case,
            "axes": {k: [_json_float(x) for x in a.tolist()] for k, a in self.axes.items()},
            "fixed": {k: _json_float(x) for k, x in sorted(self.fixed.items())},
            "torque_model": self.torque_model,
            "spin_mode": self.spin_mode,
            "options": opts,
            "t_max": self.t_max,
            "check_convergence": self.check_convergence,
            "speed_law": self.speed_law,
            "obturator_version": package_version(),
        } | ({"base": dict(sorted(self.base.items()))} if self.base else {})

    def digest(self) -> str:
        """SHA-256 (hex) of :meth:`identity`; equal specs give equal digests."""
        return study_digest(self.identity())

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, SweepSpec):
            return NotImplemented
        return self.identity() == other.identity()

    def __hash__(self) -> int:
        return hash(self.digest())
