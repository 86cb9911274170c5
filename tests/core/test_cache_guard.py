"""A damaged compiled-code cache is set aside and recompiled (obturator.core.cache_guard).

Each kind of numba cache file (the index ``.nbi`` and the data ``.nbc``) is
truncated, emptied and has a byte flipped, as a full disk or a kill during
``obturator warmup`` leaves it; the next run must give the right answer with one
notice line, the damaged folder kept aside, and the run after it no notice at all.
A tiny jitted module stands in for the integrators (same cache machinery, a
second of compile time instead of minutes).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

_MODULE = """
from numba import njit


@njit(cache=True)
def plus_one(x):
    return x + 1.0
"""
_SCRIPT = """
import sys
sys.path.insert(0, {folder!r})
from obturator.core.cache_guard import install
install()
import guarded_mod
print(guarded_mod.plus_one(41.0))
"""


def _run(folder: Path, cache: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    return subprocess.run(
        [sys.executable, "-c", _SCRIPT.format(folder=str(folder))],
        capture_output=True,
        text=True,
        timeout=120,
        env=env,
    )


def _damage(path: Path, how: str) -> None:
    data = path.read_bytes()
    if how == "truncated":
        path.write_bytes(data[: len(data) // 2])
    elif how == "emptied":
        path.write_bytes(b"")
    else:  # one flipped byte in the middle: still unpickles, or not; the seal tells
        k = len(data) // 2
        path.write_bytes(data[:k] + bytes([data[k] ^ 0xFF]) + data[k + 1 :])


@pytest.mark.parametrize("how", ["truncated", "emptied", "flipped"])
@pytest.mark.parametrize("suffix", [".nbi", ".nbc"])
def test_damaged_cache_file_is_set_aside_and_recompiled(tmp_path: Path, suffix: str, how: str):
    (tmp_path / "guarded_mod.py").write_text(_MODULE, encoding="utf-8")
    cache = tmp_path / "cache" / "obturator" / "numba" / "test"
    first = _run(tmp_path, cache)
    assert first.returncode == 0 and first.stdout.strip() == "42.0", first.stderr
    files = sorted(cache.rglob(f"*{suffix}"))
    assert len(files) == 1
    _damage(files[0], how)
    second = _run(tmp_path, cache)
    assert second.returncode == 0, second.stderr
    assert second.stdout.strip() == "42.0"
    notices = [ln for ln in second.stderr.splitlines() if ln.startswith("obturator: notice:")]
    assert len(notices) == 1 and "damaged" in notices[0], second.stderr
    assert "Traceback" not in second.stderr
    aside = [p for p in cache.iterdir() if ".damaged-" in p.name]
    assert len(aside) == 1  # kept for inspection
    third = _run(tmp_path, cache)
    assert third.returncode == 0 and third.stdout.strip() == "42.0"
    assert "notice" not in third.stderr  # the fresh cache is whole


def test_other_packages_caches_are_left_alone(tmp_path: Path):
    (tmp_path / "guarded_mod.py").write_text(_MODULE, encoding="utf-8")
    cache = tmp_path / "shared-cache"  # not ours: no seal written, numba's own format
    assert _run(tmp_path, cache).returncode == 0
    (index,) = cache.rglob("*.nbi")
    from obturator.core.cache_guard import SEAL

    assert SEAL not in index.read_bytes()
