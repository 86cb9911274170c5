"""Every kind of damaged or unusable compiled-code cache: one notice, right answers, and
nothing written outside the cache folder (obturator.core.cache_guard).

A fuzz matrix over the cache's two kinds of file (the index ``.nbi`` and the data
``.nbc``) and the ways a file goes wrong: cut short at a seeded random length,
emptied, a seeded random byte flipped, swapped with the same kind of file of the
other function (each validly sealed), replaced by a folder, a FIFO, a link to a
device, or an unsealed file (plain numba's format); and the folder itself read-only,
impossible to create, or a file. A tiny module with two jitted functions stands in for
the integrators (same cache machinery, seconds instead of minutes); the answers are
x + 1 and 2 x, so a swapped function shows. Before the guard, swapped data files gave
plus_one(41) = 82 silently, and an unwritable cache put unsealed files beside the
module's source (numba's fallback to ``__pycache__``).
"""

from __future__ import annotations

import os
import random
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import obturator

_MODULE = """
from numba import njit


@njit(cache=True)
def plus_one(x):
    return x + 1.0


@njit(cache=True)
def times_two(x):
    return x * 2.0
"""
_SCRIPT = """
import sys
sys.path.insert(0, {folder!r})
from obturator.core.cache_guard import install
install()
import guarded_mod
print(guarded_mod.plus_one(41.0), guarded_mod.times_two(21.5))
"""
_RIGHT = "42.0 43.0"  # x + 1 at 41, 2 x at 21.5: by hand
_SUB = ("obturator", "numba", "test")  # under the package's own root: sealed


def _run(folder: Path, cache: Path) -> subprocess.CompletedProcess[str]:
    path = os.pathsep.join(
        [str(Path(obturator.__file__).parents[1]), os.environ.get("PYTHONPATH", "")]
    )
    env = {
        **os.environ,
        "NUMBA_CACHE_DIR": str(cache),
        "PYTHONDONTWRITEBYTECODE": "1",
        "PYTHONPATH": path,  # this checkout's package
    }
    return subprocess.run(
        [sys.executable, "-c", _SCRIPT.format(folder=str(folder))],
        capture_output=True,
        text=True,
        timeout=180,
        env=env,
    )


def _notices(done: subprocess.CompletedProcess[str]) -> list[str]:
    return [ln for ln in done.stderr.splitlines() if ln.startswith("obturator: notice:")]


def _nothing_beside_source(folder: Path) -> None:
    # the module's folder stands in for the installed package: numba's fallback
    # (``__pycache__`` beside the source) must never be taken
    assert sorted(p.name for p in folder.rglob("*")) == ["guarded_mod.py"]


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """The module's folder and a whole sealed cache of both functions."""
    folder = tmp_path_factory.mktemp("src")
    (folder / "guarded_mod.py").write_text(_MODULE, encoding="utf-8")
    cache = tmp_path_factory.mktemp("pristine").joinpath(*_SUB)
    done = _run(folder, cache)
    assert done.returncode == 0 and done.stdout.strip() == _RIGHT, done.stderr
    assert len(list(cache.rglob("*.nbi"))) == 2 and len(list(cache.rglob("*.nbc"))) == 2
    return folder, cache


def _copy(built: tuple[Path, Path], tmp_path: Path) -> Path:
    cache = tmp_path.joinpath(*_SUB)
    shutil.copytree(built[1], cache)
    return cache


def _damage(cache: Path, suffix: str, how: str, rng: random.Random) -> None:
    one, other = sorted(cache.rglob(f"*{suffix}"))
    data = one.read_bytes()
    if how == "truncated":
        one.write_bytes(data[: rng.randrange(len(data))])
    elif how == "emptied":
        one.write_bytes(b"")
    elif how == "flipped":
        k = rng.randrange(len(data))
        one.write_bytes(data[:k] + bytes([data[k] ^ (1 << rng.randrange(8))]) + data[k + 1 :])
    elif how == "swapped":  # both validly sealed, each under the other's name
        other_data = other.read_bytes()
        one.write_bytes(other_data)
        other.write_bytes(data)
    elif how == "unsealed":  # numba's own format: the content without the seal
        from obturator.core.cache_guard import SEAL

        one.write_bytes(data[: data.rindex(SEAL)])
    elif how == "folder":
        one.unlink()
        one.mkdir()
    elif how == "fifo":
        one.unlink()
        os.mkfifo(one)
    elif how == "device":
        one.unlink()
        one.symlink_to("/dev/zero")
    else:  # pragma: no cover
        raise AssertionError(how)


_HOW = ["truncated", "emptied", "flipped", "swapped", "unsealed", "folder", "fifo", "device"]
#: The kinds the issue names, run in the fast suite; the rest of the matrix is slow.
_FAST = {("swapped", ".nbc"), ("folder", ".nbi")}


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="FIFOs and /dev/zero")
@pytest.mark.parametrize(
    ("how", "suffix"),
    [
        pytest.param(h, s, marks=() if (h, s) in _FAST else pytest.mark.slow)
        for h in _HOW
        for s in (".nbi", ".nbc")
    ],
)
def test_damaged_cache_file_gives_one_notice_and_right_answers(
    built: tuple[Path, Path], tmp_path: Path, how: str, suffix: str
) -> None:
    cache = _copy(built, tmp_path)
    _damage(cache, suffix, how, random.Random(f"{how}{suffix}"))
    second = _run(built[0], cache)
    assert second.returncode == 0, second.stderr
    assert second.stdout.strip() == _RIGHT
    notices = _notices(second)
    assert len(notices) == 1 and "damaged" in notices[0], second.stderr
    assert "Traceback" not in second.stderr
    assert [p for p in cache.iterdir() if ".damaged-" in p.name]  # kept for inspection
    _nothing_beside_source(built[0])
    third = _run(built[0], cache)  # the fresh cache is whole: loaded, no notice
    assert third.returncode == 0 and third.stdout.strip() == _RIGHT
    assert "notice" not in third.stderr, third.stderr


def _read_only(path: Path) -> None:
    """Make `path` and every folder under it unwritable, also for root (chattr +i)."""
    folders = [path, *(p for p in path.rglob("*") if p.is_dir())]
    if os.geteuid() != 0:
        for d in folders:
            d.chmod(0o555)
        return
    if shutil.which("chattr") is None:
        pytest.skip("root needs chattr to make a folder read-only")
    for d in folders:
        done = subprocess.run(["chattr", "+i", str(d)], capture_output=True)
        if done.returncode != 0:
            _writable(path)
            pytest.skip(f"chattr +i not supported here: {done.stderr!r}")


def _writable(path: Path) -> None:
    for d in [path, *(p for p in path.rglob("*") if p.is_dir())]:
        if os.geteuid() == 0:
            subprocess.run(["chattr", "-i", str(d)], capture_output=True)
        else:
            d.chmod(0o755)


@pytest.mark.parametrize("filled", [False, True], ids=["empty", "warm"])
def test_read_only_cache_compiles_in_memory_and_writes_nothing(
    built: tuple[Path, Path], tmp_path: Path, filled: bool
) -> None:
    if filled:  # a warm cache made read-only (a shared install): it is still used
        cache = _copy(built, tmp_path)
    else:
        cache = tmp_path.joinpath(*_SUB)
        cache.mkdir(parents=True)
    before = sorted(p.relative_to(cache) for p in cache.rglob("*"))
    _read_only(cache)
    try:
        done = _run(built[0], cache)
    finally:
        _writable(cache)
    assert done.returncode == 0 and done.stdout.strip() == _RIGHT, done.stderr
    assert "Traceback" not in done.stderr
    notices = _notices(done)
    if filled:  # loaded: nothing to write, nothing to say
        assert notices == [], done.stderr
    else:
        assert len(notices) == 1 and "cannot be written" in notices[0], done.stderr
    assert sorted(p.relative_to(cache) for p in cache.rglob("*")) == before
    _nothing_beside_source(built[0])


@pytest.mark.slow
@pytest.mark.parametrize("how", ["under-a-file", "folder-is-a-file"])
def test_cache_folder_that_cannot_exist_is_one_notice(
    built: tuple[Path, Path], tmp_path: Path, how: str
) -> None:
    if how == "under-a-file":  # no folder can be made there, whoever runs it
        blocker = tmp_path.joinpath(*_SUB[:-1])
        blocker.parent.mkdir(parents=True)
        blocker.write_text("a file", encoding="utf-8")
        cache = blocker / _SUB[-1]
        want = "cannot be written"
    else:  # the function's sub-folder is a file: set aside, a folder in its place
        cache = _copy(built, tmp_path)
        (sub,) = [p for p in cache.iterdir() if p.is_dir()]
        shutil.rmtree(sub)
        sub.write_text("a file", encoding="utf-8")
        want = "damaged"
    done = _run(built[0], cache)
    assert done.returncode == 0 and done.stdout.strip() == _RIGHT, done.stderr
    notices = _notices(done)
    assert len(notices) == 1 and want in notices[0], done.stderr
    _nothing_beside_source(built[0])


def test_package_functions_are_never_cached_beside_their_source(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # numba's own locators fall back to ``__pycache__`` beside the source when the cache
    # folder cannot be written: for the package's functions the guard's locator answers
    # first, with the configured folder, written or not
    from numba.core import caching, config

    from obturator.core import cache_guard, jit_cache

    cache_guard.install()
    ro = tmp_path / "ro"
    ro.mkdir()
    _read_only(ro)
    monkeypatch.setattr(config, "CACHE_DIR", str(ro / "obturator-cache"))
    try:
        impl = caching.CompileResultCacheImpl(jit_cache.core_digest)  # a package function
    finally:
        _writable(ro)
    path = impl.locator.get_cache_path()
    assert path.startswith(str(ro)) and "__pycache__" not in path
