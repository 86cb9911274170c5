"""``python -m benchmarks report`` rewrites the measured blocks of docs/benchmarks.md and
nothing else (issue 44, item 5): formatting, the rewrite, and one cheap section end to end."""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # benchmarks/ lives at the root

from benchmarks import report  # noqa: E402
from benchmarks.run import main as benchmarks_main  # noqa: E402

DOC = """# Benchmarks

Intro, kept.

<!-- measured: machine -->
old machine table
<!-- /measured: machine -->

Between, kept: `<!-- measured: machine -->` quoted inline is not a marker.

<!-- measured: imports -->
old imports table
<!-- /measured: imports -->

<!-- history -->
## History

<!-- measured: stale -->
an old block in the history, never rewritten
<!-- /measured: stale -->
"""


@pytest.mark.parametrize(
    ("value", "kind", "shown"),
    [
        (0.012345, "ms", "12.3"),
        (1.5, "ms", "1500"),
        (0.000123, "ms", "0.123"),
        (310.0, "num", "310"),
        (0.0789, "num", "0.0789"),
        (1.234, "ratio", "1.23x"),
        (1.3e-3, "error", "1.3e-03"),
        (0.0, "error", "0"),
        (12345, "int", "12,345"),
        (True, "yes/no", "yes"),
        (float("nan"), "num", "-"),
        (None, "ms", "-"),
        ("rig", "text", "rig"),
    ],
)
def test_format_value(value, kind, shown):
    assert report.format_value(value, kind) == shown


def test_markdown_table():
    cols = (report.Column("case", "case"), report.Column("wall_s", "wall [ms]", "ms"))
    got = report.markdown_table([{"case": "rig", "wall_s": 0.00052}, {"case": "flight"}], cols)
    assert got == "| case | wall [ms] |\n|:---|---:|\n| rig | 0.520 |\n| flight | - |"


def test_rewrite_replaces_only_the_named_blocks():
    block = "<!-- measured: imports -->\nNEW\n<!-- /measured: imports -->"
    new = report.rewrite(DOC, {"imports": block})
    assert new == DOC.replace("old imports table", "NEW")


def test_rewrite_refuses_a_missing_block_and_one_in_the_history():
    with pytest.raises(ValueError, match="0 blocks of section 'trajectory'"):
        report.rewrite(DOC, {"trajectory": ""})
    with pytest.raises(ValueError, match="in the history"):
        report.rewrite(DOC, {"stale": ""})


def test_every_section_has_its_block_in_the_document_above_the_history():
    text = report.DOC.read_text(encoding="utf-8")
    new = report.rewrite(text, {n: f"[block {n}]" for n in report.SECTIONS})
    assert all(f"\n[block {n}]\n" in new for n in report.SECTIONS)
    assert text.count("\n<!-- history -->\n") == 1


def test_report_command_rewrites_a_cheap_section(tmp_path, monkeypatch):
    """`python -m benchmarks report --only machine,imports --quick --doc PATH`: the two
    blocks are measured and rewritten with their stamp; the rest of the file is kept."""
    doc = tmp_path / "benchmarks.md"
    doc.write_text(DOC, encoding="utf-8")
    section = report.SECTIONS["imports"]  # one module: one fresh interpreter
    monkeypatch.setitem(report.SECTIONS, "imports", replace(section, measure=_one_import))
    argv = ["report", "--quick", "--only", "machine,imports", "--doc", str(doc)]
    assert benchmarks_main(argv) == 0
    text = doc.read_text(encoding="utf-8")
    head, history = text.split("<!-- history -->")
    assert history == DOC.split("<!-- history -->")[1]
    assert "Intro, kept." in head and "Between, kept:" in head
    assert "old machine table" not in head and "old imports table" not in head
    assert "with --quick: `python -m benchmarks report --only machine`." in head
    assert "| module | import [ms] |" in head and "| json |" in head
    assert "| cpus_available |" in head


def _one_import(quick: bool) -> list[dict]:
    from benchmarks import imports

    return imports.cost(("json",), repeat=1)


def test_report_command_reports_a_missing_block_and_leaves_the_file(tmp_path, capsys):
    doc = tmp_path / "benchmarks.md"
    doc.write_text(DOC, encoding="utf-8")
    assert benchmarks_main(["report", "--only", "trajectory", "--doc", str(doc)]) == 2
    assert "0 blocks of section 'trajectory'" in capsys.readouterr().err
    assert doc.read_text(encoding="utf-8") == DOC
