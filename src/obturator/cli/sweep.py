"""``obturator sweep``: t_cr on a grid of parameters (parallel, resumable).

Usage::

    obturator sweep --case spin-rig|flight [--spin-rate SPEC] [--mu-s SPEC]
        [--theta0-deg SPEC] [--density SPEC] [--hole-radius SPEC] [--gap SPEC]
        [--mach SPEC] [--altitude-m SPEC] [--torque-model thesis|coulomb]
        [--spin-mode constant|free|thesis-energy] [--rtol X] [--atol X]
        [--method auto|radau|rosenbrock] [--t-max S] [--workers N]
        [--scheduler ADDRESS] [--chunk-size N] --out FILE.nc [--csv FILE.csv]
        [--no-csv] [--restart] [--no-progress] [--json]

A sweep SPEC is ``START:STOP:COUNT`` (COUNT evenly spaced values, both ends
included) or a comma list ``a,b,c``; a single value holds that parameter fixed
instead of adding a dimension. Values are SI (spin rate in rad/s, radii and gap
in m, density in kg/m^3, angles in degrees where the flag says ``-deg``).

The sweep writes NetCDF to ``--out``; a CSV table goes to ``--csv`` when
given, and otherwise automatically next to the NetCDF (same name, ``.csv``)
for sweeps of at most 10,000 points (``--no-csv`` turns that off). While it
runs, finished chunks are kept in ``FILE.nc.partial.jsonl``: re-running the
same command after an interruption computes only the missing points; a
different sweep with the same ``--out`` is refused unless ``--restart``.
"""

from __future__ import annotations

import argparse
import math
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..io import check_output_path
from ..params import SWEEP_PARAMS
from ..sweeps import SweepSpec, execute_sweep, parse_axis, sweep_summary
from . import _json
from ._args import (
    study_config,
    study_options,
    study_t_max,
    warn_far_from_data,
    warn_outside_data,
)
from ._flags import (
    CSV,
    OUT_NETCDF,
    SPEED_LAW,
    command,
    convergence_flags,
    parameter_flags,
    study_flags,
    switch,
)
from ._runner import runner_from_args

__all__ = ["register", "AUTO_CSV_MAX_POINTS"]

#: Sweeps up to this many points get a CSV next to the NetCDF automatically.
AUTO_CSV_MAX_POINTS = 10_000


def _run_sweep(args: argparse.Namespace) -> int:
    axes: dict[str, Any] = {}
    if args.csv is not None and args.no_csv:
        raise InputError(
            "--no-csv", "turns off the automatic CSV, and --csv asks for one: give one"
        )
    fixed: dict[str, float] = study_config(args, "sweep")
    for name in SWEEP_PARAMS:
        text = getattr(args, name)
        if text is None:
            continue
        values = parse_axis(text, name, SWEEP_PARAMS[name].unit)
        fixed.pop(name, None)  # the flag wins over the config
        if values.size == 1:
            fixed[name] = float(values[0])
        else:
            axes[name] = values
    spec = SweepSpec(
        args.case,
        axes,
        fixed,
        torque_model=args.torque_model,
        spin_mode=args.spin_mode,
        # the cases of a sweep share their spin bands' return maps (a solver option,
        # recorded in each point's route and in the study digest)
        options=replace(study_options(args), shared_maps=True),
        t_max=study_t_max(args),
        check_convergence=args.convergence_check,
        speed_law=args.speed_law,
        base=args.base,
    )
    warn_far_from_data(spec)
    runner = runner_from_args(args)
    check_output_path("out", args.out)
    csv_path = args.csv
    to_device = not Path(args.out).is_file() and Path(args.out).exists()  # e.g. /dev/null
    if csv_path is None and not (args.no_csv or to_device) and spec.n_points <= AUTO_CSV_MAX_POINTS:
        csv_path = str(Path(args.out).with_suffix(".csv"))
    check_output_path("csv", csv_path)
    t0 = time.perf_counter()
    run = execute_sweep(spec, runner, csv=csv_path)
    wall = time.perf_counter() - t0
    summ = sweep_summary(run.table)
    rate = run.n_computed / run.elapsed_s if run.elapsed_s > 0 else math.inf
    if args.json:
        print(
            _json.dumps(
                {
                    **summ,
                    "out": args.out,
                    "csv": csv_path,
                    "n_computed": run.n_computed,
                    "n_resumed": run.n_resumed,
                    "workers": run.workers,
                    "backend": run.backend,
                    "compute_s": run.elapsed_s,
                    "wall_s": wall,
                    "points_per_s": rate,
                    "settings": spec.identity(),  # every input used, and the version
                }
            )
        )
        return 0
    dims = ", ".join(f"{d} x{n}" for d, n in zip(spec.dims, spec.shape, strict=True))
    where = (
        "dask"
        if run.backend != "local"
        else f"{run.workers} worker" + ("s" if run.workers != 1 else "")
    )
    resumed = f", {run.n_resumed} resumed" if run.n_resumed else ""
    if summ["t_cr_min_s"] is None:
        trange = "no point opened"
    else:
        at = ", ".join(f"{k}={v:g}" for k, v in summ["argmin"].items())
        trange = f"t_cr {summ['t_cr_min_s']:.6g}..{summ['t_cr_max_s']:.6g} s" + (
            f" (min at {at})" if at else ""
        )
    files = args.out + (f", {csv_path}" if csv_path else "")
    print(
        f"sweep {spec.case}: {summ['n_points']} points ({dims or 'single point'}{resumed}) "
        f"in {run.elapsed_s:.3g} s on {where} ({rate:.3g} points/s); "
        f"{summ['n_opened'] + summ['n_unconverged']} opened"
        + (f" ({summ['n_unconverged']} not converged)" if spec.check_convergence else "")
        + f", {summ['n_not_opened']} not opened by t_max, "
        f"{summ['n_failed'] + summ['n_invalid']} failed; {trange}; wrote {files}"
    )
    warn_outside_data(run.table)
    return 0


register = command(
    "sweep",
    _run_sweep,
    "Evaluate the opening time t_cr on the Cartesian grid of the given parameters. "
    "SPEC is START:STOP:COUNT (both ends included) or a list a,b,c; a single value "
    "fixes the parameter. Values take units (e.g. --spin-rate '1000:6000:11 rpm'); a "
    "number without a unit is in the unit shown.",
    *parameter_flags(grid=True),
    *study_flags(),
    OUT_NETCDF.but(required=True, help="NetCDF output"),
    SPEED_LAW.but(
        help="slip-speed law of the rig friction (sweep --speed-ratio, --slip-speed; "
        "default constant, or the config's)",
    ),
    *convergence_flags(
        False,
        "re-run each opened point with tolerances / 10, friction width / 10 and another "
        "regularisation family and mark points whose t_cr moves by more than 1e-3 "
        "(status 4; 4x the cost)",
    ),
    CSV,
    switch(
        "--no-csv",
        f"no automatic CSV next to the NetCDF (written for <= {AUTO_CSV_MAX_POINTS} points)",
    ),
)
