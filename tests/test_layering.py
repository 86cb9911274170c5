"""The package's layers: what each subpackage may import (every import, lazy ones included).

The numeric core (``core/``) is numba code over plain floats and imports only the
package's leaf vocabularies; the model, the solver and the physics of the flow know
nothing of files, the command line, studies or plots; only the command line imports
``cli``. A forbidden import found here is a design regression, not a style issue.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PKG = Path(__file__).resolve().parents[1] / "src" / "obturator"
EDGE = (
    "cli",
    "io",
    "files",
    "sweeps",
    "thesis",
    "plotting",
    "animation",
    "validation",
    "envelope",
    "runs",
)
#: The studies: each may import ``runs`` (the runner of its tasks); ``runs`` imports none.
STUDIES = ("sweeps", "thesis", "validation", "envelope", "calibration", "design")

# module prefix (relative to obturator) -> obturator subpackages/modules it must not import
FORBIDDEN: dict[str, tuple[str, ...]] = {
    "core": (
        *EDGE,
        "model",
        "solve",
        "result",
        "flow",
        "calibration",
        "approx",
        "units",
        "fitting",
    ),
    "status": (*EDGE, "core", "model", "solve"),
    "vocab": (*EDGE, "core", "model", "solve"),
    "errors": (*EDGE, "core", "model", "solve"),
    "params": (*EDGE, "core", "model", "solve"),
    # leaf helpers of the vocabulary: docstring fragments, JSON numbers, a report section
    "_docs": (*EDGE, "core", "model", "solve"),
    "json_values": (*EDGE, "core", "model", "solve"),
    "report_section": (*EDGE, "core", "model", "solve"),
    "reference": (*EDGE, "core", "model", "solve", "calibration"),
    "model": (*EDGE, "solve", "result", "calibration", "fitting"),
    "solve": (*EDGE, "calibration", "fitting"),
    # the fit engine and registry: numpy/scipy over the vocabulary (params); what it
    # fits is the studies' business
    "fitting": (*EDGE, "core", "model", "solve", "result", "flow", "approx", "calibration"),
    "result": (*EDGE, "calibration"),
    "approx": (*EDGE, "calibration", "solve"),
    "flow": (*EDGE, "core", "model", "solve", "calibration"),
    "units": (*EDGE, "core", "model", "solve"),
    # the studies reach the integrators only through solve (one front door for many t_cr)
    "calibration": ("cli", "io", "sweeps", "thesis", "plotting", "validation", "envelope", "core"),
    "sweeps": ("cli", "thesis", "plotting", "calibration", "validation", "envelope", "core"),
    "thesis": ("cli", "sweeps", "core"),
    "validation": ("cli", "thesis", "envelope", "core"),
    "envelope": ("cli", "thesis", "validation", "calibration", "core"),
    # the experiment design builds on the validation's candidates, fits and floor
    "design": ("cli", "thesis", "envelope", "sweeps", "core"),
    "plotting": ("cli", "sweeps"),
    # the opening animation draws one result (the report's selected runs use it too)
    "animation": ("cli", "sweeps", *STUDIES, "core", "runs"),
    "warmup": (*EDGE, "calibration"),
    "io": ("cli", "core", "sweeps", "thesis", "plotting"),
    # files at the edge (readers, output checks, writers): below every user of files
    "files": ("cli", "io", "core", "model", "solve", "runs", *STUDIES, "plotting"),
    # the runner of every study's tasks: execution and storage only (files for writing)
    "runs": ("cli", "io", "plotting", *STUDIES, "core", "model", "solve", "result", "flow"),
}


def _module_name(path: Path) -> str:
    rel = path.relative_to(PKG).with_suffix("")
    parts = [p for p in rel.parts if p != "__init__"]
    return ".".join(parts)


def _imports(path: Path) -> set[str]:
    """Every obturator module a file imports, relative to the package ("core.dynamics")."""
    name = _module_name(path)
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - (node.level - 1)]
                target = ".".join([*base, node.module] if node.module else base)
            elif node.module and node.module.startswith("obturator"):
                target = node.module.removeprefix("obturator").lstrip(".")
            else:
                continue
            if node.module is None or target == ".".join(package):
                out.update(f"{target}.{a.name}".lstrip(".") for a in node.names)
            else:
                out.add(target)
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.startswith("obturator."):
                    out.add(a.name.removeprefix("obturator."))
    return out


MODULES = sorted(p for p in PKG.rglob("*.py"))


@pytest.mark.parametrize("path", MODULES, ids=lambda p: _module_name(p) or "__init__")
def test_layers(path: Path) -> None:
    name = _module_name(path)
    imported = _imports(path)
    if name not in ("cli", "__main__") and not name.startswith("cli."):
        assert not any(m == "cli" or m.startswith("cli.") for m in imported), imported
    for prefix, banned in FORBIDDEN.items():
        if name == prefix or name.startswith(prefix + "."):
            bad = sorted(
                m for m in imported if any(m == b or m.startswith(b + ".") for b in banned)
            )
            assert not bad, f"{name} imports {bad}"


def test_every_subpackage_has_a_rule() -> None:
    top = {_module_name(p).split(".")[0] for p in MODULES} - {"", "__main__", "cli", "_provenance"}
    assert top <= set(FORBIDDEN) | {"plotting", "io"}, top - set(FORBIDDEN)


def test_no_source_file_is_huge() -> None:
    """One concern per file: none over about 600 lines."""
    sizes = {_module_name(p): len(p.read_text(encoding="utf-8").splitlines()) for p in MODULES}
    assert max(sizes.values()) <= 600, {k: n for k, n in sizes.items() if n > 600}
