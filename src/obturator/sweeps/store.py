"""Resumable results: a locked, checksummed sidecar of finished chunks, atomic files.

While a study with ``store=PATH`` runs, every finished chunk is appended (and
flushed) to ``PATH.partial.jsonl`` (:class:`Sidecar`). Its first line records
the study's hash; a rerun of the same study skips the points already there, a
different study is refused unless ``restart``. ``PATH.lock`` (:class:`StoreLock`)
keeps two runs from writing one output. Files are replaced atomically
(:func:`atomic_write_text`): a temporary file beside the target, fsync, rename.
"""

from __future__ import annotations

import json
import os
import zlib
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from .points import POINT_STATUSES

__all__ = [
    "SIDECAR_FORMAT",
    "Sidecar",
    "StoreLock",
    "atomic_write_text",
    "remove_stale_temporaries",
    "sidecar_path",
]

#: Format tag of the sidecar's first line (2: the status codes of obturator.status).
SIDECAR_FORMAT = "obturator-study-partial/2"


def sidecar_path(store: str | os.PathLike[str]) -> Path:
    """Path of the partial-results file kept next to ``store`` while a study runs."""
    p = Path(store)
    return p.with_name(p.name + ".partial.jsonl")


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # alive, owned by someone else
        return True
    return True


class StoreLock:
    """Exclusive lock on one output: ``<store>.lock`` created with O_EXCL.

    It holds the owner's pid and the study hash; a lock whose process is dead
    is stale and is taken over (a crash or SIGKILL leaves one behind).
    """

    def __init__(self, store: Path, digest: str) -> None:
        self.path = store.with_name(store.name + ".lock")
        text = json.dumps({"pid": os.getpid(), "spec_hash": digest})
        for _ in range(2):
            try:
                fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
            except FileExistsError:
                owner = self._owner()
                if owner is not None and owner != os.getpid() and _pid_alive(owner):
                    raise InputError(
                        "out",
                        f"{store} is being written by another run (pid {owner}); "
                        "wait for it or choose another --out",
                    ) from None
                self.path.unlink(missing_ok=True)  # stale: its process is gone
                continue
            with os.fdopen(fd, "w", encoding="utf-8") as fh:
                fh.write(text)
            return
        raise InputError("out", f"cannot lock {store} (lock file {self.path})")

    def _owner(self) -> int | None:
        try:
            return int(json.loads(self.path.read_text(encoding="utf-8"))["pid"])
        except (OSError, ValueError, KeyError, TypeError):
            return None  # half-written lock: treat as stale

    def release(self) -> None:
        if self._owner() in (os.getpid(), None):
            self.path.unlink(missing_ok=True)


def _record_crc(payload: dict[str, Any]) -> int:
    return zlib.crc32(json.dumps(payload, sort_keys=True, separators=(",", ":")).encode())


class Sidecar:
    """Append-only JSON-lines file of finished chunks, locked and checksummed.

    The first line (study hash, point count) is written atomically (temp file and
    rename), so it is either whole or absent. Every record carries the study
    hash and a CRC-32 of its payload; on resume a record that fails either
    check, has an index outside [0, n), an unknown status, a shape mismatch or
    undecodable bytes is discarded (its points are recomputed) and counted in
    :attr:`n_discarded`.
    """

    def __init__(self, path: Path, digest: str, n_points: int, restart: bool) -> None:
        self.path = path
        self.digest = digest
        self.lock: StoreLock | None = None
        self.n_discarded = 0
        self.done_index: list[np.ndarray] = []
        self.done_t: list[np.ndarray] = []
        self.done_s: list[np.ndarray] = []
        header = {"format": SIDECAR_FORMAT, "spec_hash": digest, "n_points": n_points}
        if path.exists() and restart:
            path.unlink()
        if path.exists():
            self._load(header)
        else:
            atomic_write_text(path, json.dumps(header) + "\n")
        self._fh = path.open("a", encoding="utf-8")

    def _load(self, header: dict[str, Any]) -> None:
        lines = self.path.read_bytes().split(b"\n")
        try:
            first = json.loads(lines[0].decode("utf-8")) if lines and lines[0] else {}
        except (UnicodeDecodeError, json.JSONDecodeError):
            first = {}
        if first != header:
            old = str(first.get("spec_hash", "?"))[:12] if isinstance(first, dict) else "?"
            raise InputError(
                "store",
                f"{self.path} holds partial results of a different study "
                f"(hash {old}, this one {header['spec_hash'][:12]}); "
                "use --restart (restart=True) to discard it",
            )
        n = header["n_points"]
        known = {int(s) for s in POINT_STATUSES}
        for raw in lines[1:]:
            if not raw.strip():
                continue
            try:
                rec = json.loads(raw.decode("utf-8"))
                payload = {k: rec[k] for k in ("index", "t_cr", "status")}
                ok = rec.get("spec_hash") == self.digest and rec.get("crc") == _record_crc(payload)
                idx = np.asarray(payload["index"], dtype=np.int64)
                t = np.asarray(payload["t_cr"], dtype=float)
                st = np.asarray(payload["status"], dtype=np.int64)
                ok = ok and idx.ndim == 1 and idx.shape == t.shape == st.shape
                ok = ok and bool(np.all((idx >= 0) & (idx < n)))
                ok = ok and all(int(x) in known for x in st)
            except (UnicodeDecodeError, json.JSONDecodeError, KeyError, TypeError, ValueError):
                ok = False
            if not ok:
                self.n_discarded += 1  # cut by a kill, corrupted or foreign: recompute
                continue
            self.done_index.append(idx)
            self.done_t.append(t)
            self.done_s.append(st.astype(np.int8))
        # make sure a cut-short last line does not swallow the next record
        if not self.path.read_bytes().endswith(b"\n"):
            with self.path.open("ab") as fh:
                fh.write(b"\n")

    def _write(self, record: dict[str, Any]) -> None:
        self._fh.write(json.dumps(record) + "\n")
        self._fh.flush()
        os.fsync(self._fh.fileno())

    def append(self, idx: np.ndarray, t: np.ndarray, s: np.ndarray) -> None:
        payload = {"index": idx.tolist(), "t_cr": t.tolist(), "status": s.tolist()}
        self._write({**payload, "spec_hash": self.digest, "crc": _record_crc(payload)})

    def close(self) -> None:
        if not self._fh.closed:
            self._fh.close()
        if self.lock is not None:
            self.lock.release()
            self.lock = None

    def remove(self) -> None:
        self.close()
        self.path.unlink(missing_ok=True)


def atomic_write_text(path: Path, text: str) -> None:
    """Write `text` to a temporary file beside `path`, fsync, and rename it into place.

    A character device (``/dev/null``) is written in place, never renamed over
    (:func:`obturator.files.atomic_write_text`).
    """
    from ..files import atomic_write_text as write

    write(path, text)


def remove_stale_temporaries(path: Path) -> None:
    """Delete ``.<name>.<pid>.tmp`` files of processes that no longer exist."""
    for tmp in path.parent.glob(f".{path.name}.*.tmp"):
        pid = tmp.name[len(path.name) + 2 : -4]
        if pid.isdigit() and not _pid_alive(int(pid)):
            tmp.unlink(missing_ok=True)
