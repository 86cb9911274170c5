"""Write ``rig_runs_settings.csv``: a synthetic spin-rig campaign from the package's own
exact model (thesis friction law, mu_s = 0.55) plus 4 ms Gaussian noise (seed 7).

Run from the repository root: ``python examples/make_rig_runs_settings.py``. The runs
use the optional per-run columns that ``obturator validate`` reads; ``calibrate`` on the
file without its two intermediate-angle columns should recover mu_s = 0.55 within its
interval.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from obturator.calibration.rig_model import apply_run_settings, rig_model_case
from obturator.model.cases import table1_ball
from obturator.solve import opening_times

MU_S, NOISE_S, SEED = 0.55, 4e-3, 7
#: spin [rad/s], theta_0 [deg], hole radius [mm], density [kg/m^3], angle [deg] or None
RUNS = [
    (150, 87.2, 4.72, 7669.6, None), (200, 87.4, 4.72, 7669.6, 60),
    (200, 87.1, 4.72, 7669.6, None), (200, 87.3, 4.72, 7669.6, None),
    (300, 87.1, 4.72, 7669.6, None), (300, 87.2, 4.72, 7669.6, None),
    (400, 87.3, 4.72, 7669.6, None), (150, 87.3, 3.75, 7669.6, None),
    (200, 87.2, 3.75, 7669.6, 60), (200, 87.3, 3.75, 7669.6, None),
    (300, 87.0, 3.75, 7669.6, None), (400, 87.4, 3.75, 7669.6, None),
    (200, 87.2, 4.72, 6000.0, 60), (300, 87.3, 4.72, 6000.0, None),
]  # fmt: skip
HEADER = """\
# Synthetic spin-rig campaign showing the optional per-run columns that
# `obturator validate` reads (units in the header; calibrate, which fits t_cr
# only, refuses the two intermediate-angle columns).
# Written by examples/make_rig_runs_settings.py with the package's exact model
# (thesis friction law, mu_s = 0.55) plus 4 ms Gaussian noise (seed 7): two hole
# radii (thesis Fig. 17: 4.72 and 3.75 mm), two ball densities (Fig. 16: 7669.6
# and 6000 kg/m^3), theta_0 as read per run, repeats at 200 and 300 rad/s, and for
# three runs the time from release to 60 deg (laser readout at an intermediate
# angle); ball_mass_g is the bored ball's mass (W = m g).
spin_rate_rad_s,t_cr_s,theta0_deg,hole_radius_mm,density_kg_m3,ball_mass_g,theta_measured_deg,t_measured_s
"""


def main() -> None:
    rng = np.random.default_rng(SEED)
    rows, cases, angles = [], [], []
    for w, theta0, hole_mm, rho, angle in RUNS:
        mass = table1_ball(density=rho, hole_radius=hole_mm * 1e-3).mass
        settings = {"theta0_deg": theta0, "hole_radius": hole_mm * 1e-3, "density": rho,
                    "ball_mass": mass}  # fmt: skip
        cases.append(apply_run_settings(rig_model_case, float(w), settings, mu_s=MU_S))
        if angle is not None:
            angles.append(apply_run_settings(
                rig_model_case, float(w), {**settings, "theta_cr_deg": angle}, mu_s=MU_S
            ))  # fmt: skip
        rows.append((w, theta0, hole_mm, rho, 1e3 * mass, angle))
    t_cr = opening_times(cases, strict=True)[0] + rng.normal(0.0, NOISE_S, len(cases))
    t_angle = iter(opening_times(angles, strict=True)[0] + rng.normal(0.0, NOISE_S, len(angles)))
    lines = []
    for (w, theta0, hole_mm, rho, mass_g, angle), t in zip(rows, t_cr, strict=True):
        extra = f"{angle},{next(t_angle):.4f}" if angle is not None else ","
        lines.append(f"{w},{t:.4f},{theta0},{hole_mm},{rho},{mass_g:.3f},{extra}")
    out = Path(__file__).with_name("rig_runs_settings.csv")
    out.write_text(HEADER + "\n".join(lines) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
