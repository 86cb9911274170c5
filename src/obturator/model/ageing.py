"""Contact ageing of the lucite seat: static friction that grows with contact time (issue 29).

Mechanism
---------
Dry friction of glassy polymers and rocks is not one number: the real area
of the asperity contacts creeps under load, so the static friction grows
with the time a contact has existed, logarithmically,

    mu_static(t) = mu_s + b ln(1 + t / tau)                       (1)

(Dieterich, J. H., 1972, "Time-dependent friction in rocks", Journal of
Geophysical Research 77, 3690-3697; for PMMA, the rig's lucite, the same
law, with the creep of the micro-contacts seen directly: Dieterich, J. H. and
Kilgore, B. D., 1994, "Direct observation of frictional contacts: new
insights for state-dependent properties", Pure and Applied Geophysics 143,
283-302; Berthoud, P., Baumberger, T., G'Sell, C. and Hiver, J.-M., 1999,
"Physical analysis of the state- and rate-dependent friction law: static
friction", Physical Review B 59, 14313-14327). b is the ageing rate, of order
1e-2 for these materials, tau a short cut-off time. Once the surfaces slide,
the contacts are renewed after a slip of a memory length D_c of about a
micrometre (the state variable of the Rice-Ruina rate-and-state law: Rice,
J. R. and Ruina, A. L., 1983, "Stability of steady frictional slipping",
Journal of Applied Mechanics 50, 343-349; Baumberger, T. and Caroli, C.,
2006, "Solid friction from stick-slip down to pinning and aging", Advances in
Physics 55, 279-348): at slip speed v the contact age is D_c / v.

Why it fits this rig
--------------------
The spin axis of Bloomer's rig is horizontal (shaft in pillow blocks,
chapter III.A) and the load is the ball's weight, so the contact stays at
the bottom of the socket in the laboratory (Eqs. 56-61) while the seat turns
under it at omega_p. Before release and as long as the ball sticks, every
asperity of the lucite seat is loaded only while the contact patch (Hertz
radius a, 0.28 mm: :func:`~.torques.hertz_patch_radius`) passes over it:

    t_d = 2 a / (R_s omega_p),                                     (2)

0.9 ms at 78 rad/s, 0.16 ms at 446 rad/s. The contact age at rest, and so
the static friction that resists the first slip of the ball at release and
at every re-stick, is therefore set by the spin rate: higher at low spin.
In slip the age falls to about D_c / v. Both together give the quasi-steady
age 1 / (1/t_d + v/D_c): the ageing part of (1) is b ln(1 + t_d/tau) at rest
and fades once v exceeds about D_c / t_d (a few mm/s at the rig's spins), a
Stribeck-type weakening whose height and fade speed both depend on omega_p.
The rig's other mechanisms do not vary this way: a speed law of mu alone
has the same curve at every spin.

What the spin-rig runs say
--------------------------
Fitted to the 54 runs of Appendix B (``obturator validate``, band-wise noise)
the ageing rate goes to b = 0: its -log L is that of mu_s alone, 80 AIC units
behind velocity-strengthening friction. Ageing makes the slow runs slower,
and they are measured faster than one mu predicts. The short dwell is itself
the argument for the strengthening law: with contacts renewed every
0.2-0.9 ms the state term b ln(1 + t/tau) has no time to grow, and what is
left of rate-and-state friction is its direct effect, a ln(v) with a > 0 (the
thermally activated creep of the junctions, Baumberger and Caroli 2006):
friction that rises with slip speed, which is what the ``strengthening``
candidate fits.

Model
-----
Per case (one spin rate) :meth:`ContactAgeing.friction` gives the static
coefficient mu_0 = mu_s + b ln(1 + t_d/tau) and the slip-speed law
:class:`~.torques.SlipSpeedLaw` ``"weakening"`` with ratio r = mu_s / mu_0
and speed v_s = D_c / t_d: mu(v) = mu_0 (r + (1 - r) exp(-(v/v_s)^2)), which
is mu_0 at rest and mu_s in fast slip. The Gaussian fade stands for the
logarithmic one of the quasi-steady age (same height, same speed scale; its
exact shape is beyond what t_cr can resolve). The compiled kernel is the
existing weakening law: no new torque term. With b = 0 the case is the
thesis's: :func:`~.cases.rig_case` then builds exactly the constant-mu case.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import check_range
from .torques import MAX_MU, SlipSpeedLaw

__all__ = ["DEFAULT_MEMORY_LENGTH", "ContactAgeing"]

#: Memory length D_c of the contact state [m]: about 1 um for glassy polymers such as
#: PMMA (Berthoud et al. 1999; Baumberger and Caroli 2006).
DEFAULT_MEMORY_LENGTH = 1e-6


@dataclass(frozen=True)
class ContactAgeing:
    """Logarithmic ageing of the static friction with the contact's dwell time.

    Parameters
    ----------
    rate : float
        Ageing rate b [-] of Eq. (1) of the module notes (>= 0; 0: no ageing).
    cutoff_time : float
        Cut-off time tau [s] (> 0).
    memory_length : float
        D_c [m] (> 0): slip that renews the contacts.
    """

    rate: float = 0.0
    cutoff_time: float = 1e-3
    memory_length: float = DEFAULT_MEMORY_LENGTH

    def __post_init__(self) -> None:
        check_range("ageing_rate", self.rate, 0.0, 10.0)
        check_range("ageing_time", self.cutoff_time, 0.0, math.inf, lo_open=True, unit="s")
        check_range("memory_length", self.memory_length, 0.0, math.inf, lo_open=True, unit="m")

    @staticmethod
    def dwell_time(patch_radius: float, ball_radius: float, spin_rate: float) -> float:
        """t_d = 2 a / (R_s omega_p) [s], Eq. (2): the seat's contact time per pass.

        Parameters
        ----------
        patch_radius : float
            Contact patch radius a [m].
        ball_radius : float
            R_s [m].
        spin_rate : float
            omega_p [rad/s].
        """
        return 2.0 * patch_radius / (ball_radius * spin_rate)

    def static_friction(self, mu_s: float, dwell_time: float) -> float:
        """mu_0 = mu_s + b ln(1 + t_d / tau) [-], at most the model's largest coefficient
        :data:`~.torques.MAX_MU` (reached only far outside the physical range, at a
        large b, a tiny tau and a slow spin; the fit's bounds keep b <= 0.1)."""
        return min(mu_s + self.rate * math.log1p(dwell_time / self.cutoff_time), MAX_MU)

    def friction(
        self, mu_s: float, patch_radius: float, ball_radius: float, spin_rate: float
    ) -> tuple[float, SlipSpeedLaw]:
        """The static coefficient mu_0 and the slip-speed law of one spin rate.

        Returns
        -------
        (float, SlipSpeedLaw)
            mu_0 [-] and the weakening law from mu_0 at rest to `mu_s` in fast slip
            (the constant law when b = 0 or mu_s = 0).
        """
        t_d = self.dwell_time(patch_radius, ball_radius, spin_rate)
        mu_0 = self.static_friction(mu_s, t_d)
        if mu_0 <= mu_s or mu_s <= 0.0:
            return mu_s, SlipSpeedLaw()
        return mu_0, SlipSpeedLaw("weakening", mu_s / mu_0, self.memory_length / t_d)
