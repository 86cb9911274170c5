"""Where the model is validated, and a one-line note for inputs outside it.

The rig model is checked against the 54 spin-rig runs of Appendix B (77.8-446.1 rad/s;
``obturator validate``) and its numerics for convergence down to 40 rad/s
(``tests/solve/test_convergence.py``). Far below, the ball sticks for a long time and the
regularised Coulomb friction, of width ``friction_width`` x omega_p, becomes very stiff:
with the defaults the cost per simulated second grows steeply as the spin falls, and
at 2.6 rad/s (``--spin-rate "150 deg/s"``, a plausible unit slip) a run reaches the
step limit (``docs/benchmarks.md``, history). That is the regularised law
(``method="regularised"``); the default ``auto`` runs such cases with the set-valued
solver (:mod:`obturator.solve.dispatch`), whose stick phases are closed-form rotations.

Beyond cost, :func:`outside_validated_data` names what of a rig case lies outside the
runs themselves: their spins, their release angle (87.25 +- 1 deg, chapter IV p. 97),
their ball (Table 1) and the moment that held the ball at release. A ball spun at
omega_p with its hole axis at theta_0 from the spin axis needs the moment
omega_p^2 |C - A| sin(theta_0) cos(theta_0) (:func:`holding_moment`; the gyroscopic
moment of Eq. 5 at rest relative to the rig) to stay there until the release; the seat
gives at most mu_s W R_s (:func:`seat_friction_moment`, the scale of Eq. 61) and the
holding jet about F_jet R_s (:func:`holding_jet_moment`, the bound argued for
``theta_dot0`` in :data:`obturator.params.FIT_SPECS`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import cache

from ..reference import TABLE1
from .case import Case
from .torques import CoulombContactFriction

__all__ = [
    "RIG_RUN_SPINS",
    "RIG_RUN_THETA0_DEG",
    "CONVERGENCE_CHECKED_SPIN",
    "HOLDING_JET_FORCE",
    "BALL_TOLERANCE",
    "holding_moment",
    "seat_friction_moment",
    "holding_jet_moment",
    "rig_run_holding_moments",
    "outside_validated_range",
    "outside_validated_data",
    "outside_validated_data_many",
]

#: Lowest and highest spin of the Appendix B rig runs [rad/s] (from their readouts;
#: tests/model/test_validity.py checks them against the shipped data).
RIG_RUN_SPINS: tuple[float, float] = (77.84, 446.11)

#: Release angles of the rig runs [deg]: Table 1's 87.25 deg, which "could only vary by
#: +-1 deg" (chapter IV, p. 97; the plausible range of theta0_deg in params.FIT_SPECS).
RIG_RUN_THETA0_DEG: tuple[float, float] = (86.25, 88.25)

#: Lowest rig spin at which tests/solve/test_convergence.py checks t_cr [rad/s].
CONVERGENCE_CHECKED_SPIN = 40.0

#: Force of the rig's holding jet [N]: air at ~100 m/s through a ~2 mm nozzle (the
#: bound argued for theta_dot0 in params.FIT_SPECS; chapter III.B, Figs. 26-27). Acting
#: fully tangentially at R_s it gives at most F_jet R_s.
HOLDING_JET_FORCE = 0.04

#: Relative difference of R_s, r_s or rho from Table 1's ball beyond which a ball is
#: another ball than the runs' (0.5 %: well above the printed digits of Table 1).
BALL_TOLERANCE = 5e-3


def holding_moment(case: Case) -> float:
    """Moment that holds the ball at theta_0 while it spins with the rig [N m].

    At rest relative to the projectile (theta_dot = phi_dot = 0, psi_dot = omega_p, the
    thesis's release state, p. 45) Euler's equations (Eq. 5) leave the moment
    omega_p^2 (C - A) sin(theta_0) cos(theta_0) about the line of nodes: it drives the
    nutation towards theta = 0 (C > A) and something must supply it until the release.

    Parameters
    ----------
    case : Case
        Any case; its ball's C and A [kg m^2], spin omega_p [rad/s] and theta_0 [rad].

    Returns
    -------
    float
        omega_p^2 |C - A| sin(theta_0) cos(theta_0) [N m], >= 0.
    """
    b = case.ball
    dI = abs(b.axial_inertia - b.transverse_inertia)
    return case.spin_rate**2 * dI * abs(math.sin(case.theta0) * math.cos(case.theta0))


def seat_friction_moment(case: Case) -> float:
    """Largest friction moment the seat exerts, the scale of Eq. 61 [N m].

    mu_s W R_s on the rig (the friction law's moment scale: thesis Eq. 61, Appendix A
    with C(1) = 1); in flight mu_s F_p cos(beta) R_s (Eqs. 43-55); for the point-contact
    law mu_s N_k R_s summed over its contacts. A slip-speed law scales mu between
    ``ratio`` mu_s and mu_s, so mu_s is its largest.

    Parameters
    ----------
    case : Case

    Returns
    -------
    float
        The moment [N m]; 0 without a friction term.
    """
    f = case.torque.friction
    if f is None:
        return 0.0
    if isinstance(f, CoulombContactFriction):
        return float(f.mu_s * f.load_per_contact * f.ball_radius * f.n_contacts)
    return float(f.moment_scale)


def holding_jet_moment(case: Case) -> float:
    """Largest moment of the rig's holding jet, F_jet R_s [N m].

    The bound argued for ``theta_dot0`` in :data:`obturator.params.FIT_SPECS`: a jet of
    :data:`HOLDING_JET_FORCE` acting fully tangentially at the ball's surface. A jet on a
    sphere pushes along the normal, through the centre, so this is an upper bound.

    Parameters
    ----------
    case : Case

    Returns
    -------
    float
        F_jet R_s [N m].
    """
    return HOLDING_JET_FORCE * case.ball.radius


def rig_run_holding_moments(mu_s: float | None = None) -> tuple[float, float]:
    """Range of :func:`holding_moment` over the Appendix B runs [N m].

    The runs' spins (:data:`RIG_RUN_SPINS`) with Table 1's ball at Table 1's theta_0.

    Parameters
    ----------
    mu_s : float, optional
        If given, the range is returned as multiples of the runs' seat moment
        mu_s W R_s (Table 1's W and R_s) instead [-].

    Returns
    -------
    (float, float)
        Lowest and highest holding moment [N m] (or ratio [-]).
    """
    lo, hi = _rig_run_holding_moments()
    if mu_s is None:
        return lo, hi
    seat = mu_s * TABLE1["rig_weight"] * TABLE1["ball_radius"]
    return lo / seat, hi / seat


@cache
def _rig_run_holding_moments() -> tuple[float, float]:
    # constants of the runs, built once per process: a study's check asks per point
    from .cases import rig_case

    lo, hi = (holding_moment(rig_case(w, theta0_deg=TABLE1["theta0_deg"])) for w in RIG_RUN_SPINS)
    return lo, hi


def outside_validated_range(case: Case) -> str | None:
    """What is far outside the validated range in `case`, or None.

    "Far" is a spin below half the lowest rig run, below the spins whose convergence
    is tested: there the ball sticks and slips for long and the cost explodes, on the
    rig and in flight alike. Higher spins are cheap (flight runs at 12,042 rad/s) and
    are not flagged here (see
    :func:`outside_validated_data`).

    Parameters
    ----------
    case : Case

    Returns
    -------
    str or None
        One clause naming the input, its value [rad/s] and the validated range.
    """
    lo, hi = RIG_RUN_SPINS
    w = case.spin_rate
    if w >= lo / 2.0:
        return None
    return (
        f"spin_rate {w:.4g} rad/s is far below the spin rig's runs "
        f"(Appendix B: {lo:.1f}-{hi:.1f} rad/s; convergence checked from "
        f"{CONVERGENCE_CHECKED_SPIN:g} rad/s)"
    )


def _ball_clause(case: Case) -> str | None:
    b = case.ball
    mine = {"R_s": b.radius, "r_s": b.hole_radius, "rho": b.density}
    runs = {
        "R_s": TABLE1["ball_radius"],
        "r_s": TABLE1["hole_radius"],
        "rho": TABLE1["density"],
    }
    units = {"R_s": ("mm", 1e3), "r_s": ("mm", 1e3), "rho": ("kg/m^3", 1.0)}
    off = [k for k in mine if abs(mine[k] / runs[k] - 1.0) > BALL_TOLERANCE]
    if not off:
        return None
    parts = ", ".join(
        f"{k} {mine[k] * units[k][1]:.4g} {units[k][0]} (runs {runs[k] * units[k][1]:.4g})"
        for k in off
    )
    return f"ball {parts} is not the runs' Table 1 ball"


def outside_validated_data(case: Case) -> str | None:
    """What of a rig case lies outside the Appendix B runs, as one clause, or None.

    Checks the release angle against :data:`RIG_RUN_THETA0_DEG`, the spin against
    :data:`RIG_RUN_SPINS` (from half the lowest run up; further below
    :func:`outside_validated_range` speaks), the ball against Table 1's
    (:data:`BALL_TOLERANCE`) and the :func:`holding_moment` against the largest the runs
    needed, in N m and as a multiple of the seat's :func:`seat_friction_moment` (a ball
    the rig could not have held at release). Only the spin rig is checked: in flight
    the release and the ball are the design's, not a rig's.

    Parameters
    ----------
    case : Case

    Returns
    -------
    str or None
        Clauses joined by "; ", each naming the input, its value with unit and the
        runs' range.
    """
    if case.name != "spin-rig":
        return None
    clauses: list[str] = []
    lo, hi = RIG_RUN_SPINS
    w = case.spin_rate
    if lo / 2.0 <= w < lo or w > hi:
        clauses.append(f"spin_rate {w:.4g} rad/s is outside the runs' {lo:.1f}-{hi:.1f} rad/s")
    th = math.degrees(case.theta0)
    t_lo, t_hi = RIG_RUN_THETA0_DEG
    if not t_lo <= th <= t_hi:
        clauses.append(f"theta_0 {th:.4g} deg is outside the runs' {t_lo:g}-{t_hi:g} deg")
    ball = _ball_clause(case)
    if ball:
        clauses.append(ball)
    need = holding_moment(case)
    seat = seat_friction_moment(case)
    jet = holding_jet_moment(case)
    m_lo, m_hi = rig_run_holding_moments()
    mu = case.torque.friction.mu_s if case.torque.friction is not None else 0.0
    r_hi = rig_run_holding_moments(mu)[1] if mu > 0 else math.inf
    ratio = need / seat if seat > 0 else math.inf
    if need > m_hi or ratio > r_hi:
        r_lo = rig_run_holding_moments(mu)[0] if mu > 0 else math.inf
        clauses.append(
            f"holding moment omega_p^2 |C - A| sin cos theta_0 = {need:.3g} N m is "
            f"{ratio:.3g} x the seat's mu_s W R_s = {seat:.3g} N m and "
            f"{need / jet:.3g} x the holding jet's F R_s = {jet:.3g} N m; the runs needed "
            f"{m_lo:.2g}-{m_hi:.2g} N m ({r_lo:.2g}-{r_hi:.2g} x the seat's)"
        )
    return "; ".join(clauses) or None


def outside_validated_data_many(cases: Sequence[object]) -> str | None:
    """How many of a study's cases lie outside the Appendix B runs, as one clause, or None.

    :func:`outside_validated_data` of each :class:`Case` (anything else, such as an
    invalid point's error, is skipped).

    Parameters
    ----------
    cases : sequence of Case or other

    Returns
    -------
    str or None
        ``"k of n points lie outside the validated data (first: <clause>)"``.
    """
    notes = [outside_validated_data(c) for c in cases if isinstance(c, Case)]
    flagged = [n for n in notes if n]
    if not flagged:
        return None
    return (
        f"{len(flagged)} of {len(notes)} points lie outside the validated data "
        f"(first: {flagged[0]})"
    )
