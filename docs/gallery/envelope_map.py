"""The firing envelope

``obturator envelope``: t_cr of the trajectory-coupled opening over muzzle Mach and
launch altitude, with the 0.1 s requirement; hatched where the bore is choked (Fanno) at
opening.
"""

import subprocess
import sys
from pathlib import Path

FIGURE = "envelope_map.png"

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
subprocess.run(
    [
        sys.executable,
        "-m",
        "obturator",
        "envelope",
        "--mach",
        "1.5:4:11",
        "--altitude-m",
        "0:10000:6",
        "--out",
        str(out / "envelope.nc"),
        "--figure",
        str(out / FIGURE),
    ],
    check=True,
)  # about a minute
