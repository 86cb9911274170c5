"""Performance benchmarks of :mod:`obturator` against a plain-Python baseline.

Run from the repository root::

    python -m benchmarks                 # full run (about 9 minutes on 2 cores)
    python -m benchmarks --quick         # small sweeps, for smoke runs (about 1 minute)
    python -m benchmarks --big           # adds a 10,000-point package-only 2-worker sweep
    python -m benchmarks --json out.json --plot cost.png
    python -m benchmarks report          # measure, rewrite docs/benchmarks.md's tables
    python -m benchmarks report --quick --only imports,dispatch_crossover

Every number is measured in the same run, against a baseline measured in that
run: ``scipy.integrate.solve_ivp(method="LSODA", rtol=1e-6, atol=1e-9)`` on
the plain NumPy right-hand side of :mod:`benchmarks.baseline` (same model,
torques, regularisation and parameters as the package). Nothing asserts on
timings; the benchmark reports.
"""
