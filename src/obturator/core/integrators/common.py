"""Compiled helpers shared by the integrators: output buffers, event bracket, Jacobian.

Everything here is called from inside the integrators' compiled loops; nothing
is passed around as a function object (that would defeat numba's on-disk
cache). The integrators own their step formulas, dense output and step-size
control; what they have in common lives here:

* output: :func:`start`, :func:`output_buffers`, :func:`record_row`;
* the opening event: :func:`crossed` (downward crossing of theta_cr) and the
  Illinois false-position bracket (:func:`illinois_trial`,
  :func:`illinois_update`, :func:`bracket_closed`), driven by each method's own
  re-step;
* the forward-difference Jacobian of the implicit methods (:func:`jacobian`)
  and their RMS error norm (:func:`rms_norm`);
* :func:`underflow`, the step-size collapse test.

Fastmath: none (:mod:`obturator.core.jit_flags`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..dynamics import rhs
from ..jit_flags import NO_REFCOUNT, REFCOUNT
from ..layout import N_STATE, P_FORM, P_WIDTH

__all__ = [
    "start",
    "output_buffers",
    "append_row",
    "record_row",
    "crossed",
    "illinois_trial",
    "illinois_update",
    "bracket_closed",
    "jacobian",
    "increment_cap",
    "rms_norm",
    "underflow",
]


@njit(cache=True, fastmath=False, error_model="python", **REFCOUNT)
def output_buffers(t_eval, record, y0, t0):
    """Output arrays sized for t_eval (or growing per step), holding (t0, y0) first when
    recording."""
    n_eval = t_eval.shape[0]
    cap = max(n_eval if n_eval > 0 else (1024 if record else 1), 1)
    ts = np.empty(cap)
    ys = np.empty((cap, y0.shape[0]))
    n_out = 0
    if record and n_eval == 0:
        ts[0] = t0
        ys[0, :] = y0
        n_out = 1
    return ts, ys, n_out


@njit(cache=True, fastmath=False, error_model="python", **REFCOUNT)
def start(problem, controls):
    """A run at t = t0: t0, a copy of the initial state, the output buffers (holding it
    when every step is recorded) and the event state, NaN until an event is found."""
    y = problem.y0.copy()
    ts, ys, n_out = output_buffers(controls.t_eval, controls.record, y, problem.t0)
    return problem.t0, y, ts, ys, n_out, np.full(y.shape[0], math.nan)


@njit(cache=True, fastmath=False, error_model="python", **REFCOUNT)
def append_row(ts, ys, n_out, t, y):
    """Store (t, y) as row `n_out`, doubling the buffers when full; return them and n_out + 1."""
    if n_out >= ts.shape[0]:
        cap = 2 * ts.shape[0]
        ts2 = np.empty(cap)
        ys2 = np.empty((cap, ys.shape[1]))
        ts2[:n_out] = ts[:n_out]
        ys2[:n_out] = ys[:n_out]
        ts = ts2
        ys = ys2
    ts[n_out] = t
    ys[n_out, :] = y
    return ts, ys, n_out + 1


@njit(cache=True, fastmath=False, error_model="python", **REFCOUNT)
def record_row(ts, ys, n_out, t, y, record, use_eval):
    """Append (t, y) when every accepted step is recorded (record and no t_eval)."""
    if record and not use_eval:
        return append_row(ts, ys, n_out, t, y)
    return ts, ys, n_out


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def crossed(g_old, g_new, t_event):
    """True at the first downward crossing of g = theta - theta_cr (no event found yet)."""
    return g_old > 0.0 and g_new <= 0.0 and t_event != t_event


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def illinois_trial(s_lo, g_lo, s_hi, g_hi):
    """Next trial point of Illinois false position on the bracket [s_lo, s_hi]."""
    s = (s_lo * g_hi - s_hi * g_lo) / (g_hi - g_lo)
    if not (s_lo < s < s_hi):
        s = 0.5 * (s_lo + s_hi)
    return s


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def illinois_update(s, g, s_lo, g_lo, s_hi, g_hi, side):
    """Shrink the bracket with the trial (s, g); halve the stale end's g (Illinois).

    A trial with g <= 0 (or NaN) becomes the new upper end: callers keep the
    state of the last such trial as the event state.
    """
    if g > 0.0:
        s_lo, g_lo = s, g
        if side == -1:
            g_hi *= 0.5
        side = -1
    else:
        s_hi, g_hi = s, g
        if side == 1:
            g_lo *= 0.5
        side = 1
    return s_lo, g_lo, s_hi, g_hi, side


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def bracket_closed(s_lo, s_hi, h, event_tol):
    """True when the bracket [s_lo, s_hi] of a step h is at most event_tol long [s]."""
    return (s_hi - s_lo) * h <= event_tol


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def underflow(h, t):
    """True when the step h has collapsed relative to the time t reached."""
    return h < 1e-14 * max(t, 1e-6)


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def increment_cap(scale_j, delta, w_ref, quaternion) -> float:
    """Largest forward-difference increment of component j (see :func:`jacobian`).

    Rates (scale != 1): 1e-4 delta; quaternion components: 1e-4 delta / w_ref (they move
    omega_r by about omega_p per unit); Euler angles and delta = 0: none (inf). Shared by
    :func:`jacobian` and the Radau IIA lanes.
    """
    if delta > 0.0:
        if scale_j != 1.0:
            return 1e-4 * delta
        if quaternion:  # Euler angles fare better uncapped
            return 1e-4 * delta / w_ref
    return math.inf


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def jacobian(t, y, f0, p, scale, jac, work, fwork) -> None:
    """Forward-difference Jacobian of the right-hand side at (t, y), f0 = f(t, y).

    Near sticking the friction torque varies on the scale of the regularisation
    width delta, so increments on the rate-like components must be far below
    delta or the Jacobian error (~increment / delta) spoils the stability the
    stiff phase relies on. Attitude components move omega_r by about omega_p
    per unit, so their increments are capped at 1e-4 delta / omega_p.
    """
    eps = math.sqrt(2.220446049250313e-16)
    delta = p[P_WIDTH]
    w_ref = 1.0
    for j in range(N_STATE):
        w_ref = max(w_ref, scale[j])
    for j in range(N_STATE):
        for i in range(N_STATE):
            work[i] = y[i]
        dj = eps * max(abs(y[j]), scale[j])
        dj = min(dj, increment_cap(scale[j], delta, w_ref, p[P_FORM] == 0.0))
        work[j] = y[j] + dj
        dj = work[j] - y[j]
        rhs(t, work, p, fwork)
        for i in range(N_STATE):
            jac[i, j] = (fwork[i] - f0[i]) / dj


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="python")
def rms_norm(e, y, ynew, rtol, atol, scale) -> float:
    """sqrt(mean((e_i / (atol scale_i + rtol max(|y_i|, |ynew_i|)))^2))."""
    s = 0.0
    for i in range(N_STATE):
        sc = atol * scale[i] + rtol * max(abs(y[i]), abs(ynew[i]))
        q = e[i] / sc
        s += q * q
    return math.sqrt(s / N_STATE)
