"""``obturator simulate``: one run of a built-in case, optionally from a config file."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from . import _json
from .cases import CASE_NAMES, TORQUE_MODELS, flight_case, rig_case, table1_ball
from .errors import InputError, SolverError
from .io import check_output_path, load_config, parse_quantity
from .solve import (
    FRICTION_FAMILIES,
    Case,
    ConvergenceCheck,
    NutationResult,
    SolverOptions,
    convergence_check,
    simulate,
)
from .torques import SlipSpeedLaw

__all__ = ["register", "case_from_settings", "options_from_settings"]

_SPIN_MODES = ("constant", "free", "thesis-energy")


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``simulate`` sub-command."""
    p = subparsers.add_parser(
        "simulate",
        help="integrate one case to the opening time t_cr",
        description="Integrate the ball's nutation to the opening event theta = beta_s. "
        "Quantities accept units, e.g. --spin-rate '115000 rpm'.",
    )
    p.add_argument(
        "--case",
        choices=CASE_NAMES,
        default=None,
        help="Table 1 column (default spin-rig, or the config's case)",
    )
    p.add_argument("--spin-rate", metavar="RAD_S", help="projectile spin omega_p [rad/s]")
    p.add_argument("--mu-s", metavar="X", help="sliding friction coefficient [-]")
    p.add_argument("--theta0-deg", metavar="X", help="initial nutation theta_0 [deg]")
    p.add_argument("--torque-model", choices=TORQUE_MODELS, default=None)
    p.add_argument("--spin-mode", choices=_SPIN_MODES, default=None)
    p.add_argument("--mach", metavar="M", help="flight Mach number (normal bow shock, Eq. 1)")
    p.add_argument("--altitude-m", metavar="H", help="flight altitude [m] (US 1976 atmosphere)")
    p.add_argument("--config", metavar="FILE.toml", help="run configuration (units allowed)")
    p.add_argument("--rtol", metavar="X", help="relative tolerance (default 1e-8)")
    p.add_argument(
        "--friction-width",
        metavar="X",
        help="Coulomb regularisation width / omega_p (default 1e-7)",
    )
    p.add_argument(
        "--friction-family",
        choices=tuple(FRICTION_FAMILIES),
        default=None,
        help="shape of the regularised friction magnitude (default algebraic); "
        "the convergence check reruns with another family",
    )
    p.add_argument(
        "--patch-radius",
        metavar="M",
        help="contact patch radius of --torque-model coulomb [m] "
        "(default: Hertz radius; 0: point contact)",
    )
    p.add_argument("--formulation", choices=("quaternion", "euler"), default=None)
    p.add_argument(
        "--theta-dot0", metavar="RAD_S", help="release transient theta_dot_0 [rad/s] (rig)"
    )
    p.add_argument("--release-phase", metavar="RAD", help="release azimuth psi_0 [rad] (rig)")
    p.add_argument(
        "--speed-law",
        choices=("constant", "weakening", "strengthening"),
        default=None,
        help="slip-speed dependence of mu (rig; default constant, the thesis's)",
    )
    p.add_argument("--speed-ratio", metavar="R", help="mu(v) ratio r in (0, 1] (with --speed-law)")
    p.add_argument("--slip-speed", metavar="M_S", help="mu(v) speed v_s [m/s] (with --speed-law)")
    p.add_argument("--t-max", metavar="S", help="give up after this time [s]")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument(
        "--no-check",
        action="store_true",
        help="skip the convergence check (reruns with tolerances / 10, friction width / 10 "
        "and another regularisation family)",
    )
    p.add_argument("--plot", metavar="FILE.png", help="write theta(t) as a figure")
    p.add_argument("--csv", metavar="FILE.csv", help="write the time series as CSV")
    p.set_defaults(func=_run)


def _merge(args: argparse.Namespace) -> dict[str, Any]:
    s: dict[str, Any] = load_config(args.config) if args.config else {}
    units = {  # field -> SI unit; messages name the field (spin_rate), as config errors do
        "spin_rate": "rad/s",
        "mu_s": "",
        "theta0_deg": "deg",
        "mach": "",
        "altitude_m": "m",
        "rtol": "",
        "friction_width": "",
        "patch_radius": "m",
        "t_max": "s",
        "theta_dot0": "rad/s",
        "release_phase": "rad",
        "speed_ratio": "",
        "slip_speed": "m/s",
    }
    for key, unit in units.items():
        value = getattr(args, key)
        if value is not None:
            s[key] = parse_quantity(key, value, unit)
    for key in ("case", "torque_model", "spin_mode", "formulation", "friction_family", "speed_law"):
        if getattr(args, key) is not None:
            s[key] = getattr(args, key)
    return s


def case_from_settings(s: dict[str, Any]) -> Case:
    """Build a :class:`Case` from merged settings (SI floats; see :mod:`obturator.io`)."""
    name = s.get("case", "spin-rig")
    if name not in CASE_NAMES:
        raise InputError("case", f"{name!r}; allowed: {', '.join(CASE_NAMES)}")
    if s.get("torque_model", "thesis") not in TORQUE_MODELS:
        raise InputError("torque_model", f"{s['torque_model']!r}; allowed: thesis, coulomb")
    if s.get("spin_mode", "constant") not in _SPIN_MODES:
        raise InputError("spin_mode", f"{s['spin_mode']!r}; allowed: {', '.join(_SPIN_MODES)}")
    geometry_changed = any(k in s for k in ("ball_radius", "hole_radius", "density"))
    ball = table1_ball(
        radius=s.get("ball_radius"), hole_radius=s.get("hole_radius"), density=s.get("density")
    )
    common: dict[str, Any] = {
        "ball": ball,
        "torque_model": s.get("torque_model", "thesis"),
        "spin_mode": s.get("spin_mode", "constant"),
    }
    for key in ("theta0_deg", "gap", "viscosity", "t_max"):
        if key in s:
            common[key] = s[key]
    if "patch_radius" in s:
        if common["torque_model"] != "coulomb":
            raise InputError("patch_radius", "applies to torque_model 'coulomb' only")
        common["patch_radius"] = s["patch_radius"]
    for key in ("spin_rate", "mu_s"):
        if key in s:
            common[key] = s[key]
    if "p1" in s and "altitude_m" in s:
        raise InputError("altitude", "give either p1 or altitude (which sets P1), not both")
    if "n_contacts" in s and common["torque_model"] != "coulomb":
        raise InputError("n_contacts", "applies to torque_model 'coulomb' only")
    rig_only = ("theta_dot0", "release_phase", "speed_law", "speed_ratio", "slip_speed")
    if name == "spin-rig":
        if any(k in s for k in ("speed_ratio", "slip_speed")) and "speed_law" not in s:
            raise InputError("speed_law", "give the law (weakening or strengthening) too")
        if s.get("speed_law", "constant") != "constant":
            common["speed_law"] = SlipSpeedLaw(
                s["speed_law"], s.get("speed_ratio", 0.5), s.get("slip_speed", 0.05)
            )
        common["release_rate"] = (s.get("theta_dot0", 0.0), 0.0, 0.0)
        common["release_phase"] = s.get("release_phase", 0.0)
        flight_keys = ("mach", "altitude_m", "p1", "n_contacts", "bore_radius")
        extra = sorted(k for k in flight_keys if k in s)
        if extra:
            raise InputError(extra[0], "applies to --case flight only")
        if "weight" in s:
            common["weight"] = s["weight"]
        elif geometry_changed:
            common["weight"] = None  # the weight follows the modified ball
        return rig_case(**common)
    if "weight" in s:
        raise InputError("weight", "applies to --case spin-rig only")
    extra = sorted(k for k in rig_only if k in s)
    if extra:
        raise InputError(extra[0], "applies to --case spin-rig only")
    for key in ("mach", "n_contacts", "bore_radius"):
        if key in s:
            common[key] = s[key]
    if "altitude_m" in s:
        common["altitude_m"] = s["altitude_m"]
        common["p1"] = None
    elif "p1" in s:
        common["p1"] = s["p1"]
    return flight_case(**common)


def options_from_settings(s: dict[str, Any]) -> SolverOptions:
    """Solver options from merged settings (defaults for anything not given)."""
    keys = ("rtol", "atol", "friction_width", "friction_family", "method", "formulation")
    kw = {k: s[k] for k in keys if k in s}
    if "rtol" in kw and "atol" not in kw:
        kw["atol"] = kw["rtol"] * 1e-2
    return SolverOptions(**kw)


def _print_table(res: NutationResult, check: ConvergenceCheck | None) -> None:
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
        (
            "friction regularisation",
            f"{s['friction_family']}, width {s['friction_width']:g}",
            "omega_p",
        ),
        ("status", f"{res.status}: {res.message}", ""),
        ("steps / RHS evaluations", f"{res.n_steps} / {res.nfev}", ""),
    ]
    if check is not None:
        verdict = "converged" if check.converged else "NOT converged"
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


def _plot_suffixes() -> tuple[str, ...]:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    return tuple(FigureCanvasAgg(Figure()).get_supported_filetypes())


def _plot(res: NutationResult, path: str) -> None:
    from .plotting import save, theta_history_figure

    save(theta_history_figure(res), path)


def _run(args: argparse.Namespace) -> int:
    settings = _merge(args)
    case = case_from_settings(settings)
    options = options_from_settings(settings)
    check_output_path("--csv", args.csv, ("csv",))
    if args.plot is not None:
        check_output_path("--plot", args.plot, _plot_suffixes())
    res = simulate(case, options)
    if not res.success:
        raise SolverError(res.message)
    if args.csv:
        res.to_csv(args.csv)
    if args.plot:
        _plot(res, args.plot)
    check = (
        None if args.no_check else convergence_check(case, options, opening_time_s=res.opening_time)
    )
    if args.json:
        out = res.summary()
        if check is not None:
            out["convergence"] = check.to_dict()
        print(_json.dumps(out))
    else:
        _print_table(res, check)
    if check is not None and not check.converged:
        print(
            "obturator: warning: t_cr is not converged (it changes by more than "
            f"{check.threshold:g} when tolerances or the friction width shrink tenfold or "
            "the regularisation family changes); tighten --rtol and --friction-width",
            file=sys.stderr,
        )
    return 0
