"""Study results as files: the study's table (:mod:`.table`), NetCDF (CF attributes) and a flat CSV.

Both files are written atomically; the resume store is removed only after
both are in place (:func:`write_outputs`), so an interruption while writing
loses nothing.
"""

from __future__ import annotations

import math
import os
from dataclasses import asdict
from datetime import UTC, datetime
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._provenance import command_line, package_version
from ..errors import InputError
from ..params import SWEEP_PARAMS
from ..reference import TABLE1
from ..runs.store import atomic_write_text
from ..solve.plan import ROUTES
from ..status import FLAGS
from .points import POINT_STATUSES
from .spec import SweepSpec
from .table import StudyTable, write_table_netcdf

if TYPE_CHECKING:  # pragma: no cover
    import xarray

    from ..runs import Runner

__all__ = [
    "T_CR_ATTRS",
    "check_distinct_outputs",
    "common_attrs",
    "coord_attrs",
    "grid_table",
    "route_attrs",
    "status_attrs",
    "write_csv",
    "write_netcdf",
    "write_outputs",
]


def _attr(value: Any) -> Any:
    """NetCDF-safe attribute value."""
    if value is None:
        return "none"
    if isinstance(value, bool):
        return int(value)
    return value


def check_distinct_outputs(store: Any, csv: Any) -> None:
    """Refuse a CSV path that is also the NetCDF output."""
    if store is not None and csv is not None:
        if Path(store).resolve() == Path(csv).resolve():
            raise InputError("csv", f"{str(csv)!r} is also the NetCDF output; choose another name")


def common_attrs(spec: SweepSpec) -> dict[str, Any]:
    """Dataset attributes of every study: case, models, solver, version, CF conventions."""
    attrs: dict[str, Any] = {
        "case": spec.case,
        "torque_model": spec.torque_model,
        "spin_mode": spec.spin_mode,
        "normal_load": spec.weight_model,
        "t_max_s": spec.t_max if spec.t_max is not None else spec.build_case({}).t_max,
        "obturator_version": package_version(),
        # CF / ACDD global attributes (date_created and history are added when written)
        "Conventions": "CF-1.10",
        "source": f"obturator {package_version()} (ball obturator opening model, Bloomer 1980)",
    }
    for key, value in asdict(spec.options).items():
        attrs[f"solver_{key}"] = _attr(value)
    if spec.case == "flight" and spec.resolved().get("altitude_m") is None:
        attrs["p1_Pa"] = TABLE1["p1"]
    return attrs


def coord_attrs(name: str) -> dict[str, str]:
    """CF attributes of a parameter coordinate (units, long_name)."""
    p = SWEEP_PARAMS[name]
    return {"units": p.unit, "long_name": p.long_name}


def status_attrs() -> dict[str, Any]:
    """CF flag attributes of the ``status`` variable (:data:`POINT_STATUSES`)."""
    return {
        "long_name": "integration outcome",
        "flag_values": np.array(POINT_STATUSES, dtype=np.int8),
        "flag_meanings": " ".join(FLAGS[s] for s in POINT_STATUSES),
    }


def route_attrs() -> dict[str, Any]:
    """CF flag attributes of the ``route`` variable (:data:`~obturator.solve.plan.ROUTES`)."""
    return {
        "long_name": "how t_cr was computed (obturator.solve.plan)",
        "flag_values": np.arange(len(ROUTES), dtype=np.int8),
        "flag_meanings": " ".join(r.replace(", ", "+").replace(" ", "_") for r in ROUTES),
    }


T_CR_ATTRS = {
    "units": "s",
    "long_name": "opening time t_cr (theta reaches theta_cr = beta_s)",
    "comment": "NaN where the bore did not open by t_max or the point failed; see status",
}


def grid_table(
    spec: SweepSpec, t_cr: np.ndarray, status: np.ndarray, route: np.ndarray
) -> StudyTable:
    """The sweep's results: t_cr, status and route over the swept dimensions, with the
    swept parameters as dimension coordinates and the fixed ones as scalar coordinates
    (:meth:`~.table.StudyTable.to_dataset` gives the Dataset)."""
    dims = spec.dims
    coords: dict[str, Any] = {d: (d, spec.axes[d], coord_attrs(d)) for d in dims}
    for name, value in spec.resolved().items():
        if name not in dims and value is not None:
            coords[name] = ((), value, coord_attrs(name))
    data = {
        "t_cr": (dims, t_cr.reshape(spec.shape), T_CR_ATTRS),
        "status": (dims, status.reshape(spec.shape), status_attrs()),
        "route": (dims, route.reshape(spec.shape), route_attrs()),
    }
    attrs = {"title": f"obturator sweep of t_cr over {', '.join(dims) or 'one point'}"}
    attrs.update(common_attrs(spec))
    attrs["spec_hash"] = spec.digest()
    return StudyTable(data, coords, attrs)


def write_netcdf(ds: xarray.Dataset | StudyTable, path: str | os.PathLike[str]) -> None:
    """Write a Dataset or a study's :class:`~.table.StudyTable` to NetCDF-4, atomically
    (a temporary file renamed into place, never over a device node).

    A table is written with netCDF4 directly (:func:`~.table.write_table_netcdf`: the
    same file, without xarray's imports), a Dataset by xarray.
    """
    from ..files import publish, temporary_for

    out = Path(path)
    tmp = temporary_for(out)
    try:
        if isinstance(ds, StudyTable):
            write_table_netcdf(ds, tmp)
        else:
            ds.to_netcdf(tmp, engine="netcdf4")
        publish(tmp, out)
    finally:
        tmp.unlink(missing_ok=True)


def write_csv(ds: xarray.Dataset | StudyTable, path: str | os.PathLike[str]) -> None:
    """Write a sweep or Monte Carlo study as a flat CSV table (units in the header), atomically.

    Leading ``#`` lines carry everything that is not a column: the fixed
    parameters (scalar coordinates with units), the case, models, solver
    settings, package version and the command line (the dataset's attributes),
    so a CSV alone says what it was computed with. Then one row per grid point
    (C order) or sample: the swept (or sampled) parameters, ``t_cr [s]`` (empty
    where not opened), ``status`` and ``route`` (by name: :mod:`obturator.solve.plan`).
    Written to a temporary file and renamed.
    """
    table = StudyTable.of(ds)
    t = table.values("t_cr").reshape(-1)
    s = table.values("status").reshape(-1)
    r = table.values("route").reshape(-1)
    if "sample" in table.dims("t_cr"):
        cols = [v for v in table.data if table.dims(v) == ("sample",) and v in SWEEP_PARAMS]
        columns = [table.values(c) for c in cols]
    else:
        cols = list(table.dims("t_cr"))
        mesh = np.meshgrid(*[table.values(c) for c in cols], indexing="ij")
        columns = [m.reshape(-1) for m in mesh]
    lines = []
    for name, (_, value, attrs) in table.coords.items():
        if np.ndim(value) == 0:
            unit = attrs.get("units", "")
            lines.append(f"# {name} = {np.asarray(value).item()!r} {unit}".rstrip())
    for key, value in table.attrs.items():
        if np.ndim(value) == 0:
            lines.append(f"# {key} = {' '.join(str(value).split())}")
    header = [f"{c} [{SWEEP_PARAMS[c].unit}]" for c in cols] + ["t_cr [s]", "status", "route"]
    lines.append(",".join(header))
    for k in range(t.size):
        cells = [f"{col[k]:.12g}" for col in columns]
        cells.append(f"{t[k]:.12g}" if math.isfinite(t[k]) else "")
        cells.append(str(int(s[k])))
        cells.append(ROUTES[int(r[k])])
        lines.append(",".join(cells))
    atomic_write_text(Path(path), "\n".join(lines) + "\n")


def write_outputs(table: StudyTable, runner: Runner, csv: str | os.PathLike[str] | None) -> None:
    """NetCDF (the runner's store path), then CSV, each atomic; the resume store goes only
    after both are in place (:meth:`~obturator.runs.Runner.write_outputs`: a full disk is
    one error that keeps the finished points).

    The files get the CF ``date_created`` and ``history`` (the command line); the
    returned dataset does not, so two runs of one study compare identical.
    """
    now = datetime.now(UTC).isoformat(timespec="seconds")
    table = table.with_attrs(date_created=now, history=f"{now}: {command_line()}")
    runner.write_outputs(
        [(runner.store, partial(write_netcdf, table)), (csv, partial(write_csv, table))]
    )
