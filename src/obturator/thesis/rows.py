"""The report's comparison table: every checkable printed number against the computed one.

The printed values, labels, units and notes are data
(``obturator/reference/printed_values.toml``); this module computes the
values they are compared with (:func:`computed_values`) and builds the table
by one loop over that file (:func:`checkable_rows`). ``difference (%)`` is
computed / thesis - 1; rows whose thesis value was not printed show "—" and
name an independent check in the note.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import calibration as cal
from .._docs import field_docs
from ..approx import large_spin_coefficients, mean_moment_arm
from ..flow import (
    choking_mach,
    fanno_mach,
    normal_shock_mach,
    normal_shock_pressure_ratio,
    pressure_force,
)
from ..model.cases import rig_case, table1_ball
from ..reference import CHAPTER4_SUMS, PRINTED_VALUES, TABLE1, THESIS_MU_S, thesis
from ..reference.thesis import EQ95_WEIGHT, PRINTED_SUMS_OMITTED_RUNS
from ..solve import opening_time

__all__ = ["HEADER", "Row", "checkable_rows", "computed_values"]


@field_docs
@dataclass(frozen=True)
class Row:
    """One line of the comparison table."""

    #: Name of the quantity compared.
    quantity: str
    #: Printed value (None: not printed; str: qualitative statement).
    thesis: float | str | None
    #: Value computed here (str: qualitative result).
    computed: float | str
    #: Unit of both values (empty when dimensionless or not numeric).
    unit: str = ""
    #: Where the thesis prints it.
    where: str = ""
    #: Why a difference exists, or the independent check used.
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


def computed_values(res: dict[str, Any]) -> dict[str, Any]:
    """Every computed value the table compares, by the names used in the data file.

    Parameters
    ----------
    res : dict
        The studies of :func:`obturator.thesis.reproduce.reproduce`, by task name.
    """
    ball = table1_ball()
    e_theta0 = mean_moment_arm(math.radians(TABLE1["theta0_deg"])) * math.pi / 2
    v: dict[str, Any] = {
        "axial_inertia": ball.axial_inertia,
        "transverse_inertia": ball.transverse_inertia,
        "inertia_ratio": ball.inertia_ratio,
        "weight": ball.weight,
        "opening_angle_deg": math.degrees(ball.opening_angle),
        "opening_angle": ball.opening_angle,
        "shear_constant": rig_case().torque.viscous.coefficient,
        "elliptic_e": e_theta0,
        "omitted_runs": ", ".join(str(r) for r in PRINTED_SUMS_OMITTED_RUNS),
    }
    # chapter IV least squares: the 24-run subset that reproduces the printed sums, and
    # all 28 starred runs
    for prefix, fit in (
        ("ls", cal.thesis_fit()),
        ("all_starred", cal.thesis_fit(subset="starred")),
    ):
        for key in (*CHAPTER4_SUMS, "t2_direct", "mu_s_direct"):
            v[f"{prefix}.{key}"] = getattr(fit, key)
    # Eqs. 93-95 with the chapter's W = 0.0798 N and the model's beta_s
    m_per_mu = EQ95_WEIGHT * ball.radius
    lsc = large_spin_coefficients(
        transverse_inertia=ball.transverse_inertia,
        inertia_ratio=ball.inertia_ratio,
        moment=m_per_mu,
        theta0=math.radians(TABLE1["theta0_deg"]),
        theta_cr=ball.opening_angle,
    )
    v.update(moment_per_mu=m_per_mu, eq95_t1=lsc.T1, eq95_t2=lsc.T2)
    # gas dynamics (chapter I.B.4; Eqs. 1, 3, 43)
    m1, g = TABLE1["mach"], TABLE1["gamma"]
    rh = 2 * g * m1**2 / (g + 1) - (g - 1) / (g + 1)
    v.update(
        shock_pressure_ratio=float(normal_shock_pressure_ratio(m1, g)),
        shock_pressure_ratio_by_hand=rh,
        shock_mach2=float(normal_shock_mach(m1, g)),
        pressure_force=float(pressure_force(m1, TABLE1["p1"], TABLE1["bore_radius"], g)),
        pressure_force_by_hand=math.pi * TABLE1["bore_radius"] ** 2 * TABLE1["p1"] * (rh - 1.0),
        fanno_mach=float(fanno_mach(0.102, g)),
        choking_mach_one_iteration=float(choking_mach(8.0, friction_factor=0.01275, iterations=1)),
    )
    # qualitative and dynamic results
    mn, mn35, rs = res["minimum"], res["minimum_table1"], res["rig_spin"]
    data = cal.load_thesis_data()
    k = int(np.argmin(data.opening_time))
    v.update(
        minimum_spin_approx=float(mn["spin_rate_min"].sel(model="approx")),
        minimum_spin_exact=float(mn["spin_rate_min"].sel(model="exact")),
        minimum_tcr_exact=float(mn["t_cr_min"].sel(model="exact")),
        minimum_first_tcr=float(mn["t_cr_exact"][0]),
        minimum_first_spin=float(mn["spin_rate"][0]),
        minimum_spin_exact_table1=float(mn35["spin_rate_min"].sel(model="exact")),
        minimum_tcr_exact_table1=float(mn35["t_cr_min"].sel(model="exact")),
        rig_spin_all_open="yes" if bool(np.all(np.isfinite(rs["t_cr"].values))) else "no",
        rig_spin_tcr_list=", ".join(f"{t:.3g} s" for t in rs["t_cr"].values),
        rig_spin_list=", ".join(f"{w:g}" for w in rs["spin_rate"].values),
        fastest_run_spin=float(data.spin_rate[k]),
        fastest_run_tcr=float(data.opening_time[k]),
    )
    t_fl = float(res["flight_rig"]["t_cr"].sel(case="flight"))
    cou, cap = res["couette"], res["couette_caption"]
    v.update(
        flight_tcr=t_fl,
        flight_verdict="pass" if t_fl < 0.1 else "FAIL",
        couette_opens="no" if not math.isfinite(float(cou["t_cr"].isel(scale=0))) else "yes",
        couette_theta_end=float(cou["theta_end"].isel(scale=0)),
        couette_shear_constant=float(cou.attrs["shear_constant_eq34"]),
        couette_caption_theta_end=float(cap["theta_end"].isel(scale=0)),
    )
    near = (data.spin_rate > 195.0) & (data.spin_rate < 205.0)
    fit = res["fit"]
    v.update(
        rig200_measured_mean=float(np.mean(data.opening_time[near])),
        rig200_tcr=opening_time(rig_case(200.0, THESIS_MU_S)),
        rig200_n_runs=int(near.sum()),
        rig200_min=float(data.opening_time[near].min()),
        rig200_max=float(data.opening_time[near].max()),
        fit_mu_s=fit.mu_s,
        fit_mu_s_stderr=fit.stderr["mu_s"],
        fit_mu_s_change=res["fit_converged"] - fit.mu_s,
    )
    for w, (ex, ap) in res["exact_vs_eq92"].items():
        v[f"eq92_over_exact_{w:g}"] = 100.0 * (ap / ex - 1.0)
        v[f"exact_{w:g}"] = ex
        v[f"eq92_{w:g}"] = ap
    return v


def _printed(ref: str, values: dict[str, Any]) -> float:
    """A printed value referred to as ``table.key`` (see the data file's header)."""
    table, _, key = ref.partition(".")
    if table == "chapter4":
        return CHAPTER4_SUMS[key]
    if table == "table1":
        return TABLE1[key]
    if table == "thesis":
        return getattr(thesis, key)
    if table == "appendix_b":
        return values[key]
    raise KeyError(f"unknown printed-value table {table!r} in {ref!r}")


def checkable_rows(res: dict[str, Any]) -> list[Row]:
    """The comparison table from the computed studies (see :func:`reproduce`)."""
    values = computed_values(res)
    rows = []
    for entry in PRINTED_VALUES["row"]:
        printed = entry.get("printed")
        rows.append(
            Row(
                entry["quantity"],
                _printed(printed, values) if printed else entry.get("thesis"),
                values[entry["computed"]],
                entry.get("unit", ""),
                entry.get("where", ""),
                entry.get("note", "").format(**values),
            )
        )
    return rows
