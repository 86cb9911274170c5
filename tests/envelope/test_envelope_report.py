"""``reproduce --envelope``: the firing-envelope section of the report."""

from __future__ import annotations

import re

from obturator.envelope.report import envelope_section
from obturator.thesis.render import report_context, to_html, to_markdown


def test_envelope_section_writes_its_figures_and_counts(tmp_path):
    sec = envelope_section(tmp_path, quick=True)
    for name, _ in sec.figures:
        assert (tmp_path / name).stat().st_size > 1000
    text = sec.paragraphs[0]
    met, n = map(int, re.search(r"within 0.1 s at (\d+) of (\d+) points", text).groups())
    assert n == 12 and 0 < met <= n
    # the coupled load slows the projectile, so the opening can only come later
    lo = float(re.search(r"delays the opening by (-?[\d.]+) %", text).group(1))
    assert lo > 0.0


def test_sections_render_in_markdown_and_html(tmp_path):
    from obturator.envelope.report import EnvelopeSection
    from obturator.solve import SolverOptions

    class _Fit:
        def report(self) -> str:
            return "fit"

    ctx = report_context([], {"fit": _Fit()}, [], SolverOptions(), True, 1.0)
    ctx["sections"].append(EnvelopeSection("Extra", ("first", "second"), (("a.png", "cap"),)))
    md, html = to_markdown(ctx), to_html(ctx)
    assert "## Extra\n\nfirst\n" in md and "![cap](a.png)" in md
    assert "<h2>Extra</h2><p>first</p><p>second</p>" in html and 'data-file="a.png"' in html
