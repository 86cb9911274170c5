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
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field, fields, replace
from typing import Any, Literal

from ..errors import InputError, check_range
from ..solve import SolverOptions
from .coupled import (
    DEFAULT_SEGMENT,
    STATUS_FAILED,
    STATUS_INVALID,
    STATUS_NOT_OPENED,
    STATUS_OPENED,
    STATUS_UNCONVERGED,
    ObturatorDesign,
    cached_flight,
    constant_opening,
    coupled_convergence,
    coupled_opening,
)
from .trajectory import Launch, Projectile

__all__ = ["INPUTS", "LOADS", "EVENTS", "TIMES", "FlightModel", "exceeds"]


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
EVENTS = ("first_light", "start")
#: The time each event gives, as the command line names it -> :attr:`FlightModel.event`.
TIMES = {"t_cr": "first_light", "t_start": "start"}


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
        and half the segment for the coupled load); status 2 when t_cr moves by
        more than `threshold` (relative).
    threshold : float
        Convergence threshold [-].
    tie_bore : bool
        The bore radius r_p follows the hole radius r_s (design studies).
    event : {"first_light", "start"}
        The time reported as ``t_cr``: first light (theta = beta_s, the
        thesis's t_cr) or the start of the internal flow (theta =
        theta_start(M), :mod:`obturator.model.start`; t_start).
    with_start : bool
        With ``event="first_light"``, also report ``t_start`` (and
        ``t_start_constant`` with ``load="both"``) and ``status_start``, from a
        second run to theta_start without the convergence reruns.
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
            check_range("spin_factor", factor, 0.0, 10.0, lo_open=True)
            launch = replace(launch, spin_rate=launch.muzzle_spin * factor)
        return design, launch

    def _constant(self, design: ObturatorDesign, launch: Launch) -> dict[str, Any]:
        try:
            t, conv = constant_opening(
                design,
                launch,
                self.options,
                t_max=self.t_max,
                check=self.check_convergence,
                start=self.event == "start",
            )
        except RuntimeError:
            return {"t_cr": math.nan, "status": STATUS_FAILED, "change": math.nan}
        change = math.nan
        if not math.isfinite(t):
            return {"t_cr": math.nan, "status": STATUS_NOT_OPENED, "change": change}
        status = STATUS_OPENED
        if conv is not None:
            rel = [conv["tolerance_rel_change"], conv["width_rel_change"]]
            change = max(math.inf if r is None else r for r in rel)
            if not change < self.threshold:
                status = STATUS_UNCONVERGED
        return {"t_cr": t, "status": status, "change": change}

    def _coupled(self, design: ObturatorDesign, launch: Launch) -> dict[str, Any]:
        flight = cached_flight(self.projectile, replace(launch, spin_rate=None), self.t_max)
        kw = {"segment": self.segment, "t_max": self.t_max, "spin_rate": launch.muzzle_spin}
        if self.event == "start":
            kw["stop_angle"] = design.start_angle(launch.altitude_m)
        res = coupled_opening(design, flight, self.options, **kw)  # type: ignore[arg-type]
        out = {
            "t_cr": res.t_cr,
            "status": res.status,
            "change": math.nan,
            "mach_end": res.mach_end,
            "force_end": res.force_end,
            "spin_end": res.spin_end,
        }
        if res.status == STATUS_OPENED and self.check_convergence:
            conv = coupled_convergence(
                design, flight, self.options, threshold=self.threshold, t_cr=res.t_cr, **kw
            )  # type: ignore[arg-type]
            out["change"] = conv.max_change
            if not conv.converged:
                out["status"] = STATUS_UNCONVERGED
        return out

    def __call__(self, values: Mapping[str, float]) -> dict[str, Any]:
        """Evaluate one point.

        Returns
        -------
        dict
            ``t_cr`` [s] (NaN if not opened), ``status`` (1 opened, 2 opened
            but not converged, 0 not opened by t_max, 3 subsonic before
            opening, -1 solver failure, -2 invalid input), ``change`` (largest
            relative change under refinement), and for the coupled load
            ``mach_end``, ``force_end`` [N], ``spin_end`` [rad/s] at t_cr.
            With ``load="both"`` the constant-load results are added with the
            suffix ``_constant``. With ``with_start``: ``t_start`` [s] and
            ``status_start``, ``mach_at_start`` (and ``t_start_constant``), the times to
            theta_start(M). With ``event="start"`` the time reported as
            ``t_cr`` is t_start.
        """
        try:
            design, launch = self.build(values)
        except InputError as exc:
            return _invalid(exc)
        if self.load == "constant":
            out = self._constant(design, launch)
        else:
            try:
                out = self._coupled(design, launch)
            except InputError as exc:
                return _invalid(exc)
        if self.load == "both":
            for k, v in self._constant(design, launch).items():
                out[f"{k}_constant"] = v
        if self.with_start and self.event == "first_light":
            onward = self.with_(event="start", with_start=False, check_convergence=False)
            started = onward(values)
            out["t_start"] = started["t_cr"]
            out["status_start"] = started["status"]
            out["mach_at_start"] = started.get("mach_end", math.nan)
            if "t_cr_constant" in started:
                out["t_start_constant"] = started["t_cr_constant"]
        return out

    def with_(self, **changes: Any) -> FlightModel:
        """A copy with fields replaced."""
        names = {f.name for f in fields(self)}
        for k in changes:
            if k not in names:
                raise InputError("model", f"unknown field {k!r}")
        return replace(self, **changes)
