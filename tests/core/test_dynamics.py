"""Equations of motion: torque-free limits, formulations, energy (thesis Eqs. 5, 13-18)."""

import math

import numpy as np
import pytest

from obturator import (
    Case,
    InputError,
    SolverOptions,
    TorqueModel,
    initial_state,
    rig_case,
    simulate,
)
from obturator.core.dynamics import rhs
from obturator.core.layout import N_STATE
from obturator.model.cases import table1_ball
from obturator.solve import pack_parameters

BALL = table1_ball()
A, C = BALL.transverse_inertia, BALL.axial_inertia
LAM = C / A - 1.0
THETA0 = math.radians(87.25)


def torque_free(spin=300.0, t_max=0.1, theta0=THETA0):
    return Case(BALL, TorqueModel(), spin, theta0, t_max=t_max)


def inertial_momentum(res):
    """H = R I w in inertial axes from the quaternion state (independent of the solver)."""
    out = []
    for y in res.state:
        q = y[:4] / np.linalg.norm(y[:4])
        q0, q1, q2, q3 = q
        r = np.array(
            [
                [1 - 2 * (q2**2 + q3**2), 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
                [2 * (q1 * q2 + q0 * q3), 1 - 2 * (q1**2 + q3**2), 2 * (q2 * q3 - q0 * q1)],
                [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), 1 - 2 * (q1**2 + q2**2)],
            ]
        )
        out.append(r @ (np.array([A, A, C]) * y[4:7]))
    return np.array(out)


@pytest.mark.parametrize("rtol", [1e-6, 1e-8, 1e-10])
def test_torque_free_body_rates_match_closed_form(rtol):
    # Closed form of Eqs. (5) with G = 0: w3 const, (w1, w2) rotate at lambda*w3.
    # Released co-rotating: w = omega_p (0, sin th0, cos th0) (Eq. 36 with phi = 0).
    spin = 300.0
    t = np.linspace(0.0, 0.1, 201)
    res = simulate(
        torque_free(spin), SolverOptions(rtol=rtol, atol=rtol * 1e-2), t_eval=t, terminal=False
    )
    w3 = spin * math.cos(THETA0)
    wt = spin * math.sin(THETA0)
    om = LAM * w3
    expected = np.column_stack([-wt * np.sin(om * t), wt * np.cos(om * t), np.full_like(t, w3)])
    err = np.max(np.abs(res.state[:, 4:7] - expected)) / spin
    # global error scales with the tolerance (order 2 method + error per unit step control)
    assert err < 200 * rtol
    assert res.status == 0


def test_torque_free_conserves_energy_and_angular_momentum():
    res = simulate(
        torque_free(12042.0, t_max=0.01), SolverOptions(rtol=1e-9, atol=1e-11), terminal=False
    )
    e = res.kinetic_energy
    assert np.max(np.abs(e - e[0])) / e[0] < 1e-7
    h = inertial_momentum(res)
    assert np.max(np.linalg.norm(h - h[0], axis=1)) / np.linalg.norm(h[0]) < 1e-7
    assert np.all(res.power == 0.0)


@pytest.mark.parametrize("formulation", ["quaternion", "euler"])
def test_steady_precession_eq18(formulation):
    # Eq. (18): psi_dot = C phi_dot / ((A - C) cos theta) gives theta_dot = 0 for all time.
    spin = 500.0
    theta0 = math.radians(60.0)
    phi_dot = (A - C) * math.cos(theta0) * spin / C
    y0 = initial_state(theta0, spin, formulation=formulation, phi_dot=phi_dot)
    opts = SolverOptions(rtol=1e-10, atol=1e-12, formulation=formulation)
    res = simulate(torque_free(spin, t_max=0.2, theta0=theta0), opts, y0=y0, terminal=False)
    # global error of a 2nd-order method over ~50k steps: a few hundred times rtol
    assert np.max(np.abs(res.theta - theta0)) < 1e3 * opts.rtol
    psi_rate = np.gradient(res.psi, res.t)
    assert np.median(psi_rate) == pytest.approx(spin, rel=1e-6)


def test_euler_angle_rhs_matches_quaternion_rhs_pointwise():
    # Same physical state in both formulations: d(theta)/dt from the quaternion rates must
    # equal the Euler form's theta_dot, and body accelerations must agree.
    case = rig_case(300.0, 0.5473)
    rng = np.random.default_rng(1)
    for _ in range(20):
        th, ps, ph = rng.uniform(0.2, 1.5), rng.uniform(-3, 3), rng.uniform(-3, 3)
        thd, psd, phd = rng.normal(0, 50, 3) + (0, 300, 0)
        ye = initial_state(
            th,
            300.0,
            formulation="euler",
            psi_dot=psd,
            phi_dot=phd,
            theta_dot=thd,
            psi0=ps,
            phi0=ph,
        )
        yq = initial_state(
            th,
            300.0,
            formulation="quaternion",
            psi_dot=psd,
            phi_dot=phd,
            theta_dot=thd,
            psi0=ps,
            phi0=ph,
        )
        pe = pack_parameters(case, SolverOptions(formulation="euler"), ye)
        pq = pack_parameters(case, SolverOptions(formulation="quaternion"), yq)
        de, dq = np.empty(N_STATE), np.empty(N_STATE)
        rhs(0.0, ye, pe, de)
        rhs(0.0, yq, pq, dq)
        # body angular acceleration from the Euler form, via the derivative of Eq. (13)
        sth, cth, sph, cph = math.sin(th), math.cos(th), math.sin(ph), math.cos(ph)
        thdd, psdd, phdd = de[1], de[3], de[5]
        w1d = (
            psdd * sth * sph
            + psd * (thd * cth * sph + phd * sth * cph)
            + thdd * cph
            - thd * phd * sph
        )
        w2d = (
            psdd * sth * cph
            + psd * (thd * cth * cph - phd * sth * sph)
            - thdd * sph
            - thd * phd * cph
        )
        w3d = phdd + psdd * cth - psd * thd * sth
        np.testing.assert_allclose([w1d, w2d, w3d], dq[4:7], rtol=1e-9, atol=1e-9 * 300**2)


@pytest.mark.parametrize("spin", [300.0, 700.0])
def test_both_formulations_agree_on_opening_time(spin):
    case = rig_case(spin, 0.5473)
    tq = simulate(case, SolverOptions(rtol=1e-9, atol=1e-11)).opening_time
    te = simulate(case, SolverOptions(rtol=1e-9, atol=1e-11, formulation="euler")).opening_time
    assert te == pytest.approx(tq, rel=1e-5)


@pytest.mark.parametrize("model", ["thesis", "coulomb"])
def test_relative_energy_never_increases_with_friction(model):
    # At constant projectile spin the Jacobi function T - omega_p H_Z obeys
    # d/dt = omega_r . G <= 0 for any dissipative torque.
    case = rig_case(400.0, 0.5473, torque_model=model, t_max=0.3)
    res = simulate(case, SolverOptions(rtol=1e-9, atol=1e-11), terminal=False)
    assert np.all(res.power <= 1e-15)
    j = res.jacobi_energy
    scale = np.max(np.abs(res.kinetic_energy))
    assert np.all(np.diff(j) <= 1e-9 * scale)
    assert j[-1] < j[0]


def test_free_projectile_conserves_axial_angular_momentum():
    case = rig_case(400.0, 0.5473, spin_mode="free", t_max=0.2)
    res = simulate(case, SolverOptions(rtol=1e-9, atol=1e-11), terminal=False)
    total = case.projectile_inertia * res.spin_rate + res.axial_momentum
    assert np.max(np.abs(total - total[0])) / abs(total[0]) < 1e-8
    assert res.spin_rate[-1] != res.spin_rate[0]  # the spin really is free


def test_thesis_energy_mode_keeps_total_kinetic_energy():
    # Appendix A recomputes omega_p so that ball + projectile kinetic energy stays at its
    # initial value (the thesis's assumption; labelled as such in the docs).
    case = rig_case(400.0, 0.5473, spin_mode="thesis-energy", t_max=0.2)
    res = simulate(case, SolverOptions(rtol=1e-9, atol=1e-11), terminal=False)
    total = res.kinetic_energy + 0.5 * case.projectile_inertia * res.spin_rate**2
    assert np.max(np.abs(total - total[0])) / total[0] < 1e-12


def test_result_exports(tmp_path):
    res = simulate(rig_case(450.0, 0.5473))
    ds = res.to_xarray()
    assert ds["theta"].attrs["units"] == "rad" and ds["t"].attrs["units"] == "s"
    assert ds.attrs["t_cr_s"] == res.opening_time
    assert ds.sizes["t"] == res.t.size
    path = tmp_path / "run.csv"
    res.to_csv(str(path))
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, 1], res.theta, rtol=1e-9)
    assert res.nfev > res.n_steps > 0 and res.success and res.opened


def test_release_state_body_rates_follow_eq13():
    # Eq. (13) written out: w1 = psi' s_th s_ph + th' c_ph, w2 = psi' s_th c_ph - th' s_ph,
    # w3 = phi' + psi' c_th; with phi_0 = 0 and the release rates of the Case.

    thd, phd, dpsi = 0.3, -0.2, 0.5
    case = rig_case(150.0, 0.5, release_rate=(thd, phd, dpsi), release_phase=1.1)
    y = case.initial_state()
    psd = 150.0 + dpsi
    th = case.theta0
    np.testing.assert_allclose(y[4:7], [thd, psd * math.sin(th), phd + psd * math.cos(th)])
    # psi_0 = 1.1 rad: the hole axis z = R[:, 2] lies at azimuth psi_0 - 90 deg (Fig. 7)
    q0, q1, q2, q3 = y[:4]
    zx = 2 * (q1 * q3 + q0 * q2)
    zy = 2 * (q2 * q3 - q0 * q1)
    assert math.atan2(zx, -zy) == pytest.approx(1.1)
    with pytest.raises(InputError):
        rig_case(150.0, 0.5, release_rate=(0.0, 0.0, 1e3))
