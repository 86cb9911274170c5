"""Rendering the reproduction report: Markdown and a self-contained HTML page.

Both are made from the same context (rows, figures, fit report, provenance),
with no Markdown-to-HTML conversion and no extra dependency.
"""

from __future__ import annotations

import html
import platform
from importlib.metadata import PackageNotFoundError, version
from typing import Any

from ..solve import SolverOptions
from .rows import HEADER, Row

__all__ = ["report_context", "to_html", "to_markdown"]


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
        f"command: {command or 'obturator.thesis.reproduce() from Python'}",
        f"machine: {platform.platform()}, {platform.machine()}, {os.cpu_count()} CPUs",
    ]


def _solver_lines(options: SolverOptions) -> list[str]:
    auto = (
        " (per case: the set-valued solver, no width, where the stick ratio |G_req| / M at "
        "release is low; the regularised law elsewhere)"
        if options.method == "auto"
        else ""
    )
    return [
        f"method = {options.method}{auto}",
        f"rtol = {options.rtol:g}, atol = {options.atol:g} (rates in units of omega_p0)",
        f"friction regularisation width = {options.friction_width:g} omega_p0, "
        f"family = {options.friction_family} (magnitude only; the moment arm uses the "
        "true slip direction; regularised cases only)",
        f"formulation = {options.formulation}",
        f"event location tolerance = {options.event_tol:g} s",
        "projectile spin held constant (driven rig; thesis gravity runs)",
    ]


def report_context(
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
        "sections": [],  # extra sections: objects with title, paragraphs, figures
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
    for sec in ctx.get("sections", ()):
        out += [f"## {sec.title}", "", *[f"{p}\n" for p in sec.paragraphs]]
        out += [f"```\n{block}\n```\n" for block in getattr(sec, "pre", ())]
        out += [f"![{cap}]({name})\n" for name, cap in sec.figures]
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
    sections = "\n".join(
        f"<h2>{e(sec.title)}</h2>"
        + "".join(f"<p>{e(p)}</p>" for p in sec.paragraphs)
        + "".join(f"<pre>{e(block)}</pre>" for block in getattr(sec, "pre", ()))
        + "".join(
            f'<figure class="wide"><img src="{src(n)}" alt="{e(c)}" data-file="{e(n)}">'
            f"<figcaption><b>{e(c)}.</b></figcaption></figure>"
            for n, c in sec.figures
        )
        for sec in ctx.get("sections", ())
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
figure.wide {{ display: block; max-width: 100%; }}
figure.wide img {{ max-width: 100%; }}
.explorer {{ width: 100%; }}
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
{sections}
<h2>Provenance</h2><ul>{provenance}</ul>
<h2>Versions</h2><ul>{versions}</ul>
<h2>Solver settings</h2><ul>{solver}</ul>
</body></html>
"""
