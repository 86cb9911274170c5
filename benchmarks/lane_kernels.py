"""The lane integrators alone, in one process: throughput and a dump of every output.

``python benchmarks/lane_kernels.py OUT.npz [--repeats 3] [--rig 480] [--flight 160]``

Calls :func:`integrate_lanes` on rig points (omega_p over 100-700 rad/s, the thesis's
mu_s) and flight points (Mach 1.5-4), and :func:`integrate_radau_lanes` on the rig
points DOP853 found stiff, from DOP853's last accepted states, as the batched sweep
does; no process pool, no packing in the timings (compiled code loaded first). Writes
every output array and the best-of-`repeats` CPU seconds of each call to OUT.npz, so two
source trees (run each with its own ``PYTHONPATH`` and ``NUMBA_CACHE_DIR``) can be
compared bit for bit and timed back to back.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from obturator.model.cases import flight_case, rig_case
from obturator.solve import SolverOptions

try:  # solve/many.py
    from obturator.solve import pack_points
except ImportError:  # sweeps/batch.py before it
    from obturator.sweeps.batch import pack_points

try:  # the lanes sub-package
    from obturator.core.integrators.lanes import LANES, integrate_lanes, integrate_radau_lanes
except ImportError:  # the flat layout before it
    from obturator.core.integrators.radau_lanes import integrate_radau_lanes

    from obturator.core.integrators.lanes import LANES, integrate_lanes

MU_S = 0.5473  # thesis's fitted mu_s


def _dop853(pk, options, t0=None, y0=None):
    n = pk.valid.size
    order = np.argsort(-pk.spin, kind="stable")
    return integrate_lanes(
        pk.y0 if y0 is None else y0, np.zeros(n) if t0 is None else t0, pk.p, pk.scale,
        pk.t_max, pk.h0, pk.h_max, np.full(n, options.max_steps, dtype=np.int64), order,
        options.rtol, options.atol, options.event_tol, LANES, np.zeros(n),
    )  # fmt: skip


def _radau(pk, options, t0, y0):
    from obturator.core.integrators import auto_radau_tolerances

    n = pk.valid.size
    rtol, atol = auto_radau_tolerances(options.rtol, options.atol)
    return integrate_radau_lanes(
        y0, t0, pk.p, pk.scale, pk.t_max, pk.h0, pk.h_max,
        np.full(n, options.max_steps, dtype=np.int64), np.ones(n, dtype=np.bool_),
        np.argsort(pk.spin, kind="stable"), rtol, atol, options.event_tol, LANES, LANES,
    )  # fmt: skip


def _best(fn, repeats):
    """Best of `repeats` in CPU seconds of this process (less disturbed than wall time
    on a shared machine; the integrators run on one thread) and the last result."""
    best = np.inf
    for _ in range(repeats):
        t = time.process_time()
        out = fn()
        best = min(best, time.process_time() - t)
    return best, out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--rig", type=int, default=480)
    ap.add_argument("--flight", type=int, default=160)
    a = ap.parse_args(argv)
    o = SolverOptions()
    rig = pack_points([rig_case(float(w), MU_S) for w in np.linspace(100, 700, a.rig)], o)
    fl = pack_points([flight_case(mach=float(m)) for m in np.linspace(1.5, 4, a.flight)], o)
    res = {}
    _dop853(rig.take(np.arange(2)), o)  # load the compiled code
    res["rig_s"], r = _best(lambda: _dop853(rig, o), a.repeats)
    res["flight_s"], f = _best(lambda: _dop853(fl, o), a.repeats)
    stiff = np.flatnonzero(r[0] == 3)
    sp = rig.take(stiff)
    _radau(sp.take(np.arange(2)), o, r[2][stiff[:2]], r[3][stiff[:2]])
    res["radau_s"], rr = _best(lambda: _radau(sp, o, r[2][stiff], r[3][stiff]), a.repeats)
    for name, out in (("rig", r), ("flight", f), ("radau", rr)):
        for k, x in enumerate(out):
            res[f"{name}_{k}"] = np.asarray(x)
    np.savez(a.out, **res)
    print(
        f"rig {a.rig} pts {res['rig_s']:.3f} s, flight {a.flight} pts {res['flight_s']:.3f} s,"
        f" radau {stiff.size} stiff pts {res['radau_s']:.3f} s"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
