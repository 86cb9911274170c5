"""Envelope following over the ball's revolutions at high spin: what it would save.

``python -m benchmarks.envelope_following [--spins 700,1000] [--time-scales] [--json FILE]``

Above ~220 rad/s the rig's ball slips without sticking; a point integrates every
revolution of the ball with the socket (75 at 700 rad/s, 150 at 1000 rad/s) to follow a
slow drift of theta down to theta_cr. At constant spin the equations are autonomous and
invariant under turning the ball about its own axis, so the state at the sections
psi = 0 (mod 2 pi) of the hole axis's azimuth, reduced to theta and the ball's rate in
the frame of the line of nodes, the hole axis and their normal, is a sequence x_n with a
first-return map x_{n+1} = P(x_n), and the section times t_n follow it. Envelope
following (Petzold, SIAM J. Sci. Stat. Comput. 2, 1981; Gear and Gallivan) integrates a
few revolutions and extrapolates the smooth sequence (x_n, t_n) over many.

Measured here, with the package's compiled right-hand side (regularised law at the
default width) under scipy's DOP853 at rtol 1e-10 (a tool to count, not the package's
integrator):

* the sequence's smoothness: the largest scaled sixth difference over the second half of
  the revolutions (what bounds a degree-5 extrapolation);
* the extrapolation's own error: from pairs of revolutions (n, n + 1) spaced H apart, K
  pairs, a degree 2K - 1 polynomial extrapolated H revolutions ahead, against the
  integrated section (median and largest over the run, scaled by omega_p for rates);
* the whole strategy: revolutions integrated from extrapolated states, step H adapted
  to the difference of the degree 2K - 1 and 2K - 2 extrapolations, the last
  revolutions integrated with the opening event, against a reference at rtol 1e-12:
  the t_cr error and the evaluations saved.

With ``--time-scales`` (:func:`time_scales`, :func:`per_revolution`), why it saves so
little: the time scales of an opening (the socket's revolutions to t_cr; the ball's turns
relative to its socket, one about every eight revolutions, which modulate the drift of
theta that an extrapolation over revolutions would have to follow; the dip of the
moment arm twice a revolution), and what a revolution costs when every one is integrated
(the package's DOP853 at looser tolerances and with no step limit): the floor that a
strategy which integrates revolutions has to divide.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

MU_S = 0.5473
Z = np.array([0.0, 0.0, 1.0])
P = np.polynomial.polynomial


def _rotation(y: np.ndarray) -> np.ndarray:
    q0, q1, q2, q3 = y[:4] / np.linalg.norm(y[:4])
    return np.array(
        [
            [1 - 2 * (q2 * q2 + q3 * q3), 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
            [2 * (q1 * q2 + q0 * q3), 1 - 2 * (q1 * q1 + q3 * q3), 2 * (q2 * q3 - q0 * q1)],
            [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), 1 - 2 * (q1 * q1 + q2 * q2)],
        ]
    )


def _nodal_frame(z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    n = np.cross(Z, z)
    n /= np.linalg.norm(n)
    return n, np.cross(z, n)


def reduced(y: np.ndarray) -> np.ndarray:
    """(theta [rad], the ball's inertial rate along the line of nodes, along z x nodes,
    along the hole axis z [rad/s]) of a quaternion-form state."""
    r = _rotation(y)
    z = r[:, 2]
    n, e2 = _nodal_frame(z)
    om = r @ y[4:7]
    return np.array([math.atan2(math.hypot(z[0], z[1]), z[2]), om @ n, om @ e2, om @ z])


def state(x: np.ndarray, spin: float) -> np.ndarray:
    """The state at psi = 0, phi = 0 whose reduced form is `x` (the inverse of
    :func:`reduced` on the section)."""
    th = x[0]
    q = np.array([math.cos(th / 2), math.sin(th / 2), 0.0, 0.0])
    r = _rotation(np.r_[q, np.zeros(4)])
    n, e2 = _nodal_frame(r[:, 2])
    om = x[1] * n + x[2] * e2 + x[3] * r[:, 2]
    return np.r_[q, r.T @ om, spin]


class Revolutions:
    """One rig point's revolutions under scipy's DOP853, counting evaluations."""

    def __init__(self, spin: float, rtol: float) -> None:
        from obturator.core.dynamics import rhs
        from obturator.core.layout import P_THETA_CR
        from obturator.model.cases import rig_case
        from obturator.solve import SolverOptions, integration_setup

        problem, _ = integration_setup(rig_case(spin, MU_S), SolverOptions(method="regularised"))
        self.p, self.y0 = problem.p.copy(), problem.y0.copy()
        self.theta_cr = float(self.p[P_THETA_CR])
        self.spin = float(self.y0[7])
        self.rtol = rtol
        self.nfev = 0
        self._rhs, self._dy = rhs, np.empty(8)

    def _f(self, t: float, y: np.ndarray) -> np.ndarray:
        self.nfev += 1
        self._rhs(t, y, self.p, self._dy)
        return self._dy.copy()

    def one(self, t0: float, y0: np.ndarray) -> tuple[float, np.ndarray | None]:
        """To the next section psi = 0 (mod 2 pi) after t0, or to the opening (state
        None)."""
        from scipy.integrate import solve_ivp

        def section(t, y):
            return _rotation(y)[0, 2]  # z_X = sin(theta) sin(psi)

        section.direction = 1.0

        def opening(t, y):
            return reduced(y)[0] - self.theta_cr

        opening.terminal, opening.direction = True, -1.0
        period = 2.0 * math.pi / self.spin
        atol = self.rtol * 1e-2 * np.r_[1, 1, 1, 1, self.spin, self.spin, self.spin, self.spin]
        sol = solve_ivp(self._f, (t0, t0 + 3 * period), y0, method="DOP853", rtol=self.rtol,
                        atol=atol, events=[section, opening])  # fmt: skip
        if len(sol.t_events[1]):
            return float(sol.t_events[1][0]), None
        i = next(i for i, t in enumerate(sol.t_events[0]) if t > t0 + 0.5 * period)
        return float(sol.t_events[0][i]), sol.y_events[0][i]

    def all(self) -> tuple[float, np.ndarray]:
        """t_cr [s] and the sections (t_n, x_n) of the whole run."""
        t, y, rows = 0.0, self.y0, [np.r_[0.0, reduced(self.y0)]]
        while True:
            t, y = self.one(t, y)
            if y is None:
                return t, np.array(rows)
            rows.append(np.r_[t, reduced(y)])


def extrapolation_errors(rows: np.ndarray, spin: float, k: int, h: int) -> tuple[float, float]:
    """Median and largest scaled error of the degree 2k - 1 extrapolation from k pairs
    spaced `h` apart, `h` revolutions ahead, over the run."""
    scale = np.r_[1.0, 1.0, spin, spin, spin]
    errs = []
    for n0 in range(2 * h, rows.shape[0] - h - 1):
        nodes = [m for j in range(k - 1, -1, -1) for m in (n0 - j * h, n0 - j * h + 1)]
        if nodes[0] < 1:
            continue
        n = np.array(nodes, float)
        c = P.polyfit((n - n[-1]) / (n[-1] - n[0]), rows[nodes], 2 * k - 1)
        x = P.polyval((n0 + h - n[-1]) / (n[-1] - n[0]), c)
        errs.append(np.max(np.abs(x - rows[n0 + h]) / scale))
    return float(np.median(errs)), float(np.max(errs))


def envelope(spin: float, tol: float, k: int, rtol: float = 1e-10) -> dict[str, float]:
    """The strategy of the module docstring: t_cr [s], evaluations, jumps."""
    run = Revolutions(spin, rtol)
    scale = np.r_[1.0, 1.0, run.spin, run.spin, run.spin]
    t, y = 0.0, run.y0
    ns: list[float] = []
    xs: list[np.ndarray] = []

    def integrate_one() -> bool:
        nonlocal t, y
        t, y = run.one(t, y)
        if y is None:
            return True
        ns.append((ns[-1] if ns else 0.0) + 1.0)
        xs.append(np.r_[t, reduced(y)])
        return False

    for _ in range(2 * k):  # start-up: consecutive revolutions
        if integrate_one():
            return {"t_cr": t, "nfev": run.nfev, "jumps": 0}
    h, jumps = 2.0, 0
    while True:
        n, x = np.array(ns[-2 * k :]), np.array(xs[-2 * k :])
        span = max(1.0, n[-1] - n[0])
        at = (h) / span
        hi = P.polyval(at, P.polyfit((n - n[-1]) / span, x, 2 * k - 1))
        lo = P.polyval(at, P.polyfit((n - n[-1]) / span, x, 2 * k - 2))
        err = float(np.max(np.abs(hi - lo) / scale))
        near = hi[1] + 3.0 * abs(x[-1, 1] - x[-2, 1]) < run.theta_cr
        if near or err > tol:
            if not near and h > 1.0:
                h = max(1.0, float(int(h / 2)))
                continue
            if integrate_one():
                return {"t_cr": t, "nfev": run.nfev, "jumps": jumps}
            continue
        ns.append(ns[-1] + h)
        xs.append(hi)
        jumps += 1
        t, y = float(hi[0]), state(hi[1:], run.spin)
        if integrate_one():
            return {"t_cr": t, "nfev": run.nfev, "jumps": jumps}
        grow = min(2.0, 0.8 * (tol / max(err, 1e-300)) ** (1.0 / (2 * k)))
        h = max(1.0, float(int(h * grow)))


def study(spin: float, tols: tuple[float, ...], pairs: tuple[int, ...]) -> dict[str, Any]:
    """Everything the module docstring lists, for one spin [rad/s]."""
    ref = Revolutions(spin, 1e-12)
    t_ref, _ = ref.all()
    full = Revolutions(spin, 1e-10)
    t_full, rows = full.all()
    scale = np.r_[1.0, 1.0, spin, spin, spin]
    late = rows[rows.shape[0] // 2 :]
    d6 = np.max(np.abs(np.diff(late, n=6, axis=0)) / scale) if late.shape[0] > 6 else math.nan
    rec: dict[str, Any] = {
        "spin_rad_s": spin,
        "t_cr_reference_s": t_ref,
        "revolutions": int(rows.shape[0] - 1),
        "full": {"nfev": full.nfev, "rel_error": (t_full - t_ref) / t_ref},
        "sixth_difference_late": float(d6),
        "extrapolation": [],
        "envelope": [],
    }
    for k in pairs:
        for h in (2, 4, 8, 16):
            med, big = extrapolation_errors(rows, spin, k, h)
            rec["extrapolation"].append({"pairs": k, "H": h, "median": med, "largest": big})
        for tol in tols:
            e = envelope(spin, tol, k)
            rec["envelope"].append(
                {"pairs": k, "tol": tol, "jumps": e["jumps"], "nfev": e["nfev"],
                 "fewer": full.nfev / e["nfev"], "rel_error": (e["t_cr"] - t_ref) / t_ref}
            )  # fmt: skip
    return rec


#: Full integrations whose cost per revolution :func:`per_revolution` measures, through
#: the package's front door on the regularised path: (label, rtol, largest step in spin
#: periods; None: the case's default, a twentieth on the rig). The width is the default
#: 1e-7 or rtol, whichever is larger (the regularised methods need width >= rtol).
FULL_SETTINGS: tuple[tuple[str, float, float | None], ...] = (
    ("rtol 1e-8, step <= T/20 (default)", 1e-8, None),
    ("rtol 1e-7, no step limit", 1e-7, math.inf),
    ("rtol 1e-6, no step limit", 1e-6, math.inf),
    ("rtol 1e-5, no step limit", 1e-5, math.inf),
)


def time_scales(spin: float, samples: int = 256) -> dict[str, float]:
    """The time scales of one rig opening at `spin` [rad/s] (the package's default
    regularised run, sampled `samples` times a revolution).

    Returns
    -------
    dict
        ``t_cr_s``; ``revolutions``, t_cr omega_p / (2 pi), the socket's turns; ``turns``,
        the integral of |omega_r| dt over 2 pi, the ball's turns relative to its socket
        (thesis Eqs. 35-36), whose slow rotation modulates the drift of theta between
        revolutions; ``smallest_arm``, the median over revolutions of the smallest moment
        arm sqrt(1 - u_X^2) in each (thesis Eq. 61, u = omega_r / |omega_r|): the rig's
        arm dips to about |u_Z| twice a revolution, a feature about |u_Z| / (2 pi) of a
        revolution wide that any integrator must resolve.
    """
    from obturator.model.cases import rig_case
    from obturator.solve import SolverOptions, opening_time, simulate

    case = rig_case(spin, MU_S)
    options = SolverOptions(method="regularised")
    t_cr = opening_time(case, options)
    period = 2.0 * math.pi / spin
    t = np.arange(0.0, t_cr, period / samples)
    run = simulate(case, options, t_eval=t)
    y = np.asarray(run.state)
    arm = np.full(y.shape[0], math.nan)
    for k in range(y.shape[0]):
        w_r = _rotation(y[k]) @ y[k, 4:7] - y[k, 7] * Z
        size = float(np.linalg.norm(w_r))
        if size > 1e-9 * spin:
            arm[k] = math.sqrt(max(0.0, 1.0 - (w_r[0] / size) ** 2))
    whole = (y.shape[0] // samples) * samples
    per_rev = np.nanmin(arm[samples:whole].reshape(-1, samples), axis=1)
    turns = float(np.trapezoid(np.asarray(run.omega_r), np.asarray(run.t))) / (2.0 * math.pi)
    return {
        "t_cr_s": t_cr,
        "revolutions": t_cr / period,
        "turns": turns,
        "smallest_arm": float(np.median(per_rev)),
    }


def per_revolution(spin: float, reference: float | None = None) -> list[dict[str, Any]]:
    """Right-hand sides per revolution of full integrations of one rig point at `spin`
    [rad/s] under :data:`FULL_SETTINGS` (the sweep's path, a batch of one), and each one's
    t_cr error against `reference` [s] (default: rtol 1e-11 with steps <= T/50)."""
    from obturator.model.cases import rig_case
    from obturator.solve import SolverOptions, integrate_packed, pack_points

    case = rig_case(spin, MU_S)
    period = 2.0 * math.pi / spin

    def run(rtol: float, max_step: float | None) -> tuple[float, int]:
        options = SolverOptions(
            method="regularised", rtol=rtol, atol=rtol * 1e-2,
            friction_width=max(1e-7, rtol),
            max_step=None if max_step is None else min(10.0, max_step * period),
        )  # fmt: skip
        nfev = np.zeros(1, dtype=np.int64)
        t_cr = integrate_packed(pack_points([case], options), options, point_nfev=nfev)[0]
        return float(t_cr[0]), int(nfev[0])

    if reference is None:
        reference = run(1e-11, 0.02)[0]
    rows = []
    for label, rtol, max_step in FULL_SETTINGS:
        t_cr, nfev = run(rtol, max_step)
        rows.append(
            {"setting": label, "rhs_per_revolution": nfev * period / t_cr,
             "rel_error": (t_cr - reference) / reference}
        )  # fmt: skip
    return rows


def _print_time_scales(spins: tuple[float, ...], out: Path | None) -> int:
    recs = []
    for w in spins:
        rec = time_scales(w) | {"spin_rad_s": w, "full": per_revolution(w)}
        recs.append(rec)
        print(f"{w:g} rad/s: t_cr {rec['t_cr_s']:.6f} s, {rec['revolutions']:.1f} "
              f"revolutions, {rec['turns']:.2f} turns of the ball in its socket, smallest "
              f"arm per revolution {rec['smallest_arm']:.3f} (median)")  # fmt: skip
        for r in rec["full"]:
            print(f"  {r['setting']}: {r['rhs_per_revolution']:.0f} right-hand sides per "
                  f"revolution, t_cr error {r['rel_error']:+.1e}")  # fmt: skip
    if out is not None:
        out.write_text(json.dumps(recs, indent=1))
    return 0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.envelope_following")
    ap.add_argument("--spins", default="700,1000")
    ap.add_argument("--tols", default="1e-8,1e-6,1e-4")
    ap.add_argument("--pairs", default="3,4")
    ap.add_argument("--json", type=Path, default=None)
    ap.add_argument("--time-scales", action="store_true",
                    help="the time scales and the cost per revolution of full integration "
                    "(time_scales, per_revolution) at --spins instead")  # fmt: skip
    a = ap.parse_args(argv)
    if a.time_scales:
        return _print_time_scales(tuple(float(x) for x in a.spins.split(",")), a.json)
    tols = tuple(float(x) for x in a.tols.split(","))
    pairs = tuple(int(x) for x in a.pairs.split(","))
    out = []
    for w in (float(x) for x in a.spins.split(",")):
        r = study(w, tols, pairs)
        out.append(r)
        print(f"\n{w:g} rad/s: t_cr {r['t_cr_reference_s']:.10f} s, {r['revolutions']} "
              f"revolutions, every revolution integrated: {r['full']['nfev']} evaluations "
              f"(error {r['full']['rel_error']:.1e}); largest scaled 6th difference of "
              f"the sections over the second half {r['sixth_difference_late']:.1e}")  # fmt: skip
        print("  extrapolation H revolutions ahead (scaled error): "
              + "; ".join(f"K={e['pairs']} H={e['H']}: median {e['median']:.1e} largest "
                          f"{e['largest']:.1e}" for e in r["extrapolation"]))  # fmt: skip
        for e in r["envelope"]:
            print(f"  envelope K={e['pairs']} tol {e['tol']:.0e}: {e['jumps']} jumps, "
                  f"{e['nfev']} evaluations ({e['fewer']:.2f}x fewer), t_cr error "
                  f"{e['rel_error']:+.1e}")  # fmt: skip
    if a.json is not None:
        a.json.write_text(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
