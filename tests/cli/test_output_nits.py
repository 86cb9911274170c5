"""Console output a reader reads: columns that line up, no stray unit or sign."""

from __future__ import annotations

import re

import numpy as np
import xarray as xr

from obturator.cli.envelope import _print_envelope


def test_envelope_table_columns_line_up(capsys):
    mach, alt = np.array([1.5, 7 / 3, 4.0]), np.array([0.0, 5000.0, 10000.0])
    tc = np.array([[0.062623, 0.11045, 0.21027], [0.027128, 0.04781, 0.091016], [1e-2, 2e-2, 3e-2]])
    shape = (3, 3)
    ds = xr.Dataset(
        {
            "t_cr_coupled": (("mach", "altitude_m"), tc),
            "t_cr_constant": (("mach", "altitude_m"), tc * 0.98),
            "status_coupled": (("mach", "altitude_m"), np.ones(shape, int)),
            "status_constant": (("mach", "altitude_m"), np.ones(shape, int)),
            "choked_at_opening": (("mach", "altitude_m"), np.eye(3, dtype=bool)),
        },
        coords={"mach": mach, "altitude_m": alt},
    )
    _print_envelope(ds)
    lines = capsys.readouterr().out.splitlines()[1:]
    # every value cell ends in the same column as its altitude heading (flags after it)
    ends = [[m.end() for m in re.finditer(r"\)", line)] for line in lines[1:]]
    assert all(e == ends[0] for e in ends), lines
    head = [m.end() for m in re.finditer(r"\d+(?= )", lines[0])]
    assert head == ends[0], lines
    assert lines[2].split()[0] == "2.33"  # Mach to 3 digits
