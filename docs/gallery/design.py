"""Which rig runs decide between the mechanisms

``obturator design-experiment``: for each planned run, t_cr of each candidate mechanism
(velocity-strengthening friction, a release offset) over each setting the rig can change,
with 95 % predictive bands, drawn through that run's own setting; the planned value is
marked, and the separation in replicate SDs is written on each panel. See

"""

import sys
from pathlib import Path

from obturator import design_experiment
from obturator.design.plotting import save_design_figure

FIGURE = "design.png"

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
result = design_experiment()  # about 30 s on 2 cores (13,240 exact solves)
save_design_figure(result, out / FIGURE)
