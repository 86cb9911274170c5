"""Firing-envelope studies beyond the thesis (issue 14).

Will the ball open in time across the firing envelope? The thesis answers for
one flight condition (Table 1: Mach 3, P_1 = 0.099 MPa, mu_s = 0.35) and
recommends coupling to a trajectory model and a numerical optimisation
(chapter VI). This subpackage provides:

* :mod:`.drag`, :mod:`.trajectory`: point-mass flight after muzzle exit;
* :mod:`.coupled`: the obturator integrated along the flight (trajectory-coupled
  load F_p(t) and spin omega_p(t));
* (the points run on a :class:`obturator.runs.Runner`: local processes or Dask, resumable);
* :mod:`.envelope`: t_cr and t_start maps over muzzle Mach x altitude (x temperature),
  with the delay t_start - t_cr and the unstartable region;
* :mod:`.start`: t_start (the bow shock swallowed, :mod:`obturator.model.start`)
  along one flight, both loads;
* :mod:`.reliability`: P(t_cr > requirement) by importance sampling;
* :mod:`.sensitivity`: Sobol indices with SALib;
* :mod:`.optimize`: robust design optimisation and the t_cr-mass Pareto front.
"""
