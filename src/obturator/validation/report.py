"""The validation section of the reproduction report (``obturator reproduce``).

The full report runs the default study (:data:`~.candidates.DEFAULT_MODELS`, profile
intervals); ``--quick`` runs :data:`QUICK_MODELS` without profiles and says so.
"""

from __future__ import annotations

import json
from pathlib import Path

from ..report_section import ReportSection
from ..runs import Runner
from ..runs.store import atomic_write_text
from .plotting import save_validation_figure
from .results import ValidationResult
from .study import run_validation
from .textreport import floor_table, params_table, predictive_table, ranked_table, thesis_line

__all__ = ["QUICK_MODELS", "ValidationSection", "validation_section", "run_for_report"]

#: Candidates of the quick report (the full report runs the default set).
QUICK_MODELS = ("thesis-1980", "mu", "strengthening")


#: This study's section of the report.
ValidationSection = ReportSection


def run_for_report(quick: bool, runner: Runner | None = None) -> ValidationResult:
    """The study behind the section (quick: three candidates, Wald intervals only)."""
    models = QUICK_MODELS if quick else None
    return run_validation(models=models, profile=not quick, runner=runner)


def validation_section(
    result: ValidationResult, out_dir: str | Path, *, quick: bool
) -> ValidationSection:
    """Write ``validation.png`` and ``validation.json`` to `out_dir`; return the section."""
    out = Path(out_dir)
    save_validation_figure(result, out / "validation.png")
    atomic_write_text(out / "validation.json", json.dumps(result.to_dict(), indent=1) + "\n")
    scope = (
        f"quick mode: only {', '.join(QUICK_MODELS)}, Wald intervals; the full report "
        "fits every default candidate with profile-likelihood intervals"
        if quick
        else "every default candidate, profile-likelihood intervals for the recommended one"
    )
    paragraphs = (
        "One model and one parameter set for every spin-rig run (`obturator validate`): "
        "candidates fitted by maximum likelihood to all runs (censored where a run does not "
        "open within the horizon, spin readout error as errors in variables), ranked by "
        f"AIC, scored by what they predict (each run predicted by the model refitted without "
        f"its replicate cluster, and without its spin band), against the pure-error floor "
        f"of the replicate clusters ({scope}).",
        f"Recommended: {result.recommendation}",
        thesis_line(result),
    )
    rec = result.model(result.recommended).fit
    pre = (
        "\n".join([*floor_table(result), "", *ranked_table(result), "", *predictive_table(result)]),
        "\n".join(params_table(rec)),
    )
    figures = (("validation.png", "Validation: data, model curves and the replicate floor"),)
    return ValidationSection("Validation against all 54 runs", paragraphs, figures, pre)
