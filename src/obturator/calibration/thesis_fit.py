"""The thesis's friction calibration (chapter IV): least squares of the Appendix B runs.

The runs and how the rig measured them are described in :mod:`obturator.calibration.data`;
chapter IV fits the starred runs to the large-spin form t = T2 omega_p (Eq. 96), and
T2 gives mu_s through Eq. (95).

What the data reproduce (see ``tests/calibration/test_experiment.py``)
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

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .._docs import field_docs
from ..approx import mean_moment_arm
from ..errors import InputError
from ..reference import (
    CHAPTER4_SUMS,
    EQ95_COEFFICIENT,
    PRINTED_SUMS_OMITTED_RUNS,
    TABLE1,
    THESIS_FIT_MIN_SPIN,
)
from .data import SpinRigData, load_thesis_data

__all__ = [
    "EQ95_COEFFICIENT",
    "PRINTED_SUMS_OMITTED_RUNS",
    "THESIS_FIT_MIN_SPIN",
    "THESIS_THETA0",
    "ThesisComparison",
    "ThesisLeastSquares",
    "SubsetMatch",
    "compare_with_thesis",
    "format_comparison",
    "printed_subset",
    "printed_thesis_sums",
    "search_printed_sums_subsets",
    "thesis_fit",
    "thesis_least_squares",
]

#: Initial nutation angle of the rig runs [rad] (Table 1: 87.25 deg).
THESIS_THETA0 = math.radians(TABLE1["theta0_deg"])


@field_docs
@dataclass(frozen=True)
class ThesisLeastSquares:
    """Chapter IV least-squares fit of t = T2 omega_p (Eq. 96), both directions.

    The thesis's T2 = sum t^2 / sum(t omega) minimises sum (omega - t/T2)^2,
    i.e. it fits omega = t / T2 with residuals in omega; the direct fit of
    t = T2 omega with residuals in t is sum(t omega) / sum omega^2.
    """

    #: Number of runs N.
    n: int
    #: sum t^2 over the runs [s^2].
    sum_t2: float
    #: sum omega^2 over the runs [rad^2/s^2].
    sum_omega2: float
    #: sum t omega over the runs [rad].
    sum_t_omega: float
    #: Thesis T2 = sum t^2 / sum t omega [s^2/rad].
    t2: float
    #: Thesis sigma^2 = (1/N)(sum omega^2 - sum t omega / T2) [rad^2/s^2], the mean squared omega
    #: residual.
    sigma2: float
    #: Thesis variance sigma_T^2 of T2 [s^4/rad^2], from 1/sigma_T^2 = sum t^2 / (sigma^2 T2^4).
    sigma_t2: float
    #: Thesis standard deviation sigma_T of T2 [s^2/rad], the square root of `sigma_t2`.
    sigma_t: float
    #: sigma_T / T2 [-] (printed as "sigma/T = 0.023").
    relative_sigma: float
    #: (2/pi) E(theta0) [-] (Eq. 78).
    mean_arm: float
    #: mu_bar = 3.03e-4 / T2 (Eq. 95) [-].
    mu_bar: float
    #: mu_s = mu_bar / mean_arm [-].
    mu_s: float
    #: Standard omega residual sqrt(SS / (N - 1)) [rad/s] of the thesis fit.
    omega_residual_std: float
    #: Standard error of T2 [s^2/rad] (delta method, N - 1 divisor); sigma_t with N - 1 in place of
    #: N.
    t2_stderr: float
    #: T2 of the direct fit t = T2 omega, sum t omega / sum omega^2 [s^2/rad].
    t2_direct: float
    #: sqrt(sum (t - T2d omega)^2 / (N - 1)) [s].
    time_residual_std: float
    #: Standard error of T2d [s^2/rad].
    t2_direct_stderr: float
    #: mu_bar of Eq. (95) with T2d in place of T2, 3.03e-4 / T2d [-].
    mu_bar_direct: float
    #: mu_s from Eq. (95) with T2d, mu_bar_direct / mean_arm [-].
    mu_s_direct: float
    #: Initial nutation angle used for mean_arm [rad].
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

    Keys match :class:`ThesisLeastSquares` attributes; the values are
    :data:`obturator.reference.CHAPTER4_SUMS`. ``mean_arm`` is the printed
    (2/pi) E = 0.63954, which the thesis obtained from E = 1.00458 (the line
    also shows "(1.00448)"); the correct E(87.25 deg) is 1.00452. ``sigma_t`` =
    1.97742e-5 disagrees with sqrt(sigma_t2) = 1.97942e-5.
    """
    return dict(CHAPTER4_SUMS)


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


@field_docs
@dataclass(frozen=True)
class SubsetMatch:
    """A run subset whose sums match the printed ones (see :func:`search_printed_sums_subsets`)."""

    #: Run numbers dropped from the starred set.
    removed: tuple[int, ...]
    #: Run numbers added from the unstarred set.
    added: tuple[int, ...]
    #: Runs in the subset.
    n: int
    #: The subset's sum t^2 [s^2].
    sum_t2: float
    #: The subset's sum omega^2 [rad^2/s^2].
    sum_omega2: float
    #: The subset's sum t omega [rad].
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


def printed_subset(data: SpinRigData | None = None) -> SpinRigData:
    """The 24 runs that reproduce the thesis's printed sums.

    Starred runs without runs 40, 41, 45 and 51, with the printed omega_p
    column (see the module docstring).
    """
    data = load_thesis_data() if data is None else data
    return data.fit_subset().exclude_runs(PRINTED_SUMS_OMITTED_RUNS).with_printed_spin_rate()


def thesis_fit(
    data: SpinRigData | None = None,
    *,
    subset: str = "printed",
    theta0_deg: float = TABLE1["theta0_deg"],
) -> ThesisLeastSquares:
    """Chapter IV least squares (Eqs. 95-96) on the thesis data or a user's runs.

    Parameters
    ----------
    data : SpinRigData, optional
        Default: Appendix B.
    subset : {"printed", "starred"}
        For the thesis data: the 24-run subset that reproduces the printed
        sums, or all 28 starred runs with omega_p = f pi / 9. User data: starred.
    theta0_deg : float
        theta_0 [deg] for the mean moment arm (2/pi) E(theta_0).
    """
    if subset not in ("printed", "starred"):
        raise InputError("subset", f"{subset!r}; allowed: printed, starred")
    if data is None and subset == "printed":
        runs = printed_subset()
    else:
        runs = (load_thesis_data() if data is None else data).fit_subset()
    return thesis_least_squares(runs, theta0=math.radians(theta0_deg))
