"""A damaged or unusable compiled-code cache is set aside or bypassed, never fatal.

numba trusts its cache files: an index (``.nbi``) that a full disk or a kill
during ``obturator warmup`` left truncated or empty raises from inside the
dispatcher (every later run fails, until the user finds and deletes the
folder), flipped bytes in a data file (``.nbc``) that still unpickle would be
loaded as machine code, two data files swapped load one function's machine code
for another, and an index replaced by a folder fails every run. An unwritable
cache folder makes numba fall back to the source tree: it writes unsealed cache
files into the installed package's ``__pycache__`` folders. For the package's own
cache folders only, this module

* seals every index and data file it writes with a SHA-256 of the file's name and
  content (a data file also of its function's source stamp), and checks the seal
  before unpickling, so a file under another name (swapped, copied) is damage;
* reads a cache file only when it is a regular file: a folder, FIFO or device in
  its place is damage too (a FIFO would block the read);
* treats a file that cannot be read back (truncated, emptied, garbled, seal
  broken, wrong kind) and any other failure to load a cached function as damage:
  the folder is renamed to ``<folder>.damaged-<time>-<pid>`` (kept for inspection),
  a fresh empty one takes its place, one notice line goes to stderr, and numba
  recompiles;
* locates the package's functions only in the configured cache folder
  (``numba.config.CACHE_DIR``), never in the source tree: where that folder cannot
  be written (read-only, not a folder, a failed write), the functions compile in
  memory, with one notice, and nothing is written.

Caches of other packages (a shared ``NUMBA_CACHE_DIR``) are left alone.
"""

from __future__ import annotations

import hashlib
import io
import os
import pickle
import stat
import sys
import time
from functools import lru_cache
from pathlib import Path

__all__ = ["install", "SEAL", "set_aside"]

#: Marks the SHA-256 seal at the end of a cache file (``v2``: the seal covers the name).
SEAL = b"obturator-sha256-v2:"
_DIGEST = 32
#: Larger than any cache file of the package: a file this large is not one of ours.
_MAX_BYTES = 1 << 30
_PACKAGE = Path(__file__).resolve().parent.parent
_noticed: set[str] = set()
#: Cache folders this process cannot write, and why: their functions compile in memory.
_unwritable: dict[str, str] = {}


class _Damaged(Exception):
    """A cache file that is not what this module wrote."""


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
    return f"{os.sep}obturator{os.sep}numba{os.sep}" in os.path.abspath(cache_path) + os.sep


def _notice(key: str, text: str) -> None:
    if key not in _noticed:
        _noticed.add(key)
        print(f"obturator: notice: {text}", file=sys.stderr)


def set_aside(cache_path: str, why: str) -> None:
    """Rename the damaged folder, put an empty one in its place, say so once.

    Where the folder cannot be renamed (read-only), its functions compile in memory.
    """
    aside = f"{cache_path}.damaged-{int(time.time())}-{os.getpid()}"
    try:
        os.rename(cache_path, aside)
    except OSError:
        aside = ""  # another process got there first, or read-only
    try:
        os.makedirs(cache_path, exist_ok=True)
        fresh = bool(aside) or not any(os.scandir(cache_path))
    except OSError:
        fresh = False
    if not fresh:
        _unwritable[cache_path] = "damaged"
        _noticed.add("unwritable")  # this notice says it
    where = f"; set aside as {aside}" if aside else ""
    into = "into a fresh cache" if fresh else "in memory"
    _notice(
        f"damaged:{cache_path}",
        f"compiled-code cache {cache_path} was damaged ({why}){where}; recompiling {into}",
    )


def _cannot_write(cache_path: str) -> None:
    """Say once that a compiled function is kept in memory only."""
    _notice(
        "unwritable",
        f"compiled-code cache {cache_path} cannot be written ({_unwritable[cache_path]}); "
        "compiling in memory (nothing is kept for the next run; set NUMBA_CACHE_DIR to a "
        "writable folder)",
    )


def _seal(name: str, blob: bytes, stamp: object = None) -> bytes:
    return blob + SEAL + _digest(name, blob, stamp)


def _digest(name: str, blob: bytes, stamp: object) -> bytes:
    h = hashlib.sha256(name.encode() + b"\0")
    if stamp is not None:
        h.update(pickle.dumps(stamp, protocol=4) + b"\0")
    h.update(blob)
    return h.digest()


def _unseal(name: str, blob: bytes, stamp: object = None) -> bytes | None:
    """The content of a sealed file, or None when the seal is missing or broken."""
    if len(blob) < len(SEAL) + _DIGEST:
        return None
    body, seal = blob[: -len(SEAL) - _DIGEST], blob[-len(SEAL) - _DIGEST :]
    return body if seal == SEAL + _digest(name, body, stamp) else None


def _read(path: str) -> bytes | None:
    """The bytes of the regular file `path`; None when there is none.

    Raises ``_Damaged`` for anything else in its place (a folder, FIFO, device, a
    file too large or unreadable): opened without blocking, checked before reading.
    """
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(path, flags)
    except (FileNotFoundError, NotADirectoryError):  # no such file (its folder cannot exist)
        return None
    except OSError as exc:
        raise _Damaged(f"cannot be read: {exc.strerror or type(exc).__name__}") from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise _Damaged("not a regular file")
        if info.st_size > _MAX_BYTES:
            raise _Damaged(f"{info.st_size} bytes, too large")
        parts = []
        while part := os.read(fd, 1 << 20):
            parts.append(part)
        return b"".join(parts)
    except OSError as exc:
        raise _Damaged(f"cannot be read: {exc.strerror or type(exc).__name__}") from None
    finally:
        os.close(fd)


def _in_package(py_file: str) -> bool:
    try:
        return Path(py_file).resolve().is_relative_to(_PACKAGE)
    except OSError:
        return False


def _locator_class() -> type:
    """numba cache locator of the package's functions: the configured folder, or memory."""
    from numba.core import caching, config

    class OwnCacheLocator(caching.UserProvidedCacheLocator):
        """The package's functions in ``numba.config.CACHE_DIR`` only (never the source
        tree); a folder that cannot be written compiles in memory."""

        @classmethod
        def from_function(cls, py_func, py_file):  # type: ignore[no-untyped-def]
            if not config.CACHE_DIR or not os.path.exists(py_file):
                return None
            if not (_in_package(py_file) or _under_own_root(config.CACHE_DIR)):
                return None
            self = cls(py_func, py_file)
            self.ensure_cache_path()
            return self

        def ensure_cache_path(self) -> None:
            path = self.get_cache_path()
            if path in _unwritable:
                return
            try:
                if os.path.lexists(path) and not os.path.isdir(path):
                    set_aside(path, "not a folder")
                super().ensure_cache_path()
            except OSError as exc:  # said when a function compiles (a warm cache loads)
                _unwritable[path] = exc.strerror or type(exc).__name__

    return OwnCacheLocator


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
            blob = _read(self._index_path)
            if blob is None:
                return {}
            body = _unseal(self._index_name, blob)
            if body is None:
                raise ValueError("seal broken")
            stream = io.BytesIO(body)
            if pickle.load(stream) != self._version:
                return {}  # another numba's index: overwritten on save, as numba does
            stamp, overloads = pickle.loads(stream.read())
            if not isinstance(overloads, dict):
                raise TypeError("not a mapping")
        except Exception as exc:  # truncated, emptied, garbled, wrong kind
            set_aside(self._cache_path, f"{self._index_name}: {exc or type(exc).__name__}")
            return {}
        return overloads if stamp == self._source_stamp else {}

    def save_index(self, overloads):  # type: ignore[no-untyped-def]
        if not _ours(self._cache_path):
            return originals["_save_index"](self, overloads)
        blob = pickle.dumps(self._version, protocol=-1) + self._dump(
            (self._source_stamp, overloads)
        )
        _write(self, self._index_path, _seal(self._index_name, blob))

    def load_data(self, name):  # type: ignore[no-untyped-def]
        if not _ours(self._cache_path):
            return originals["_load_data"](self, name)
        try:
            blob = _read(self._data_path(name))
            if blob is None:
                raise OSError(f"{name}: missing")  # numba recompiles
            body = _unseal(name, blob, self._source_stamp)
            if body is None:
                raise ValueError("seal broken")
            return pickle.loads(body)
        except OSError:
            raise
        except Exception as exc:
            set_aside(self._cache_path, f"{name}: {exc or type(exc).__name__}")
            raise OSError(f"{name}: damaged") from None

    def save_data(self, name, data):  # type: ignore[no-untyped-def]
        if not _ours(self._cache_path):
            return originals["_save_data"](self, name, data)
        _write(self, self._data_path(name), _seal(name, self._dump(data), self._source_stamp))

    def _write(self, path: str, blob: bytes) -> None:  # type: ignore[no-untyped-def]
        if self._cache_path not in _unwritable:
            try:
                with self._open_for_write(path) as f:
                    f.write(blob)
                return
            except OSError as exc:  # read-only, full disk, a folder in the file's place
                _unwritable[self._cache_path] = exc.strerror or type(exc).__name__
        _cannot_write(self._cache_path)

    cls._load_index, cls._save_index = load_index, save_index
    cls._load_data, cls._save_data = load_data, save_data
    _guard_loads(caching)
    caching.CacheImpl._locator_classes.insert(0, _locator_class())
    cls._obturator_guard = True


def _guard_loads(caching) -> None:  # type: ignore[no-untyped-def]
    """Any failure to rebuild a cached function of ours is damage (recompiled)."""
    original = caching.Cache.load_overload

    def load_overload(self, sig, target_context):  # type: ignore[no-untyped-def]
        if not _ours(self._cache_path):
            return original(self, sig, target_context)
        try:
            return original(self, sig, target_context)
        except Exception as exc:
            set_aside(self._cache_path, f"{type(exc).__name__}: {exc}"[:200])
            return None

    caching.Cache.load_overload = load_overload
