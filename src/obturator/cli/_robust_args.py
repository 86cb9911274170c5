"""Flags of ``probability``, ``sensitivity`` and ``optimize`` with their kinds and defaults."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable

from ..params import Range
from ..reference import FLIGHT_SOBOL_RANGES
from ..sweeps.montecarlo import MAX_SAMPLES
from ._args import quantity_of
from ._flags import (
    CONFIDENCE,
    OUT_NETCDF,
    SEED_FLAG,
    VARY,
    add_command,
    add_flags,
    count,
    option,
    quantity_option,
    switch,
)
from ._flight_args import (
    ALTITUDE_GRID,
    FIGURE_FLAG,
    LAUNCH_MACH,
    MACH_GRID,
    REQUIREMENT_FLAG,
    add_execution_arguments,
    add_model_arguments,
)
from ._kinds import Text

__all__ = [
    "add_robust_commands",
    "DEFAULT_UNCERTAINTY",
    "DEFAULT_RANGES",
    "DEFAULT_RIG_RANGES",
    "IS_FLAGS",
    "MAX_SOBOL_BASE",
    "PROBABILITY_DEFAULTS",
]

#: Default uncertain inputs of ``probability`` (manufacturing and knowledge
#: uncertainty about Table 1): mu_s lognormal with 10 % spread; theta_0 within
#: +-1 deg; gap, hole radius and density with 3-sigma tolerances of 7.5 um,
#: 0.05 mm and 120 kg/m^3; muzzle spin +-1 % (muzzle-velocity dispersion).
DEFAULT_UNCERTAINTY = (
    "mu_s=lognormal:0.35,0.1",
    "theta0_deg=uniform:86.25,88.25",
    "gap=normal:5.08e-5,2.5e-6",
    "hole_radius=normal:4.72e-3,1.7e-5",
    "density=normal:7669.6,40",
    "spin_factor=normal:1,0.01",
)
#: Default ranges of ``sensitivity`` in flight (uniform, around Table 1).
DEFAULT_RANGES = FLIGHT_SOBOL_RANGES
#: Default ranges of ``sensitivity`` on the spin rig (weight follows the ball).
DEFAULT_RIG_RANGES = (
    "spin_rate=uniform:300,500",
    "mu_s=uniform:0.5,0.6",
    "theta0_deg=uniform:86.25,88.25",
    "gap=uniform:4.08e-5,6.08e-5",
    "hole_radius=uniform:4.62e-3,4.82e-3",
    "density=uniform:7500,7850",
)


#: Defaults of ``probability``'s sampling flags, resolved after parsing (the flags
#: default to None, so that one given with a --method it does not act in is refused):
#: ``samples`` acts with --method mc or both, the others with is or both.
PROBABILITY_DEFAULTS = {
    "samples": "2000",
    "stage_samples": "500",
    "final_samples": "1000",
    "rho": "0.1",
}
#: The flags of ``probability`` that act with the importance sampler only.
IS_FLAGS = (
    ("--stage-samples", "stage_samples"),
    ("--final-samples", "final_samples"),
    ("--rho", "rho"),
)

_POSITIVE = Range(0.0, math.inf, True, True)
#: Largest SALib base sample N: N (2 D + 2) model runs, ~0.9 million for D = 6 at
#: 65536; Sobol-index intervals shrink as 1 / sqrt(N), already below 0.01 there.
MAX_SOBOL_BASE = 65_536


def add_robust_commands(
    subparsers: argparse._SubParsersAction,
    run_probability: Callable[[argparse.Namespace], int],
    run_sensitivity: Callable[[argparse.Namespace], int],
    run_optimize: Callable[[argparse.Namespace], int],
) -> None:
    """Add the ``probability``, ``sensitivity`` and ``optimize`` sub-commands."""
    for command in (
        _add_probability(subparsers, run_probability),
        _add_sensitivity(subparsers, run_sensitivity),
        _add_optimize(subparsers, run_optimize),
    ):
        add_model_arguments(command, launch_point=False)
        add_execution_arguments(command)
        add_flags(command, OUT_NETCDF)


_EVENT = option(
    "--event",
    choices=("t_cr", "t_start", "t_start_late"),
    default="t_cr",
    help="t_cr, t_start or t_start_late (theta_start's late bound: wall friction, lowest "
    "discharge coefficient; never starting counts as not in time)",
)


def _add_probability(
    subparsers: argparse._SubParsersAction, run: Callable[[argparse.Namespace], int]
) -> argparse.ArgumentParser:
    return add_command(
        subparsers,
        "probability",
        run,
        "Probability that the bore opens later than the requirement, by cross-entropy "
        "importance sampling (--method is), brute-force Monte Carlo (mc) or both, with "
        "confidence intervals. Default inputs: " + " ".join(DEFAULT_UNCERTAINTY),
        MACH_GRID.but(help="muzzle Mach (default 3, or the config's [flight] mach)"),
        ALTITUDE_GRID.but(help="altitude [m] (default 0, or the config's [flight] altitude)"),
        VARY,
        REQUIREMENT_FLAG,
        _EVENT,
        option(
            "--method",
            choices=("is", "mc", "both"),
            default="is",
            help="cross-entropy importance sampling (is, the default), brute-force Monte "
            "Carlo (mc) or both",
        ),
        count(
            "--samples",
            1,
            MAX_SAMPLES,
            f"brute-force samples (at most {MAX_SAMPLES}, as montecarlo; default "
            f"{PROBABILITY_DEFAULTS['samples']}; --method mc or both)",
            example=20,
        ),
        count(
            "--stage-samples",
            20,
            MAX_SAMPLES,
            f"IS samples per stage (default {PROBABILITY_DEFAULTS['stage_samples']}; "
            "--method is or both)",
        ),
        count(
            "--final-samples",
            20,
            MAX_SAMPLES,
            f"IS final samples (default {PROBABILITY_DEFAULTS['final_samples']}; "
            "--method is or both)",
        ),
        quantity_option(
            "--rho",
            "",
            Range(0.0, 1.0, True, True),
            "0.1",
            f"IS elite fraction (default {PROBABILITY_DEFAULTS['rho']}; --method is or both)",
        ),
        SEED_FLAG,
        CONFIDENCE,
    )


def _add_sensitivity(
    subparsers: argparse._SubParsersAction, run: Callable[[argparse.Namespace], int]
) -> argparse.ArgumentParser:
    return add_command(
        subparsers,
        "sensitivity",
        run,
        "First-order and total Sobol indices of t_cr. Defaults: flight "
        + " ".join(DEFAULT_RANGES)
        + "; spin-rig "
        + " ".join(DEFAULT_RIG_RANGES),
        option(
            "--case",
            choices=("flight", "spin-rig"),
            default="flight",
            help="Table 1 column (default flight)",
        ),
        option(
            "--mach",
            dest="mach_point",
            metavar="X",
            type=LAUNCH_MACH,
            help="muzzle Mach (flight, 3)",
        ),
        option(
            "--altitude-m",
            dest="altitude_point",
            metavar="X",
            type=quantity_of("altitude_m"),
            help="altitude [m] (0)",
        ),
        VARY,
        count(
            "--samples",
            8,
            MAX_SOBOL_BASE,
            f"SALib base N (power of 2; at most {MAX_SOBOL_BASE}: N (2 D + 2) runs)",
            default="256",
        ),
        _EVENT,
        count("--resamples", 10, 100_000, "bootstrap resamples (at most 100000)", default="1000"),
        SEED_FLAG,
        CONFIDENCE,
        FIGURE_FLAG.but(help="bar chart"),
    )


def _add_optimize(
    subparsers: argparse._SubParsersAction, run: Callable[[argparse.Namespace], int]
) -> argparse.ArgumentParser:
    return add_command(
        subparsers,
        "optimize",
        run,
        "Differential evolution (SciPy) + SLSQP polish over the design variables, subject "
        "to the bore-able hole, the ball blocking the bore at launch, the socket wall and "
        "the mass budget; reports the optimum, its sensitivity and (--pareto N) the "
        "t_cr-mass Pareto front.",
        MACH_GRID.but(
            help="muzzle Mach numbers of the envelope (1.5,2.75,4, or the config's [flight] mach)"
        ),
        ALTITUDE_GRID.but(
            help="launch altitudes of the envelope [m] (0,10000, or the config's [flight] altitude)"
        ),
        option(
            "--objective",
            default="max",
            metavar="[t_cr:|t_start:|t_start_late:]max|quantile:Q",
            type=Text(example="max"),
            help="aggregate over the conditions of t_cr (default), of t_start or of its "
            "late bound t_start_late, e.g. t_start, t_start:quantile:0.9, t_start_late",
        ),
        option(
            "--variables",
            default="hole_radius,ball_radius,density,gap,mu_s",
            metavar="A,B,...",
            type=Text(example="mu_s"),
            help="design variables (default all five)",
        ),
        option(
            "--bound",
            action="append",
            metavar="NAME=LO,HI",
            type=Text(example="mu_s=0.3,0.4"),
            help="override bounds (SI)",
        ),
        quantity_option(
            "--mass-budget",
            "kg",
            _POSITIVE,
            "10 g",
            "largest ball mass (Table 1 ball's)",
            metavar="KG",
        ),
        quantity_option(
            "--wall",
            "m",
            _POSITIVE,
            "2 mm",
            "smallest socket wall R_p - R_s (2.061 mm)",
            metavar="M",
        ),
        quantity_option(
            "--block-margin-deg",
            "deg",
            Range(0.0, 90.0, False, True),
            "2 deg",
            "theta0-beta-beta_s",
            metavar="DEG",
            default="2",
        ),
        count(
            "--popsize",
            2,
            1000,
            "differential-evolution population per variable (at most 1000)",
            default="10",
        ),
        count(
            "--maxiter",
            1,
            10_000,
            "differential-evolution generations (at most 10000)",
            default="30",
        ),
        SEED_FLAG,
        switch("--no-polish", "skip the SLSQP polish"),
        count("--pareto", 2, 100, "trace the t_cr-mass Pareto front with N points (at most 100)"),
        FIGURE_FLAG.but(help="Pareto front figure (with --pareto)"),
    )
