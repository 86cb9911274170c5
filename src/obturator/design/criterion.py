"""The discrimination criterion and the plan search.

Criterion: Box and Hill (1967), "Discrimination among mechanistic models",
Technometrics 9(1), 57-71. For one run with predictive distributions
N(y_i, sigma^2 + sigma_i^2) under model i (sigma the replicate noise, sigma_i^2 the
model's parameter uncertainty), their upper bound on the expected entropy change is

    D = sum_{i<j} P_i P_j J_ij,

J_ij = KL(p_i || p_j) + KL(p_j || p_i) the symmetric (Jeffreys) divergence between the
predictive distributions, P_i the prior model probabilities. KL(p_i || p_j) is the
expected log Bayes factor of i over j when i is true, so D is the expected log Bayes
factor in both directions. For a plan of N runs the predictive distributions are the
joint Gaussians N(mu_i, Sigma_i) of the N runs (Sigma_i = parameter covariance + noise,
so runs that share a model's parameter uncertainty are not counted as independent),
and the same formula applies with the multivariate KL divergence

    KL = 1/2 [tr(S_j^-1 S_i) + (mu_j - mu_i)^T S_j^-1 (mu_j - mu_i) - N + ln det S_j / det S_i].

Search: greedy (add the run that raises D most), then Fedorov's exchange (replace any
run by any candidate while D rises); runs may repeat a setting (replicates).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "EXCHANGE_PASSES",
    "box_hill",
    "gaussian_kl",
    "greedy_exchange",
    "jeffreys",
    "plan_value",
    "plan_values",
]


def gaussian_kl(
    mu0: NDArray[np.float64], cov0: NDArray[np.float64], mu1: NDArray[np.float64], cov1: NDArray
) -> float:
    """KL(N(mu0, cov0) || N(mu1, cov1)) [nats] of multivariate Gaussians (closed form).

    1-D arrays and scalars are accepted (a single run: cov as variance).
    """
    m0, m1 = np.atleast_1d(mu0).astype(float), np.atleast_1d(mu1).astype(float)
    s0 = np.atleast_2d(cov0).astype(float)
    s1 = np.atleast_2d(cov1).astype(float)
    n = m0.size
    l1 = np.linalg.cholesky(s1)
    l0 = np.linalg.cholesky(s0)
    a = np.linalg.solve(l1, l0)  # L1^-1 L0: tr(S1^-1 S0) = ||A||_F^2
    d = np.linalg.solve(l1, m1 - m0)
    logdet = 2.0 * (np.sum(np.log(np.diag(l1))) - np.sum(np.log(np.diag(l0))))
    return 0.5 * (float(np.sum(a * a)) + float(d @ d) - n + logdet)


def jeffreys(mu0: NDArray, cov0: NDArray, mu1: NDArray, cov1: NDArray) -> float:
    """Symmetric divergence KL(0||1) + KL(1||0) [nats]."""
    m0, m1 = np.atleast_1d(mu0).astype(float), np.atleast_1d(mu1).astype(float)
    l0 = np.linalg.cholesky(np.atleast_2d(cov0).astype(float))
    l1 = np.linalg.cholesky(np.atleast_2d(cov1).astype(float))
    return float(_jeffreys_factored(m0, l0, m1, l1))


def _jeffreys_factored(
    m0: NDArray[np.float64], l0: NDArray[np.float64], m1: NDArray[np.float64], l1: NDArray
) -> NDArray[np.float64]:
    """:func:`jeffreys` from the Cholesky factors L0, L1 of the covariances, over any
    leading (stacked) axes. The log determinants of the two directions cancel:
    J = (tr(S1^-1 S0) + tr(S0^-1 S1) + d' (S0^-1 + S1^-1) d) / 2 - n with d = mu1 - mu0,
    each term a squared Frobenius norm of one triangular solve with the other factor and
    d as right-hand sides."""
    d = (m1 - m0)[..., None]
    a = np.linalg.solve(l1, np.concatenate((l0, d), axis=-1))  # L1^-1 [L0, d]
    b = np.linalg.solve(l0, np.concatenate((l1, d), axis=-1))  # L0^-1 [L1, d]
    return 0.5 * (np.sum(a * a, axis=(-2, -1)) + np.sum(b * b, axis=(-2, -1))) - m0.shape[-1]


def box_hill(
    means: Sequence[NDArray[np.float64]],
    covs: Sequence[NDArray[np.float64]],
    prior: Sequence[float] | None = None,
) -> float:
    """Box-Hill D = sum_{i<j} P_i P_j J_ij over the models' predictive Gaussians (each
    covariance factored once for all its pairs)."""
    mus = [np.atleast_1d(mu).astype(float) for mu in means]
    chol = [np.linalg.cholesky(np.atleast_2d(c).astype(float)) for c in covs]
    return float(_box_hill_factored(mus, chol, prior))


def _box_hill_factored(
    mus: Sequence[NDArray[np.float64]],
    chol: Sequence[NDArray[np.float64]],
    prior: Sequence[float] | None = None,
) -> NDArray[np.float64]:
    """:func:`box_hill` from the models' means and covariance factors, over any leading
    (stacked) axes: one value per stacked plan."""
    m = len(mus)
    p = np.full(m, 1.0 / m) if prior is None else np.asarray(prior, dtype=float)
    return sum(  # type: ignore[return-value]
        p[i] * p[j] * _jeffreys_factored(mus[i], chol[i], mus[j], chol[j])
        for i in range(m)
        for j in range(i + 1, m)
    )


def plan_value(
    surrogates: Iterable[Any], noise_sd: NDArray[np.float64], plan: Sequence[int]
) -> float:
    """Box-Hill D of a plan (setting indices) from the models' surrogates and the noise SD."""
    return float(plan_values(surrogates, noise_sd, np.asarray([plan], dtype=np.intp))[0])


def plan_values(
    surrogates: Iterable[Any], noise_sd: NDArray[np.float64], plans: NDArray[np.intp]
) -> NDArray[np.float64]:
    """Box-Hill D of each plan, `plans` an integer array (P, N): one plan of N setting
    indices per row. All the plans at once (stacked covariances, one LAPACK call per
    stack): the plan search asks for every candidate of one step together, and one plan
    at a time its Python overhead was most of design-experiment's search."""
    idx = np.asarray(plans, dtype=np.intp)
    diag = np.arange(idx.shape[-1])
    mus, chol = [], []
    for s in surrogates:
        cov = s.covariance(idx)  # (P, N, N)
        cov[..., diag, diag] += noise_sd[idx] ** 2
        mus.append(s.mean(idx))
        chol.append(np.linalg.cholesky(cov))
    return _box_hill_factored(mus, chol)


#: Most exchange passes of :func:`greedy_exchange` after its greedy start.
EXCHANGE_PASSES = 6


def greedy_exchange(
    n_runs: int,
    candidates: Sequence[int],
    value: Callable[[NDArray[np.intp]], NDArray[np.float64]],
    max_passes: int = EXCHANGE_PASSES,
    advance: Callable[[int], None] | None = None,
) -> tuple[list[int], float]:
    """Maximise the value of plans of `n_runs` candidates (repeats allowed).

    Greedy start, then exchange passes until a pass improves D by less than 1e-9
    relative or `max_passes` have run. `value(plans)` gives the value of each row of an
    integer array (P, n_runs) of candidates: every plan of one greedy step, or of one
    position's exchanges, is asked for in one call (as :func:`plan_values` takes them).
    Returns the plan (sorted) and its value. `advance(k)`, if given, is told of each of
    the ``n_runs * (1 + max_passes)`` steps (a run placed, a position exchanged; the
    passes not needed at the end, at once).
    """
    step = advance or (lambda k: None)
    cands = np.asarray(candidates, dtype=np.intp)
    plan = np.empty(0, dtype=np.intp)
    for _ in range(n_runs):
        trials = np.column_stack((np.tile(plan, (cands.size, 1)), cands))
        plan = np.append(plan, cands[int(np.argmax(value(trials)))])
        step(1)
    best = float(value(plan[None, :])[0])
    passes = 0
    for _ in range(max_passes):
        start = best
        passes += 1
        for pos in range(n_runs):
            # the other positions stay fixed while this one is exchanged: every candidate
            # for it at once, then taken in order wherever it beats the best so far
            others = cands[cands != plan[pos]]
            trials = np.tile(plan, (others.size, 1))
            trials[:, pos] = others
            for c, v in zip(others.tolist(), value(trials).tolist(), strict=True):
                if v > best * (1.0 + 1e-12):
                    best, plan[pos] = v, c
            step(1)
        if not best > start * (1.0 + 1e-9) or not math.isfinite(best):
            break
    step(n_runs * (max_passes - passes))
    return sorted(plan.tolist()), best
