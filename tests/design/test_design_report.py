"""The experiment-design section of the reproduction report (quick mode; about a minute:
the two candidates are fitted to the 54 runs of Appendix B)."""

from __future__ import annotations

import pytest

from obturator.design.report import design_section
from obturator.runs import Runner
from obturator.thesis.render import to_markdown


@pytest.mark.slow
def test_design_section_renders_in_the_report(tmp_path):
    sec = design_section(tmp_path, quick=True, runner=Runner(workers=1))
    assert (tmp_path / "design.png").stat().st_size > 10_000
    assert (tmp_path / "design.json").is_file()
    text = " ".join(sec.paragraphs)
    assert "Recommended campaign" in text and "Box-Hill" in text
    assert "P(decisive" in sec.pre[1]
    ctx = {
        "mode": "quick",
        "elapsed": 0.0,
        "rows": [],
        "flagged": [],
        "fit_text": "",
        "figures": [],
        "sections": [sec],
        "provenance": [],
        "versions": {},
        "solver": [],
    }
    md = to_markdown(ctx)
    assert "## Which experiment decides between the mechanisms" in md
    assert "![Experiment design" in md
