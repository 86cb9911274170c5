"""Every console block of README.md and the docs pages against what the code prints now.

``tools/readme_blocks.py`` produces each block (``python tools/readme_blocks.py --write``
rewrites them all); here each block is rerun and compared line by line, with the
block's machine-dependent parts masked (timings, worker counts) and near-stick digits
compared to the block's stated relative tolerance. Each block's cost and whether it is
slow: ``python tools/readme_blocks.py --list`` (the blocks' own record, not repeated
here). The validate run is shared with the whole-study checks of the validation tests
(``readme_validate_run`` in ``tests/conftest.py``), so CI pays for it once.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tools"))
import readme_blocks as rb  # noqa: E402

#: Blocks checked only with ``OBTURATOR_README_ALL=1`` (none: CI checks every block).
HEAVY: tuple[str, ...] = ()


def _marks(name: str) -> list:
    marks = [pytest.mark.slow] if rb.BLOCKS[name].slow else []
    if name in HEAVY:
        marks.append(
            pytest.mark.skipif(
                not os.environ.get("OBTURATOR_README_ALL"),
                reason=f"{name}: {rb.BLOCKS[name].cost}; set OBTURATOR_README_ALL=1",
            )
        )
    return marks


@pytest.mark.parametrize("name", [pytest.param(n, marks=_marks(n)) for n in rb.BLOCKS])
def test_readme_block_is_what_the_code_prints(name, request):
    page = rb.page_of(name)
    text = page.read_text(encoding="utf-8")
    if name == "validate":  # the run the whole-study checks of the validation tests share
        fresh = request.getfixturevalue("readme_validate_run")[0]
    else:
        fresh = rb.fresh_output(name)
    diff = rb.differences(rb.block_text(text, name), fresh, rb.BLOCKS[name])
    assert not diff, (
        f"block {name!r} of {page.name} drifted from the code; regenerate it with "
        f"'python tools/readme_blocks.py --write --only {name}':\n" + "\n".join(diff)
    )


def test_every_console_block_has_a_generator():
    """Every console block of the README and the docs pages has a marker and a generator,
    each block once (a block moved to a docs page keeps its check)."""
    for page in rb.pages():
        lines = page.read_text(encoding="utf-8").splitlines()
        consoles = [i for i, line in enumerate(lines) if line.startswith("```console")]
        assert all(rb.MARKER.match(lines[i - 1]) for i in consoles), page
    assert set(rb.page_blocks()) == set(rb.BLOCKS)
    assert rb.page_of("simulate") == rb.README  # the worked example stays in the README


def test_readme_is_short_and_the_root_holds_no_scratch_files():
    """The README is what it is, the quick start, one worked example and links (at most
    250 lines; the rest lives in docs/), and no stray figures sit at the root."""
    assert len(rb.README.read_text(encoding="utf-8").splitlines()) <= 250
    assert not sorted(p.name for p in rb.ROOT.glob("*.png"))


def test_a_block_on_two_pages_is_refused(tmp_path, monkeypatch):
    a, b = tmp_path / "README.md", tmp_path / "docs" / "x.md"
    b.parent.mkdir()
    block = "<!-- readme-block: sweep -->\n```console\n$ obturator x\n```\n"
    a.write_text(block, encoding="utf-8")
    b.write_text(block, encoding="utf-8")
    monkeypatch.setattr(rb, "README", a)
    monkeypatch.setattr(rb, "DOCS", b.parent)
    with pytest.raises(ValueError, match="two pages"):
        rb.page_blocks()


def test_comparison_masks_times_and_honours_the_tolerance():
    block = rb.Block(("obturator x",), rtol=1e-4)
    same = "$ obturator x\nt_cr 42.7232 s in 0.553 s on 2 workers (36.2 points/s)"
    moved = "$ obturator x\nt_cr 42.7233 s in 2.72 s on 1 worker (7.36 points/s)"
    assert rb.differences(same, moved, block) == []  # 2e-6 relative, timings masked
    assert rb.differences(same, moved.replace("42.7233", "42.80"), block)
    assert rb.differences(same, moved.replace("t_cr", "t_op"), block)
    assert rb.differences(same, same + "\nmore", block)


def test_excerpt_marks_each_gap_once():
    lines = ["a 1", "b", "c", "a 2", "d"]
    assert rb.excerpt(lines, (r"^a",)) == ["a 1", "...", "a 2", "..."]
    assert rb.excerpt(lines, ()) == lines
