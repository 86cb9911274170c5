"""Where numba keeps the compiled core: a directory keyed by the core's source.

numba's on-disk cache checks only the source file of each jitted function, but
the integrators (:mod:`obturator.core.integrators`) compile the right-hand side
of :mod:`obturator.core.dynamics` and the shared helpers into themselves, and
freeze module constants (parameter slots, status codes) into machine code.
After an edit of ``dynamics.py`` alone they would load stale machine code:
measured while the friction law was being corrected, t_cr at 78 rad/s came out
7e-4 off until the cache was cleared. Keying the cache directory on a digest of
every core module's source (and of :mod:`obturator.status`) turns any change to
any of them into a fresh cache.

``NUMBA_CACHE_DIR``, when set, wins (the benchmarks use it to time cold and
warm starts). Either way a damaged cache file is set aside and recompiled
(:mod:`.cache_guard`).
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from pathlib import Path

__all__ = ["CORE_MODULES", "core_digest", "configure_cache"]

_PACKAGE = Path(__file__).resolve().parent.parent


#: The modules of ``core/`` that hold no compiled code (this cache machinery): an edit
#: of them leaves every cached function valid. A change of the cache files' format
#: changes ``cache_guard.SEAL``, which the digest covers instead.
_NOT_COMPILED = ("core/cache_guard.py", "core/jit_cache.py")


def _core_modules() -> tuple[str, ...]:
    core = sorted(p.relative_to(_PACKAGE).as_posix() for p in (_PACKAGE / "core").rglob("*.py"))
    return ("status.py", *(name for name in core if name not in _NOT_COMPILED))


#: The modules (relative to the package) whose source the compiled core depends on.
CORE_MODULES = _core_modules()


def core_digest(root: Path | None = None, names: Sequence[str] = CORE_MODULES) -> str:
    """First 16 hex digits of the SHA-256 of the core modules' source.

    Parameters
    ----------
    root : Path, optional
        Folder the names are relative to (default: the ``obturator`` package).
    names : sequence of str
        File names, in a fixed order.
    """
    from .cache_guard import SEAL

    root = _PACKAGE if root is None else root
    h = hashlib.sha256(SEAL)
    for name in names:
        h.update(name.encode())
        h.update((root / name).read_bytes())
    return h.hexdigest()[:16]


#: The folders :func:`configure_cache` pointed numba at in this process (any other
#: value of ``numba.config.CACHE_DIR`` is the user's ``NUMBA_CACHE_DIR``).
_SET_HERE: set[str] = set()


def configure_cache() -> str | None:
    """Point numba's cache at ``$XDG_CACHE_HOME/obturator/numba/<digest>``.

    Must run before the jitted modules define their functions (``dynamics``
    calls it first). Returns the directory, or None if ``NUMBA_CACHE_DIR`` is set.
    """
    from .cache_guard import install

    install()
    import numba
    import platformdirs

    base = platformdirs.user_cache_path()  # $XDG_CACHE_HOME or ~/.cache on Linux
    path = str(base / "obturator" / "numba" / core_digest())
    if numba.config.CACHE_DIR and numba.config.CACHE_DIR not in _SET_HERE:
        return None  # NUMBA_CACHE_DIR, as numba read it
    numba.config.CACHE_DIR = path
    _SET_HERE.add(path)
    return path
