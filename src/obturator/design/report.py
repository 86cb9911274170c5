"""The experiment-design section of the reproduction report (``obturator reproduce --design``).

The full report runs :func:`~.study.design_experiment` with its defaults (reusing the
validation section's fits of the candidates when it has them); ``--quick`` a small grid
and 20 campaigns per model, and says so.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path

from ..report_section import ReportSection
from ..runs import Runner
from ..runs.store import atomic_write_text
from ..validation.results import CandidateFit
from .plotting import save_design_figure
from .settings import SettingRanges
from .study import design_experiment
from .textreport import (
    decision_table,
    feasibility_lines,
    flat_lines,
    mechanism_note,
    misfit_lines,
    plan_table,
)

__all__ = ["DesignSection", "design_section"]


#: This study's section of the report.
DesignSection = ReportSection


def design_section(
    out_dir: str | Path,
    *,
    quick: bool = False,
    runner: Runner | None = None,
    fits: Mapping[str, CandidateFit] | None = None,
) -> DesignSection:
    """Run the design study; write ``design.png`` and ``design.json``; return the section."""
    out = Path(out_dir)
    kw = (
        {
            "ranges": SettingRanges(n_spin=4, n_theta0=2, n_hole=2, n_density=1),
            "campaigns": 20,
            "naive_runs": (5, 10, 20, 40),
        }
        if quick
        else {}
    )
    res = design_experiment(runner=runner, fits=fits, **kw)
    save_design_figure(res, out / "design.png")
    atomic_write_text(out / "design.json", json.dumps(res.to_dict(), indent=1, default=str) + "\n")
    rec = res.recommended
    need = res.naive_runs_needed(rec.p_decisive)
    need_txt = (
        f"the naive plan needs {need} runs for the same rate"
        if need is not None
        else f"the naive plan does not reach it within {max(res.naive_rates)} runs"
    )
    scope = (
        "quick mode: a small grid and 20 campaigns per model; the full report uses the "
        "default grid and 200"
        if quick
        else f"{res.campaigns} simulated campaigns per generating model"
    )
    notes = "; ".join(
        f"({k}) {mechanism_note(r['setting'])}"
        for k, r in enumerate(res.ranked_plan(rec.n_runs), 1)
    )
    paragraphs = (
        "Which rig runs would decide between "
        + " and ".join(f"'{m}'" for m in res.models)
        + " (`obturator design-experiment`): the Box-Hill (1967) criterion, the expected "
        "symmetric Kullback-Leibler divergence between the models' predictive distributions "
        "of t_cr (parameters from the Laplace posterior of each fit to all runs; noise the "
        "replicate SD of each spin band, raised where a setting opens later or is steeper in "
        "the release angle than the measured runs), maximised over spin, release angle, "
        f"hole radius and ball density; checked by simulated campaigns ({scope}) with exact "
        "solves at posterior draws, decided by Bayes factor > 10.",
        f"Recommended campaign: {rec.n_runs} runs, decisive in {100 * rec.p_decisive:.0f} % "
        f"of simulated campaigns; the naive plan of the same size (spins spread as Appendix "
        f"B, Table 1 rig) in {100 * rec.naive_p_decisive:.0f} %; {need_txt}.",
        f"What the planned settings test: {notes}.",
        *(
            " ".join(x.strip() for x in block)
            for block in (feasibility_lines(res), misfit_lines(res))
            if block
        ),
    )
    pre = (
        "\n".join(plan_table(res, rec.n_runs)),
        "\n".join(decision_table(res)),
        *("\n".join(flat) for flat in (flat_lines(res),) if flat),
    )
    figures = (("design.png", "Experiment design: candidates' t_cr over each setting"),)
    return DesignSection(
        "Which experiment decides between the mechanisms", paragraphs, figures, pre
    )
