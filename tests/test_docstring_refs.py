"""Every fully qualified cross-reference in the package's docstrings resolves.

A reference such as ``:func:`obturator.solve.opening_times``` names a module path;
after a file moves (the flat layout into subpackages) a stale one silently points
nowhere. Each ``obturator.``-qualified target of a ``:mod:``, ``:func:``, ``:class:``,
``:meth:``, ``:data:``, ``:attr:`` or ``:exc:`` role in ``src/`` must import, attribute
by attribute.
"""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "obturator"
_ROLE = re.compile(r":(?:mod|func|class|meth|data|attr|exc|obj):`~?(obturator(?:\.\w+)+)`")


def _targets() -> list[tuple[str, str]]:
    out = set()
    for path in sorted(SRC.rglob("*.py")):
        for target in _ROLE.findall(path.read_text(encoding="utf-8")):
            out.add((target, str(path.relative_to(SRC))))
    return sorted(out)


def _resolves(target: str) -> bool:
    parts = target.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        try:
            for attr in parts[cut:]:
                obj = getattr(obj, attr)
        except AttributeError:
            return False
        return True
    return False


def test_there_are_references_to_check():
    assert len(_targets()) > 50


@pytest.mark.parametrize("target,where", _targets(), ids=lambda x: x)
def test_reference_resolves(target: str, where: str) -> None:
    assert _resolves(target), f"{where}: {target} does not resolve"
