"""Point-mass flight of the projectile after muzzle exit (beyond the thesis).

The thesis evaluates the obturator at one flight condition (Table 1: M_1 = 3,
P_1 = 0.099 MPa, omega_p = 12042 rad/s) held constant. In flight the
projectile decelerates, climbs or falls and loses spin, so the normal-shock load
F_p = pi r_p^2 (P_2 - P_1) (thesis Eqs. 1, 3, 43) and omega_p change while the
ball opens. This module integrates the trajectory; :mod:`obturator.envelope.coupled`
feeds it to the obturator.

Model (flat Earth, no wind, zero yaw):

    dx/dt = u,   dz/dt = w,
    du/dt = -(rho S C_D(M) V / (2 m_p)) u,
    dw/dt = -(rho S C_D(M) V / (2 m_p)) w - g,
    I_p d(omega_p)/dt = (1/2) rho V^2 S d (omega_p d / V) C_lp,

with V = sqrt(u^2 + w^2), S = pi R_p^2, d = 2 R_p, M = V / a. The spin equation
is the standard aeroballistic roll-damping moment with the non-dimensional spin
p d / V and the roll-damping coefficient C_lp < 0 (McCoy, *Modern Exterior
Ballistics*, chapter on aerodynamic forces and moments). m_p, R_p, I_p are
thesis Table 1's (0.141 kg, 9.96 mm, 8.58e-6 kg m^2); C_lp = -0.012 is a value
representative of spin-stabilised 20-30 mm projectiles at supersonic speed
(not measured for the tubular projectile, whose internal bore adds skin-friction
roll damping: give your own with ``roll_damping``). With it the spin decays by
about 1 % in 0.1 s at Mach 3, sea level.

Air: U.S. Standard Atmosphere 1976 (:func:`obturator.flow.atmosphere.standard_atmosphere`)
at the current altitude (launch altitude plus height gained; below 0 m the
sea-level state is used, since a flat-fire shot from a sea-level gun drops only
centimetres while the ball opens). An off-standard day is a temperature offset
Delta T [K] added to the standard temperature at every altitude with the
standard pressure kept, so density and speed of sound follow the gas law.

Muzzle spin: by default the rifling twist fixes omega_p0 = 2 pi V_0 / twist,
with the twist (0.5327 m per turn, 26.7 calibres) that turns Table 1's Mach 3 at
the sea-level speed of sound into its 12042 rad/s; or a given spin.

The integration stops at ``t_end`` or when the Mach number falls to 1 (the
normal-shock load model of the thesis has no subsonic branch).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.integrate import quad, solve_ivp

from .._docs import field_docs
from ..errors import InputError, check_range
from ..flow import pressure_force
from ..flow.atmosphere import MAX_ALTITUDE, R_AIR, STANDARD_GRAVITY, standard_atmosphere
from ..model.cases import TABLE1
from .drag import DragModel, drag_model

__all__ = [
    "DEFAULT_ROLL_DAMPING",
    "SEA_LEVEL_SOUND_SPEED",
    "TABLE1_TWIST",
    "Projectile",
    "Launch",
    "Trajectory",
    "air_state",
    "fly",
]

#: Roll-damping coefficient C_lp [-] (McCoy's p d / V form); representative value.
DEFAULT_ROLL_DAMPING = -0.012
#: Speed of sound at sea level in the 1976 standard atmosphere [m/s].
SEA_LEVEL_SOUND_SPEED = math.sqrt(1.4 * R_AIR * 288.15)
#: Rifling twist [m per turn] that gives Table 1's spin at Table 1's Mach 3 at sea level.
TABLE1_TWIST = 2.0 * math.pi * TABLE1["mach"] * SEA_LEVEL_SOUND_SPEED / TABLE1["flight_spin_rate"]
_GAMMA_AIR = 1.4


def air_state(altitude_m: Any, temperature_offset_k: float = 0.0) -> tuple[Any, Any, Any]:
    """Static pressure [Pa], density [kg/m^3] and speed of sound [m/s] of the air.

    Parameters
    ----------
    altitude_m : float or array_like
        Geometric altitude [m]; values below 0 m take the sea-level state.
    temperature_offset_k : float
        Delta T added to the 1976 standard temperature [K] (pressure kept).
    """
    z = np.clip(np.asarray(altitude_m, dtype=float), 0.0, None)
    atm = standard_atmosphere(z if z.ndim else float(z))
    t = np.asarray(atm.temperature) + temperature_offset_k
    p = np.asarray(atm.pressure)
    rho = p / (R_AIR * t)
    a = np.sqrt(_GAMMA_AIR * R_AIR * t)
    if np.ndim(altitude_m) == 0:
        return float(p), float(rho), float(a)
    return p, rho, a


@dataclass(frozen=True)
class Projectile:
    """Mass, size, spin inertia and aerodynamics of the projectile.

    Parameters
    ----------
    mass : float
        m_p [kg] (Table 1: 0.141).
    radius : float
        R_p [m] (Table 1: 9.96e-3); reference area pi R_p^2, diameter 2 R_p.
    length : float
        L_p [m] (Table 1: 76.2e-3; sets the bore L/D for Fanno choking).
    inertia : float
        Axial moment of inertia I_p [kg m^2] (Table 1: 8.58e-6).
    roll_damping : float
        C_lp [-], <= 0 (default -0.012, see the module docstring).
    drag : DragTable or ClosedInletDrag
        C_D(M) referred to pi R_p^2 (default the closed-inlet curve of
        :mod:`obturator.envelope.drag`).
    """

    mass: float = TABLE1["projectile_mass"]
    radius: float = TABLE1["projectile_radius"]
    length: float = TABLE1["projectile_length"]
    inertia: float = TABLE1["projectile_inertia"]
    roll_damping: float = DEFAULT_ROLL_DAMPING
    drag: DragModel = field(default_factory=drag_model)

    def __post_init__(self) -> None:
        check_range("projectile_mass", self.mass, 0.0, lo_open=True, unit="kg")
        check_range("projectile_radius", self.radius, 0.0, 1.0, lo_open=True, unit="m")
        check_range("projectile_length", self.length, 0.0, 10.0, lo_open=True, unit="m")
        check_range("projectile_inertia", self.inertia, 0.0, lo_open=True, unit="kg m^2")
        check_range("roll_damping", self.roll_damping, -1.0, 0.0)

    @property
    def diameter(self) -> float:
        """Reference length d = 2 R_p [m]."""
        return 2.0 * self.radius

    @property
    def area(self) -> float:
        """Reference area S = pi R_p^2 [m^2]."""
        return math.pi * self.radius**2

    def ballistic_k(self, density: float, cd: float) -> float:
        """k = rho S C_D / (2 m_p) [1/m]: flat-fire velocity decay V = V_0 exp(-k x)."""
        return density * self.area * cd / (2.0 * self.mass)


@dataclass(frozen=True)
class Launch:
    """Muzzle-exit conditions.

    Parameters
    ----------
    mach : float
        Muzzle Mach number M_0 (>= 1; the load model needs supersonic flight).
    altitude_m : float
        Launch (muzzle) altitude [m], in [0, 20 000].
    elevation_deg : float
        Elevation of the velocity above the horizontal [deg], in [-90, 90].
    temperature_offset_k : float
        Off-standard temperature Delta T [K], in [-80, 60].
    spin_rate : float or None
        Muzzle spin omega_p0 [rad/s]; None derives it from the twist.
    twist : float
        Rifling twist [m per turn] (default :data:`TABLE1_TWIST`).
    gravity : float
        g [m/s^2], >= 0 (0 for the closed-form checks).
    """

    mach: float = TABLE1["mach"]
    altitude_m: float = 0.0
    elevation_deg: float = 0.0
    temperature_offset_k: float = 0.0
    spin_rate: float | None = None
    twist: float = TABLE1_TWIST
    gravity: float = STANDARD_GRAVITY

    def __post_init__(self) -> None:
        check_range("mach", self.mach, 1.0, 10.0, lo_open=True)
        check_range("altitude_m", self.altitude_m, 0.0, 20_000.0, unit="m")
        check_range("elevation_deg", self.elevation_deg, -90.0, 90.0, unit="deg")
        check_range("temperature_offset_k", self.temperature_offset_k, -80.0, 60.0, unit="K")
        if self.spin_rate is not None:
            check_range("spin_rate", self.spin_rate, 0.0, lo_open=True, unit="rad/s")
        check_range("twist", self.twist, 0.0, lo_open=True, unit="m")
        check_range("gravity", self.gravity, 0.0, 100.0, unit="m/s^2")

    @property
    def sound_speed(self) -> float:
        """Speed of sound at the muzzle [m/s]."""
        return air_state(self.altitude_m, self.temperature_offset_k)[2]

    @property
    def velocity(self) -> float:
        """Muzzle velocity V_0 = M_0 a [m/s]."""
        return self.mach * self.sound_speed

    @property
    def muzzle_spin(self) -> float:
        """omega_p0 [rad/s]: given, or 2 pi V_0 / twist."""
        if self.spin_rate is not None:
            return float(self.spin_rate)
        return 2.0 * math.pi * self.velocity / self.twist


def _rhs(projectile: Projectile, launch: Launch) -> Any:
    s, d, m, ip = projectile.area, projectile.diameter, projectile.mass, projectile.inertia
    clp, g = projectile.roll_damping, launch.gravity
    h0, dt = launch.altitude_m, launch.temperature_offset_k
    drag = projectile.drag

    def f(_t: float, y: np.ndarray) -> np.ndarray:
        _, rho, a = air_state(h0 + y[1], dt)
        v = math.hypot(y[2], y[3])
        c = rho * s * drag(v / a) * v / (2.0 * m)
        return np.array(
            [y[2], y[3], -c * y[2], -c * y[3] - g, 0.5 * rho * v * s * d * d * clp * y[4] / ip]
        )

    return f


@field_docs
@dataclass(frozen=True)
class Trajectory:
    """A computed flight; every method takes times [s] from muzzle exit."""

    #: The projectile flown (mass, size, spin inertia, aerodynamics).
    projectile: Projectile
    #: Its muzzle-exit conditions.
    launch: Launch
    #: Last time covered [s] (earlier than requested if the flight went subsonic).
    t_end: float
    #: True if the Mach number fell to 1 at ``t_end``.
    subsonic: bool
    #: Right-hand-side evaluations.
    nfev: int
    #: Dense output of the integration (SciPy ``OdeSolution``): state [x, z, u, w, omega_p] at
    #: times in [0, t_end] (private).
    _sol: Any = field(repr=False)
    #: Segment tables already computed by :meth:`segment_loads`, by argument set (private).
    _cache: dict[Any, Any] = field(default_factory=dict, repr=False, compare=False)

    def _y(self, t: Any) -> np.ndarray:
        tt = np.asarray(t, dtype=float)
        if np.any(tt < 0.0) or np.any(tt > self.t_end * (1.0 + 1e-12)):
            raise InputError("t", f"outside the computed flight [0, {self.t_end:g}] s")
        return self._sol(np.clip(tt, 0.0, self.t_end))

    def state(self, t: Any) -> np.ndarray:
        """[x, z, u, w, omega_p] (range, height [m], velocity [m/s], spin [rad/s])."""
        return self._y(t)

    def altitude(self, t: Any) -> Any:
        """Geometric altitude [m] (launch altitude + height gained)."""
        return self.launch.altitude_m + self._y(t)[1]

    def velocity(self, t: Any) -> Any:
        """Flight speed V [m/s]."""
        y = self._y(t)
        return np.hypot(y[2], y[3])

    def air(self, t: Any) -> tuple[Any, Any, Any]:
        """Free-stream pressure [Pa], density [kg/m^3], speed of sound [m/s]."""
        return air_state(self.altitude(t), self.launch.temperature_offset_k)

    def mach(self, t: Any) -> Any:
        """Flight Mach number [-]."""
        return self.velocity(t) / self.air(t)[2]

    def spin_rate(self, t: Any) -> Any:
        """Projectile spin omega_p [rad/s]."""
        return self._y(t)[4]

    def pressure_force(self, t: Any, bore_radius: float, gamma: float = 1.4) -> Any:
        """Normal-shock load F_p = pi r_p^2 (P_2 - P_1) on the closed obturator [N] (Eq. 43)."""
        return pressure_force(self.mach(t), self.air(t)[0], bore_radius, gamma)

    def segment_loads(
        self, segment: float, t_end: float, bore_radius: float, gamma: float = 1.4
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Mid-segment flight values for a partition of [0, t_end] into segments.

        Parameters
        ----------
        segment : float
            Segment length Delta [s]; the last segment may be shorter.
        t_end : float
            End of the partition [s] (at most :attr:`t_end`).
        bore_radius : float
            r_p [m] for F_p.
        gamma : float
            Ratio of specific heats [-].

        Returns
        -------
        (start, length, mach, force, spin) : tuple of ndarray
            Segment start times and lengths [s], Mach number [-], F_p [N] (NaN
            where M <= 1) and omega_p [rad/s] at the segment midpoints.
            Computed once per argument set and kept (vectorised queries).
        """
        key = (float(segment), float(t_end), float(bore_radius), float(gamma))
        hit = self._cache.get(key)
        if hit is not None:
            return hit
        n = max(1, math.ceil(t_end / segment * (1.0 - 1e-12)))
        start = np.arange(n) * segment
        length = np.minimum(segment, t_end - start)
        mid = start + 0.5 * length
        y = self._y(mid)
        p, _, a = air_state(self.launch.altitude_m + y[1], self.launch.temperature_offset_k)
        mach = np.hypot(y[2], y[3]) / a
        sup = mach > 1.0
        force = np.full(n, np.nan)
        if sup.any():
            force[sup] = pressure_force(mach[sup], np.asarray(p)[sup], bore_radius, gamma)
        out = (start, length, mach, force, y[4])
        self._cache[key] = out
        return out

    def energy(self, t: Any) -> Any:
        """Mechanical energy (1/2) m_p V^2 + m_p g z [J] (z: height gained)."""
        y = self._y(t)
        m = self.projectile.mass
        return 0.5 * m * (y[2] ** 2 + y[3] ** 2) + m * self.launch.gravity * y[1]

    def drag_power(self, t: float) -> float:
        """Power of the drag force D V = (1/2) rho V^3 S C_D [W]."""
        v = float(self.velocity(t))
        _, rho, a = self.air(t)
        return 0.5 * rho * v**3 * self.projectile.area * self.projectile.drag(v / a)

    def drag_work(self, t: float) -> float:
        """Work done against drag from 0 to `t` [J], by adaptive quadrature of D V."""
        val, _ = quad(self.drag_power, 0.0, float(t), epsabs=0.0, epsrel=1e-11, limit=200)
        return float(val)

    def to_xarray(self, n: int = 201) -> Any:
        """The flight sampled at `n` times as an :class:`xarray.Dataset`."""
        import xarray as xr

        t = np.linspace(0.0, self.t_end, int(n))
        y = self._y(t)
        p, rho, _ = self.air(t)
        data = {
            "x": ("t", y[0], {"units": "m", "long_name": "range"}),
            "height": ("t", y[1], {"units": "m", "long_name": "height above the muzzle"}),
            "velocity": ("t", np.hypot(y[2], y[3]), {"units": "m/s"}),
            "mach": ("t", self.mach(t), {"units": "1"}),
            "pressure": ("t", p, {"units": "Pa", "long_name": "free-stream static pressure P_1"}),
            "density": ("t", rho, {"units": "kg/m^3"}),
            "spin_rate": ("t", y[4], {"units": "rad/s", "long_name": "projectile spin omega_p"}),
        }
        attrs = {
            "muzzle_mach": self.launch.mach,
            "launch_altitude_m": self.launch.altitude_m,
            "elevation_deg": self.launch.elevation_deg,
            "temperature_offset_k": self.launch.temperature_offset_k,
            "muzzle_spin_rad_s": self.launch.muzzle_spin,
            "roll_damping_clp": self.projectile.roll_damping,
            "drag_model": getattr(self.projectile.drag, "name", "table"),
            "subsonic_at_end": int(self.subsonic),
        }
        return xr.Dataset(data, coords={"t": ("t", t, {"units": "s"})}, attrs=attrs)


def fly(
    projectile: Projectile | None = None,
    launch: Launch | None = None,
    t_end: float = 1.0,
    *,
    rtol: float = 1e-10,
    atol: float = 1e-9,
) -> Trajectory:
    """Integrate the point-mass trajectory from muzzle exit.

    Parameters
    ----------
    projectile : Projectile, optional
        Table 1 projectile by default.
    launch : Launch, optional
        Table 1 flight condition (Mach 3, sea level, horizontal) by default.
    t_end : float
        Flight time to cover [s], in (0, 100].
    rtol, atol : float
        Tolerances of the DOP853 integration (atol in m, m/s, rad/s).

    Returns
    -------
    Trajectory
        Dense (continuous) solution; stops early at Mach 1.
    """
    projectile = projectile or Projectile()
    launch = launch or Launch()
    t_end = check_range("t_end", t_end, 0.0, 100.0, lo_open=True, unit="s")
    v0 = launch.velocity
    e = math.radians(launch.elevation_deg)
    y0 = np.array([0.0, 0.0, v0 * math.cos(e), v0 * math.sin(e), launch.muzzle_spin])
    h0, dt = launch.altitude_m, launch.temperature_offset_k

    def sonic(_t: float, y: np.ndarray) -> float:
        return math.hypot(y[2], y[3]) / air_state(h0 + y[1], dt)[2] - 1.0

    def ceiling(_t: float, y: np.ndarray) -> float:
        return MAX_ALTITUDE - (h0 + y[1])

    sonic.terminal = True  # type: ignore[attr-defined]
    sonic.direction = -1  # type: ignore[attr-defined]
    ceiling.terminal = True  # type: ignore[attr-defined]
    sol = solve_ivp(
        _rhs(projectile, launch),
        (0.0, t_end),
        y0,
        method="DOP853",
        rtol=rtol,
        atol=atol,
        dense_output=True,
        events=(sonic, ceiling),
    )
    if sol.status < 0:  # pragma: no cover - defensive
        raise RuntimeError(f"trajectory integration failed: {sol.message}")
    subsonic = bool(sol.t_events[0].size)
    if sol.t_events[1].size:
        raise InputError("t_end", "the trajectory leaves the 1976 atmosphere model (86 km)")
    return Trajectory(projectile, launch, float(sol.t[-1]), subsonic, int(sol.nfev), sol.sol)
