"""One chunk of a study's points: rows of parameter values -> cases -> the front door.

Every grid point or Monte Carlo sample is a row of values; :func:`run_chunk` builds
the rows' cases (:meth:`~obturator.sweeps.spec.SweepSpec.build_case`; an invalid
point keeps its :class:`~obturator.errors.InputError`) and hands them to
:func:`obturator.solve.opening_times`, the same deterministic function wherever it
runs (in this process, a process pool or a Dask worker), so local, pooled and
distributed results are identical bit for bit. :func:`run_chunk` is module level so
that workers can import it.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import replace

import numpy as np

from ..errors import InputError
from ..model.case import Case
from ..model.cases import rig_case
from ..solve import (
    POINT_STATUSES,
    PackedPoints,
    SolverOptions,
    batchable,
    integrate_packed,
    opening_time,
    opening_times,
    pack_points,
    point_status,
)
from ..solve.limits import width_rule_waived
from .spec import SweepSpec

__all__ = [
    "POINT_STATUSES",
    "VALIDITY_POINTS",
    "is_warm",
    "pack_rows",
    "point_status",
    "run_chunk",
    "validity_note",
    "warm",
]

#: Most points of a study whose cases :func:`validity_note` builds (evenly spaced beyond).
VALIDITY_POINTS = 20_000


def rows_to_cases(spec: SweepSpec, names: tuple[str, ...], rows: np.ndarray) -> list[object]:
    """The case of each row (values in `names` order); an invalid point keeps its
    :class:`~obturator.errors.InputError`."""
    cases: list[object] = []
    for row in rows:
        values: Mapping[str, float] = dict(zip(names, row.tolist(), strict=True))
        try:
            cases.append(spec.build_case(values))
        except InputError as exc:
            cases.append(exc)
    return cases


def validity_note(
    spec: SweepSpec,
    names: tuple[str, ...],
    rows_of: Callable[[np.ndarray], np.ndarray],
    n_points: int,
    unit: str = "points",
) -> str | None:
    """What of a study's points lies outside the Appendix B runs, as one clause, or None.

    :func:`obturator.model.validity.outside_validated_data_many` of the cases of the
    rows ``rows_of(idx)``, at most :data:`VALIDITY_POINTS` of them, evenly spaced (the
    clause then says how many were checked). Only the spin rig has runs to compare with.

    Parameters
    ----------
    spec : SweepSpec
    names : tuple of str
        The varied inputs, in the rows' column order.
    rows_of : callable
        Flat point indices -> rows of values.
    n_points : int
        Points of the study.
    unit : str
        What a point is called in the clause (``"points"``, ``"samples"``).

    Returns
    -------
    str or None
    """
    from ..model.validity import outside_validated_data_many

    if spec.case != "spin-rig" or n_points < 1:
        return None
    idx = np.unique(np.linspace(0, n_points - 1, min(n_points, VALIDITY_POINTS)).astype(np.int64))
    note = outside_validated_data_many(_respun_cases(spec, names, rows_of(idx)))
    if note and idx.size < n_points:
        note += f" ({idx.size} evenly spaced {unit} checked)"
    return note


def _respun_cases(spec: SweepSpec, names: tuple[str, ...], rows: np.ndarray) -> list[object]:
    """:func:`rows_to_cases` of rig rows, for the validity note: rows that differ in the
    spin alone share one built case, re-spun (:func:`dataclasses.replace`, which checks
    the spin again in :class:`~obturator.model.case.Case`). A rig case of
    :func:`~obturator.model.cases.case_from_settings` depends on omega_p only through
    ``Case.spin_rate``; a group whose first row is invalid builds each row itself.
    Building a case is most of the note's cost (``docs/benchmarks.md``, history)."""
    if "spin_rate" not in names or rows.shape[0] < 2:
        return rows_to_cases(spec, names, rows)
    k = names.index("spin_rate")
    others = np.delete(rows, k, axis=1)
    _, first, group = np.unique(others, axis=0, return_index=True, return_inverse=True)
    built = rows_to_cases(spec, names, rows[first])
    cases: list[object] = []
    for row, g in zip(rows, group.ravel(), strict=True):
        base = built[g]
        if not isinstance(base, Case):
            cases.extend(rows_to_cases(spec, names, row[None, :]))
            continue
        try:
            cases.append(replace(base, spin_rate=float(row[k])))
        except InputError as exc:
            cases.append(exc)
    return cases


def pack_rows(spec: SweepSpec, names: tuple[str, ...], rows: np.ndarray) -> PackedPoints:
    """:class:`~obturator.solve.PackedPoints` of the rows of one chunk."""
    return pack_points(rows_to_cases(spec, names, rows), spec.options)


def run_chunk(
    spec: SweepSpec, names: tuple[str, ...], rows: np.ndarray, packed: PackedPoints | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """t_cr [s], status and route code (:data:`~obturator.solve.plan.ROUTES`) of the
    points of one chunk (rows of values in ``names`` order).

    Through :func:`obturator.solve.opening_times` (lanes where the options allow, the
    convergence checks' reruns too);
    `packed`: the rows' :class:`~obturator.solve.PackedPoints` where already built
    (:mod:`obturator.sweeps.ahead`). Module level so that process pools and dask
    workers can import it.
    """
    if batchable(spec.options) and not spec.check_convergence:
        packed = pack_rows(spec, names, rows) if packed is None else packed
        t, s, stats = integrate_packed(packed, spec.options)
    else:
        cases = rows_to_cases(spec, names, rows)
        t, s, stats = opening_times(cases, spec.options, check_convergence=spec.check_convergence)
    return t, s, stats["route"]


def warm(options: SolverOptions) -> None:
    """Load (or compile) the integrators once: a short rig run that turns stiff (150
    rad/s, 10 ms) with these options, so ``regularised`` loads DOP853 and Radau IIA, and
    the same run through :func:`obturator.solve.opening_times` (one point: one by one,
    so the DOP853 lanes load with a worker's first lane chunk). ``auto``'s set-valued
    solver and the Radau IIA lanes load with the first point that takes them (in the
    runner's probe, before workers fork, or in each worker), so a study with none does
    not pay them. Loading never changes a result (:mod:`obturator.core.jit_flags`)."""
    if is_warm(options):
        return
    case = rig_case(150.0, 0.5, t_max=1e-2)
    regularised = replace(options, method="regularised") if options.method == "auto" else options
    try:
        # loading code only: no width/rtol rule (solve.limits), which the points meet
        with width_rule_waived():
            opening_time(case, regularised)
            if batchable(options):
                opening_times([case], regularised)
    except RuntimeError:  # pragma: no cover - warm-up only
        pass
    _WARM.add(options)


#: The options of the :func:`warm` calls done in this process (forked workers inherit
#: it with the loaded code).
_WARM: set[SolverOptions] = set()


def is_warm(options: SolverOptions) -> bool:
    """True when :func:`warm` has loaded the integrators for `options` in this process."""
    return options in _WARM
