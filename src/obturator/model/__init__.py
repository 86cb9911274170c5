"""The physical model: the bored ball, the torques on it, and one problem to solve.

==========================  =============================================================
module                      what (thesis)
==========================  =============================================================
:mod:`.geometry`            :class:`~.geometry.BoredBall`: mass, weight, inertias C and A,
                            lambda = C/A - 1, beta_s = asin(r_s/R_s) (Eqs. 6-12, Table 1)
:mod:`.torques`             viscous torque (Couette Eq. 34; Nakabayashi Eqs. 39-42),
                            sliding friction in flight and on the rig (Eqs. 43-61 and
                            Appendix A), the exact Coulomb contact patch, slip-speed laws;
                            :class:`~.torques.TorqueModel` packs them for the core
:mod:`.case`                :class:`~.case.Case` (ball + torques + spin + release state) and
                            :func:`~.case.initial_state` (co-rotating release, Eqs. 13-17)
:mod:`.passage`             open area A(theta) of the straight passage through the tilted
                            ball (lens of the two mouth projections), its inverse, a ray
                            trace as independent check, the seat ring's backed share
:mod:`.start`               theta_start(M): Kantrowitz-Donaldson (Eq. 2) on A(theta), the
                            unstartable and Fanno-choked flags, the spill load bracket
:mod:`.cases`               the built-in cases (:func:`~.cases.rig_case`,
                            :func:`~.cases.flight_case`, :func:`~.cases.couette_case`) and
                            settings -> :class:`~.case.Case` (:func:`~.cases.case_from_settings`)
==========================  =============================================================

Plain SI floats throughout; quantities with units are converted at the edges
(:mod:`obturator.units`). Solving a :class:`~.case.Case` is :mod:`obturator.solve`'s job.
"""
