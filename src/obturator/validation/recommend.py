"""Which candidate the validation study recommends, and why.

Recommendation rule
-------------------
Models are chosen by what they predict. The score is the leave-one-cluster-out
deviance (:mod:`.predictive`): -2 sum_i log p(y_i | the model refitted without run i's
replicate cluster), the measured counterpart of what AIC estimates (Stone 1977), with
the replicate cluster, not the run, as the unit left out, since the runs of one
cluster share their misfit. Among candidates whose fitted parameters all lie in their
physically argued ranges (:data:`~.candidates.PARAMETERS`), the lowest score; a
plausible candidate with fewer parameters within 2 units of it is preferred (Burnham
and Anderson's "substantial support" band, on the same deviance scale). If no candidate
is plausible, the lowest score overall, and the recommendation says so. Without
predictive scores (a study that did not compute them) the score is the AIC of the
all-run fit. The leave-one-band-out score (prediction across a quarter of the spin
range) and AIC are reported beside it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from .candidates import PARAMETERS
from .results import ModelResult

__all__ = ["OUT_OF_BAND_SPLIT", "best_predictor", "model_aic", "recommend"]

#: Spin [rad/s] that splits the runs for the out-of-band refits (the thesis trusted its
#: model only above 200 rad/s).
OUT_OF_BAND_SPLIT = 200.0


def recommend(models: Sequence[ModelResult]) -> tuple[str, str]:
    """The recommended model and the reason (rule in the module notes)."""
    fitted = [m for m in models if m.fit.params]
    pool = [m for m in fitted if m.fit.all_plausible]
    caveat = ""
    if not pool:
        pool = fitted or list(models)
        caveat = " No candidate has all its parameters in their physical ranges."
    predictive = all(math.isfinite(_loco(m)) for m in pool)
    score = _loco if predictive else model_aic
    what = "leave-one-cluster-out deviance" if predictive else "AIC"
    best = min(pool, key=score)
    near = [m for m in pool if score(m) - score(best) <= 2.0]
    choice = min(near, key=lambda m: (len(m.fit.params), score(m)))
    others = sorted((m for m in models if m is not choice), key=lambda m: m.fit.aic)
    f = choice.fit
    vals = ", ".join(
        f"{k} = {f.values[k]:.4g}" + ("" if PARAMETERS[k].unit == "1" else f" {PARAMETERS[k].unit}")
        for k in f.params
    )
    why = (
        f"'{choice.name}' ({vals}): lowest {what} among candidates with every parameter in "
        f"its physical range"
    )
    if choice is not best:
        why += (
            f" within 2 units of '{best.name}' ({score(best) - score(choice):+.2f}) "
            "and with fewer parameters"
        )
    why += f"; all-run rms {f.rms:.4f} s."
    if others:
        nxt = others[0]
        by_aic = min(pool, key=model_aic)
        why += f" Next by AIC: '{nxt.name}' (delta AIC {nxt.fit.aic - f.aic:+.2f})"
        if predictive and by_aic is not choice:
            why += (
                f"; AIC alone would choose '{by_aic.name}', which predicts the left-out "
                f"clusters {_loco(by_aic) - _loco(choice):+.1f} deviance units worse"
            )
        why += "."
    oob = choice.out_of_band_rms.get("high->low")
    if oob is not None and math.isfinite(oob):
        rivals = [
            m for m in others[:4] if math.isfinite(m.out_of_band_rms.get("high->low", math.nan))
        ]
        why += (
            f" Fitted only to the runs at >= {OUT_OF_BAND_SPLIT:g} rad/s it predicts those "
            f"below with rms {oob:.3f} s"
        )
        if rivals:
            why += (
                " ("
                + ", ".join(f"{m.name}: {m.out_of_band_rms['high->low']:.3f} s" for m in rivals)
                + ")"
            )
        why += "."
    why += _predictive_clause(choice, models)
    g = choice.goodness
    if g and not math.isfinite(g["overall"]["p_value"]):
        why += " No band has replicates: no lack-of-fit test against a floor."
    elif g:
        failing = [b for b, row in g["bands"].items() if row["p_value"] < 0.05]
        why += (
            f" Against the replicate floor (band by band): overall lack-of-fit "
            f"p = {g['overall']['p_value']:.2g}"
            + (f", failing at 5 % in {', '.join(failing)}" if failing else ", no band failing")
            + "."
        )
        passing = [
            m.name for m in models if m.goodness and m.goodness["overall"]["p_value"] >= 0.05
        ]
        why += " Passing overall at 5 %: " + (", ".join(passing) if passing else "none") + "."
    implausible = [m.name for m in fitted if not m.fit.all_plausible]
    if implausible:
        why += " Outside their physical ranges: " + ", ".join(implausible) + "."
    return choice.name, why + caveat


_SCHEME_TEXT = (
    ("leave_one_cluster_out", "its replicate cluster"),
    ("leave_one_band_out", "its spin band"),
)


def best_predictor(models: Sequence[ModelResult], scheme: str) -> ModelResult | None:
    """The model with the smallest cross-validated deviance of `scheme` (None: no scores)."""
    scored = [
        m
        for m in models
        if m.fit.params and math.isfinite(m.predictive.get(scheme, {}).get("deviance", math.nan))
    ]
    return min(scored, key=lambda m: m.predictive[scheme]["deviance"]) if scored else None


def _predictive_clause(choice: ModelResult, models: Sequence[ModelResult]) -> str:
    """What the cross-validated scores say (:mod:`.predictive`), and how the choice stands
    against them."""
    text = ""
    bests = []
    for scheme, how in _SCHEME_TEXT:
        best = best_predictor(models, scheme)
        own = choice.predictive.get(scheme)
        if best is None or own is None:
            continue
        bests.append(best)
        sb = best.predictive[scheme]
        text += (
            f" Each run predicted by the model refitted with {how} left out: "
            f"'{choice.name}' rms {own['rms_s']:.3f} s "
            f"(-2 log predictive density {own['deviance']:.1f})"
        )
        if best is choice:
            text += ", the best of all candidates."
        else:
            text += (
                f"; best: '{best.name}', rms {sb['rms_s']:.3f} s "
                f"({sb['deviance']:.1f}, {own['deviance'] - sb['deviance']:.1f} better)."
            )
    if not bests:
        return ""
    if all(b is choice for b in bests):
        text += f" '{choice.name}' predicts best by both cross-validations."
    else:
        names = sorted({b.name for b in bests})
        text += " Predicts best: " + " and ".join(f"'{n}'" for n in names)
        implausible = sorted({b.name for b in bests if not b.fit.all_plausible})
        if implausible:
            text += " (outside the physical ranges: " + ", ".join(implausible) + ")"
        text += "."
    return text


# --------------------------------------------------------------------------- study


def _loco(m: ModelResult) -> float:
    """Leave-one-cluster-out deviance of a model (NaN: not computed)."""
    return float(m.predictive.get("leave_one_cluster_out", {}).get("deviance", math.nan))


def model_aic(m: ModelResult) -> float:
    """AIC of a model's all-run fit (a sort key)."""
    return m.fit.aic
