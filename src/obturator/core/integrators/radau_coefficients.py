"""Radau IIA (3 stages, order 5) coefficients, computed once at import.

Published data (Hairer & Wanner, *Solving Ordinary Differential Equations II*,
2nd ed., Sec. IV.8 and Table IV.5.6): the Butcher tableau (nodes
(4 -+ sqrt 6)/10, 1) and the embedded error estimate (gamma0 = 1/(3 + 3^(2/3)
- 3^(1/3)), weights (-13 - 7 sqrt 6, -13 + 7 sqrt 6, -1)/3). Derived here: the
real similarity T that brings A^-1 to block-diagonal form gamma (+) [alpha,
-beta; beta, alpha] (so each simplified-Newton iteration solves one real and
one complex 8x8 system instead of a 24x24 one), its entries as scalars
(``T00`` ... ``TI22``) for the compiled code, and the Lagrange weights of the
collocation polynomial on the nodes {0, c1, c2, 1}.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["RADAU_A", "RADAU_C", "TRANSFORM", "TRANSFORM_INV", "EIGENVALUES"]


def _tableau() -> tuple[np.ndarray, np.ndarray]:
    """Radau IIA (s = 3) Butcher matrix A and nodes c (Hairer & Wanner, Table IV.5.6)."""
    s6 = math.sqrt(6.0)
    a = np.array(
        [
            [(88.0 - 7.0 * s6) / 360.0, (296.0 - 169.0 * s6) / 1800.0, (-2.0 + 3.0 * s6) / 225.0],
            [(296.0 + 169.0 * s6) / 1800.0, (88.0 + 7.0 * s6) / 360.0, (-2.0 - 3.0 * s6) / 225.0],
            [(16.0 - s6) / 36.0, (16.0 + s6) / 36.0, 1.0 / 9.0],
        ]
    )
    c = np.array([(4.0 - s6) / 10.0, (4.0 + s6) / 10.0, 1.0])
    return a, c


def _block_transform(a: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, float, float]:
    """Real T with T^-1 A^-1 T = [[gamma, 0, 0], [0, alpha, -beta], [0, beta, alpha]]."""
    ainv = np.linalg.inv(a)
    lam, vec = np.linalg.eig(ainv)
    i_real = int(np.argmin(np.abs(lam.imag)))
    i_cplx = int(np.argmax(lam.imag))  # alpha + i beta with beta > 0
    v = vec[:, i_real].real
    x = vec[:, i_cplx]
    # A^-1 (u + i w) = (alpha + i beta)(u + i w) gives A^-1 [u, -w] = [u, -w] [[alpha, -beta],
    # [beta, alpha]]; scale so that the last row of T is (1, 1, 0) (Z3 = W1 + W2).
    t = np.column_stack([v / v[2], x.real, -x.imag])
    # make t[2, 1] = 1, t[2, 2] = 0 by a rotation within the complex pair (commutes with the block)
    ang = math.atan2(t[2, 2], t[2, 1])
    rot = np.array([[math.cos(ang), math.sin(ang)], [-math.sin(ang), math.cos(ang)]])
    t[:, 1:] = t[:, 1:] @ rot
    t[:, 1:] /= t[2, 1]
    ti = np.linalg.inv(t)
    return t, ti, float(lam[i_real].real), float(lam[i_cplx].real), float(lam[i_cplx].imag)


RADAU_A, RADAU_C = _tableau()
TRANSFORM, TRANSFORM_INV, GAMMA, ALPHA, BETA = _block_transform(RADAU_A)
#: gamma, alpha, beta: the eigenvalues of A^-1 are gamma and alpha +- i beta.
EIGENVALUES = (GAMMA, ALPHA, BETA)

S6 = math.sqrt(6.0)
C1 = float(RADAU_C[0])
C2 = float(RADAU_C[1])
# Embedded error estimate weights, already divided by gamma0 = 1/gamma (H&W IV.8, Eq. 8.20).
E1 = (-13.0 - 7.0 * S6) / 3.0
E2 = (-13.0 + 7.0 * S6) / 3.0
E3 = -1.0 / 3.0
# Lagrange denominators on the collocation nodes {0, c1, c2, 1}; the polynomial vanishes at 0.
D1 = C1 * (C1 - C2) * (C1 - 1.0)
D2 = C2 * (C2 - C1) * (C2 - 1.0)
D3 = 1.0 * (1.0 - C1) * (1.0 - C2)
RD1 = 1.0 / D1
RD2 = 1.0 / D2
RD3 = 1.0 / D3

T00, T01, T02 = (float(x) for x in TRANSFORM[0])
T10, T11, T12 = (float(x) for x in TRANSFORM[1])
T20, T21, T22 = (float(x) for x in TRANSFORM[2])
TI00, TI01, TI02 = (float(x) for x in TRANSFORM_INV[0])
TI10, TI11, TI12 = (float(x) for x in TRANSFORM_INV[1])
TI20, TI21, TI22 = (float(x) for x in TRANSFORM_INV[2])
