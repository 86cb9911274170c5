"""The state of the Radau IIA lanes (:mod:`.radau`): named tuples of flat lane arrays.

Vectors are ``x[i * LANES + lane]``, matrices ``a[(i * N_STATE + j) * LANES + lane]``
(:mod:`.simd`); the Newton workspace is one array with constant offsets
(:mod:`.radau_steps`, ``NW_*``), its parts views of it.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from ...layout import N_STATE
from ..radau import EventWork
from .radau_steps import NW_F, NW_R1, NW_R2, NW_R3, NW_SCAL, NW_SIZE, NW_Z
from .simd import LANES, REFCOUNT

__all__ = ["Lanes", "Attempt", "OneLane", "Settings", "new_lanes", "new_attempt", "new_one_lane"]

_N = N_STATE
_V = N_STATE * LANES  # one vector of every lane
_M = N_STATE * N_STATE * LANES  # one matrix of every lane


class Lanes(NamedTuple):
    """What each lane carries from step to step (``radau._move_lane`` copies all of it)."""

    p: np.ndarray  #: parameters (N_PARAM * LANES)
    y: np.ndarray  #: state (vector)
    f0: np.ndarray  #: f(y) (vector)
    scale: np.ndarray  #: error-weight scales (vector)
    cap: np.ndarray  #: Jacobian increment caps (vector, :func:`.common.increment_cap`)
    z_acc: np.ndarray  #: the last accepted step's stage increments (three vectors)
    jac: np.ndarray  #: Jacobian (matrix)
    t: np.ndarray  #: time [s]
    h: np.ndarray  #: step [s]
    h_acc: np.ndarray  #: the last accepted step [s]
    t_max: np.ndarray  #: end time [s]
    h_max: np.ndarray  #: largest step [s]
    h_lim: np.ndarray  #: step limit after Newton failures [s]
    h_gus: np.ndarray  #: Gustafsson's previous step [s]
    err_gus: np.ndarray  #: Gustafsson's previous error
    faccon: np.ndarray  #: Newton's contraction estimate
    g_old: np.ndarray  #: theta - theta_cr at the step start (inf: not computed)
    t_stick: np.ndarray  #: last time the slip was below saturation (hand-back) [s]
    cos_cr: np.ndarray  #: cos(theta_cr)
    max_steps: np.ndarray  #: int: accepted-step limit
    idx: np.ndarray  #: int: the point in the lane
    cnt: np.ndarray  #: int (3, LANES): nfev, steps, rejected
    new_jac: np.ndarray  #: bool: the Jacobian is stale
    fresh: np.ndarray  #: bool: the Jacobian is new this step
    poly: np.ndarray  #: bool: z_acc holds a collocation polynomial
    first: np.ndarray  #: bool: first step
    hand_back: np.ndarray  #: bool: stop once sliding has resumed
    rejected: np.ndarray  #: bool: the last step was rejected
    live: np.ndarray  #: bool: the lane holds a point


class Attempt(NamedTuple):
    """One attempted step of every lane: Newton workspace, LU factors, per-lane scalars."""

    ynew: np.ndarray  #: y + Z_3 (vector)
    nw: np.ndarray  #: the Newton workspace (:mod:`.radau_steps`, ``NW_*``)
    f: np.ndarray  #: view of nw: stage derivatives (three vectors)
    z: np.ndarray  #: view of nw: stage increments (three vectors)
    work: np.ndarray  #: view of nw: R1, the real residual / correction (vector)
    cbr: np.ndarray  #: view of nw: R2 (vector)
    cbi: np.ndarray  #: view of nw: R3 (vector)
    scal: np.ndarray  #: view of nw: reciprocal error weights (vector)
    fw: np.ndarray  #: right-hand side scratch (vector)
    err_v: np.ndarray  #: right side of the error estimate (vector)
    lu_r: np.ndarray  #: real LU (matrix)
    lu_cr: np.ndarray  #: complex LU, real part (matrix)
    lu_ci: np.ndarray  #: complex LU, imaginary part (matrix)
    piv_r: np.ndarray  #: real pivots (vector)
    piv_c: np.ndarray  #: complex pivots (vector)
    swap_r: np.ndarray  #: bool (N_STATE,): a lane swapped rows at column k (real)
    swap_c: np.ndarray  #: bool (N_STATE,): the same, complex
    theta: np.ndarray  #: Newton's contraction rate
    dyn_old: np.ndarray  #: previous Newton increment norm
    thq_old: np.ndarray  #: previous contraction quotient
    dyno: np.ndarray  #: Newton increment norm, then scratch
    err: np.ndarray  #: error estimate
    h_fac: np.ndarray  #: step factor after a Newton failure
    cos_n: np.ndarray  #: largest cos(theta) over the nodes and the step end
    cos_k: np.ndarray  #: cos(theta) at one node
    vmax: np.ndarray  #: pivot and Jacobian scratch
    newt: np.ndarray  #: int: Newton iterations
    state: np.ndarray  #: int: Newton outcome (_RUNNING, _CONVERGED, _FAILED, _IDLE)
    ok: np.ndarray  #: bool: the LU is regular
    fin: np.ndarray  #: bool: the residual is finite
    run: np.ndarray  #: bool: the lane takes this Newton update
    acc: np.ndarray  #: bool: mask (f(y) wanted, filtered error wanted)
    want: np.ndarray  #: bool: the lanes whose stage derivatives are wanted (Newton)


class OneLane(NamedTuple):
    """One lane's data for the scalar event location (radau.locate_opening_at)."""

    y: np.ndarray
    ynew: np.ndarray
    p: np.ndarray
    scal: np.ndarray
    z: np.ndarray  #: (3, N_STATE)
    jac: np.ndarray  #: (N_STATE, N_STATE)
    event: EventWork  #: what the event location writes
    rates: tuple  #: (state, derivative, parameters): the generic kernel's scratch


class Settings(NamedTuple):
    """Tolerances (RADAU5's transformed ones) and the lane count of the vector loops."""

    rtol: float
    atol: float
    fnewt: float  #: Newton stopping tolerance
    event_tol: float  #: bracket width of the event time [s]
    vw: int  #: LANES, passed at run time (see :mod:`.lu`)
    generic: bool  #: the generic right-hand side, else the thesis kernel (.rates.rates_lanes)


@njit(cache=True, fastmath=False, error_model="numpy", **REFCOUNT)
def new_lanes(n_par: int) -> Lanes:
    f = np.zeros(LANES)
    one = np.ones(LANES)
    i = np.zeros(LANES, dtype=np.int64)
    b = np.zeros(LANES, dtype=np.bool_)
    return Lanes(
        p=np.zeros(n_par * LANES),
        y=np.zeros(_V),
        f0=np.zeros(_V),
        scale=np.ones(_V),
        cap=np.ones(_V),
        z_acc=np.zeros(3 * _V),
        jac=np.zeros(_M),
        t=f.copy(),
        h=one.copy(),
        h_acc=one.copy(),
        t_max=f.copy(),
        h_max=f.copy(),
        h_lim=f.copy(),
        h_gus=f.copy(),
        err_gus=one.copy(),
        faccon=one.copy(),
        g_old=f.copy(),
        t_stick=f.copy(),
        cos_cr=f.copy(),
        max_steps=i.copy(),
        idx=i.copy(),
        cnt=np.zeros((3, LANES), dtype=np.int64),
        new_jac=b.copy(),
        fresh=b.copy(),
        poly=b.copy(),
        first=b.copy(),
        hand_back=b.copy(),
        rejected=b.copy(),
        live=b.copy(),
    )


@njit(cache=True, fastmath=False, error_model="numpy", **REFCOUNT)
def new_attempt() -> Attempt:
    nw = np.zeros(NW_SIZE)
    scal = nw[NW_SCAL : NW_SCAL + _V]
    scal[:] = 1.0
    v = np.zeros(_V)
    f = np.zeros(LANES)
    one = np.ones(LANES)
    i = np.zeros(LANES, dtype=np.int64)
    b = np.zeros(LANES, dtype=np.bool_)
    return Attempt(
        ynew=v.copy(),
        nw=nw,
        f=nw[NW_F : NW_F + 3 * _V],
        z=nw[NW_Z : NW_Z + 3 * _V],
        work=nw[NW_R1 : NW_R1 + _V],
        cbr=nw[NW_R2 : NW_R2 + _V],
        cbi=nw[NW_R3 : NW_R3 + _V],
        scal=scal,
        fw=v.copy(),
        err_v=v.copy(),
        lu_r=np.zeros(_M),
        lu_cr=np.zeros(_M),
        lu_ci=np.zeros(_M),
        piv_r=v.copy(),
        piv_c=v.copy(),
        swap_r=np.zeros(_N, dtype=np.bool_),
        swap_c=np.zeros(_N, dtype=np.bool_),
        theta=f.copy(),
        dyn_old=one.copy(),
        thq_old=one.copy(),
        dyno=f.copy(),
        err=f.copy(),
        h_fac=one.copy(),
        cos_n=f.copy(),
        cos_k=f.copy(),
        vmax=f.copy(),
        newt=i.copy(),
        state=i.copy(),
        ok=np.ones(LANES, dtype=np.bool_),
        fin=np.ones(LANES, dtype=np.bool_),
        run=b.copy(),
        acc=b.copy(),
        want=b.copy(),
    )


@njit(cache=True, fastmath=False, error_model="numpy", **REFCOUNT)
def new_one_lane(n_par: int) -> OneLane:
    s = np.empty(_N)
    m = np.empty((_N, _N))
    z = np.empty((3, _N))
    piv = np.empty(_N, dtype=np.int64)
    return OneLane(
        y=s.copy(),
        ynew=s.copy(),
        p=np.empty(n_par),
        scal=s.copy(),
        z=z.copy(),
        jac=m.copy(),
        event=EventWork(
            zacc=z.copy(),
            stage=(z.copy(), z.copy(), z.copy()),
            lu=(m.copy(), piv.copy(), m.copy(), m.copy(), piv.copy()),
            scratch=(s.copy(), s.copy(), s.copy()),
            ytry=s.copy(),
            y_event=s.copy(),
        ),
        rates=(s.copy(), s.copy(), np.empty(n_par)),
    )
