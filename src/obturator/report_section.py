"""One section the studies add to the reproduction report (``obturator reproduce``).

The validation, firing-envelope and experiment-design studies each return one; the
report renders its title, paragraphs, preformatted blocks and figures in that order.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["ReportSection"]


@dataclass(frozen=True)
class ReportSection:
    """A report section: title, paragraphs, preformatted blocks and (file, caption) figures."""

    title: str
    paragraphs: tuple[str, ...]
    figures: tuple[tuple[str, str], ...]
    pre: tuple[str, ...] = ()
