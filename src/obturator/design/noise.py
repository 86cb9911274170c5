"""The run-to-run scatter a planned run is expected to show (the design's noise).

The replicate floor of the measured runs (:func:`obturator.validation.replicate_floor`)
gives a pooled SD per spin band (0.104 s below 120 rad/s, 0.012-0.013 s at 120-300,
0.039 s above on Appendix B). A planned run at a setting the thesis never used may
scatter more, for two reasons this model carries:

* it opens later than the measured runs: the band's coefficient of variation
  (pooled SD over the band's mean t_cr) times the predicted t_cr;
* its t_cr is steeper in the release angle: near 90 deg the ball leaves its start
  slowly and t_cr grows about as ln 1/(90 deg - theta_0), so a release that repeats to
  sigma_theta scatters t_cr by sigma_theta |dt_cr/dtheta_0|. sigma_theta is not
  measured; its upper bound is the jitter that would explain the *whole* replicate SD
  of the tightest band by the release alone (min over bands of SD_b / mean |dt/dtheta_0|
  at the band's runs), and that bound is used.

A run's SD is the largest of the band's pooled SD and these two; it is the same for
every candidate (the models' mean slope), so the criterion compares the models' means
and parameter uncertainties, not their noise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._docs import field_docs
from ..calibration.data import SpinRigData
from ..validation.floor import band_of, replicate_floor

__all__ = ["RELEASE_STEP_DEG", "ReplicateNoise"]

#: Step of the release-angle slope dt_cr/dtheta_0 (one-sided, towards lower angles) [deg].
RELEASE_STEP_DEG = 0.25


@field_docs
@dataclass(frozen=True)
class ReplicateNoise:
    """The replicate scatter per spin band and its extrapolation (module notes)."""

    #: Pooled replicate SD per spin band [s].
    sd: dict[str, float]
    #: Coefficient of variation per spin band: its pooled SD over its mean measured t_cr [-].
    cv: dict[str, float]
    #: Pooled SD of all runs [s] (for a band without replicates).
    overall_sd: float
    #: Release-angle jitter SD [deg] (0 until :meth:`with_release_bound`, or as measured).
    release_sd_deg: float = 0.0
    #: Where `release_sd_deg` comes from: "none" (not set), "the most the replicates allow"
    #: (the bound of :meth:`with_release_bound`) or "given" (measured).
    release_source: str = "none"

    @classmethod
    def of(cls, data: SpinRigData) -> ReplicateNoise:
        """Band SDs and CVs of the measured runs (bands by cluster-mean spin)."""
        floor = replicate_floor(data.spin_rate, data.opening_time)
        band = band_of(floor.cluster_mean_spin())
        sd = {k: b.pooled_sd for k, b in floor.bands.items()}
        cv = {
            k: v / float(np.mean(data.opening_time[band == k])) if np.any(band == k) else math.nan
            for k, v in sd.items()
        }
        return cls(sd, cv, floor.overall.pooled_sd)

    def with_release_bound(
        self, data: SpinRigData, slope_deg: NDArray[np.float64]
    ) -> ReplicateNoise:
        """The same with the release jitter bound from the measured runs.

        Parameters
        ----------
        data : SpinRigData
            The measured runs.
        slope_deg : ndarray
            |dt_cr/dtheta_0| at each run's spin on the Table 1 rig [s/deg].
        """
        floor = replicate_floor(data.spin_rate, data.opening_time)
        band = band_of(floor.cluster_mean_spin())
        bounds = [
            sd / float(np.mean(np.abs(slope_deg[band == k])))
            for k, sd in self.sd.items()
            if math.isfinite(sd) and np.any(band == k) and np.mean(np.abs(slope_deg[band == k]))
        ]
        return replace(
            self,
            release_sd_deg=min(bounds) if bounds else 0.0,
            release_source="the most the replicates allow",
        )

    def at(
        self,
        spin: NDArray[np.float64],
        t_cr: NDArray[np.float64],
        slope_deg: NDArray[np.float64] | None = None,
    ) -> NDArray[np.float64]:
        """Replicate SD [s] of runs at `spin` [rad/s] expected to open at `t_cr` [s] with
        release slope |dt_cr/dtheta_0| `slope_deg` [s/deg] (module notes)."""
        labels = [str(b) for b in band_of(spin)]
        sd = np.array([self.sd.get(b, math.nan) for b in labels], dtype=float)
        cv = np.array([self.cv.get(b, math.nan) for b in labels], dtype=float)
        sd = np.where(np.isfinite(sd), sd, self.overall_sd)
        rel = np.nan_to_num(np.where(np.isfinite(cv), cv, 0.0) * np.asarray(t_cr), nan=0.0)
        out = np.maximum(sd, rel)
        if slope_deg is not None:
            jitter = np.nan_to_num(self.release_sd_deg * np.abs(slope_deg), nan=0.0)
            out = np.maximum(out, jitter)
        return out

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready."""
        return {
            "rule": "max(band pooled SD, band CV x predicted t_cr, "
            "release jitter x |dt_cr/dtheta_0|)",
            "sd_by_band_s": self.sd,
            "cv_by_band": self.cv,
            "overall_sd_s": self.overall_sd,
            "release_sd_deg": self.release_sd_deg,
            "release_sd_source": self.release_source,
        }
