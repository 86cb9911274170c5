"""Stop the command line at once on Ctrl-C or SIGTERM, whatever it is doing.

Python runs signal handlers only between bytecodes of the main thread, so a
long compiled integration (or a numba call that is interrupted mid-way) would
not see Ctrl-C until it returned. Instead the signals are routed to a wake-up
pipe (:func:`signal.set_wakeup_fd`); a watcher thread blocked on that pipe
prints one line and ends the process with ``os._exit`` (130 for SIGINT, 143
for SIGTERM). The integrators release the GIL (``nogil=True``), so the watcher
runs within milliseconds even mid-integration. The Python-level handler in the
main thread does the same, whichever comes first: while the main thread runs a
Python loop of small NumPy calls (each releasing and retaking the GIL) the woken
watcher could wait seconds for the GIL (CPython's convoy effect, seen in
``calibrate``'s bootstrap), and there the main thread reaches its handler at
the next bytecode. Both write with ``os.write`` (no buffered-stream lock to
re-enter) and only the first to take :data:`_EXITING` writes.

Nothing finished is lost: sweep and Monte Carlo records are fsynced one by one
as they finish; outputs are written to temporary files and renamed, so an
interrupted write leaves the old state; stale locks and temporary files of a
dead process are cleared by the next run; pool workers die with the main
process (``PR_SET_PDEATHSIG``).
"""

from __future__ import annotations

import os
import signal
import threading

__all__ = ["install"]

_MESSAGES = {signal.SIGINT: ("interrupted", 130), signal.SIGTERM: ("terminated", 143)}

#: Commands whose finished work is kept in their ``--out`` store, so that running the
#: same command again resumes (``envelope`` always has one: its default --out).
RESUMING = (
    "sweep",
    "montecarlo",
    "envelope",
    "probability",
    "sensitivity",
    "optimize",
    "validate",
    "reproduce",
)

#: Appended to the one line when the running command resumes (set by :func:`note_command`).
_resume_hint = ""


def note_command(command: str | None, out: str | None) -> None:
    """Remember whether `command` with store `out` resumes when run again."""
    global _resume_hint
    resumes = command in RESUMING and (out is not None or command == "envelope")
    _resume_hint = "; run the same command again to resume (finished work is kept)" * resumes


def line(text: str = "interrupted") -> str:
    """The one line printed when the command stops: ``obturator: <text>[; resume hint]``."""
    return f"obturator: {text}{_resume_hint}"


#: Taken by whichever of the two paths stops the process first.
_EXITING = threading.Lock()


def _stop(signum: int) -> None:
    """Write the one line for `signum` and end the process (a no-op if already ending)."""
    if not _EXITING.acquire(blocking=False):
        return
    text, code = _MESSAGES.get(signum, ("interrupted", 130))
    try:
        os.write(2, f"{line(text)}\n".encode())
    finally:
        os._exit(code)


def _watch(fd: int) -> None:
    while True:
        try:
            data = os.read(fd, 1)
        except OSError:  # pragma: no cover
            return
        if not data:  # pragma: no cover
            return
        _stop(data[0])


def install() -> bool:
    """Route SIGINT and SIGTERM to the watcher (main thread only); return whether it did."""
    if threading.current_thread() is not threading.main_thread():
        return False
    r, w = os.pipe()
    os.set_blocking(w, False)
    try:
        signal.set_wakeup_fd(w, warn_on_full_buffer=False)
    except ValueError:  # pragma: no cover - not the main thread / no signals
        os.close(r)
        os.close(w)
        return False
    for sig in _MESSAGES:
        signal.signal(sig, lambda signum, _frame: _stop(signum))
    threading.Thread(target=_watch, args=(r,), name="obturator-signals", daemon=True).start()
    return True
