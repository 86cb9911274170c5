"""Environment variables, checked at start-up before numba is imported.

Our own switches and the numba variables that would otherwise end the run in
a traceback at import (``NUMBA_NUM_THREADS=0``) or a raw warning with numba's
traceback text (``NUMBA_OPT=MAX``, an empty value) are checked here, as numba parses
them (words exactly, whole numbers by ``int``); ``NUMBA_DISABLE_JIT`` other than 0 is
refused (the package runs its integrators compiled only). A bad value is one line
``obturator: error: <VARIABLE>: ...`` and exit code 2.
"""

from __future__ import annotations

import os
import re
import sys
import warnings
from collections.abc import Mapping

from ..errors import InputError

__all__ = ["check_environment", "RETIRED", "SWITCHES", "NUMBA_WORDS", "NUMBA_INTEGERS"]

#: Our on/off variables and what they do.
SWITCHES: dict[str, str] = {
    "OBTURATOR_DEBUG": "1: an internal error re-raises with its traceback",
    "OBTURATOR_FULL_EXIT": "1: end through the interpreter's full teardown (coverage tools)",
}
#: Variables that once chose a solver path and are no longer read: a path is a solver
#: option, recorded in each result's route and in the study digest; each names it.
RETIRED: dict[str, str] = {
    "OBTURATOR_LANES": "SolverOptions(lanes=False) in Python",
    "OBTURATOR_RADAU_LANES": "SolverOptions(radau_lanes=False) in Python",
    "OBTURATOR_SHARED_MAPS": "SolverOptions(shared_maps=...) in Python",
    "OBTURATOR_SLIP_LANES": "SolverOptions(slip_lanes=False) in Python",
}
_ON_OFF = ("", "0", "1")
#: numba variables that take one of a few words.
NUMBA_WORDS: dict[str, tuple[str, ...]] = {
    "NUMBA_OPT": ("0", "1", "2", "3", "max"),
    "NUMBA_THREADING_LAYER": (
        "default",
        "safe",
        "forksafe",
        "threadsafe",
        "tbb",
        "omp",
        "workqueue",
    ),
}
#: numba variables that take a whole number, with the smallest allowed.
NUMBA_INTEGERS: dict[str, int] = {
    "NUMBA_NUM_THREADS": 1,
    "NUMBA_DISABLE_JIT": 0,
    "NUMBA_BOUNDSCHECK": 0,
    "NUMBA_DEBUG": 0,
    "NUMBA_DEBUGINFO": 0,
    "NUMBA_DEVELOPER_MODE": 0,
}


def check_environment(env: Mapping[str, str] | None = None) -> None:
    """Raise InputError naming the first variable with a value that would break a run."""
    env = os.environ if env is None else env
    for name, instead in RETIRED.items():
        if name in env:
            raise InputError(name, f"is no longer read; unset it (use {instead})")
    for name, what in SWITCHES.items():
        value = env.get(name)
        if value is not None and value.strip() not in _ON_OFF:
            raise InputError(name, f"{value[:40]!r}; allowed: 0 or 1 ({what})")
    for name, words in NUMBA_WORDS.items():
        value = env.get(name)
        if value is not None and value not in words:  # numba compares exactly
            raise InputError(name, f"{value[:40]!r}; allowed: {', '.join(words)}")
    for name, lo in NUMBA_INTEGERS.items():
        value = env.get(name)
        if value is None:
            continue
        try:
            n = int(value)
        except ValueError:
            raise InputError(name, f"{value[:40]!r} is not a whole number") from None
        if n < lo:
            raise InputError(name, f"{n} is outside the allowed range >= {lo}")
        if name == "NUMBA_DISABLE_JIT" and n != 0:
            raise InputError(
                name,
                f"{n} is not supported: obturator runs its integrators compiled only; "
                "allowed: 0 (or unset)",
            )
    if env is os.environ:
        _numba_parses()
    cache = env.get("NUMBA_CACHE_DIR")
    if cache and os.path.exists(cache) and not os.path.isdir(cache):
        raise InputError("NUMBA_CACHE_DIR", f"{cache!r} exists and is not a folder")


def _numba_parses() -> None:
    """Any other ``NUMBA_*`` variable that numba cannot parse: one line, not its traceback.

    numba reads its variables when it is imported and warns with the traceback of a
    failed parse; that import is done here only when such a variable is set.
    """
    known = {*NUMBA_WORDS, *NUMBA_INTEGERS, "NUMBA_CACHE_DIR"}
    if "numba" in sys.modules or not any(
        k.startswith("NUMBA_") and k not in known for k in os.environ
    ):
        return
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            import numba.core.config  # noqa: F401
        except Exception as exc:  # a variable numba refuses at import
            names = sorted(k for k in os.environ if k.startswith("NUMBA_") and k not in known)
            text = " ".join(str(exc).split())[:200]
            raise InputError(", ".join(names), f"numba cannot start with them: {text}") from None
    for w in caught:
        found = re.match(r"Environment variable '(NUMBA_\w+)' is defined but", str(w.message))
        if found:
            name = found.group(1)
            value = os.environ.get(name, "")
            raise InputError(
                name,
                f"{value[:40]!r} is not a value numba can read (its environment variables: "
                "numba.readthedocs.io/en/stable/reference/envvars.html)",
            )
