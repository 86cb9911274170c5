"""Opening-time maps over the firing envelope: muzzle Mach x launch altitude (x temperature).

Every grid point is one :class:`~obturator.envelope.model.FlightModel` call
with ``load="both"``: the thesis's constant muzzle load and the
trajectory-coupled load, each with its convergence status. The map also marks
where the internal flow model changes once the bore is open:

* **not started** (Kantrowitz-Donaldson, thesis Eq. 2): below the self-starting
  Mach number of the capture-to-throat ratio A_c/A_t
  (:func:`obturator.flow.inlet.start_mach`) the bow shock is not swallowed;
  in this frictionless, perfect-throat limit the constant-area Table 1 bore
  (A_c/A_t = 1) starts at any supersonic Mach; with the wall friction of the
  post-shock flow and the lens's discharge coefficient (the late bound,
  :mod:`obturator.model.start`) it never starts below M 2.05 at sea level
  (``never_starts_late``; friction alone: below M 1.38).
* **choked** (Fanno, thesis chapter I.B.4.c): below the choking Mach of the bore
  (L/D = L_p / 2 r_p = 8.07 for Table 1) a normal shock stands in the bore;
  :func:`obturator.flow.fanno.choking_mach_freestream` iterates the friction
  factor with the free-stream Reynolds number of the launch altitude
  (standard day). Marked at the muzzle and at the moment of opening.

In both regions the closed-obturator load (normal shock ahead of the blocked
inlet, Eqs. 1, 3, 43) still applies until the bore opens, but what happens
after opening -- and the drag curve -- differ.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import partial
from typing import Any

import numpy as np

from ..errors import InputError, check_range
from ..flow import choking_mach_freestream, start_mach
from ..runs import Runner
from .coupled import STATUS_FLAGS, STATUS_OPENED, STATUS_UNCONVERGED
from .model import FlightModel, warm_integrators

__all__ = ["EnvelopeSpec", "run_envelope", "envelope_summary", "status_attrs"]

_MAX_POINTS = 100_000


def _axis(name: str, values: Any, lo: float, hi: float, unit: str) -> tuple[float, ...]:
    arr = np.atleast_1d(np.asarray(values, dtype=float))
    if arr.ndim != 1 or arr.size == 0:
        raise InputError(name, "expected a non-empty list of values")
    for x in arr:
        check_range(name, float(x), lo, hi, lo_open=name == "mach", unit=unit)
    if len(np.unique(arr)) != arr.size:
        raise InputError(name, "repeats a value")
    return tuple(float(x) for x in arr)


@dataclass(frozen=True)
class EnvelopeSpec:
    """An envelope map: grid, model, requirement and inlet geometry.

    Parameters
    ----------
    mach : sequence of float
        Muzzle Mach numbers M_0, each in (1, 10].
    altitude_m : sequence of float
        Launch altitudes [m], each in [0, 20 000].
    temperature_offset_k : sequence of float
        Off-standard temperatures Delta T [K], each in [-80, 60] (default 0 only).
    model : FlightModel
        Design, projectile, solver settings; its ``load`` is set to ``"both"``.
    requirement : float
        Opening-time requirement [s] (thesis: well inside 0.1 s).
    area_ratio : float
        Capture-to-throat area ratio A_c/A_t of the inlet, >= 1 (Table 1 bore: 1).
    relative_roughness : float
        Bore wall roughness eps/D for the Fanno friction factor.
    """

    mach: tuple[float, ...]
    altitude_m: tuple[float, ...]
    temperature_offset_k: tuple[float, ...] = (0.0,)
    model: FlightModel = field(default_factory=FlightModel)
    requirement: float = 0.1
    area_ratio: float = 1.0
    relative_roughness: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "mach", _axis("mach", self.mach, 1.0, 10.0, ""))
        object.__setattr__(
            self, "altitude_m", _axis("altitude_m", self.altitude_m, 0.0, 20_000.0, "m")
        )
        object.__setattr__(
            self,
            "temperature_offset_k",
            _axis("temperature_offset_k", self.temperature_offset_k, -80.0, 60.0, "K"),
        )
        if not isinstance(self.model, FlightModel):
            raise InputError("model", "expected a FlightModel")
        object.__setattr__(self, "model", self.model.with_(load="both", with_start=True))
        check_range("requirement", self.requirement, 0.0, 10.0, lo_open=True, unit="s")
        check_range("area_ratio", self.area_ratio, 1.0, 10.0)
        check_range("relative_roughness", self.relative_roughness, 0.0, 0.05)
        if math.prod(self.shape) > _MAX_POINTS:
            raise InputError("mach", f"{math.prod(self.shape)} points exceed {_MAX_POINTS}")
        start_mach(self.area_ratio)  # raises when the ratio never self-starts

    @property
    def shape(self) -> tuple[int, int, int]:
        """(n_mach, n_altitude, n_temperature)."""
        return (len(self.mach), len(self.altitude_m), len(self.temperature_offset_k))

    def tasks(self) -> list[dict[str, float]]:
        """Inputs of every grid point, C order (mach, altitude, temperature)."""
        return [
            {"mach": m, "altitude_m": h, "temperature_offset_k": dt}
            for m in self.mach
            for h in self.altitude_m
            for dt in self.temperature_offset_k
        ]

    def identity(self) -> dict[str, Any]:
        """JSON-ready description (the resume store's study hash)."""
        return {
            "study": "envelope",
            "mach": list(self.mach),
            "altitude_m": list(self.altitude_m),
            "temperature_offset_k": list(self.temperature_offset_k),
            "model": self.model.identity(),
            "requirement": self.requirement,
            "area_ratio": self.area_ratio,
            "relative_roughness": self.relative_roughness,
        }

    def choke_mach(self, altitude_m: float) -> float:
        """Fanno choking Mach of the bore at a launch altitude (standard day)."""
        r_p = self.model.design.bore_radius
        return choking_mach_freestream(
            self.model.projectile.length / (2.0 * r_p),
            2.0 * r_p,
            altitude_m=altitude_m,
            relative_roughness=self.relative_roughness,
        )


def status_attrs() -> dict[str, Any]:
    """CF flag attributes of a status variable."""
    return {
        "long_name": "integration outcome",
        "flag_values": np.array(sorted(STATUS_FLAGS), dtype=np.int8),
        "flag_meanings": " ".join(STATUS_FLAGS[k] for k in sorted(STATUS_FLAGS)),
    }


def run_envelope(spec: EnvelopeSpec, runner: Runner | None = None) -> Any:
    """Compute t_cr (constant and coupled load) over the envelope grid.

    Parameters
    ----------
    spec : EnvelopeSpec
    runner : Runner, optional
        Execution (local processes, Dask, resume store); default in-process.

    Returns
    -------
    xarray.Dataset
        Dimensions ``mach``, ``altitude_m`` (and ``temperature_offset_k`` when
        more than one is given). Variables: ``t_cr_coupled``, ``t_cr_constant``
        [s] with ``status_*`` and ``change_*`` (largest relative change under
        refinement), ``relative_difference`` (coupled / constant - 1),
        ``mach_at_opening``, ``force_at_opening`` [N], ``spin_at_opening``
        [rad/s], ``muzzle_velocity`` [m/s], ``muzzle_spin`` [rad/s],
        ``choke_mach`` (per altitude), ``choked_at_muzzle``,
        ``choked_at_opening``, ``started``, ``meets_requirement_coupled`` and
        ``meets_requirement_constant`` (1/0); ``t_start_coupled``,
        ``t_start_constant`` [s] (to theta_start(M), :mod:`obturator.model.start`;
        not convergence-checked), ``delay_coupled``, ``delay_constant``
        (t_start - t_cr) [s], ``theta_start_muzzle`` [deg] and ``unstartable``
        (1/0: the aligned ball cannot swallow the shock at the muzzle Mach),
        ``choked_at_start`` (1/0: Fanno-choked at the Mach of t_start, coupled).
    """
    import xarray as xr

    runner = runner or Runner(workers=1)
    results = runner.map(
        spec.model.evaluate_many, spec.tasks(), label="envelope", warm=warm_integrators,
        batched=True,
    )  # fmt: skip
    grid = partial(_grid, results, spec.shape)
    data = {**_opening_variables(spec, grid), **_flow_variables(spec, grid)}
    data |= _requirement_and_start_variables(spec, grid)
    ds = xr.Dataset(data, coords=_coords(spec), attrs=_attrs(spec, runner.backend))
    if len(spec.temperature_offset_k) == 1:
        ds = ds.squeeze("temperature_offset_k")
    return ds


_DIMS = ("mach", "altitude_m", "temperature_offset_k")
_OPENED = (STATUS_OPENED, STATUS_UNCONVERGED)
#: A dataset variable: (dimensions, values, attributes).
_Variable = tuple[tuple[str, ...], np.ndarray, dict[str, Any]]


def _grid(results: list[dict[str, Any]], shape: tuple[int, ...], key: str, dtype: Any = float):
    """One result field of every grid point as an array of the grid's shape (NaN, or
    status -2, where a point lacks it)."""
    fill = math.nan if dtype is float else -2
    return np.asarray([r.get(key, fill) for r in results], dtype=dtype).reshape(shape)


def _opening_variables(spec: EnvelopeSpec, grid: Any) -> dict[str, _Variable]:
    """t_cr under both loads, their statuses and refinement changes, the state at
    opening and the muzzle conditions."""
    t_cpl, t_con = grid("t_cr"), grid("t_cr_constant")
    velocity = np.empty(spec.shape)
    spin0 = np.empty(spec.shape)
    for i, task in enumerate(spec.tasks()):
        launch = replace(spec.model.launch, **task)
        velocity.flat[i] = launch.velocity
        spin0.flat[i] = launch.muzzle_spin
    s_attrs = status_attrs()
    return {
        "t_cr_coupled": (_DIMS, t_cpl, {"units": "s", "long_name": "t_cr, trajectory-coupled"}),
        "status_coupled": (_DIMS, grid("status", np.int8), s_attrs),
        "change_coupled": (
            _DIMS,
            grid("change"),
            {"units": "1", "long_name": "largest relative change of t_cr under refinement"},
        ),
        "t_cr_constant": (_DIMS, t_con, {"units": "s", "long_name": "t_cr, constant muzzle load"}),
        "status_constant": (_DIMS, grid("status_constant", np.int8), s_attrs),
        "change_constant": (_DIMS, grid("change_constant"), {"units": "1"}),
        "relative_difference": (
            _DIMS,
            t_cpl / t_con - 1.0,
            {"units": "1", "long_name": "t_cr coupled / t_cr constant - 1"},
        ),
        "mach_at_opening": (_DIMS, grid("mach_end"), {"units": "1"}),
        "force_at_opening": (_DIMS, grid("force_end"), {"units": "N", "long_name": "F_p at t_cr"}),
        "spin_at_opening": (_DIMS, grid("spin_end"), {"units": "rad/s"}),
        "muzzle_velocity": (_DIMS, velocity, {"units": "m/s"}),
        "muzzle_spin": (_DIMS, spin0, {"units": "rad/s"}),
    }


def _flow_variables(spec: EnvelopeSpec, grid: Any) -> dict[str, _Variable]:
    """Where the flow model changes: Fanno choking (muzzle, opening, start), the
    Kantrowitz start and theta_start at the muzzle Mach."""
    shape = spec.shape
    choke = np.array([spec.choke_mach(h) for h in spec.altitude_m])[None, :, None]
    mach = np.asarray(spec.mach)[:, None, None]
    theta_start = np.empty(shape)
    theta_late = np.empty(shape)
    for i, task in enumerate(spec.tasks()):
        angle = spec.model.design.start_angle(task["altitude_m"])
        theta_start.flat[i] = math.degrees(angle(task["mach"]))
        late = spec.model.design.start_angle(task["altitude_m"], "late")
        theta_late.flat[i] = math.degrees(late(task["mach"]))
    started = np.broadcast_to(mach > float(start_mach(spec.area_ratio)), shape)
    return {
        "choke_mach": (
            ("altitude_m",),
            choke[0, :, 0],
            {"units": "1", "long_name": "Fanno choking Mach of the open bore"},
        ),
        "choked_at_muzzle": (_DIMS, (mach <= choke).astype(np.int8), {}),
        "choked_at_opening": (_DIMS, (grid("mach_end") <= choke).astype(np.int8), {}),
        "started": (
            _DIMS,
            started.astype(np.int8),
            {"long_name": "muzzle Mach above the Kantrowitz self-starting Mach"},
        ),
        "theta_start_muzzle": (
            _DIMS,
            theta_start,
            {"units": "deg", "long_name": "theta_start at the muzzle Mach (Eq. 2 on A(theta))"},
        ),
        "choked_at_start": (
            _DIMS,
            (grid("mach_at_start") <= choke).astype(np.int8),
            {"long_name": "the flight Mach at t_start is at or below the Fanno choking Mach"},
        ),
        "unstartable": (
            _DIMS,
            (~np.isfinite(theta_start)).astype(np.int8),
            {"long_name": "even the aligned ball cannot swallow the shock at the muzzle Mach"},
        ),
        "theta_start_late_muzzle": (
            _DIMS,
            theta_late,
            {
                "units": "deg",
                "long_name": "theta_start at the muzzle Mach, late bound (wall friction, "
                "lowest discharge coefficient)",
            },
        ),
        "never_starts_late": (
            _DIMS,
            (~np.isfinite(theta_late)).astype(np.int8),
            {"long_name": "the late bound never starts at the muzzle Mach"},
        ),
    }


def _requirement_and_start_variables(spec: EnvelopeSpec, grid: Any) -> dict[str, _Variable]:
    """Whether each load meets the requirement, and t_start with its delay after t_cr
    (not convergence-checked)."""
    data: dict[str, _Variable] = {}
    for load, suffix in (("coupled", ""), ("constant", "_constant")):
        meets = np.isin(grid("status" + suffix, np.int8), _OPENED)
        meets &= grid("t_cr" + suffix) <= spec.requirement
        data[f"meets_requirement_{load}"] = (_DIMS, meets.astype(np.int8), {})
    for load, suffix in (("coupled", ""), ("constant", "_constant")):
        what = "trajectory-coupled" if load == "coupled" else "constant muzzle load"
        t_start = grid("t_start" + suffix)
        data[f"t_start_{load}"] = (
            _DIMS,
            t_start,
            {"units": "s", "long_name": f"t_start (shock swallowed), {what}"},
        )
        data[f"delay_{load}"] = (
            _DIMS,
            t_start - grid("t_cr" + suffix),
            {"units": "s", "long_name": f"t_start - t_cr, {what}"},
        )
        data[f"t_start_late_{load}"] = (
            _DIMS,
            grid("t_start_late" + suffix),
            {
                "units": "s",
                "long_name": f"t_start, late bound (wall friction, lowest C_d; NaN: never "
                f"starts or not by t_max), {what}",
            },
        )
    return data


def _coords(spec: EnvelopeSpec) -> dict[str, Any]:
    return {
        "mach": ("mach", np.asarray(spec.mach), {"units": "1", "long_name": "muzzle Mach M_0"}),
        "altitude_m": ("altitude_m", np.asarray(spec.altitude_m), {"units": "m"}),
        "temperature_offset_k": (
            "temperature_offset_k",
            np.asarray(spec.temperature_offset_k),
            {"units": "K", "long_name": "off-standard temperature"},
        ),
    }


def _attrs(spec: EnvelopeSpec, backend: str) -> dict[str, Any]:
    """The study's settings: requirement, inlet, model, design."""
    model = spec.model
    attrs = {
        "title": "obturator opening time over the firing envelope",
        "requirement_s": spec.requirement,
        "area_ratio": spec.area_ratio,
        "start_mach": float(start_mach(spec.area_ratio)),
        "segment_s": model.segment,
        "t_max_s": model.t_max,
        "convergence_threshold": model.threshold,
        "check_convergence": int(model.check_convergence),
        "drag_model": getattr(model.projectile.drag, "name", "table"),
        "roll_damping_clp": model.projectile.roll_damping,
        "spin_law": "given" if model.launch.spin_rate is not None else "twist",
        "twist_m": model.launch.twist,
        "elevation_deg": model.launch.elevation_deg,
        "backend": backend,
    }
    for k, v in model.design.to_dict().items():
        attrs[f"design_{k}"] = v
    return attrs


def envelope_summary(ds: Any) -> dict[str, Any]:
    """Headline numbers of an envelope map (JSON-ready).

    Counts of opened / converged points, t_cr ranges, the largest coupled
    vs constant difference and where, and the points where the two loads give
    a different verdict on the requirement.
    """
    req = float(ds.attrs["requirement_s"])
    out: dict[str, Any] = {"points": int(ds["t_cr_coupled"].size), "requirement_s": req}
    for load in ("coupled", "constant"):
        s = ds[f"status_{load}"].values
        t = ds[f"t_cr_{load}"].values
        out[f"{load}_opened"] = int(np.isin(s, (STATUS_OPENED, STATUS_UNCONVERGED)).sum())
        out[f"{load}_not_converged"] = int((s == STATUS_UNCONVERGED).sum())
        out[f"{load}_meets_requirement"] = int(ds[f"meets_requirement_{load}"].values.sum())
        fin = np.isfinite(t)
        out[f"{load}_t_cr_min_s"] = float(t[fin].min()) if fin.any() else None
        out[f"{load}_t_cr_max_s"] = float(t[fin].max()) if fin.any() else None
    rd = ds["relative_difference"]
    if np.isfinite(rd.values).any():
        idx = rd.fillna(0.0).argmax(...)
        where = {k: float(ds[k].values[v.values]) for k, v in idx.items()}
        out["max_relative_difference"] = float(rd.isel(idx).values)
        out["max_relative_difference_at"] = where
        out["min_relative_difference"] = float(np.nanmin(rd.values))
    flip = (ds["meets_requirement_constant"] == 1) & (ds["meets_requirement_coupled"] == 0)
    out["verdict_changed_points"] = int(flip.values.sum())
    out["choked_at_opening_points"] = int(ds["choked_at_opening"].values.sum())
    out["not_started_points"] = int((ds["started"] == 0).values.sum())
    if "delay_coupled" in ds:
        d = ds["delay_coupled"].values
        fin = np.isfinite(d)
        out["delay_coupled_min_s"] = float(d[fin].min()) if fin.any() else None
        out["delay_coupled_max_s"] = float(d[fin].max()) if fin.any() else None
        out["unstartable_points"] = int(ds["unstartable"].values.sum())
        out["choked_at_start_points"] = int(ds["choked_at_start"].values.sum())
    if "never_starts_late" in ds:
        out["never_starts_late_points"] = int(ds["never_starts_late"].values.sum())
        late = ds["t_start_late_coupled"].values
        fin = np.isfinite(late)
        out["t_start_late_coupled_max_s"] = float(late[fin].max()) if fin.any() else None
    return out
