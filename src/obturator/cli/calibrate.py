"""``obturator calibrate``: fit the sliding friction of the exact model to spin-rig data."""

from __future__ import annotations

import argparse
import math
import sys
from typing import Any

from ..errors import InputError
from ..params import Range
from ..reference import TABLE1
from ._args import quantity_of, solver_options
from ._flags import CONFIG, JSON, SEED_FLAG, command, count, figure_flags, option, quantity_option
from ._kinds import InputFile, Text

__all__ = ["register"]


#: Config keys calibrate passes to the rig model as they are (fit_exact's ``model``).
_MODEL_KEYS = (
    "t_max",
    "torque_model",
    "weight",
    "patch_radius",
    "theta_dot0",
    "release_phase",
    "speed_law",
    "speed_ratio",
    "slip_speed",
)


def _base_case(conf: dict[str, Any]) -> dict[str, Any]:
    """The rig model's settings of a config's base case (the file ``simulate`` runs).

    The spin is each run's and mu_s is what the fit finds: the file's values of both
    are replaced (said on stderr). The ball's radius, hole and density make the ball;
    the gap and its viscosity set the viscous constant S of Eq. (42) through the
    viscosity (``rig_model_case``), exactly since S is linear in the viscosity.
    """
    from ..model.cases import rig_case, table1_ball

    if conf.get("case", "spin-rig") != "spin-rig":
        raise InputError("case", "calibrate fits spin-rig runs: give case = 'spin-rig'")
    if conf.get("spin_mode", "constant") != "constant":
        raise InputError("spin_mode", "the rig is driven: calibrate models spin_mode 'constant'")
    flight = sorted(
        k for k in ("mach", "p1", "altitude_m", "n_contacts", "bore_radius") if k in conf
    )
    if flight:
        raise InputError(flight[0], "applies to the flight case only; calibrate fits rig runs")
    replaced = [k for k in ("spin_rate", "mu_s") if k in conf]
    if replaced:
        print(
            "obturator: note: the config's "
            + " and ".join(replaced)
            + " are replaced: each run has its own spin, and mu_s is fitted",
            file=sys.stderr,
        )
    kw: dict[str, Any] = {k: conf[k] for k in _MODEL_KEYS if k in conf}
    geometry = {k: conf[k] for k in ("ball_radius", "hole_radius", "density") if k in conf}
    ball = table1_ball(
        radius=geometry.get("ball_radius"),
        hole_radius=geometry.get("hole_radius"),
        density=geometry.get("density"),
    )
    if geometry:
        kw["ball"] = ball
    if "gap" in conf or "viscosity" in conf:
        from ..calibration.rig_model import S_TABLE1

        gap = {k: conf[k] for k in ("gap", "viscosity") if k in conf}
        given = rig_case(ball=ball, **gap).torque.viscous.coefficient
        default_gap = rig_case(ball=ball).torque.viscous.coefficient
        kw["shear_constant"] = S_TABLE1 * given / default_gap
    return kw


def _calibrate(args: argparse.Namespace) -> int:
    from ..calibration import calibrate_csv
    from ..io import CASE_FIELDS, study_settings

    if args.seed is not None and args.bootstrap == 0:
        raise InputError("--seed", "seeds the bootstrap, which --bootstrap 0 turns off")
    conf = study_settings(args.config, "calibrate", CASE_FIELDS)
    kwargs: dict[str, object] = _base_case(conf)
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
        bootstrap_seed=0 if args.seed is None else args.seed,
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
    "(18-tooth wheel) or spin_rate_rad_s, optionally starred (1/0), omega_p_printed_rad_s, "
    "comment, and each run's own theta0, hole_radius, density, ball_mass (unit in the "
    "header: theta0_deg, hole_radius_mm, density [kg/m^3], ball_mass (g)); any other "
    "column is refused. Runs fitted: spin >= --min-spin if given, else the starred runs, "
    "else all runs.",
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
    CONFIG.but(
        help="the rig case (the file simulate runs: spin and mu_s are replaced by each "
        "run's spin and the fit) and [solver] settings (flags win)"
    ),
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
    SEED_FLAG.but(
        metavar="N", default=None, help="bootstrap seed (default 0; with --bootstrap N > 0)"
    ),
    JSON,
    *figure_flags("fit.png", "write data, model and residuals"),
)
