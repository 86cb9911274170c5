"""solve.advance: many cases from given states, the segments of a piecewise-constant load."""

from __future__ import annotations

import numpy as np
import pytest

from obturator import InputError
from obturator.model.cases import rig_case
from obturator.solve import SolverOptions, advance, opening_times, simulate
from obturator.status import Status

MU_S = 0.5473


@pytest.mark.parametrize("method", ["regularised", "auto"])
def test_end_states_are_the_one_trajectory_states_at_t_max(method):
    """Not opened by t_max: the end state is the one-trajectory run's state at t_max (its
    dense output there), for points that stay in DOP853 and points that go stiff, and
    under ``auto`` for the points it gives the set-valued solver (60 and 150 rad/s)."""
    opts = SolverOptions(method=method)
    cases = [rig_case(w, MU_S, t_max=0.02) for w in (60.0, 150.0, 300.0, 500.0)]
    states = np.array([c.initial_state(opts.formulation) for c in cases])
    out = advance(cases, states, opts)
    assert list(out.status) == [Status.T_MAX] * 4
    assert out.stats["n_stiff" if method == "regularised" else "n_set_valued"] >= 1
    for case, y in zip(cases, out.state, strict=True):
        ref = simulate(case, opts, t_eval=np.array([case.t_max])).state[-1]
        np.testing.assert_allclose(y, ref, rtol=1e-12, atol=1e-14)


def test_from_release_states_it_is_opening_times():
    opts = SolverOptions()
    cases = [rig_case(w, MU_S) for w in (250.0, 400.0, 650.0)]
    states = np.array([c.initial_state(opts.formulation) for c in cases])
    out = advance(cases, states, opts)
    t_cr, status, _ = opening_times(cases, opts)
    np.testing.assert_array_equal(out.t_cr, t_cr)
    np.testing.assert_array_equal(out.status, status)


def test_two_segments_continue_one_run():
    """Stopping at t1 and going on from the end state changes t_cr only by the restart's
    fresh initial step: agreement to the integrator's tolerance, for lanes and for the
    one-by-one path (method radau)."""
    for opts in (SolverOptions(), SolverOptions(method="radau")):
        full = [rig_case(w, MU_S) for w in (300.0, 500.0)]
        first = [c.with_(t_max=0.05) for c in full]
        states = np.array([c.initial_state(opts.formulation) for c in full])
        a = advance(first, states, opts)
        assert list(a.status) == [Status.T_MAX] * 2
        b = advance([c.with_(t_max=c.t_max - 0.05) for c in full], a.state, opts)
        t_ref, _, _ = opening_times(full, opts)
        np.testing.assert_allclose(0.05 + b.t_cr, t_ref, rtol=1e-6)


def test_states_of_the_wrong_shape_are_refused():
    with pytest.raises(InputError, match="states"):
        advance([rig_case(300.0, MU_S)], np.zeros((2, 8)))
