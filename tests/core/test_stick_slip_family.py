"""Return maps shared across spins (core/integrators/stick_slip_family.py).

References: the node cycles integrated one at a time (:class:`stick_slip_map._Nodes`,
the map's own definition), the one-spin run (:func:`obturator.solve.opening_time`:
its own map, or its cycles one by one), the regularised family limit (tanh and linear
at width 1e-10 omega_p, Radau IIA at rtol 1e-12: an independent path), and the stick
ratio kappa = omega_p^2 |C - A| sin(2 theta) / (2 M) of docs/stick_slip.md section 3
(thesis Eqs. 5a-5c, 56-61).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from obturator.core.integrators import stick_slip, stick_slip_family, stick_slip_map
from obturator.core.layout import P_A, P_C, P_FRIC
from obturator.model.cases import rig_case
from obturator.reference import THESIS_MU_S
from obturator.solve import SolverOptions, opening_time, opening_times
from obturator.solve.setup import integration_setup

SET_VALUED = SolverOptions(method="set-valued")
#: 14 spins in one fixed band, [1.15^28, 1.15^29) = [50.07, 57.58) rad/s, ~160-230 cycles
#: each.
SPINS = np.linspace(50.2, 57.4, 14)


def _setups(spins, mu_s=THESIS_MU_S):
    pairs = [integration_setup(rig_case(float(w), mu_s), SET_VALUED) for w in spins]
    return [p for p, _ in pairs], [c for _, c in pairs]


@pytest.fixture(scope="module")
def band():
    problems, controls = _setups(SPINS)
    maps, counts = stick_slip_family.shared_maps(problems, controls)
    return problems, controls, maps, counts


def test_one_band_gets_one_map_per_spin(band):
    """Every spin of the band gets its series; the nodes were integrated once."""
    _, _, maps, counts = band
    assert {stick_slip_family.band_edges(float(w)) for w in SPINS} == {(1.15**28, 1.15**29)}
    assert all(m is not None for m in maps)
    assert counts[0] > 0 and counts[2] > 0  # right-hand sides and steps of the nodes
    assert len({m.lo for m in maps}) == 1 and len({m.k_step for m in maps}) == 1


def test_series_interpolates_the_node_cycles_at_the_lowest_spin(band):
    """At the band's lowest spin (a Chebyshev-Lobatto node in log spin) and the middle
    theta node (one of every level's), the series of log(-D) and T reproduce the cycle
    integrated there on its own: interpolation is exact at its nodes."""
    w_lo = stick_slip_family.band_edges(float(SPINS[0]))[0]
    (problem,), (control,) = _setups([w_lo])
    m = stick_slip_family.band_map(problem, control)
    problem = problem._replace(p=stick_slip.zero_width(problem.p.copy()))
    nodes = stick_slip_map._Nodes(problem, control, stick_slip.run_cycles())
    x = stick_slip_map._lobatto(9)[4]  # cos(pi / 2): the middle node of every level
    theta = float(stick_slip_map.nutation_at(np.array(m.lo + 0.5 * (m.hi - m.lo) * (1.0 + x))))
    log_d, t_half, _, k = nodes.cycle(theta)
    assert k == m.k_step
    # the band's node was built from the group's spin-normalised data, this one from the
    # case's own: they differ by rounding, which the cycle's adaptive steps carry to
    # ~1e-8 in log(-D), far inside the map's tolerance (MAP_TOL rtol)
    assert np.polynomial.chebyshev.chebval(x, m.c_logd) == pytest.approx(log_d, abs=5e-8)
    t_series = np.polynomial.chebyshev.chebval(x, m.c_time)
    assert t_series == pytest.approx(t_half * math.pi / w_lo, rel=1e-9)


def test_shared_maps_give_the_one_spin_opening_times(band):
    """Each spin's t_cr through its shared map within 1e-6 of the one-spin run (its own
    map or its cycles); the front door with ``shared_maps`` gives the same as the core
    with the maps, alone or in a batch."""
    problems, controls, maps, _ = band
    by_family = np.array(
        [
            stick_slip.integrate(p, c, shared=m).t_event
            for p, c, m in zip(problems, controls, maps, strict=True)
        ]
    )
    cases = [rig_case(float(w), THESIS_MU_S) for w in SPINS]
    one_by_one = np.array([opening_time(c, SET_VALUED) for c in cases])
    assert np.max(np.abs(by_family / one_by_one - 1.0)) < 1e-6
    shared = SolverOptions(method="set-valued", shared_maps=True)
    t_cr, status, stats = opening_times(cases, shared)
    assert stats["n_set_valued"] == len(SPINS)
    np.testing.assert_array_equal(t_cr, by_family)
    np.testing.assert_array_equal(opening_time(cases[3], shared), by_family[3])


@pytest.mark.slow
def test_shared_map_agrees_with_the_regularised_limit(band):
    """At the band's ends the shared-map t_cr within 1e-6 of the regularised family limit
    (plus that limit's own tanh-linear spread)."""
    problems, controls, maps, _ = band
    for i in (0, len(SPINS) - 1):
        t = stick_slip.integrate(problems[i], controls[i], shared=maps[i]).t_event
        fam = [
            opening_time(
                rig_case(float(SPINS[i]), THESIS_MU_S),
                SolverOptions(
                    method="radau",
                    rtol=1e-12,
                    atol=1e-14,
                    friction_width=1e-10,
                    friction_family=f,
                ),  # fmt: skip
            )
            for f in ("tanh", "linear")
        ]
        ref = 0.5 * (fam[0] + fam[1])
        assert abs(t / ref - 1.0) < 1e-6 + abs(fam[0] - fam[1]) / ref


def test_only_cases_the_map_applies_to_get_one():
    """A Coulomb patch case (no map) and an Euler-angle case (outside the solver) get
    none, with no node integrated, and neither raises here."""
    coulomb, coulomb_c = integration_setup(
        rig_case(55.0, THESIS_MU_S, torque_model="coulomb"), SET_VALUED
    )
    euler, euler_c = integration_setup(
        rig_case(55.0, THESIS_MU_S), SolverOptions(method="set-valued", formulation="euler")
    )
    maps, counts = stick_slip_family.shared_maps([coulomb, euler], [coulomb_c, euler_c])
    assert maps == [None, None]
    assert counts[0] == 0


def test_band_edges_are_a_fixed_lattice():
    """Each spin falls in [1.15^k, 1.15^(k+1)), its edges included as the lattice says."""
    for w in (40.0, 50.0, 1.15**28, 57.0, 99.99, 218.0):
        lo, hi = stick_slip_family.band_edges(w)
        assert lo <= w < hi and hi / lo == pytest.approx(stick_slip_family.BAND_RATIO)
        assert math.log(lo) / math.log(1.15) == pytest.approx(
            round(math.log(lo) / math.log(1.15)), abs=1e-9
        )


@pytest.mark.parametrize("spin", [60.0, 90.0, 140.0])
def test_interval_ends_where_kappa_reaches_its_limit(spin):
    """theta_lo of a band up to `spin`: kappa(theta_lo) = KAPPA_END when that is above
    THETA_LOW and theta_cr (kappa from docs/stick_slip.md section 3, not the module)."""
    problems, controls = _setups([spin])
    problem = problems[0]._replace(p=stick_slip.zero_width(problems[0].p.copy()))
    group = stick_slip_family._group(problem, controls[0])
    grid = stick_slip_family._Grid(group, stick_slip.run_cycles())
    lo, hi, theta_lo = grid.interval(spin)
    p = problem.p
    kappa = spin**2 * abs(p[P_C] - p[P_A]) * math.sin(2.0 * theta_lo) / (2.0 * p[P_FRIC + 1])
    if theta_lo > stick_slip_map.THETA_LOW + 1e-12:
        assert kappa == pytest.approx(stick_slip_family.KAPPA_END, rel=1e-12)
    else:
        assert kappa <= stick_slip_family.KAPPA_END
    assert lo == pytest.approx(stick_slip_map.abscissa(theta_lo))
    assert hi == pytest.approx(stick_slip_map.abscissa(grid.theta0))


def test_no_grid_where_few_cycles_are_left_to_skip():
    """160-175 rad/s: kappa reaches KAPPA_END within a cycle or two of release (the
    estimate from the first node's drop, D ~ (sin theta cos theta)^3), so no grid is built
    (one node cycle integrated at most) and the cases run as on their own."""
    spins = np.linspace(161.0, 174.0, 12)  # in [1.15^36, 1.15^37) = [153.2, 176.2)
    problems, controls = _setups(spins)
    maps, counts = stick_slip_family.shared_maps(problems, controls)
    assert maps == [None] * len(spins)
    assert counts[2] < 400  # the steps of at most one cycle


def test_maps_do_not_depend_on_the_order_or_the_other_cases(band):
    """The same cases shuffled, or each alone after the band's grids were dropped, get
    the same maps: a map is a function of its case."""
    problems, controls, maps, _ = band
    order = np.random.default_rng(3).permutation(len(SPINS))
    stick_slip_family._MEMO.clear()
    shuffled, _ = stick_slip_family.shared_maps(
        [problems[i] for i in order], [controls[i] for i in order]
    )
    stick_slip_family._MEMO.clear()
    alone = stick_slip_family.band_map(problems[5], controls[5])
    np.testing.assert_array_equal(alone.c_logd, maps[5].c_logd)
    for j, i in enumerate(order):
        np.testing.assert_array_equal(shuffled[j].c_logd, maps[i].c_logd)
        np.testing.assert_array_equal(shuffled[j].c_time, maps[i].c_time)


def test_a_failing_node_leaves_the_cases_to_run_alone(band, monkeypatch):
    """A node integration that raises gives no map (the cases' own runs report their
    failures), not an error of the whole batch."""
    problems, controls, _, _ = band

    def broken(self, theta):
        raise ZeroDivisionError("node")

    monkeypatch.setattr(stick_slip_map._Nodes, "cycle", broken)
    monkeypatch.setattr(stick_slip_family, "_MEMO", type(stick_slip_family._MEMO)())
    maps, _ = stick_slip_family.shared_maps(problems, controls)
    assert maps == [None] * len(SPINS)
