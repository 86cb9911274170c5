"""The batched Radau IIA (stiff points of a sweep in lanes) against the scalar Radau IIA,
for the thesis kernel and the generic right-hand side (Coulomb contact patch, the tanh
and linear friction families, rig and flight: ``KERNELS``).

References are not produced by the code under test: every t_cr is compared with
:func:`obturator.solve.opening_time` (``regularised``: DOP853 handing the run to the
one-trajectory Radau IIA of :mod:`obturator.core.integrators.radau`), a separate
implementation of the same method, and a few points with Radau IIA at rtol
1e-11. The lanes may round differently from the scalar code (vectorised LU), and
near stick the trajectory amplifies rounding, so agreement is required to 1e-6
relative, not to the bit. Measured on the 1,786 near-stick points (100-207 rad/s)
of a 10,000-point sweep (``python -m benchmarks.dense_accuracy``): lanes vs scalar
<= 4.1e-8 at the default rtol 1e-8 and <= 4.3e-10 at rtol 1e-10
(``SolverOptions.for_opening_time_accuracy(1e-6)``), the lanes within 1.2e-7 and
5.0e-8 of Radau IIA at rtol 1e-12. (Before ``auto`` ran Radau IIA at a third of
the tolerances, rtol 1e-8 left single near-stick points up to 1.7e-4 apart.)
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from obturator.core.integrators import HandOff
from obturator.core.integrators.lanes import LANES, integrate_radau_lanes
from obturator.model.cases import flight_case, rig_case
from obturator.solve import (
    OPENING_TIME_ACCURACY,
    SolverOptions,
    integration_setup,
    opening_time,
    opening_times,
)
from obturator.solve import many as batch
from obturator.status import Status

#: Fewest stiff points the batches below put in the Radau IIA lanes (they take every one).
RADAU_LANES_MIN = 32

# the lanes themselves, also for groups lanes_pay_from would run one by one
pytestmark = pytest.mark.usefixtures("lanes_always")

MU_S = 0.5473  # thesis's rig value
# near-stick band of the rig at the thesis's mu_s: DOP853 reports stiffness below ~215 rad/s
STIFF_BAND = np.linspace(100.0, 210.0, 40)
# flight with Coulomb contacts at the same mu_s: DOP853 reports stiffness at every point of
# 4000-6500 rad/s; the ball opens by t_max = 0.5 s only at the top of the band
FLIGHT_STIFF_BAND = np.linspace(4000.0, 6500.0, 40)


#: The regularised law (the Radau IIA lanes are its; ``auto`` gives these spins to the
#: set-valued solver).
REGULARISED = SolverOptions(method="regularised")
ACCURATE = SolverOptions.for_opening_time_accuracy(1e-6, method="regularised")


def _scalar(case, options=ACCURATE):
    return opening_time(case, options)


# The kernels the Radau IIA lanes meet, each on near-stick points that DOP853 hands over:
# (case builder, its keywords, SolverOptions keywords). "thesis" runs the specialised
# kernel; the others the generic right-hand side (Coulomb contact with pivot friction of a
# finite patch, the tanh and linear regularisation families of Eq. 61's magnitude).
KERNELS = {
    "thesis": (rig_case, {}, {}),
    "coulomb-patch": (rig_case, {"torque_model": "coulomb"}, {}),
    "tanh": (rig_case, {}, {"friction_family": "tanh"}),
    "linear": (rig_case, {}, {"friction_family": "linear"}),
    "flight-coulomb": (flight_case, {"torque_model": "coulomb"}, {}),
}


def _kernel_batch(kernel):
    """Cases and options of KERNELS[kernel] over the near-stick band (thesis's mu_s)."""
    make, kw, opt = KERNELS[kernel]
    band = FLIGHT_STIFF_BAND if make is flight_case else STIFF_BAND
    return [make(float(w), MU_S, **kw) for w in band], SolverOptions.for_opening_time_accuracy(
        1e-6, method="regularised", **opt
    )


@pytest.fixture(scope="module", params=list(KERNELS))
def stiff_batch(request):
    """opening_times of one kernel's near-stick batch, and how many points the Radau IIA
    lanes took (a spy on integrate_radau_lanes: the comparison below must not pass
    because every point went one by one). With ``radau_lanes`` (the default) every stiff
    point of every kernel continues in the lanes."""
    cases, options = _kernel_batch(request.param)
    in_lanes = []

    def spy(y0, *rest):
        in_lanes.append(y0.shape[0])
        return lanes_radau(y0, *rest)

    lanes_radau = batch.integrate_radau_lanes
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(batch, "integrate_radau_lanes", spy)
        t, s, stats = opening_times(cases, options)
    return cases, options, t, s, stats, in_lanes


def test_every_stiff_point_matches_scalar_radau(stiff_batch):
    """Every kernel: each t_cr within 1e-6 of the scalar ``auto`` path (DOP853 handing
    over to the one-trajectory Radau IIA, an independent implementation), not opened
    (NaN) where it is not; the lanes ran on at least RADAU_LANES_MIN points. On the rig
    every point opens and points went back to the DOP853 lanes; in flight the top of
    the band opens."""
    cases, options, t, s, stats, in_lanes = stiff_batch
    assert stats["n_stiff"] >= RADAU_LANES_MIN and in_lanes[0] >= RADAU_LANES_MIN
    if cases[0].name == "spin-rig":
        assert stats["n_hand_backs"] > 0 and np.all(s == Status.OPENED)
    else:
        assert set(s) == {Status.OPENED, Status.T_MAX}
    ref = np.array([_scalar(c, options) for c in cases])
    np.testing.assert_allclose(t, ref, rtol=1e-6, atol=0.0)  # NaN where ref is NaN


def test_same_as_one_by_one_hand_over(stiff_batch):
    """``radau_lanes=False`` continues the same points one by one (scalar Radau IIA)."""
    cases, options, t, s, _, _ = stiff_batch
    t1, s1, stats = opening_times(cases, replace(options, radau_lanes=False))
    np.testing.assert_array_equal(s, s1)
    np.testing.assert_allclose(t, t1, rtol=1e-6, atol=0.0)


@pytest.mark.parametrize("stiff_batch", ["thesis"], indirect=True)
@pytest.mark.parametrize("w", [100.0, 150.0, 205.0])
def test_against_tight_radau(stiff_batch, w):
    """Accuracy, not only agreement: within 1e-6 of Radau IIA at rtol 1e-11."""
    cases, options, t, _, _, _ = stiff_batch
    k = int(np.argmin(np.abs(STIFF_BAND - w)))
    tight = _scalar(cases[k], replace(options, method="radau", rtol=1e-11, atol=1e-13))
    assert t[k] == pytest.approx(tight, rel=1e-6)


def test_default_tolerances_statuses_and_accuracy():
    """At the default rtol 1e-8: every point opens, within 1e-6 of the scalar path (on
    the 1,786 near-stick points of the dense check at most 4.2e-8 apart; the range-wide
    accuracy of rtol 1e-8 in ``OPENING_TIME_ACCURACY`` is set by the runs below 100
    rad/s, and the lanes hold it here too)."""
    cases = [rig_case(float(w), MU_S) for w in STIFF_BAND]
    t, s, stats = opening_times(cases, REGULARISED)
    assert stats["n_stiff"] >= RADAU_LANES_MIN and np.all(s == Status.OPENED)
    assert OPENING_TIME_ACCURACY[0][1] == 1e-8 and OPENING_TIME_ACCURACY[0][0] >= 1e-6
    ref = np.array([opening_time(c, REGULARISED) for c in cases])
    np.testing.assert_allclose(t, ref, rtol=1e-6, atol=0.0)


def _direct(cases, n_lanes, t_max=None, max_steps=None, start=None, hand_back=False):
    """integrate_radau_lanes from t = 0 (no DOP853 before it) or from `start`, a list
    of (t0, y0)."""
    opts = REGULARISED
    setups = [integration_setup(c, opts) for c in cases]
    pr = [s[0] for s in setups]
    ct = [s[1] for s in setups]
    n = len(cases)
    y0 = np.array([p.y0 for p in pr]) if start is None else np.array([y for _, y in start])
    t0 = np.zeros(n) if start is None else np.array([t for t, _ in start])
    return integrate_radau_lanes(
        y0, t0, np.array([p.p for p in pr]),
        np.array([p.scale for p in pr]),
        np.array([c.t_max if t_max is None else t_max for c in ct]),
        np.array([c.h0 for c in ct]), np.array([c.h_max for c in ct]),
        np.array([c.max_steps if max_steps is None else max_steps for c in ct]),
        np.full(n, hand_back), np.arange(n), opts.rtol, opts.atol, opts.event_tol, n_lanes,
        LANES,
    )  # fmt: skip


def test_hand_back_where_the_scalar_radau_hands_back(raw):
    """From DOP853's stiff state, each lane stops with NONSTIFF (sliding resumed) within
    a step of where the one-trajectory Radau IIA (:mod:`obturator.core.integrators.radau`,
    a separate implementation) stops: the lanes round differently, which near stick
    moves the step grid, and the hand-back is checked after each accepted step. Without
    `hand_back` both run to the opening."""
    cases = [rig_case(float(w), MU_S) for w in (120.0, 150.0, 180.0, 205.0)]
    opts = REGULARISED
    dop = [raw(c, opts, method="dop853")[0] for c in cases]
    assert all(d.status == HandOff.STIFF for d in dop)
    start = [(d.t_end, d.y_end) for d in dop]
    st, _, t_end, y_end, *_ = _direct(cases, LANES, start=start, hand_back=True)
    for k, (c, d) in enumerate(zip(cases, dop, strict=True)):
        ref, _ = raw(c, opts, method="radau", y0=d.y_end, t0=d.t_end, hand_back=True)
        assert st[k] == ref.status == HandOff.NONSTIFF
        h_max = integration_setup(c, opts)[1].h_max
        assert abs(t_end[k] - ref.t_end) <= h_max
    st, *_ = _direct(cases, LANES, start=start, hand_back=False)
    assert np.all(st == Status.OPENED)


@pytest.mark.parametrize("n_lanes", [1, 5])
def test_lane_count_does_not_change_results(n_lanes):
    """Each lane's arithmetic depends on its own data only: the same t_cr, to the bit,
    whether a point shares the vector loops with others or not (refill and packing)."""
    cases = [rig_case(float(w), MU_S) for w in np.linspace(140.0, 200.0, 9)]
    full = _direct(cases, LANES)
    part = _direct(cases, n_lanes)
    np.testing.assert_array_equal(full[0], part[0])
    np.testing.assert_array_equal(full[1], part[1])
    assert np.all(full[0] == Status.OPENED)


def test_statuses_t_max_and_step_limit():
    """Not opened by t_max and the step limit, as the scalar Radau IIA reports them."""
    cases = [rig_case(150.0, MU_S), rig_case(180.0, MU_S)]
    st, t_ev, _, _, nfev, steps, _ = _direct(cases, LANES, t_max=0.05)
    assert list(st) == [Status.T_MAX] * 2 and np.all(np.isnan(t_ev))
    st, t_ev, _, _, _, steps, _ = _direct(cases, LANES, max_steps=20)
    assert list(st) == [Status.STEP_LIMIT] * 2 and list(steps) == [20, 20]
    assert np.all(nfev > 0)


def test_width_must_be_lane_count():
    with pytest.raises(ValueError, match="LANES"):
        _direct_width([rig_case(150.0, MU_S)], 8)


def _direct_width(cases, vw):
    opts = REGULARISED
    p, c = integration_setup(cases[0], opts)
    one = np.ones(1)
    return integrate_radau_lanes(
        p.y0[None], 0.0 * one, p.p[None], p.scale[None], c.t_max * one, c.h0 * one,
        c.h_max * one, np.full(1, c.max_steps), np.zeros(1, dtype=bool),
        np.zeros(1, dtype=np.int64), opts.rtol, opts.atol, opts.event_tol, 1, vw,
    )  # fmt: skip


def test_few_stiff_points_take_the_lanes_as_many_do():
    """A stiff point continues in the Radau IIA lanes however few share its batch (the
    route is the point's own, solve/plan.py): two stiff points give each the t_cr it has
    alone, bit for bit."""
    cases = [rig_case(float(w), MU_S) for w in (120.0, 160.0, 400.0)]
    t, s, stats = opening_times(cases, REGULARISED)
    assert stats["n_stiff"] == 2 and all(math.isfinite(x) for x in t)
    for k, case in enumerate(cases):
        np.testing.assert_array_equal(opening_times([case], REGULARISED)[0], t[k : k + 1])


def test_lane_lu_solves_match_numpy():
    """The lane LU (per-lane pivoting, generated solves) solves random real and complex systems
    as numpy.linalg.solve does, with row interchanges in some lanes and a singular lane
    reported as such."""
    from obturator.core.integrators.lanes.lu import lu_factor_complex_lanes, lu_factor_lanes
    from obturator.core.integrators.lanes.solves import lu_solve_lanes, lu_solve_pair_lanes

    rng = np.random.default_rng(5)
    n = 8
    a = rng.normal(size=(LANES, n, n)) + 4.0 * np.eye(n)
    a[3] = rng.normal(size=(n, n))  # no diagonal dominance: pivoting
    a[5] = a[5][::-1]  # rows reversed: interchanges at every column
    c = rng.normal(size=(LANES, n, n)) + 1j * rng.normal(size=(LANES, n, n))
    b = rng.normal(size=(LANES, n))
    bc = rng.normal(size=(LANES, n)) + 1j * rng.normal(size=(LANES, n))

    def mat(x):
        return np.ascontiguousarray(np.transpose(x, (1, 2, 0))).ravel()

    def vec(x):
        return np.ascontiguousarray(x.T).ravel()

    m, mr, mi = mat(a), mat(c.real), mat(c.imag)
    piv, pivc = np.zeros(n * LANES), np.zeros(n * LANES)
    sw, swc = np.zeros(n, dtype=np.bool_), np.zeros(n, dtype=np.bool_)
    ok, scratch = np.ones(LANES, dtype=np.bool_), np.zeros(LANES)
    lu_factor_lanes(m, piv, sw, ok, scratch, LANES)
    lu_factor_complex_lanes(mr, mi, pivc, swc, ok, scratch, LANES)
    assert ok.all() and sw.any()
    x, xr, xi, x2 = vec(b), vec(bc.real), vec(bc.imag), vec(b)
    lu_solve_pair_lanes(m, piv, sw, x, mr, mi, pivc, swc, xr, xi, LANES)
    lu_solve_lanes(m, piv, sw, x2, LANES)
    want = np.linalg.solve(a, b[..., None])[..., 0]
    want_c = np.linalg.solve(c, bc[..., None])[..., 0]
    np.testing.assert_allclose(x.reshape(n, LANES).T, want, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(x2, x, rtol=0.0, atol=0.0)
    got_c = (xr + 1j * xi).reshape(n, LANES).T
    np.testing.assert_allclose(got_c, want_c, rtol=1e-10, atol=1e-12)
    a[7, :, 2] = 0.0  # a zero column: singular
    ok[:] = True
    lu_factor_lanes(mat(a), piv, sw, ok, scratch, LANES)
    assert list(np.flatnonzero(~ok)) == [7]


def test_generated_lane_lu_is_current():
    """lanes/solves.py is what tools/gen_lane_linalg.py writes."""
    import subprocess
    import sys
    from pathlib import Path

    tool = Path(__file__).resolve().parents[2] / "tools" / "gen_lane_linalg.py"
    if not tool.exists():  # pragma: no cover - installed package without the repository
        pytest.skip("tools/ not present")
    assert subprocess.run([sys.executable, str(tool), "--check"]).returncode == 0
