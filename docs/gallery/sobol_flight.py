"""Sobol indices in flight

``obturator sensitivity --case flight --load constant``: first-order and total Sobol
indices of t_cr with bootstrap 95 % intervals (SALib, Saltelli sampling). The figure
warns when an interval is wider than its index or an index leaves [0, 1] (too few
samples).
"""

import subprocess
import sys
from pathlib import Path

FIGURE = "sobol_flight.png"

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
subprocess.run(
    [
        sys.executable,
        "-m",
        "obturator",
        "sensitivity",
        "--case",
        "flight",
        "--load",
        "constant",
        "--out",
        str(out / "sobol.nc"),
        "--figure",
        str(out / FIGURE),
    ],
    check=True,
)
