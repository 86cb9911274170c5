"""Parameter sweeps and Monte Carlo studies of the opening time t_cr.

Numerics and orchestration only (no plotting). Every grid point or sample is
one independent call of :func:`obturator.solve.opening_time`, so a study is
embarrassingly parallel; this module decides how the points are grouped,
where they run and how finished work survives an interruption.

Grids
    :func:`parse_axis` reads ``START:STOP:COUNT`` (evenly spaced, both ends
    included) or a comma list ``a,b,c``. A :class:`SweepSpec` holds the case
    name, the swept axes, fixed values, torque model, spin mode and
    :class:`~obturator.solve.SolverOptions`; :func:`run_sweep` evaluates the full
    Cartesian grid and returns an :class:`xarray.Dataset` with ``t_cr`` [s]
    (NaN where the bore did not open) and an integer ``status``.

Execution
    Points are grouped into chunks (several points per task, so that process
    and scheduling overhead is amortised). A chunk takes every k-th remaining
    point, which mixes cheap and expensive points (t_cr grows with spin) and
    balances the load. ``workers=1`` (or a single chunk) runs in this process;
    ``workers=N >= 2`` uses a :class:`concurrent.futures.ProcessPoolExecutor`
    with N processes (default: the CPUs this process may use). On Linux, from
    a single-threaded parent, the workers are forked after the compiled
    integrator has been loaded once in the parent, so every worker starts
    warm; otherwise they are spawned and each loads the numba cache once, in
    its first chunk. ``scheduler="tcp://host:port"`` or a :class:`distributed.Client`
    sends the same chunks to a dask.distributed cluster (``client.submit`` and
    ``as_completed``); the workers there need ``obturator`` importable. Each
    point is computed by the same deterministic function wherever it runs, so
    local, pooled and distributed results are identical bit for bit.

Resuming
    With ``store=PATH`` every finished chunk is appended (and flushed) to the
    sidecar ``PATH.partial.jsonl``. Its first line records a SHA-256 hash of
    the study (case, axes, fixed values, models, solver options, package
    version). Re-running the same study skips the points already in the
    sidecar; a sidecar written for a different study is an error unless
    ``restart=True``. At the end the NetCDF is written to PATH (atomically,
    through a temporary file) and the sidecar is removed.

Monte Carlo
    :func:`monte_carlo` draws the uncertain inputs from distributions written
    as ``name=kind:args`` (:func:`parse_distribution`), one
    :class:`numpy.random.SeedSequence` child per sample
    (``SeedSequence(seed).spawn(n)``), so sample i is the same whatever the
    worker count, chunking or total sample count. The summary
    (:func:`summarize_monte_carlo`) gives t_cr quantiles with distribution-free
    order-statistic (binomial) confidence intervals and the fraction not
    opened with a Clopper-Pearson interval.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import multiprocessing
import os
import sys
import threading
import time
import zlib
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from contextlib import contextmanager, suppress
from dataclasses import asdict, dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from ..model.cases import CASE_NAMES, TABLE1, TORQUE_MODELS, flight_case, rig_case, table1_ball
from ..errors import ClusterError, InputError, check_range
from ..solve import Case, SolverOptions, convergence_check, opening_time

if TYPE_CHECKING:  # pragma: no cover
    import xarray

__all__ = [
    "PARAMETERS",
    "STATUS_OPENED",
    "STATUS_NOT_OPENED",
    "STATUS_FAILED",
    "STATUS_INVALID",
    "STATUS_UNCONVERGED",
    "SweepSpec",
    "SweepRun",
    "Distribution",
    "QuantileEstimate",
    "MonteCarloSummary",
    "parse_axis",
    "parse_distribution",
    "run_sweep",
    "execute_sweep",
    "sweep_summary",
    "monte_carlo",
    "summarize_monte_carlo",
    "monte_carlo_summary",
    "sample_inputs",
    "write_netcdf",
    "write_csv",
    "sidecar_path",
    "default_workers",
]

#: Status codes stored in the ``status`` variable.
STATUS_OPENED = 1
STATUS_NOT_OPENED = 0
STATUS_FAILED = -1
STATUS_INVALID = -2
#: Opened, but t_cr moved by more than 1e-3 (relative) when the tolerances or the
#: friction width were divided by 10 or the regularisation family was changed
#: (only with ``check_convergence=True``).
STATUS_UNCONVERGED = 2
_STATUS_FLAGS = {
    STATUS_INVALID: "invalid_input",
    STATUS_FAILED: "solver_failed_or_step_limit",
    STATUS_NOT_OPENED: "not_opened_by_t_max",
    STATUS_OPENED: "opened",
    STATUS_UNCONVERGED: "opened_not_converged",
}


@dataclass(frozen=True)
class _Param:
    unit: str
    long_name: str
    flight_only: bool = False


#: Parameters a sweep or Monte Carlo study may vary: name -> (unit, description).
PARAMETERS: dict[str, _Param] = {
    "spin_rate": _Param("rad/s", "projectile spin rate omega_p"),
    "mu_s": _Param("1", "sliding friction coefficient mu_s"),
    "theta0_deg": _Param("deg", "initial nutation angle theta_0"),
    "density": _Param("kg/m^3", "ball density rho"),
    "hole_radius": _Param("m", "ball hole radius r_s"),
    "gap": _Param("m", "ball-socket gap h"),
    "mach": _Param("1", "flight Mach number M_1", flight_only=True),
    "altitude_m": _Param("m", "flight altitude (US 1976 atmosphere)", flight_only=True),
}

# Plain per-parameter ranges (lo, hi, lo_open, hi_open) checked on sampled
# values before any integration; combined limits (theta_0 > beta_s) are
# checked by the case factories.
_RANGES: dict[str, tuple[float, float, bool, bool]] = {
    "spin_rate": (0.0, math.inf, True, True),
    "mu_s": (0.0, 2.0, False, False),
    "theta0_deg": (0.0, 90.0, True, False),
    "density": (0.0, math.inf, True, True),
    "hole_radius": (0.0, TABLE1["ball_radius"] / math.sqrt(2.0), False, True),
    "gap": (0.0, TABLE1["ball_radius"], True, True),
    "mach": (1.0, math.inf, False, True),
    "altitude_m": (0.0, 86_000.0, False, False),
}

_SPIN_MODES = ("constant", "free", "thesis-energy")
_MAX_POINTS = 100_000_000
_MAX_CHUNK = 64
_CHUNKS_PER_WORKER = 8
_SIDECAR_FORMAT = "obturator-study-partial/1"


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("obturator")
    except PackageNotFoundError:  # pragma: no cover - source tree without metadata
        return "0+unknown"


def default_workers() -> int:
    """Number of CPUs this process may use (the default worker count)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, os.cpu_count() or 1)


# --------------------------------------------------------------------------- parsing


def _float(name: str, text: str, what: str, unit: str | None = None) -> float:
    """A number, or with `unit` also a quantity such as "7.8 g/cm^3" converted to it."""
    t = text.strip()
    if unit is not None:
        from ..io import parse_quantity

        try:
            return parse_quantity(name, t, "" if unit == "1" else unit)
        except InputError as exc:
            raise InputError(name, f"{what}: {str(exc).split(': ', 1)[1]}") from None
    try:
        x = float(t)
    except ValueError:
        raise InputError(name, f"{what} {t!r} is not a number") from None
    if not math.isfinite(x):
        raise InputError(name, f"{what} {t!r} must be finite")
    return x


def parse_axis(text: str, name: str = "axis", unit: str | None = None) -> np.ndarray:
    """Parse the values of one sweep axis.

    Parameters
    ----------
    text : str
        ``START:STOP:COUNT`` -- COUNT evenly spaced values from START to STOP,
        both ends included (``numpy.linspace``; the last value is STOP
        exactly); START > STOP gives a decreasing axis. COUNT is a whole
        number >= 1; COUNT = 1 is accepted only with START == STOP (a single
        value is better written as a plain number). Or a comma list
        ``a,b,c`` of distinct values, kept in the given order; a plain number
        is a list of one value.
    name : str
        Parameter name used in error messages (e.g. ``"--spin-rate"``).
    unit : str, optional
        The parameter's unit. When given, every value may carry a unit of its
        own (``"7.8 g/cm^3"``, ``"1000 rpm:6000 rpm:11"``) or a range one unit
        for START and STOP after COUNT (``"1000:6000:11 rpm"``); bare numbers
        are in `unit` (as on the ``simulate`` command line).

    Returns
    -------
    numpy.ndarray
        1-D float array, in the unit of the parameter.

    Raises
    ------
    InputError
        On malformed text, non-finite values, COUNT < 1 or not a whole
        number, repeated values, or a spacing below floating-point resolution.
    """
    if not isinstance(text, str) or not text.strip():
        raise InputError(name, "empty value: expected START:STOP:COUNT or a list a,b,c")
    s = text.strip()
    if ":" in s:
        parts = s.split(":")
        if len(parts) != 3:
            raise InputError(
                name, f"malformed range {s!r}: expected START:STOP:COUNT (e.g. 200:700:20)"
            )
        count_text, _, trailing = parts[2].strip().partition(" ")
        if trailing.strip():
            if unit is None:
                raise InputError(name, f"malformed range {s!r}: units are not accepted here")
            parts = [f"{parts[0]} {trailing}", f"{parts[1]} {trailing}", count_text]
        start = _float(name, parts[0], "START", unit)
        stop = _float(name, parts[1], "STOP", unit)
        try:
            count = int(parts[2].strip())
        except ValueError:
            raise InputError(
                name, f"malformed range {s!r}: COUNT {parts[2].strip()!r} is not a whole number"
            ) from None
        if count < 1:
            raise InputError(name, f"malformed range {s!r}: COUNT must be >= 1, got {count}")
        if count > _MAX_POINTS:
            raise InputError(name, f"COUNT {count} exceeds the limit of {_MAX_POINTS} points")
        if count == 1:
            if start != stop:
                raise InputError(
                    name,
                    f"range {s!r} has COUNT = 1 but START != STOP; give a single value instead",
                )
            return np.array([start])
        values = np.linspace(start, stop, count)
    else:
        parts = s.split(",")
        values = np.array([_float(name, p, "value", unit) for p in parts], dtype=float)
        if len(np.unique(values)) != len(values):
            raise InputError(name, f"list {s!r} repeats a value")
        return values
    steps = np.diff(values)
    if not (np.all(steps > 0) or np.all(steps < 0)):
        raise InputError(
            name, f"range {s!r}: the {count} values are not distinct in floating point"
        )
    return values


def _canonical_name(text: str) -> str:
    key = text.strip().lstrip("-").replace("-", "_")
    if key not in PARAMETERS:
        raise InputError(
            "parameter", f"unknown parameter {text!r}; allowed: {', '.join(PARAMETERS)}"
        )
    return key


# --------------------------------------------------------------------------- the spec


def _as_axis(name: str, values: Any) -> np.ndarray:
    try:
        arr = np.array(values, dtype=float).reshape(-1) if np.ndim(values) <= 1 else None
    except (TypeError, ValueError):
        raise InputError(name, f"axis values must be numbers, got {values!r}") from None
    if arr is None:
        raise InputError(name, "axis values must be a 1-D sequence")
    if arr.size == 0:
        raise InputError(name, "an axis needs at least one value")
    if not np.all(np.isfinite(arr)):
        raise InputError(name, "axis values must be finite")
    if len(np.unique(arr)) != arr.size:
        raise InputError(name, "axis values must be distinct")
    arr.setflags(write=False)
    return arr


def _json_float(x: float) -> float | str:
    return x if math.isfinite(x) else repr(x)


@dataclass(frozen=True, eq=False)
class SweepSpec:
    """A parameter study: case, swept axes, fixed values, models, solver settings.

    Parameters
    ----------
    case : {"spin-rig", "flight"}
        Thesis Table 1 column; the grid points are built with
        :func:`obturator.cases.rig_case` or :func:`obturator.cases.flight_case`.
    axes : mapping of str to array_like
        Swept parameters, in dimension order: name -> 1-D values (distinct,
        finite). Allowed names and units (:data:`PARAMETERS`): ``spin_rate``
        [rad/s], ``mu_s`` [-], ``theta0_deg`` [deg], ``density`` [kg/m^3],
        ``hole_radius`` [m], ``gap`` [m], and for the flight case only
        ``mach`` [-] and ``altitude_m`` [m].
    fixed : mapping of str to float
        Values held fixed (same names and units). Anything neither swept nor
        fixed takes the case factory's Table 1 default (spin_rate 200 rad/s on
        the rig and 12042 rad/s in flight, mu_s 0.35, theta_0 87.25 deg,
        rho 7669.6 kg/m^3, r_s 4.72 mm, h 50.8 um, M_1 = 3, P_1 = 0.099 MPa).
    torque_model : {"thesis", "coulomb"}
    spin_mode : {"constant", "free", "thesis-energy"}
    options : SolverOptions
    t_max : float or None
        Give-up time [s]; None keeps the factory default (100 s rig, 0.5 s flight).
    check_convergence : bool
        Re-run every opened point with the tolerances divided by 10, with the
        friction width divided by 10 and with another regularisation family
        (four times the cost) and mark points whose t_cr moves by more than
        1e-3 with status ``STATUS_UNCONVERGED`` (typical at low spin, where
        long near-stick phases need a small width).

    Notes
    -----
    The ball is :func:`obturator.cases.table1_ball` with the given density and
    hole radius. On the rig the normal load is Table 1's *measured*
    W = 0.07987 N unless ``density`` or ``hole_radius`` is swept or fixed; then
    the weight follows the ball (``weight=None``, W = rho g V), as in the
    thesis's geometry studies (Figs. 16-17). In flight a different hole radius
    changes the ball only; the bore radius r_p that sets the pressure force
    and the contact angle stays Table 1's 4.72 mm. With ``altitude_m`` the
    free-stream pressure comes from the 1976 standard atmosphere instead of
    P_1 = 0.099 MPa.

    Validation is eager: names, models, and every corner of the grid (each
    axis at its smallest and largest value) are built into cases, which
    catches out-of-range values before any integration.
    """

    case: str = "spin-rig"
    axes: Mapping[str, Any] = field(default_factory=dict)
    fixed: Mapping[str, float] = field(default_factory=dict)
    torque_model: str = "thesis"
    spin_mode: str = "constant"
    options: SolverOptions = field(default_factory=SolverOptions)
    t_max: float | None = None
    check_convergence: bool = False

    def __post_init__(self) -> None:
        if self.case not in CASE_NAMES:
            raise InputError("case", f"{self.case!r}; allowed: {', '.join(CASE_NAMES)}")
        if self.torque_model not in TORQUE_MODELS:
            raise InputError(
                "torque_model", f"{self.torque_model!r}; allowed: {', '.join(TORQUE_MODELS)}"
            )
        if self.spin_mode not in _SPIN_MODES:
            raise InputError("spin_mode", f"{self.spin_mode!r}; allowed: {', '.join(_SPIN_MODES)}")
        if not isinstance(self.options, SolverOptions):
            raise InputError("options", "expected a SolverOptions")
        axes: dict[str, np.ndarray] = {}
        for name, values in dict(self.axes).items():
            self._check_name(name)
            axes[name] = _as_axis(name, values)
        fixed: dict[str, float] = {}
        for name, value in dict(self.fixed).items():
            self._check_name(name)
            if name in axes:
                raise InputError(name, "is both swept and fixed")
            fixed[name] = check_range(name, value)
        object.__setattr__(self, "axes", axes)
        object.__setattr__(self, "fixed", fixed)
        if self.t_max is not None:
            object.__setattr__(
                self, "t_max", check_range("t_max", self.t_max, 0.0, lo_open=True, unit="s")
            )
        if self.n_points > _MAX_POINTS:
            raise InputError("axes", f"{self.n_points} grid points exceed the limit {_MAX_POINTS}")
        self._check_corners()

    def _check_name(self, name: str) -> None:
        if name not in PARAMETERS:
            raise InputError(
                "parameter", f"unknown parameter {name!r}; allowed: {', '.join(PARAMETERS)}"
            )
        if PARAMETERS[name].flight_only and self.case != "flight":
            raise InputError(name, "applies to the flight case only")

    def _check_corners(self) -> None:
        names = list(self.axes)
        if not names:
            self.build_case({})
            return
        ends = [sorted({float(a.min()), float(a.max())}) for a in self.axes.values()]
        for corner in itertools.product(*ends):
            self.build_case(dict(zip(names, corner, strict=True)))

    # -- shape of the grid
    @property
    def dims(self) -> tuple[str, ...]:
        """Swept parameter names, in dimension order."""
        return tuple(self.axes)

    @property
    def shape(self) -> tuple[int, ...]:
        """Grid shape (one entry per swept parameter)."""
        return tuple(len(a) for a in self.axes.values())

    @property
    def n_points(self) -> int:
        """Number of grid points (1 when nothing is swept)."""
        return int(math.prod(self.shape))

    def rows(self, indices: np.ndarray) -> np.ndarray:
        """Swept values at flat (C-order) grid indices, shape (len(indices), len(dims))."""
        idx = np.asarray(indices, dtype=np.int64)
        if not self.axes:
            return np.empty((idx.size, 0))
        multi = np.unravel_index(idx, self.shape)
        return np.column_stack([a[m] for a, m in zip(self.axes.values(), multi, strict=True)])

    # -- building cases
    @property
    def weight_from_ball(self) -> bool:
        """True when the rig load is the ball's computed weight (geometry varied)."""
        varied = set(self.axes) | set(self.fixed)
        return self.case == "spin-rig" and bool(varied & {"density", "hole_radius"})

    @property
    def weight_model(self) -> str:
        """How the normal load is set (text stored in the results)."""
        if self.case == "flight":
            return "flight: pressure force behind the normal bow shock (Eqs. 1, 3, 43)"
        if self.weight_from_ball:
            return "spin-rig: weight W = rho g V computed from the (modified) ball"
        return f"spin-rig: Table 1 measured weight W = {TABLE1['rig_weight']} N"

    def resolved(self) -> dict[str, float | None]:
        """Every parameter's value when not swept: fixed, else the factory default."""
        defaults: dict[str, float | None] = {
            "spin_rate": TABLE1["rig_spin_rate" if self.case == "spin-rig" else "flight_spin_rate"],
            "mu_s": TABLE1["mu_s"],
            "theta0_deg": TABLE1["theta0_deg"],
            "density": TABLE1["density"],
            "hole_radius": TABLE1["hole_radius"],
            "gap": TABLE1["gap"],
        }
        if self.case == "flight":
            defaults["mach"] = TABLE1["mach"]
            defaults["altitude_m"] = None
        defaults.update(self.fixed)
        return defaults

    def build_case(self, values: Mapping[str, float]) -> Case:
        """The :class:`~obturator.solve.Case` at one grid point.

        Parameters
        ----------
        values : mapping of str to float
            Values of (some of) the swept parameters; everything else is taken
            from ``fixed`` or the factory defaults. Units as in :data:`PARAMETERS`.
        """
        v: dict[str, Any] = {**self.fixed, **{k: float(x) for k, x in values.items()}}
        kw: dict[str, Any] = {"torque_model": self.torque_model, "spin_mode": self.spin_mode}
        for key in ("spin_rate", "mu_s", "theta0_deg", "gap"):
            if key in v:
                kw[key] = v[key]
        if self.t_max is not None:
            kw["t_max"] = self.t_max
        kw["ball"] = table1_ball(density=v.get("density"), hole_radius=v.get("hole_radius"))
        if self.case == "spin-rig":
            if self.weight_from_ball:
                kw["weight"] = None
            return rig_case(**kw)
        if "mach" in v:
            kw["mach"] = v["mach"]
        if "altitude_m" in v:
            kw["altitude_m"] = v["altitude_m"]
            kw["p1"] = None
        return flight_case(**kw)

    # -- identity
    def identity(self) -> dict[str, Any]:
        """JSON-ready description of everything that determines the results."""
        opts = {
            k: (_json_float(x) if isinstance(x, float) else x)
            for k, x in asdict(self.options).items()
        }
        return {
            "case": self.case,
            "axes": {k: [_json_float(x) for x in a.tolist()] for k, a in self.axes.items()},
            "fixed": {k: _json_float(x) for k, x in sorted(self.fixed.items())},
            "torque_model": self.torque_model,
            "spin_mode": self.spin_mode,
            "options": opts,
            "t_max": self.t_max,
            "check_convergence": self.check_convergence,
            "obturator_version": _version(),
        }

    def digest(self) -> str:
        """SHA-256 (hex) of :meth:`identity`; equal specs give equal digests."""
        text = json.dumps(self.identity(), sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, SweepSpec):
            return NotImplemented
        return self.identity() == other.identity()

    def __hash__(self) -> int:
        return hash(self.digest())


# --------------------------------------------------------------------------- one point


def _evaluate_point(spec: SweepSpec, values: Mapping[str, float]) -> tuple[float, int]:
    """t_cr [s] and status code at one point (never raises for a bad point)."""
    try:
        case = spec.build_case(values)
    except InputError:
        return math.nan, STATUS_INVALID
    try:
        t = opening_time(case, spec.options)
        if spec.check_convergence and math.isfinite(t):
            if not convergence_check(case, spec.options, opening_time_s=t).converged:
                return t, STATUS_UNCONVERGED
    except RuntimeError:
        return math.nan, STATUS_FAILED
    return (t, STATUS_OPENED) if math.isfinite(t) else (math.nan, STATUS_NOT_OPENED)


def _run_chunk(
    spec: SweepSpec, names: tuple[str, ...], rows: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Evaluate the points of one chunk (rows of values in ``names`` order).

    Module level so that process pools and dask workers can import it.
    """
    t = np.empty(len(rows))
    s = np.empty(len(rows), dtype=np.int8)
    for k, row in enumerate(rows):
        t[k], s[k] = _evaluate_point(spec, dict(zip(names, row.tolist(), strict=True)))
    return t, s


def _warm(options: SolverOptions) -> None:
    """Load (or compile) the integrator once: a short rig run with these options."""
    try:
        opening_time(rig_case(700.0, 0.5, t_max=1e-3), options)
    except RuntimeError:  # pragma: no cover - warm-up only
        pass


# --------------------------------------------------------------------------- resumable store


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


class _StoreLock:
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


class _Sidecar:
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
        self.lock: _StoreLock | None = None
        self.n_discarded = 0
        self.done_index: list[np.ndarray] = []
        self.done_t: list[np.ndarray] = []
        self.done_s: list[np.ndarray] = []
        header = {"format": _SIDECAR_FORMAT, "spec_hash": digest, "n_points": n_points}
        if path.exists() and restart:
            path.unlink()
        if path.exists():
            self._load(header)
        else:
            _atomic_write_text(path, json.dumps(header) + "\n")
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
        known = set(_STATUS_FLAGS)
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


def _atomic_write_text(path: Path, text: str) -> None:
    """Write `text` to a temporary file beside `path`, fsync, and rename it into place."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        with tmp.open("w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def _remove_stale_temporaries(path: Path) -> None:
    """Delete ``.<name>.<pid>.tmp`` files of processes that no longer exist."""
    for tmp in path.parent.glob(f".{path.name}.*.tmp"):
        pid = tmp.name[len(path.name) + 2 : -4]
        if pid.isdigit() and not _pid_alive(int(pid)):
            tmp.unlink(missing_ok=True)


# --------------------------------------------------------------------------- execution


def _chunks(todo: np.ndarray, workers: int, chunk_size: int | None) -> list[np.ndarray]:
    if todo.size == 0:
        return []
    if chunk_size is None:
        chunk_size = max(1, min(_MAX_CHUNK, math.ceil(todo.size / (_CHUNKS_PER_WORKER * workers))))
    elif int(chunk_size) < 1:
        raise InputError("chunk_size", f"{chunk_size} is outside the allowed range >= 1")
    n_chunks = math.ceil(todo.size / int(chunk_size))
    return [todo[k::n_chunks] for k in range(n_chunks)]


def _mp_context() -> multiprocessing.context.BaseContext:
    # fork is cheap and inherits the loaded integrator; it is only used on
    # Linux while this process runs a single thread (the progress bar's thread
    # starts after the workers, see _run_pool); otherwise spawn, which is safe
    # but needs the usual ``if __name__ == "__main__":`` guard in scripts
    others = [t for t in threading.enumerate() if t.name != "obturator-signals"]
    if sys.platform == "linux" and len(others) == 1:  # the signal watcher only reads a pipe
        return multiprocessing.get_context("fork")
    return multiprocessing.get_context("spawn")


@contextmanager
def _progress(enabled: bool, total: int, done: int, label: str) -> Iterator[Callable[[int], None]]:
    if not enabled:
        yield lambda n: None
        return
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    with Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        TextColumn("eta"),
        TimeRemainingColumn(),
        console=Console(stderr=True),
        transient=True,
    ) as bar:
        task = bar.add_task(label, total=total, completed=done)
        yield lambda n: bar.advance(task, n)


Sink = Callable[[np.ndarray, np.ndarray, np.ndarray], None]


def _run_local(spec, names, rows_of, chunks, sink, progress, label, total, done) -> None:
    with _progress(progress, total, done, label) as advance:
        for idx in chunks:
            t, s = _run_chunk(spec, names, rows_of(idx))
            sink(idx, t, s)
            advance(idx.size)


def _die_with_parent(parent: int) -> None:
    """Worker initializer: end this worker when the main process ends, however it ends.

    Linux ``prctl(PR_SET_PDEATHSIG, SIGKILL)``: a SIGKILL or SIGTERM of the main
    process (which runs no clean-up) must not leave workers computing for good.
    Elsewhere nothing is set (the pool still ends them on a normal exit).
    """
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the main process's to handle
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.set_wakeup_fd(-1)  # the main process's watcher pipe is not ours
    if sys.platform.startswith("linux"):
        import ctypes

        try:
            ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
        except (OSError, AttributeError):  # pragma: no cover - unusual libc
            return
        if os.getppid() != parent:  # the parent died before prctl took effect
            os._exit(1)


def _run_pool(spec, names, rows_of, chunks, sink, workers, progress, label, total, done) -> None:
    ctx = _mp_context()
    if ctx.get_start_method() == "fork":
        _warm(spec.options)  # workers inherit the loaded integrator
    pool = ProcessPoolExecutor(
        max_workers=workers,
        mp_context=ctx,
        initializer=_die_with_parent,
        initargs=(os.getpid(),),
    )
    try:
        # every task is submitted (and, with fork, every worker started) before
        # the progress bar starts its refresh thread
        pending = {pool.submit(_run_chunk, spec, names, rows_of(idx)): idx for idx in chunks}
        _prefetch_output()  # this process is idle meanwhile
        with _progress(progress, total, done, label) as advance:
            while pending:
                finished, _ = wait(pending, return_when=FIRST_COMPLETED)
                for fut in finished:
                    idx = pending.pop(fut)
                    t, s = fut.result()
                    sink(idx, t, s)
                    advance(idx.size)
    except BaseException:
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown(wait=True)


def _prefetch_output() -> None:
    """Import xarray and build a tiny Dataset (its lazy set-up takes ~1 s)."""
    import xarray as xr

    xr.Dataset({"t_cr": ("x", np.zeros(1))})


#: Seconds after which connecting to a Dask scheduler is given up.
CONNECT_TIMEOUT_S = 10.0


def _client(scheduler: Any) -> tuple[Any, bool]:
    """A connected ``distributed.Client``, or one InputError within CONNECT_TIMEOUT_S.

    The connection is made in a helper thread with a hard deadline: a port that
    accepts a connection but never speaks the Dask protocol would otherwise
    block the handshake for many minutes.
    """
    if not isinstance(scheduler, str):
        return scheduler, False
    try:
        from distributed import Client
    except ImportError:
        raise InputError(
            "scheduler", "needs dask.distributed: pip install 'obturator[cluster]'"
        ) from None
    box: dict[str, Any] = {}

    def connect() -> None:
        try:
            box["client"] = Client(scheduler, timeout=f"{CONNECT_TIMEOUT_S:g}s")
        except Exception as exc:  # any failure becomes one line for the user
            box["error"] = exc

    thread = threading.Thread(target=connect, name="obturator-dask-connect", daemon=True)
    thread.start()
    thread.join(CONNECT_TIMEOUT_S + 2.0)
    if "client" in box:
        return box["client"], True
    why = box.get("error")
    text = " ".join(str(why).split()) if why is not None else "no answer"
    raise InputError(
        "scheduler",
        f"cannot connect to {scheduler!r} within {CONNECT_TIMEOUT_S:g} s: {text}",
    )


#: Seconds without a connected scheduler after which a running study gives up.
LOST_SCHEDULER_S = 10.0


def _run_dask(spec, names, rows_of, chunks, sink, scheduler, progress, label, total, done) -> None:
    """Chunks as tasks on a Dask cluster; finished chunks go to `sink` as they arrive.

    A scheduler or worker that dies mid-study is a :class:`ClusterError` (one
    line on the command line) within LOST_SCHEDULER_S, never a hang: the
    finished chunks are already in the resume store, so the study resumes
    (locally or on a new cluster) to the same result.
    """
    from distributed import wait as dask_wait

    client, owned = _client(scheduler)
    futures = []
    try:
        index_of = {}
        for idx in chunks:
            fut = client.submit(_run_chunk, spec, names, rows_of(idx), pure=False)
            index_of[fut.key] = idx
            futures.append(fut)
        _prefetch_output()
        pending = set(futures)
        lost_since: float | None = None
        with _progress(progress, total, done, label) as advance:
            while pending:
                try:
                    dask_wait(list(pending), timeout=1.0, return_when="FIRST_COMPLETED")
                except Exception:  # nothing finished within 1 s (or the wait itself broke)
                    pass
                if client.status != "running":
                    lost_since = lost_since or time.monotonic()
                    if time.monotonic() - lost_since > LOST_SCHEDULER_S:
                        raise ClusterError(f"lost the Dask scheduler {client.scheduler!s}")
                else:
                    lost_since = None
                for fut in [f for f in pending if f.status != "pending"]:
                    pending.discard(fut)
                    if fut.status != "finished":
                        raise ClusterError(f"a Dask task ended with status {fut.status!r}")
                    try:
                        t, s = fut.result(timeout=LOST_SCHEDULER_S)
                    except Exception as exc:
                        raise ClusterError(f"a Dask task failed: {exc}") from None
                    idx = index_of[fut.key]
                    sink(idx, t, s)
                    advance(idx.size)
    except BaseException:
        if futures:
            with suppress(Exception):
                client.cancel(futures)
        raise
    finally:
        if owned:
            with suppress(Exception):
                client.close(timeout=2)


@dataclass(frozen=True)
class _Outcome:
    t_cr: np.ndarray
    status: np.ndarray
    n_resumed: int
    n_computed: int
    workers: int
    backend: str
    elapsed_s: float
    sidecar: _Sidecar | None


def _compute(
    spec: SweepSpec,
    names: tuple[str, ...],
    rows_of: Callable[[np.ndarray], np.ndarray],
    n_points: int,
    digest: str,
    *,
    workers: int | None,
    scheduler: Any,
    store: str | os.PathLike[str] | None,
    restart: bool,
    chunk_size: int | None,
    progress: bool,
    label: str,
    extra_outputs: tuple[str, ...] = (),
) -> _Outcome:
    t0 = time.perf_counter()
    t_cr = np.full(n_points, np.nan)
    status = np.full(n_points, -128, dtype=np.int8)  # -128: not computed yet
    sidecar = None
    if store is not None:
        out = Path(store)
        if not out.parent.is_dir():
            raise InputError("out", f"directory {str(out.parent)!r} does not exist")
        lock = _StoreLock(out, digest)
        try:
            for p in (out, sidecar_path(out), *extra_outputs):
                _remove_stale_temporaries(Path(p))
            sidecar = _Sidecar(sidecar_path(out), digest, n_points, restart)
        except BaseException:
            lock.release()
            raise
        sidecar.lock = lock
        if sidecar.n_discarded:
            print(
                f"obturator: notice: {sidecar.n_discarded} damaged or foreign records in "
                f"{sidecar.path.name} discarded; their points are recomputed",
                file=sys.stderr,
            )
        for idx, t, s in zip(sidecar.done_index, sidecar.done_t, sidecar.done_s, strict=True):
            t_cr[idx], status[idx] = t, s
    todo = np.flatnonzero(status == -128)
    n_resumed = n_points - todo.size

    def sink(idx: np.ndarray, t: np.ndarray, s: np.ndarray) -> None:
        t_cr[idx], status[idx] = t, s
        if sidecar is not None:
            sidecar.append(idx, t, s)

    if scheduler is not None:
        n_workers = 0
        backend = "dask.distributed"
    else:
        n_workers = default_workers() if workers is None else int(workers)
        if n_workers < 1:
            if sidecar is not None:
                sidecar.close()
            raise InputError("workers", f"{workers} is outside the allowed range >= 1")
        backend = "local"
    chunks = _chunks(todo, max(n_workers, 1) if scheduler is None else 8, chunk_size)
    args = (spec, names, rows_of, chunks, sink)
    tail = (progress, label, n_points, n_resumed)
    try:
        if not chunks:
            pass
        elif scheduler is not None:
            _run_dask(*args, scheduler, *tail)
        elif min(n_workers, len(chunks)) <= 1:
            n_workers = 1
            _run_local(*args, *tail)
        else:
            n_workers = min(n_workers, len(chunks))
            _run_pool(*args, n_workers, *tail)
    except BaseException:
        if sidecar is not None:
            sidecar.close()
        raise
    if np.any(status == -128):  # pragma: no cover - a chunk went missing
        raise RuntimeError("some points were not computed")
    return _Outcome(
        t_cr,
        status,
        n_resumed,
        int(todo.size),
        n_workers,
        backend,
        time.perf_counter() - t0,
        sidecar,
    )


# --------------------------------------------------------------------------- output


def _attr(value: Any) -> Any:
    """NetCDF-safe attribute value."""
    if value is None:
        return "none"
    if isinstance(value, bool):
        return int(value)
    return value


def _command_line() -> str:
    from .._provenance import command_line

    return command_line()


def _check_distinct_outputs(store: Any, csv: Any) -> None:
    if store is not None and csv is not None:
        if Path(store).resolve() == Path(csv).resolve():
            raise InputError("csv", f"{str(csv)!r} is also the NetCDF output; choose another name")


def _common_attrs(spec: SweepSpec) -> dict[str, Any]:
    attrs: dict[str, Any] = {
        "case": spec.case,
        "torque_model": spec.torque_model,
        "spin_mode": spec.spin_mode,
        "normal_load": spec.weight_model,
        "t_max_s": spec.t_max if spec.t_max is not None else spec.build_case({}).t_max,
        "obturator_version": _version(),
        # CF / ACDD global attributes (date_created and history are added when written)
        "Conventions": "CF-1.10",
        "source": f"obturator {_version()} (ball obturator opening model, Bloomer 1980)",
    }
    for key, value in asdict(spec.options).items():
        attrs[f"solver_{key}"] = _attr(value)
    if spec.case == "flight" and spec.resolved().get("altitude_m") is None:
        attrs["p1_Pa"] = TABLE1["p1"]
    return attrs


def _coord(name: str, values: Any) -> tuple[Any, Any, dict[str, str]]:
    p = PARAMETERS[name]
    return (name, values, {"units": p.unit, "long_name": p.long_name})


def _status_attrs() -> dict[str, Any]:
    return {
        "long_name": "integration outcome",
        "flag_values": np.array(list(_STATUS_FLAGS), dtype=np.int8),
        "flag_meanings": " ".join(_STATUS_FLAGS.values()),
    }


_T_CR_ATTRS = {
    "units": "s",
    "long_name": "opening time t_cr (theta reaches theta_cr = beta_s)",
    "comment": "NaN where the bore did not open by t_max or the point failed; see status",
}


def _grid_dataset(spec: SweepSpec, t_cr: np.ndarray, status: np.ndarray) -> xarray.Dataset:
    import xarray as xr

    dims = spec.dims
    coords: dict[str, Any] = {d: (d, spec.axes[d], _coord(d, None)[2]) for d in dims}
    for name, value in spec.resolved().items():
        if name not in dims and value is not None:
            coords[name] = ((), value, _coord(name, None)[2])
    data = {
        "t_cr": (dims, t_cr.reshape(spec.shape), _T_CR_ATTRS),
        "status": (dims, status.reshape(spec.shape), _status_attrs()),
    }
    attrs = {"title": f"obturator sweep of t_cr over {', '.join(dims) or 'one point'}"}
    attrs.update(_common_attrs(spec))
    attrs["spec_hash"] = spec.digest()
    return xr.Dataset(data, coords=coords, attrs=attrs)


def write_netcdf(ds: xarray.Dataset, path: str | os.PathLike[str]) -> str:
    """Write ``ds`` to NetCDF atomically; return the engine used (netcdf4 or scipy)."""
    try:
        import netCDF4  # noqa: F401

        engine = "netcdf4"
    except ImportError:  # pragma: no cover - optional engine
        engine = "scipy"
    out = Path(path)
    tmp = out.with_name(f".{out.name}.{os.getpid()}.tmp")
    try:
        ds.to_netcdf(tmp, engine=engine)
        os.replace(tmp, out)
    finally:
        tmp.unlink(missing_ok=True)
    return engine


def write_csv(ds: xarray.Dataset, path: str | os.PathLike[str]) -> None:
    """Write a sweep or Monte Carlo dataset as a flat CSV table (units in the header), atomically.

    Leading ``#`` lines carry everything that is not a column: the fixed
    parameters (scalar coordinates with units), the case, models, solver
    settings, package version and the command line (the dataset's attributes),
    so a CSV alone says what it was computed with. Then one row per grid point
    (C order) or sample: the swept (or sampled) parameters, ``t_cr [s]`` (empty
    where not opened) and ``status``. Written to a temporary file and renamed.
    """
    if "sample" in ds.dims:
        cols = [v for v in ds.data_vars if ds[v].dims == ("sample",) and v in PARAMETERS]
        table = [ds[c].values for c in cols]
        t = ds["t_cr"].values
        s = ds["status"].values
    else:
        cols = list(ds["t_cr"].dims)
        mesh = np.meshgrid(*[ds[c].values for c in cols], indexing="ij")
        table = [m.reshape(-1) for m in mesh]
        t = ds["t_cr"].values.reshape(-1)
        s = ds["status"].values.reshape(-1)
    lines = []
    for name, coord in ds.coords.items():
        if coord.ndim == 0:
            unit = coord.attrs.get("units", "")
            lines.append(f"# {name} = {coord.item()!r} {unit}".rstrip())
    for key, value in ds.attrs.items():
        if np.ndim(value) == 0:
            lines.append(f"# {key} = {' '.join(str(value).split())}")
    header = [f"{c} [{PARAMETERS[c].unit}]" for c in cols] + ["t_cr [s]", "status"]
    lines.append(",".join(header))
    for k in range(t.size):
        cells = [f"{col[k]:.12g}" for col in table]
        cells.append(f"{t[k]:.12g}" if math.isfinite(t[k]) else "")
        cells.append(str(int(s[k])))
        lines.append(",".join(cells))
    _atomic_write_text(Path(path), "\n".join(lines) + "\n")


def _write_outputs(
    ds: xarray.Dataset, out: _Outcome, store: Any, csv: str | os.PathLike[str] | None
) -> None:
    """NetCDF, then CSV, each atomic; the sidecar goes only after both are in place.

    The files get the CF ``date_created`` and ``history`` (the command line); the
    returned dataset does not, so two runs of one study compare identical.
    """
    now = datetime.now(UTC).isoformat(timespec="seconds")
    ds = ds.assign_attrs(date_created=now, history=f"{now}: {_command_line()}")
    for path, write in ((store, write_netcdf), (csv, write_csv)):
        if path is None:
            continue
        try:
            write(ds, path)
        except (OSError, RuntimeError) as exc:  # full disk, quota, I/O error, HDF error
            kept = f"; the finished points are kept in {out.sidecar.path}" if out.sidecar else ""
            reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
            if out.sidecar is not None:
                out.sidecar.close()
            raise InputError(
                "out", f"cannot write {str(path)!r}: {reason}{kept}; free space and rerun"
            ) from None
    if out.sidecar is not None:
        out.sidecar.remove()


# --------------------------------------------------------------------------- sweeps


@dataclass(frozen=True)
class SweepRun:
    """Outcome of :func:`execute_sweep`.

    Attributes
    ----------
    dataset : xarray.Dataset
        The results (see :func:`run_sweep`).
    n_computed, n_resumed : int
        Points integrated in this call and points taken from the sidecar.
    workers : int
        Local processes used (1: in this process; 0: a dask cluster).
    backend : str
        ``"local"`` or ``"dask.distributed"``.
    elapsed_s : float
        Wall time of the computation [s] (without writing files).
    """

    dataset: xarray.Dataset
    n_computed: int
    n_resumed: int
    workers: int
    backend: str
    elapsed_s: float


def execute_sweep(
    spec: SweepSpec,
    *,
    workers: int | None = None,
    scheduler: Any = None,
    store: str | os.PathLike[str] | None = None,
    restart: bool = False,
    chunk_size: int | None = None,
    progress: bool = True,
    csv: str | os.PathLike[str] | None = None,
) -> SweepRun:
    """Run a sweep and return the dataset with run statistics; see :func:`run_sweep`.

    `csv`, if given, is written (atomically) before the partial-results file is
    removed, so an interruption while writing outputs loses nothing.
    """
    if not isinstance(spec, SweepSpec):
        raise InputError("spec", "expected a SweepSpec")
    _check_distinct_outputs(store, csv)
    out = _compute(
        spec,
        spec.dims,
        spec.rows,
        spec.n_points,
        spec.digest(),
        workers=workers,
        scheduler=scheduler,
        store=store,
        restart=restart,
        chunk_size=chunk_size,
        progress=progress,
        label="sweep",
        extra_outputs=() if csv is None else (str(csv),),
    )
    ds = _grid_dataset(spec, out.t_cr, out.status)
    _write_outputs(ds, out, store, csv)
    return SweepRun(ds, out.n_computed, out.n_resumed, out.workers, out.backend, out.elapsed_s)


def run_sweep(
    spec: SweepSpec,
    *,
    workers: int | None = None,
    scheduler: Any = None,
    store: str | os.PathLike[str] | None = None,
    progress: bool = True,
    restart: bool = False,
    chunk_size: int | None = None,
) -> xarray.Dataset:
    """Evaluate t_cr on the full Cartesian grid of a :class:`SweepSpec`.

    Parameters
    ----------
    spec : SweepSpec
    workers : int, optional
        Local worker processes (default: the CPUs available). 1 runs in this
        process. Ignored when `scheduler` is given.
    scheduler : str or distributed.Client, optional
        Address of a dask.distributed scheduler (``"tcp://host:8786"``) or a
        client; the chunks are computed on that cluster instead.
    store : path, optional
        NetCDF file to write at the end; while running, finished chunks go to
        ``<store>.partial.jsonl`` so that an interrupted run resumes.
    progress : bool
        Show a rich progress bar on stderr.
    restart : bool
        Discard a sidecar left by a *different* study instead of failing.
    chunk_size : int, optional
        Points per task (default: about 8 tasks per worker, at most 64 points).

    Returns
    -------
    xarray.Dataset
        ``t_cr`` [s] over the swept dimensions (NaN where not opened),
        ``status`` (1 opened, 0 not opened by t_max, -1 solver failure or step
        limit, -2 invalid input), coordinates with ``units``, scalar
        coordinates for the parameters not swept, and attributes with the
        case, torque model, spin mode, solver settings, package version and
        the study hash.

    Raises
    ------
    InputError
        On a bad worker count or chunk size, a missing output directory, an
        unreachable scheduler, or a sidecar of a different study.
    """
    return execute_sweep(
        spec,
        workers=workers,
        scheduler=scheduler,
        store=store,
        restart=restart,
        chunk_size=chunk_size,
        progress=progress,
    ).dataset


def sweep_summary(ds: xarray.Dataset) -> dict[str, Any]:
    """Counts and the t_cr range of a sweep (or Monte Carlo) dataset.

    Returns
    -------
    dict
        ``n_points``, ``n_opened``, ``n_not_opened``, ``n_failed``,
        ``n_invalid``, ``t_cr_min_s``, ``t_cr_max_s`` (None if nothing opened)
        and ``argmin``: the parameter values at the smallest t_cr.
    """
    t = np.asarray(ds["t_cr"].values, dtype=float)
    s = np.asarray(ds["status"].values)
    res: dict[str, Any] = {
        "n_points": int(t.size),
        "n_opened": int(np.sum(s == STATUS_OPENED)),
        "n_unconverged": int(np.sum(s == STATUS_UNCONVERGED)),
        "n_not_opened": int(np.sum(s == STATUS_NOT_OPENED)),
        "n_failed": int(np.sum(s == STATUS_FAILED)),
        "n_invalid": int(np.sum(s == STATUS_INVALID)),
        "t_cr_min_s": None,
        "t_cr_max_s": None,
        "argmin": {},
    }
    if np.any(np.isfinite(t)):
        res["t_cr_min_s"] = float(np.nanmin(t))
        res["t_cr_max_s"] = float(np.nanmax(t))
        if "sample" not in ds["t_cr"].dims and t.ndim:
            where = np.unravel_index(int(np.nanargmin(t)), t.shape)
            res["argmin"] = {
                d: float(ds[d].values[i]) for d, i in zip(ds["t_cr"].dims, where, strict=True)
            }
    return res


# --------------------------------------------------------------------------- Monte Carlo

DistKind = Literal["normal", "uniform", "lognormal", "truncnormal"]
_DIST_ARGS = {"normal": 2, "uniform": 2, "lognormal": 2, "truncnormal": 4}
_DIST_HELP = (
    "normal:MEAN,SD | uniform:LO,HI | lognormal:MEDIAN,SIGMA_LN | truncnormal:MEAN,SD,LO,HI"
)


@dataclass(frozen=True)
class Distribution:
    """Distribution of one uncertain input (values in the parameter's unit).

    Parameters
    ----------
    kind : {"normal", "uniform", "lognormal", "truncnormal"}
        ``normal``: (mean, sd), sd >= 0. ``uniform``: (lo, hi), lo < hi.
        ``lognormal``: (median, sigma_ln) with ln X ~ Normal(ln median,
        sigma_ln); median > 0, sigma_ln >= 0. ``truncnormal``: (mean, sd, lo,
        hi): a normal restricted to [lo, hi], sd > 0, lo < hi.
    params : tuple of float
    """

    kind: DistKind
    params: tuple[float, ...]

    def __post_init__(self) -> None:
        if self.kind not in _DIST_ARGS:
            raise InputError("distribution", f"{self.kind!r}; allowed: {_DIST_HELP}")
        p = tuple(float(x) for x in self.params)
        object.__setattr__(self, "params", p)
        if len(p) != _DIST_ARGS[self.kind]:
            raise InputError(
                "distribution", f"{self.kind} takes {_DIST_ARGS[self.kind]} numbers, got {len(p)}"
            )
        if not all(math.isfinite(x) for x in p):
            raise InputError("distribution", f"{self} has non-finite parameters")
        k = self.kind
        if k == "normal" and p[1] < 0:
            raise InputError("distribution", f"{self}: SD must be >= 0")
        if k == "uniform" and not p[0] < p[1]:
            raise InputError("distribution", f"{self}: needs LO < HI")
        if k == "lognormal" and (p[0] <= 0 or p[1] < 0):
            raise InputError("distribution", f"{self}: needs MEDIAN > 0 and SIGMA_LN >= 0")
        if k == "truncnormal" and (p[1] <= 0 or not p[2] < p[3]):
            raise InputError("distribution", f"{self}: needs SD > 0 and LO < HI")

    def __str__(self) -> str:
        return f"{self.kind}:{','.join(repr(x) for x in self.params)}"

    def draw(self, rng: np.random.Generator) -> float:
        """One value drawn with ``rng``."""
        p = self.params
        if self.kind == "normal":
            return p[0] + p[1] * float(rng.standard_normal())
        if self.kind == "uniform":
            return p[0] + (p[1] - p[0]) * float(rng.random())
        if self.kind == "lognormal":
            return p[0] * math.exp(p[1] * float(rng.standard_normal()))
        return _truncnormal(p[0], p[1], p[2], p[3], float(rng.random()))


def _truncnormal(mean: float, sd: float, lo: float, hi: float, u: float) -> float:
    """Inverse-CDF draw of a normal truncated to [lo, hi] from u in [0, 1).

    :func:`scipy.stats.truncnorm` works in log space in the tails, so a window many
    standard deviations away from the mean is sampled correctly (a plain
    ndtr/ndtri inversion underflows there and returns an end point every time).
    """
    from scipy.stats import truncnorm

    a, b = (lo - mean) / sd, (hi - mean) / sd
    z = float(truncnorm.ppf(u, a, b))
    return min(max(mean + sd * z, lo), hi)


def parse_distribution(text: str) -> tuple[str, Distribution]:
    """Parse ``name=kind:args``, e.g. ``mu_s=normal:0.5473,0.03``.

    Parameters
    ----------
    text : str
        ``NAME=normal:MEAN,SD``, ``NAME=uniform:LO,HI``,
        ``NAME=lognormal:MEDIAN,SIGMA_LN`` or ``NAME=truncnormal:MEAN,SD,LO,HI``;
        NAME one of :data:`PARAMETERS` (hyphens allowed), numbers in its unit.

    Returns
    -------
    (str, Distribution)
    """
    s = text.strip() if isinstance(text, str) else ""
    if "=" not in s or ":" not in s.split("=", 1)[1]:
        raise InputError("vary", f"malformed {text!r}: expected NAME=KIND:ARGS ({_DIST_HELP})")
    name_text, rest = s.split("=", 1)
    name = _canonical_name(name_text)
    kind, args = rest.split(":", 1)
    kind = kind.strip().lower()
    if kind not in _DIST_ARGS:
        raise InputError(name, f"unknown distribution {kind!r}; allowed: {_DIST_HELP}")
    unit = PARAMETERS[name].unit
    items = args.split(",")
    # lognormal's SIGMA_LN is a pure number; every other parameter is in the unit
    units = [unit if not (kind == "lognormal" and i == 1) else "1" for i in range(len(items))]
    numbers = [_float(name, a, "parameter", u) for a, u in zip(items, units, strict=True)]
    try:
        return name, Distribution(kind, tuple(numbers))  # type: ignore[arg-type]
    except InputError as exc:
        raise InputError(name, str(exc).split(": ", 1)[1]) from None


def sample_inputs(
    distributions: Mapping[str, Distribution], samples: int, seed: int
) -> dict[str, np.ndarray]:
    """Draw the inputs of every sample.

    Sample i uses its own generator ``default_rng(SeedSequence(seed).spawn(n)[i])``
    and draws the parameters in :data:`PARAMETERS` order, so it does not depend
    on the worker count, the chunking, the total ``samples`` or the order in
    which the distributions were given.

    Returns
    -------
    dict of str to numpy.ndarray
        name -> values, shape (samples,), in the parameter's unit.
    """
    n = int(samples)
    names = [k for k in PARAMETERS if k in distributions]
    out = {k: np.empty(n) for k in names}
    for i, child in enumerate(np.random.SeedSequence(int(seed)).spawn(n)):
        rng = np.random.default_rng(child)
        for k in names:
            out[k][i] = distributions[k].draw(rng)
    return out


def _check_samples(values: Mapping[str, np.ndarray]) -> None:
    for name, x in values.items():
        lo, hi, lo_open, hi_open = _RANGES[name]
        bad = ~(((x > lo) if lo_open else (x >= lo)) & ((x < hi) if hi_open else (x <= hi)))
        if np.any(bad):
            i = int(np.flatnonzero(bad)[0])
            left, right = "(" if lo_open else "[", ")" if hi_open else "]"
            raise InputError(
                name,
                f"{int(bad.sum())} sampled values fall outside the allowed range "
                f"{left}{lo:g}, {hi:g}{right} {PARAMETERS[name].unit} (first: sample {i}, "
                f"{x[i]:g}); narrow the distribution or use truncnormal",
            )


def _check_sample_cases(spec: SweepSpec, values: Mapping[str, np.ndarray]) -> None:
    """Build every sample's case before any integration; refuse the study if any is invalid.

    Per-parameter ranges are checked by :func:`_check_samples`; this catches the
    combined limits of the case factories (theta_0 above the opening angle
    beta_s, the hole inside the ball, ...), so a distribution whose support
    leaves the physical domain is an input error, not a study whose every
    sample is silently invalid.
    """
    names = list(values)
    n = len(values[names[0]]) if names else 0
    bad: list[int] = []
    first = ""
    for i in range(n):
        try:
            spec.build_case({k: float(values[k][i]) for k in names})
        except InputError as exc:
            bad.append(i)
            first = first or str(exc)
    if bad:
        raise InputError(
            "vary",
            f"{len(bad)} of {n} samples are not valid cases (first: sample {bad[0]}, {first}); "
            "narrow the distribution or use truncnormal",
        )


@dataclass(frozen=True)
class QuantileEstimate:
    """One t_cr quantile with its confidence interval.

    Attributes
    ----------
    probability : float
        p in (0, 1).
    value, lower, upper : float
        Estimate and interval [s]. ``value = inf`` means "beyond t_max" (the
        order statistic is a sample that did not open); ``upper = inf`` an
        open upper end (that, or too few samples), ``lower = -inf`` a missing
        lower bound (too few samples for the confidence asked).
    coverage : float
        Exact binomial coverage of [lower, upper] (>= the confidence asked).
    """

    probability: float
    value: float
    lower: float
    upper: float
    coverage: float

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready; non-finite bounds become None with flags."""

        def f(x: float) -> float | None:
            return x if math.isfinite(x) else None

        return {
            "probability": self.probability,
            "t_cr_s": f(self.value),
            "lower_s": f(self.lower),
            "upper_s": f(self.upper),
            "coverage": self.coverage,
            "beyond_t_max": bool(self.value == math.inf),
        }


@dataclass(frozen=True)
class MonteCarloSummary:
    """Summary of a Monte Carlo study of t_cr.

    Attributes
    ----------
    n_samples, n_opened, n_not_opened, n_failed, n_invalid : int
    fraction_not_opened : float
        Not opened by t_max, among the opened + not opened samples.
    fraction_not_opened_ci : (float, float)
        Clopper-Pearson interval at ``confidence``.
    quantiles : tuple of QuantileEstimate
    confidence : float
    t_max : float
        Give-up time [s] (not-opened samples count as t_cr > t_max).
    mean_s, std_s : float
        Mean and sample standard deviation of t_cr over the opened samples [s].
    """

    n_samples: int
    n_opened: int
    n_not_opened: int
    n_failed: int
    n_invalid: int
    fraction_not_opened: float
    fraction_not_opened_ci: tuple[float, float]
    quantiles: tuple[QuantileEstimate, ...]
    confidence: float
    t_max: float
    mean_s: float
    std_s: float
    n_unconverged: int = 0

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict."""
        d = {
            k: getattr(self, k)
            for k in (
                "n_samples",
                "n_opened",
                "n_not_opened",
                "n_failed",
                "n_invalid",
                "n_unconverged",
                "fraction_not_opened",
                "confidence",
                "t_max",
            )
        }
        d["fraction_not_opened_ci"] = list(self.fraction_not_opened_ci)
        d["mean_s"] = self.mean_s if math.isfinite(self.mean_s) else None
        d["std_s"] = self.std_s if math.isfinite(self.std_s) else None
        d["quantiles"] = [q.to_dict() for q in self.quantiles]
        d["ci_method"] = _CI_METHOD
        return d


_CI_METHOD = (
    "quantile: order statistic x_(ceil(n p)); interval [x_(l), x_(u)] with "
    "l = binom.ppf(a/2, n, p), u = binom.ppf(1 - a/2, n, p) + 1 (distribution-free); "
    "fraction not opened: Clopper-Pearson"
)


def _quantile_ci(x_sorted: np.ndarray, p: float, confidence: float) -> QuantileEstimate:
    from scipy.stats import binom

    n = x_sorted.size
    if n == 0:
        return QuantileEstimate(p, math.nan, math.nan, math.nan, math.nan)
    k = min(max(math.ceil(n * p - 1e-12), 1), n)
    alpha = 1.0 - confidence
    lo = int(binom.ppf(alpha / 2, n, p))
    hi = int(binom.ppf(1 - alpha / 2, n, p)) + 1
    coverage = float(binom.cdf(hi - 1, n, p) - binom.cdf(lo - 1, n, p))
    lower = float(x_sorted[lo - 1]) if lo >= 1 else -math.inf
    upper = float(x_sorted[hi - 1]) if hi <= n else math.inf
    return QuantileEstimate(p, float(x_sorted[k - 1]), lower, upper, coverage)


def summarize_monte_carlo(
    t_cr: np.ndarray,
    status: np.ndarray,
    *,
    t_max: float,
    quantiles: Sequence[float] = (0.05, 0.5, 0.95),
    confidence: float = 0.95,
) -> MonteCarloSummary:
    """Quantiles of t_cr with confidence intervals, and the fraction not opened.

    Samples that did not open by t_max are kept as right-censored values
    (t_cr > t_max, ranked last), so a quantile that falls among them is
    reported as ``inf`` ("beyond t_max"). Solver failures and invalid samples
    are left out (and counted). Quantile intervals are distribution-free
    order-statistic intervals: with B ~ Binomial(n, p) the number of samples
    below the true quantile, [x_(l), x_(u)] covers it with probability
    P(l <= B <= u - 1) >= ``confidence``; the exact coverage is reported.

    Parameters
    ----------
    t_cr : array_like
        Opening times [s] (NaN where not opened).
    status : array_like
        Status codes (see :data:`STATUS_OPENED` etc.).
    t_max : float
        Give-up time of the runs [s].
    quantiles : sequence of float
        Probabilities in (0, 1).
    confidence : float
        Confidence level of the intervals, in (0, 1).
    """
    from scipy.stats import beta

    conf = check_range("confidence", confidence, 0.0, 1.0, lo_open=True, hi_open=True)
    probs = [check_range("quantile", q, 0.0, 1.0, lo_open=True, hi_open=True) for q in quantiles]
    t = np.asarray(t_cr, dtype=float).reshape(-1)
    s = np.asarray(status).reshape(-1)
    # opened-but-not-converged samples (status 2) are regularisation artefacts
    # until shown otherwise: excluded from quantiles and mean, counted apart
    opened = t[s == STATUS_OPENED]
    n_not = int(np.sum(s == STATUS_NOT_OPENED))
    ranked = np.sort(np.concatenate([opened, np.full(n_not, np.inf)]))
    n_valid = ranked.size
    alpha = 1.0 - conf
    if n_valid:
        frac = n_not / n_valid
        lo = 0.0 if n_not == 0 else float(beta.ppf(alpha / 2, n_not, n_valid - n_not + 1))
        hi = 1.0 if n_not == n_valid else float(beta.ppf(1 - alpha / 2, n_not + 1, n_valid - n_not))
    else:
        frac, lo, hi = math.nan, math.nan, math.nan
    return MonteCarloSummary(
        n_samples=int(t.size),
        n_opened=int(opened.size),
        n_not_opened=n_not,
        n_failed=int(np.sum(s == STATUS_FAILED)),
        n_invalid=int(np.sum(s == STATUS_INVALID)),
        fraction_not_opened=frac,
        fraction_not_opened_ci=(lo, hi),
        quantiles=tuple(_quantile_ci(ranked, p, conf) for p in probs),
        confidence=conf,
        t_max=float(t_max),
        mean_s=float(opened.mean()) if opened.size else math.nan,
        std_s=float(opened.std(ddof=1)) if opened.size > 1 else math.nan,
        n_unconverged=int(np.sum(s == STATUS_UNCONVERGED)),
    )


def monte_carlo(
    case: str = "spin-rig",
    vary: Mapping[str, Distribution | str] | Sequence[str] = (),
    *,
    samples: int,
    seed: int,
    fixed: Mapping[str, float] | None = None,
    torque_model: str = "thesis",
    spin_mode: str = "constant",
    options: SolverOptions | None = None,
    t_max: float | None = None,
    quantiles: Sequence[float] = (0.05, 0.5, 0.95),
    confidence: float = 0.95,
    workers: int | None = None,
    scheduler: Any = None,
    store: str | os.PathLike[str] | None = None,
    restart: bool = False,
    chunk_size: int | None = None,
    progress: bool = True,
    csv: str | os.PathLike[str] | None = None,
    check_convergence: bool = True,
) -> xarray.Dataset:
    """Monte Carlo study of t_cr under uncertain inputs.

    Every opened sample is checked for convergence by default (tolerances / 10,
    friction width / 10, another regularisation family; four times the cost):
    a sample whose t_cr moves by more than 1e-3 gets status 2
    (``opened_not_converged``), stays in the dataset, and is excluded from the
    quantiles and the mean (counted in ``n_unconverged``).

    Parameters
    ----------
    case : {"spin-rig", "flight"}
    vary : mapping of str to Distribution or str, or sequence of str
        Uncertain inputs: ``{"mu_s": Distribution("normal", (0.5473, 0.03))}``,
        ``{"mu_s": "normal:0.5473,0.03"}`` or ``["mu_s=normal:0.5473,0.03"]``
        (see :func:`parse_distribution`); any name in :data:`PARAMETERS`.
    samples : int
        Number of samples n >= 1.
    seed : int
        Root seed (>= 0); sample i uses ``SeedSequence(seed).spawn(n)[i]``.
    fixed : mapping of str to float, optional
        Inputs held fixed (e.g. ``{"spin_rate": 300.0}``); see :class:`SweepSpec`.
    torque_model, spin_mode, options, t_max
        As in :class:`SweepSpec`.
    quantiles : sequence of float
        Probabilities reported, default 5, 50 and 95 %.
    confidence : float
        Confidence level of the intervals.
    workers, scheduler, store, restart, chunk_size, progress
        As in :func:`run_sweep` (the store holds the samples' results).

    Returns
    -------
    xarray.Dataset
        Along ``sample``: the sampled inputs (with units), ``t_cr`` [s] and
        ``status``; along ``quantile``: ``t_cr_quantile``, ``t_cr_quantile_lower``,
        ``t_cr_quantile_upper`` [s] (inf = beyond t_max) and ``ci_coverage``;
        attributes with the distributions, seed, counts, fraction not opened
        and its interval, and the solver settings.
    """
    import xarray as xr

    dists = _distributions(vary)
    try:
        n = int(samples)
    except (TypeError, ValueError):
        raise InputError("samples", f"expected a whole number, got {samples!r}") from None
    if n < 1 or n > _MAX_POINTS:
        raise InputError("samples", f"{n} is outside the allowed range [1, {_MAX_POINTS}]")
    try:
        seed_i = int(seed)
    except (TypeError, ValueError):
        raise InputError("seed", f"expected a whole number, got {seed!r}") from None
    if seed_i < 0:
        raise InputError("seed", f"{seed_i} is outside the allowed range >= 0")
    _check_distinct_outputs(store, csv)
    fixed = dict(fixed or {})
    for name in dists:
        if name in fixed:
            raise InputError(name, "is both varied and fixed")
    spec = SweepSpec(
        case,
        {},
        fixed,
        torque_model=torque_model,
        spin_mode=spin_mode,
        options=options or SolverOptions(),
        t_max=t_max,
        check_convergence=bool(check_convergence),
    )
    for name in dists:
        spec._check_name(name)
    values = sample_inputs(dists, n, seed_i)
    _check_samples(values)
    _check_sample_cases(spec, values)
    names = tuple(values)
    table = np.column_stack([values[k] for k in names]) if names else np.empty((n, 0))
    ident = {
        "spec": spec.identity(),
        "vary": {k: str(d) for k, d in dists.items()},
        "seed": seed_i,
        "samples": n,
    }
    digest = hashlib.sha256(json.dumps(ident, sort_keys=True).encode()).hexdigest()
    out = _compute(
        spec,
        names,
        lambda idx: table[idx],
        n,
        digest,
        workers=workers,
        scheduler=scheduler,
        store=store,
        restart=restart,
        chunk_size=chunk_size,
        progress=progress,
        label="monte carlo",
        extra_outputs=() if csv is None else (str(csv),),
    )
    t_max_used = spec.t_max if spec.t_max is not None else spec.build_case({}).t_max
    summ = summarize_monte_carlo(
        out.t_cr, out.status, t_max=t_max_used, quantiles=quantiles, confidence=confidence
    )
    data: dict[str, Any] = {k: ("sample", values[k], _coord(k, None)[2]) for k in names}
    data["t_cr"] = ("sample", out.t_cr, _T_CR_ATTRS)
    data["status"] = ("sample", out.status, _status_attrs())
    q_attrs = {"units": "s", "comment": "inf: the order statistic did not open by t_max"}
    qs = summ.quantiles
    data["t_cr_quantile"] = ("quantile", [q.value for q in qs], q_attrs)
    data["t_cr_quantile_lower"] = ("quantile", [q.lower for q in qs], q_attrs)
    data["t_cr_quantile_upper"] = ("quantile", [q.upper for q in qs], q_attrs)
    data["ci_coverage"] = ("quantile", [q.coverage for q in qs], {"units": "1"})
    coords: dict[str, Any] = {
        "sample": ("sample", np.arange(n), {"long_name": "sample number"}),
        "quantile": ("quantile", [q.probability for q in qs], {"units": "1"}),
    }
    for name, value in spec.resolved().items():
        if name not in names and value is not None:
            coords[name] = ((), value, _coord(name, None)[2])
    attrs: dict[str, Any] = {
        "title": "obturator Monte Carlo study of t_cr",
        "distributions": "; ".join(f"{k}={d}" for k, d in dists.items()) or "none",
        "seed": seed_i,
        "samples": n,
        "seeding": "numpy.random.SeedSequence(seed).spawn(samples), one child per sample",
        "confidence": summ.confidence,
        "ci_method": _CI_METHOD,
        "n_opened": summ.n_opened,
        "n_not_opened": summ.n_not_opened,
        "n_failed": summ.n_failed,
        "n_invalid": summ.n_invalid,
        "n_unconverged": summ.n_unconverged,
        "fraction_not_opened": summ.fraction_not_opened,
        "fraction_not_opened_ci": np.array(summ.fraction_not_opened_ci),
        "mean_t_cr_s": summ.mean_s,
        "std_t_cr_s": summ.std_s,
    }
    attrs.update(_common_attrs(spec))
    attrs["study_hash"] = digest
    ds = xr.Dataset(data, coords=coords, attrs=attrs)
    _write_outputs(ds, out, store, csv)
    return ds


def _distributions(vary: Any) -> dict[str, Distribution]:
    dists: dict[str, Distribution] = {}
    items: list[tuple[str, Distribution]] = []
    if isinstance(vary, Mapping):
        for key, d in vary.items():
            name = _canonical_name(key)
            if isinstance(d, str):
                _, d = parse_distribution(f"{name}={d}")
            if not isinstance(d, Distribution):
                raise InputError(name, f"expected a Distribution or text, got {d!r}")
            items.append((name, d))
    elif isinstance(vary, str):
        items.append(parse_distribution(vary))
    else:
        items.extend(parse_distribution(v) for v in vary)
    for name, d in items:
        if name in dists:
            raise InputError(name, "is varied twice")
        dists[name] = d
    return dists


def monte_carlo_summary(ds: xarray.Dataset) -> MonteCarloSummary:
    """Recompute the :class:`MonteCarloSummary` of a :func:`monte_carlo` dataset."""
    return summarize_monte_carlo(
        ds["t_cr"].values,
        ds["status"].values,
        t_max=float(ds.attrs["t_max_s"]),
        quantiles=[float(q) for q in ds["quantile"].values],
        confidence=float(ds.attrs["confidence"]),
    )
