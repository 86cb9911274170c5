"""Where numba keeps the compiled core: a directory keyed by the core's source.

numba's on-disk cache checks only the source file of each jitted function, but
the integrators (``_dop853``, ``_radau``, ``_rosenbrock``) compile the
right-hand side of :mod:`obturator.dynamics` into themselves. After an edit of
``dynamics.py`` alone they would load stale machine code: measured while the
friction law was being corrected, t_cr at 78 rad/s came out 7e-4 off until the
cache was cleared. Keying the cache directory on a digest of every jitted
module's source turns any change to any of them into a fresh cache.

``NUMBA_CACHE_DIR``, when set, wins (the benchmarks use it to time cold and
warm starts).
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Sequence
from pathlib import Path

__all__ = ["CORE_MODULES", "core_digest", "configure_cache"]

#: The modules whose jitted functions call each other.
CORE_MODULES = ("dynamics.py", "_rosenbrock.py", "_dop853.py", "_radau.py")


def core_digest(root: Path | None = None, names: Sequence[str] = CORE_MODULES) -> str:
    """First 16 hex digits of the SHA-256 of the core modules' source.

    Parameters
    ----------
    root : Path, optional
        Folder holding the modules (default: this package).
    names : sequence of str
        File names, in a fixed order.
    """
    root = Path(__file__).parent if root is None else root
    h = hashlib.sha256()
    for name in names:
        h.update(name.encode())
        h.update((root / name).read_bytes())
    return h.hexdigest()[:16]


def configure_cache() -> str | None:
    """Point numba's cache at ``$XDG_CACHE_HOME/obturator/numba/<digest>``.

    Must run before the jitted modules define their functions (``dynamics``
    calls it first). Returns the directory, or None if ``NUMBA_CACHE_DIR`` is set.
    """
    if os.environ.get("NUMBA_CACHE_DIR"):
        return None
    import numba

    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    path = str(base / "obturator" / "numba" / core_digest())
    numba.config.CACHE_DIR = path
    return path
