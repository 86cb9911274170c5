"""Right-hand sides of every lane at once, and the nutation pre-test of both lane drivers.

The thesis's kernel (:func:`obturator.core.specialised.thesis_rates`, the same
compiled function as the scalar path's) in one vector loop over lanes, and the
generic right-hand side (:func:`obturator.core.dynamics.rhs`) lane by lane, and
:func:`rates_lanes`, the one place where a lane driver's kernel choice is made.
Vectors are flat and component-major (``x[i * LANES + lane]``, :mod:`.simd`).

The vector loops always run over all :data:`~.simd.LANES` lanes, live or not: with a
trip count below the vector width part of the lanes would run through LLVM's scalar
remainder loop instead (the same bits without fast-math, :mod:`obturator.core.jit_flags`,
but one loop shape for every batch keeps that from resting on the flags alone).
"""

from __future__ import annotations

import math

from numba import njit, uint64

from ...dynamics import rhs
from ...layout import (
    FORM_EULER,
    KERNEL_THESIS,
    KERNEL_THESIS_STRENGTHENING,
    N_STATE,
    P_DERIVED,
    P_FORM,
    P_FRIC,
    P_KERNEL,
    P_SPEED,
    P_VISC,
    SPEED_CONSTANT,
    SPEED_STRENGTHENING,
    SPEED_WEAKENING,
)
from ...specialised import thesis_rates
from .simd import DRIVER_PHASE, LANE_KERNEL, LANES, NO_REFCOUNT

__all__ = [
    "rhs_thesis_lanes",
    "rhs_generic_lanes",
    "rhs_generic_masked_lanes",
    "rates_lanes",
    "cos_nutation_lanes",
    "cos_nutation_any_lanes",
]


@njit(**LANE_KERNEL)
def rhs_thesis_lanes(y, p, dy, do) -> None:
    """:func:`~obturator.core.specialised.thesis_rates` of every lane into ``dy[do:]``.

    A lane kernel (:data:`.simd.LANE_KERNEL`: no reference counting), kept apart from
    the generic right-hand side. The loop evaluates the laminar viscous branch; if any
    lane's slip reached the turbulent transition it is run again with the turbulent
    branch (same results as the scalar kernel). The variant (slip-speed law) is lane
    0's ``P_KERNEL``: a batch holds one kernel (:func:`obturator.solve.opening_times`
    groups by it).
    """
    kernel = p[P_KERNEL * LANES]
    if kernel == KERNEL_THESIS:
        if _thesis_lanes(y, p, dy, do, False, SPEED_CONSTANT):
            _thesis_lanes(y, p, dy, do, True, SPEED_CONSTANT)
    elif kernel == KERNEL_THESIS_STRENGTHENING:
        if _thesis_lanes(y, p, dy, do, False, SPEED_STRENGTHENING):
            _thesis_lanes(y, p, dy, do, True, SPEED_STRENGTHENING)
    elif _thesis_lanes(y, p, dy, do, False, SPEED_WEAKENING):
        _thesis_lanes(y, p, dy, do, True, SPEED_WEAKENING)


@njit(inline="always", **LANE_KERNEL)
def _thesis_lanes(y, p, dy, do, turbulent, speed) -> int:
    """The loop of :func:`rhs_thesis_lanes`; returns the lanes at or above the turbulent
    transition.

    Indices are cast to unsigned (see :mod:`.dop853_sums`): with signed offsets numba's
    negative-index wrap-around kept this loop scalar (measured ~32 ns per lane and
    call against ~10 ns vectorised).
    """
    d = P_DERIVED
    n_above = 0
    for j in range(LANES):
        c = (
            p[uint64((P_VISC + 1) * LANES + j)],
            p[uint64((P_VISC + 2) * LANES + j)],
            p[uint64((P_VISC + 3) * LANES + j)],
            p[uint64(d * LANES + j)],
            p[uint64((d + 1) * LANES + j)],
            p[uint64((d + 2) * LANES + j)],
            p[uint64((d + 3) * LANES + j)],
            p[uint64((d + 4) * LANES + j)],
            p[uint64((d + 5) * LANES + j)],
            p[uint64((d + 6) * LANES + j)],
            p[uint64((d + 7) * LANES + j)],
            p[uint64((P_SPEED + 1) * LANES + j)],
            p[uint64((P_FRIC + 2) * LANES + j)],
            p[uint64((P_SPEED + 2) * LANES + j)],
        )
        r0, r1, r2, r3, r4, r5, r6, r7, above = thesis_rates(
            y[j],
            y[uint64(j + LANES)],
            y[uint64(j + 2 * LANES)],
            y[uint64(j + 3 * LANES)],
            y[uint64(j + 4 * LANES)],
            y[uint64(j + 5 * LANES)],
            y[uint64(j + 6 * LANES)],
            y[uint64(j + 7 * LANES)],
            c,
            turbulent,
            speed,
        )
        n_above += above
        o = do + j
        dy[uint64(o)] = r0
        dy[uint64(o + LANES)] = r1
        dy[uint64(o + 2 * LANES)] = r2
        dy[uint64(o + 3 * LANES)] = r3
        dy[uint64(o + 4 * LANES)] = r4
        dy[uint64(o + 5 * LANES)] = r5
        dy[uint64(o + 6 * LANES)] = r6
        dy[uint64(o + 7 * LANES)] = r7
    return n_above


@njit(cache=True, error_model="numpy", **NO_REFCOUNT, fastmath=False)
def rhs_generic_lanes(y, p, dy, do, nl, one) -> None:
    """The generic right-hand side (:func:`~obturator.core.dynamics.rhs`) in lanes
    0..nl-1, through `one` = (state, derivative, parameters) of one lane (scratch)."""
    for j in range(nl):
        _generic_lane(y, p, dy, do, j, one)


@njit(cache=True, error_model="numpy", **NO_REFCOUNT, fastmath=False)
def rhs_generic_masked_lanes(y, p, dy, do, nl, one, mask) -> None:
    """:func:`rhs_generic_lanes` in the lanes 0..nl-1 with `mask` set only: the generic
    right-hand side costs as much per lane as the scalar one, so a lane driver in lock
    step evaluates only the lanes that use the result (the others keep ``dy``)."""
    for j in range(nl):
        if mask[j]:
            _generic_lane(y, p, dy, do, j, one)


@njit(inline="always", cache=True, error_model="numpy", **NO_REFCOUNT, fastmath=False)
def _generic_lane(y, p, dy, do, j, one) -> None:
    """rhs of lane j (gathered into `one`, scattered back into ``dy[do:]``)."""
    ys, ds, ps = one
    n_par = p.shape[0] // LANES
    for i in range(N_STATE):
        ys[i] = y[i * LANES + j]
    for i in range(n_par):
        ps[i] = p[i * LANES + j]
    rhs(0.0, ys, ps, ds)
    for i in range(N_STATE):
        dy[do + i * LANES + j] = ds[i]


@njit(**DRIVER_PHASE)
def rates_lanes(y, p, dy, do, kernel, mask) -> None:
    """f(y) into ``dy[do:]`` with the kernel the points were packed for, in the lanes
    whose result is used (`mask`, bool per lane).

    `kernel` is (generic, nl, one): ``generic`` True where the rows carry
    ``P_KERNEL = KERNEL_GENERIC`` (every torque model and friction family of
    :func:`~obturator.core.dynamics.rhs`; lanes 0..nl-1 with `mask` set, one by one
    through the scratch `one` = (state, derivative, parameters)), else the thesis
    kernel over all lanes in one vector loop (cheaper than selecting).
    """
    generic, nl, one = kernel
    if generic:
        rhs_generic_masked_lanes(y, p, dy, do, nl, one, mask)
    else:
        rhs_thesis_lanes(y, p, dy, do)


@njit(**LANE_KERNEL)
def cos_nutation_any_lanes(y, p, out) -> None:
    """cos(theta) of every lane in either formulation (``p[P_FORM]`` per lane): the
    quaternion expression of :func:`cos_nutation_lanes`, or cos of the Euler angle
    theta = y[0]."""
    for j in range(LANES):
        q0 = y[j]
        q1 = y[uint64(LANES + j)]
        q2 = y[uint64(2 * LANES + j)]
        q3 = y[uint64(3 * LANES + j)]
        c = 1.0 - 2.0 * (q1 * q1 + q2 * q2) / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
        euler = p[uint64(P_FORM * LANES + j)] == FORM_EULER
        out[j] = math.cos(q0) if euler else c


@njit(**LANE_KERNEL)
def cos_nutation_lanes(y, out) -> None:
    """cos(theta) = 1 - 2 (q1^2 + q2^2) / |q|^2 of quaternion-form lanes (vectorised)."""
    for j in range(LANES):
        q0 = y[j]
        q1 = y[uint64(LANES + j)]
        q2 = y[uint64(2 * LANES + j)]
        q3 = y[uint64(3 * LANES + j)]
        out[j] = 1.0 - 2.0 * (q1 * q1 + q2 * q2) / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
