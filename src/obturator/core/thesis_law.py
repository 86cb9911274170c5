"""The thesis's torque law on the ball, written once for every path that evaluates it.

Two right-hand sides evaluate the thesis's torques: the generic
:func:`obturator.core.dynamics.applied_torque` (every model and regularisation) and
the specialised kernel :func:`obturator.core.specialised.thesis_rates` (the default
path of the scalar integrators and of the batched lanes). They differ in algebra, not
in law: each takes the parts of the law from here, so an edit here changes every
path (``tests/core/test_thesis_law.py`` perturbs this module and checks that the scalar
DOP853 and Radau IIA, both lanes and the generic right-hand side all move).

* :func:`viscous_coefficient`: k in Q = -k omega_r, laminar S (Eq. 42) below the
  transition slip omega_t (Eq. 41), turbulent K |omega_r|^0.75 at and above it (Eq. 39);
* :func:`arm_weights` and :func:`arm_slip_sq`: the sliding-friction moment arm as
  ARM^2 |omega_r|^2 = b_X w_X^2 + w_Y^2 + b_Z w_Z^2 with (b_X, b_Z) = (0, 1) on the rig
  (one bottom contact, Eq. 61: ARM^2 = 1 - u_X^2) and (cos^2 beta, sin^2 beta) in
  flight (Appendix A: ARM^2 = 1 - sin^2 beta u_X^2 - cos^2 beta u_Z^2); written as a
  sum of squares, it has no cancellation near the arm's minimum;
* :func:`algebraic_spread_sq`: the algebraic regularisation s(x) = x / sqrt(1 + x^2),
  x = slip / width, as (slip / s)^2 = width^2 + slip^2 (the kernel folds it into one
  square root with the arm; :func:`~obturator.core.dynamics.slip_saturation` takes
  its square root);
* :func:`slip_speed_factor`: mu(v) / mu_s of the slip-speed laws that extend the
  thesis's constant mu_s (Stribeck-type weakening, polymer strengthening; not in the
  thesis, :class:`obturator.model.torques.SlipSpeedLaw`).

The functions are inlined into their callers (numba IR); no caller allows fast-math
(:mod:`obturator.core.jit_flags`), so they round alike everywhere.
"""

from __future__ import annotations

import math

from numba import njit

from .jit_cache import configure_cache
from .jit_flags import NO_REFCOUNT
from .layout import FRIC_THESIS_FLIGHT, FRIC_THESIS_RIG, SPEED_STRENGTHENING, SPEED_WEAKENING

configure_cache()

__all__ = [
    "viscous_coefficient",
    "arm_weights",
    "arm_slip_sq",
    "algebraic_spread_sq",
    "slip_speed_factor",
]


@njit(cache=True, inline="always", **NO_REFCOUNT)
def viscous_coefficient(slip_sq, s_laminar, k_turbulent, w_transition, turbulent):
    """Viscous coefficient k [N m s] of Q = -k omega_r (thesis Eqs. 39, 41, 42).

    Parameters
    ----------
    slip_sq : float
        |omega_r|^2 [rad^2/s^2].
    s_laminar : float
        Laminar coefficient S [N m s] (Nakabayashi's spherical Couette form, Eq. 42).
    k_turbulent : float
        K [N m s^0.25] of the turbulent moment K |omega_r|^1.75 (Eq. 39).
    w_transition : float
        Transition slip omega_t [rad/s] (Re_t = 70 eps^-1.6, Eq. 41).
    turbulent : bool
        Take the turbulent branch where the slip reaches the transition (False: S
        throughout, the lanes' first pass).

    Returns
    -------
    tuple
        (k [N m s], whether |omega_r| >= omega_t).
    """
    above = slip_sq >= w_transition * w_transition
    k = s_laminar
    if turbulent and above:  # K |omega_r|^0.75 as sqrt(x) sqrt(sqrt(x)): vectorises, pow does not
        rw = math.sqrt(math.sqrt(slip_sq))
        k = k_turbulent * (rw * math.sqrt(rw))
    return k, above


@njit(cache=True, inline="always", **NO_REFCOUNT)
def arm_weights(code, beta):
    """(b_X, b_Z) of the sliding-friction moment arm (rig Eq. 61, flight Appendix A).

    Parameters
    ----------
    code : float
        ``FRIC_THESIS_RIG`` or ``FRIC_THESIS_FLIGHT`` (any other code: (1, 1), ARM = 1).
    beta : float
        Contact angle of the flight ring [rad] (Eqs. 47-55); unused on the rig.

    Returns
    -------
    tuple of float
        Weights [-] of ARM^2 |omega_r|^2 = b_X w_X^2 + w_Y^2 + b_Z w_Z^2.
    """
    if code == FRIC_THESIS_RIG:  # one contact at the bottom of the socket, gravity along -X
        return 0.0, 1.0
    if code == FRIC_THESIS_FLIGHT:  # two contacts on the ring at beta
        sb, cb = math.sin(beta), math.cos(beta)
        return cb * cb, sb * sb
    return 1.0, 1.0


@njit(cache=True, inline="always", **NO_REFCOUNT)
def arm_slip_sq(wx2, wy2, wz2, b_x, b_z):
    """ARM^2 |omega_r|^2 [rad^2/s^2] from the squared inertial slip components."""
    return b_x * wx2 + wy2 + b_z * wz2


@njit(cache=True, inline="always", **NO_REFCOUNT)
def algebraic_spread_sq(slip_sq, width_sq):
    """(slip / s)^2 of the algebraic regularisation s = x / sqrt(1 + x^2), x = slip/width.

    ``width_sq + slip_sq``: s = slip / sqrt(width^2 + slip^2) (width 1: s(x) itself).
    """
    return width_sq + slip_sq


@njit(cache=True, inline="always", **NO_REFCOUNT)
def slip_speed_factor(v, code, ratio, speed):
    """mu(v) / mu_s for a slip speed v [m/s] (1 for the thesis's constant mu_s).

    ``SPEED_WEAKENING`` (Stribeck type): r + (1 - r) exp(-(v/v_s)^2), from mu_s at
    rest to r mu_s in fast slip. ``SPEED_STRENGTHENING`` (polymers such as the
    rig's lucite housing): r + (1 - r) v / (v + v_s), from r mu_s at rest to
    mu_s in fast slip. r = `ratio` in (0, 1], v_s = `speed` > 0 [m/s].
    """
    if code == SPEED_WEAKENING:
        x = v / speed
        return ratio + (1.0 - ratio) * math.exp(-x * x)
    if code == SPEED_STRENGTHENING:
        return ratio + (1.0 - ratio) * v / (v + speed)
    return 1.0
