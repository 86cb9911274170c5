"""The compiled core's cache is keyed by the source of every jitted module."""

import shutil
from pathlib import Path

import numba

from obturator.core import jit_cache as _jit_cache
from obturator.core.jit_cache import CORE_MODULES, core_digest


def test_digest_changes_when_any_core_module_changes(tmp_path):
    src = Path(_jit_cache.__file__).parents[1]  # the obturator package
    assert "core/dynamics.py" in CORE_MODULES and "core/integrators/radau.py" in CORE_MODULES
    for name in CORE_MODULES:
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(src / name, tmp_path / name)
    before = core_digest(tmp_path)
    assert before == core_digest()  # same bytes, same digest
    for name in CORE_MODULES:
        path = tmp_path / name
        text = path.read_text()
        path.write_text(text + "\n# edit\n")
        assert core_digest(tmp_path) != before, name
        path.write_text(text)
    assert core_digest(tmp_path) == before


def test_cache_dir_follows_digest_unless_user_sets_one(monkeypatch, tmp_path):
    old = numba.config.CACHE_DIR
    try:
        monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
        monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
        path = _jit_cache.configure_cache()
        assert path == str(tmp_path / "obturator" / "numba" / core_digest())
        assert numba.config.CACHE_DIR == path
        # the user's NUMBA_CACHE_DIR, as numba read it at start-up (numba.config)
        monkeypatch.setattr(numba.config, "CACHE_DIR", str(tmp_path / "mine"))
        assert _jit_cache.configure_cache() is None
    finally:
        numba.config.CACHE_DIR = old
