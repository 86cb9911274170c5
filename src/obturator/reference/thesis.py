"""Numbers printed in J. W. Bloomer II, *Ball Obturation of a Spin Stabilized
Tubular Projectile*, M.S. thesis, Naval Postgraduate School, 1980.

Every thesis number the code uses as an *input* lives here, SI units, with
where it is printed. The values the reproduction report *checks* are a data
file beside this module (``printed_values.toml``, :mod:`.printed`, read by
:mod:`obturator.thesis.rows`); the Appendix B runs are
``bloomer1980_appendix_b.csv`` (read by :mod:`obturator.calibration.data`).

>>> TABLE1["theta0_deg"], THESIS_MU_S
(87.25, 0.5473)
"""

from __future__ import annotations

from .printed import CHAPTER4_SUMS

__all__ = [
    "FLIGHT_SOBOL_RANGES",
    "TABLE1",
    "THESIS_MU_S",
    "COUETTE_P52",
    "CAPTION_SHEAR_CONSTANT",
    "EQ95_COEFFICIENT",
    "EQ95_WEIGHT",
    "THESIS_FIT_MIN_SPIN",
    "PRINTED_SUMS_OMITTED_RUNS",
    "THESIS_REYNOLDS",
    "THESIS_REYNOLDS_MACH",
    "RIG_TEETH",
]

#: Table 1 ("common values"), SI units; the rig column ("gravitational model")
#: and the flight column ("aerodynamic model").
TABLE1: dict[str, float] = {
    "theta0_deg": 87.25,
    "density": 7669.6,
    "ball_radius": 7.899e-3,
    "hole_radius": 4.72e-3,
    "bore_radius": 4.72e-3,
    "viscosity": 1.917e-5,
    "mu_s": 0.35,
    "gap": 5.08e-5,
    "shear_constant": 12.38e-9,
    # flight (aerodynamic model)
    "projectile_radius": 9.96e-3,
    "projectile_length": 76.2e-3,
    "projectile_mass": 0.141,
    "projectile_inertia": 8.58e-6,
    "mach": 3.0,
    "gamma": 1.4,
    "p1": 0.099e6,
    "flight_spin_rate": 12042.0,
    # rig (gravitational model)
    "rig_weight": 0.07987,
    "rig_spin_rate": 200.0,
}

#: Sliding friction coefficient fitted to the rig runs in chapter IV [-] (printed once,
#: with the chapter's other results, in ``printed_values.toml``).
THESIS_MU_S: float = CHAPTER4_SUMS["mu_s"]

#: Inputs of the viscous-only runs of Figs. 9-10 (p. 52): R_s, r_s, h [m],
#: rho [kg/m^3], mu_f [Pa s], omega_p [rad/s].
COUETTE_P52: dict[str, float] = {
    "ball_radius": 7.62e-3,
    "hole_radius": 4.7625e-3,
    "gap": 0.0254e-3,
    "density": 7800.0,
    "viscosity": 1.92e-5,
    "spin_rate": 12042.77,
}

#: Shear constant printed in the caption of Fig. 9 [N m s] (Eq. 34 with the
#: p. 52 inputs gives 56 times less).
CAPTION_SHEAR_CONSTANT = 1.2e-6

#: Eq. (95): T2 = 3.03e-4 / mu_bar [s^2], the large-spin coefficient.
EQ95_COEFFICIENT = 3.03e-4
#: Weight used for Eq. (95) in chapter IV ("measured weight W = 0.0798 N") [N].
EQ95_WEIGHT = 0.0798

#: Lowest printed spin of the starred runs [rad/s] (chapter IV). The 676 Hz
#: run has f pi / 9 = 235.9685 < 235.97: filter on the printed column, on the
#: star, or with a threshold a little below this value.
THESIS_FIT_MIN_SPIN = 235.97

#: 1-based run numbers (order of Appendix B: left column group 1-36, right
#: 37-54) of the four starred runs that must be left out, with the printed
#: omega_p, to reproduce the printed least-squares sums of chapter IV.
PRINTED_SUMS_OMITTED_RUNS: tuple[int, ...] = (40, 41, 45, 51)

#: Reynolds number of the inlet flow assumed in chapter I.B.4.c, and the Mach
#: number it belongs to.
THESIS_REYNOLDS = 5.0e5
THESIS_REYNOLDS_MACH = 2.5

#: Teeth on the rig's bucket wheel (chapter III.C): omega_p = 2 pi f / 18.
RIG_TEETH = 18

#: Uniform ranges around Table 1 for the flight Sobol study (``obturator sensitivity``
#: and the report's envelope section): mu_s 0.35 +- 0.1, theta_0 87.25 +- 1 deg, gap
#: 5.08e-5 +- 1e-5 m, hole radius 4.72e-3 +- 1e-4 m, density 7500-7850 kg/m^3, muzzle
#: spin +-3 %.
FLIGHT_SOBOL_RANGES: tuple[str, ...] = (
    "mu_s=uniform:0.25,0.45",
    "theta0_deg=uniform:86.25,88.25",
    "gap=uniform:4.08e-5,6.08e-5",
    "hole_radius=uniform:4.62e-3,4.82e-3",
    "density=uniform:7500,7850",
    "spin_factor=uniform:0.97,1.03",
)
