"""Where the model is validated, and a one-line note for inputs far outside it.

The rig model is checked against the 54 spin-rig runs of Appendix B (77.8-446.1 rad/s;
``obturator validate``) and its numerics for convergence down to 40 rad/s
(``tests/solve/test_convergence.py``). Far below, the ball sticks for a long time and the
regularised Coulomb friction, of width ``friction_width`` x omega_p, becomes very stiff:
measured on the Zen 4 development machine with the defaults, the cost per simulated
second rises from ~0.03 s at 40 rad/s to ~0.3 s at 5 rad/s and ~80 s at 2.6 rad/s
(``--spin-rate "150 deg/s"``, a plausible unit slip), where a run reaches the step
limit after minutes. That is the regularised law (``method="regularised"``); the default
``auto`` runs such cases with the set-valued solver (:mod:`obturator.solve.dispatch`),
whose stick phases are closed-form rotations (2.6 rad/s: stick to t_max in ~0.2 ms).
"""

from __future__ import annotations

from .case import Case

__all__ = ["RIG_RUN_SPINS", "CONVERGENCE_CHECKED_SPIN", "outside_validated_range"]

#: Lowest and highest spin of the Appendix B rig runs [rad/s] (from their readouts;
#: tests/model/test_validity.py checks them against the shipped data).
RIG_RUN_SPINS: tuple[float, float] = (77.84, 446.11)

#: Lowest rig spin at which tests/solve/test_convergence.py checks t_cr [rad/s].
CONVERGENCE_CHECKED_SPIN = 40.0


def outside_validated_range(case: Case) -> str | None:
    """What is far outside the validated range in `case`, or None.

    "Far" is a spin below half the lowest rig run, below the spins whose convergence
    is tested: there the ball sticks and slips for long and the cost explodes, on the
    rig and in flight alike. Higher spins are cheap (flight runs at 12,042 rad/s) and
    are not flagged.

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
