# ruff: noqa: E501  (the caption table quotes the thesis line by line)
"""Figure captions of the reproduce report: the thesis's caption, what we computed, the difference.

Each caption is built from the study results, so its numbers are the ones the
figure shows. Thesis captions are quoted from its List of Figures (page numbers
of the thesis in parentheses).
"""

from __future__ import annotations

import math
from typing import Any

__all__ = ["THESIS_CAPTIONS", "figure_captions"]

#: Figure file stem -> (thesis caption, thesis page). Ours have no thesis caption.
THESIS_CAPTIONS: dict[str, tuple[str, int | None]] = {
    "fig09": ("theta vs. time for applied torques due to fluid friction from Couette model (Eq. 32)", 53),
    "fig10": ("theta vs. time for obturator with applied torques due to fluid friction with increasing orders of magnitude of S", 53),
    "fig13": ("Plot of theta vs. time for BOT utilizing aerodynamic force development", 67),
    "fig14": ("Plot of theta vs. time for BOT utilizing gravitational force development", 68),
    "fig15": ("Comparison plot of theta vs. time for the (a) exact and (b) approximate solutions", 76),
    "fig16": ("Comparison plot of theta vs. time for obturator material densities of (a) 6000 kg/m^3 and (b) 10,000 kg/m^3", 78),
    "fig17": ("Comparison plot of theta vs. time for obturator hole radii of (a) 3.75 mm and (b) 5.58 mm", 80),
    "fig32": ("theta vs. time for gravity model, omega_p = 40 s^-1", 98),
    "fig33": ("theta vs. time for gravity model, omega_p = 100 s^-1", 99),
    "fig34": ("theta vs. time for gravity model, omega_p = 200 s^-1", 100),
    "fig35": ("theta vs. time for gravity model, omega_p = 500 s^-1", 101),
    "fig36": ("theta vs. time for gravity model, omega_p = 700 s^-1", 102),
    "fig37": ("theta vs. time for gravity model, omega_p = 1000 s^-1", 103),
    "fig38": ("Plot of experimental data and t_cr calculated from approximate solution", 104),
    "fig39": ("Plot of t_cr vs. omega_p for various values of sliding friction coefficient mu_s", 105),
    "fig40": ("Plot of t_cr vs. omega_p for various values of theta_0", 106),
    "fig41": ("Plot of experimental data showing the relative insensitivity to small variations in theta_0", 107),
    "fig42": ("Plot of experimental data on plot from Fig. 39 showing close correlation for omega_p 200 s^-1 with curve for mu_s = 0.55", 108),
    "fig43": ("Plot of experimental data, linear approximation from least squares fit of data and values obtained from exact solution for mu_s = 0.5437", 113),
}  # fmt: skip


def _t(x: float) -> str:
    return f"{x:.4g} s" if math.isfinite(x) else "does not open"


def _computed(stem: str, res: dict[str, Any]) -> tuple[str, str]:
    """(what we computed, key difference) for one figure."""
    if stem == "fig09":
        c = res["couette"]
        return (
            "Couette S of Eq. 34 with the p. 52 inputs, "
            f"{float(c.attrs['shear_constant_eq34']):.3g} N m s; envelope of the fast "
            "nutation and its first 3 ms",
            "the caption's S (1.2e-6 N m s) is 56 times Eq. 34's; with either the ball does "
            "not open within 0.1 s, as the thesis concludes",
        )
    if stem == "fig10":
        return ("S times 1, 10, 100, 1000", "same trend as the thesis: only a much larger S opens")
    if stem in ("fig13", "fig14"):
        case = "flight" if stem == "fig13" else "rig"
        t = float(res["flight_rig"]["t_cr"].sel(case=case))
        return (f"Table 1 {case} case, t_cr = {_t(t)}", "agrees in shape with the thesis's curve")
    if stem == "fig15":
        ds = res["fig15"]
        return (
            f"exact t_cr = {_t(ds.attrs['t_cr_exact'])}, Eq. 92 {_t(ds.attrs['t_cr_eq92'])}",
            "the linearised solution runs a few per cent faster than the exact one",
        )
    if stem in ("fig16", "fig17"):
        ds = res["density" if stem == "fig16" else "hole"]
        ts = ", ".join(_t(float(x)) for x in ds["t_cr"].values)
        diff = (
            "density barely matters: inertia and friction moment both scale with rho"
            if stem == "fig16"
            else "the smaller hole opens far later: smaller lambda = C/A - 1, weaker coupling"
        )
        return (f"t_cr = {ts}", diff)
    if stem in ("fig32", "fig33", "fig34", "fig35", "fig36", "fig37"):
        i = int(stem[3:5]) - 32
        ds = res["rig_spin"]
        w, t = float(ds["spin_rate"][i]), float(ds["t_cr"][i])
        return (
            f"rig at {w:g} rad/s, mu_s = {ds.attrs['mu_s']:g}: t_cr = {_t(t)}",
            "the ball opens at every spin, slower at low and high spin than in between "
            "(thesis p. 97); the moment arm uses the true slip direction",
        )
    if stem in ("fig38", "fig39", "fig40", "fig41", "fig42"):
        return (
            "Eq. 92 over 100-1000 rad/s (and the exact model where labelled) with the 54 runs",
            "as in the thesis: data below the approximation at high spin, above it at low spin",
        )
    if stem == "fig43":
        ds = res["fig43"]
        return (
            f"T2 = {ds.attrs['T2']:.6g} s^2 from the printed 24-run sums; exact model at "
            f"mu_s = {ds.attrs['mu_s']:.4f} from 125 rad/s",
            "the caption's 0.5437 is a transposition of the text's 0.5473; the exact curve "
            "lies above the least-squares line at high spin",
        )
    if stem == "tcr_minimum":
        m = res["minimum"]
        w = float(m["spin_rate_min"].sel(model="exact"))
        w35 = float(res["minimum_table1"]["spin_rate_min"].sel(model="exact"))
        return (
            f"exact minimum at {w:.1f} rad/s for mu_s = {m.attrs['mu_s']:g} "
            f"({w35:.1f} rad/s for mu_s = 0.35); Eq. 92's at "
            f"{float(m['spin_rate_min'].sel(model='approx')):.1f} rad/s",
            "the thesis puts the minimum near 150 rad/s (chapter V), which the Table 1 mu_s "
            "reproduces",
        )
    if stem == "calibration_residuals":
        fit = res["fit"]
        return (
            f"exact-model fit to the starred runs, mu_s = {fit.mu_s:.4f}",
            "the thesis fitted the linearised line (mu_s = 0.5473)",
        )
    return ("", "")


def figure_captions(names: list[str], res: dict[str, Any]) -> dict[str, str]:
    """One caption per figure file name: thesis caption (page) | computed | difference."""
    out = {}
    for name in names:
        stem = name.rsplit(".", 1)[0]
        key = stem[:5] if stem.startswith("fig") else stem
        computed, diff = _computed(key, res)
        thesis = THESIS_CAPTIONS.get(key)
        parts = []
        if thesis is not None:
            parts.append(f"Thesis Fig. {int(key[3:5])} (p. {thesis[1]}): {thesis[0]}.")
        else:
            parts.append("Not in the thesis.")
        if computed:
            parts.append(f"Computed: {computed}.")
        if diff:
            parts.append(f"Difference: {diff}.")
        out[name] = " ".join(parts)
    return out
