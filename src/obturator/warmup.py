"""Build numba's on-disk cache of the compiled integrators once, in parallel.

A fresh environment compiles each integrator on first use (seconds each; the compile
table of ``python -m benchmarks``, ``docs/benchmarks.md``); a first sweep or study
pays that inside its own time, once per integrator it meets. :func:`warm_up`
compiles them ahead of time, each in its own fresh process so that they compile
side by side, and leaves the machine code in the cache directory of
:mod:`obturator.core.jit_cache`. ``obturator warmup`` runs it after installation.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, as_completed
from multiprocessing import get_context

from .errors import InputError

__all__ = ["WARMUP_TARGETS", "load_radau_lanes", "warm_up"]

#: Integrator -> what compiling it takes: ``auto`` runs need DOP853 and Radau IIA (its
#: regularised cases) and the set-valued solver (its low-spin cases);
#: Rosenbrock is compiled only with ``everything``.
WARMUP_TARGETS: dict[str, str] = {
    "dop853": "explicit DOP853 (every regularised run)",
    "radau": "Radau IIA (regularised runs that stick; method radau)",
    "set-valued": "set-valued stick-slip solver (auto runs at low spin; method set-valued)",
    "lanes": "batched DOP853 lanes (sweeps, Monte Carlo)",
    "radau-lanes": "batched Radau IIA lanes (stiff points of sweeps and Monte Carlo)",
    "rosenbrock": "Rosenbrock ode23s (method rosenbrock)",
}


def _compiled_anything() -> bool:
    """True when this process compiled any jitted core function (a numba cache miss)
    rather than only loading machine code from the cache."""
    import sys

    from numba.core.registry import CPUDispatcher

    return any(
        sum(v.stats.cache_misses.values()) > 0
        for name, module in list(sys.modules.items())
        if name.startswith("obturator.core")
        for v in vars(module).values()
        if isinstance(v, CPUDispatcher)
    )


def _compile(method: str) -> tuple[str, float, str | None, bool]:
    """In a fresh process: compile (or load) `method` with a short rig run; return the
    method, the seconds it took, the cache directory and whether it compiled."""
    t0 = time.perf_counter()
    _load(method)
    from .core.jit_cache import configure_cache

    return method, time.perf_counter() - t0, configure_cache(), _compiled_anything()


def _load(method: str) -> None:
    """Run `method` once so that numba compiles it or loads it from the cache."""
    from .model.cases import rig_case
    from .solve import SolverOptions, opening_time

    if method == "radau-lanes":
        load_radau_lanes()
        return
    if method == "lanes":  # the batched kernel itself (solve.many drives it)
        import numpy as np

        from .core.integrators.lanes import integrate_lanes
        from .solve import integration_setup

        pr, c = integration_setup(rig_case(300.0, 0.5, t_max=1e-3), SolverOptions())
        one = np.ones(1)
        integrate_lanes(
            pr.y0[None], 0.0 * one, pr.p[None], pr.scale[None], c.t_max * one, c.h0 * one,
            c.h_max * one, np.full(1, c.max_steps), np.zeros(1, dtype=np.int64), c.rtol,
            c.atol, c.event_tol, 16, np.zeros(1),
        )  # fmt: skip
        return
    # a short run that stays non-stiff: "regularised" compiles DOP853 alone; each process
    # also compiles what every run needs (parameter packing), so none waits for another
    opening_time(
        rig_case(300.0, 0.5, t_max=1e-3),
        SolverOptions(method="regularised" if method == "dop853" else method),  # type: ignore[arg-type]
    )
    if method == "set-valued":
        _load_set_valued_study()


def _load_set_valued_study() -> None:
    """Load (or compile) what a study's set-valued points run beyond one case alone: the
    return map of a fixed spin band (``shared_maps``, 60 and 62 rad/s).

    Without it the first study after ``obturator warmup`` compiled these in every worker
    (most of a short sweep's time)."""
    from .model.cases import rig_case
    from .solve import SolverOptions, opening_times

    opening_times([rig_case(w, 0.5473) for w in (60.0, 62.0)], SolverOptions(shared_maps=True))


def load_radau_lanes() -> None:
    """Load (or compile) the Radau IIA lanes: one short near-stick rig point (1 ms)."""
    import numpy as np

    from .core.integrators.lanes import LANES, integrate_radau_lanes
    from .model.cases import rig_case
    from .solve import SolverOptions, integration_setup

    pr, c = integration_setup(rig_case(150.0, 0.5, t_max=1e-3), SolverOptions())
    one = np.ones(1)
    integrate_radau_lanes(
        pr.y0[None], 0.0 * one, pr.p[None], pr.scale[None], c.t_max * one, c.h0 * one,
        c.h_max * one, np.full(1, c.max_steps), np.ones(1, dtype=np.bool_),
        np.zeros(1, dtype=np.int64), c.rtol, c.atol, c.event_tol, LANES, LANES,
    )  # fmt: skip


def warm_up(
    *,
    jobs: int = 2,
    everything: bool = False,
    report: Callable[[str, float, bool, int, int], None] | None = None,
) -> dict[str, object]:
    """Compile the integrators into numba's cache, `jobs` at a time.

    Parameters
    ----------
    jobs : int
        Processes compiling side by side (>= 1).
    everything : bool
        Also compile the Rosenbrock method (rarely used).
    report : callable, optional
        Called as each target finishes: ``report(target, seconds, compiled, done,
        total)`` (seconds in its process; compiled False: loaded from the cache).

    Returns
    -------
    dict
        ``seconds`` per integrator (compile or cache load, in its process),
        ``compiled`` per integrator (False: loaded from the cache), ``wall_s`` of
        the whole warm-up and the cache ``directory`` (``NUMBA_CACHE_DIR`` when set).
    """
    if int(jobs) < 1:
        raise InputError("jobs", f"{jobs} is outside the allowed range >= 1")
    targets = [m for m in WARMUP_TARGETS if everything or m != "rosenbrock"]
    t0 = time.perf_counter()
    # spawn: every process compiles from scratch (a fork would inherit nothing useful)
    with ProcessPoolExecutor(max_workers=int(jobs), mp_context=get_context("spawn")) as pool:
        futures = {pool.submit(_compile, m): m for m in targets}
        finished = {}
        for future in as_completed(futures):
            m, s, directory, compiled = future.result()
            finished[m] = (m, s, directory, compiled)
            if report is not None:
                report(m, s, compiled, len(finished), len(targets))
    done = [finished[m] for m in targets]  # in the order of WARMUP_TARGETS
    return {
        "seconds": {m: s for m, s, _, _ in done},
        "compiled": {m: c for m, _, _, c in done},
        "wall_s": time.perf_counter() - t0,
        "directory": done[0][2] or _numba_cache_dir(),
    }


def _numba_cache_dir() -> str:
    """numba's cache folder as numba read it (``NUMBA_CACHE_DIR``)."""
    import numba

    return str(numba.config.CACHE_DIR)
