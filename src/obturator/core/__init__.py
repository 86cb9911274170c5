"""The numeric core: numba-compiled equations of motion and integrators, SI floats only.

* :mod:`.layout`: the flat parameter vector and the codes the kernels dispatch on;
* :mod:`.dynamics`: right-hand side, torques, nutation angle, observables;
* :mod:`.integrators`: DOP853, Radau IIA, Rosenbrock behind one contract;
* :mod:`.jit_cache`: where numba caches the compiled code.

Nothing here knows about units, files, the command line or studies; the
model (:mod:`obturator.model`) packs a case into the parameter vector and
:mod:`obturator.solve` turns raw solutions into results.
"""
