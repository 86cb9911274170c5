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
from ..model.validity import outside_validated_data, outside_validated_range
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
from ..solve.plan import route_of
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
    "ball_radius",
    "hole_radius",
    "density",
    "gap",
    "weight",
    "bore_radius",
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


#: The convergence check's reruns may take this many times the main run's steps (at
#: least CHECK_MIN_STEPS): a regularised rerun of a case the set-valued solver ran
#: (e.g. far below the rig's spins) can need millions of steps; the check then stops
#: and is reported as failed, and the main answer stands.
CHECK_STEP_FACTOR = 50
CHECK_MIN_STEPS = 200_000


def _check_budget(options: SolverOptions, main_steps: int) -> SolverOptions:
    """`options` with the step limit of the convergence check's reruns."""
    budget = max(CHECK_MIN_STEPS, CHECK_STEP_FACTOR * int(main_steps))
    return dataclasses.replace(options, max_steps=min(options.max_steps, budget))


def _checked(
    case: Case, options: SolverOptions, t_cr: float, main_steps: int
) -> ConvergenceCheck | str:
    """The convergence check of a valid answer, or why it could not finish (a rerun's
    solver failure or step budget): the check never replaces the main answer."""
    budget = _check_budget(options, main_steps)
    try:
        return convergence_check(case, budget, opening_time_s=t_cr)
    except SolverError as exc:
        why = " ".join(str(exc).split())[:160].rstrip(".")
        return (
            f"a rerun stopped: {why} (the reruns' limit is {budget.max_steps:,} steps, "
            f"{CHECK_STEP_FACTOR}x the main run's)"
        )


def _flight_start(
    case: Any, settings: dict[str, Any], options: SolverOptions, check: bool, main_steps: int
) -> tuple[StartTimes, ConvergenceCheck | str | None]:
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
        conv = _checked(started, options, st.t_start, main_steps)
    return st, conv


def _start_rows(st: StartTimes, check: ConvergenceCheck | str | None) -> list[tuple[str, str, str]]:
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
        *_bracket_rows(st),
    ]
    if isinstance(check, str):
        rows.append(("t_start convergence", f"check FAILED: {check}", ""))
    elif check is not None:
        verdict = "converged" if check.converged else "NOT converged"
        change = check.largest_change
        rows.append(("t_start convergence", f"{verdict}: relative change {change:.1e}", ""))
    return rows


def _bracket_rows(st: StartTimes) -> list[tuple[str, str, str]]:
    """theta_start and t_start, early (turned flow) to late (friction, lowest C_d)."""
    c = st.condition

    def deg(x: float) -> str:
        return f"{math.degrees(x):.5g}" if x == x else "-"

    def sec(x: float) -> str:
        return f"{x:.5g} s" if x == x else "not reached by t_max"

    lens = f"lens, f_D L/D {c.friction_fld:.3g}, C_d {c.discharge_coefficients[0]:.3g}"
    if c.late_startable:
        late_theta = f"{deg(c.theta_start_late)} deg ({lens})"
        late_t = sec(st.t_start_late)
    else:
        late_theta = f"{c.late_verdict} ({lens})"
        late_t = "never starts"
    return [
        (
            "theta_start bracket, early .. late",
            f"{deg(c.theta_start_early)} deg (turned flow) .. {late_theta}",
            "",
        ),
        ("t_start bracket, early .. late", f"{sec(st.t_start_early)} .. {late_t}", ""),
    ]


def _print_table(
    res: NutationResult,
    check: ConvergenceCheck | str | None,
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
    if isinstance(check, str):
        rows.append(("convergence", f"check FAILED, the answer above is unchecked: {check}", ""))
    elif check is not None:
        verdict = "converged" if check.converged else "NOT converged"
        if check.strategy == "set-valued":
            rows.append(
                (
                    "convergence (tol / 10)",
                    f"{verdict}: relative change {check.tolerance_change:.1e}",
                    "",
                )
            )
            rows.append(
                (
                    "cross-check (regularised, width -> 0)",
                    f"t_cr {check.cross_check:.6g} s: relative change "
                    f"{check.cross_check_change:.1e} (its own spread "
                    f"{check.cross_check_spread:.1e})",
                    "",
                )
            )
        else:
            rows.append(
                (
                    f"convergence (tol / 10, width / 10, {check.family})",
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


def _check_dict(check: ConvergenceCheck | str) -> dict[str, Any]:
    """JSON of a convergence check, or of one that failed (``converged`` false)."""
    if isinstance(check, str):
        return {"converged": False, "failed": check}
    return check.to_dict()


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
    """What a timed probe says of this run's cost: an estimate where the probe covered
    at least a quarter of the horizon (near stick the steps per simulated second grow as
    the run goes on, so a longer extrapolation is no estimate), else none."""
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
    check = (
        f"; the convergence check's reruns stop at {CHECK_STEP_FACTOR}x the main run's "
        f"steps (at least {CHECK_MIN_STEPS:,}) and, where they fail, leave the answer "
        "unchecked (--no-convergence-check skips them)"
    )
    if probe.status != Status.T_MAX:
        return "a timed probe ended early; no cost estimate" + check
    covered = min(horizon, case.t_max)
    t_limit = options.max_steps * covered / max(steps, 1)
    if covered * 4.0 < min(case.t_max, t_limit):
        return (
            f"a timed probe ({covered:.2g} s of motion in {wall:.2g} s) covers too little of "
            f"t_max {case.t_max:g} s for an estimate (near stick the steps per simulated "
            f"second grow as the run goes on); {_FIX}" + check
        )
    cost = wall * min(case.t_max, t_limit) / covered
    text = f"a timed probe ({covered:.2g} s of motion in {wall:.2g} s) expects ~{_duration(cost)}"
    text += " for the main run"
    if t_limit < case.t_max:
        text += f", then the step limit ({options.max_steps:,} steps) by t = {t_limit:.2g} s"
    return text + check


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
    check_output_path("--animate", args.animate, ("html",))
    if args.figure is not None:
        from ..plotting import figure_suffixes

        check_output_path("--figure", args.figure, figure_suffixes())
    note = outside_validated_range(case)
    data = outside_validated_data(case)
    if note:
        note = f"{note}; {data}" if data else note
        print(f"obturator: warning: {note}; {_expected_cost(case, options)}", file=sys.stderr)
    elif data:  # one line: what lies outside the Appendix B runs, with their range
        print(f"obturator: warning: outside the validated data: {data}", file=sys.stderr)
    res = simulate(case, options)
    if res.status == Status.STEP_LIMIT:
        raise SolverError(_step_limit_message(res, case, options))
    if not res.success:
        raise SolverError(res.message)
    if args.csv:
        res.to_csv(args.csv)
    if args.figure:
        _plot(res, args.figure)
    if args.animate:
        from ..animation import write_animation

        write_animation(res, args.animate)
    check = None
    if args.convergence_check:
        check = _checked(case, options, res.opening_time, res.n_steps)
    start = None
    if case.name == "flight":
        start = _flight_start(case, settings, options, args.convergence_check, res.n_steps)
    if args.json:
        out = res.summary()
        out["route"] = route_of(res.solver, options, t_cr_only=False)
        if check is not None:
            out["convergence"] = _check_dict(check)
        if start is not None:
            out["start"] = start[0].to_dict()
            if start[1] is not None:
                out["start"]["convergence"] = _check_dict(start[1])
        print(_json.dumps(out))
    else:
        _print_table(res, check, None if start is None else _start_rows(*start))
    for what, failed in (("t_cr", check), ("t_start", start and start[1])):
        if isinstance(failed, str):
            print(
                f"obturator: warning: the convergence check of {what} could not finish, "
                f"the answer is reported unchecked: {failed}",
                file=sys.stderr,
            )
    if isinstance(check, ConvergenceCheck) and not check.converged:
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
    _quantity("ball_radius", "M", "ball radius R_s [m] (Table 1: 7.899e-3)"),
    _quantity(
        "hole_radius",
        "M",
        "hole radius r_s [m] (Table 1: 4.72e-3; the rig's load then follows the ball, W = rho g V)",
    ),
    _quantity("density", "RHO", "ball density rho [kg/m^3] (Table 1: 7669.6)"),
    _quantity("gap", "M", "ball-socket gap h [m] (Table 1: 5.08e-5)"),
    _quantity("weight", "N", "rig normal load W [N] (Table 1: 0.07987; default: measured)"),
    _quantity("bore_radius", "M", "flight bore radius r_p [m] (Table 1: 4.72e-3)"),
    _quantity("t_max", "S", "give up after this time [s]"),
    JSON,
    *convergence_flags(
        True,
        "rerun with tolerances / 10, friction width / 10 and another regularisation family "
        "and report how much t_cr moves",
    ),
    *figure_flags("theta.png", "write theta(t) as a figure"),
    CSV.but(type=OutputFile(("csv",), example="theta.csv"), help="write the time series as CSV"),
    option(
        "--animate",
        metavar="HTML",
        type=OutputFile(("html",), example="opening.html"),
        help="write an animation of the opening (the ball in its bore, theta(t), a time "
        "slider) as one standalone HTML file (plotly.js inline: opens offline)",
    ),
)
