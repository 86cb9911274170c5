"""theta(t) on the spin rig at 200 rad/s

The nutation of Table 1's ball on the spin rig at 200 rad/s with the thesis's
calibrated mu_s = 0.5473 (chapter IV): released at theta_0 = 87.25 deg, it sticks and
slips, then nutates down to the opening angle theta_cr = beta_s = 36.69 deg.
The same run from the command line: ``obturator simulate --case spin-rig --spin-rate 200
--mu-s 0.5473``.
"""

import sys
from pathlib import Path

from obturator import rig_case, simulate
from obturator.plotting import save, theta_history_figure

FIGURE = "theta_rig_200.png"
RUN_IN_DOCS = True  # one run of about a second

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
res = simulate(rig_case(spin_rate=200.0, mu_s=0.5473))
save(theta_history_figure(res), out / FIGURE)
