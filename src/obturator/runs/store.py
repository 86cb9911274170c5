"""The one resume store: a locked, checksummed sidecar of finished chunks; atomic files.

While a run with an output ``PATH`` computes, every finished chunk is appended (and
flushed) to ``PATH.partial.jsonl`` (:class:`ResumeStore`) as one record
``{"keys": [...], "values": ..., "study": digest, "crc": crc32}``: the keys address
the chunk's tasks within the study (a sweep's flat point indices, or the content
hash of a task's inputs, :func:`~obturator.runs.digest.task_key`), the values are
their JSON-ready results. The first line records the study's digest; a rerun of the
same study finds the finished tasks whatever the chunking or the worker count, a
different study is refused unless ``restart``. ``PATH.lock`` (:class:`StoreLock`)
keeps two runs from writing one output. Files are replaced atomically
(:func:`atomic_write_text`): a temporary file beside the target, fsync, rename.

A full disk (or any write error) is one :class:`~obturator.errors.InputError` that
names the file and says that the finished work is kept: the header is written
atomically (whole or absent, and an empty sidecar is taken as absent), records are
whole lines with a CRC, so a rerun resumes without ``--restart``.
"""

from __future__ import annotations

import json
import os
import zlib
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..files import atomic_write_text, write_all

__all__ = [
    "STORE_FORMAT",
    "ResumeStore",
    "StoreLock",
    "atomic_write_text",
    "full_disk_error",
    "remove_stale_temporaries",
    "sidecar_path",
    "write_all",
]

#: Format tag of the sidecar's first line.
STORE_FORMAT = "obturator-run-store/1"


def sidecar_path(out: str | os.PathLike[str]) -> Path:
    """Path of the partial-results file kept next to the output `out` while a run runs."""
    p = Path(out)
    return p.with_name(p.name + ".partial.jsonl")


def full_disk_error(
    path: str | os.PathLike[str], exc: BaseException, kept: Path | None
) -> InputError:
    """The one-line error of a failed write of `path` (full disk, quota, I/O error)."""
    reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
    where = f"; the finished points are kept in {kept}" if kept is not None else ""
    return InputError("out", f"cannot write {str(path)!r}: {reason}{where}; free space and rerun")


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # alive, owned by someone else
        return True
    return True


class StoreLock:
    """Exclusive lock on one output: ``<out>.lock`` created with O_EXCL.

    It holds the owner's pid and the study digest; a lock whose process is dead
    is stale and is taken over (a crash or SIGKILL leaves one behind). A lock that
    cannot be written (a full disk) is removed again and reported.
    """

    def __init__(self, out: Path, digest: str) -> None:
        self.path = out.with_name(out.name + ".lock")
        text = json.dumps({"pid": os.getpid(), "spec_hash": digest})
        for _ in range(2):
            try:
                fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
            except FileExistsError:
                owner = self._owner()
                if owner is not None and owner != os.getpid() and _pid_alive(owner):
                    raise InputError(
                        "out",
                        f"{out} is being written by another run (pid {owner}); "
                        "wait for it or choose another --out",
                    ) from None
                self.path.unlink(missing_ok=True)  # stale: its process is gone
                continue
            except OSError as exc:
                raise full_disk_error(self.path, exc, None) from None
            try:
                write_all(fd, text.encode())
            except OSError as exc:
                self.path.unlink(missing_ok=True)
                raise full_disk_error(self.path, exc, None) from None
            finally:
                os.close(fd)
            return
        raise InputError("out", f"cannot lock {out} (lock file {self.path})")

    def _owner(self) -> int | None:
        try:
            return int(json.loads(self.path.read_text(encoding="utf-8"))["pid"])
        except (OSError, ValueError, KeyError, TypeError):
            return None  # half-written lock: treat as stale

    def release(self) -> None:
        """Remove the lock if this process holds it."""
        if self._owner() in (os.getpid(), None):
            self.path.unlink(missing_ok=True)


def record_crc(keys: Any, values: Any) -> int:
    """CRC-32 of a record's payload (compact JSON, sorted keys)."""
    text = json.dumps({"keys": keys, "values": values}, sort_keys=True, separators=(",", ":"))
    return zlib.crc32(text.encode())


class ResumeStore:
    """Append-only JSON-lines file of finished chunks of one study, locked and checksummed.

    Parameters
    ----------
    out : path
        The run's final output; the sidecar is :func:`sidecar_path` of it.
    digest : str
        The study's digest (:func:`~obturator.runs.digest.study_digest`).
    restart : bool
        Discard a sidecar of a different study instead of failing.
    extra_outputs : sequence of path
        Further outputs of the run (their stale temporary files are removed).

    Attributes
    ----------
    records : list of (list, object)
        ``(keys, values)`` of every intact record, in file order. A record that fails
        the digest or CRC check or cannot be decoded is dropped and counted in
        :attr:`n_discarded` (its tasks are recomputed).
    """

    def __init__(
        self,
        out: str | os.PathLike[str],
        digest: str,
        *,
        restart: bool = False,
        extra_outputs: Sequence[str | os.PathLike[str]] = (),
    ) -> None:
        out = Path(out)
        if not out.parent.is_dir():
            raise InputError("out", f"directory {str(out.parent)!r} does not exist")
        self.path = sidecar_path(out)
        self.digest = digest
        self.records: list[tuple[list[Any], Any]] = []
        self.n_discarded = 0
        self.lock: StoreLock | None = StoreLock(out, digest)
        try:
            for p in (out, self.path, *extra_outputs):
                remove_stale_temporaries(Path(p))
            header = {"format": STORE_FORMAT, "study": digest}
            if restart or (self.path.exists() and not self.path.read_bytes().strip()):
                self.path.unlink(missing_ok=True)  # an empty file: its header never got written
            if self.path.exists():
                self._load(header)
            else:
                self._atomic(json.dumps(header) + "\n")
            self._fd: int | None = os.open(self.path, os.O_WRONLY | os.O_APPEND)
        except BaseException:
            self.lock.release()
            raise

    def _atomic(self, text: str) -> None:
        try:
            atomic_write_text(self.path, text)
        except OSError as exc:
            raise full_disk_error(self.path, exc, None) from None

    def _load(self, header: dict[str, Any]) -> None:
        data = self.path.read_bytes()
        lines = data.split(b"\n")
        try:
            first = json.loads(lines[0].decode("utf-8"))
        except (UnicodeDecodeError, json.JSONDecodeError):
            first = {}
        if first != header:
            old = str(first.get("study", "?"))[:12] if isinstance(first, dict) else "?"
            raise InputError(
                "store",
                f"{self.path} holds partial results of a different study "
                f"(hash {old}, this one {self.digest[:12]}); "
                "use --restart (restart=True) to discard it",
            )
        for raw in lines[1:]:
            if not raw.strip():
                continue
            try:
                rec = json.loads(raw.decode("utf-8"))
                keys, values = rec["keys"], rec["values"]
                ok = isinstance(keys, list) and rec.get("study") == self.digest
                ok = ok and rec.get("crc") == record_crc(keys, values)
            except (UnicodeDecodeError, json.JSONDecodeError, KeyError, TypeError):
                ok = False
            if ok:
                self.records.append((keys, values))
            else:
                self.n_discarded += 1  # cut by a kill, corrupted or foreign: recompute
        if not data.endswith(b"\n"):  # a cut-short last line must not swallow the next record
            self._append(b"\n")

    def _append(self, line: bytes) -> None:
        fd = os.open(self.path, os.O_WRONLY | os.O_APPEND)
        try:
            write_all(fd, line)
        except OSError as exc:
            raise full_disk_error(self.path, exc, self.path) from None
        finally:
            os.close(fd)

    def append(self, keys: list[Any], values: Any) -> None:
        """Record one finished chunk (flushed and synced at once).

        Raises
        ------
        InputError
            The record cannot be written (full disk, quota, I/O error); the records
            before it stay intact and the store is closed.
        """
        rec = {
            "keys": keys,
            "values": values,
            "study": self.digest,
            "crc": record_crc(keys, values),
        }
        if self._fd is None:
            raise InputError("store", f"{self.path} is closed")
        try:
            write_all(self._fd, (json.dumps(rec) + "\n").encode())
            os.fsync(self._fd)
        except OSError as exc:
            self.close()  # a partial line is discarded on resume
            raise full_disk_error(self.path, exc, self.path) from None

    def close(self) -> None:
        """Close the file (kept for a later resume) and release the lock."""
        if getattr(self, "_fd", None) is not None:
            os.close(self._fd)
            self._fd = None
        if self.lock is not None:
            self.lock.release()
            self.lock = None

    def remove(self) -> None:
        """Close and delete the sidecar (after the final outputs are written)."""
        self.close()
        self.path.unlink(missing_ok=True)


def remove_stale_temporaries(path: Path) -> None:
    """Delete ``.<name>.<pid>.tmp`` files of processes that no longer exist."""
    for tmp in path.parent.glob(f".{path.name}.*.tmp"):
        pid = tmp.name[len(path.name) + 2 : -4]
        if pid.isdigit() and not _pid_alive(int(pid)):
            tmp.unlink(missing_ok=True)
