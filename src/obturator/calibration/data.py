"""Spin-rig opening times: the thesis's Appendix B runs and a user's CSV (chapter III).

The rig spins a lucite "projectile" holding the ball; a counter reads the
passing frequency f of an 18-tooth bucket wheel, so omega_p = f pi / 9
(chapter III.C). Appendix B lists 54 runs (readout, t_cr, printed omega_p);
the starred runs (omega_p >= 235.97 rad/s) are fitted in chapter IV to the
large-spin form t = T2 omega_p (Eq. 96), and T2 gives the friction coefficient
through Eq. (95), mu_bar = 3.03e-4 / T2, and mu_s = mu_bar / ((2/pi) E(theta0)).

The thesis's chapter IV fit of these runs (and what it reproduces) is in
:mod:`obturator.calibration.thesis_fit`.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._docs import field_docs
from ..errors import InputError, check_range
from ..reference import APPENDIX_B_CSV, RIG_TEETH, data_text
from .schema import (
    _KNOWN,
    _PRINTED,
    _READOUT,
    _SPIN,
    _STARRED,
    _STRICT_NUMBER,
    _TIME,
    CASE_COLUMNS,
    RUN_COLUMNS,
    SETTING_NAMES,
    _fail,
    check_header,
    check_runs,
    column_help,
    column_unit,
)

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

__all__ = [
    "SpinRigData",
    "load_spin_rig_csv",
    "load_thesis_data",
    "readout_to_spin_rate",
    "MAX_RUNS",
    "MAX_LINE_CHARS",
    "CASE_COLUMNS",
    "RUN_COLUMNS",
    "column_help",
]

#: Most runs in one data file. Every least-squares iteration integrates every run, so a
#: fit's time grows with the runs, with no progress to show: this bound keeps it within
#: minutes (``docs/benchmarks.md``, history); a rig campaign has tens to hundreds of runs.
MAX_RUNS = 2_000
#: Longest line of a data file [characters]: a row is a few numbers (the csv
#: module's own field limit, 128 KiB, would otherwise end the read with its error).
MAX_LINE_CHARS = 1_000
#: Allowed values (lo, hi] per column and unit: positive, and far enough from 0 and
#: infinity that reciprocals and squares stay finite (1 us to 11.6 days for a time).
_LIMITS = {"s": (0.0, 1e6), "Hz": (0.0, 1e7), "rad/s": (0.0, 1e6)}
_MIN_TIME = 1e-6

_TRUE = {"1", "true", "yes", "y", "*"}
_FALSE = {"0", "false", "no", "n", ""}


def readout_to_spin_rate(readout_hz: ArrayLike, teeth: int = RIG_TEETH) -> NDArray[np.float64]:
    """Counter readout to spin rate, omega_p = 2 pi f / teeth [rad/s] (chapter III.C).

    Parameters
    ----------
    readout_hz : array_like
        Tooth-passing frequency f [Hz].
    teeth : int
        Teeth on the bucket wheel (18 on Bloomer's rig, giving f pi / 9).
    """
    return 2.0 * math.pi * np.asarray(readout_hz, dtype=float) / teeth


def _frozen(a: ArrayLike | None, dtype: Any) -> NDArray[Any] | None:
    if a is None:
        return None
    out = np.array(a, dtype=dtype, copy=True).reshape(-1)
    out.setflags(write=False)
    return out


@field_docs
@dataclass(frozen=True, kw_only=True)
class SpinRigData:
    """Opening times measured on the spin rig."""

    #: Rig spin omega_p [rad/s] (from the readout where there is one).
    spin_rate: NDArray[np.float64]
    #: Measured opening time t_cr [s].
    opening_time: NDArray[np.float64]
    #: Runs marked for the least-squares fit.
    starred: NDArray[np.bool_]
    #: Counter readout f [Hz]; None for files that give omega_p directly.
    readout_hz: NDArray[np.float64] | None = None
    #: omega_p as printed in the source [rad/s], kept for comparison.
    spin_rate_printed: NDArray[np.float64] | None = None
    #: 1-based run number in the source (defaults to 1..n).
    run: NDArray[np.int64] | None = None
    #: Where the data came from.
    source: str = ""
    #: Optional per-run settings of the rig (NaN where a run leaves it at Table 1): ``theta0_deg``
    #: [deg], ``hole_radius`` [m], ``density`` [kg/m^3], ``ball_mass`` [kg] (the load W = m g), and
    #: ``theta_measured_deg`` [deg] with ``t_measured`` [s], an intermediate angle the laser readout
    #: saw and the time from release to it (:data:`RUN_COLUMNS`).
    settings: dict[str, NDArray[np.float64]] = field(default_factory=dict)
    #: Number of runs, set at construction (private; see ``len()``).
    _n: int = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        n = np.size(self.spin_rate)
        set_ = object.__setattr__
        set_(self, "spin_rate", _frozen(self.spin_rate, float))
        set_(self, "opening_time", _frozen(self.opening_time, float))
        set_(self, "starred", _frozen(self.starred, bool))
        set_(self, "readout_hz", _frozen(self.readout_hz, float))
        set_(self, "spin_rate_printed", _frozen(self.spin_rate_printed, float))
        set_(self, "run", _frozen(np.arange(1, n + 1) if self.run is None else self.run, np.int64))
        set_(self, "_n", n)
        set_(self, "settings", {k: _frozen(v, float) for k, v in self.settings.items()})
        for k, v in self.settings.items():
            if v.size != n:
                raise InputError(k, f"has {v.size} entries, expected {n} (one per run)")
        for name in ("opening_time", "starred", "readout_hz", "spin_rate_printed", "run"):
            arr = getattr(self, name)
            if arr is not None and arr.size != n:
                raise InputError(name, f"has {arr.size} entries, expected {n} (one per run)")
        for name, unit in (("spin_rate", "rad/s"), ("opening_time", "s")):
            arr = getattr(self, name)
            bad = ~(np.isfinite(arr) & (arr > 0.0))
            if bad.any():
                i = int(np.flatnonzero(bad)[0])
                check_range(
                    f"{name}[{i}]",
                    float(arr[i]),
                    0.0,
                    math.inf,
                    lo_open=True,
                    hi_open=True,
                    unit=unit,
                )

    def __len__(self) -> int:
        return self._n

    def select(self, mask: ArrayLike) -> SpinRigData:
        """Rows where `mask` (bool array, or integer indices) is true."""
        m = np.asarray(mask)

        def pick(a: NDArray[Any] | None) -> NDArray[Any] | None:
            return None if a is None else a[m]

        return replace(
            self,
            spin_rate=self.spin_rate[m],
            opening_time=self.opening_time[m],
            starred=self.starred[m],
            readout_hz=pick(self.readout_hz),
            spin_rate_printed=pick(self.spin_rate_printed),
            run=self.run[m],
            settings={k: v[m] for k, v in self.settings.items()},
        )

    def run_settings(self) -> list[tuple[tuple[str, float], ...]]:
        """Each run's own settings as sorted (name, SI value) pairs (empty: Table 1).

        Hashable, so runs with the same settings can share a model evaluation.
        """
        names = sorted(self.settings)
        return [
            tuple(
                (k, float(self.settings[k][i])) for k in names if math.isfinite(self.settings[k][i])
            )
            for i in range(self._n)
        ]

    def fit_subset(self, min_spin_rate: float | None = None) -> SpinRigData:
        """Runs used in the chapter IV fit.

        Parameters
        ----------
        min_spin_rate : float, optional
            If given, keep runs with ``spin_rate >= min_spin_rate`` [rad/s];
            otherwise keep the starred runs.
        """
        if min_spin_rate is None:
            if not self.starred.any():
                raise InputError(
                    "starred",
                    f"{self.source or 'data'}: no starred runs; give min_spin_rate "
                    "(allowed range (0, inf) rad/s) instead",
                )
            return self.select(self.starred)
        thr = check_range("min_spin_rate", min_spin_rate, 0.0, math.inf, hi_open=True, unit="rad/s")
        return self.select(self.spin_rate >= thr)

    def exclude_runs(self, runs: Iterable[int]) -> SpinRigData:
        """Drop the given 1-based run numbers."""
        return self.select(~np.isin(self.run, np.fromiter(runs, dtype=np.int64)))

    def with_printed_spin_rate(self) -> SpinRigData:
        """Same runs with ``spin_rate`` replaced by the printed omega_p column."""
        if self.spin_rate_printed is None:
            raise InputError("spin_rate_printed", f"{self.source or 'data'}: no printed column")
        return replace(self, spin_rate=self.spin_rate_printed)

    def to_dataframe(self) -> pd.DataFrame:
        """A :class:`pandas.DataFrame` with one row per run, indexed by run number."""
        import pandas as pd

        cols: dict[str, NDArray[Any]] = {}
        if self.readout_hz is not None:
            cols[_READOUT] = self.readout_hz
        cols[_SPIN] = self.spin_rate
        if self.spin_rate_printed is not None:
            cols[_PRINTED] = self.spin_rate_printed
        cols[_TIME] = self.opening_time
        cols[_STARRED] = self.starred
        cols.update(self.settings)
        return pd.DataFrame(cols, index=pd.Index(self.run, name="run"))


def _positive(cell: str, column: str, unit: str, source: str, line: int) -> float:
    lo, hi = _LIMITS[unit]
    if unit == "s":
        lo = _MIN_TIME
    allowed = f"allowed range ({lo:g}, {hi:g}] {unit}"
    if not _STRICT_NUMBER.match(cell):
        raise _fail(column, source, line, f"{cell!r} is not a number ({allowed})")
    x = float(cell)
    if not (math.isfinite(x) and lo < x <= hi):
        raise _fail(column, source, line, f"{x:g} {unit} is outside the {allowed}")
    return x


def _parse(
    text: str, source: str, teeth: int, columns: tuple[str, ...] = tuple(RUN_COLUMNS)
) -> SpinRigData:
    """Parse CSV text; errors name `source`, the 1-based line and the column."""
    n_teeth = check_range("teeth", teeth, 1.0, math.inf, hi_open=True)
    if n_teeth != int(n_teeth):
        raise InputError("teeth", f"{teeth!r} is not a whole number (allowed range [1, inf))")
    teeth = int(n_teeth)
    header: list[str] | None = None
    header_line = 0
    rows: list[tuple[int, list[str]]] = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        if len(raw) > MAX_LINE_CHARS:
            raise InputError(
                "file", f"{source}, line {lineno}: longer than {MAX_LINE_CHARS} characters"
            )
        stripped = raw.strip()
        if not stripped or stripped.startswith("#"):
            continue
        cells = [c.strip() for c in next(csv.reader([raw]))]
        if header is None:
            header, header_line = cells, lineno
            seen = set()
            for c in cells:
                if c in seen:
                    raise _fail(c, source, lineno, f"column {c!r} appears twice in the header")
                seen.add(c)
            continue
        if cells == header:
            raise _fail(
                cells[0], source, lineno, f"duplicated header (first at line {header_line})"
            )
        if len(cells) != len(header):
            raise _fail(
                header[min(len(cells), len(header)) - 1],
                source,
                lineno,
                f"{len(cells)} fields, expected {len(header)} ({', '.join(header)})",
            )
        rows.append((lineno, cells))
        if len(rows) > MAX_RUNS:
            raise InputError(
                "file",
                f"{source}: more than {MAX_RUNS} runs (obturator.calibration.data.MAX_RUNS: "
                "each fit iteration integrates every run)",
            )
    if header is None:
        raise InputError(
            "file",
            f"{source}: empty file (expected a header with {_TIME} and {_READOUT} or {_SPIN})",
        )
    check_header(header, source, header_line, columns)
    if _TIME not in header:
        raise _fail(_TIME, source, header_line, f"missing column {_TIME!r} (header: {header})")
    has_f, has_w = _READOUT in header, _SPIN in header
    if has_f == has_w:
        what = "both" if has_f else "neither of"
        raise _fail(
            _READOUT if has_f else _SPIN,
            source,
            header_line,
            f"need exactly one of {_READOUT!r} or {_SPIN!r}, found {what} (header: {header})",
        )
    if not rows:
        raise InputError("file", f"{source}: no data rows after the header at line {header_line}")
    col = {name: header.index(name) for name in _KNOWN if name in header}

    def numbers(name: str, unit: str) -> NDArray[np.float64] | None:
        if name not in col:
            return None
        j = col[name]
        return np.array([_positive(c[j], name, unit, source, ln) for ln, c in rows])

    readout = numbers(_READOUT, "Hz")
    spin = readout_to_spin_rate(readout, teeth) if readout is not None else numbers(_SPIN, "rad/s")
    times = numbers(_TIME, "s")
    assert times is not None  # the header holds _TIME (checked above)
    settings = _run_settings(header, rows, source, header_line)
    check_runs(settings, times, rows, source)
    starred = np.zeros(len(rows), dtype=bool)
    if _STARRED in col:
        j = col[_STARRED]
        for k, (ln, c) in enumerate(rows):
            v = c[j].lower()
            if v not in _TRUE | _FALSE:
                raise _fail(
                    _STARRED, source, ln, f"{c[j]!r} is not a flag (allowed: 1/0, true/false, *)"
                )
            starred[k] = v in _TRUE
    return SpinRigData(
        spin_rate=spin,
        opening_time=times,
        starred=starred,
        readout_hz=readout,
        spin_rate_printed=numbers(_PRINTED, "rad/s"),
        source=source,
        settings=settings,
    )


def _run_settings(
    header: list[str], rows: list[tuple[int, list[str]]], source: str, header_line: int
) -> dict[str, NDArray[np.float64]]:
    """The optional per-run columns in SI units (NaN for an empty cell), checked."""
    from ..params import PARAMS
    from ..units import parse_quantity

    out: dict[str, NDArray[np.float64]] = {}
    for j, cell in enumerate(header):
        found = column_unit(cell)
        if found is None:
            continue
        name, unit = found
        si, _, param = RUN_COLUMNS[name]
        key = SETTING_NAMES[name]
        if key in out:
            raise _fail(cell, source, header_line, f"a second {name!r} column")
        try:
            factor = parse_quantity(cell, f"1 {unit}", si)
        except InputError as exc:
            raise _fail(
                cell,
                source,
                header_line,
                f"unit {unit!r} is not a unit of {si} ({str(exc).split(': ', 1)[-1]})",
            ) from None
        rng = PARAMS[param].range if name != "t_measured" else None
        values = np.full(len(rows), np.nan)
        for k, (ln, c) in enumerate(rows):
            text = c[j].strip()
            if not text:
                continue
            x = _number(text, cell, source, ln) * factor
            ok = rng.contains(x) if rng is not None else _MIN_TIME < x <= _LIMITS["s"][1]
            if not ok:
                allowed = rng if rng is not None else f"({_MIN_TIME:g}, {_LIMITS['s'][1]:g}]"
                raise _fail(
                    cell, source, ln, f"{x:g} {si} is outside the allowed range {allowed} {si}"
                )
            values[k] = x
        out[key] = values
    return out


def _number(text: str, column: str, source: str, line: int) -> float:
    if not _STRICT_NUMBER.match(text):
        raise _fail(column, source, line, f"{text!r} is not a number")
    x = float(text)
    if not math.isfinite(x):
        raise _fail(column, source, line, f"{text!r} is not finite")
    return x


def load_spin_rig_csv(
    path: str | Path, *, teeth: int = RIG_TEETH, columns: Iterable[str] | None = None
) -> SpinRigData:
    """Read a user's spin-rig CSV file.

    Parameters
    ----------
    path : str or Path
        CSV with a header line; lines starting with ``#`` and blank lines are
        skipped. Columns: ``t_cr_s`` (opening time [s]), exactly one of
        ``readout_hz`` (counter readout [Hz], converted with 2 pi f / teeth) or
        ``spin_rate_rad_s`` ([rad/s]); optional ``starred`` (1/0, true/false,
        ``*``) and ``omega_p_printed_rad_s``; optional per-run settings
        (:data:`RUN_COLUMNS`; an empty cell keeps Table 1's value): ``theta0``
        [deg], ``hole_radius`` [mm], ``density`` [kg/m^3], ``ball_mass`` [g], and
        ``theta_measured`` [deg] with ``t_measured`` [s], each with its unit in the
        header (``hole_radius_m``, ``density [g/cm^3]``, ``theta0 (deg)``) or else in
        the unit in brackets here; ``comment``, free text read by nothing. Any
        other column is refused, naming the closest known name.
    teeth : int
        Teeth on the bucket wheel (18 on Bloomer's rig).
    columns : iterable of str, optional
        The per-run setting columns (:data:`RUN_COLUMNS`) the caller uses; a
        known column outside them is refused (``calibrate`` and ``design-experiment``
        use :data:`CASE_COLUMNS`, ``validate`` every one). Default: all.

    Raises
    ------
    InputError
        For a missing or empty file, a missing or duplicated column, a repeated
        header line, an unknown or unused column, a cell that is not a plain
        decimal number (``3_00``, ``inf``), runs whose columns disagree or that cannot
        open (:func:`~.schema.check_runs`), or a time,
        readout or spin rate outside (0, inf), a setting's unit that does not convert
        or a value outside its range (:data:`obturator.params.PARAMS`); the message
        names the file, line number, column and allowed range.
    """
    from ..files import read_text_file

    p = Path(path)
    used = tuple(RUN_COLUMNS) if columns is None else tuple(columns)
    for c in used:
        if c not in RUN_COLUMNS:
            raise InputError("columns", f"{c!r}; allowed: {', '.join(RUN_COLUMNS)}")
    return _parse(read_text_file(p, "path"), str(p), teeth, used)


def load_thesis_data() -> SpinRigData:
    """The 54 runs of thesis Appendix B (packaged CSV, transcribed as printed).

    ``spin_rate`` is f pi / 9 from the readout; ``spin_rate_printed`` keeps the
    printed omega_p; ``run`` numbers follow the print (left column group 1-36,
    right 37-54).
    """
    return _parse(data_text(APPENDIX_B_CSV), f"obturator/reference/{APPENDIX_B_CSV}", RIG_TEETH)
