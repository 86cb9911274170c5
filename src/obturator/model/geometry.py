"""Mass properties of the bored ball obturator (thesis chapter II.A and II.D).

The ball is a sphere of radius R_s bored through along a diameter with a hole
of radius r_s; the two end caps go with the bore, so the solid is a "napkin
ring". The thesis's printed Eqs. (9d), (10a) and (11c) are garbled by OCR; here
every property is integrated from thin cylindrical shells of radius rho_r and
half-length h = sqrt(R_s^2 - rho_r^2) (thesis Eqs. 6-8):

    dm      = 4 pi rho rho_r h d(rho_r)                         (Eq. 8)
    dC      = rho_r^2 dm                                        (Eq. 10b)
    dI_perp = (rho_r^2 / 2 + h^2 / 3) dm                        (Eq. 7)

With U = R_s^2 - r_s^2 this gives, in closed form,

    m = (4/3) pi rho U^(3/2)
    C = 4 pi rho (r_s^2/5 + 2 R_s^2/15) U^(3/2)                 (Eq. 10b)
    A = C/2 + (4/15) pi rho U^(5/2)
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field

from ..errors import InputError, check_range

__all__ = ["STANDARD_GRAVITY", "BoredBall"]

#: Standard acceleration of gravity [m/s^2] used to turn mass into weight W.
STANDARD_GRAVITY = 9.80665


@dataclass(frozen=True)
class BoredBall:
    """A sphere bored through along one diameter: the ball obturator.

    Parameters
    ----------
    radius : float
        Ball radius R_s [m].
    hole_radius : float
        Radius of the diametral hole r_s [m]; must satisfy
        0 <= r_s < R_s / sqrt(2) (thesis p. 77: beyond that the ball cannot
        block the bore).
    density : float
        Material density rho [kg/m^3].
    gravity : float, optional
        Acceleration of gravity g [m/s^2] used for the weight W.

    Notes
    -----
    Thesis Table 1 (R_s = 7.899 mm, r_s = 4.72 mm, rho = 7669.6 kg/m^3) gives
    C = 3.128e-7 kg m^2 and A = 2.219e-7 kg m^2 (the thesis prints 3.125e-7
    and 2.216e-7), lambda = 0.41 and W = 0.0800 N.
    """

    radius: float
    hole_radius: float
    density: float
    gravity: float = STANDARD_GRAVITY
    _u: float = field(init=False, repr=False, compare=False)
    _ca: tuple[float, float] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        r_big = check_range("radius", self.radius, 0.0, math.inf, lo_open=True, unit="m")
        r_lim = r_big / math.sqrt(2.0)
        r_small = check_range("hole_radius", self.hole_radius, 0.0, unit="m")
        if r_small >= r_lim:
            raise InputError(
                "hole_radius",
                f"{r_small:g} m is outside the allowed range [0, R_s/sqrt(2)) = [0, {r_lim:g}) m "
                "(a larger hole leaves too little ball to block the bore)",
            )
        check_range("density", self.density, 0.0, math.inf, lo_open=True, unit="kg/m^3")
        check_range("gravity", self.gravity, 0.0, math.inf, unit="m/s^2")
        object.__setattr__(self, "_u", r_big**2 - r_small**2)
        # (C, A) once: every case packs them (the flight studies build a case a segment)
        object.__setattr__(self, "_ca", self._inertias(self.density))
        self._check_inertia()

    def _check_inertia(self) -> None:
        """Refuse a ball whose moment of inertia A (the smaller of A, C; A = rho R_s^5
        times a number of order 1) is below the smallest normal double: Euler's
        equations divide by it, and its reciprocal would overflow (the rig's ball: below
        a density of 7.7e-298 kg/m^3; a steel ball: below a radius of ~4e-63 m). Names
        whichever of density and radius lies further, in orders of magnitude of A, from
        a steel ball of radius 1 cm."""
        a, tiny = self.transverse_inertia, sys.float_info.min
        if a >= tiny:
            return
        why = (
            f"gives the ball a moment of inertia A = {a:g} kg m^2, below the smallest "
            f"normal double {tiny:g} kg m^2 (the equations of motion divide by it)"
        )
        off_density = abs(math.log10(self.density) - math.log10(7800.0))  # no underflow
        if off_density >= 5.0 * abs(math.log10(self.radius) - math.log10(0.01)):
            rho_min = tiny / self._inertias(1.0)[1]  # A is linear in rho
            raise InputError(
                "density",
                f"{self.density:g} kg/m^3 {why}; allowed at this size: >= {rho_min:.3g} kg/m^3",
            )
        # solid sphere A = 8 pi rho R^5 / 15: the bore only lowers A
        r_min = (15.0 * tiny / (8.0 * math.pi * self.density)) ** 0.2
        raise InputError(
            "radius", f"{self.radius:g} m {why}; allowed at this density: above ~{r_min:.3g} m"
        )

    @property
    def volume(self) -> float:
        """Volume V [m^3].

        Equals the thesis's 2 pi R_s cos(beta) [R_s^2 (1 - cos^2(beta)/3) - r_p^2] (p. 77).
        """
        return 4.0 / 3.0 * math.pi * self._u**1.5

    @property
    def mass(self) -> float:
        """Mass m [kg]."""
        return self.density * self.volume

    @property
    def weight(self) -> float:
        """Weight W = m g [N] (thesis Eq. 61 load on the spin rig)."""
        return self.mass * self.gravity

    @property
    def axial_inertia(self) -> float:
        """Moment of inertia C about the hole axis z [kg m^2], thesis Eq. (10b)."""
        return self._ca[0]

    @property
    def transverse_inertia(self) -> float:
        """Moment of inertia A about a diameter normal to the hole [kg m^2] (thesis A, Eq. 11)."""
        return self._ca[1]

    def _inertias(self, density: float) -> tuple[float, float]:
        """(C, A) [kg m^2] of this ball's shape at `density` [kg/m^3] (Eqs. 10b, 11)."""
        r, big = self.hole_radius, self.radius
        c = 4.0 * math.pi * density * (r**2 / 5.0 + 2.0 * big**2 / 15.0) * self._u**1.5
        return c, 0.5 * c + 4.0 / 15.0 * math.pi * density * self._u**2.5

    @property
    def inertia_ratio(self) -> float:
        """lambda = C/A - 1 [-], thesis Eq. (12)."""
        return self.axial_inertia / self.transverse_inertia - 1.0

    @property
    def opening_angle(self) -> float:
        """beta_s = asin(r_s / R_s) [rad]: the bore opens when theta falls to this value."""
        return math.asin(self.hole_radius / self.radius)
