"""The firing-envelope section of the reproduction report (``reproduce --envelope``).

Beyond the thesis, which answers for one flight condition: the Table 1 projectile's
t_cr over muzzle Mach x launch altitude with the trajectory-coupled and the constant
load (:func:`~obturator.envelope.envelope.run_envelope`), and the first-order and
total Sobol indices of t_cr in flight (:func:`~obturator.envelope.sensitivity.sobol_indices`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..reference import FLIGHT_SOBOL_RANGES
from ..report_section import ReportSection
from ..runs import Runner
from .envelope import EnvelopeSpec, envelope_summary, run_envelope
from .figures import plot_envelope, plot_sobol
from .model import INPUTS, FlightModel
from .sensitivity import sobol_indices
from .uncertain import parse_input_distribution, performance

__all__ = ["EnvelopeSection", "SOBOL_RANGES", "envelope_section"]

#: Input ranges of the report's flight Sobol study (as ``obturator sensitivity``).
SOBOL_RANGES = FLIGHT_SOBOL_RANGES


#: This study's section of the report.
EnvelopeSection = ReportSection


def envelope_section(
    out_dir: str | Path, *, quick: bool = False, runner: Runner | None = None
) -> EnvelopeSection:
    """Run the envelope map and the flight Sobol study; write their figures to `out_dir`.

    Full: Mach 1.5-4 (11) x 0-10 km (6), Sobol N = 256 (2,048 runs); quick: 4 x 3 and
    N = 16, constant load for the Sobol study. `runner`: where the runs go (default
    in this process).
    """
    out = Path(out_dir)
    runner = runner or Runner(workers=1)
    mach = np.linspace(1.5, 4.0, 4 if quick else 11)
    alt = np.linspace(0.0, 10_000.0, 3 if quick else 6)
    spec = EnvelopeSpec(tuple(mach), tuple(alt), (0.0,), model=FlightModel(), requirement=0.1)
    ds = run_envelope(spec, runner)
    plot_envelope(ds, out / "envelope_map.png")
    s = envelope_summary(ds)
    n = s["points"]
    rd_lo, rd_hi = 100 * s["min_relative_difference"], 100 * s["max_relative_difference"]
    at = s["max_relative_difference_at"]
    dists = dict(parse_input_distribution(t, tuple(INPUTS)) for t in SOBOL_RANGES)
    model = FlightModel(load="constant", check_convergence=not quick)
    sob = sobol_indices(performance(model, runner, "sobol"), dists, 16 if quick else 256)
    plot_sobol(sob, out / "sobol_flight.png")
    order = np.argsort(-sob["ST"].values)
    ranked = ", ".join(
        f"{sob['input'].values[i]} {sob['ST'].values[i]:.3f} ± {sob['ST_conf'].values[i]:.3f}"
        for i in order[:3]
    )
    paragraphs = (
        "The thesis answers whether the bore opens well inside 0.1 s for one condition "
        "(Mach 3, 0.099 MPa, mu_s = 0.35). Over muzzle Mach "
        f"{mach[0]:g}-{mach[-1]:g} and launch altitude 0-{alt[-1] / 1000:g} km ({n} points, "
        "Table 1 projectile and ball, US 1976 atmosphere, point-mass flight with drag and "
        f"spin decay) the bore opens within 0.1 s at {s['coupled_meets_requirement']} of "
        f"{n} points with the trajectory-coupled load ({s['constant_meets_requirement']} "
        "with the constant muzzle load); the coupled load delays the opening by "
        f"{rd_lo:.2f} % to {rd_hi:.2f} % (largest at M {at.get('mach', float('nan')):g}, "
        f"{at.get('altitude_m', float('nan')):g} m) and changes the verdict at "
        f"{s['verdict_changed_points']} points; {s['choked_at_opening_points']} points are "
        "choked (Fanno) at opening.",
        "Sobol indices of t_cr in flight (Mach 3, sea level, constant load; "
        f"{', '.join(SOBOL_RANGES)}): largest total indices {ranked}.",
    )
    figures = (
        ("envelope_map.png", "t_cr over the firing envelope, coupled vs constant load"),
        ("sobol_flight.png", "Sobol indices of t_cr in flight"),
    )
    return EnvelopeSection("Beyond the thesis: the firing envelope", paragraphs, figures)
