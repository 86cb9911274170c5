"""The flat parameter vector of the compiled core, and the codes it dispatches on.

The numba kernels take plain floats: a :class:`~obturator.model.case.Case` and
:class:`~obturator.solve.SolverOptions` are packed once into ``p``
(:func:`obturator.solve.pack_parameters`), and the right-hand side reads its
slots below. Torque models pack their own block (``pack()`` methods in
:mod:`obturator.model.torques`), tagged with the ``VISC_*``/``FRIC_*`` codes.
"""

from __future__ import annotations

from ..vocab import FORMULATIONS, FRICTION_FAMILIES, SPEED_LAWS, SPIN_MODES

__all__ = [
    "N_STATE",
    "N_PARAM",
    "P_A",
    "P_C",
    "P_IP",
    "P_SPIN_MODE",
    "P_KE0",
    "P_FORM",
    "P_WIDTH",
    "P_THETA_CR",
    "P_VISC",
    "P_FRIC",
    "P_FAMILY",
    "P_SPEED",
    "P_KERNEL",
    "P_DERIVED",
    "KERNEL_GENERIC",
    "KERNEL_THESIS",
    "KERNEL_THESIS_WEAKENING",
    "KERNEL_THESIS_STRENGTHENING",
    "THESIS_KERNELS",
    "FORM_CODES",
    "SPIN_CODES",
    "FAMILY_CODES",
    "SPEED_CODES",
]

#: Length of the state vector (both formulations).
N_STATE = 8

# Slots of p: inertias A, C, I_p [kg m^2]; spin-mode code; kinetic energy at
# release [J] (Appendix A's energy form); formulation code; regularisation
# width delta [rad/s]; opening angle theta_cr [rad].
P_A, P_C, P_IP, P_SPIN_MODE, P_KE0, P_FORM, P_WIDTH, P_THETA_CR = range(8)
P_VISC = 8  # code, S, K_turb, omega_transition
P_FRIC = 12  # code, moment scale, R_s, beta, n_contacts, pivot arm eps
P_FAMILY = 18  # regularisation family of the Coulomb magnitude
P_SPEED = 19  # slip-speed law of mu: code, ratio r, reference speed v_s [m/s]
# Right-hand-side kernel code and the derived coefficients of the specialised kernel
# (filled by obturator.core.specialised.specialise, from the slots above):
# 1/A, 1/C, C - A, free-spin factor 1/I_p (0 for a constant spin), moment M,
# delta^2, arm weights b_X, b_Z (ARM^2 |omega_r|^2 = b_X w_X^2 + w_Y^2 + b_Z w_Z^2).
P_KERNEL = 22
P_DERIVED = 23
N_PARAM = 31

FORM_QUATERNION, FORM_EULER = 0, 1
SPIN_CONSTANT, SPIN_FREE, SPIN_THESIS_ENERGY = 0, 1, 2
FAMILY_ALGEBRAIC, FAMILY_TANH, FAMILY_LINEAR = 0, 1, 2
SPEED_CONSTANT, SPEED_WEAKENING, SPEED_STRENGTHENING = 0, 1, 2
VISC_NONE, VISC_LINEAR = 0, 1
FRIC_NONE, FRIC_THESIS_RIG, FRIC_THESIS_FLIGHT, FRIC_COULOMB = 0, 1, 2, 3
# the thesis kernel, one variant per slip-speed law of mu (compiled apart: the constant
# mu_s of the default pays nothing for the others)
KERNEL_GENERIC, KERNEL_THESIS, KERNEL_THESIS_WEAKENING, KERNEL_THESIS_STRENGTHENING = 0, 1, 2, 3
THESIS_KERNELS = (KERNEL_THESIS, KERNEL_THESIS_WEAKENING, KERNEL_THESIS_STRENGTHENING)

# name (obturator.vocab) -> code
FORM_CODES = dict(zip(FORMULATIONS, (FORM_QUATERNION, FORM_EULER), strict=True))
SPIN_CODES = dict(zip(SPIN_MODES, (SPIN_CONSTANT, SPIN_FREE, SPIN_THESIS_ENERGY), strict=True))
FAMILY_CODES = dict(
    zip(FRICTION_FAMILIES, (FAMILY_ALGEBRAIC, FAMILY_TANH, FAMILY_LINEAR), strict=True)
)
SPEED_CODES = dict(
    zip(SPEED_LAWS, (SPEED_CONSTANT, SPEED_WEAKENING, SPEED_STRENGTHENING), strict=True)
)
