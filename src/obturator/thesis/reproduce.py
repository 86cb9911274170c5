"""``obturator reproduce``: every thesis figure, the checkable numbers and the calibration.

:func:`reproduce` runs the studies (:mod:`.histories`, :mod:`.opening_times`),
the calibrations of :mod:`obturator.calibration` and the explorer
(:mod:`.explorer`), writes one PNG per figure (:mod:`obturator.plotting`) and
a report in Markdown and HTML (:mod:`.render`) around the table that compares
every number of the thesis's Table 1 and chapters II-IV that it prints (or
states qualitatively) with the computed value (:mod:`.rows`).
"""

from __future__ import annotations

import base64
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from .. import __version__
from .. import calibration as cal
from .._docs import field_docs
from ..model.cases import rig_case
from ..reference import TABLE1, THESIS_MU_S
from ..runs import Progress, Runner, study_digest
from ..runs.store import atomic_write_text
from ..solve import SolverOptions, opening_times, simulate
from .explorer import explorer_data
from .histories import (
    couette_study,
    density_study,
    exact_vs_approximate,
    flight_and_rig_study,
    hole_radius_study,
    rig_spin_study,
)
from .opening_times import fig43_study, opening_time_minimum, opening_time_vs_spin
from .render import report_context, to_html, to_markdown
from .rows import Row, checkable_rows

__all__ = ["Row", "ReproduceResult", "checkable_rows", "reproduce", "to_html", "to_markdown"]

#: Relative cost of reproduce's validation step and of its figures step against one
#: thesis study (the unit of the progress display's time left), in quick and full
#: mode alike: the validation fits all 54 runs (its cost is most of the run's).
VALIDATION_WEIGHT = 300.0
FIGURES_WEIGHT = 30.0


@field_docs
@dataclass
class ReproduceResult:
    """What :func:`reproduce` wrote and computed."""

    #: Directory the figures and reports were written to.
    out_dir: Path
    #: Paths of the figures (PNG) written, those of the added sections included.
    figures: list[Path]
    #: Path of the Markdown report, ``report.md``.
    report_md: Path
    #: Path of the self-contained HTML report, ``report.html``.
    report_html: Path
    #: The comparison table: each checked quantity, thesis value against computed.
    rows: list[Row]
    #: The exact-model calibration of mu_s to the thesis runs (an
    #: :class:`~obturator.calibration.ExactFit`).
    fit: Any
    #: Wall time of the whole run [s].
    elapsed_s: float
    #: The study Datasets by name.
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
                "theta0_deg_values": (TABLE1["theta0_deg"],),
                "spin_rates": np.geomspace(80.0, 700.0, 8),
            },
            "fit": {
                "bootstrap": 40,
                "table": cal.TableSettings(resolution=1.5, max_points=16, verify=3),
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
            lambda: couette_study(n_points=n, options=options),
        ),
        (
            "couette_caption",
            "Fig. 9 with the caption's S",
            lambda: couette_study((1.0,), base="caption", n_points=n, options=options),
        ),
        (
            "flight_rig",
            "Figs. 13-14",
            lambda: flight_and_rig_study(n_points=n, options=options),
        ),
        ("fig15", "Fig. 15", lambda: exact_vs_approximate(n_points=n, options=options)),
        ("density", "Fig. 16", lambda: density_study(n_points=n, options=options)),
        ("hole", "Fig. 17", lambda: hole_radius_study(n_points=n, options=options)),
        ("rig_spin", "Figs. 32-37", lambda: rig_spin_study(n_points=n, options=options)),
        (
            "approx_mu",
            "Figs. 38, 39, 42 (Eq. 92)",
            # 0.35 first: Fig. 38 draws the first mu_s (Table 1)
            lambda: opening_time_vs_spin(s["spins"], mu_s_values=(0.35, 0.1, 0.25, 0.55)),
        ),
        (
            "approx_theta0",
            "Figs. 40-41 (Eq. 92)",
            lambda: opening_time_vs_spin(
                s["spins"],
                mu_s_values=(0.35,),
                theta0_deg_values=(75.0, 80.0, 85.0, TABLE1["theta0_deg"]),
            ),
        ),
        (
            "exact_mu",
            "Figs. 39, 42 (exact)",
            lambda: opening_time_vs_spin(
                s["exact_spins"], mu_s_values=mus, method="exact", options=options
            ),
        ),
        (
            "fig43",
            "Fig. 43",
            lambda: fig43_study(spin_rates=s["fig43_spins"], options=options),
        ),
        (
            "minimum",
            "t_cr minimum, mu_s = 0.5473",
            lambda: opening_time_minimum(THESIS_MU_S, n_grid=s["min_grid"], options=options),
        ),
        (
            "minimum_table1",
            "t_cr minimum, mu_s = 0.35",
            lambda: opening_time_minimum(0.35, n_grid=s["min_grid"], options=options),
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
    exact = opening_times([rig_case(w, THESIS_MU_S) for w in spins], options, strict=True)[0]
    approx = opening_time_vs_spin(list(spins), mu_s_values=(THESIS_MU_S,))["t_cr"].values.ravel()
    return {w: (float(ex), float(ap)) for w, ex, ap in zip(spins, exact, approx, strict=True)}


# ---------------------------------------------------------------------------
# figures


def _figures(res: dict[str, Any]) -> list[tuple[str, str, Callable[[], Any]]]:
    from .. import plotting as pl

    data = cal.load_thesis_data()
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


# ---------------------------------------------------------------------------
# driver


def reproduce(
    out_dir: str | Path,
    *,
    quick: bool = False,
    runner: Runner | None = None,
    options: SolverOptions | None = None,
    command: str | None = None,
    envelope: bool = False,
    validation: bool = True,
    design: bool = False,
) -> ReproduceResult:
    """Run every study, write the figures (PNG) and report.md / report.html into `out_dir`.

    Parameters
    ----------
    out_dir : str or Path
        Created if missing.
    quick : bool
        Fewer points, a smaller bootstrap (for tests and a first look).
    runner : Runner, optional
        Progress display and the workers of the validation and envelope sections
        (:class:`obturator.runs.Runner`; default two workers, no progress display).
    options : SolverOptions, optional
        Solver settings for every exact run (default :class:`SolverOptions`).
    command : str, optional
        The command line, recorded in the report's provenance.
    validation : bool
        Add the validation section (:mod:`obturator.validation.report`: every candidate
        fitted to all 54 runs; quick mode: three candidates, Wald intervals), with
        ``validation.png`` and ``validation.json``.
    envelope : bool
        Add the firing-envelope section (:mod:`obturator.envelope.report`: t_cr map
        over muzzle Mach x altitude and flight Sobol indices; about 1 minute).
    design : bool
        Add the experiment-design section (:mod:`obturator.design.report`: the campaign
        that decides between the validation's leading mechanisms and its decision curve,
        reusing the validation section's fits), with ``design.png`` and ``design.json``.

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

    runner = runner or Runner(workers=2)
    if runner.store is not None:  # finished studies kept in report.partial.jsonl
        identity = {"study": "reproduce", "version": __version__, "quick": quick}
        identity |= {"options": opts, "validation": validation}
        runner.open(study_digest(identity))
    quiet = replace(runner, progress=Progress("off"))  # one display at a time: the report's
    # the envelope and design sections are separate studies, run without the store
    storeless = replace(quiet, store=None, sidecar=None)
    total = len(tasks) + 1 + int(validation)
    # the progress lines' time left is that of the whole run: each step weighted by its
    # relative cost (a thesis study = 1; measured with obturator reproduce, piped)
    weights = [1.0] * len(tasks) + [VALIDATION_WEIGHT] * int(validation) + [FIGURES_WEIGHT]
    runner.reporter.plan(
        "reproduce",
        f"{len(tasks)} thesis studies"
        + (", the validation study" if validation else "")
        + (", the envelope section" if envelope else "")
        + f" and the figures on {runner.n_workers} worker(s)"
        + ("; about a minute" if quick else "; several minutes"),
    )
    with runner.reporter.track("reproduce", total, unit="steps", weights=weights) as step:

        def run(key: str, label: str, fn: Callable[[], Any]) -> Any:
            step.describe(label)
            value = runner.memo({"study": key}, fn)  # from the store after an interruption
            step(1)
            return value

        for key, label, fn in tasks:
            res[key] = run(key, label, fn)
        if validation:
            from ..validation.report import run_for_report

            # its fits go to the same store one by one, so an interruption inside it
            # keeps the finished fits too
            res["validation"] = run(
                "validation", "validation (all 54 runs)", lambda: run_for_report(quick, quiet)
            )
        figs = _figures(res)
        step.describe("figures")
        paths.extend(save(make(), out / name) for name, _, make in figs)
        step(1)
    from .explorer import explorer_html

    rows = checkable_rows(res)
    elapsed = time.perf_counter() - t0
    ctx = report_context(rows, res, [(n, c) for n, c, _ in figs], opts, quick, elapsed, command)
    if validation:
        from ..validation.report import validation_section

        vsec = validation_section(res["validation"], out, quick=quick)
        ctx["sections"].append(vsec)
        paths.extend(out / name for name, _ in vsec.figures)
    if envelope:
        from ..envelope.report import envelope_section

        section = envelope_section(out, quick=quick, runner=storeless)
        ctx["sections"].append(section)
        paths.extend(out / name for name, _ in section.figures)
    if design:
        from ..design.report import design_section

        fits = {m.name: m.fit for m in res["validation"].models} if validation else None
        dsec = design_section(out, quick=quick, runner=storeless, fits=fits)
        ctx["sections"].append(dsec)
        paths.extend(out / name for name, _ in dsec.figures)
    ctx["images"] = {p.name: base64.b64encode(p.read_bytes()).decode("ascii") for p in paths}
    ctx["explorer"] = explorer_html(res["explorer"]) + _animations(options)
    md, hp = out / "report.md", out / "report.html"
    # whole or absent, also on a full disk; then the store goes (kept if a write fails)
    runner.write_outputs(
        [
            (md, lambda path: atomic_write_text(path, to_markdown(ctx))),
            (hp, lambda path: atomic_write_text(path, to_html(ctx))),
        ]
    )
    return ReproduceResult(out, paths, md, hp, rows, res["fit"], elapsed, res)


#: Rig runs animated in the report [rad/s]: near the t_cr minimum, where the ball sticks
#: and slips after release, and fast spin, where it slips from the start.
ANIMATED_SPINS = (150.0, 400.0)


def _animations(options: SolverOptions | None) -> str:
    """The opening of selected rig runs (Table 1, the thesis's mu_s) as animations: the
    ball in its bore, theta(t), a time slider (:mod:`obturator.animation`; the report's
    plotly.js, inlined once by the explorer, draws them)."""
    from ..animation import animation_html

    parts = [
        "<h2>The opening, animated</h2>",
        "<p>The ball in the projectile's bore, seen in the projectile's frame, from release "
        "to first light (theta = theta_cr = beta_s), beside theta(t): move the slider or "
        f"press play. Spin rig, Table 1, mu_s = {THESIS_MU_S}.</p>",
    ]
    for w in ANIMATED_SPINS:
        run = simulate(rig_case(spin_rate=w, mu_s=THESIS_MU_S), options)
        parts.append(
            animation_html(run, div_id=f"opening-{w:.0f}", include_plotlyjs=False, n_frames=60)
        )
    return "\n".join(parts)
