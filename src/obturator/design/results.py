"""Result objects of the design study (numbers; text in :mod:`.textreport`)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from .._docs import field_docs
from .campaigns import DECISIVE_BAYES_FACTOR, MISFIT_LEVEL, OUTSIDE, Rates
from .criterion import plan_value
from .feasibility import Feasibility, ValidatedRange
from .noise import ReplicateNoise
from .posterior import Posterior
from .settings import Setting, SettingRanges
from .surrogate import Surrogate

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr

__all__ = ["DesignResult", "PlanResult"]

#: Smallest campaign recommended: replicates enough to check the replicate SD at a new
#: setting (a 5-run cluster estimates its SD to about +-35 %).
MIN_CAMPAIGN = 5
#: Two-sided 95 % normal quantile (predictive intervals).
_Z95 = 1.959963984540054


def _mean_rate(rates: Mapping[str, Rates], key: str) -> float:
    """Mean over the candidates (equal prior) of one rate; truths outside the candidates
    (``"<model>+discrepancy"``) are not averaged in."""
    return float(np.mean([getattr(r, key) for m, r in rates.items() if not _outside(m)]))


def _outside(name: str) -> bool:
    return name.endswith(OUTSIDE.format(""))


def recommended_plan(plans: Sequence[PlanResult]) -> PlanResult:
    """The smallest plan of at least :data:`MIN_CAMPAIGN` runs decisive in >= 95 % of
    campaigns, else the largest."""
    good = [p for p in plans if p.p_decisive >= 0.95 and p.n_runs >= MIN_CAMPAIGN]
    return min(good, key=lambda p: p.n_runs) if good else plans[-1]


@field_docs
@dataclass(frozen=True)
class PlanResult:
    """The designed plan of one size and the simulated campaigns of it and the naive plan."""

    #: Campaign size N: the number of runs of the plan.
    n_runs: int
    #: Setting indices of the runs (sorted; repeats are replicates).
    runs: list[int]
    #: Box-Hill D of the plan [nats].
    criterion: float
    #: D of the naive plan of the same size [nats].
    naive_criterion: float
    #: Decision rates of the designed plan per generating model.
    designed: dict[str, Rates]
    #: Decision rates of the naive plan of the same size per generating model.
    naive: dict[str, Rates]
    #: Setting indices of the naive plan of the same size.
    naive_runs: list[int]

    @property
    def p_decisive(self) -> float:
        """Mean over the generating models (equal prior) of P(decisive), designed plan."""
        return _mean_rate(self.designed, "p_decisive")

    @property
    def naive_p_decisive(self) -> float:
        """The same for the naive plan."""
        return _mean_rate(self.naive, "p_decisive")


@field_docs
@dataclass(frozen=True)
class DesignResult:
    """The whole design study (:func:`obturator.design_experiment`)."""

    #: Names of the candidates compared, in order.
    models: tuple[str, ...]
    #: Laplace posterior of each candidate's parameters, by name.
    posteriors: dict[str, Posterior]
    #: Every setting solved (the candidate grid and the measured runs' spins).
    settings: list[Setting]
    #: Settings the plan search could choose.
    candidate_mask: NDArray[np.bool_]
    #: Surrogate of each candidate's t_cr over the settings, by name.
    surrogates: dict[str, Surrogate]
    #: Replicate SD at each setting [s].
    noise_sd: NDArray[np.float64]
    #: Band SDs and CVs, the release-jitter bound.
    noise_model: ReplicateNoise
    #: |dt_cr/dtheta_0| at each setting [s/deg] (mean over the models' best fits).
    release_slope: NDArray[np.float64]
    #: The designed plans, one per campaign size.
    plans: list[PlanResult]
    #: The naive plan's rates at every simulated size.
    naive_rates: dict[int, dict[str, Rates]]
    #: Surrogate against exact t_cr at the campaign draws, per generating model.
    surrogate_error: dict[str, dict[str, float]]
    #: Ranges of the controllable settings and the candidate grid.
    ranges: SettingRanges
    #: Simulated campaigns per generating model and plan.
    campaigns: int
    #: Seed of the posterior draws and the replicate noise.
    seed: int
    #: Exact solves of the study (surrogates and simulated campaigns).
    n_solves: int
    #: Where the measured runs came from (the data's ``SpinRigData.source``).
    data_source: str
    #: Wall time of the study [s].
    elapsed_s: float
    #: Holding moment, the rig's bound and the distance from the measured runs of every
    #: setting (:mod:`.feasibility`).
    feasibility: list[Feasibility] = field(default_factory=list)
    #: What the measured runs cover.
    validated: ValidatedRange | None = None
    #: Other plans of the recommended size, by what they drop: "without the feasibility
    #: check", "on the as-built ball alone"; each (N, setting indices, Box-Hill D [nats]).
    alternative_plans: dict[str, tuple[int, list[int], float]] = field(default_factory=dict)
    #: Flat directions of each candidate's fit (:func:`obturator.validation.valley.
    #: flat_directions`).
    flat_directions: dict[str, list[dict[str, Any]]] = field(default_factory=dict)

    # ------------------------------------------------------------------ derived

    def plan(self, n_runs: int) -> PlanResult:
        """The plan of `n_runs`."""
        for p in self.plans:
            if p.n_runs == n_runs:
                return p
        raise KeyError(n_runs)

    @property
    def recommended(self) -> PlanResult:
        """The smallest plan of at least :data:`MIN_CAMPAIGN` runs decisive in >= 95 % of
        campaigns, else the largest."""
        return recommended_plan(self.plans)

    def misfit_rates(self, p: PlanResult) -> dict[str, float]:
        """P(every candidate fails its predictive check) of a plan per generating truth:
        the candidates (false alarms) and the truths outside them (exposed misfits)."""
        return {m: r.p_misfit for m, r in p.designed.items()}

    def naive_runs_needed(self, target: float) -> int | None:
        """Smallest simulated naive size whose mean P(decisive) reaches `target` (None: none)."""
        for n in sorted(self.naive_rates):
            if _mean_rate(self.naive_rates[n], "p_decisive") >= target:
                return n
        return None

    def designed_runs_needed(self, target: float) -> int | None:
        """Smallest planned size whose mean P(decisive) reaches `target` (None: none)."""
        for p in sorted(self.plans, key=lambda p: p.n_runs):
            if p.p_decisive >= target:
                return p.n_runs
        return None

    def separation(self, idx: Sequence[int]) -> NDArray[np.float64]:
        """|difference of the first two models' mean t_cr| over the replicate SD, per run."""
        i = np.asarray(idx, dtype=np.intp)
        a, b = (self.surrogates[m].mean(i) for m in self.models[:2])
        return np.abs(a - b) / self.noise_sd[i]

    def axis_effects(self, i: int) -> dict[str, float]:
        """Separation (replicate SDs) at setting `i` with each changed setting put back to
        the Table 1 rig's (where that setting was solved): what each change buys."""
        s = self.settings[i]
        index = {x: k for k, x in enumerate(self.settings)}
        nominal = Setting(s.spin_rate)
        out = {}
        for name in ("theta0_deg", "hole_radius", "density"):
            if getattr(s, name) != getattr(nominal, name):
                back = replace(s, **{name: getattr(nominal, name)})
                if back in index:
                    out[name] = float(self.separation([index[back]])[0])
        return out

    def predictive(self, idx: Sequence[int]) -> dict[str, dict[str, NDArray[np.float64]]]:
        """Per model: predictive mean [s] and 95 % interval [s] (parameters and noise)."""
        i = np.asarray(idx, dtype=np.intp)
        out = {}
        for m, s in self.surrogates.items():
            mean = s.mean(i)
            sd = np.sqrt(s.sd()[i] ** 2 + self.noise_sd[i] ** 2)
            out[m] = {"mean": mean, "lo": mean - _Z95 * sd, "hi": mean + _Z95 * sd}
        return out

    def ranked_plan(self, n_runs: int) -> list[dict[str, Any]]:
        """The plan's distinct settings, most important first (by the loss of D without
        them), each with its replicates, predictions and separation."""
        p = self.plan(n_runs)
        sur = list(self.surrogates.values())
        rows = []
        for i in sorted(set(p.runs)):
            rest = [j for j in p.runs if j != i]
            loss = p.criterion - (plan_value(sur, self.noise_sd, rest) if rest else 0.0)
            pred = self.predictive([i])
            means = [pred[m]["mean"][0] for m in self.models]
            sep = abs(means[0] - means[1]) / self.noise_sd[i]
            rows.append(
                {
                    "setting": self.settings[i],
                    "index": i,
                    "feasibility": self.feasibility[i] if self.feasibility else None,
                    "replicates": p.runs.count(i),
                    "criterion_loss_without": float(loss),
                    "predicted": {
                        m: (
                            float(pred[m]["mean"][0]),
                            float(pred[m]["lo"][0]),
                            float(pred[m]["hi"][0]),
                        )
                        for m in self.models
                    },
                    "replicate_sd_s": float(self.noise_sd[i]),
                    "separation_in_replicate_sd": float(sep),
                }
            )
        return sorted(rows, key=lambda r: -r["criterion_loss_without"])

    # ------------------------------------------------------------------ output

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready, unit-suffixed keys."""

        def rows(n: int) -> list[dict[str, Any]]:
            out = []
            for r in self.ranked_plan(n):
                out.append(
                    {
                        **r["setting"].to_dict(),
                        "replicates": r["replicates"],
                        "criterion_loss_without_nats": r["criterion_loss_without"],
                        "replicate_sd_s": r["replicate_sd_s"],
                        "separation_in_replicate_sd": r["separation_in_replicate_sd"],
                        **(r["feasibility"].to_dict() if r["feasibility"] else {}),
                        "as_built_ball": r["setting"].is_as_built_ball,
                        "predicted_t_cr_s": {
                            m: {"mean_s": v[0], "pi95_low_s": v[1], "pi95_high_s": v[2]}
                            for m, v in r["predicted"].items()
                        },
                    }
                )
            return out

        rec = self.recommended
        return {
            "models": list(self.models),
            "criterion": "Box-Hill (1967) expected symmetric KL divergence between the "
            "models' joint predictive distributions (parameters from the Laplace posterior, "
            "noise the replicate SD per spin band)",
            "decision_rule": f"Bayes factor > {DECISIVE_BAYES_FACTOR:g} for the generating "
            "model over every other (evidence from the surrogate; prior odds 1)",
            "measured_quantity": "t_cr (opening time)",
            "posteriors": {m: p.to_dict() for m, p in self.posteriors.items()},
            "noise": self.noise_model.to_dict(),
            "ranges": self.ranges.to_dict(),
            "n_candidate_settings": int(self.candidate_mask.sum()),
            "recommended_n_runs": rec.n_runs,
            "plans": [
                {
                    "n_runs": p.n_runs,
                    "criterion_nats": p.criterion,
                    "naive_criterion_nats": p.naive_criterion,
                    "p_decisive": p.p_decisive,
                    "naive_p_decisive": p.naive_p_decisive,
                    "naive_runs_for_same_p_decisive": self.naive_runs_needed(p.p_decisive),
                    "separation_in_replicate_sd_mean": float(np.mean(self.separation(p.runs))),
                    "naive_separation_in_replicate_sd_mean": float(
                        np.mean(self.separation(p.naive_runs))
                    ),
                    "designed": {m: r.to_dict() for m, r in p.designed.items()},
                    "naive": {m: r.to_dict() for m, r in p.naive.items()},
                    "runs": rows(p.n_runs),
                }
                for p in self.plans
            ],
            "naive_curve": [
                {
                    "n_runs": n,
                    "p_decisive": _mean_rate(r, "p_decisive"),
                    "by_model": {m: x.to_dict() for m, x in r.items()},
                }
                for n, r in sorted(self.naive_rates.items())
            ],
            "runs_needed": {
                f"p_decisive_{t:g}": {
                    "designed": self.designed_runs_needed(t),
                    "naive": self.naive_runs_needed(t),
                }
                for t in (0.9, 0.95, 0.99)
            },
            "surrogate_error": self.surrogate_error,
            "validated_range": None if self.validated is None else self.validated.to_dict(),
            "n_infeasible_settings": sum(not f.feasible for f in self.feasibility),
            "alternative_plans": {
                label: {
                    "n_runs": n,
                    "criterion_nats": d,
                    "runs": [
                        {
                            **self.settings[i].to_dict(),
                            "replicates": runs.count(i),
                            **(self.feasibility[i].to_dict() if self.feasibility else {}),
                        }
                        for i in sorted(set(runs))
                    ],
                }
                for label, (n, runs, d) in self.alternative_plans.items()
            },
            "misfit_check": {
                "rule": "every candidate's posterior predictive check (chi^2, N dof) fails "
                f"at {MISFIT_LEVEL:g}",
                "truth_outside": "generating model + its all-run fit's mean residual per "
                "replicate cluster, interpolated in ln omega_p",
                "p_misfit_exposed_recommended": self.misfit_rates(rec),
            },
            "flat_directions": self.flat_directions,
            "campaigns_per_model": self.campaigns,
            "seed": self.seed,
            "n_exact_solves": self.n_solves,
            "data_source": self.data_source,
            "elapsed_s": self.elapsed_s,
        }

    def to_dataset(self) -> xr.Dataset:
        """Every setting's predictions, the plans and the decision curves (NetCDF-ready)."""
        import xarray as xr

        from .settings import setting_arrays

        cols = setting_arrays(self.settings)
        idx = np.arange(len(self.settings))
        pred = self.predictive(idx)
        data: dict[str, Any] = {
            "spin_rate": ("setting", cols["spin_rate"], {"units": "rad/s"}),
            "theta0_set_deg": ("setting", cols["theta0_set_deg"], {"units": "deg"}),
            "hole_radius": ("setting", cols["hole_radius"], {"units": "m"}),
            "density": ("setting", cols["density"], {"units": "kg/m^3"}),
            "replicate_sd": ("setting", self.noise_sd, {"units": "s"}),
            "release_slope": ("setting", self.release_slope, {"units": "s/deg"}),
            "candidate": ("setting", self.candidate_mask.astype(np.int8), {}),
            "holding_moment": (
                "setting",
                np.array([f.holding_moment for f in self.feasibility]),
                {"units": "N m"},
            ),
            "holding_bound": (
                "setting",
                np.array([f.bound for f in self.feasibility]),
                {"units": "N m"},
            ),
            "extrapolated": (
                "setting",
                np.array([bool(f.extrapolated) for f in self.feasibility], dtype=np.int8),
                {"note": "1: outside what the measured runs cover (spin, release, ball, kappa)"},
            ),
            "t_cr_mean": (
                ("model", "setting"),
                np.array([pred[m]["mean"] for m in self.models]),
                {"units": "s"},
            ),
            "t_cr_pi95_low": (
                ("model", "setting"),
                np.array([pred[m]["lo"] for m in self.models]),
                {"units": "s"},
            ),
            "t_cr_pi95_high": (
                ("model", "setting"),
                np.array([pred[m]["hi"] for m in self.models]),
                {"units": "s"},
            ),
            "t_cr_at_best_fit": (
                ("model", "setting"),
                np.array([self.surrogates[m].t0 for m in self.models]),
                {"units": "s"},
            ),
        }
        n_max = max(p.n_runs for p in self.plans)
        runs = np.full((len(self.plans), n_max), -1, dtype=np.int64)
        for k, p in enumerate(self.plans):
            runs[k, : p.n_runs] = p.runs
        data["plan_setting"] = (("n_runs", "run"), runs, {"note": "setting index; -1: none"})
        data["p_decisive_designed"] = (
            ("n_runs", "generating_model"),
            np.array([[p.designed[m].p_decisive for m in self.models] for p in self.plans]),
            {},
        )
        data["p_decisive_naive"] = (
            ("n_runs", "generating_model"),
            np.array([[p.naive[m].p_decisive for m in self.models] for p in self.plans]),
            {},
        )
        naive_n = sorted(self.naive_rates)
        data["p_decisive_naive_curve"] = (
            ("naive_n_runs", "generating_model"),
            np.array([[self.naive_rates[n][m].p_decisive for m in self.models] for n in naive_n]),
            {},
        )
        return xr.Dataset(
            data,
            coords={
                "setting": idx,
                "model": list(self.models),
                "generating_model": list(self.models),
                "n_runs": [p.n_runs for p in self.plans],
                "run": np.arange(n_max),
                "naive_n_runs": naive_n,
            },
            attrs={
                "title": "obturator design-experiment",
                "criterion": "Box-Hill 1967 (symmetric KL of joint predictive Gaussians)",
                "decisive": f"Bayes factor > {DECISIVE_BAYES_FACTOR:g}",
                "campaigns_per_model": self.campaigns,
                "seed": self.seed,
                "n_exact_solves": self.n_solves,
                "data_source": self.data_source,
                "surrogate_rms_error_s": "; ".join(
                    f"{m}: {e['rms_s']:.3g}" for m, e in self.surrogate_error.items()
                ),
                "elapsed_s": self.elapsed_s if math.isfinite(self.elapsed_s) else -1.0,
            },
        )
