"""Robust design: t_cr against ball mass

``obturator optimize --pareto N``: the worst-case opening time over a set of flight
conditions against the ball's mass, one robust optimum per mass budget. Where every
budget gives the same design (the front collapsed to one point, because the mass budget
is not active) the figure says so.
"""

import subprocess
import sys
from pathlib import Path

FIGURE = "pareto.png"

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
subprocess.run(
    [
        sys.executable,
        "-m",
        "obturator",
        "optimize",
        "--mach",
        "1.5,2.5,4",
        "--altitude-m",
        "0,5000",
        "--popsize",
        "8",
        "--maxiter",
        "10",
        "--load",
        "constant",
        "--pareto",
        "4",
        "--out",
        str(out / "optimize.nc"),
        "--figure",
        str(out / FIGURE),
    ],
    check=True,
)
