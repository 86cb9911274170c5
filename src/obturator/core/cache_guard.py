"""A damaged compiled-code cache is set aside and recompiled, never fatal.

numba trusts its cache files: an index (``.nbi``) that a full disk or a kill
during ``obturator warmup`` left truncated or empty raises from inside the
dispatcher (every later run fails, until the user finds and deletes the
folder), and flipped bytes in a data file (``.nbc``) that still unpickle would
be loaded as machine code. For the package's own cache folders only, this
module

* seals every index and data file it writes with a SHA-256 of its content,
  and checks the seal before unpickling;
* treats an index or data file that cannot be read back (truncated, emptied,
  garbled, seal broken) as damage: the folder is renamed to
  ``<folder>.damaged-<time>-<pid>`` (kept for inspection), a fresh empty one
  takes its place, one notice line goes to stderr, and numba recompiles.

Caches of other packages (a shared ``NUMBA_CACHE_DIR``) are left alone.
"""

from __future__ import annotations

import hashlib
import io
import os
import pickle
import sys
import time
from functools import lru_cache
from pathlib import Path

__all__ = ["install", "SEAL"]

#: Marks the SHA-256 seal at the end of a data file.
SEAL = b"obturator-sha256:"
_DIGEST = 32
_PACKAGE = Path(__file__).resolve().parent.parent
_noticed: set[str] = set()


@lru_cache(maxsize=1)
def _our_subpaths() -> frozenset[str]:
    """numba's cache sub-folder names of the package's source folders."""
    from numba.core.caching import UserProvidedCacheLocator

    dirs = {p.parent for p in _PACKAGE.rglob("*.py")}
    return frozenset(
        UserProvidedCacheLocator.get_suitable_cache_subpath(str(d / "m.py")) for d in dirs
    )


def _ours(cache_path: str) -> bool:
    return os.path.basename(os.path.normpath(cache_path)) in _our_subpaths() or _under_own_root(
        cache_path
    )


def _under_own_root(cache_path: str) -> bool:
    """In ``$XDG_CACHE_HOME/obturator/numba`` (configure_cache's folder)."""
    return f"{os.sep}obturator{os.sep}numba{os.sep}" in os.path.abspath(cache_path)


def set_aside(cache_path: str, why: str) -> None:
    """Rename the damaged folder, put an empty one in its place, say so once."""
    aside = f"{cache_path}.damaged-{int(time.time())}-{os.getpid()}"
    try:
        os.rename(cache_path, aside)
    except OSError:
        aside = ""  # another process got there first, or read-only: recompile anyway
    os.makedirs(cache_path, exist_ok=True)
    if cache_path not in _noticed:
        _noticed.add(cache_path)
        where = f"; set aside as {aside}" if aside else ""
        print(
            f"obturator: notice: compiled-code cache {cache_path} was damaged ({why}){where}; "
            "recompiling into a fresh cache",
            file=sys.stderr,
        )


def _seal(blob: bytes) -> bytes:
    return blob + SEAL + hashlib.sha256(blob).digest()


def _unseal(blob: bytes) -> bytes | None:
    """The content of a sealed file, or None when the seal is missing or broken."""
    body, seal = blob[: -len(SEAL) - _DIGEST], blob[-len(SEAL) - _DIGEST :]
    return body if seal == SEAL + hashlib.sha256(body).digest() else None


def install() -> None:
    """Seal numba's index and data files in our folders and check them on load (idempotent)."""
    from numba.core import caching

    cls = caching.IndexDataCacheFile
    if getattr(cls, "_obturator_guard", False):
        return
    originals = {
        k: getattr(cls, k) for k in ("_load_index", "_save_index", "_load_data", "_save_data")
    }

    def load_index(self):  # type: ignore[no-untyped-def]
        if not _ours(self._cache_path):
            return originals["_load_index"](self)
        try:
            with open(self._index_path, "rb") as f:
                blob = f.read()
        except FileNotFoundError:
            return {}
        body = _unseal(blob)
        try:
            if body is None:
                raise ValueError("seal broken")
            stream = io.BytesIO(body)
            if pickle.load(stream) != self._version:
                return {}  # another numba's index: overwritten on save, as numba does
            stamp, overloads = pickle.loads(stream.read())
            if not isinstance(overloads, dict):
                raise TypeError("not a mapping")
        except Exception as exc:  # truncated, emptied or garbled
            set_aside(self._cache_path, f"{self._index_name}: {exc or type(exc).__name__}")
            return {}
        return overloads if stamp == self._source_stamp else {}

    def save_index(self, overloads):  # type: ignore[no-untyped-def]
        if not _ours(self._cache_path):
            return originals["_save_index"](self, overloads)
        blob = pickle.dumps(self._version, protocol=-1) + self._dump(
            (self._source_stamp, overloads)
        )
        with self._open_for_write(self._index_path) as f:
            f.write(_seal(blob))

    def load_data(self, name):  # type: ignore[no-untyped-def]
        if not _ours(self._cache_path):
            return originals["_load_data"](self, name)
        with open(self._data_path(name), "rb") as f:  # OSError: numba recompiles
            body = _unseal(f.read())
        try:
            if body is None:
                raise ValueError("seal broken")
            return pickle.loads(body)
        except Exception as exc:
            set_aside(self._cache_path, f"{name}: {exc or type(exc).__name__}")
            raise OSError(f"{name}: damaged") from None

    def save_data(self, name, data):  # type: ignore[no-untyped-def]
        if not _ours(self._cache_path):
            return originals["_save_data"](self, name, data)
        with self._open_for_write(self._data_path(name)) as f:
            f.write(_seal(self._dump(data)))

    cls._load_index, cls._save_index = load_index, save_index
    cls._load_data, cls._save_data = load_data, save_data
    cls._obturator_guard = True
