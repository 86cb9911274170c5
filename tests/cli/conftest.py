"""Command-line tests run in a temporary folder: an output option fuzzed with its bare
example value (``theta.csv``) must not write into the checkout."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True)
def _in_tmp_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
