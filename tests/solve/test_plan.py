"""Same point, same bits: a case's t_cr and status do not depend on its batch.

The property (thesis cases: the rig of Table 1 over the spin range of Figs. 32-37 and
beyond, the flight case, the exact Coulomb patch law): every random batch (sizes 1-300,
any order, repeats allowed) drawn from a pool of cases gives, for every case, the t_cr
and status of that case run alone (:func:`obturator.solve.opening_time`, a batch of one),
bit for bit, under the default options and with each speed strategy switched. The
reference values are the cases run alone: an independent computation of each point,
sharing nothing with the batch.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from obturator import SolverOptions
from obturator.model.cases import flight_case, rig_case
from obturator.reference import THESIS_MU_S
from obturator.solve import opening_time, opening_times
from obturator.solve.many import pack_points
from obturator.solve.plan import ROUTE_CODES, ROUTES, plan_routes, route_counts


def _pool() -> list:
    """Rig spins log-uniform over 40-1000 rad/s (set-valued below ~218 rad/s, regularised
    above), flight cases at Mach 1.5-4 and both mu_s, the Coulomb patch law at 80-400."""
    rng = np.random.default_rng(44)
    rig = [rig_case(float(w), 0.5473) for w in np.exp(rng.uniform(np.log(40), np.log(1000), 24))]
    flight = [flight_case(mach=m, mu_s=mu) for m in (1.5, 3.0, 4.0) for mu in (0.35, THESIS_MU_S)]
    coulomb = [rig_case(float(w), 0.5473, torque_model="coulomb") for w in rng.uniform(80, 400, 6)]
    return rig + flight + coulomb


POOL = _pool()
#: The options each property runs under: the defaults, and every speed strategy switched
#: (the one-spin map and the shared band maps; lanes off; the scalar Radau IIA; the
#: set-valued last slips in the mode loop).
OPTIONS = {
    "default": SolverOptions(),
    "shared maps": SolverOptions(shared_maps=True),
    "no lanes, scalar Radau": SolverOptions(lanes=False, radau_lanes=False),
    "no slip lanes": SolverOptions(slip_lanes=False),
}


@pytest.fixture(scope="module")
def alone() -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """(t_cr, status) of every pool case run alone, per options."""
    out = {}
    for name, options in OPTIONS.items():
        t, s = [], []
        for case in POOL:
            t_cr, status, _ = opening_times([case], options)
            t.append(t_cr[0])
            s.append(status[0])
        out[name] = (np.array(t), np.array(s))
    return out


def _same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return bool(np.array_equal(a.view(np.int64), b.view(np.int64)))


@pytest.mark.parametrize("name", list(OPTIONS))
@settings(
    max_examples=6, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(data=st.data())
def test_any_batch_gives_each_point_its_alone_bits(name, alone, data):
    picks = data.draw(
        st.lists(st.integers(0, len(POOL) - 1), min_size=1, max_size=300), label="batch"
    )
    n_chunks = data.draw(st.integers(1, 4), label="chunks")
    options = OPTIONS[name]
    idx = np.array(picks)
    t_ref, s_ref = alone[name]
    # the whole batch, and the same points in `n_chunks` consecutive chunks
    t, s, stats = opening_times([POOL[i] for i in idx], options)
    assert _same_bits(t, t_ref[idx]) and np.array_equal(s, s_ref[idx])
    assert stats["route"].shape == idx.shape
    for part in np.array_split(idx, n_chunks):
        if part.size:
            t_part, s_part, _ = opening_times([POOL[i] for i in part], options)
            assert _same_bits(t_part, t_ref[part]) and np.array_equal(s_part, s_ref[part])


def test_opening_time_is_a_batch_of_one(alone):
    """The public one-case call returns the batch's bits (it is the same loop)."""
    t_ref, _ = alone["default"]
    for k in (0, 5, len(POOL) - 1):
        t = opening_time(POOL[k])
        assert _same_bits(np.array([t]), t_ref[k : k + 1])


def test_route_is_planned_from_the_point_and_the_options_alone():
    """Each route follows from its point: the set-valued solver below the stick ratio of
    :data:`obturator.solve.dispatch.SET_VALUED_BELOW` (rig: 0.6, i.e. about 218 rad/s
    at mu_s 0.5473 by Eq. 61's moment scale), the regularised law above; the same in any
    order."""
    cases = [rig_case(60.0, 0.5473), rig_case(700.0, 0.5473), rig_case(100.0, 0.5473)]
    packed = pack_points(cases, SolverOptions())
    routes = plan_routes(packed.valid, packed.p, packed.y0, SolverOptions())
    assert [ROUTES[r] for r in routes] == [
        "set-valued, last slip in lanes",
        "regularised, Radau IIA lanes",
        "set-valued, last slip in lanes",
    ]
    shuffled = pack_points(cases[::-1], SolverOptions(shared_maps=True))
    routes = plan_routes(shuffled.valid, shuffled.p, shuffled.y0, SolverOptions(shared_maps=True))
    shared = "set-valued, shared map, last slip in lanes"
    assert [ROUTES[r] for r in routes] == [shared, "regularised, Radau IIA lanes", shared]
    assert route_counts(routes) == {shared: 2, "regularised, Radau IIA lanes": 1}


def test_stats_count_the_routes():
    cases = [rig_case(60.0, 0.5473), rig_case(700.0, 0.5473)]
    _, _, stats = opening_times(
        cases, replace(SolverOptions(), radau_lanes=False, slip_lanes=False)
    )
    assert stats["routes"] == {"set-valued": 1, "regularised": 1}
    assert list(stats["route"]) == [ROUTE_CODES["set-valued"], ROUTE_CODES["regularised"]]


def test_every_route_name_is_unique_and_invalid_is_zero():
    assert len(set(ROUTES)) == len(ROUTES) and ROUTES[0] == "invalid"
    t, _, stats = opening_times([rig_case(300.0, 0.5473)], SolverOptions(method="radau"))
    assert stats["routes"] == {"radau": 1} and math.isfinite(t[0])


def test_every_solver_option_is_in_the_study_digest():
    """Flip each SolverOptions field: the sweep digest (what a resume store is keyed by)
    changes, so a study never mixes points computed under two settings."""
    from dataclasses import fields

    from obturator.sweeps import SweepSpec

    base = SweepSpec(axes={"spin_rate": [100.0, 200.0]})
    flipped = {
        "rtol": 1e-9, "atol": 1e-11, "friction_width": 1e-6, "friction_family": "tanh",
        "formulation": "euler", "max_steps": 1000, "event_tol": 1e-10, "max_step": 1e-3,
        "method": "regularised", "fixed_step": None, "lanes": False, "radau_lanes": False,
        "shared_maps": False, "slip_lanes": False,
    }  # fmt: skip
    assert set(flipped) == {f.name for f in fields(SolverOptions)}
    for name, value in flipped.items():
        if name == "fixed_step":  # only with moreau-jean
            other = replace(base.options, method="moreau-jean", fixed_step=1e-5)
        else:
            other = replace(base.options, **{name: value})
        assert replace(base, options=other).digest() != base.digest(), name


def test_no_environment_is_read_below_the_cli():
    """A result never depends on an environment variable: only ``cli/`` (the program's
    edge) reads the environment."""
    import re
    from pathlib import Path

    import obturator

    root = Path(obturator.__file__).parent
    pattern = re.compile(r"os\.environ|os\.getenv|environ\.get")
    offenders = [
        str(p.relative_to(root))
        for p in root.rglob("*.py")
        if "cli" not in p.relative_to(root).parts[:1] and pattern.search(p.read_text())
    ]
    assert not offenders, offenders
