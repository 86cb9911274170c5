"""Command-line options declared once (:class:`Flag`) and composed into commands.

An option that several commands take (``--json``, ``--seed``, the solver tolerances,
the execution flags, the outputs) is one :class:`Flag` here, with its kind
(:mod:`._kinds`); a command adds the ones it takes with :func:`add_flags` (or
:func:`add_command`; a module with one sub-command declares it with :func:`command`),
changing a setting only where its meaning differs there (:meth:`Flag.but`: another
default, help or destination). :func:`count`, :func:`quantity_option` and :func:`switch`
make the options of the common kinds.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from ..params import SWEEP_PARAMS, Range
from ..vocab import CASE_NAMES, FRICTION_FAMILIES, METHODS, SPEED_LAWS, SPIN_MODES, TORQUE_MODELS
from ._args import MAX_WORKERS, SEED, axis_of, flag, quantity_of
from ._kinds import Count, InputFile, OutputFile, Quantity, SchedulerAddress, Text

__all__ = [
    "Flag",
    "option",
    "count",
    "switch",
    "add_flags",
    "add_command",
    "command",
    "quantity_option",
    "execution_flags",
    "RESTART",
    "study_flags",
    "parameter_flags",
    "JSON",
    "NO_PROGRESS",
    "CONFIG",
    "RTOL",
    "ATOL",
    "T_MAX",
    "RIG_HORIZON",
    "SEED_FLAG",
    "CONFIDENCE",
    "VARY",
    "OUT_NETCDF",
    "CSV",
    "PLOT",
    "TORQUE_MODEL",
    "CASE",
    "SPIN_MODE",
    "FRICTION_FAMILY",
    "SPEED_LAW",
    "RIG_DATA",
    "FIGURE",
    "alias",
    "convergence_flags",
    "figure_flags",
]


@dataclass(frozen=True)
class Flag:
    """One command-line option: its names and its ``add_argument`` settings."""

    names: tuple[str, ...]
    settings: Mapping[str, Any] = field(default_factory=dict)

    def but(self, **changes: Any) -> Flag:
        """The same option with some settings changed (a command's default or help)."""
        return Flag(self.names, MappingProxyType({**self.settings, **changes}))


def option(*names: str, **settings: Any) -> Flag:
    """A :class:`Flag` with these names and ``add_argument`` settings."""
    return Flag(names, MappingProxyType(settings))


def count(
    name: str, lo: int, hi: int, text: str, *, example: int | None = None, **settings: Any
) -> Flag:
    """A whole-number option N in [lo, hi] (:class:`._kinds.Count`) with its help `text`;
    `example` is the value the contract tests try (default `lo`)."""
    kind = Count(lo, hi, example=str(lo if example is None else example))
    return option(name, metavar="N", type=kind, help=text, **settings)


def quantity_option(
    name: str,
    unit: str,
    rng: Range,
    example: str,
    text: str,
    *,
    metavar: str = "X",
    **settings: Any,
) -> Flag:
    """An option with a value in `unit` within `rng` (:class:`._kinds.Quantity`) and its
    help `text`; `example` is a valid value with its unit (for the contract tests)."""
    return option(name, metavar=metavar, type=Quantity(unit, rng, example), help=text, **settings)


def switch(name: str, text: str) -> Flag:
    """An on/off option (``store_true``) with its help `text`."""
    return option(name, action="store_true", help=text)


def alias(flag: Flag, *old: str) -> Flag:
    """`flag` under its former spellings `old`, hidden from ``--help``: an old command
    line keeps working for a release while the help shows one spelling per concept."""
    dest = flag.settings.get("dest") or flag.names[0].lstrip("-").replace("-", "_")
    hidden = {"help": argparse.SUPPRESS, "default": argparse.SUPPRESS, "dest": dest}
    return Flag(old, MappingProxyType({**flag.settings, **hidden}))


def convergence_flags(default: bool, text: str) -> tuple[Flag, ...]:
    """The convergence check (dest ``convergence_check``), on by default where `default`:
    ``--no-convergence-check`` turns it off there, ``--convergence-check`` on elsewhere
    (the other spelling is accepted, hidden, as are the former ``--no-check``,
    ``--no-check-convergence`` and ``--check-convergence``). `text` says what it does."""
    hidden = {"help": argparse.SUPPRESS, "default": argparse.SUPPRESS}
    dest = "convergence_check"
    on = ("--convergence-check", "--check-convergence")
    off = ("--no-convergence-check", "--no-check", "--no-check-convergence")
    if default:
        shown = option(
            off[0], action="store_false", dest=dest, help=f"skip the convergence check ({text})"
        )
        return (
            shown,
            option(*off[1:], action="store_false", dest=dest, **hidden),
            option(*on, action="store_true", dest=dest, **hidden),
        )
    shown = option(on[0], action="store_true", dest=dest, help=text)
    return (
        shown,
        option(*on[1:], action="store_true", dest=dest, **hidden),
        option(*off, action="store_false", dest=dest, **hidden),
    )


def add_flags(parser: Any, *flags: Flag) -> None:
    """Add `flags` to `parser` (an ``ArgumentParser`` or an argument group), in order."""
    for f in flags:
        parser.add_argument(*f.names, **f.settings)


def add_command(
    subparsers: argparse._SubParsersAction,
    name: str,
    run: Callable[[argparse.Namespace], int],
    description: str,
    *flags: Flag,
) -> argparse.ArgumentParser:
    """Add sub-command `name` (its one-line help from ``obturator.cli._COMMANDS``) that
    calls `run` with the parsed flags; returns its parser for further flags."""
    from . import _COMMANDS

    parser = subparsers.add_parser(name, help=_COMMANDS[name][1], description=description)
    add_flags(parser, *flags)
    parser.set_defaults(func=run)
    return parser


def command(
    name: str, run: Callable[[argparse.Namespace], int], description: str, *flags: Flag
) -> Callable[[argparse._SubParsersAction], argparse.ArgumentParser]:
    """The ``register(subparsers)`` of a module with one sub-command: it adds `name`,
    which takes `flags` and calls `run`, with :func:`add_command`."""

    def register(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
        return add_command(subparsers, name, run, description, *flags)

    register.__doc__ = f"Add the ``{name}`` sub-command."
    return register


JSON = switch("--json", "print one JSON object")
NO_PROGRESS = switch("--no-progress", "no progress bar")
CONFIG = option(
    "--config", metavar="FILE.toml", type=InputFile(), help="TOML settings (flags override)"
)
RTOL = option(
    "--rtol", metavar="X", type=quantity_of("rtol"), help="relative tolerance (default 1e-8)"
)
ATOL = option(
    "--atol", metavar="X", type=quantity_of("atol"), help="absolute tolerance (default 1e-10)"
)
T_MAX = option(
    "--t-max", metavar="S", type=quantity_of("t_max"), help="give up after this time [s]"
)
#: Horizon of the commands fitted to spin-rig data: later runs count as censored.
RIG_HORIZON = T_MAX.but(default="20", type=Quantity("s", Range(0.0, 1e4, True, False), "20 s"))
TORQUE_MODEL = option(
    "--torque-model",
    choices=TORQUE_MODELS,
    default=None,
    help="sliding-friction model: thesis (Eqs. 56-61, Appendix A; the default) or exact "
    "Coulomb contacts",
)
CASE = option("--case", choices=CASE_NAMES, default=None, help="Table 1 column")
SPIN_MODE = option(
    "--spin-mode",
    choices=SPIN_MODES,
    default=None,
    help="projectile spin: constant (driven rig, the default), free (axial angular momentum "
    "conserved) or thesis-energy (Appendix A's energy form)",
)
FRICTION_FAMILY = option("--friction-family", choices=FRICTION_FAMILIES, default=None)
SPEED_LAW = option("--speed-law", choices=SPEED_LAWS, default=None)
#: Measured spin-rig runs (the ``calibrate`` CSV format); thesis Appendix B by default.
RIG_DATA = option("--data", metavar="FILE.csv", type=InputFile(example="runs.csv"))
SEED_FLAG = option(
    "--seed",
    metavar="S",
    default="0",
    type=SEED,
    help="random seed (default 0; the same seed gives the same bits)",
)
#: Level of a confidence interval.
CONFIDENCE = option(
    "--confidence",
    metavar="C",
    default="0.95",
    type=Quantity("", Range(0.0, 1.0, True, True), "0.9"),
    help="confidence level of the intervals (default 0.95)",
)
#: An uncertain input, repeatable.
VARY = option(
    "--vary",
    action="append",
    metavar="NAME=KIND:ARGS",
    type=Text(example="mu_s=uniform:0.3,0.4"),
    help="uncertain input",
)
OUT_NETCDF = option(
    "--out", metavar="FILE.nc", type=OutputFile(), help="NetCDF output (and resume store)"
)
CSV = option(
    "--csv", metavar="FILE.csv", type=OutputFile(example="out.csv"), help="also write a CSV table"
)
#: A figure file (one spelling for every command; ``--plot`` is its former name).
FIGURE = option("--figure", metavar="FILE.png", help="write a figure")
PLOT = FIGURE


def figure_flags(example: str, text: str) -> tuple[Flag, Flag]:
    """``--figure FILE`` (a format matplotlib writes) saying what it draws, and its
    former spelling ``--plot`` as a hidden alias."""
    figure = FIGURE.but(type=OutputFile(figure=True, example=example), help=text)
    return (figure, alias(figure, "--plot"))


RESTART = switch("--restart", "discard partial results of a different study")


def execution_flags() -> tuple[Flag, ...]:
    """Workers, Dask scheduler, chunk size, restart, progress (every study that runs on
    a :class:`obturator.runs.Runner`)."""
    from ..sweeps.grid import MAX_POINTS  # not at import: start-up time

    return (
        count(
            "--workers", 1, MAX_WORKERS, "local worker processes (default: all CPUs; 1: in-process)"
        ),
        option(
            "--scheduler",
            metavar="ADDRESS",
            type=SchedulerAddress(example="tcp://127.0.0.1:1"),
            help="dask.distributed scheduler, e.g. tcp://host:8786",
        ),
        count("--chunk-size", 1, MAX_POINTS, "points per task (default: automatic)"),
        RESTART,
        NO_PROGRESS,
    )


def study_flags() -> tuple[Flag, ...]:
    """Flags common to ``sweep`` and ``montecarlo``: case, models, solver, execution."""
    return (
        CASE.but(help="Table 1 column (default spin-rig)"),
        TORQUE_MODEL,
        SPIN_MODE,
        CONFIG.but(help="settings (schema in obturator.io; flags win)"),
        RTOL,
        ATOL.but(help="absolute tolerance (default rtol/100, or 1e-10)"),
        quantity_option(
            "--tcr-rtol",
            "",
            Range(0.0, 1.0, True, True),
            "1e-4",
            "set the tolerances for this relative t_cr accuracy (measured tables in "
            "obturator.solve: with the default method auto >= 1.6e-8, its default rtol 1e-8 "
            "within 1.9e-7 of the width-free limit over 40-1000 rad/s; with --method "
            "regularised and the others >= 4.5e-7, set by the rig's long near-stick runs: "
            "the default rtol 1e-8 gives <= 3e-7 above 100 rad/s, <= 1.6e-3 below)",
        ),
        option("--method", choices=METHODS, default=None, help="integrator"),
        option(
            "--friction-width",
            metavar="X",
            type=quantity_of("friction_width"),
            help="regularisation width / omega_p (default 1e-7)",
        ),
        FRICTION_FAMILY.but(help="regularisation family (default algebraic)"),
        T_MAX,
        *execution_flags(),
        JSON,
    )


def parameter_flags(*, grid: bool) -> tuple[Flag, ...]:
    """One flag per sweepable parameter (``obturator.params.SWEEP_PARAMS``): a grid
    axis (``sweep``) or a fixed value (``montecarlo``)."""
    flags = []
    for name, par in SWEEP_PARAMS.items():
        extra = " (flight only)" if par.flight_only else ""
        text = f"{par.long_name} [{par.unit}]{extra}"
        kind, metavar = (axis_of(name), "SPEC") if grid else (quantity_of(name), "X")
        flags.append(
            option(
                flag(name),
                dest=name,
                metavar=metavar,
                type=kind,
                help=text if grid else "fixed " + text,
            )
        )
    return tuple(flags)
