"""The explicit fused multiply-add of the compiled core (:mod:`obturator.core.fma`).

Reference: exact rational arithmetic (:class:`fractions.Fraction`), rounded once by
Python's correctly rounded int / int division, an independent computation of IEEE 754's
fusedMultiplyAdd.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from numba import njit

from obturator.core.fma import fma

finite = st.floats(min_value=-1e150, max_value=1e150, allow_nan=False, allow_infinity=False)


@njit(cache=False, fastmath=False, error_model="numpy")
def _scalar(a, b, c):
    return fma(a, b, c)


@njit(cache=False, fastmath=False, error_model="numpy")
def _vector(a, b, c, out):
    for j in range(a.shape[0]):  # a loop LLVM vectorises, with a scalar remainder
        out[j] = fma(a[j], b[j], c[j])


def _exact(a: float, b: float, c: float) -> float:
    q = Fraction(a) * Fraction(b) + Fraction(c)
    return q.numerator / q.denominator


@settings(max_examples=300, deadline=None)
@given(finite, finite, finite)
def test_fma_rounds_once(a, b, c):
    """fma(a, b, c) is a * b + c computed exactly and rounded once."""
    got = _scalar(a, b, c)
    want = _exact(a, b, c)
    assert got == want or (got == 0.0 and want == 0.0)


def test_fma_differs_from_two_roundings():
    """(1 + 2^-30)(1 - 2^-30) - 1 = -2^-60 exactly; rounded twice it is 0."""
    a, b = 1.0 + 2.0**-30, 1.0 - 2.0**-30
    assert a * b - 1.0 == 0.0
    assert _scalar(a, b, -1.0) == -(2.0**-60)


def test_fma_is_the_same_in_a_vector_loop_and_alone():
    """Each element of a vectorised loop (body and remainder: 37 elements) has the bits of
    the scalar call: the fusion does not depend on the context it is compiled in."""
    rng = np.random.default_rng(3)
    a, b, c = (rng.normal(size=37) * 10.0 ** rng.integers(-8, 8, 37) for _ in range(3))
    out = np.empty(37)
    _vector(a, b, c, out)
    alone = np.array([_scalar(x, y, z) for x, y, z in zip(a, b, c, strict=True)])
    np.testing.assert_array_equal(out, alone)
    assert all(out[j] == _exact(a[j], b[j], c[j]) for j in range(37))


def test_fma_converts_integers_and_propagates_nan():
    """Integer operands are converted as in ``a * b + c``; NaN and inf as IEEE 754 says."""
    assert _scalar(2, 3, 1) == 7.0
    assert math.isnan(_scalar(math.inf, 0.0, 1.0))
    assert math.isnan(_scalar(1.0, 1.0, math.nan))
    assert _scalar(1e308, 10.0, -math.inf) == -math.inf
