"""What a user might pick instead: numbalsoda and diffrax on the same rig trajectory.

Optional (``pip install ".[bench]"``; numbalsoda builds with a Fortran compiler, e.g.
Debian's ``gfortran``): skipped with a note when the libraries are missing.

* numbalsoda's DOP853 and LSODA (compiled Fortran/C) on the package's own compiled
  right-hand side, wrapped in a numba ``cfunc``. numbalsoda has no event location,
  so each run integrates to the reference t_cr and is timed for that.
* diffrax (JAX on CPU, ``jax.jit``) with Tsit5 and Dopri8 on the same model written
  in ``jax.numpy`` (the plain-NumPy model of :mod:`benchmarks.baseline`, branches as
  ``where``), also to the reference t_cr.

Accuracy is reported as the t_cr error implied by the end state:
(theta(t_ref) - theta_cr) / theta_dot(t_ref), relative to t_ref, where t_ref is
Radau IIA's t_cr at rtol 1e-11; the package's own ``auto`` run at the same rtol is
timed beside them with its event-located t_cr.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from benchmarks.baseline import initial_state, model_from_case
from obturator.core.dynamics import nutation_angle_of_state, rhs
from obturator.model.cases import rig_case
from obturator.solve import SolverOptions, opening_time, pack_parameters

MU_S = 0.5473
SPIN = 300.0
REFERENCE = SolverOptions(method="radau", rtol=1e-11, atol=1e-13)


def _best(fn, repeat: int) -> tuple[float, Any]:
    best, out = math.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def _timing_error(y_end: np.ndarray, p: np.ndarray, t_ref: float) -> float:
    """Relative t_cr error implied by the state at t_ref (theta error / theta rate)."""
    h = 1e-7
    dy = np.empty(8)
    rhs(t_ref, np.asarray(y_end, float), p, dy)
    th = nutation_angle_of_state(np.asarray(y_end, float), p)
    th2 = nutation_angle_of_state(np.asarray(y_end, float) + h * dy, p)
    rate = (th2 - th) / h
    return (th - p_theta_cr(p)) / rate / t_ref


def p_theta_cr(p: np.ndarray) -> float:
    from obturator.core.layout import P_THETA_CR

    return float(p[P_THETA_CR])


def _numbalsoda(case, p, y0, t_ref: float, rtol: float, repeat: int) -> list[dict[str, Any]]:
    import numbalsoda
    from numba import carray, cfunc

    from obturator.core.layout import N_PARAM, N_STATE

    @cfunc(numbalsoda.lsoda_sig)
    def f(t, u, du, data):  # pragma: no cover - compiled
        rhs(t, carray(u, (N_STATE,)), carray(data, (N_PARAM,)), carray(du, (N_STATE,)))

    t_eval = np.array([0.0, t_ref])
    rows = []
    for name in ("dop853", "lsoda"):
        solver = getattr(numbalsoda, name)

        def run(solver=solver):
            return solver(f.address, y0, t_eval, data=p, rtol=rtol, atol=rtol * 1e-2)

        run()
        wall, (usol, ok) = _best(run, repeat)
        rows.append(
            {
                "solver": f"numbalsoda {name}",
                "rtol": rtol,
                "wall_s": wall,
                "t_cr_rel_error": _timing_error(usol[-1], p, t_ref) if ok else math.nan,
                "event_location": False,
            }
        )
    return rows


def _jax_rhs(model):
    import jax.numpy as jnp

    a, c = model.a, model.c

    def f(t, y, args):
        q = y[:4] / jnp.linalg.norm(y[:4])
        w = y[4:7]
        q0, q1, q2, q3 = q
        rot = jnp.array(
            [
                [1 - 2 * (q2 * q2 + q3 * q3), 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
                [2 * (q1 * q2 + q0 * q3), 1 - 2 * (q1 * q1 + q3 * q3), 2 * (q2 * q3 - q0 * q1)],
                [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), 1 - 2 * (q1 * q1 + q2 * q2)],
            ]
        )
        w_rel = rot @ w - jnp.array([0.0, 0.0, y[7]])
        speed = jnp.linalg.norm(w_rel)
        k = jnp.where(
            speed >= model.transition_rate,
            model.viscous_turbulent * speed**0.75,
            model.viscous,
        )
        safe = jnp.where(speed > 0.0, speed, 1.0)
        e = w_rel / safe
        x = speed / model.delta
        arm2 = 1.0 - e[0] ** 2
        sat = x / jnp.sqrt(1.0 + x * x)
        fric = jnp.where(speed > 0.0, model.friction * jnp.sqrt(jnp.maximum(arm2, 0.0)) * sat, 0.0)
        torque = -k * w_rel - fric * e
        g = rot.T @ torque
        dw = jnp.array(
            [
                (g[0] - (c - a) * w[1] * w[2]) / a,
                (g[1] + (c - a) * w[0] * w[2]) / a,
                g[2] / c,
            ]
        )
        y0_, y1_, y2_, y3_ = y[:4]
        dq = 0.5 * jnp.array(
            [
                -y1_ * w[0] - y2_ * w[1] - y3_ * w[2],
                y0_ * w[0] + y2_ * w[2] - y3_ * w[1],
                y0_ * w[1] + y3_ * w[0] - y1_ * w[2],
                y0_ * w[2] + y1_ * w[1] - y2_ * w[0],
            ]
        )
        return jnp.concatenate([dq, dw, jnp.zeros(1)])

    return f


def _diffrax(case, p, t_ref: float, rtol: float, repeat: int) -> list[dict[str, Any]]:
    import jax

    jax.config.update("jax_enable_x64", True)
    import diffrax
    import jax.numpy as jnp

    model = model_from_case(case)
    term = diffrax.ODETerm(_jax_rhs(model))
    y0 = jnp.asarray(initial_state(model))
    rows = []
    for name in ("Tsit5", "Dopri8"):
        solver = getattr(diffrax, name)()
        ctrl = diffrax.PIDController(rtol=rtol, atol=rtol * 1e-2)

        @jax.jit
        def solve(y0, solver=solver, ctrl=ctrl):
            sol = diffrax.diffeqsolve(
                term, solver, 0.0, t_ref, None, y0,
                stepsize_controller=ctrl, max_steps=1_000_000,
                saveat=diffrax.SaveAt(t1=True),
            )  # fmt: skip
            return sol.ys[-1]

        solve(y0).block_until_ready()
        wall, y_end = _best(lambda s=solve: s(y0).block_until_ready(), repeat)
        rows.append(
            {
                "solver": f"diffrax {name} (CPU)",
                "rtol": rtol,
                "wall_s": wall,
                "t_cr_rel_error": _timing_error(np.asarray(y_end), p, t_ref),
                "event_location": False,
            }
        )
    return rows


def alternatives(
    repeat: int = 20, rtols: tuple[float, ...] = (1e-10, 1e-8, 1e-6)
) -> dict[str, Any]:
    """Rig at 300 rad/s: the package against numbalsoda and diffrax (when installed)."""
    case = rig_case(SPIN, MU_S)
    t_ref = opening_time(case, REFERENCE)
    opts = SolverOptions()
    y0 = case.initial_state(opts.formulation)
    p = pack_parameters(case, opts, y0)
    rows: list[dict[str, Any]] = []
    notes: list[str] = []
    for rtol in rtols:
        o = SolverOptions(rtol=rtol, atol=rtol * 1e-2)
        opening_time(case, o)
        wall, t = _best(lambda o=o: opening_time(case, o), repeat)
        rows.append(
            {
                "solver": "obturator auto (DOP853, event located)",
                "rtol": rtol,
                "wall_s": wall,
                "t_cr_rel_error": t / t_ref - 1.0,
                "event_location": True,
            }
        )
        for label, fn in (
            ("numbalsoda", lambda r=rtol: _numbalsoda(case, p, y0, t_ref, r, repeat)),
            ("diffrax", lambda r=rtol: _diffrax(case, p, t_ref, r, max(3, repeat // 4))),
        ):
            try:
                rows += fn()
            except ImportError:
                if label not in " ".join(notes):
                    notes.append(f"{label} not installed (pip install '.[bench]')")
    return {"case": f"rig {SPIN:g} rad/s, mu_s {MU_S}", "t_ref_s": t_ref, "rows": rows,
            "notes": notes}  # fmt: skip


def print_alternatives(rec: dict[str, Any]) -> None:
    """A rich table of :func:`alternatives`."""
    from rich.console import Console
    from rich.table import Table

    con = Console(width=160)
    t = Table(title=f"{rec['case']}: other integrators to the same t_cr (best of repeats)")
    for col in ("solver", "rtol", "wall", "t_cr error", "event located"):
        t.add_column(col, justify="left" if col == "solver" else "right")
    for r in rec["rows"]:
        t.add_row(
            r["solver"],
            f"{r['rtol']:g}",
            f"{r['wall_s'] * 1e3:.3g} ms",
            f"{r['t_cr_rel_error']:.1e}",
            "yes" if r["event_location"] else "no (to the reference t_cr)",
        )
    con.print(t)
    for n in rec["notes"]:
        con.print(f"  {n}")
