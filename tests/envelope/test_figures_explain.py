"""The envelope studies' figures say what they show (issue 48): the Sobol figure warns
when its estimates are noise, the Pareto figure says when the front collapsed and why,
the requirement contour of the envelope map is named in a legend, not by an inline
label that cuts it. Synthetic datasets, no solves; reference values: the issue's
``sensitivity --samples 16`` (S1(mu_s) = 1.17 +- 0.85) and the README's ``optimize
--pareto 4`` (four designs bunched at 2.5 g)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from obturator.envelope import figures
from obturator.envelope.figures import pareto_collapse
from obturator.envelope.sensitivity import sobol_warnings


@pytest.fixture
def drawn(monkeypatch):
    """The figures the plot functions would save (kept open to inspect)."""
    kept: list = []
    monkeypatch.setattr(figures, "_save", lambda fig, path: kept.append(fig) or str(path))
    return kept


def _sobol(s1, s1c, st, stc) -> xr.Dataset:
    names = ["mu_s", "theta0_deg", "gap"]
    data = {
        k: ("input", np.asarray(v, float))
        for k, v in zip(("S1", "S1_conf", "ST", "ST_conf"), (s1, s1c, st, stc), strict=True)
    }
    return xr.Dataset(data, coords={"input": names}, attrs={"n_base": 16, "title": "Sobol"})


def test_sobol_noise_is_flagged_in_text_and_figure(drawn):
    noisy = _sobol([1.17, 0.02, -0.2], [0.85, 0.3, 0.1], [0.9, 0.05, 0.0], [0.2, 0.02, 0.001])
    lines = sobol_warnings(noisy)
    assert any("S1 outside [0, 1]" in x and "mu_s 1.17" in x and "gap -0.2" in x for x in lines)
    assert any("S1 interval wider" in x and "theta0_deg" in x for x in lines)
    assert not any(x.startswith("ST") for x in lines)  # ST is fine
    assert "--samples 16" in lines[-1]
    figures.plot_sobol(noisy, "s.png")
    ax = drawn[-1].axes[0]
    assert "NOT RELIABLE" in ax.get_title()
    assert sum(bool(b.get_hatch()) for b in ax.patches if hasattr(b, "get_hatch")) >= 3


def test_clean_sobol_indices_carry_no_warning(drawn):
    # the README's flight numbers: mu_s carries nearly all the variance
    clean = _sobol([0.95, 0.007, 0.0], [0.15, 0.004, 0.002], [0.95, 0.007, 0.0], [0.13, 0.003, 0.0])
    assert sobol_warnings(clean) == []
    figures.plot_sobol(clean, "s.png")
    assert "NOT RELIABLE" not in drawn[-1].axes[0].get_title()


def _front(mass_g, objective, lightest_g) -> xr.Dataset:
    return xr.Dataset(
        {
            "mass": ("point", 1e-3 * np.asarray(mass_g)),
            "objective": ("point", np.asarray(objective)),
        },
        attrs={
            "objective": "max",
            "baseline_mass": 8.163e-3,
            "baseline_objective": 0.1077,
            "lightest_feasible_mass": 1e-3 * lightest_g,
            "degenerate": 0,
        },
    )


def test_a_collapsed_front_says_so_and_why(drawn):
    bunched = _front([2.544, 2.535, 2.527, 2.519], [0.02226, 0.02227, 0.02228, 0.0223], 2.519)
    why = pareto_collapse(bunched)
    assert why and "collapsed" in why and "do not compete" in why
    assert "(2.544 g, 0.02226 s)" in why  # the fastest design: the optimum, the heaviest
    figures.plot_pareto(bunched, "p.png")
    ax = drawn[-1].axes[0]
    assert "No trade-off" in ax.get_title()
    assert any("collapsed" in t.get_text() for t in ax.texts)


def test_a_real_front_is_drawn_as_one(drawn):
    spread = _front([6.0, 5.0, 4.0, 3.0], [0.018, 0.019, 0.021, 0.025], 3.0)
    assert pareto_collapse(spread) is None
    figures.plot_pareto(spread, "p.png")
    assert drawn[-1].axes[0].get_title().startswith("Pareto front")


def test_requirement_contour_is_named_in_the_legend_not_cut_by_a_label(drawn):
    mach = np.array([1.5, 2.0, 2.5, 3.0])
    alt = np.array([0.0, 5000.0, 10000.0])
    tc = 0.05 + 0.04 * (alt[None, :] / 5000.0) / mach[:, None] ** 0.5  # crosses 0.1 s
    z = np.zeros_like(tc)
    ds = xr.Dataset(
        {
            "t_cr_coupled": (("mach", "altitude_m"), tc),
            "t_cr_constant": (("mach", "altitude_m"), 0.98 * tc),
            "relative_difference": (("mach", "altitude_m"), z + 0.02),
            "choked_at_opening": (("mach", "altitude_m"), z.astype(bool)),
            "started": (("mach", "altitude_m"), np.ones_like(tc, bool)),
            "status_coupled": (("mach", "altitude_m"), z.astype(int) + 1),
            "status_constant": (("mach", "altitude_m"), z.astype(int) + 1),
        },
        coords={"mach": mach, "altitude_m": alt},
        attrs={"requirement_s": 0.1},
    )
    figures.plot_envelope(ds, "e.png")
    ax = drawn[-1].axes[0]
    assert not ax.texts  # no inline contour label sits on the line
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "0.1 s, coupled" in labels and "0.1 s, constant load" in labels
