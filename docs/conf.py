"""Sphinx configuration of the obturator documentation.

Build (warnings are errors, as in CI): ``sphinx-build -W -b html docs docs/_build/html``.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))
sys.path.insert(0, str(HERE.parent / "src"))  # the checkout's package, installed or not

import obturator  # noqa: E402

project = "obturator"
author = "obturator contributors"
copyright = "obturator contributors, MIT licence"  # noqa: A001 - Sphinx's name
version = release = obturator.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "obturator_docs",
]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build", "_generated", "gallery/*.py"]
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3
suppress_warnings = ["myst.header"]  # moved pages start their sections where the README did

autosummary_generate = True
autodoc_default_options: dict[str, object] = {}  # module pages: their docstring only
autodoc_typehints = "none"  # the numpydoc sections state types and units
numpydoc_show_class_members = False
numpydoc_validation_checks: set[str] = set()
numpydoc_xref_param_type = False

html_theme = "pydata_sphinx_theme"
html_title = f"obturator {release}"
html_theme_options = {"navigation_with_keys": False, "show_toc_level": 2}

_LITERAL = re.compile(r"(``.+?``|`[^`]+`_?)")
_GRID = re.compile(r"^\s*\+[-=]{3,}")


def _plain_text_math(app, what, name, obj, options, lines) -> None:  # noqa: ANN001
    """The docstrings write magnitudes as plain text, ``|omega_r|``, and NumPy types as
    ``np.bool_``: to reStructuredText those are substitutions and link targets. Escape
    them outside literals (the text reads the same in ``help()`` and on the page)."""
    if any(_GRID.match(line) for line in lines):
        return
    for i, line in enumerate(lines):
        parts = _LITERAL.split(line)
        for k in range(0, len(parts), 2):  # even parts: outside literals and roles
            parts[k] = re.sub(r"(?<!\\)\|", r"\\|", parts[k])
            parts[k] = re.sub(r"\b(np\.\w+?)_(?=[\s,.;)\]]|$)", r"\1\\_", parts[k])
        lines[i] = "".join(parts)


def setup(app) -> None:  # noqa: ANN001
    app.connect("autodoc-process-docstring", _plain_text_math, priority=900)
