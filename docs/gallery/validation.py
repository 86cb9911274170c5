"""Validation against all 54 runs

``obturator validate --figure validation.png``: the 54 runs of Appendix B, their replicate
scatter and each candidate mechanism's fit.
"""

import subprocess
import sys
from pathlib import Path

FIGURE = "validation.png"

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
subprocess.run(
    [
        sys.executable,
        "-m",
        "obturator",
        "validate",
        "--out",
        str(out / "validation"),
        "--figure",
        str(out / FIGURE),
    ],
    check=True,
)  # about 1.3 min
