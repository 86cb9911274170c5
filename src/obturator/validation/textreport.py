"""Plain-text and Markdown tables of a :class:`~.results.ValidationResult`."""

from __future__ import annotations

import math

from .candidates import PARAMETERS
from .floor import band_labels
from .results import CandidateFit, ModelResult, ValidationResult

__all__ = [
    "cluster_table",
    "floor_table",
    "goodness_table",
    "format_report",
    "markdown_summary",
    "params_table",
    "ranked_table",
    "thesis_line",
]


def _f(x: float, fmt: str = ".4f") -> str:
    return "-" if x is None or not math.isfinite(x) else format(x, fmt)


def floor_table(result: ValidationResult) -> list[str]:
    """Lines: the replicate floor overall and per band."""
    fl = result.floor
    lines = [
        f"Replicate floor ({fl.n_clusters} clusters, single linkage in omega_p, "
        f"gap {fl.gap:.2f} rad/s)",
        f"  {'band':<8} {'runs':>4} {'clust':>5} {'df':>3} {'pooled SD [s]':>13} "
        f"{'saturated rms':>13}",
    ]
    for b in (fl.overall, *fl.bands.values()):
        lines.append(
            f"  {b.label:<8} {b.n_runs:>4d} {b.n_clusters:>5d} {b.dof:>3d} "
            f"{_f(b.pooled_sd):>13} {_f(b.saturated_rms):>13}"
        )
    lines.append("  (a perfect model's expected rms is the pooled SD; the saturated cluster-mean")
    lines.append("   model's in-sample rms is the lower bound no smooth model reaches)")
    return lines


def ranked_table(result: ValidationResult) -> list[str]:
    """Lines: every model ranked by AIC, with rms overall/per band, BIC, out-of-band rms."""
    bands = band_labels()
    best_aic = min(m.fit.aic for m in result.models)
    head = (
        f"  {'#':>2} {'model':<27} {'k':>2} {'rms all':>8} "
        + " ".join(f"{b:>8}" for b in bands)
        + f" {'AIC':>8} {'dAIC':>6} {'BIC':>8} {'hi->lo':>7} {'lo->hi':>7} {'st->all':>7} phys"
    )
    lines = ["Models ranked by AIC (all-run fit; rms [s]; out-of-band rms [s])", head]
    floor = result.floor
    lines.append(
        f"  {'':>2} {'replicate floor':<27} {'':>2} {_f(floor.floor_rms):>8} "
        + " ".join(f"{_f(floor.bands[b].floor_rms):>8}" for b in bands)
    )
    for i, m in enumerate(result.models, 1):
        f = m.fit
        rb = f.rms_by_band
        oob = m.out_of_band_rms
        mark = "*" if m.name == result.recommended else " "
        lines.append(
            f"  {i:>2} {(m.name + mark):<27} {f.k:>2d} {_f(f.rms):>8} "
            + " ".join(f"{_f(rb[b]):>8}" for b in bands)
            + f" {_f(f.aic, '.2f'):>8} {_f(f.aic - best_aic, '.2f'):>6} {_f(f.bic, '.2f'):>8}"
            + f" {_f(oob.get('high->low', math.nan)):>7} {_f(oob.get('low->high', math.nan)):>7}"
            + f" {_f(oob.get('starred->all', math.nan)):>7}"
            + f" {'yes' if f.all_plausible else 'NO'}"
        )
    lines.append(
        "  k counts sigma; hi->lo: fit omega_p >= 200, rms on < 200; lo->hi: the reverse; "
        "st->all: fit to starred runs, rms on all; * recommended"
    )
    return lines


def predictive_table(result: ValidationResult) -> list[str]:
    """Lines: every model's cross-validated predictive scores beside its AIC (empty when
    the study computed none)."""
    keys = ("leave_one_cluster_out", "leave_one_band_out")
    if not any(m.predictive for m in result.models):
        return []
    best = {
        k: min(
            (m.predictive[k]["deviance"] for m in result.models if k in m.predictive),
            default=math.nan,
        )
        for k in keys
    }
    lines = [
        "Predictive scores: each run predicted by the model refitted without its replicate "
        "cluster (LOCO) or its spin band (LOBO); rms [s] and -2 log predictive density "
        "(deviance, the scale of AIC; d: above the best)",
        f"  {'model':<27} {'AIC':>8} {'LOCO rms':>9} {'deviance':>9} {'d':>6} "
        f"{'LOBO rms':>9} {'deviance':>9} {'d':>7}",
    ]

    def loco(m: ModelResult) -> float:
        return float(m.predictive.get(keys[0], {}).get("deviance", math.inf))

    for m in sorted(result.models, key=loco):
        name = m.name + ("*" if m.name == result.recommended else "")
        row = f"  {name:<27} {_f(m.fit.aic, '.2f'):>8}"
        for k, wide in zip(keys, (6, 7), strict=True):
            sc = m.predictive.get(k, {})
            dev = sc.get("deviance", math.nan)
            row += (
                f" {_f(sc.get('rms_s', math.nan)):>9} {_f(dev, '.2f'):>9}"
                f" {_f(dev - best[k], '.2f'):>{wide}}"
            )
        lines.append(row)
    lines.append(
        "  refits start at the all-run optimum with its slopes and sigmas held (one "
        "least-squares pass); * recommended"
    )
    return lines


def params_table(fit: CandidateFit, indent: str = "  ") -> list[str]:
    """Lines: value, stderr, 95 % interval and physical range of each parameter."""
    lines = []
    for k in fit.params:
        p = PARAMETERS[k]
        lo, hi = fit.ci95[k]
        plaus = "in range" if fit.plausible[k] else "OUT of range"
        lines.append(
            f"{indent}{k:<16} {fit.values[k]:>10.5g} +- {_f(fit.stderr[k], '.3g'):<9} "
            f"95% [{_f(lo, '.5g')}, {_f(hi, '.5g')}] ({fit.ci_method[k]}) {p.unit:<5} "
            f"physical {p.plausible[0]:g}..{p.plausible[1]:g}: {plaus}"
        )
    if fit.noise == "band" and fit.sigma_by_group:
        per = ", ".join(f"{g} {v:.4f}" for g, v in fit.sigma_by_group.items())
        lines.append(f"{indent}{'sigma by band':<16} {per} s (ML run-to-run scatter)")
    else:
        lines.append(f"{indent}{'sigma':<16} {fit.sigma:>10.5g} s (ML run-to-run scatter)")
    return lines


def goodness_table(result: ValidationResult) -> list[str]:
    """Lines: lack of fit per band against the replicate floor, every model."""
    bands = band_labels()
    head = f"  {'model':<27} " + " ".join(f"{b:>15}" for b in bands) + f" {'overall':>16}"
    lines = [
        "Goodness of fit against the replicate floor: per band rms [s] / lack-of-fit p "
        "(F test of the cluster means on the band's pure error); overall X2(dof) p",
        head,
    ]
    for m in result.models:
        g = m.goodness
        if not g:
            continue
        cells = []
        for b in bands:
            row = g["bands"].get(b)
            cells.append(
                "-" if row is None else f"{_f(row['rms_s'], '.3f')} / {_f(row['p_value'], '.2g')}"
            )
        o = g["overall"]
        overall = (
            f"{_f(o['X2'], '.1f'):>6}({o['dof']}) {_f(o['p_value'], '.2g'):>6}"
            if o["n_bands"]
            else f"{'-':>16}"
        )
        lines.append(f"  {m.name:<27} " + " ".join(f"{c:>15}" for c in cells) + f" {overall}")
    lines.append(
        "  p < 0.05: the band's cluster means miss the model by more than replicates scatter"
    )
    return lines


def cluster_table(result: ValidationResult, n_models: int = 5) -> list[str]:
    """Lines: every replicated cluster, its scatter, and the residual of the recommended
    and the next best models (model - measured mean [s], z on the band's pure error)."""
    models = [result.model(result.recommended)]
    models += [m for m in result.models if m.name != result.recommended][: n_models - 1]
    models = [m for m in models if m.goodness]
    if not models:
        return []
    head = f"  {'cluster':>9} {'n':>2} {'t mean':>7} {'SD':>7} " + " ".join(
        f"{m.name[:16]:>16}" for m in models
    )
    lines = [
        "Replicate clusters: measured mean and SD [s]; per model: residual [s] (z on the "
        "band's pure-error SD / sqrt(n))",
        head,
    ]
    rows = {m.name: {r["cluster"]: r for r in m.goodness["clusters"]} for m in models}
    for r in models[0].goodness["clusters"]:
        if r["n"] < 2:
            continue
        cells = []
        for m in models:
            q = rows[m.name][r["cluster"]]
            cells.append(f"{q['residual_s']:+.3f} ({_f(q['z_band'], '+.1f')})")
        lines.append(
            f"  {r['name']:>9} {r['n']:>2d} {r['t_mean_s']:>7.4f} {_f(r['t_sd_s']):>7} "
            + " ".join(f"{c:>16}" for c in cells)
        )
    return lines + _tightest_cluster(result)


def _tightest_cluster(result: ValidationResult) -> list[str]:
    """Every model's residual at the tightest cluster of three or more runs (on the thesis
    runs 96 rad/s, SD 0.002 s): where a smooth model's misfit is plainest."""
    models = [m for m in result.models if m.goodness]
    rows = [r for r in models[0].goodness["clusters"] if r["n"] >= 3] if models else []
    if not rows:
        return []
    tight = min(rows, key=lambda r: r["t_sd_s"])
    res = {
        m.name: next(r for r in m.goodness["clusters"] if r["cluster"] == tight["cluster"])
        for m in models
    }
    cells = ", ".join(f"{name} {r['residual_s']:+.3f}" for name, r in res.items())
    return [
        f"Tightest replicated cluster, {tight['name']} ({tight['n']} runs, mean "
        f"{tight['t_mean_s']:.4f} s, SD {tight['t_sd_s']:.4f} s): model - measured [s]: " + cells
    ]


def _model_lines(m: ModelResult) -> list[str]:
    f = m.fit
    lines = [f"{m.name}: {m.description}"]
    lines += params_table(f, "    ")
    conv = m.convergence
    if conv:
        lines.append(
            f"    convergence at {conv['n_runs']} runs: max rel change "
            f"{conv['max_rel_change']:.2g} (tol {conv['max_tolerance_rel_change']:.2g}, "
            f"width {conv['max_width_rel_change']:.2g}, family "
            f"{conv['max_family_rel_change']:.2g}); not converged: {conv['n_not_converged']}"
        )
    lof = m.lack_of_fit
    if lof and math.isfinite(lof.get("F", math.nan)):
        lines.append(
            f"    lack of fit: F({lof['df_lof']}, {lof['df_pe']}) = {lof['F']:.2f}, "
            f"p = {lof['p_value']:.3g}"
        )
    if f.n_censored:
        lines.append(f"    censored runs (not opened by {f.t_max:g} s): {f.n_censored}")
    for d in f.flat_directions[:1]:
        change = ", ".join(f"{k} {v:+.3g}" for k, v in d["one_sd_change"].items())
        lines.append(
            f"    flat direction: a valley {d['axis_ratio']:.0f} times longer than wide "
            f"(one SD along it: {change}); {f.n_restarts} restarts along it, the lowest "
            "-log L kept"
        )
    seen: list[CandidateFit] = []
    for sub in (m.starred, m.high, m.low):
        if sub is None or any(sub is x for x in seen):
            continue
        seen.append(sub)
        vals = ", ".join(f"{k}={sub.values[k]:.4g}" for k in sub.params)
        lines.append(f"    fit to {sub.selection} ({sub.ndata} runs): {vals}; rms {sub.rms:.4f} s")
    return lines


def format_report(result: ValidationResult, *, details: bool = True) -> str:
    """The study as text: floor, ranked table, recommendation, per-model details."""
    lines = floor_table(result) + [""] + ranked_table(result) + [""]
    pred = predictive_table(result)
    lines += [*pred, ""] if pred else []
    lines += goodness_table(result) + [""] + cluster_table(result) + [""]
    rec = result.model(result.recommended)
    lines.append("Recommended: " + result.recommendation)
    lines += params_table(rec.fit)
    th = next((m for m in result.models if m.name == "thesis-1980"), None)
    if th is not None:
        lines.append(_thesis_line(th, result))
    if result.phase_scatter:
        ps = result.phase_scatter
        sds = [x for x in ps["sd_over_phase_s"] if x is not None and math.isfinite(x)]
        if sds:
            lines.append(
                f"Release phase psi_0 (uniform per run): SD of t_cr over psi_0 for "
                f"'{ps['model']}' is {min(sds):.4f}-{max(sds):.4f} s across the cluster spins."
            )
    if details:
        lines.append("")
        for m in result.models:
            lines += _model_lines(m)
    lines.append("")
    lines.append(f"elapsed {result.elapsed_s:.1f} s, {result.settings.get('jobs', 1)} worker(s)")
    return "\n".join(lines)


def thesis_line(result: ValidationResult) -> str:
    """What the thesis's mu_s = 0.5473 and theta_0 = 87.25 +- 1 deg look like on all runs
    ("" if the study has no "thesis-1980" candidate)."""
    th = next((m for m in result.models if m.name == "thesis-1980"), None)
    return "" if th is None else _thesis_line(th, result)


def _thesis_line(th: ModelResult, result: ValidationResult) -> str:
    f = th.fit
    rb = f.rms_by_band
    fl = result.floor
    text = (
        "Thesis (mu_s = 0.5473, theta_0 = 87.25 deg) against all runs: rms "
        f"{f.rms:.4f} s = {f.rms / fl.floor_rms:.1f} x the floor; per band "
        + ", ".join(
            f"{b} {_f(rb[b])} s ({rb[b] / fl.bands[b].floor_rms:.1f} x)"
            if math.isfinite(fl.bands[b].floor_rms)
            else f"{b} {_f(rb[b])} s"
            for b in band_labels()
        )
        + "."
    )
    for m in result.models:
        if m.name == "theta0":
            v, lo, hi = m.fit.values["theta0_deg"], *m.fit.ci95["theta0_deg"]
            inside = 86.25 <= v <= 88.25
            text += (
                f" The thesis's +-1 deg: fitted alone with mu_s, theta_0 = {v:.2f} deg "
                f"(95 % {lo:.2f}-{hi:.2f}), {'inside' if inside else 'outside'} 86.25-88.25 deg."
            )
        if m.name == "mu":
            v, lo, hi = m.fit.values["mu_s"], *m.fit.ci95["mu_s"]
            text += (
                f" mu_s alone fitted to all runs: {v:.3f} ({lo:.3f}-{hi:.3f}), rms "
                f"{m.fit.rms:.3f} s: no mu_s serves both ends of the spin range."
            )
    return text


def markdown_summary(result: ValidationResult) -> list[str]:
    """Markdown lines for the report's validation section (table + recommendation)."""
    bands = band_labels()
    fl = result.floor
    best_aic = min(m.fit.aic for m in result.models)
    out = [
        f"Replicate floor (pure error of {fl.n_clusters} clusters, df {fl.overall.dof}): "
        f"a perfect model's rms is **{fl.floor_rms:.4f} s** overall; per band "
        + ", ".join(f"{b} {_f(fl.bands[b].floor_rms)} s (df {fl.bands[b].dof})" for b in bands)
        + ".",
        "",
        "| # | model | k | rms all [s] | "
        + " | ".join(bands)
        + " | AIC | dAIC | BIC | hi->lo | lo->hi | physical |",
        "|---|---|---|---|" + "---|" * len(bands) + "---|---|---|---|---|---|",
        f"| | replicate floor | | {_f(fl.floor_rms)} | "
        + " | ".join(_f(fl.bands[b].floor_rms) for b in bands)
        + " | | | | | | |",
    ]
    for i, m in enumerate(result.models, 1):
        f = m.fit
        rb = f.rms_by_band
        oob = m.out_of_band_rms
        name = f"**{m.name}**" if m.name == result.recommended else m.name
        out.append(
            f"| {i} | {name} | {f.k} | {_f(f.rms)} | "
            + " | ".join(_f(rb[b]) for b in bands)
            + f" | {_f(f.aic, '.1f')} | {_f(f.aic - best_aic, '.1f')} | {_f(f.bic, '.1f')} | "
            f"{_f(oob.get('high->low', math.nan))} | {_f(oob.get('low->high', math.nan))} | "
            f"{'yes' if f.all_plausible else 'no'} |"
        )
    good = [m for m in result.models if m.goodness]
    if good:
        out += [
            "",
            "Lack of fit per band against the replicate floor (p of the F test of the "
            "cluster means on the band's pure error; p < 0.05: the model misses):",
            "",
            "| model | " + " | ".join(bands) + " | overall X2 (dof) | p |",
            "|---|" + "---|" * len(bands) + "---|---|",
        ]
        for m in good:
            g = m.goodness
            cells = [_f(g["bands"].get(b, {}).get("p_value", math.nan), ".2g") for b in bands]
            o = g["overall"]
            out.append(
                f"| {m.name} | " + " | ".join(cells) + f" | {_f(o['X2'], '.1f')} ({o['dof']}) "
                f"| {_f(o['p_value'], '.2g')} |"
            )
    rec = result.model(result.recommended)
    out += ["", "**Recommended:** " + result.recommendation, ""]
    out += ["```"] + params_table(rec.fit) + ["```"]
    th = next((m for m in result.models if m.name == "thesis-1980"), None)
    if th is not None:
        out += ["", _thesis_line(th, result)]
    return out
