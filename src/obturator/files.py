"""Files at the edge: one reader for inputs, one check and one writer for outputs.

Every file a user names goes through here, whatever the command:

* :func:`read_text_file` reads configs, data CSVs and drag tables: a regular
  file of at most :data:`MAX_FILE_BYTES`, UTF-8, no NUL bytes. Devices
  (``/dev/zero``), FIFOs and directories are refused before they are opened
  (reading them would block or never end).
* :func:`check_output_path` runs before any work: a regular file or a new file
  in a writable directory; a character device (``/dev/null``) is written in
  place; FIFOs, sockets and block devices are refused (writing a FIFO without
  a reader blocks; a block device is a disk); an empty name, ``.``, a
  directory and a symlink loop are refused with one line.
* :func:`publish` puts a finished temporary file in place: renamed over a
  regular file (atomic), copied into a character device (never renamed over
  it: as root, a rename would replace ``/dev/null`` with a regular file).
"""

from __future__ import annotations

import errno
import os
import shutil
import stat
from pathlib import Path

from .errors import InputError

__all__ = [
    "MAX_FILE_BYTES",
    "read_text_file",
    "check_output_path",
    "check_output_dir",
    "temporary_for",
    "publish",
    "atomic_write_text",
    "write_all",
    "figure_format",
]

#: Largest config, data or drag-table file read [bytes]: 1 MiB holds ~30,000 rows of
#: a spin-rig CSV, far beyond any rig campaign (thesis Appendix B: 54 runs).
MAX_FILE_BYTES = 1 << 20


def _stat(field: str, p: Path, what: str) -> os.stat_result | None:
    """``os.stat`` of `p` (None when it does not exist); loops and other errors refused."""
    try:
        return p.stat()
    except FileNotFoundError:
        return None
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise InputError(field, f"{str(p)!r} is a symlink loop") from None
        if exc.errno == errno.ENOTDIR:
            return None  # a parent is a file: reported as a missing directory
        raise InputError(field, f"cannot {what} {str(p)!r}: {exc.strerror or exc}") from None


def read_text_file(path: str | Path, field: str, max_bytes: int = MAX_FILE_BYTES) -> str:
    """The UTF-8 text of a regular file of at most `max_bytes`, or one clear InputError.

    Parameters
    ----------
    path : str or Path
        The file.
    field : str
        Option name for messages (``"config"``, ``"data"``, ``"--drag"``).
    max_bytes : int
        Largest accepted size [bytes] (default :data:`MAX_FILE_BYTES`).
    """
    if not str(path).strip():
        raise InputError(field, "empty file name")
    p = Path(path)
    st = _stat(field, p, "read")
    if st is None:
        raise InputError(field, f"cannot read {str(p)!r}: No such file or directory")
    if not stat.S_ISREG(st.st_mode):
        raise InputError(field, f"{str(p)!r} is not a regular file")
    if st.st_size > max_bytes:
        raise InputError(field, f"{str(p)!r} is larger than {max_bytes} bytes")
    try:
        with p.open("rb") as fh:
            data = fh.read(max_bytes + 1)
    except OSError as exc:
        raise InputError(field, f"cannot read {str(p)!r}: {exc.strerror or exc}") from None
    if len(data) > max_bytes:
        raise InputError(field, f"{str(p)!r} is larger than {max_bytes} bytes")
    if b"\x00" in data:
        raise InputError(field, f"{str(p)!r} is binary, not text")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(
            field, f"{str(p)!r} is not UTF-8 text (byte {exc.start}); save it as UTF-8"
        ) from None


def check_output_path(
    field: str, path: str | os.PathLike[str] | None, suffixes: tuple[str, ...] | None = None
) -> Path | None:
    """Check, before any work, that `path` can be written; return it as a Path.

    Parameters
    ----------
    field : str
        Option name for messages (e.g. ``"--csv"``).
    path : str or None
        None passes through.
    suffixes : tuple of str, optional
        Allowed file suffixes without the dot (case-insensitive), e.g. the
        figure formats matplotlib can write.
    """
    if path is None:
        return None
    text = os.fspath(path)
    if not isinstance(text, str) or not text.strip() or text.strip() in (".", ".."):
        raise InputError(field, f"{text!r} is not a file name")
    if "\x00" in text:
        raise InputError(field, "the file name contains a NUL byte")
    p = Path(text)
    st = _stat(field, p, "write")
    device = st is not None and stat.S_ISCHR(st.st_mode)  # /dev/null takes any format
    if suffixes is not None and not device and p.suffix.lower().lstrip(".") not in suffixes:
        raise InputError(
            field, f"{text!r}: unsupported file type; allowed: .{', .'.join(sorted(suffixes))}"
        )
    if st is not None:
        if stat.S_ISDIR(st.st_mode):
            raise InputError(field, f"{text!r} is a directory")
        if stat.S_ISCHR(st.st_mode):  # /dev/null, /dev/full: written in place
            if not os.access(p, os.W_OK):
                raise InputError(field, f"{text!r} is not writable")
            return p
        if not stat.S_ISREG(st.st_mode):
            raise InputError(field, f"{text!r} is not a regular file (a FIFO, socket or disk)")
    parent = p.parent
    pst = _stat(field, parent, "write into")
    if pst is None or not stat.S_ISDIR(pst.st_mode):
        raise InputError(field, f"directory of {text!r} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK) or (st is not None and not os.access(p, os.W_OK)):
        raise InputError(field, f"{text!r} is not writable")
    return p


def check_output_dir(field: str, path: str | os.PathLike[str] | None) -> Path | None:
    """Check, before any work, that the folder `path` exists or can be created.

    An empty name is refused (it would mean the current folder by accident);
    ``.`` names the current folder on purpose and is accepted.
    """
    if path is None:
        return None
    text = os.fspath(path)
    if not text.strip():
        raise InputError(field, "empty folder name")
    p = Path(text)
    st = _stat(field, p, "write into")
    if st is not None and not stat.S_ISDIR(st.st_mode):
        raise InputError(field, f"{text!r} exists and is not a folder")
    probe = p
    while _stat(field, probe, "write into") is None:  # the nearest existing ancestor
        if probe.parent == probe:
            break
        probe = probe.parent
    pst = _stat(field, probe, "write into")
    if pst is None or not stat.S_ISDIR(pst.st_mode):
        raise InputError(field, f"{text!r} cannot be created: {str(probe)!r} is not a folder")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise InputError(field, f"{str(probe)!r} is not writable")
    return p


def _is_device(target: Path) -> bool:
    try:
        return stat.S_ISCHR(target.stat().st_mode)
    except OSError:
        return False


def temporary_for(target: str | os.PathLike[str]) -> Path:
    """A temporary name for writing `target`: beside it, or in the temp folder for a device."""
    target = Path(target)
    name = f".{target.name}.{os.getpid()}.tmp"
    if _is_device(target):
        import tempfile

        return Path(tempfile.gettempdir()) / name
    return target.with_name(name)


def publish(tmp: Path, target: str | os.PathLike[str]) -> None:
    """Put the finished file `tmp` (from :func:`temporary_for`) at `target`.

    A regular (or new) target is replaced atomically (rename); a character
    device is written in place (copied into), never renamed over; anything
    else (FIFO, socket, disk) is refused.
    """
    target = Path(target)
    try:
        mode = target.stat().st_mode
    except OSError:
        mode = None
    if mode is not None and not stat.S_ISREG(mode):
        try:
            if not stat.S_ISCHR(mode):
                raise InputError(str(target), "is not a regular file (a FIFO, socket or disk)")
            with tmp.open("rb") as src, target.open("wb") as dst:
                shutil.copyfileobj(src, dst)
        finally:
            tmp.unlink(missing_ok=True)
        return
    os.replace(tmp, target)


def _write(fd: int, data: memoryview) -> int:
    """``os.write``: the one place where the package's stored bytes reach the disk (the
    full-disk tests inject ENOSPC here)."""
    return os.write(fd, data)


def write_all(fd: int, data: bytes) -> None:
    """Write every byte of `data` to the file descriptor `fd` (short writes continued)."""
    view = memoryview(data)
    while view:
        view = view[_write(fd, view) :]


def atomic_write_text(path: str | os.PathLike[str], text: str) -> None:
    """Write `text` to a temporary file, fsync, and :func:`publish` it at `path`.

    Whole or absent, also on a full disk; an error names `path`, not the temporary.
    """
    tmp = temporary_for(path)
    try:
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        try:
            write_all(fd, text.encode("utf-8"))
            os.fsync(fd)
        finally:
            os.close(fd)
        publish(tmp, path)
    except OSError as exc:
        raise OSError(exc.errno, exc.strerror, str(path)) from None
    finally:
        tmp.unlink(missing_ok=True)


def figure_format(path: str | os.PathLike[str]) -> str:
    """The figure format of `path`: its suffix, or ``png`` for a name without one.

    Passed to ``savefig(format=...)`` so that matplotlib never appends a suffix of
    its own: ``--plot /dev/null`` must write the device, not create ``/dev/null.png``.
    """
    return Path(path).suffix.lower().lstrip(".") or "png"
