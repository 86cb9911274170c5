"""Compiled explicit integrator: Dormand & Prince's 8(5,3) Runge-Kutta pair (DOP853).

Only :mod:`obturator.solve` calls into this module. Outside sticking phases the
equations of motion are not stiff (the friction Jacobian is ~ mu N R_s / (A
|omega_r|), small once the ball slips at several rad/s), so an explicit
high-order pair needs far fewer right-hand-side evaluations than the implicit
methods and no Jacobian. In sticking phases it is hopeless, and it says so
(:data:`STATUS_STIFF`) so that the caller can fall back to Radau IIA.

* Method: the eighth-order pair of Hairer, Norsett & Wanner, *Solving
  Ordinary Differential Equations I*, 2nd ed., Sec. II.10 (code DOP853), with
  its combined 5th/3rd-order error estimate
  ``err = h |e5|^2 / sqrt(|e5|^2 + 0.01 |e3|^2)`` and step control
  ``h_new = h min(10, max(0.2, 0.9 err^(-1/8)))`` (no growth right after a
  rejection). The coefficients are published data; the decimal values here
  were taken from SciPy's ``scipy/integrate/_ivp/dop853_coefficients.py``
  (which transcribes Hairer's ``dop853.f``).
* Error weights as in the other integrators, ``atol * scale[i] + rtol *
  max(|y_i|, |ynew_i|)``, but with (rtol, atol) multiplied by
  :data:`TOL_FACTOR` = 0.01 (rtol floored at 1e-14), so that t_cr errors are
  ~1e-9 relative at rtol 1e-8, as with Radau (which transforms its rtol too).
* Opening event theta = theta_cr (downward crossing) is tested at step ends and
  located by re-stepping from the step start with a shorter step (Illinois
  false position), so the event state is as accurate as an accepted step
  (eighth order), to a bracket of ``event_tol``.
* t_eval output re-steps from the start of the step that contains each output
  time (11 right-hand sides per point), so output values carry the accuracy
  of an accepted step (no interpolation error); it is not used for t_cr.
* Stiffness guard: the run stops with :data:`STATUS_STIFF` once the number of
  accepted plus rejected steps exceeds ``STEPS_PER_PERIOD`` per spin period of
  simulated time plus ``STEP_ALLOWANCE`` (200 and 1000; non-stiff runs need
  ~15-70 steps per period at requested rtol 1e-6..1e-11, h_max being a tenth
  of a period; a sticking phase needs ~1e5), when the step size collapses, or
  when the state turns non-finite.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._rosenbrock import (
    STATUS_MAX_STEPS,
    STATUS_OPENED,
    STATUS_T_MAX,
    append_row,
    illinois_trial,
    illinois_update,
    output_buffers,
)
from .dynamics import N_STATE, nutation_angle_of_state, rhs

__all__ = ["STATUS_STIFF", "STEPS_PER_PERIOD", "STEP_ALLOWANCE", "TOL_FACTOR", "integrate"]

#: Returned when the problem looks stiff (step budget exceeded, step collapse).
STATUS_STIFF = 3
#: Step budget per spin period of simulated time, and the fixed allowance on top.
STEPS_PER_PERIOD = 200.0
STEP_ALLOWANCE = 1000
#: The step error is controlled to this fraction of the requested (rtol, atol).
TOL_FACTOR = 0.01

# ---- DOP853 coefficients (Hairer, Norsett & Wanner, Sec. II.10; values as in
# scipy/integrate/_ivp/dop853_coefficients.py). Stage 12 is f(t + h, y_new).
_C = np.array(
    [
        0.0,
        0.05260015195876773,
        0.0789002279381516,
        0.1183503419072274,
        0.2816496580927726,
        0.3333333333333333,
        0.25,
        0.3076923076923077,
        0.6512820512820513,
        0.6,
        0.8571428571428571,
        1.0,
    ]
)
_A = np.zeros((12, 12))
_A[1, 0] = 0.05260015195876773
_A[2, 0] = 0.0197250569845379
_A[2, 1] = 0.0591751709536137
_A[3, 0] = 0.02958758547680685
_A[3, 2] = 0.08876275643042054
_A[4, 0] = 0.2413651341592667
_A[4, 2] = -0.8845494793282861
_A[4, 3] = 0.924834003261792
_A[5, 0] = 0.037037037037037035
_A[5, 3] = 0.17082860872947386
_A[5, 4] = 0.12546768756682242
_A[6, 0] = 0.037109375
_A[6, 3] = 0.17025221101954405
_A[6, 4] = 0.06021653898045596
_A[6, 5] = -0.017578125
_A[7, 0] = 0.03709200011850479
_A[7, 3] = 0.17038392571223998
_A[7, 4] = 0.10726203044637328
_A[7, 5] = -0.015319437748624402
_A[7, 6] = 0.008273789163814023
_A[8, 0] = 0.6241109587160757
_A[8, 3] = -3.3608926294469414
_A[8, 4] = -0.868219346841726
_A[8, 5] = 27.59209969944671
_A[8, 6] = 20.154067550477894
_A[8, 7] = -43.48988418106996
_A[9, 0] = 0.47766253643826434
_A[9, 3] = -2.4881146199716677
_A[9, 4] = -0.590290826836843
_A[9, 5] = 21.230051448181193
_A[9, 6] = 15.279233632882423
_A[9, 7] = -33.28821096898486
_A[9, 8] = -0.020331201708508627
_A[10, 0] = -0.9371424300859873
_A[10, 3] = 5.186372428844064
_A[10, 4] = 1.0914373489967295
_A[10, 5] = -8.149787010746927
_A[10, 6] = -18.52006565999696
_A[10, 7] = 22.739487099350505
_A[10, 8] = 2.4936055526796523
_A[10, 9] = -3.0467644718982196
_A[11, 0] = 2.273310147516538
_A[11, 3] = -10.53449546673725
_A[11, 4] = -2.0008720582248625
_A[11, 5] = -17.9589318631188
_A[11, 6] = 27.94888452941996
_A[11, 7] = -2.8589982771350235
_A[11, 8] = -8.87285693353063
_A[11, 9] = 12.360567175794303
_A[11, 10] = 0.6433927460157636
_B = np.array(
    [
        0.054293734116568765,
        0.0,
        0.0,
        0.0,
        0.0,
        4.450312892752409,
        1.8915178993145003,
        -5.801203960010585,
        0.3111643669578199,
        -0.1521609496625161,
        0.20136540080403034,
        0.04471061572777259,
    ]
)
_E3 = np.array(
    [
        -0.18980075407240762,
        0.0,
        0.0,
        0.0,
        0.0,
        4.450312892752409,
        1.8915178993145003,
        -5.801203960010585,
        -0.4226823213237919,
        -0.1521609496625161,
        0.20136540080403034,
        0.02265179219836082,
    ]
)
_E5 = np.array(
    [
        0.01312004499419488,
        0.0,
        0.0,
        0.0,
        0.0,
        -1.2251564463762044,
        -0.4957589496572502,
        1.6643771824549864,
        -0.35032884874997366,
        0.3341791187130175,
        0.08192320648511571,
        -0.022355307863886294,
    ]
)


@njit(cache=True, fastmath={"contract"})
def _stages(t, y, h, p, k, ynew, work) -> None:
    """Stages k[1..11] (k[0] = f(t, y) given) and the 8th-order solution ynew."""
    n = N_STATE
    for s in range(1, 12):
        for i in range(n):
            acc = 0.0
            for j in range(s):
                acc += _A[s, j] * k[j, i]
            work[i] = y[i] + h * acc
        rhs(t + _C[s] * h, work, p, k[s])
    for i in range(n):
        acc = 0.0
        for j in range(12):
            acc += _B[j] * k[j, i]
        ynew[i] = y[i] + h * acc


@njit(cache=True, fastmath={"contract"})
def _error_norm(k, h, y, ynew, rtol, atol, scale) -> float:
    """DOP853's combined estimate h |e5|^2 / sqrt((|e5|^2 + 0.01 |e3|^2) n)."""
    n = N_STATE
    s5 = 0.0
    s3 = 0.0
    for i in range(n):
        sc = atol * scale[i] + rtol * max(abs(y[i]), abs(ynew[i]))
        e5 = 0.0
        e3 = 0.0
        for j in range(12):
            e5 += _E5[j] * k[j, i]
            e3 += _E3[j] * k[j, i]
        e5 /= sc
        e3 /= sc
        s5 += e5 * e5
        s3 += e3 * e3
    if s5 == 0.0 and s3 == 0.0:
        return 0.0
    return abs(h) * s5 / math.sqrt((s5 + 0.01 * s3) * n)


@njit(cache=True, nogil=True)  # nogil: the CLI watcher thread can stop a long run
def integrate(
    y0, p, t_max, rtol, atol, scale, h0, h_max, max_steps, t_eval, record, terminal, event_tol
):
    """Integrate from t = 0 until theta = theta_cr (event) or t_max.

    Same interface as :func:`obturator._rosenbrock.integrate`, plus status
    :data:`STATUS_STIFF` (3) when the problem looks stiff; njev is always 0.

    Returns
    -------
    tuple
        (status, t_event, y_event, ts, ys, nfev, njev, n_steps, n_rejected, t_end, y_end)
    """
    n = N_STATE
    theta_cr = p[7]
    y = y0.copy()
    t = 0.0
    k = np.empty((12, n))
    f1 = np.empty(n)  # f(t + h, ynew), the first stage of the next step
    ynew = np.empty(n)
    ytry = np.empty(n)
    work = np.empty(n)
    n_eval = t_eval.shape[0]
    use_eval = n_eval > 0
    ts, ys, n_out = output_buffers(t_eval, record, y)
    i_eval = 0
    nfev = 0
    n_steps = 0
    n_rej = 0
    status = STATUS_T_MAX
    t_event = math.nan
    y_event = np.full(n, math.nan)
    # spin period of the release state: the largest component scale is omega_p0
    w0 = 0.0
    for i in range(n):
        w0 = max(w0, scale[i])
    # Tolerance transformation: the local error per step is controlled to
    # TOL_FACTOR * (rtol, atol). At the requested tolerances the accumulated
    # phase error gave t_cr errors up to ~1e-6 (rig, 700 rad/s, rtol 1e-8) and
    # a t_cr(mu_s) ripple that spoils finite-difference fits; a hundredth gives
    # ~1e-9 for ~1.5x the right-hand sides, like Radau's at equal rtol.
    tol_f = max(TOL_FACTOR, 1e-14 / rtol)
    rtol = tol_f * rtol
    atol = tol_f * atol
    steps_per_time = STEPS_PER_PERIOD * w0 / (2.0 * math.pi)
    rhs(t, y, p, k[0])
    nfev += 1
    h = min(h0, h_max, t_max)
    g_old = nutation_angle_of_state(y, p) - theta_cr
    rejected = False
    while t < t_max:
        if n_steps >= max_steps:
            status = STATUS_MAX_STEPS
            break
        if n_steps + n_rej > steps_per_time * t + STEP_ALLOWANCE:
            status = STATUS_STIFF
            break
        if t + 1.01 * h >= t_max:
            h = t_max - t
        _stages(t, y, h, p, k, ynew, work)
        nfev += 11
        err = _error_norm(k, h, y, ynew, rtol, atol, scale)
        if not (err == err):
            err = 1e10
        if err > 1.0:
            n_rej += 1
            rejected = True
            h *= max(0.2, 0.9 * err ** (-1.0 / 8.0))
            if h < 1e-14 * max(t, 1e-6):
                status = STATUS_STIFF
                break
            continue
        # ---- accepted ----
        t_new = t + h
        t_stop = t_new
        rhs(t_new, ynew, p, f1)
        nfev += 1
        g_new = nutation_angle_of_state(ynew, p) - theta_cr
        if g_old > 0.0 and g_new <= 0.0 and t_event != t_event:
            # Illinois false position on g(s) = theta(step(y, s h)) - theta_cr;
            # k[0] = f(t, y) is unchanged by the trial steps.
            s_lo, s_hi = 0.0, 1.0
            g_lo, g_hi = g_old, g_new
            for i in range(n):
                y_event[i] = ynew[i]
            side = 0
            for _ in range(200):
                if (s_hi - s_lo) * h <= event_tol:
                    break
                s = illinois_trial(s_lo, g_lo, s_hi, g_hi)
                _stages(t, y, s * h, p, k, ytry, work)
                nfev += 11
                g = nutation_angle_of_state(ytry, p) - theta_cr
                s_lo, g_lo, s_hi, g_hi, side = illinois_update(s, g, s_lo, g_lo, s_hi, g_hi, side)
                if not g > 0.0:  # same branch as illinois_update (NaN included)
                    for i in range(n):
                        y_event[i] = ytry[i]
            t_event = t + s_hi * h
            if terminal:
                status = STATUS_OPENED
                t_stop = t_event
        # output on t_eval inside (t, t_stop]: re-step from (t, y), as accurate as a step
        if use_eval:
            while i_eval < n_eval and t_eval[i_eval] <= t_stop:
                _stages(t, y, t_eval[i_eval] - t, p, k, ytry, work)
                nfev += 11
                ts[n_out] = t_eval[i_eval]
                ys[n_out, :] = ytry
                n_out += 1
                i_eval += 1
        if status == STATUS_OPENED:
            if record and not use_eval:
                ts, ys, n_out = append_row(ts, ys, n_out, t_event, y_event)
            y[:] = y_event
            t = t_event
            break
        g_old = g_new
        t = t_new
        for i in range(n):
            y[i] = ynew[i]
            k[0, i] = f1[i]
        n_steps += 1
        if record and not use_eval:
            ts, ys, n_out = append_row(ts, ys, n_out, t, y)
        if not (y[0] == y[0]):
            status = STATUS_STIFF
            break
        fac = 10.0 if err == 0.0 else min(10.0, max(0.2, 0.9 * err ** (-1.0 / 8.0)))
        if rejected:
            fac = min(fac, 1.0)
        rejected = False
        h = min(h * fac, h_max)
    return (status, t_event, y_event, ts[:n_out], ys[:n_out], nfev, 0, n_steps, n_rej, t, y)
