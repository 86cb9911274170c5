"""Is a t_cr converged? Reruns with tighter tolerances, a narrower width, another family."""

from __future__ import annotations

import math
from collections.abc import Sequence
from contextlib import AbstractContextManager
from dataclasses import dataclass, replace

import numpy as np

from .._docs import field_docs
from ..errors import InputError
from ..json_values import finite_or_none
from ..model.case import Case
from ..status import Status
from ..vocab import FRICTION_FAMILIES, check_choice
from .dispatch import method_of
from .limits import WIDTH_BOUND_METHODS, width_rule_waived
from .one import opening_time
from .options import SolverOptions

__all__ = [
    "mark_unconverged",
    "ConvergenceCheck",
    "alternative_family",
    "convergence_check",
    "convergence_checks",
    "refined_options",
]


def alternative_family(family: str) -> str:
    """The family a convergence check compares with: "linear" for the smooth
    families (the most different shape: it reaches full friction at a finite
    slip), "algebraic" for "linear"."""
    return "algebraic" if family == "linear" else "linear"


@field_docs
@dataclass(frozen=True)
class ConvergenceCheck:
    """t_cr re-computed to bound its own error, and, for the set-valued solver, an
    independent cross-check.

    Regularised law (every method but ``set-valued``): t_cr with tighter tolerances, a
    narrower width and another family. A width study alone cannot reveal a
    regularisation that converges to the wrong limit (each family looks converged as its
    own width shrinks); a second family with a different shape can. Its error is bounded
    by all three changes.

    Set-valued solver (no width): its own error is the change at tighter tolerances. The
    regularised law is an independent computation of the same limit: extrapolated to
    zero width from two widths (t_cr about linear in the width, so Richardson's
    t_0 = t(w/f) + (t(w/f) - t(w)) / (f - 1)) in two families, whose difference is the
    cross-check's own error. The regularised runs' changes (:attr:`width_change`,
    :attr:`family_change`) are that path's width error, not the reported t_cr's.
    """

    #: t_cr with the given options [s] (NaN if it did not open).
    opening_time: float
    #: t_cr with rtol and atol divided by `factor` [s].
    tighter_tolerance: float
    #: t_cr with ``friction_width`` divided by `factor` [s] (tolerances divided by `factor` too, so
    #: slip speeds of order delta stay resolved).
    narrower_width: float
    #: t_cr with ``friction_family`` replaced by `family` [s] (for the set-valued solver: at the
    #: narrower width).
    other_family: float
    #: The family of that rerun.
    family: str
    #: Refinement factor (10 by default).
    factor: float
    #: Largest relative change accepted as converged.
    threshold: float
    #: The route checked: ``"set-valued"`` or ``"regularised"`` (every method with a width).
    strategy: str = "regularised"
    #: Set-valued only: the regularised law at the given width, tolerances / `factor`, in
    #: ``friction_family`` and in `family` [s] (NaN otherwise): with :attr:`narrower_width`
    #: and :attr:`other_family` the two widths of the extrapolation.
    wide_width: tuple[float, float] = (math.nan, math.nan)

    @staticmethod
    def _rel(a: float, b: float) -> float:
        if math.isnan(a) and math.isnan(b):
            return 0.0  # both "did not open by t_max"
        if math.isnan(a) or math.isnan(b):
            return math.inf
        return abs(b - a) / abs(a)

    @property
    def tolerance_change(self) -> float:
        """|t_tight - t| / t [-] (0 when neither run opened, inf when only one did)."""
        return self._rel(self.opening_time, self.tighter_tolerance)

    @property
    def width_change(self) -> float:
        """|t_narrow - t| / t [-] (set-valued: the regularised path's, |t(w/f) - t(w)| / t)."""
        if self.strategy == "set-valued":
            return self._rel(self.wide_width[0], self.narrower_width)
        return self._rel(self.opening_time, self.narrower_width)

    @property
    def family_change(self) -> float:
        """|t_family - t| / t [-] (set-valued: the regularised path's at the narrower width)."""
        if self.strategy == "set-valued":
            return self._rel(self.narrower_width, self.other_family)
        return self._rel(self.opening_time, self.other_family)

    @property
    def extrapolated(self) -> tuple[float, float]:
        """Set-valued only: the regularised t_cr extrapolated to zero width [s] in
        ``friction_family`` and in `family` (NaN otherwise)."""
        f = self.factor
        narrow = (self.narrower_width, self.other_family)
        return tuple(n + (n - w) / (f - 1.0) for n, w in zip(narrow, self.wide_width, strict=True))

    @property
    def cross_check(self) -> float:
        """Set-valued only: the mean of :attr:`extrapolated` [s] (NaN otherwise)."""
        return 0.5 * sum(self.extrapolated)

    @property
    def cross_check_change(self) -> float:
        """|t_extrapolated - t| / t [-]: the set-valued t_cr against the regularised
        limit (0 for the regularised law, which is its own check)."""
        if self.strategy != "set-valued":
            return 0.0
        return self._rel(self.opening_time, self.cross_check)

    @property
    def cross_check_spread(self) -> float:
        """The cross-check's own error: its two families' extrapolations apart, / t [-]."""
        if self.strategy != "set-valued":
            return 0.0
        a, b = self.extrapolated
        return self._rel(self.opening_time, self.opening_time + abs(a - b))

    @property
    def own_change(self) -> float:
        """The bound on the reported t_cr's own error [-]: the tolerance change for the
        set-valued solver, the largest of the three changes for the regularised law."""
        if self.strategy == "set-valued":
            return self.tolerance_change
        return max(self.tolerance_change, self.width_change, self.family_change)

    @property
    def largest_change(self) -> float:
        """The larger of :attr:`own_change` and :attr:`cross_check_change` [-]."""
        return max(self.own_change, self.cross_check_change)

    @property
    def converged(self) -> bool:
        """The own error below the threshold, and the set-valued t_cr within the
        threshold (or the cross-check's own spread, if larger) of the regularised limit."""
        if not self.own_change < self.threshold:
            return False
        if self.strategy != "set-valued":
            return True
        return self.cross_check_change < max(self.threshold, self.cross_check_spread)

    def to_dict(self) -> dict[str, object]:
        """JSON-ready summary (None for NaN/inf): the reported t_cr's own changes, and
        for the set-valued solver the regularised cross-check under ``cross_check``."""
        out: dict[str, object] = {
            "converged": self.converged,
            "strategy": self.strategy,
            "tolerance_rel_change": finite_or_none(self.tolerance_change),
            "t_cr_tighter_tolerance_s": finite_or_none(self.tighter_tolerance),
            "factor": self.factor,
            "threshold": self.threshold,
        }
        regularised = {
            "width_rel_change": finite_or_none(self.width_change),
            "family_rel_change": finite_or_none(self.family_change),
            "t_cr_narrower_width_s": finite_or_none(self.narrower_width),
            "t_cr_other_family_s": finite_or_none(self.other_family),
            "other_family": self.family,
        }
        if self.strategy != "set-valued":
            return out | regularised
        ext = self.extrapolated
        out["cross_check"] = {
            "strategy": "regularised law extrapolated to zero width (Richardson in the "
            f"width, widths w and w / {self.factor:g}, two families)",
            "t_cr_s": finite_or_none(self.cross_check),
            "rel_change": finite_or_none(self.cross_check_change),
            "own_spread_rel": finite_or_none(self.cross_check_spread),
            "t_cr_extrapolated_s": [finite_or_none(x) for x in ext],
            "regularised_path": regularised
            | {"t_cr_width_s": [finite_or_none(x) for x in self.wide_width]},
        }
        return out


def convergence_check(
    case: Case,
    options: SolverOptions | None = None,
    *,
    factor: float = 10.0,
    threshold: float = 1e-3,
    opening_time_s: float | None = None,
    family: str | None = None,
) -> ConvergenceCheck:
    """Recompute t_cr with tighter tolerances, a narrower width and another family.

    Parameters
    ----------
    case : Case
    options : SolverOptions, optional
        The options whose result is being checked. Under ``"auto"`` the check is that
        of the integrator the case runs with (:func:`~obturator.solve.dispatch.method_of`):
        a case run set-valued is checked against the regularised path.
    factor : float
        Refinement factor for (rtol, atol) and for ``friction_width``.
    threshold : float
        Relative change below which t_cr counts as converged.
    opening_time_s : float, optional
        t_cr already computed with `options` [s] (saves one run).
    family : str, optional
        Regularisation family of the third rerun; default
        :func:`alternative_family` of ``options.friction_family``.
    """
    options = options or SolverOptions()
    family = alternative_family(options.friction_family) if family is None else family
    t0 = opening_time(case, options) if opening_time_s is None else float(opening_time_s)
    chosen = _resolved(case, options)
    reruns = _reruns(options, chosen, factor, family)
    with _own_reruns(options):
        t1, t2, t3 = (opening_time(case, o) for o in reruns)
        if chosen.method != "set-valued":
            return ConvergenceCheck(t0, t1, t2, t3, family, factor, threshold)
        wide = tuple(opening_time(case, o) for o in _wide_reruns(reruns, factor))
    return ConvergenceCheck(t0, t1, t2, t3, family, factor, threshold, "set-valued", wide)


def _own_reruns(options: SolverOptions) -> AbstractContextManager[None]:
    """The context of the reruns of a check of `options`: where its method is not bound by
    the width-against-rtol rule (``"auto"``, ``"set-valued"``), neither are the
    regularised reruns it makes by itself (:func:`~obturator.solve.limits.width_rule_waived`);
    an explicitly regularised method's reruns keep its width/rtol ratio or raise it."""
    return width_rule_waived(options.method not in WIDTH_BOUND_METHODS)


def _wide_reruns(
    reruns: tuple[SolverOptions, ...], factor: float
) -> tuple[SolverOptions, SolverOptions]:
    """The regularised runs at the given width of a set-valued case's check: the
    narrow-width reruns (`reruns` [1:]) at `factor` times their width, same tolerances."""
    narrow, other = reruns[1:]
    return (
        replace(narrow, friction_width=narrow.friction_width * factor),
        replace(other, friction_width=other.friction_width * factor),
    )


def _reruns(
    options: SolverOptions, chosen: SolverOptions, factor: float, family: str
) -> tuple[SolverOptions, SolverOptions, SolverOptions]:
    """The three reruns of a case run with `options` by the integrator of `chosen` (its
    resolved method): :func:`refined_options` of `chosen`, but under ``"auto"`` the
    tighter-tolerance rerun stays ``"auto"``, so that it tightens the tolerances the
    case ran with (a set-valued case runs at a third of them,
    :func:`~obturator.solve.dispatch.dispatched_controls`)."""
    tight, narrow, other = refined_options(chosen, factor, family)
    if options.method == "auto":
        tight = options.tighter(factor)
    return tight, narrow, other


def refined_options(
    options: SolverOptions, factor: float = 10.0, family: str | None = None
) -> tuple[SolverOptions, SolverOptions, SolverOptions]:
    """The three reruns of a convergence check: tolerances / `factor`; width / `factor`
    (tolerances too, so slip speeds of order the width stay resolved); the other
    regularisation `family` (default :func:`alternative_family`). For the set-valued
    method, which has no width, the last two are the regularised path at the narrower
    width. For ``"auto"`` those of its regularised cases (the last two run
    ``"regularised"``); a case it runs set-valued is checked as ``"set-valued"``
    (:func:`convergence_check` and :func:`convergence_checks` choose per case)."""
    family = alternative_family(options.friction_family) if family is None else family
    check_choice("family", family, FRICTION_FAMILIES)
    try:
        narrow = replace(options.tighter(factor), friction_width=options.friction_width / factor)
    except InputError as exc:  # the rerun's width, not the one given: say so
        raise InputError(
            "friction_width",
            f"{options.friction_width:g} is checked at width / {factor:g}, and {exc.message}",
        ) from None
    other = replace(options, friction_family=family)
    if options.method == "auto":  # the width and the family are the regularised law's
        narrow = replace(narrow, method="regularised")
        other = replace(other, method="regularised")
    if options.method == "set-valued":  # no width: the regularised path is the check
        narrow = replace(narrow, method="regularised")
        other = replace(narrow, friction_family=family)
    return options.tighter(factor), narrow, other


def _resolved(case: Case, options: SolverOptions) -> SolverOptions:
    """`options` with ``"auto"`` replaced by the integrator it runs `case` with."""
    if options.method != "auto":
        return options
    return replace(options, method=method_of(case, options))  # type: ignore[arg-type]


def convergence_checks(
    cases: Sequence[Case],
    options: SolverOptions | None = None,
    *,
    factor: float = 10.0,
    threshold: float = 1e-3,
    opening_times_s: Sequence[float] | None = None,
    family: str | None = None,
) -> list[ConvergenceCheck]:
    """:func:`convergence_check` of many cases, each rerun through the front door
    (:func:`obturator.solve.opening_times`: in lanes where the options allow).

    Parameters are those of :func:`convergence_check`, with `opening_times_s` the
    t_cr of every case already computed with `options` [s] (NaN: not opened). Under
    ``"auto"`` the cases are rerun in groups by the integrator each runs with, as
    :func:`convergence_check` checks them.
    """
    from .many import opening_times

    options = options or SolverOptions()
    family = alternative_family(options.friction_family) if family is None else family
    t0 = (
        opening_times(cases, options)[0]
        if opening_times_s is None
        else np.asarray(opening_times_s, dtype=float)
    )
    groups: dict[str, list[int]] = {}
    for i, case in enumerate(cases):
        method = _resolved(case, options).method if isinstance(case, Case) else options.method
        groups.setdefault(method, []).append(i)
    reruns = np.full((5, len(cases)), np.nan)
    strategy = ["regularised"] * len(cases)
    for method, idx in groups.items():
        chosen = replace(options, method=method)  # type: ignore[arg-type]
        some = [cases[i] for i in idx]
        planned = _reruns(options, chosen, factor, family)
        if method == "set-valued":
            planned = (*planned, *_wide_reruns(planned, factor))
            for i in idx:
                strategy[i] = "set-valued"
        with _own_reruns(options):
            for r, o in enumerate(planned):
                reruns[r, idx] = opening_times(some, o)[0]
    return [
        ConvergenceCheck(
            float(t0[i]),
            *(float(r[i]) for r in reruns[:3]),
            family,
            factor,
            threshold,
            strategy[i],
            _wide(reruns[3:, i], strategy[i]),
        )  # fmt: skip
        for i in range(len(cases))
    ]


def _wide(values: np.ndarray, strategy: str) -> tuple[float, float]:
    """A check's `wide_width` field: the two values for the set-valued solver, the
    default NaNs (the same objects, so equal checks compare equal) otherwise."""
    if strategy != "set-valued":
        return ConvergenceCheck.__dataclass_fields__["wide_width"].default
    return float(values[0]), float(values[1])


def mark_unconverged(
    cases: Sequence[object], options: SolverOptions, t_cr: np.ndarray, status: np.ndarray
) -> None:
    """Status ``UNCONVERGED`` (in place) for the opened cases whose convergence check
    fails; a rerun that fails to integrate leaves its t_cr unconfirmed, so it fails too."""
    opened = np.flatnonzero(status == Status.OPENED)
    if opened.size:
        picked = [cases[i] for i in opened]
        checks = convergence_checks(picked, options, opening_times_s=t_cr[opened])  # type: ignore[arg-type]
        for i, check in zip(opened, checks, strict=True):
            if not check.converged:
                status[i] = Status.UNCONVERGED
