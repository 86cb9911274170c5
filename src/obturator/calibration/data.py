"""Spin-rig experiment data and the thesis's friction calibration (chapters III-IV, Appendix B).

The rig spins a lucite "projectile" holding the ball; a counter reads the
passing frequency f of an 18-tooth bucket wheel, so omega_p = f pi / 9
(chapter III.C). Appendix B lists 54 runs (readout, t_cr, printed omega_p);
the starred runs (omega_p >= 235.97 rad/s) are fitted in chapter IV to the
large-spin form t = T2 omega_p (Eq. 96), and T2 gives the friction coefficient
through Eq. (95), mu_bar = 3.03e-4 / T2, and mu_s = mu_bar / ((2/pi) E(theta0)).

What the data reproduce (see ``tests/test_experiment.py``)
----------------------------------------------------------
* Every printed omega_p equals f pi / 9 rounded to its printed precision.
* The 28 starred runs do *not* reproduce the printed sums (sum t^2 = 2.5030002
  s^2 against the printed 2.1046884). Dropping the four starred runs 40, 41, 45
  and 51 (right-hand column rows 4, 5, 9 and 15: 936, 983, 1063 and 1255 Hz)
  and using the *printed* omega_p column reproduces all three printed sums and
  T2 = 8.6603508e-4 s^2 to every printed digit; the implied N = 24 also follows
  from the printed sigma^2. That subset is the only one found among all
  removals of up to eight starred runs combined with up to two added
  unstarred runs (:func:`search_printed_sums_subsets`); with f pi / 9 instead
  of the printed omega_p no subset matches.
* The printed sigma_T = 1.97742e-5 is inconsistent with the printed
  sigma_T^2 = 3.9181053e-10, whose root is 1.97942e-5 (a transposed digit).
* The printed sum of t omega (2.430257e3) is the truncation of 2430.25767.
"""

from __future__ import annotations

import csv
import itertools
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace
from importlib.resources import files
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..approx import mean_moment_arm
from ..errors import InputError, check_range

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

__all__ = [
    "EQ95_COEFFICIENT",
    "PRINTED_SUMS_OMITTED_RUNS",
    "THESIS_FIT_MIN_SPIN",
    "THESIS_THETA0",
    "ThesisComparison",
    "SpinRigData",
    "SubsetMatch",
    "ThesisLeastSquares",
    "compare_with_thesis",
    "format_comparison",
    "load_spin_rig_csv",
    "load_thesis_data",
    "printed_thesis_sums",
    "readout_to_spin_rate",
    "search_printed_sums_subsets",
    "thesis_least_squares",
]

#: Initial nutation angle of the rig runs [rad] (Table 1: 87.25 deg).
THESIS_THETA0 = math.radians(87.25)
#: Eq. (95): T2 = 3.03e-4 / mu_bar [s^2]; the thesis's large-spin coefficient.
EQ95_COEFFICIENT = 3.03e-4
#: Lowest printed spin of the starred runs [rad/s] (chapter IV). Note that the
#: 676 Hz run has f pi / 9 = 235.9685 < 235.97: filter on the printed column,
#: on the star, or with a threshold a little below this value.
THESIS_FIT_MIN_SPIN = 235.97
#: 1-based run numbers (order of Appendix B: left column group 1-36, right
#: 37-54) of the four starred runs that must be left out, with the printed
#: omega_p, to reproduce the thesis's printed least-squares sums.
PRINTED_SUMS_OMITTED_RUNS: tuple[int, ...] = (40, 41, 45, 51)

_DATA_FILE = "bloomer1980_appendix_b.csv"
_TIME = "t_cr_s"
_READOUT = "readout_hz"
_SPIN = "spin_rate_rad_s"
_PRINTED = "omega_p_printed_rad_s"
_STARRED = "starred"
_KNOWN = (_READOUT, _SPIN, _TIME, _PRINTED, _STARRED)
_TRUE = {"1", "true", "yes", "y", "*"}
_FALSE = {"0", "false", "no", "n", ""}


def readout_to_spin_rate(readout_hz: ArrayLike, teeth: int = 18) -> NDArray[np.float64]:
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


@dataclass(frozen=True, kw_only=True)
class SpinRigData:
    """Opening times measured on the spin rig.

    Attributes
    ----------
    spin_rate : ndarray
        Rig spin omega_p [rad/s] (from the readout where there is one).
    opening_time : ndarray
        Measured opening time t_cr [s].
    starred : ndarray of bool
        Runs marked for the least-squares fit.
    readout_hz : ndarray or None
        Counter readout f [Hz]; None for files that give omega_p directly.
    spin_rate_printed : ndarray or None
        omega_p as printed in the source [rad/s], kept for comparison.
    run : ndarray of int
        1-based run number in the source (defaults to 1..n).
    source : str
        Where the data came from.
    """

    spin_rate: NDArray[np.float64]
    opening_time: NDArray[np.float64]
    starred: NDArray[np.bool_]
    readout_hz: NDArray[np.float64] | None = None
    spin_rate_printed: NDArray[np.float64] | None = None
    run: NDArray[np.int64] | None = None
    source: str = ""
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
        )

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
        return pd.DataFrame(cols, index=pd.Index(self.run, name="run"))


def _fail(column: str, source: str, line: int, what: str) -> InputError:
    return InputError(column, f"{source}, line {line}: {what}")


def _positive(cell: str, column: str, unit: str, source: str, line: int) -> float:
    allowed = f"allowed range (0, inf) {unit}"
    try:
        x = float(cell)
    except ValueError:
        raise _fail(column, source, line, f"{cell!r} is not a number ({allowed})") from None
    if not (math.isfinite(x) and x > 0.0):
        raise _fail(column, source, line, f"{x:g} {unit} is outside the {allowed}")
    return x


def _parse(text: str, source: str, teeth: int) -> SpinRigData:
    """Parse CSV text; errors name `source`, the 1-based line and the column."""
    n_teeth = check_range("teeth", teeth, 1.0, math.inf, hi_open=True)
    if n_teeth != int(n_teeth):
        raise InputError("teeth", f"{teeth!r} is not a whole number (allowed range [1, inf))")
    teeth = int(n_teeth)
    header: list[str] | None = None
    header_line = 0
    rows: list[tuple[int, list[str]]] = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
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
    if header is None:
        raise InputError(
            "file",
            f"{source}: empty file (expected a header with {_TIME} and {_READOUT} or {_SPIN})",
        )
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
        opening_time=numbers(_TIME, "s"),
        starred=starred,
        readout_hz=readout,
        spin_rate_printed=numbers(_PRINTED, "rad/s"),
        source=source,
    )


def load_spin_rig_csv(path: str | Path, *, teeth: int = 18) -> SpinRigData:
    """Read a user's spin-rig CSV file.

    Parameters
    ----------
    path : str or Path
        CSV with a header line; lines starting with ``#`` and blank lines are
        skipped. Columns: ``t_cr_s`` (opening time [s]), exactly one of
        ``readout_hz`` (counter readout [Hz], converted with 2 pi f / teeth) or
        ``spin_rate_rad_s`` ([rad/s]); optional ``starred`` (1/0, true/false,
        ``*``) and ``omega_p_printed_rad_s``. Other columns are ignored.
    teeth : int
        Teeth on the bucket wheel (18 on Bloomer's rig).

    Raises
    ------
    InputError
        For a missing or empty file, a missing or duplicated column, a repeated
        header line, a wrong number of fields, a non-numeric cell, or a time,
        readout or spin rate outside (0, inf); the message names the file,
        line number, column and allowed range.
    """
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise InputError("path", f"{p}: no such file") from None
    except (IsADirectoryError, PermissionError, UnicodeDecodeError) as exc:
        raise InputError("path", f"{p}: cannot be read as a UTF-8 CSV file ({exc})") from None
    return _parse(text, str(p), teeth)


def load_thesis_data() -> SpinRigData:
    """The 54 runs of thesis Appendix B (packaged CSV, transcribed as printed).

    ``spin_rate`` is f pi / 9 from the readout; ``spin_rate_printed`` keeps the
    printed omega_p; ``run`` numbers follow the print (left column group 1-36,
    right 37-54).
    """
    text = files("obturator").joinpath("data", _DATA_FILE).read_text(encoding="utf-8")
    return _parse(text, f"obturator/data/{_DATA_FILE}", 18)


@dataclass(frozen=True)
class ThesisLeastSquares:
    """Chapter IV least-squares fit of t = T2 omega_p (Eq. 96), both directions.

    The thesis's T2 = sum t^2 / sum(t omega) minimises sum (omega - t/T2)^2,
    i.e. it fits omega = t / T2 with residuals in omega; the direct fit of
    t = T2 omega with residuals in t is sum(t omega) / sum omega^2.

    Attributes
    ----------
    n : int
        Number of runs N.
    sum_t2, sum_omega2, sum_t_omega : float
        sum t^2 [s^2], sum omega^2 [rad^2/s^2], sum t omega [rad].
    t2 : float
        Thesis T2 = sum t^2 / sum t omega [s^2/rad].
    sigma2 : float
        Thesis sigma^2 = (1/N)(sum omega^2 - sum t omega / T2) [rad^2/s^2],
        the mean squared omega residual.
    sigma_t2, sigma_t : float
        Thesis 1/sigma_T^2 = sum t^2 / (sigma^2 T2^4): variance [s^4/rad^2]
        and standard deviation [s^2/rad] of T2.
    relative_sigma : float
        sigma_T / T2 [-] (printed as "sigma/T = 0.023").
    mean_arm : float
        (2/pi) E(theta0) [-] (Eq. 78).
    mu_bar, mu_s : float
        3.03e-4 / T2 (Eq. 95) and mu_bar / mean_arm.
    omega_residual_std : float
        Standard omega residual sqrt(SS / (N - 1)) [rad/s] of the thesis fit.
    t2_stderr : float
        Standard error of T2 [s^2/rad] (delta method, N - 1 divisor);
        sigma_t with N - 1 in place of N.
    t2_direct : float
        T2 of the direct fit t = T2 omega, sum t omega / sum omega^2 [s^2/rad].
    time_residual_std : float
        sqrt(sum (t - T2d omega)^2 / (N - 1)) [s].
    t2_direct_stderr : float
        Standard error of T2d [s^2/rad].
    mu_bar_direct, mu_s_direct : float
        Eq. (95) with T2d.
    theta0 : float
        Initial nutation angle used for mean_arm [rad].
    """

    n: int
    sum_t2: float
    sum_omega2: float
    sum_t_omega: float
    t2: float
    sigma2: float
    sigma_t2: float
    sigma_t: float
    relative_sigma: float
    mean_arm: float
    mu_bar: float
    mu_s: float
    omega_residual_std: float
    t2_stderr: float
    t2_direct: float
    time_residual_std: float
    t2_direct_stderr: float
    mu_bar_direct: float
    mu_s_direct: float
    theta0: float


def thesis_least_squares(
    data: SpinRigData,
    *,
    theta0: float = THESIS_THETA0,
    eq95_coefficient: float = EQ95_COEFFICIENT,
) -> ThesisLeastSquares:
    """Fit t = T2 omega_p to every run in `data` as chapter IV does, plus standard statistics.

    Parameters
    ----------
    data : SpinRigData
        Runs to fit, e.g. ``load_thesis_data().fit_subset()``.
    theta0 : float
        Initial nutation angle [rad] for the mean moment arm (2/pi) E(theta0).
    eq95_coefficient : float
        The constant in T2 = coefficient / mu_bar [s^2/rad] (Eq. 95: 3.03e-4).

    Returns
    -------
    ThesisLeastSquares
    """
    n = len(data)
    if n < 2:
        raise InputError("data", f"{n} runs to fit; allowed range [2, inf)")
    t, w = data.opening_time, data.spin_rate
    stt, sww, stw = float(t @ t), float(w @ w), float(t @ w)
    t2 = stt / stw
    ss_w = float(np.sum((w - t / t2) ** 2))  # = sww - stw / t2, without the cancellation
    sigma2 = ss_w / n
    sigma_t2 = sigma2 * t2**4 / stt
    t2d = stw / sww
    ss_t = float(np.sum((t - t2d * w) ** 2))
    s_w = math.sqrt(ss_w / (n - 1))
    s_t = math.sqrt(ss_t / (n - 1))
    arm = mean_moment_arm(theta0)
    mu_bar = eq95_coefficient / t2
    mu_bar_d = eq95_coefficient / t2d
    return ThesisLeastSquares(
        n=n,
        sum_t2=stt,
        sum_omega2=sww,
        sum_t_omega=stw,
        t2=t2,
        sigma2=sigma2,
        sigma_t2=sigma_t2,
        sigma_t=math.sqrt(sigma_t2),
        relative_sigma=math.sqrt(sigma_t2) / t2,
        mean_arm=arm,
        mu_bar=mu_bar,
        mu_s=mu_bar / arm,
        omega_residual_std=s_w,
        t2_stderr=s_w / math.sqrt(stt) * t2**2,
        t2_direct=t2d,
        time_residual_std=s_t,
        t2_direct_stderr=s_t / math.sqrt(sww),
        mu_bar_direct=mu_bar_d,
        mu_s_direct=mu_bar_d / arm,
        theta0=theta0,
    )


def printed_thesis_sums() -> dict[str, float]:
    """The values printed in thesis chapter IV (as printed, typos included).

    Keys match :class:`ThesisLeastSquares` attributes. ``mean_arm`` is the
    printed (2/pi) E = 0.63954, which the thesis obtained from E = 1.00458 (the
    line also shows "(1.00448)"); the correct E(87.25 deg) is 1.00452.
    ``sigma_t`` = 1.97742e-5 disagrees with sqrt(sigma_t2) = 1.97942e-5.
    """
    return {
        "sum_t2": 2.1046884,
        "sum_omega2": 2.8413714e6,
        "sum_t_omega": 2.430257e3,
        "t2": 8.6603508e-4,
        "sigma2": 1.4659547e3,
        "sigma_t2": 3.9181053e-10,
        "sigma_t": 1.97742e-5,
        "relative_sigma": 0.023,
        "mu_bar": 0.35,
        "mean_arm": 0.63954,
        "mu_s": 0.5473,
    }


class ThesisComparison(NamedTuple):
    """One line of :func:`compare_with_thesis`."""

    name: str
    computed: float
    printed: float
    relative_difference: float


def compare_with_thesis(result: ThesisLeastSquares) -> list[ThesisComparison]:
    """Computed vs printed chapter IV values, relative difference computed/printed - 1."""
    return [
        ThesisComparison(k, float(getattr(result, k)), v, float(getattr(result, k)) / v - 1.0)
        for k, v in printed_thesis_sums().items()
    ]


def format_comparison(rows: Sequence[ThesisComparison]) -> str:
    """Plain-text table of :func:`compare_with_thesis` rows."""
    lines = [f"{'quantity':<16}{'computed':>16}{'printed':>16}{'rel. diff':>12}"]
    lines += [
        f"{r.name:<16}{r.computed:>16.8g}{r.printed:>16.8g}{r.relative_difference:>12.2e}"
        for r in rows
    ]
    return "\n".join(lines)


@dataclass(frozen=True)
class SubsetMatch:
    """A run subset whose sums match the printed ones (see :func:`search_printed_sums_subsets`).

    Attributes
    ----------
    removed, added : tuple of int
        Run numbers dropped from the starred set / added from the unstarred set.
    n : int
        Runs in the subset.
    sum_t2, sum_omega2, sum_t_omega : float
        Its sums [s^2], [rad^2/s^2], [rad].
    """

    removed: tuple[int, ...]
    added: tuple[int, ...]
    n: int
    sum_t2: float
    sum_omega2: float
    sum_t_omega: float


def search_printed_sums_subsets(
    data: SpinRigData,
    *,
    max_removed: int = 6,
    max_added: int = 1,
    use_printed_spin: bool = True,
) -> list[SubsetMatch]:
    """Find starred-run subsets (a few runs removed / added) reproducing the printed sums.

    A subset matches when each of sum t^2, sum omega^2 and sum t omega lies
    within one unit of the last printed digit of the thesis value (one unit,
    not half, so that truncation as well as rounding is accepted). sum t^2
    needs no spin rate and is screened first.

    Parameters
    ----------
    data : SpinRigData
        All runs (starred and not), e.g. :func:`load_thesis_data`.
    max_removed, max_added : int
        Largest number of starred runs dropped / unstarred runs added.
    use_printed_spin : bool
        Use the printed omega_p column instead of f pi / 9.

    Returns
    -------
    list of SubsetMatch
        Fewest changes first.
    """
    printed = printed_thesis_sums()
    # One unit of the last printed digit of 2.1046884, 2.8413714e6 and 2.430257e3.
    tol = {"sum_t2": 1e-7, "sum_omega2": 1.0, "sum_t_omega": 1e-3}
    w = data.spin_rate_printed if use_printed_spin else data.spin_rate
    if w is None:
        raise InputError("spin_rate_printed", f"{data.source or 'data'}: no printed column")
    t = data.opening_time
    tt, ww, tw = t * t, w * w, t * w
    star = np.flatnonzero(data.starred)
    other = np.flatnonzero(~data.starred)
    base = tt[star].sum()
    matches: list[SubsetMatch] = []
    for k in range(max_removed + 1):
        # All k-run removals at once; the additions (few) are looped over.
        combos = list(itertools.combinations(star, k))
        rem_all = np.array(combos, dtype=int).reshape(len(combos), k)
        s_rem = base - tt[rem_all].sum(axis=1)
        for j in range(max_added + 1):
            for add in itertools.combinations(other, j):
                add_idx = np.asarray(add, dtype=int)
                gap = np.abs(s_rem + tt[add_idx].sum() - printed["sum_t2"])
                for h in np.flatnonzero(gap <= tol["sum_t2"]):
                    idx = np.concatenate([np.setdiff1d(star, rem_all[h]), add_idx])
                    sww, stw = float(ww[idx].sum()), float(tw[idx].sum())
                    if (
                        abs(sww - printed["sum_omega2"]) <= tol["sum_omega2"]
                        and abs(stw - printed["sum_t_omega"]) <= tol["sum_t_omega"]
                    ):
                        matches.append(
                            SubsetMatch(
                                removed=tuple(int(r) for r in data.run[rem_all[h]]),
                                added=tuple(int(r) for r in data.run[add_idx]),
                                n=int(idx.size),
                                sum_t2=float(tt[idx].sum()),
                                sum_omega2=sww,
                                sum_t_omega=stw,
                            )
                        )
    return matches
