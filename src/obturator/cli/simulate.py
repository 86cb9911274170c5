"""``obturator simulate``: one run of a built-in case, optionally from a config file."""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import time
from typing import Any

from ..errors import SolverError
from ..io import check_output_path, load_config
from ..model.case import Case
from ..model.cases import case_from_settings
from ..model.validity import outside_validated_range
from ..params import PARAMS
from ..result import NutationResult
from ..solve import (
    ConvergenceCheck,
    SolverOptions,
    StartTimes,
    convergence_check,
    simulate,
    start_times,
)
from ..status import Status
from ..units import parse_quantity
from ..vocab import (
    FORMULATIONS,
    SET_VALUED_METHODS,
)
from . import _json
from ._args import flag, quantity_of, solver_options
from ._flags import (
    CASE,
    CONFIG,
    CSV,
    FRICTION_FAMILY,
    JSON,
    SPEED_LAW,
    SPIN_MODE,
    TORQUE_MODEL,
    Flag,
    command,
    convergence_flags,
    figure_flags,
    option,
)
from ._kinds import OutputFile

__all__ = ["register", "case_from_settings", "options_from_settings"]

#: Flags that take a quantity (field names; units from obturator.params).
_QUANTITY_FLAGS = (
    "spin_rate",
    "mu_s",
    "theta0_deg",
    "mach",
    "altitude_m",
    "rtol",
    "friction_width",
    "patch_radius",
    "t_max",
    "theta_dot0",
    "release_phase",
    "speed_ratio",
    "slip_speed",
)


def _quantity(name: str, metavar: str, text: str) -> Flag:
    """The flag of parameter `name` (one of _QUANTITY_FLAGS): unit and range from
    obturator.params."""
    return option(flag(name), metavar=metavar, type=quantity_of(name), help=text)


def _merge(args: argparse.Namespace) -> dict[str, Any]:
    s: dict[str, Any] = load_config(args.config) if args.config else {}
    for key in _QUANTITY_FLAGS:  # messages name the field (spin_rate), as config errors do
        value = getattr(args, key)
        if value is not None:
            s[key] = parse_quantity(key, value, PARAMS[key].pint_unit)
    for key in ("case", "torque_model", "spin_mode", "formulation", "friction_family", "speed_law"):
        if getattr(args, key) is not None:
            s[key] = getattr(args, key)
    return s


def options_from_settings(s: dict[str, Any]) -> SolverOptions:
    """Solver options from merged settings (defaults for anything not given)."""
    return solver_options(s)


def _flight_start(
    case: Any, settings: dict[str, Any], options: SolverOptions, check: bool
) -> tuple[StartTimes, ConvergenceCheck | None]:
    """theta_start at the case's Mach and t_start past first light (flight only)."""
    from ..model.start import start_condition
    from ..reference import TABLE1

    cond = start_condition(
        settings.get("mach", TABLE1["mach"]),
        case.ball,
        settings.get("bore_radius", TABLE1["bore_radius"]),
        altitude_m=settings.get("altitude_m", 0.0),
    )
    st = start_times(case, cond, options)
    conv = None
    if check and st.t_start == st.t_start:  # the continuous run to theta_start, refined
        started = case.with_(theta_cr=cond.theta_start)
        conv = convergence_check(started, options, opening_time_s=st.t_start)
    return st, conv


def _start_rows(st: StartTimes, check: ConvergenceCheck | None) -> list[tuple[str, str, str]]:
    c = st.condition
    t = st.t_start
    rows = [
        ("theta_start (shock swallowed, Eq. 2)", f"{math.degrees(c.theta_start):.6g}", "deg"),
        ("start time t_start", f"{t:.6g} s" if t == t else "not started by t_max", ""),
        ("delay t_start - t_cr", f"{st.delay:.6g} s" if t == t else "-", ""),
        (
            "t_start, spill load bracket",
            f"[{st.t_start_high_load:.4g}, {st.t_start_low_load:.4g}] s",
            "",
        ),
        ("inlet", f"{c.verdict} (Fanno choking Mach {c.choke_mach:.4g})", ""),
    ]
    if check is not None:
        verdict = "converged" if check.converged else "NOT converged"
        change = max(check.tolerance_change, check.width_change, check.family_change)
        rows.append(("t_start convergence", f"{verdict}: relative change {change:.1e}", ""))
    return rows


def _print_table(
    res: NutationResult,
    check: ConvergenceCheck | None,
    start: list[tuple[str, str, str]] | None = None,
) -> None:
    s = res.summary()
    t_cr = res.opening_time
    rows = [
        ("case", str(s["case"]), ""),
        ("torque model", str(s["torque_model"]), ""),
        ("spin rate omega_p", f"{s['spin_rate_rad_s']:.6g}", "rad/s"),
        ("mu_s", f"{s['mu_s']}", "-"),
        ("theta_0", f"{s['theta0_deg']:.6g}", "deg"),
        ("theta_cr = beta_s", f"{s['theta_cr_deg']:.6g}", "deg"),
        ("opening time t_cr", f"{t_cr:.6g} s" if res.opened else "not opened by t_max", ""),
        *(start or []),
        (
            (
                "friction regularisation",
                f"{s['friction_family']}, width {s['friction_width']:g}",
                "omega_p",
            )
            if s["solver"] not in SET_VALUED_METHODS
            else ("friction law", f"set-valued, no width (method {_method(s)})", "")
        ),
        ("status", f"{res.status}: {res.message}", ""),
        ("steps / RHS evaluations", f"{res.n_steps} / {res.nfev}", ""),
    ]
    if check is not None:
        verdict = "converged" if check.converged else "NOT converged"
        rows.append(
            (  # set-valued methods: checked against the regularised limit
                f"convergence (tol / 10, width / 10, {check.family})"
                if s["solver"] not in SET_VALUED_METHODS
                else f"convergence (tol / 10; regularised: width {s['friction_width'] / 10:g}, "
                f"{check.family})",
                f"{verdict}: relative change {check.tolerance_change:.1e}, "
                f"{check.width_change:.1e}, {check.family_change:.1e}",
                "",
            )
        )
    inputs = s["inputs"]
    rows.append(("inputs", "", ""))
    for key, value in inputs.items():
        if isinstance(value, dict):
            value = ", ".join(f"{k}={v}" for k, v in value.items())
        rows.append((f"  {key}", f"{value:.6g}" if isinstance(value, float) else str(value), ""))
    width = max(len(r[0]) for r in rows)
    for label, value, unit in rows:
        print(f"{label:<{width}}  {value} {unit}".rstrip())


def _method(summary: dict[str, Any]) -> str:
    """The method as asked, and what ``auto`` chose where it chose."""
    asked, ran = summary["method"], summary["solver"]
    return str(asked) if asked == ran else f"{asked}: {ran}"


def _plot(res: NutationResult, path: str) -> None:
    from ..plotting import save, theta_history_figure

    save(theta_history_figure(res), path)


_FIX = (
    "check the spin's unit (the rig's runs are 78-446 rad/s), widen --friction-width "
    "(e.g. 1e-5: the convergence check shows what that changes) or shorten --t-max"
)


def _duration(seconds: float) -> str:
    """`seconds` [s] as s, min or h."""
    if seconds < 120.0:
        return f"{seconds:.2g} s"
    return f"{seconds / 60:.2g} min" if seconds < 7200.0 else f"{seconds / 3600:.2g} h"


def _expected_cost(case: Case, options: SolverOptions) -> str:
    """Time a short stretch of the run and extrapolate to t_max or the step limit."""
    tiny = case.with_(t_max=min(1e-6, case.t_max))
    for method in dict.fromkeys((options.method, "radau")):  # load the compiled code first
        simulate(tiny, dataclasses.replace(options, method=method))
    horizon, wall, steps = 1e-4, 0.0, 0
    for _ in range(12):
        t0 = time.perf_counter()
        probe = simulate(case.with_(t_max=min(horizon, case.t_max)), options)
        wall, steps = time.perf_counter() - t0, probe.n_steps
        if probe.status != Status.T_MAX or horizon >= case.t_max or wall >= 0.2:
            break
        horizon *= 4.0
    if probe.status != Status.T_MAX:
        return "a timed probe ended early; no cost estimate"
    # near stick the steps per simulated second grow as the run goes on: a lower bound
    t_limit = options.max_steps * horizon / max(steps, 1)
    cost = wall * min(case.t_max, t_limit) / horizon
    text = (
        f"a timed probe ({horizon:.2g} s of motion in {wall:.2g} s) expects at least "
        f"~{_duration(cost)} for this run"
    )
    if t_limit < case.t_max:
        text += f", then the step limit ({options.max_steps:,} steps) by t = {t_limit:.2g} s"
    if cost < 10.0 and t_limit >= case.t_max:
        return text
    return f"{text} (--no-check skips the check's 3 reruns); {_FIX}"


def _step_limit_message(res: NutationResult, case: Case, options: SolverOptions) -> str:
    """The step limit with its cause (stiff near-stick friction) and the fixes."""
    width = options.friction_width * case.spin_rate
    return (
        f"step limit: {res.n_steps:,} steps reached at t = {res.t[-1]:.3g} s of t_max "
        f"{case.t_max:g} s before the bore opened; near stick the regularised friction "
        f"(width {width:.2g} rad/s = friction_width x omega_p) needs tiny steps, the more "
        f"so the lower the spin; {_FIX}"
    )


def _run(args: argparse.Namespace) -> int:
    settings = _merge(args)
    case = case_from_settings(settings)
    options = options_from_settings(settings)
    check_output_path("--csv", args.csv, ("csv",))
    if args.figure is not None:
        from ..plotting import figure_suffixes

        check_output_path("--figure", args.figure, figure_suffixes())
    note = outside_validated_range(case)
    if note:
        print(f"obturator: warning: {note}; {_expected_cost(case, options)}", file=sys.stderr)
    res = simulate(case, options)
    if res.status == Status.STEP_LIMIT:
        raise SolverError(_step_limit_message(res, case, options))
    if not res.success:
        raise SolverError(res.message)
    if args.csv:
        res.to_csv(args.csv)
    if args.figure:
        _plot(res, args.figure)
    check = None
    if args.convergence_check:
        check = convergence_check(case, options, opening_time_s=res.opening_time)
    start = None
    if case.name == "flight":
        start = _flight_start(case, settings, options, args.convergence_check)
    if args.json:
        out = res.summary()
        if check is not None:
            out["convergence"] = check.to_dict()
        if start is not None:
            out["start"] = start[0].to_dict()
            if start[1] is not None:
                out["start"]["convergence"] = start[1].to_dict()
        print(_json.dumps(out))
    else:
        _print_table(res, check, None if start is None else _start_rows(*start))
    if check is not None and not check.converged:
        print(
            "obturator: warning: t_cr is not converged (it changes by more than "
            f"{check.threshold:g} when tolerances or the friction width shrink tenfold or "
            "the regularisation family changes); tighten --rtol and --friction-width",
            file=sys.stderr,
        )
    return 0


register = command(
    "simulate",
    _run,
    "Integrate the ball's nutation to the opening event theta = beta_s. Quantities "
    "accept units, e.g. --spin-rate '115000 rpm'.",
    CASE.but(help="Table 1 column (default spin-rig, or the config's case)"),
    _quantity("spin_rate", "RAD_S", "projectile spin omega_p [rad/s]"),
    _quantity("mu_s", "X", "sliding friction coefficient [-]"),
    _quantity("theta0_deg", "X", "initial nutation theta_0 [deg]"),
    TORQUE_MODEL,
    SPIN_MODE,
    _quantity("mach", "M", "flight Mach number (normal bow shock, Eq. 1)"),
    _quantity("altitude_m", "H", "flight altitude [m] (US 1976 atmosphere)"),
    CONFIG.but(help="run configuration (units allowed)"),
    _quantity("rtol", "X", "relative tolerance (default 1e-8)"),
    _quantity("friction_width", "X", "Coulomb regularisation width / omega_p (default 1e-7)"),
    FRICTION_FAMILY.but(
        help="shape of the regularised friction magnitude (default algebraic); "
        "the convergence check reruns with another family",
    ),
    _quantity(
        "patch_radius",
        "M",
        "contact patch radius of --torque-model coulomb [m] "
        "(default: Hertz radius; 0: point contact)",
    ),
    option(
        "--formulation",
        choices=FORMULATIONS,
        default=None,
        help="state of the equations of motion: quaternion (default) or Euler angles",
    ),
    _quantity("theta_dot0", "RAD_S", "release transient theta_dot_0 [rad/s] (rig)"),
    _quantity("release_phase", "RAD", "release azimuth psi_0 [rad] (rig)"),
    SPEED_LAW.but(help="slip-speed dependence of mu (rig; default constant, the thesis's)"),
    _quantity("speed_ratio", "R", "mu(v) ratio r in (0, 1] (with --speed-law)"),
    _quantity("slip_speed", "M_S", "mu(v) speed v_s [m/s] (with --speed-law)"),
    _quantity("t_max", "S", "give up after this time [s]"),
    JSON,
    *convergence_flags(
        True,
        "rerun with tolerances / 10, friction width / 10 and another regularisation family "
        "and report how much t_cr moves",
    ),
    *figure_flags("theta.png", "write theta(t) as a figure"),
    CSV.but(type=OutputFile(("csv",), example="theta.csv"), help="write the time series as CSV"),
)
