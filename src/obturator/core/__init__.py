"""The numeric core: numba-compiled equations of motion and integrators, SI floats only.

* :mod:`.layout`: the flat parameter vector and the codes the kernels dispatch on;
* :mod:`.dynamics`: right-hand side, torques, nutation angle, observables;
* :mod:`.thesis_law`: the thesis's torque law, written once (viscous coefficient, moment
  arm, regularisation) for :mod:`.dynamics` and :mod:`.specialised`, the thesis kernel
  of the scalar integrators and the lanes;
* :mod:`.integrators`: DOP853, Radau IIA, Rosenbrock behind one contract, and both in
  SIMD lanes for many points at once (:mod:`.integrators.lanes`);
* :mod:`.jit_cache`: where numba caches the compiled code.

Nothing here knows about units, files, the command line or studies; the
model (:mod:`obturator.model`) packs a case into the parameter vector and
:mod:`obturator.solve` turns raw solutions into results.
"""
