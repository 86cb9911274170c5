"""Models judged by what they predict: leave-one-cluster-out and leave-one-band-out scores.

AIC ranks the fits to all runs by their in-sample likelihood and a parameter count. A
model may win there and still predict badly where it was not fitted (a model fitted
to the high-spin runs alone can miss the low-spin ones by far more than another with
the same AIC). This module scores each candidate by
cross-validation over the natural units of the data:

* **leave one cluster out** (LOCO): each replicate cluster (:func:`.floor.cluster_runs`;
  29 on Appendix B) in turn is left out, the model refitted to the others and its
  prediction of the left-out runs kept; every run is predicted once;
* **leave one band out** (LOBO): the same with each spin band (:data:`.floor.BANDS`)
  left out: a prediction across a quarter of the spin range, the harder test.

Scores, over all runs: the rms prediction error [s] (a run the refit does not open by
t_max predicted at t_max) and the log predictive density, reported as
-2 sum log p(y_i | fit without i's fold) on the deviance scale of AIC (smaller is
better; AIC is its asymptotic approximation for independent runs, Stone 1977). The
predictive SD of a left-out run is the all-run fit's effective SD of that run (its
band's sigma and the spin error term), so the scores compare the models' mean curves.

Cost, bounded. Leaving out one cluster of 29 moves the optimum a little: the refit is
one Gauss-Newton step from the all-run optimum x_hat, dx = argmin ||r_keep + J_keep dx||
with the scaled residuals r and their Jacobian J at x_hat (central differences, the
step of the fit's covariance; slopes and sigmas the all-run fit's), the first-order
influence of the fold, exact for a model linear in its parameters; the left-out runs
are then predicted by exact solves at x_hat + dx. One Jacobian serves all 29 folds:
2k + 1 evaluations of the runs per model. A step longer than :data:`STEP_TRUSTED`
posterior SDs (along a flat valley, where one step is no longer a refit) is replaced by
the refit below. Leaving out a band moves it further: each of
the (at most four) folds is refitted by a least-squares pass from x_hat with the slopes
and sigmas held, as a profile probe. All folds of one model run in one task with one
:class:`.evaluate.ModelEvaluator` (its cache serves every fold at the shared start);
each model is one task of the study's runner, kept in its resume store.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..fitting import ParameterSet, central_jacobian
from ..solve import SolverOptions
from .candidates import CANDIDATES, PARAMETERS, Candidate
from .evaluate import ModelEvaluator
from .fit import COVARIANCE_STEP, Conditions, FitControls, RunModels, fit_candidate, predict
from .likelihood import nll_terms, scaled_residuals
from .results import CandidateFit

__all__ = ["SCHEMES", "cross_validation_task", "predictive_line"]

#: The two schemes, by their JSON key: (label of a fold, what a fold is).
SCHEMES: dict[str, str] = {
    "leave_one_cluster_out": "replicate cluster",
    "leave_one_band_out": "spin band",
}
_XTOL_FOLD = 1e-4
#: Longest one-step refit trusted [posterior SDs of the all-run fit]: leaving out one of
#: 29 clusters moves a well-determined optimum by a fraction of an SD; a longer step runs
#: along a valley where the linearisation fails, and that fold is refitted instead.
STEP_TRUSTED = 1.0


def _pick(conds: Sequence[Conditions] | None, mask: NDArray[np.bool_]) -> list[Conditions] | None:
    return None if conds is None else [c for c, m in zip(conds, mask, strict=True) if m]


def cross_validation_task(
    name: str,
    fit: CandidateFit,
    folds: dict[str, NDArray[np.int64]],
    spin_sd: float,
    options: SolverOptions | None,
) -> dict[str, dict[str, Any]]:
    """Every fold of every scheme of one candidate (a runner task; module notes).

    Parameters
    ----------
    name : str
        Candidate name.
    fit : CandidateFit
        Its fit to all observations (the start of every refit).
    folds : dict of str to ndarray of int
        Per scheme (a key of :data:`SCHEMES`), the fold label of every observation.
    spin_sd : float
        Spin error SD [rad/s].
    options : SolverOptions or None
        Solver settings.

    Returns
    -------
    dict
        Per scheme: ``rms_s``, ``deviance`` (-2 sum log p), ``n_folds``,
        ``n_refitted`` (folds with enough runs left to refit), ``predicted_s`` (per
        observation; NaN: not opened by t_max, or its fold not refitted).
    """
    cand = CANDIDATES[name]
    ev = ModelEvaluator(cand, fit.t_max, options)
    w, y, t_max = fit.spin_rate, fit.measured, fit.t_max
    conds = list(fit.conditions) if fit.conditions is not None else None
    step = _GaussNewtonStep(cand, fit, ev, conds) if cand.params else None
    out: dict[str, dict[str, Any]] = {}
    for scheme, labels in folds.items():
        pred = np.full(w.size, np.nan)
        done = np.zeros(w.size, dtype=bool)
        n_folds = n_refits = 0
        for fold in np.unique(labels):
            n_folds += 1
            test = labels == fold
            keep = ~test
            if step is None:
                pred[test] = fit.model[test]
                done[test] = True
                continue
            if int(keep.sum()) < cand.n_params + 2:
                continue
            if scheme == "leave_one_cluster_out":
                values, length = step.values_without(test)
                if length <= STEP_TRUSTED:
                    pred[test] = predict(
                        cand, values, w[test], evaluator=ev, conditions=_pick(conds, test)
                    )
                    done[test] = True
                    continue
                n_refits += 1  # a long step along a valley: refitted instead
            refit = fit_candidate(
                cand,
                w[keep],
                y[keep],
                band=fit.band[keep],
                run=fit.run[keep],
                start=dict(fit.values),
                spin_sd=spin_sd,
                t_max=t_max,
                options=options,
                evaluator=ev,
                controls=FitControls(
                    fit.slope[keep],
                    covariance=False,
                    xtol=_XTOL_FOLD,
                    sigma=fit.sigma_per_run[keep],
                ),
                noise=fit.noise,
                conditions=_pick(conds, keep),
            )
            pred[test] = predict(
                cand, refit.values, w[test], evaluator=ev, conditions=_pick(conds, test)
            )
            done[test] = True
        filled = np.where(np.isfinite(pred), pred, t_max)
        r = (filled - y)[done]
        dev = 2.0 * float(np.sum(nll_terms(y[done], pred[done], fit.sd[done], t_max)))
        out[scheme] = {
            "refit": "one Gauss-Newton step from the all-run optimum (a least-squares "
            "pass where the step is longer than one posterior SD)"
            if scheme == "leave_one_cluster_out"
            else "least-squares pass from the all-run optimum, slopes and sigmas held",
            "rms_s": float(np.sqrt(np.mean(r * r))) if r.size else math.nan,
            "deviance": dev if r.size else math.nan,
            "n_folds": n_folds,
            "n_refitted": n_refits if scheme == "leave_one_cluster_out" else n_folds,
            "n_predicted": int(done.sum()),
            "predicted_s": pred.tolist(),
        }
    return out


class _GaussNewtonStep:
    """The scaled residuals of the all-run fit and their Jacobian at its optimum, and the
    one-step refit without some runs (module notes)."""

    def __init__(
        self,
        cand: Candidate,
        fit: CandidateFit,
        ev: ModelEvaluator,
        conds: Sequence[Conditions] | None,
    ) -> None:
        self.params = ParameterSet(tuple(PARAMETERS[k] for k in cand.params))
        models = RunModels(ev, conds)
        y, t_max = fit.measured, fit.t_max
        pset = self.params

        def residuals(x: NDArray[np.float64]) -> NDArray[np.float64]:
            m = models.opening_times(pset.from_internal(x), fit.spin_rate)
            return scaled_residuals(y, m, fit.sd, t_max)

        def prefetch(xs: Sequence[NDArray[np.float64]]) -> None:
            models.prefetch([pset.from_internal(x) for x in xs], fit.spin_rate)

        self.x0 = pset.to_internal([fit.values[k] for k in cand.params])
        self.bounds = pset.internal_bounds()
        self.r0 = residuals(self.x0)
        self.jac = central_jacobian(
            residuals, self.x0, self.bounds, COVARIANCE_STEP, prefetch=prefetch
        )

    def values_without(self, test: NDArray[np.bool_]) -> tuple[dict[str, float], float]:
        """Parameter values after one Gauss-Newton step on the runs not in `test`, and the
        step's length in posterior SDs of the all-run fit, sqrt(dx^T J^T J dx)."""
        keep = ~test
        dx = np.linalg.lstsq(self.jac[keep], -self.r0[keep], rcond=None)[0]
        length = float(np.linalg.norm(self.jac @ dx))
        return self.params.values(np.clip(self.x0 + dx, *self.bounds)), length


def predictive_line(scores: dict[str, dict[str, Any]]) -> str:
    """One clause with a model's two rms scores [s] (for the recommendation)."""
    parts = []
    for key, short in (("leave_one_cluster_out", "LOCO"), ("leave_one_band_out", "LOBO")):
        s = scores.get(key)
        if s is not None and math.isfinite(s["rms_s"]):
            parts.append(f"{short} rms {s['rms_s']:.3f} s")
    return ", ".join(parts)
