"""One evaluation of t_cr for given inputs: the point function of every study.

:class:`FlightModel` bundles the obturator design, the projectile, the launch
conditions, the load model and the solver settings. Called with a mapping of
input values (names in :data:`INPUTS`, SI units) it builds the design and the
launch, computes t_cr with the constant load (the thesis's approach), the
trajectory-coupled load, or both, with the convergence status of each, and
never raises for a bad point (status ``invalid_input`` instead). Instances are
frozen and picklable, so process pools and Dask workers can run them.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field, replace
from typing import Any, Literal

import numpy as np

from ..errors import InputError, check_range, replace_fields
from ..model.case import Case
from ..params import PARAMS
from ..solve import SolverOptions, convergence_checks, opening_times
from ..status import Status
from .coupled import (
    DEFAULT_SEGMENT,
    STATUS_FAILED,
    STATUS_INVALID,
    STATUS_NOT_OPENED,
    STATUS_OPENED,
    STATUS_UNCONVERGED,
    FlightPoints,
    ObturatorDesign,
    cached_flight,
    constant_case,
    coupled_convergences,
    coupled_openings,
)
from .trajectory import Launch, Projectile

__all__ = ["INPUTS", "LOADS", "EVENTS", "TIMES", "FlightModel", "exceeds", "opening_rows"]


@dataclass(frozen=True)
class _Input:
    unit: str
    long_name: str
    target: Literal["design", "launch"]


#: Inputs a study may vary: name -> unit, description, and what it belongs to.
INPUTS: dict[str, _Input] = {
    "mu_s": _Input("1", "sliding friction coefficient mu_s", "design"),
    "theta0_deg": _Input("deg", "initial nutation angle theta_0", "design"),
    "gap": _Input("m", "ball-socket gap h", "design"),
    "hole_radius": _Input("m", "ball hole radius r_s", "design"),
    "ball_radius": _Input("m", "ball radius R_s", "design"),
    "density": _Input("kg/m^3", "ball density rho", "design"),
    "bore_radius": _Input("m", "projectile bore radius r_p", "design"),
    "viscosity": _Input("Pa s", "gap fluid viscosity mu_f", "design"),
    "spin_rate": _Input("rad/s", "muzzle spin omega_p0", "launch"),
    "spin_factor": _Input("1", "muzzle spin / nominal muzzle spin", "launch"),
    "mach": _Input("1", "muzzle Mach number M_0", "launch"),
    "altitude_m": _Input("m", "launch altitude (US 1976 atmosphere)", "launch"),
    "temperature_offset_k": _Input("K", "off-standard temperature Delta T", "launch"),
    "elevation_deg": _Input("deg", "elevation angle", "launch"),
}

#: Load models: the thesis's constant muzzle load, the trajectory-coupled one, or both.
LOADS = ("coupled", "constant", "both")
#: Which event ends the run: first light (t_cr) or the started tube (t_start).
EVENTS = ("first_light", "start", "start_late")
#: The time each event gives, as the command line names it -> :attr:`FlightModel.event`:
#: t_start to the frictionless lens's theta_start, t_start_late to the late bound's
#: (wall friction, lowest discharge coefficient; :mod:`obturator.model.start`).
TIMES = {"t_cr": "first_light", "t_start": "start", "t_start_late": "start_late"}
#: The bound of theta_start each start event runs to
#: (:meth:`~.design.ObturatorDesign.start_angle`).
_START_BOUNDS = {"start": "nominal", "start_late": "late"}


def warm_integrators() -> None:
    """Load the compiled integrators once (forked workers inherit them): the runner's
    warm-up of every envelope study."""
    from ..model.cases import flight_case
    from ..solve import opening_time

    try:
        opening_time(flight_case(t_max=1e-3))
    except RuntimeError:  # pragma: no cover - warm-up only
        pass


def exceeds(t_cr: float, status: int, requirement: float) -> bool:
    """True when the bore did not open by `requirement` [s].

    A point that did not open, went subsonic, failed or had invalid input
    counts as exceeding (conservative: it is not shown to open in time).
    """
    if status in (STATUS_OPENED, STATUS_UNCONVERGED):
        return not t_cr <= requirement
    return True


def _invalid(exc: Exception) -> dict[str, Any]:
    return {"t_cr": math.nan, "status": STATUS_INVALID, "change": math.nan, "error": str(exc)}


def opening_rows(
    cases: Sequence[Case | InputError | None],
    options: SolverOptions,
    check_convergence: bool,
    threshold: float = 1e-3,
) -> list[dict[str, Any]]:
    """``t_cr``, ``status`` and ``change`` of many constant-load cases (the rows of the
    envelope studies), through the front door with batched convergence checks.

    ``None`` in place of a case: a point that cannot reach its event (not opened, not
    integrated); an InputError: invalid input. ``change`` is the largest relative
    change of :func:`obturator.solve.convergence_checks` (tolerances, width, family);
    status ``UNCONVERGED`` where it reaches `threshold`.
    """
    run = [i for i, c in enumerate(cases) if c is not None]
    t_cr = np.full(len(cases), math.nan)
    status = np.full(len(cases), Status.T_MAX, dtype=np.int8)
    if run:
        t_cr[run], status[run], _ = opening_times([cases[i] for i in run], options)
    opened = np.flatnonzero(status == Status.OPENED)
    change = np.full(len(cases), math.nan)
    if check_convergence and opened.size:
        checks = convergence_checks(
            [cases[i] for i in opened], options, opening_times_s=t_cr[opened]
        )  # type: ignore[misc]
        for i, c in zip(opened, checks, strict=True):
            change[i] = c.largest_change
    out = []
    for i, case in enumerate(cases):
        if isinstance(case, InputError):
            out.append(_invalid(case))
            continue
        s = {Status.OPENED: STATUS_OPENED, Status.T_MAX: STATUS_NOT_OPENED}.get(
            Status(int(status[i])), STATUS_FAILED
        )
        if s == STATUS_OPENED and check_convergence and not change[i] < threshold:
            s = STATUS_UNCONVERGED
        t = float(t_cr[i]) if s in (STATUS_OPENED, STATUS_UNCONVERGED) else math.nan
        out.append({"t_cr": t, "status": s, "change": float(change[i])})
    return out


@dataclass(frozen=True)
class FlightModel:
    """t_cr of one obturator design at one flight condition.

    Parameters
    ----------
    design : ObturatorDesign
        Baseline design (Table 1 by default); inputs override its fields.
    launch : Launch
        Baseline muzzle conditions (Mach 3, sea level, twist-law spin).
    projectile : Projectile
        Mass, size, drag and roll damping (Table 1, closed-inlet drag).
    load : {"coupled", "constant", "both"}
        Which t_cr to compute; ``"both"`` reports both, ``t_cr`` being the
        coupled one.
    options : SolverOptions
        Obturator integrator settings.
    segment : float
        Segment length of the coupled integration [s].
    t_max : float
        Give-up time [s] (also the length of the computed flight).
    check_convergence : bool
        Rerun every opened point refined (tolerances and friction width / 10,
        and half the segment for the coupled load); status 4 (``UNCONVERGED``) when t_cr moves by
        more than `threshold` (relative).
    threshold : float
        Convergence threshold [-].
    tie_bore : bool
        The bore radius r_p follows the hole radius r_s (design studies).
    event : {"first_light", "start", "start_late"}
        The time reported as ``t_cr``: first light (theta = beta_s, the
        thesis's t_cr), the start of the internal flow (theta =
        theta_start(M), :mod:`obturator.model.start`; t_start) or its late bound
        (theta_start with wall friction and the lowest discharge coefficient; NaN,
        status not opened, where it never starts).
    with_start : bool
        With ``event="first_light"``, also report ``t_start`` and ``t_start_late``
        (and ``t_start_constant``, ``t_start_late_constant`` with ``load="both"``),
        ``status_start`` and ``status_start_late``, from further runs to theta_start
        without the convergence reruns.
    """

    design: ObturatorDesign = field(default_factory=ObturatorDesign)
    launch: Launch = field(default_factory=Launch)
    projectile: Projectile = field(default_factory=Projectile)
    load: str = "coupled"
    options: SolverOptions = field(default_factory=SolverOptions)
    segment: float = DEFAULT_SEGMENT
    t_max: float = 1.0
    check_convergence: bool = True
    threshold: float = 1e-3
    tie_bore: bool = False
    event: str = "first_light"
    with_start: bool = False

    def __post_init__(self) -> None:
        if self.event not in EVENTS:
            raise InputError("event", f"{self.event!r}; allowed: {', '.join(EVENTS)}")
        if self.load not in LOADS:
            raise InputError("load", f"{self.load!r}; allowed: {', '.join(LOADS)}")
        check_range("segment", self.segment, 0.0, 0.1, lo_open=True, unit="s")
        check_range("t_max", self.t_max, 0.0, 100.0, lo_open=True, unit="s")
        check_range("threshold", self.threshold, 0.0, 1.0, lo_open=True)

    def identity(self) -> dict[str, Any]:
        """JSON-ready description of everything that determines the results."""
        proj = asdict(self.projectile)
        proj["drag"] = repr(self.projectile.drag)
        return {
            "design": self.design.to_dict(),
            "launch": asdict(self.launch),
            "projectile": proj,
            "load": self.load,
            "options": asdict(self.options),
            "segment": self.segment,
            "t_max": self.t_max,
            "check_convergence": self.check_convergence,
            "threshold": self.threshold,
            "tie_bore": self.tie_bore,
            "event": self.event,
            "with_start": self.with_start,
        }

    def build(self, values: Mapping[str, float]) -> tuple[ObturatorDesign, Launch]:
        """Design and launch with `values` applied (raises InputError when invalid)."""
        d: dict[str, float] = {}
        lv: dict[str, float] = {}
        for name, x in values.items():
            if name not in INPUTS:
                raise InputError("input", f"unknown input {name!r}; allowed: {', '.join(INPUTS)}")
            (d if INPUTS[name].target == "design" else lv)[name] = float(x)
        if self.tie_bore and "hole_radius" in d and "bore_radius" not in d:
            d["bore_radius"] = d["hole_radius"]
        design = self.design.with_(**d) if d else self.design
        factor = lv.pop("spin_factor", None)
        launch = replace(self.launch, **lv) if lv else self.launch
        if factor is not None:
            rng = PARAMS["spin_factor"].range
            check_range("spin_factor", factor, rng.lo, rng.hi, lo_open=rng.lo_open)
            launch = replace(launch, spin_rate=launch.muzzle_spin * factor)
        return design, launch

    def _constant(self, points: list[tuple[ObturatorDesign, Launch]]) -> list[dict[str, Any]]:
        """Constant muzzle load (thesis): every point's case through the front door."""
        cases: list[Case | InputError | None] = []
        for design, launch in points:
            try:
                case: Case | None = constant_case(design, launch, self.t_max)
                if self.event in _START_BOUNDS:  # on to theta_start(M_0), closed-bore load
                    bound = _START_BOUNDS[self.event]
                    theta = design.start_angle(launch.altitude_m, bound)(launch.mach)
                    # None: the tube cannot start at the muzzle Mach, never reaches theta_start
                    case = case.with_(theta_cr=theta) if math.isfinite(theta) else None
                cases.append(case)
            except InputError as exc:
                cases.append(exc)
        return opening_rows(cases, self.options, self.check_convergence, self.threshold)

    def _coupled(self, points: list[tuple[ObturatorDesign, Launch]]) -> list[dict[str, Any]]:
        """Trajectory-coupled load: all points segment by segment in lanes."""
        flights = [
            cached_flight(self.projectile, replace(launch, spin_rate=None), self.t_max)
            for _, launch in points
        ]
        pts = FlightPoints(
            [d for d, _ in points],
            flights,
            [launch.muzzle_spin for _, launch in points],
            [
                d.start_angle(lc.altitude_m, _START_BOUNDS[self.event])
                if self.event in _START_BOUNDS
                else None
                for d, lc in points
            ],
        )
        res = coupled_openings(pts, self.options, segment=self.segment, t_max=self.t_max)
        out: list[dict[str, Any]] = []
        for r in res:
            if isinstance(r, InputError):
                out.append(_invalid(r))
                continue
            out.append({
                "t_cr": r.t_cr, "status": r.status, "change": math.nan,
                "mach_end": r.mach_end, "force_end": r.force_end, "spin_end": r.spin_end,
            })  # fmt: skip
        check = [i for i, r in enumerate(res) if not isinstance(r, InputError) and r.opened]
        if not (self.check_convergence and check):
            return out
        convs = coupled_convergences(
            pts.take(check), self.options, segment=self.segment, t_max=self.t_max,
            threshold=self.threshold, t_cr=[out[i]["t_cr"] for i in check],
        )  # fmt: skip
        for i, conv in zip(check, convs, strict=True):
            if isinstance(conv, InputError):
                out[i] = _invalid(conv)
                continue
            out[i]["change"] = conv.max_change
            if not conv.converged:
                out[i]["status"] = STATUS_UNCONVERGED
        return out

    def evaluate_many(self, values: Sequence[Mapping[str, float]]) -> list[dict[str, Any]]:
        """Evaluate many points together (the lanes); each result as :meth:`__call__`'s.

        A point's result does not depend on the other points beyond the rounding of
        the Radau IIA lanes (see :func:`obturator.solve.opening_times`).
        """
        results: list[dict[str, Any]] = [{} for _ in values]
        points: list[tuple[ObturatorDesign, Launch]] = []
        where: list[int] = []
        for i, v in enumerate(values):
            try:
                points.append(self.build(v))
                where.append(i)
            except InputError as exc:
                results[i] = _invalid(exc)
        if points:
            if self.load == "constant":
                main = self._constant(points)
            else:
                main = self._coupled(points)
                if self.load == "both":
                    for row, const in zip(main, self._constant(points), strict=True):
                        if row["status"] != STATUS_INVALID:
                            row.update({f"{k}_constant": v for k, v in const.items()})
            for i, row in zip(where, main, strict=True):
                results[i] = row
        if self.with_start and self.event == "first_light" and where:
            for event, name in (("start", "t_start"), ("start_late", "t_start_late")):
                onward = self.with_(event=event, with_start=False, check_convergence=False)
                started = onward.evaluate_many([values[i] for i in where])
                for i, st in zip(where, started, strict=True):
                    if results[i]["status"] == STATUS_INVALID:
                        continue
                    results[i][name] = st["t_cr"]
                    results[i]["status" + name.removeprefix("t")] = st["status"]
                    results[i]["mach_at" + name.removeprefix("t")] = st.get("mach_end", math.nan)
                    if "t_cr_constant" in st:
                        results[i][f"{name}_constant"] = st["t_cr_constant"]
        return results

    def __call__(self, values: Mapping[str, float]) -> dict[str, Any]:
        """Evaluate one point (:meth:`evaluate_many` of one).

        Returns
        -------
        dict
            ``t_cr`` [s] (NaN if not opened), ``status`` (1 opened, 2 opened
            but not converged, 0 not opened by t_max, 3 subsonic before
            opening, -1 solver failure, -2 invalid input), ``change`` (largest
            relative change under refinement: tolerances, friction width, the other
            regularisation family and, coupled, half the segment), and for the coupled
            load ``mach_end``, ``force_end`` [N], ``spin_end`` [rad/s] at t_cr.
            With ``load="both"`` the constant-load results are added with the
            suffix ``_constant``. With ``with_start``: ``t_start`` [s] and
            ``status_start``, ``mach_at_start`` (and ``t_start_constant``), the times to
            theta_start(M), and the same with ``_late`` (``t_start_late``,
            ``status_start_late``, ``mach_at_start_late``, ``t_start_late_constant``) to
            its late bound. With ``event="start"`` (``"start_late"``) the time reported
            as ``t_cr`` is t_start (its late bound).
        """
        return self.evaluate_many([values])[0]

    def with_(self, **changes: Any) -> FlightModel:
        """A copy with fields replaced."""
        return replace_fields(self, "model", changes)
