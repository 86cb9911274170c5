"""``obturator reproduce``: every thesis figure, the checkable numbers and the calibration.

:func:`reproduce` runs the studies of :mod:`obturator.studies`, the
calibrations of :mod:`obturator.calibration`, writes one PNG per figure and a
report in Markdown and HTML. Both report files are rendered from the same
:class:`Row` list (no Markdown-to-HTML conversion, no extra dependency). The
table compares every number of the thesis's Table 1 and chapters II-IV that it prints (or
states qualitatively) with the computed value; ``difference (%)`` is
computed / thesis - 1. Rows whose thesis value was not printed show "—" and
name an independent check in the note.
"""

from __future__ import annotations

import base64
import html
import math
import platform
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

import numpy as np

from ..approx import large_spin_coefficients, mean_moment_arm
from ..calibration import exact as cal
from ..calibration.data import PRINTED_SUMS_OMITTED_RUNS, compare_with_thesis, load_thesis_data
from ..flow import (
    choking_mach,
    fanno_mach,
    normal_shock_mach,
    normal_shock_pressure_ratio,
    pressure_force,
)
from ..model.cases import TABLE1, rig_case, table1_ball
from ..solve import SolverOptions, opening_time
from . import studies
from .explorer import explorer_data

__all__ = ["Row", "ReproduceResult", "checkable_rows", "reproduce", "to_html", "to_markdown"]

_FIG9_CAPTION_S = studies.CAPTION_SHEAR_CONSTANT
#: Thesis Appendix A's hard-coded opening angle [rad].
_APPENDIX_A_THETA_CR = 0.6411
#: Weight used for Eq. (95) in chapter IV [N] ("measured weight W = 0.0798 N").
_EQ95_WEIGHT = 0.0798


@dataclass(frozen=True)
class Row:
    """One line of the comparison table.

    Attributes
    ----------
    quantity : str
    thesis : float, str or None
        Printed value (None: not printed; str: qualitative statement).
    computed : float or str
    unit : str
    where : str
        Where the thesis prints it.
    note : str
        Why a difference exists, or the independent check used.
    """

    quantity: str
    thesis: float | str | None
    computed: float | str
    unit: str = ""
    where: str = ""
    note: str = ""

    @property
    def difference(self) -> float | None:
        """100 (computed / thesis - 1) [%], or None when not numeric on both sides."""
        if isinstance(self.thesis, float | int) and isinstance(self.computed, float | int):
            if self.thesis != 0 and math.isfinite(self.computed):
                return 100.0 * (self.computed / self.thesis - 1.0)
        return None

    def cells(self) -> list[str]:
        """Table cells: quantity, thesis, computed, difference, unit, where, note."""
        d = self.difference
        return [
            self.quantity,
            _fmt(self.thesis),
            _fmt(self.computed),
            "—" if d is None else f"{d:+.2f}",
            self.unit,
            self.where,
            self.note,
        ]


def _fmt(x: float | str | None) -> str:
    if x is None:
        return "—"
    if isinstance(x, str):
        return x
    if not math.isfinite(x):
        return "NaN"
    return f"{x:.6g}"


HEADER = ["quantity", "thesis value", "computed", "difference (%)", "unit", "thesis", "note"]


@dataclass
class ReproduceResult:
    """What :func:`reproduce` wrote and computed.

    Attributes
    ----------
    out_dir : Path
    figures : list of Path
    report_md, report_html : Path
    rows : list of Row
    fit : ExactFit
    elapsed_s : float
        Wall time of the whole run [s].
    studies : dict
        The study Datasets by name.
    """

    out_dir: Path
    figures: list[Path]
    report_md: Path
    report_html: Path
    rows: list[Row]
    fit: Any
    elapsed_s: float
    studies: dict[str, Any] = field(repr=False)


# ---------------------------------------------------------------------------
# computing


def _settings(quick: bool) -> dict[str, Any]:
    if quick:
        return {
            "n_points": 301,
            "spins": np.linspace(100.0, 1000.0, 19),
            "exact_spins": np.linspace(100.0, 1000.0, 10),
            "fig43_spins": np.linspace(125.0, 700.0, 13),
            "min_grid": 20,
            "explorer": {
                "mu_s_values": (0.35, 0.5473),
                "theta0_deg_values": (87.25,),
                "spin_rates": np.geomspace(80.0, 700.0, 8),
            },
            "fit": {
                "bootstrap": 40,
                "table_resolution": 1.5,
                "table_max_points": 16,
                "table_verify": 3,
            },
        }
    return {
        "n_points": 1501,
        "spins": np.linspace(100.0, 1000.0, 91),
        "exact_spins": np.linspace(100.0, 1000.0, 46),
        "fig43_spins": np.linspace(125.0, 700.0, 47),
        "min_grid": 60,
        "explorer": {},
        "fit": {"bootstrap": 200},
    }


def _tasks(quick: bool, options: SolverOptions | None) -> list[tuple[str, str, Callable[[], Any]]]:
    s = _settings(quick)
    n = s["n_points"]
    mus = (0.1, 0.25, 0.35, 0.55)
    return [
        (
            "couette",
            "Figs. 9-10 (Couette)",
            lambda: studies.couette_study(n_points=n, options=options),
        ),
        (
            "couette_caption",
            "Fig. 9 with the caption's S",
            lambda: studies.couette_study((1.0,), base="caption", n_points=n, options=options),
        ),
        (
            "flight_rig",
            "Figs. 13-14",
            lambda: studies.flight_and_rig_study(n_points=n, options=options),
        ),
        ("fig15", "Fig. 15", lambda: studies.exact_vs_approximate(n_points=n, options=options)),
        ("density", "Fig. 16", lambda: studies.density_study(n_points=n, options=options)),
        ("hole", "Fig. 17", lambda: studies.hole_radius_study(n_points=n, options=options)),
        ("rig_spin", "Figs. 32-37", lambda: studies.rig_spin_study(n_points=n, options=options)),
        (
            "approx_mu",
            "Figs. 38, 39, 42 (Eq. 92)",
            # 0.35 first: Fig. 38 draws the first mu_s (Table 1)
            lambda: studies.opening_time_vs_spin(s["spins"], mu_s_values=(0.35, 0.1, 0.25, 0.55)),
        ),
        (
            "approx_theta0",
            "Figs. 40-41 (Eq. 92)",
            lambda: studies.opening_time_vs_spin(
                s["spins"], mu_s_values=(0.35,), theta0_deg_values=(75.0, 80.0, 85.0, 87.25)
            ),
        ),
        (
            "exact_mu",
            "Figs. 39, 42 (exact)",
            lambda: studies.opening_time_vs_spin(
                s["exact_spins"], mu_s_values=mus, method="exact", options=options
            ),
        ),
        (
            "fig43",
            "Fig. 43",
            lambda: studies.fig43_study(spin_rates=s["fig43_spins"], options=options),
        ),
        (
            "minimum",
            "t_cr minimum, mu_s = 0.5473",
            lambda: studies.opening_time_minimum(
                studies.THESIS_MU_S, n_grid=s["min_grid"], options=options
            ),
        ),
        (
            "minimum_table1",
            "t_cr minimum, mu_s = 0.35",
            lambda: studies.opening_time_minimum(0.35, n_grid=s["min_grid"], options=options),
        ),
        ("fit", "exact-model calibration", lambda: cal.fit_exact(options=options, **s["fit"])),
        (
            "explorer",
            "interactive explorer",
            lambda: explorer_data(options=options, **s["explorer"]),
        ),
        (
            "fit_converged",
            "calibration, tighter solver",
            lambda: cal.fit_exact(options=_tighter(options), bootstrap=0).mu_s,
        ),
        (
            "exact_vs_eq92",
            "exact vs Eq. 92 at 500, 700 rad/s",
            lambda: _exact_vs_eq92((500.0, 700.0), options),
        ),
    ]


def _tighter(options: SolverOptions | None) -> SolverOptions:
    """rtol, atol / 100 and friction width / 10: the convergence check of the fit."""
    o = (options or SolverOptions()).tighter(100.0)
    return replace(o, friction_width=o.friction_width / 10.0)


def _exact_vs_eq92(spins: tuple[float, ...], options: SolverOptions | None) -> dict[float, tuple]:
    out = {}
    for w in spins:
        ex = opening_time(rig_case(w, studies.THESIS_MU_S), options)
        ap = studies.opening_time_vs_spin([w], mu_s_values=(studies.THESIS_MU_S,))
        out[w] = (ex, float(ap["t_cr"].values.ravel()[0]))
    return out


# ---------------------------------------------------------------------------
# the table


def checkable_rows(res: dict[str, Any]) -> list[Row]:
    """The comparison table from the computed studies (see :func:`reproduce`)."""
    ball = table1_ball()
    rows: list[Row] = [
        Row(
            "C (axial inertia)",
            3.125e-7,
            ball.axial_inertia,
            "kg m^2",
            "Table 1",
            "thin-shell integral dI = (rho_r^2/2 + h^2/3) dm, exact 3.128e-7; the thesis's "
            "printed Eqs. 9d-11c are garbled",
        ),
        Row(
            "A (transverse inertia)",
            2.216e-7,
            ball.transverse_inertia,
            "kg m^2",
            "Table 1",
            "thin-shell integral, exact 2.219e-7",
        ),
        Row("lambda = C/A - 1", 0.41, ball.inertia_ratio, "1", "Table 1"),
        Row(
            "W (ball weight)",
            TABLE1["rig_weight"],
            ball.weight,
            "N",
            "Table 1 (measured)",
            "computed from rho, R_s, r_s and g = 9.80665 m/s^2",
        ),
        Row(
            "beta_s = asin(r_s/R_s)",
            36.734,
            math.degrees(ball.opening_angle),
            "deg",
            "ch. IV",
            "from the Table 1 radii; the thesis value implies r_s = 4.725 mm",
        ),
        Row(
            "beta_s in Appendix A code",
            _APPENDIX_A_THETA_CR,
            ball.opening_angle,
            "rad",
            "App. A (THCRIT)",
        ),
        Row(
            "S, Nakabayashi (Eq. 42)",
            12.38e-9,
            rig_case().torque.viscous.coefficient,
            "N m s",
            "Table 1",
        ),
        Row(
            "E(87.25 deg)",
            1.00458,
            mean_moment_arm(math.radians(87.25)) * math.pi / 2,
            "1",
            "ch. IV",
            "the same line prints (1.00448); E = 1.00452 (scipy ellipe)",
        ),
        Row(
            "E(theta_0) in Table 1",
            1.0063,
            mean_moment_arm(math.radians(87.25)) * math.pi / 2,
            "1",
            "Table 1",
            "1.0063 is E(86.67 deg), not E(87.25 deg)",
        ),
    ]
    # chapter IV least squares on the 24-run subset that reproduces the printed sums
    ls = cal.thesis_fit()
    labels = {
        "sum_t2": ("sum t^2", "s^2"),
        "sum_omega2": ("sum omega^2", "s^-2"),
        "sum_t_omega": ("sum t omega", "1"),
        "t2": ("T2 = sum t^2 / sum t omega", "s^2"),
        "sigma2": ("sigma^2", "s^-2"),
        "sigma_t2": ("sigma_T^2", "s^4"),
        "sigma_t": ("sigma_T", "s^2"),
        "relative_sigma": ("sigma_T / T2", "1"),
        "mu_bar": ("mu_bar = 3.03e-4 / T2 (Eq. 95)", "1"),
        "mean_arm": ("(2/pi) E(theta_0) (Eq. 78)", "1"),
        "mu_s": ("mu_s = mu_bar / ((2/pi) E)", "1"),
    }
    notes = {
        "sigma_t": "printed 1.97742e-5 is a transposed digit: sqrt(3.9181053e-10) = 1.97942e-5",
        "mean_arm": "thesis used E = 1.00458 (see above)",
        "relative_sigma": "printed to two digits",
        "mu_bar": "printed to two digits (3.03/8.66)",
    }
    omitted = ", ".join(str(r) for r in PRINTED_SUMS_OMITTED_RUNS)
    for c in compare_with_thesis(ls):
        name, unit = labels[c.name]
        rows.append(
            Row(
                f"{name} [24 runs]",
                c.printed,
                c.computed,
                unit,
                "ch. IV",
                notes.get(c.name, f"starred runs without {omitted}, printed omega_p"),
            )
        )
    all_star = cal.thesis_fit(subset="starred")
    rows += [
        Row(
            "sum t^2 [all 28 starred runs]",
            2.1046884,
            all_star.sum_t2,
            "s^2",
            "ch. IV",
            f"the printed sums leave out starred runs {omitted}",
        ),
        Row("T2 [all 28 starred runs, f pi/9]", 8.6603508e-4, all_star.t2, "s^2", "ch. IV"),
        Row("mu_s [all 28 starred runs]", 0.5473, all_star.mu_s, "1", "ch. IV"),
        Row(
            "T2, direct fit t = T2 omega [24 runs]",
            8.6603508e-4,
            ls.t2_direct,
            "s^2",
            "ch. IV",
            "thesis T2 = sum t^2/sum t omega fits omega = t/T2 (residuals in "
            "omega); the direct fit has residuals in t",
        ),
        Row("mu_s, direct fit [24 runs]", 0.5473, ls.mu_s_direct, "1", "ch. IV"),
    ]
    # Eqs. 93-95 with the chapter's W = 0.0798 N and the model's beta_s
    m_per_mu = _EQ95_WEIGHT * ball.radius
    lsc = large_spin_coefficients(
        transverse_inertia=ball.transverse_inertia,
        inertia_ratio=ball.inertia_ratio,
        moment=m_per_mu,
        theta0=math.radians(87.25),
        theta_cr=ball.opening_angle,
    )
    rows += [
        Row(
            "M / mu_bar = W R_s",
            6.34e-4,
            m_per_mu,
            "N m",
            "ch. IV",
            "0.0798 N x 7.899 mm = 6.303e-4; the printed T1, T2 follow from 6.303e-4",
        ),
        Row("T1 / mu_bar (Eq. 95)", 2.039e5, lsc.T1, "rad^3/s^2", "Eq. 95"),
        Row("T2 mu_bar (Eq. 95)", 3.03e-4, lsc.T2, "s^2", "Eq. 95"),
    ]
    # gas dynamics (chapter I.B.4; Eqs. 1, 3, 43)
    m1, g = TABLE1["mach"], TABLE1["gamma"]
    rh = 2 * g * m1**2 / (g + 1) - (g - 1) / (g + 1)
    fp_check = math.pi * TABLE1["bore_radius"] ** 2 * TABLE1["p1"] * (rh - 1.0)
    rows += [
        Row(
            "normal shock P2/P1, M1 = 3",
            None,
            float(normal_shock_pressure_ratio(m1, g)),
            "1",
            "Eqs. 1, 3",
            f"not printed; Rankine-Hugoniot 2gM^2/(g+1)-(g-1)/(g+1) = {rh:.6g}",
        ),
        Row(
            "normal shock M2, M1 = 3",
            None,
            float(normal_shock_mach(m1, g)),
            "1",
            "Eq. 3",
            "not printed; tables: 0.4752",
        ),
        Row(
            "F_p = pi r_p^2 (P2 - P1)",
            None,
            float(pressure_force(m1, TABLE1["p1"], TABLE1["bore_radius"], g)),
            "N",
            "Eq. 43",
            f"not printed; by hand {fp_check:.5g} N",
        ),
        Row(
            "Fanno choking M, fL/D = 0.102",
            1.41,
            float(fanno_mach(0.102, g)),
            "1",
            "ch. I.B.4.c",
            "thesis read a table to two decimals",
        ),
        Row(
            "Fanno M after one f iteration",
            1.44,
            float(choking_mach(8.0, friction_factor=0.01275, iterations=1)),
            "1",
            "ch. I.B.4.c",
            "Re revised in proportion to M (5e5 at M = 2.5), smooth-pipe Colebrook f",
        ),
    ]
    # qualitative and dynamic results
    mn, mn35 = res["minimum"], res["minimum_table1"]
    data = load_thesis_data()
    k = int(np.argmin(data.opening_time))
    rows += [
        Row(
            "t_cr minimum location, Eq. 92 (mu_s = 0.5473)",
            150.0,
            float(mn["spin_rate_min"].sel(model="approx")),
            "rad/s",
            "ch. V",
            "Eq. 92 = T1/w^3 + T2 w (+ viscous term): minimum at (3 T1/T2)^(1/4)",
        ),
        Row(
            "t_cr minimum location, exact (mu_s = 0.5473)",
            150.0,
            float(mn["spin_rate_min"].sel(model="exact")),
            "rad/s",
            "ch. V",
            f"t_cr = {float(mn['t_cr_min'].sel(model='exact')):.4f} s; chapter IV's larger "
            "mu_s moves the minimum up; t_cr rises steeply below it "
            f"({float(mn['t_cr_exact'][0]):.1f} s at {float(mn['spin_rate'][0]):g} rad/s)",
        ),
        Row(
            "t_cr minimum location, exact (mu_s = 0.35)",
            150.0,
            float(mn35["spin_rate_min"].sel(model="exact")),
            "rad/s",
            "ch. V",
            f"Table 1 mu_s; t_cr = {float(mn35['t_cr_min'].sel(model='exact')):.4f} s",
        ),
        Row(
            "exact model opens at every spin 40-1000 rad/s (mu_s = 0.35)",
            "yes",
            "yes" if bool(np.all(np.isfinite(res["rig_spin"]["t_cr"].values))) else "no",
            "",
            "Figs. 32-37",
            "t_cr = "
            + ", ".join(f"{t:.3g} s" for t in res["rig_spin"]["t_cr"].values)
            + " at "
            + ", ".join(f"{w:g}" for w in res["rig_spin"]["spin_rate"].values)
            + " rad/s",
        ),
        Row(
            "fastest measured run",
            150.0,
            float(data.spin_rate[k]),
            "rad/s",
            "App. B",
            f"t_cr = {data.opening_time[k]:.4f} s; the thesis's 150 rad/s matches the data",
        ),
    ]
    fl = res["flight_rig"]
    t_fl = float(fl["t_cr"].sel(case="flight"))
    cou, cap = res["couette"], res["couette_caption"]
    th1 = float(cou["theta_end"].isel(scale=0))
    thc = float(cap["theta_end"].isel(scale=0))
    rows += [
        Row(
            "flight t_cr (Table 1, mu_s = 0.35)",
            "< 0.1 s",
            t_fl,
            "s",
            "ch. II.B",
            "pass" if t_fl < 0.1 else "FAIL",
        ),
        Row(
            "viscous only (Fig. 9) opens within 0.1 s",
            "no",
            "no" if not math.isfinite(float(cou["t_cr"].isel(scale=0))) else "yes",
            "",
            "Fig. 9",
            f"theta(0.1 s) = {th1:.2f} deg with Eq. 34 S",
        ),
        Row(
            "Fig. 9 shear constant S",
            _FIG9_CAPTION_S,
            float(cou.attrs["shear_constant_eq34"]),
            "N m s",
            "Fig. 9 caption",
            "Eq. 34 with the p. 52 inputs; the caption's S is 56x larger; with it theta(0.1 s) "
            f"= {thc:.2f} deg, still not open",
        ),
    ]
    fit = res["fit"]
    near = (data.spin_rate > 195.0) & (data.spin_rate < 205.0)
    t200 = opening_time(rig_case(200.0, studies.THESIS_MU_S))
    rows += [
        Row(
            "rig t_cr at 200 rad/s (mu_s = 0.5473)",
            float(np.mean(data.opening_time[near])),
            t200,
            "s",
            "App. B",
            f"thesis value = mean of the {int(near.sum())} runs at 198.97-200.36 rad/s "
            f"(range {data.opening_time[near].min():.4f}-{data.opening_time[near].max():.4f})",
        ),
        Row(
            "mu_s fitted with the exact model",
            0.5473,
            fit.mu_s,
            "1",
            "ch. IV",
            f"28 starred runs; +/- {fit.stderr['mu_s']:.3g}; the thesis fit the linearised "
            "large-spin line, which runs ~3.5 % below the exact t_cr",
        ),
    ]
    rows.append(
        Row(
            "mu_s fit change, rtol/100 and width/10",
            None,
            res["fit_converged"] - fit.mu_s,
            "1",
            "—",
            "convergence of the exact-model fit (tolerances / 100, friction width / 10)",
        )
    )
    for w, (ex, ap) in res["exact_vs_eq92"].items():
        rows.append(
            Row(
                f"Eq. 92 / exact t_cr - 1 at {w:g} rad/s",
                None,
                100.0 * (ap / ex - 1.0),
                "%",
                "ch. IV",
                f"exact {ex:.4f} s, Eq. 92 {ap:.4f} s (mu_s = 0.5473)",
            )
        )
    return rows


# ---------------------------------------------------------------------------
# figures


def _figures(res: dict[str, Any]) -> list[tuple[str, str, Callable[[], Any]]]:
    from .. import plotting as pl

    data = load_thesis_data()
    figs: list[tuple[str, str, Callable[[], Any]]] = [
        ("fig09_couette.png", "Fig. 9", lambda: pl.fig09_couette(res["couette"])),
        ("fig10_couette_scaled.png", "Fig. 10", lambda: pl.fig10_couette_scaled(res["couette"])),
        ("fig13_flight.png", "Fig. 13", lambda: pl.fig13_flight(res["flight_rig"])),
        ("fig14_rig.png", "Fig. 14", lambda: pl.fig14_rig(res["flight_rig"])),
        (
            "fig15_exact_vs_approx.png",
            "Fig. 15",
            lambda: pl.fig15_exact_vs_approximate(res["fig15"]),
        ),
        ("fig16_density.png", "Fig. 16", lambda: pl.fig16_density(res["density"])),
        ("fig17_hole_radius.png", "Fig. 17", lambda: pl.fig17_hole_radius(res["hole"])),
    ]
    for number, w in zip(range(32, 38), res["rig_spin"]["spin_rate"].values, strict=False):
        figs.append(
            (
                f"fig{number}_rig_{w:g}.png",
                f"Fig. {number}",
                lambda w=w: pl.fig32_37_rig_spin(res["rig_spin"], float(w)),
            )
        )
    am, at, ex = res["approx_mu"], res["approx_theta0"], res["exact_mu"]
    figs += [
        ("fig38_eq92_data.png", "Fig. 38", lambda: pl.fig38_eq92_data(am, data)),
        (
            "fig39_mu_sensitivity.png",
            "Fig. 39",
            lambda: pl.fig39_mu_sensitivity(am.sortby("mu_s"), ex),
        ),
        ("fig40_theta0_sensitivity.png", "Fig. 40", lambda: pl.fig40_theta0_sensitivity(at)),
        ("fig41_theta0_data.png", "Fig. 41", lambda: pl.fig41_theta0_data(at, data)),
        ("fig42_mu_data.png", "Fig. 42", lambda: pl.fig42_mu_data(am.sortby("mu_s"), data, ex)),
        ("fig43_least_squares.png", "Fig. 43", lambda: pl.fig43_least_squares(res["fig43"])),
        (
            "tcr_minimum.png",
            "t_cr minimum",
            lambda: pl.opening_time_minimum_figure(res["minimum"], data),
        ),
        (
            "calibration_residuals.png",
            "exact-model calibration",
            lambda: pl.calibration_residuals(res["fit"]),
        ),
    ]
    return figs


# ---------------------------------------------------------------------------
# rendering


def _versions() -> dict[str, str]:
    out = {"python": platform.python_version()}
    pkgs = ("obturator", "numpy", "scipy", "numba", "xarray", "matplotlib", "pint", "rich")
    for pkg in (*pkgs, "dask", "distributed", "netCDF4", "plotly"):
        try:
            out[pkg] = version(pkg)
        except PackageNotFoundError:  # pragma: no cover
            out[pkg] = "not installed"
    return out


def _provenance(command: str | None) -> list[str]:
    import os
    from datetime import UTC, datetime

    return [
        f"date: {datetime.now(UTC).isoformat(timespec='seconds')}",
        f"command: {command or 'obturator.report.reproduce() from Python'}",
        f"machine: {platform.platform()}, {platform.machine()}, {os.cpu_count()} CPUs",
    ]


def _solver_lines(options: SolverOptions) -> list[str]:
    return [
        f"method = {options.method}",
        f"rtol = {options.rtol:g}, atol = {options.atol:g} (rates in units of omega_p0)",
        f"friction regularisation width = {options.friction_width:g} omega_p0, "
        f"family = {options.friction_family} (magnitude only; the moment arm uses the "
        "true slip direction)",
        f"formulation = {options.formulation}",
        f"event location tolerance = {options.event_tol:g} s",
        "projectile spin held constant (driven rig; thesis gravity runs)",
    ]


def _context(
    rows: list[Row],
    res: dict[str, Any],
    figures: list[tuple[str, str]],
    options: SolverOptions,
    quick: bool,
    elapsed: float,
    command: str | None = None,
) -> dict[str, Any]:
    from .captions import figure_captions

    flagged = [r for r in rows if r.difference is not None and abs(r.difference) > 2.0]
    captions = figure_captions([n for n, _ in figures], res)
    return {
        "rows": rows,
        "flagged": flagged,
        "fit_text": res["fit"].report(),
        "figures": [(n, c, captions[n]) for n, c in figures],
        "versions": _versions(),
        "solver": _solver_lines(options),
        "provenance": _provenance(command),
        "mode": "quick (fewer points, smaller bootstrap)" if quick else "full",
        "elapsed": elapsed,
        "images": {},
        "explorer": "",
    }


def to_markdown(ctx: dict[str, Any]) -> str:
    """The report as Markdown (GitHub table syntax)."""

    def cell(s: str) -> str:
        return s.replace("|", "\\|")

    out = [
        "# obturator: reproduction of Bloomer (1980)",
        "",
        f"Mode: {ctx['mode']}; run time {ctx['elapsed']:.1f} s.",
        "",
        "## Checkable numbers (Table 1, chapters II-IV, Appendix B)",
        "",
        "| " + " | ".join(HEADER) + " |",
        "|" + "|".join("---" for _ in HEADER) + "|",
    ]
    out += ["| " + " | ".join(cell(c) for c in r.cells()) + " |" for r in ctx["rows"]]
    out += ["", f"Rows differing by more than 2 %: {len(ctx['flagged'])}.", ""]
    out += [f"- {r.quantity}: {r.difference:+.1f} % ({r.note})" for r in ctx["flagged"]]
    out += ["", "## Calibration", "", "```", ctx["fit_text"], "```", "", "## Figures", ""]
    out += [f"### {cap}\n\n![{cap}]({name})\n\n{text}\n" for name, cap, text in ctx["figures"]]
    out += ["## Provenance", ""]
    out += [f"- {s}" for s in ctx["provenance"]]
    out += ["", "## Versions", ""]
    out += [f"- {k}: {v}" for k, v in ctx["versions"].items()]
    out += ["", "## Solver settings", ""]
    out += [f"- {s}" for s in ctx["solver"]]
    return "\n".join(out) + "\n"


def to_html(ctx: dict[str, Any]) -> str:
    """The report as a self-contained HTML page (same content as :func:`to_markdown`)."""
    e = html.escape
    head = "".join(f"<th>{e(h)}</th>" for h in HEADER)
    body = "\n".join(
        "<tr>" + "".join(f"<td>{e(c)}</td>" for c in r.cells()) + "</tr>" for r in ctx["rows"]
    )
    flagged = "\n".join(
        f"<li>{e(r.quantity)}: {r.difference:+.1f} % ({e(r.note)})</li>" for r in ctx["flagged"]
    )

    def src(name: str) -> str:  # embedded, so the one file carries every figure
        data = ctx["images"].get(name)
        return f"data:image/png;base64,{data}" if data else e(name)

    figs = "\n".join(
        f'<figure><img src="{src(n)}" alt="{e(c)}" data-file="{e(n)}">'
        f"<figcaption><b>{e(c)}.</b> {e(t)}</figcaption></figure>"
        for n, c, t in ctx["figures"]
    )
    provenance = "".join(f"<li>{e(s)}</li>" for s in ctx["provenance"])
    versions = "".join(f"<li>{e(k)}: {e(v)}</li>" for k, v in ctx["versions"].items())
    solver = "".join(f"<li>{e(s)}</li>" for s in ctx["solver"])
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>obturator: reproduction of Bloomer (1980)</title>
<style>
body {{ font-family: sans-serif; margin: 2em; }}
table {{ border-collapse: collapse; font-size: 0.85em; }}
td, th {{ border: 1px solid #aaa; padding: 2px 6px; vertical-align: top; }}
th {{ background: #eee; }}
figure {{ display: inline-block; margin: 0.5em; max-width: 580px; vertical-align: top; }}
figcaption {{ font-size: 0.85em; }}
img {{ max-width: 560px; }}
pre {{ background: #f6f6f6; padding: 0.5em; font-size: 0.85em; }}
</style></head><body>
<h1>obturator: reproduction of Bloomer (1980)</h1>
<p>Mode: {e(ctx["mode"])}; run time {ctx["elapsed"]:.1f} s.</p>
<h2>Checkable numbers (Table 1, chapters II-IV, Appendix B)</h2>
<table><thead><tr>{head}</tr></thead><tbody>
{body}
</tbody></table>
<p>Rows differing by more than 2 %: {len(ctx["flagged"])}.</p>
<ul>
{flagged}
</ul>
<h2>Calibration</h2>
<pre>{e(ctx["fit_text"])}</pre>
<h2>Figures</h2>
{figs}
<h2>Interactive explorer</h2>
<p>t_cr of the exact rig model for several mu_s and theta_0 with the 54 measured runs
(hover a run for its number, spin, measured and model t_cr), and theta(t) of any run.</p>
{ctx["explorer"]}
<h2>Provenance</h2><ul>{provenance}</ul>
<h2>Versions</h2><ul>{versions}</ul>
<h2>Solver settings</h2><ul>{solver}</ul>
</body></html>
"""


# ---------------------------------------------------------------------------
# driver


@contextmanager
def _progress(enabled: bool, total: int) -> Iterator[Callable[[str, Callable[[], Any]], Any]]:
    """Yield ``run(label, fn)``: calls fn() under a rich progress bar on stderr."""
    if not enabled:
        yield lambda label, fn: fn()
        return
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    with Progress(
        TextColumn("{task.description:<36}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        console=Console(stderr=True),
    ) as bar:
        task = bar.add_task("reproduce", total=total)

        def run(label: str, fn: Callable[[], Any]) -> Any:
            bar.update(task, description=label)
            value = fn()
            bar.advance(task)
            return value

        yield run


def reproduce(
    out_dir: str | Path,
    *,
    quick: bool = False,
    progress: bool = True,
    options: SolverOptions | None = None,
    command: str | None = None,
) -> ReproduceResult:
    """Run every study, write the figures (PNG) and report.md / report.html into `out_dir`.

    Parameters
    ----------
    out_dir : str or Path
        Created if missing.
    quick : bool
        Fewer points, a smaller bootstrap (for tests and a first look).
    progress : bool
        Show a rich progress bar on stderr.
    options : SolverOptions, optional
        Solver settings for every exact run (default :class:`SolverOptions`).
    command : str, optional
        The command line, recorded in the report's provenance.

    Returns
    -------
    ReproduceResult
        ``report.html`` is self-contained: figures embedded as data URIs and the
        interactive explorer with plotly.js inline.
    """
    t0 = time.perf_counter()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    opts = options or SolverOptions()
    tasks = _tasks(quick, options)
    res: dict[str, Any] = {}
    paths: list[Path] = []
    from ..plotting import save

    with _progress(progress, len(tasks) + 1) as run:
        for key, label, fn in tasks:
            res[key] = run(label, fn)
        figs = _figures(res)
        run("figures", lambda: paths.extend(save(make(), out / name) for name, _, make in figs))
    from .explorer import explorer_html

    rows = checkable_rows(res)
    elapsed = time.perf_counter() - t0
    ctx = _context(rows, res, [(n, c) for n, c, _ in figs], opts, quick, elapsed, command)
    ctx["images"] = {p.name: base64.b64encode(p.read_bytes()).decode("ascii") for p in paths}
    ctx["explorer"] = explorer_html(res["explorer"])
    md, hp = out / "report.md", out / "report.html"
    md.write_text(to_markdown(ctx), encoding="utf-8")
    hp.write_text(to_html(ctx), encoding="utf-8")
    return ReproduceResult(out, paths, md, hp, rows, res["fit"], elapsed, res)
