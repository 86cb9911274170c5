"""A study's table and its NetCDF file (obturator.sweeps.table).

The reference for the file written with netCDF4 directly is xarray's own writer:
the same results as a Dataset, written by :meth:`xarray.Dataset.to_netcdf`, and both
files read back by xarray must be identical, values, attributes and encodings.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from obturator.runs import Runner
from obturator.sweeps import (
    SweepSpec,
    monte_carlo,
    monte_carlo_summary,
    monte_carlo_table,
    write_netcdf,
)
from obturator.sweeps.export import grid_table
from obturator.sweeps.table import StudyTable, write_table_netcdf


def _sweep_table() -> StudyTable:
    spec = SweepSpec(
        "spin-rig", {"spin_rate": np.array([150.0, 300.0]), "mu_s": np.array([0.5, 0.55])}
    )
    t_cr = np.array([0.3, np.nan, 0.25, 0.27])
    status = np.array([1, 0, 1, 1], dtype=np.int8)
    route = np.array([0, 1, 2, 1], dtype=np.int8)
    return grid_table(spec, t_cr, status, route).with_attrs(note="", seed=3)


def _read_both(table: StudyTable, tmp_path) -> tuple[xr.Dataset, xr.Dataset]:
    ours, theirs = tmp_path / "ours.nc", tmp_path / "xarray.nc"
    write_netcdf(table, ours)
    write_netcdf(table.to_dataset(), theirs)  # a Dataset goes through xarray
    return xr.open_dataset(ours), xr.open_dataset(theirs)


def test_sweep_file_is_the_one_xarray_writes(tmp_path):
    table = _sweep_table()
    ours, theirs = _read_both(table, tmp_path)
    xr.testing.assert_identical(ours, theirs)
    xr.testing.assert_identical(ours, table.to_dataset())
    assert set(ours.coords) == {"spin_rate", "mu_s", *[n for n in table.coords]}
    for name in ours.variables:
        assert ours[name].dtype == theirs[name].dtype, name
        mine, ref = ours[name].encoding.get("_FillValue"), theirs[name].encoding.get("_FillValue")
        assert (mine is None) == (ref is None), name
        if ref is not None:
            assert np.isnan(mine) and np.isnan(ref), name
    assert np.isnan(ours["t_cr"].values[0, 1])  # NaN survives as a value, not as a fill
    # xarray refuses a bool attribute; the table writes it as 0/1 as the study's
    # solver settings are written (obturator.sweeps.export.common_attrs)
    write_netcdf(table.with_attrs(flag=True), tmp_path / "flag.nc")
    assert xr.open_dataset(tmp_path / "flag.nc").attrs["flag"] == 1


def test_monte_carlo_file_is_its_dataset(tmp_path):
    out = tmp_path / "mc.nc"
    ds = monte_carlo(
        "spin-rig",
        {"mu_s": "uniform:0.5,0.55"},
        samples=3,
        seed=1,
        fixed={"spin_rate": 300.0},
        check_convergence=False,
        runner=Runner(workers=1, progress=False, store=str(out)),
    )
    back = xr.open_dataset(out)
    for key in ("date_created", "history"):  # stamped on the file only
        assert key in back.attrs and key not in ds.attrs
        del back.attrs[key]
    xr.testing.assert_identical(back, ds)
    table = monte_carlo_table(
        "spin-rig", {"mu_s": "uniform:0.5,0.55"}, samples=3, seed=1,
        fixed={"spin_rate": 300.0}, check_convergence=False,
        runner=Runner(workers=1, progress=False),
    )  # fmt: skip
    xr.testing.assert_identical(table.to_dataset(), ds)
    assert monte_carlo_summary(table) == monte_carlo_summary(ds)


def test_table_refuses_what_it_cannot_write(tmp_path):
    text = StudyTable({"name": ("x", np.array(["a", "b"]), {})}, {})
    with pytest.raises(TypeError, match="name: only numeric"):
        write_table_netcdf(text, tmp_path / "a.nc")
    ragged = StudyTable({"a": ("x", np.zeros(2), {}), "b": ("x", np.zeros(3), {})}, {})
    with pytest.raises(ValueError, match="dimension 'x' has sizes 2 and 3"):
        write_table_netcdf(ragged, tmp_path / "b.nc")
    bad_attr = StudyTable({"a": ("x", np.zeros(2), {"when": object()})}, {})
    with pytest.raises(TypeError, match="a: attribute 'when' of type object"):
        write_table_netcdf(bad_attr, tmp_path / "c.nc")


@pytest.mark.parametrize(
    "command",
    [
        ["sweep", "--case", "spin-rig", "--spin-rate", "250,300", "--workers", "1"],
        ["montecarlo", "--case", "spin-rig", "--spin-rate", "300", "--samples", "2",
         "--seed", "1", "--vary", "mu_s=normal:0.5473,0.03", "--workers", "1"],
    ],
    ids=["sweep", "montecarlo"],
)  # fmt: skip
def test_command_line_writes_without_xarray(tmp_path, command):
    out = tmp_path / "s.nc"
    code = (
        "import sys\n"
        "from obturator.cli import main\n"
        f"rc = main({[*command, '--no-progress', '--out', str(out)]!r})\n"
        "print(rc, 'xarray' in sys.modules)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.split()[-2:] == ["0", "False"]
    ds = xr.open_dataset(out)
    assert ds["t_cr"].shape == (2,) and np.all(ds["status"].values == 1)
