"""The documentation site builds warning-free (``sphinx-build -W``), as CI builds it.

Sphinx with the pydata theme, MyST Markdown pages and the API reference rendered from
the numpydoc docstrings (``docs/conf.py``). The build runs the ``obturator-help``
directive (every command page shows the parser's own help) and the gallery's one
quick script. The pages' Python sessions run in ``tests/test_doctests.py`` and their
console blocks in ``tests/test_readme.py``. Without Sphinx the test skips, except in CI
(``.[test]`` installs it), where it fails.
"""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.slow  # about a minute and a half on a loaded 2-core machine


def test_docs_build_without_warnings(tmp_path):
    if importlib.util.find_spec("sphinx") is None:
        if os.environ.get("CI"):
            pytest.fail("Sphinx is required in CI (pip install '.[test]')")
        pytest.skip("Sphinx is not installed (pip install '.[docs]')")
    out = tmp_path / "html"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "src"), *sys.path]))
    res = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html"]
        + ["docs", str(out)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=900,
        check=False,
    )
    assert res.returncode == 0, (res.stdout + res.stderr)[-4000:]
    # the API reference is rendered from the numpydoc sections
    api = (out / "api" / "obturator.simulate.html").read_text(encoding="utf-8")
    assert "Parameters" in api and "Returns" in api
    # each command's page carries its own --help (the option the animation added included)
    page = (out / "commands" / "simulate.html").read_text(encoding="utf-8")
    assert "usage: obturator simulate" in page and "--animate" in page
    # every console block a page shows travelled with it, and the gallery drew its figure
    study = (out / "studies" / "validation.html").read_text(encoding="utf-8")
    assert "$ obturator validate --out validation" in re.sub(r"<[^>]+>", "", study)
    assert (out / "_images" / "theta_rig_200.png").stat().st_size > 10_000
