"""``obturator calibrate``: fit the sliding friction of the exact model to spin-rig data."""

from __future__ import annotations

import argparse
import math
import sys

from ..params import Range
from ..reference import TABLE1
from ._args import quantity_of, solver_options
from ._flags import CONFIG, JSON, SEED_FLAG, command, count, figure_flags, option, quantity_option
from ._kinds import InputFile, Text

__all__ = ["register"]


def _calibrate(args: argparse.Namespace) -> int:
    from ..calibration import calibrate_csv
    from ..io import study_settings

    conf = study_settings(
        args.config, "calibrate", ("theta0_deg", "t_max", "torque_model", "weight")
    )
    kwargs: dict[str, object] = {
        k: conf[k] for k in ("t_max", "torque_model", "weight") if k in conf
    }
    names = tuple(n.strip() for n in args.fit.split(",") if n.strip())
    theta0 = (
        args.theta0_deg
        if args.theta0_deg is not None
        else conf.get("theta0_deg", TABLE1["theta0_deg"])
    )
    fit = calibrate_csv(
        args.data,
        theta0_deg=theta0,
        min_spin=args.min_spin,
        fit=names,
        bootstrap=args.bootstrap,
        bootstrap_seed=args.seed,
        options=solver_options(conf.get("solver", {})),
        **kwargs,
    )
    if args.figure:
        from ..plotting import calibration_residuals, save

        save(calibration_residuals(fit), args.figure)
    sys.stdout.write((fit.to_json() if args.json else fit.report()) + "\n")
    return 0


register = command(
    "calibrate",
    _calibrate,
    "Least-squares fit of mu_s of the exact rig model (integrated equations of motion) "
    "to measured opening times. DATA.csv has a header with t_cr_s and readout_hz "
    "(18-tooth wheel) or spin_rate_rad_s, optionally starred (1/0) and each run's own "
    "theta0, hole_radius, density, ball_mass, theta_measured with t_measured (unit in the "
    "header: theta0_deg, hole_radius_mm, density [kg/m^3], ...). Runs fitted: spin "
    ">= --min-spin if given, else the starred runs, else all runs.",
    option(
        "data",
        metavar="DATA.csv",
        type=InputFile(example="runs.csv"),
        help="spin-rig opening times",
    ),
    option(
        "--theta0-deg",
        metavar="X",
        type=quantity_of("theta0_deg"),
        default=None,
        help=f"theta_0 [deg] ({TABLE1['theta0_deg']}; on runs with their own theta0 "
        "column, its offset from that value is added)",
    ),
    CONFIG.but(help="theta0, t_max, torque_model, [rig] weight and [solver] settings (flags win)"),
    quantity_option(
        "--min-spin",
        "rad/s",
        Range(0.0, math.inf, False, True),
        "1e5 rad/s",
        "fit runs with omega_p >= X rad/s",
    ),
    option(
        "--fit",
        metavar="NAMES",
        default="mu_s",
        type=Text(example="mu_s"),
        help="comma list of fitted parameters, mu_s among them: theta0_deg, "
        "shear_constant, theta_dot0, release_phase, speed_ratio, slip_speed, patch_radius "
        "(bounds and their reasons: obturator.params.FIT_SPECS)",
    ),
    # 1e5 resamples give percentile intervals to ~1e-3 of their width; more is wasted
    count("--bootstrap", 0, 100_000, "bootstrap resamples (0: none; at most 100000)", default=200),
    SEED_FLAG.but(metavar="N", default=0, help="bootstrap seed"),
    JSON,
    *figure_flags("fit.png", "write data, model and residuals"),
)
