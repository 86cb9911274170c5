"""Open area of the passage through the tilted bored ball (thesis Fig. 11, Table 1 geometry).

The ball (radius R_s, centred at the origin) carries a diametral hole of radius
r_s along its body axis e; the projectile's bore (radius r_p) runs along the
spin axis Z, and e is tilted from Z by the nutation angle theta. The solid is
the sphere minus the infinite cylinder of the hole.

**Open area** A(theta) is the projected area, on a plane normal to Z and
inside the bore circle, of the straight lines parallel to Z that cross the
ball without touching the solid: the cross-section of the stream tube that
passes the ball without turning, and the area of the light seen through it
(the rig's laser and the range camera of chapter III see exactly this set).

Derivation. A line p + s Z with |p| < r_p cuts the sphere on s in [-h, h],
h = sqrt(R_s^2 - |p|^2). Its squared distance from the hole axis is a convex
quadratic in s, so the line stays inside the hole on the whole chord if and
only if both chord ends do, i.e. both lie on the hole's mouths, the spherical
caps |u . e| >= c with c = sqrt(R_s^2 - r_s^2) = R_s cos(beta_s). With
e = (sin theta, 0, cos theta) and r_p < c (the entry and exit cannot lie on the
same mouth), this is h cos(theta) - |x| sin(theta) >= c, which squared is

    (|x| + c sin theta)^2 / cos^2 theta + y^2 <= r_s^2,

the projections along Z of the two mouth circles: ellipses with semi-axes
r_s cos(theta) and r_s centred at x = -/+ c sin(theta). The open set is their
lens, cut by the bore circle. Scaling x by 1/cos(theta) turns the lens into
that of two circles of radius r_s whose centres are 2 c tan(theta) apart:

    A(theta) = 2 r_s^2 cos(theta) [acos k - k sqrt(1 - k^2)],
    k = tan(theta) / tan(beta_s),

for r_p >= r_s (the lens lies inside the circle of radius r_s, so the bore
cuts nothing). For r_p < r_s the bore circle cuts the lens and A is a
quadrature of the lens half-width clipped by the bore (scipy ``quad`` with the
crossings as break points, converged to 1e-12 relative).

Closed-form checks: A(0) = pi min(r_s, r_p)^2 (the aligned bore); A = 0 for
theta >= beta_s = asin(r_s/R_s) (k >= 1: the mouth projections no longer
overlap); A falls monotonically in between because the lens at a larger
theta lies inside the lens at a smaller one (for x >= 0 the left side of the
inequality grows with theta).

**Throat.** The minimum section of the straight-through stream tube is the
lens itself, bounded by the upstream mouth on one side and the downstream
mouth on the other (the hole's wall between them lies outside the lens, by
the convexity above). First light passes at the bore axis (x = y = 0) at
theta = beta_s, and the lens grows about it. A flow that turns through the
tilted hole can use the larger windows where each mouth overlaps the bore
(:func:`turned_open_area`, open from theta = beta_s + asin(r_p/R_s) on): the
projection along Z of the mouth, the ellipse of semi-axes r_s cos(theta) and r_s
centred at x = c sin(theta), cut by the bore circle. The start criterion
(:mod:`obturator.model.start`) takes the lens as the nominal throat A_t (a started
supersonic stream turned by theta exceeds the largest deflection of an attached
oblique shock and detaches it again) and the window as the early bound: the
turned flow starts the tube sooner. Neither is a conservative choice on its own:
wall friction between lip and ball and the lens's discharge coefficient delay the
start (:mod:`obturator.flow.start_friction`, the late bound).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError, check_range

__all__ = [
    "open_area",
    "open_area_fraction",
    "open_angle",
    "open_area_ray_count",
    "ring_contact_fraction",
    "turned_open_area",
    "turned_open_angle",
]


def _geometry(
    ball_radius: float, hole_radius: float, bore_radius: float
) -> tuple[float, float, float, float]:
    big = check_range("ball_radius", ball_radius, 0.0, math.inf, lo_open=True, unit="m")
    r_s = check_range("hole_radius", hole_radius, 0.0, big, lo_open=True, hi_open=True, unit="m")
    c = math.sqrt(big * big - r_s * r_s)
    r_p = check_range("bore_radius", bore_radius, 0.0, math.inf, lo_open=True, unit="m")
    if r_p >= c:
        raise InputError(
            "bore_radius",
            f"{r_p:g} m is outside the allowed range (0, sqrt(R_s^2 - r_s^2)) = (0, {c:g}) m "
            "(a wider bore sees past the ball's rim)",
        )
    return big, r_s, r_p, c


def _theta(theta: float) -> float:
    return math.radians(
        check_range("theta", math.degrees(theta), 0.0, 90.0, hi_open=True, unit="deg")
    )


def _lens_area(theta: float, r_s: float, c: float) -> float:
    k = c * math.tan(theta) / r_s  # = tan(theta) / tan(beta_s)
    if k >= 1.0:
        return 0.0
    return 2.0 * r_s * r_s * math.cos(theta) * (math.acos(k) - k * math.sqrt(1.0 - k * k))


def _clipped_lens_area(theta: float, r_s: float, r_p: float, c: float) -> float:
    from scipy.integrate import quad  # on use: kept out of start-up (docs/benchmarks.md)

    cos_t, sin_t = math.cos(theta), math.sin(theta)
    d = c * sin_t
    x_end = min(r_s * cos_t - d, r_p)  # lens half-width R_s sin(beta_s - theta), or the bore
    if x_end <= 0.0:
        return 0.0

    def half_width(x: float) -> float:
        lens = r_s * r_s - ((x + d) / cos_t) ** 2
        bore = r_p * r_p - x * x
        return math.sqrt(max(0.0, min(lens, bore)))

    # crossings of lens and bore boundary: x^2 sin^2 + 2 d x + d^2 - (r_s^2 - r_p^2) cos^2 = 0
    qa, qb = sin_t * sin_t, 2.0 * d
    qc = d * d - (r_s * r_s - r_p * r_p) * cos_t * cos_t
    disc = qb * qb - 4.0 * qa * qc
    roots: list[float] = []
    if disc >= 0.0:
        q = -0.5 * (qb + math.sqrt(disc))  # stable for qa -> 0 (theta -> 0)
        roots = [qc / q] if q != 0.0 else []
        if qa > 0.0 and q != 0.0:
            roots.append(q / qa)
    points = sorted(x for x in roots if 0.0 < x < x_end)
    value, _ = quad(
        half_width, 0.0, x_end, points=points or None, epsabs=0.0, epsrel=1e-12, limit=200
    )
    return 4.0 * value


def open_area(theta: float, ball_radius: float, hole_radius: float, bore_radius: float) -> float:
    """Open area A(theta) of the straight passage through the tilted ball [m^2].

    Parameters
    ----------
    theta : float
        Nutation angle theta [rad], in [0, pi/2).
    ball_radius : float
        R_s [m].
    hole_radius : float
        r_s [m], in (0, R_s).
    bore_radius : float
        Projectile bore r_p [m], in (0, sqrt(R_s^2 - r_s^2)).

    Returns
    -------
    float
        A [m^2]: pi min(r_s, r_p)^2 at theta = 0, 0 from theta = beta_s on.
    """
    _, r_s, r_p, c = _geometry(ball_radius, hole_radius, bore_radius)
    t = _theta(theta)
    if r_p >= r_s:
        return _lens_area(t, r_s, c)
    return _clipped_lens_area(t, r_s, r_p, c)


def open_area_fraction(
    theta: float, ball_radius: float, hole_radius: float, bore_radius: float
) -> float:
    """A(theta) / (pi r_p^2): the open share of the bore [-]."""
    return open_area(theta, ball_radius, hole_radius, bore_radius) / (math.pi * bore_radius**2)


def open_angle(area: float, ball_radius: float, hole_radius: float, bore_radius: float) -> float:
    """The angle theta [rad] at which the open area reaches ``area`` (inverse of :func:`open_area`).

    Parameters
    ----------
    area : float
        Open area [m^2], in [0, A(0)] with A(0) = pi min(r_s, r_p)^2.
    ball_radius, hole_radius, bore_radius : float
        R_s, r_s, r_p [m] as in :func:`open_area`.

    Returns
    -------
    float
        theta in [0, beta_s] [rad]; beta_s for ``area`` = 0, 0 for the full area.
    """
    from scipy.optimize import brentq

    big, r_s, r_p, _ = _geometry(ball_radius, hole_radius, bore_radius)
    full = math.pi * min(r_s, r_p) ** 2
    a = check_range("area", area, 0.0, full * (1.0 + 1e-12), unit="m^2")
    beta = math.asin(r_s / big)
    if a <= 0.0:
        return beta
    if a >= full:
        return 0.0
    return brentq(
        lambda t: open_area(t, big, r_s, r_p) - a,
        0.0,
        beta,
        xtol=1e-15,
        rtol=4 * np.finfo(float).eps,
    )


def open_area_ray_count(
    theta: float,
    ball_radius: float,
    hole_radius: float,
    bore_radius: float,
    *,
    rays: int = 1_000_000,
    seed: int = 0,
    chunk: int = 2_000_000,
) -> tuple[float, float]:
    """Monte Carlo estimate of :func:`open_area` by tracing rays through the solid ball.

    Independent of the lens construction: rays parallel to Z start at points
    drawn uniformly in the bore circle; each is intersected with the sphere
    (chord s in [-h, h]) and with the hole's infinite cylinder (the interval
    where the squared distance from the axis, a quadratic in s, is <= r_s^2);
    a ray is clear if the chord lies inside the cylinder's interval.

    Parameters
    ----------
    theta : float
        Nutation angle [rad].
    ball_radius, hole_radius, bore_radius : float
        R_s, r_s, r_p [m].
    rays : int
        Number of rays, >= 1.
    seed : int
        numpy ``default_rng`` seed.
    chunk : int
        Rays per vectorised batch (memory bound).

    Returns
    -------
    (float, float)
        Estimated area [m^2] and its standard error [m^2].
    """
    big, r_s, r_p, _ = _geometry(ball_radius, hole_radius, bore_radius)
    t = _theta(theta)
    n = int(check_range("rays", rays, 1, 1e10))
    rng = np.random.default_rng(seed)
    e = np.array([math.sin(t), 0.0, math.cos(t)])
    clear = 0
    done = 0
    while done < n:
        m = min(chunk, n - done)
        rad = r_p * np.sqrt(rng.random(m))
        phi = 2.0 * math.pi * rng.random(m)
        x, y = rad * np.cos(phi), rad * np.sin(phi)
        h = np.sqrt(big * big - rad * rad)
        # |p + s Z|^2 - ((p + s Z).e)^2 <= r_s^2  ->  qa s^2 + qb s + qc <= 0
        pe = x * e[0] + y * e[1]
        qa = 1.0 - e[2] * e[2]
        qb = -2.0 * pe * e[2]
        qc = rad * rad - pe * pe - r_s * r_s
        if qa < 1e-300:  # aligned: the distance does not change along the ray
            ok = qc <= 0.0
        else:
            disc = qb * qb - 4.0 * qa * qc
            root = np.sqrt(np.maximum(disc, 0.0))
            s_lo, s_hi = (-qb - root) / (2.0 * qa), (-qb + root) / (2.0 * qa)
            ok = (disc >= 0.0) & (s_lo <= -h) & (s_hi >= h)
        clear += int(np.count_nonzero(ok))
        done += m
    full = math.pi * r_p * r_p
    p = clear / n
    return full * p, full * math.sqrt(max(p * (1.0 - p), 1.0 / n) / n)


def ring_contact_fraction(
    theta: float, ball_radius: float, hole_radius: float, bore_radius: float
) -> float:
    """Share of the seat ring (Eq. 47's circle of contact) still backed by ball material [-].

    The ring is where the bore meets the socket: points at angle
    beta_p = asin(r_p/R_s) from Z. A ring point at azimuth gamma (from the
    tilt plane) lies over the upstream mouth when its angle from e is below
    beta_s, i.e. cos(gamma) >= q with
    q = (cos beta_s - cos beta_p cos theta) / (sin beta_p sin theta).
    The fraction is 1 - acos(q)/pi for |q| < 1. For r_p = r_s it is
    1 down to theta = 2 beta_s, 0.65 at first light (theta = beta_s) and
    tends to 1/2 as theta -> 0: the thesis's two diametral contacts (Eq. 47)
    keep at least half of the ring to sit on.

    Parameters
    ----------
    theta : float
        Nutation angle [rad], in (0, pi/2).
    ball_radius, hole_radius, bore_radius : float
        R_s, r_s, r_p [m].

    Returns
    -------
    float
        In [0, 1].
    """
    big, r_s, r_p, _ = _geometry(ball_radius, hole_radius, bore_radius)
    t = _theta(theta)
    if t == 0.0:
        return 0.5 if r_p == r_s else (1.0 if r_p > r_s else 0.0)
    cos_bs = math.sqrt(1.0 - (r_s / big) ** 2)
    sin_bp = r_p / big
    cos_bp = math.sqrt(1.0 - sin_bp * sin_bp)
    q = (cos_bs - cos_bp * math.cos(t)) / (sin_bp * math.sin(t))
    if q >= 1.0:
        return 1.0
    if q <= -1.0:
        return 0.0
    return 1.0 - math.acos(q) / math.pi


def turned_open_area(
    theta: float, ball_radius: float, hole_radius: float, bore_radius: float
) -> float:
    """Window of one mouth onto the bore, the throat of the flow turned through the hole [m^2].

    The area, projected along Z, of the bore circle (radius r_p) that opens into the
    upstream mouth: the overlap of that circle with the ellipse
    ((x - c sin theta) / cos theta)^2 + y^2 <= r_s^2 (the mouth circle seen along Z,
    c = sqrt(R_s^2 - r_s^2)); the downstream window is its mirror image. Both
    intervals in y are centred on y = 0, so the overlap's half-width is the smaller of
    the two half-widths, the circle's sqrt(r_p^2 - x^2) or the ellipse's
    sqrt(r_s^2 - u^2) with u = (x - c sin theta) / cos theta. Between the crossings of
    the two boundaries the smaller one is integrated in closed form
    (:func:`_segment`). Written out, not left to adaptive quadrature: a study asks for
    thousands of start conditions, and the quadrature inside the inverse
    (:func:`turned_open_angle`) was the larger part of each
    (``tests/model/test_start.py`` checks it against scipy's ``quad``).

    Parameters
    ----------
    theta : float
        Nutation angle [rad], in [0, pi/2).
    ball_radius, hole_radius, bore_radius : float
        R_s, r_s, r_p [m] as in :func:`open_area`.

    Returns
    -------
    float
        Window [m^2]: pi min(r_s, r_p)^2 at theta = 0, at least :func:`open_area`, 0 from
        theta = beta_s + asin(r_p/R_s) on.
    """
    big, r_s, r_p, c = _geometry(ball_radius, hole_radius, bore_radius)
    t = _theta(theta)
    cos_t, sin_t = math.cos(t), math.sin(t)
    d = c * sin_t
    left, right = d - r_s * cos_t, d + r_s * cos_t  # the ellipse's ends in x
    lo, hi = max(-r_p, left), min(r_p, right)
    if hi <= lo:
        return 0.0
    # crossings of the two boundaries: x^2 sin^2 - 2 d x + d^2 - (r_s^2 - r_p^2) cos^2 = 0
    qa, qb, qc = sin_t * sin_t, -2.0 * d, d * d - (r_s * r_s - r_p * r_p) * cos_t * cos_t
    edges = [lo, hi]
    if qa > 0.0:
        disc = qb * qb - 4.0 * qa * qc
        if disc >= 0.0:
            root = math.sqrt(disc)
            edges += [x for x in ((-qb - root) / (2 * qa), (-qb + root) / (2 * qa)) if lo < x < hi]
    edges.sort()
    value = 0.0
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        mid = 0.5 * (a + b)
        if r_s * r_s - ((mid - d) / cos_t) ** 2 <= r_p * r_p - mid * mid:  # the ellipse's
            ends = (
                (a - left) / cos_t,
                (b - left) / cos_t,
                (right - a) / cos_t,
                (right - b) / cos_t,
            )
            value += cos_t * _segment(r_s, *ends)
        else:
            value += _segment(r_p, a + r_p, b + r_p, r_p - a, r_p - b)
    return min(2.0 * value, math.pi * min(r_s, r_p) ** 2)


def _segment(radius: float, va: float, vb: float, wa: float, wb: float) -> float:
    """Integral of sqrt(radius^2 - u^2) du between two points a < b of [-radius, radius],
    given by their distances from the ends: v = u + radius, w = radius - u.

    From the nearer end: the area from an end to a point at distance v is
    radius^2 (phi - sin phi cos phi) / 2 with phi = 2 asin(sqrt(v / (2 radius))), the
    bracket by its series where phi is small. A sliver at an end (where the window opens
    or closes) is thus as accurate as a wide band; differences of the primitive
    (u sqrt(radius^2 - u^2) + radius^2 asin(u / radius)) / 2 lose it to rounding there.
    """
    r2 = 0.5 * radius * radius

    def from_end(dist: float) -> float:
        ratio = min(max(dist, 0.0) / (2.0 * radius), 1.0)
        phi = 2.0 * math.asin(math.sqrt(ratio))
        if phi < 0.25:  # phi - sin(phi) cos(phi) = (x - sin x) / 2, x = 2 phi
            x = 2.0 * phi
            x2, term, total = x * x, x * x * x / 6.0, 0.0
            for k in range(1, 9):
                total += term
                term *= -x2 / ((2 * k + 2) * (2 * k + 3))
            return r2 * 0.5 * total
        return r2 * (phi - math.sin(phi) * math.cos(phi))

    if vb <= radius:  # both points in the left half
        return from_end(vb) - from_end(va)
    if va >= radius:  # both in the right half
        return from_end(wa) - from_end(wb)
    return (math.pi * r2 - from_end(wb)) - from_end(va)


def turned_open_angle(
    area: float, ball_radius: float, hole_radius: float, bore_radius: float
) -> float:
    """The angle theta [rad] at which :func:`turned_open_area` reaches ``area`` (its inverse).

    Parameters
    ----------
    area : float
        Window [m^2], in [0, pi min(r_s, r_p)^2].
    ball_radius, hole_radius, bore_radius : float
        R_s, r_s, r_p [m].

    Returns
    -------
    float
        theta in [0, beta_s + asin(r_p/R_s)] [rad].
    """
    from scipy.optimize import brentq

    big, r_s, r_p, _ = _geometry(ball_radius, hole_radius, bore_radius)
    full = math.pi * min(r_s, r_p) ** 2
    a = check_range("area", area, 0.0, full * (1.0 + 1e-12), unit="m^2")
    end = min(math.asin(r_s / big) + math.asin(r_p / big), math.radians(89.999))
    if a <= 0.0:
        return end
    if a >= full:
        return 0.0
    return brentq(
        lambda t: turned_open_area(t, big, r_s, r_p) - a,
        0.0,
        end,
        xtol=1e-15,
        rtol=4 * np.finfo(float).eps,
    )
