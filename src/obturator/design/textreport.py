"""Text of the design study: the ranked plan, the decision table, what each setting tests."""

from __future__ import annotations

import math

import numpy as np

from ..model.cases import table1_ball
from .results import DesignResult
from .settings import NOMINAL_SETTING, Setting

__all__ = [
    "decision_table",
    "feasibility_lines",
    "flat_lines",
    "format_design",
    "mechanism_note",
    "misfit_lines",
    "plan_table",
    "setting_notes",
]


def _setting_text(s: Setting) -> str:
    return (
        f"{s.spin_rate:6.1f} rad/s  theta0 {s.theta0_deg:5.2f} deg  "
        f"r_s {1e3 * s.hole_radius:4.2f} mm  rho {s.density:6.0f} kg/m^3"
    )


def mechanism_note(s: Setting) -> str:
    """Which mechanism a setting tests: what it changes from the measured rig, and why the
    candidates answer differently there (for the experimentalist)."""
    parts = []
    if s.spin_rate < 120.0:
        parts.append(
            "low spin: the ball slips slowly over the seat, where a slip-speed law of mu "
            "(strengthening: mu falls to r mu_s at low slip) changes the friction most and a "
            "constant mu with a release offset does not"
        )
    elif s.spin_rate > 300.0:
        parts.append(
            "high spin: fast slip, mu near its full value in every model; t_cr grows about "
            "linearly with spin (thesis Eq. 96), so it tests the friction level itself"
        )
    if abs(s.theta0_deg - NOMINAL_SETTING.theta0_deg) > 0.5:
        parts.append(
            f"release angle set to {s.theta0_deg:.1f} deg: a release offset (theta0 model) "
            "shifts the start by the same angle at every set angle, and its effect on t_cr "
            "shrinks as the set angle moves away from 90 deg (the ball leaves 90 deg "
            "slowly, t_cr grows about as ln 1/(90 deg - theta0)); the other models take the "
            "set angle as true"
            + (
                "; released this far from 90 deg the opening is short and much of it is the "
                "first slip after release, where velocity-strengthening friction is still low "
                "(r mu_s) and a constant mu is not"
                if s.theta0_deg < 80.0
                else ""
            )
        )
    if abs(s.hole_radius - NOMINAL_SETTING.hole_radius) > 1e-5:
        ball = table1_ball(hole_radius=s.hole_radius, density=s.density)
        slower = s.hole_radius < NOMINAL_SETTING.hole_radius
        parts.append(
            f"hole radius {1e3 * s.hole_radius:.2f} mm (a new ball): opening angle "
            f"beta_s = asin(r_s/R_s) {math.degrees(ball.opening_angle):.1f} deg (Table 1: "
            f"36.7) and inertia ratio lambda = C/A - 1 {ball.inertia_ratio:.2f} (0.41), the "
            "gyroscopic drive that turns the hole axis onto the spin axis; "
            + (
                "the ball turns further and more slowly, which stretches every t_cr and with "
                "it the difference a release offset or a slip-speed law makes"
                if slower
                else "the ball opens sooner, after a shorter turn, so the start of the "
                "motion (where the release angle acts) weighs more in t_cr"
            )
        )
    if abs(s.density - NOMINAL_SETTING.density) > 1.0:
        parts.append(
            f"density {s.density:.0f} kg/m^3: weight and inertia scale together, so the "
            "sliding friction per inertia is unchanged and the viscous torque per inertia "
            "scales as 1/rho: it weighs the gap flow against the sliding friction"
        )
    if not parts:
        parts.append("the Table 1 rig at a mid-range spin: the slip-speed law at moderate slip")
    return "; ".join(parts)


def plan_table(result: DesignResult, n_runs: int) -> list[str]:
    """The ranked plan of `n_runs` runs, one line per distinct setting."""
    m = result.models
    head = (
        "  #  x  setting"
        + " " * 54
        + "  ".join(f"{x[:14]:>24}" for x in m)
        + "  sep/SD  hold/bound  extrapolated"
    )
    lines = [head]
    for k, r in enumerate(result.ranked_plan(n_runs), 1):
        preds = "  ".join(
            f"{v[0]:7.4f} [{v[1]:6.3f},{v[2]:6.3f}]".rjust(24) for v in r["predicted"].values()
        )
        f = r["feasibility"]
        where = ""
        if f is not None:
            where = f"  {f.holding_moment / f.bound:10.2f}  {', '.join(f.extrapolated) or '-'}"
        lines.append(
            f"{k:3d} {r['replicates']:2d}  {_setting_text(r['setting'])}  {preds}"
            f"  {r['separation_in_replicate_sd']:6.1f}{where}"
        )
    lines.append(
        "  x: replicates; predicted t_cr [s]: mean [95 % predictive interval: parameters "
        "and replicate noise]; sep/SD: difference of the first two models' means in "
        "replicate SDs; hold/bound: holding moment at the set angle over the rig's bound; "
        "extrapolated: where the setting leaves the measured runs"
    )
    return lines


def feasibility_lines(result: DesignResult) -> list[str]:
    """The rig's holding bound, the settings it excludes, and the plans of the recommended
    size without the check and on the as-built ball alone."""
    if not result.feasibility or result.validated is None:
        return []
    v = result.validated
    grid = result.feasibility
    n_out = sum(not f.feasible for f in grid)
    lines = [
        "Feasibility: holding the ball at the set angle while it spins needs "
        "omega_p^2 |C - A| sin theta_0 cos theta_0; the rig's bound is the larger of the "
        "seat's friction moment mu_s W R_s + the holding jet's F_jet R_s and the "
        f"{v.holding_moment_max:.3g} N m the measured runs needed (stick ratio "
        f"{v.stick_ratio[0]:.3f}-{v.stick_ratio[1]:.2f}); {n_out} of "
        f"{len(grid)} settings exceed it and are never planned; nor is a new ball set "
        "within 0.5 deg + two prior SDs of its own theta_0 offset of 90 deg (the run would "
        "tell only that offset).",
    ]
    for label, (n, runs, d) in result.alternative_plans.items():
        parts = []
        for i in sorted(set(runs)):
            f = result.feasibility[i]
            parts.append(
                f"{runs.count(i)} x {_setting_text(result.settings[i]).strip()} (hold "
                f"{f.holding_moment:.2g} N m = {f.holding_moment / f.bound:.2f} x bound"
                + ("" if f.feasible else ", infeasible")
                + ")"
            )
        rec = result.plan(n)
        lines.append(
            f"  {n}-run plan {label}: D {d:.2f} nats (planned: {rec.criterion:.2f}): "
            + "; ".join(parts)
        )
    return lines


def misfit_lines(result: DesignResult) -> list[str]:
    """How often the recommended plan exposes a misfit, per generating truth."""
    rec = result.recommended
    rates = result.misfit_rates(rec)
    if not rates or all(math.isnan(x) for x in rates.values()):
        return []
    inside = ", ".join(f"{m} {x:.2f}" for m, x in rates.items() if m in result.models)
    outside = [(m, x) for m, x in rates.items() if m not in result.models]
    lines = [
        f"Can the {rec.n_runs}-run plan say 'neither'? P(every candidate fails its posterior "
        f"predictive check at 5 %): under a candidate's own truth {inside} (false alarms)"
    ]
    for m, x in outside:
        lead = rec.designed[m]
        lines.append(
            f"  truth outside the candidates, {m} (fits every measured cluster): misfit "
            f"exposed in {x:.2f} of campaigns; decisive for a candidate (misleading) in "
            f"{lead.p_misleading:.2f}"
        )
    return lines


def flat_lines(result: DesignResult) -> list[str]:
    """The flat directions of each candidate's fit (where a valley makes the point
    estimate arbitrary)."""
    lines = []
    for m, dirs in result.flat_directions.items():
        for d in dirs[:1]:
            change = ", ".join(f"{k} {v:+.3g}" for k, v in d["one_sd_change"].items())
            lines.append(
                f"  {m}: a valley {d['axis_ratio']:.0f} times longer than wide; one SD along "
                f"it moves {change}"
            )
    if lines:
        lines.insert(0, "Flat directions of the fits (one fit per model, shared with validate):")
    return lines


def decision_table(result: DesignResult) -> list[str]:
    """P(decisive) of the designed and naive plans per size, and the sizes each needs."""
    m = result.models
    lines = [
        f"P(decisive: Bayes factor > 10 for the generating model), {result.campaigns} "
        "simulated campaigns per generating model (d: designed, n: naive)",
        "   N  designed  naive  " + "  ".join(f"{x[:13]:>13} d/n" for x in m) + "  sep/SD d/n",
    ]
    for p in result.plans:
        per = "  ".join(
            f"{p.designed[x].p_decisive:4.2f}/{p.naive[x].p_decisive:4.2f}".rjust(17) for x in m
        )
        sep_d = float(np.mean(result.separation(p.runs)))
        sep_n = float(np.mean(result.separation(p.naive_runs)))
        lines.append(
            f"{p.n_runs:4d}  {p.p_decisive:8.2f}  {p.naive_p_decisive:5.2f}  {per}"
            f"  {sep_d:5.1f}/{sep_n:.1f}"
        )
    curve = ", ".join(
        f"{n}: {np.mean([v[m].p_decisive for m in result.models]):.3f}"
        for n, v in sorted(result.naive_rates.items())
    )
    lines.append(f"  naive plan (spins spread as the measured runs, Table 1 rig) by N: {curve}")
    top = max(result.naive_rates)
    for target in (0.95, 0.99):
        d, n = result.designed_runs_needed(target), result.naive_runs_needed(target)
        d_txt = str(d) if d else f"> {result.plans[-1].n_runs}"
        n_txt = str(n) if n else f"> {top}"
        lines.append(f"  runs for P(decisive) >= {target:g}: designed {d_txt}, naive {n_txt}")
    lines.append(
        "  sep/SD: mean over the plan's runs of |difference of the first two models' mean "
        "t_cr| in replicate SDs"
    )
    return lines


def setting_notes(result: DesignResult, n_runs: int) -> list[str]:
    """What each planned setting tests, with the separation each change from the Table 1
    rig buys (the separation with that change undone)."""
    names = {"theta0_deg": "release angle", "hole_radius": "hole radius", "density": "density"}
    nominal = {"theta0_deg": "87.25 deg", "hole_radius": "4.72 mm", "density": "7670 kg/m^3"}
    out = []
    for k, r in enumerate(result.ranked_plan(n_runs), 1):
        i = r["index"]
        undo = ", ".join(
            f"{names[a]} back at {nominal[a]}: {v:.1f}" for a, v in result.axis_effects(i).items()
        )
        sep = f"separation {r['separation_in_replicate_sd']:.1f} replicate SDs" + (
            f" ({undo})" if undo else ""
        )
        slope = float(result.release_slope[i])
        if slope > 0.0:
            sep += (
                f"; dt_cr/dtheta_0 {slope:.3f} s/deg: the planned SD "
                f"{r['replicate_sd_s']:.3f} s needs a release repeatable to "
                f"{r['replicate_sd_s'] / slope:.2f} deg (SD)"
            )
        ball = (
            " On the as-built ball."
            if r["setting"].is_as_built_ball
            else " On a new ball: its theta_0 offset is its own (the laser reads that ball's "
            "polished spot), drawn from the prior, not the as-built ball's fitted offset."
        )
        out.append(
            f"  {k}. {_setting_text(r['setting']).strip()}: {sep}. "
            f"{mechanism_note(r['setting'])}.{ball}"
        )
    return out


def format_design(result: DesignResult) -> str:
    """The study as text."""
    rec = result.recommended
    lines = [
        f"Experiment design: {' vs '.join(result.models)} "
        f"({int(result.candidate_mask.sum())} candidate settings; measured quantity t_cr)",
        "Criterion: Box-Hill (1967) expected symmetric KL divergence of the joint "
        "predictive distributions (Laplace posterior of each fit).",
        "Noise per run: the largest of its spin band's replicate SD, the band's CV x predicted "
        f"t_cr and a release jitter of {result.noise_model.release_sd_deg:.3f} deg "
        f"({result.noise_model.release_source}) x |dt_cr/dtheta_0|; bands: "
        + ", ".join(
            f"{k} {v:.4f} s ({100 * result.noise_model.cv[k]:.1f} %)"
            if math.isfinite(v)
            else f"{k} no replicates"
            for k, v in result.noise_model.sd.items()
        ),
        "",
        f"Recommended campaign: {rec.n_runs} runs "
        f"(P(decisive) {rec.p_decisive:.2f}; "
        f"naive plan of the same size {rec.naive_p_decisive:.2f})",
        *plan_table(result, rec.n_runs),
        "",
        *decision_table(result),
        "",
        "What each planned setting tests:",
    ]
    lines += setting_notes(result, rec.n_runs)
    for extra in (feasibility_lines(result), misfit_lines(result), flat_lines(result)):
        if extra:
            lines += ["", *extra]
    lines.append("")
    lines.append(
        "Surrogate (second-order in the posterior, central differences one SD along each "
        "posterior axis) against exact t_cr at the campaign draws:"
    )
    for name, e in result.surrogate_error.items():
        lines.append(
            f"  {name}: rms {e['rms_s']:.2e} s, max {e['max_abs_s']:.2e} s, rms "
            f"{e['rms_in_replicate_sd']:.2f} replicate SDs over {e['n_compared']} "
            "(draw, setting) pairs"
            f"; {e['n_not_opened']} not opened by t_max"
        )
    lines.append(
        f"{result.n_solves} exact solves (front door obturator.solve.opening_times), "
        f"{result.elapsed_s:.1f} s; seed {result.seed}"
    )
    return "\n".join(lines)
