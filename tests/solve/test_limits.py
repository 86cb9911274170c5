"""The regularisation widths the regularised paths cannot carry are refused in one line.

Refused: ``friction_width`` below ``MIN_FRICTION_WIDTH`` for the methods that integrate
stick phases with Radau IIA (measured by ``python -m benchmarks.regularised_limits``:
t_cr against the set-valued solver at rtol 1e-12); the methods that do not use the
width, or carry it, keep the whole allowed range. And, where a case with friction meets
the options, a width below rtol for the explicitly chosen regularised methods (the
measured basis: docs/benchmarks.md, History, "Width against tolerance").
"""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from obturator import SolverOptions
from obturator.errors import InputError
from obturator.model.cases import rig_case
from obturator.solve import integration_setup, pack_points, refined_options
from obturator.solve.limits import MIN_FRICTION_WIDTH, WIDTH_BOUND_METHODS, width_rule_waived


@pytest.mark.parametrize("method", sorted(MIN_FRICTION_WIDTH))
def test_width_below_the_limit_is_refused_naming_field_and_range(method: str) -> None:
    lo = MIN_FRICTION_WIDTH[method]
    SolverOptions(method=method, friction_width=lo)  # the limit itself is carried
    with pytest.raises(InputError) as err:
        SolverOptions(method=method, friction_width=lo / 10)
    assert err.value.field == "friction_width"
    assert f"[{lo:g}, 1]" in err.value.message and repr(method) in err.value.message


@pytest.mark.parametrize("method", ["auto", "set-valued", "moreau-jean", "rosenbrock"])
def test_other_methods_keep_the_whole_range(method: str) -> None:
    SolverOptions(method=method, friction_width=1e-12)


def test_cli_refuses_in_one_line(tmp_path, capsys: pytest.CaptureFixture[str]) -> None:
    from obturator.cli import main

    rc = main(
        ["sweep", "--method", "regularised", "--friction-width", "1e-11", "--spin-rate",
         "100:200:2", "--no-progress", "--out", str(tmp_path / "w.nc")]
    )  # fmt: skip
    err = capsys.readouterr().err
    assert rc == 2
    assert err.startswith("obturator: error: friction_width: 1e-11 is outside the range ")
    assert err.count("\n") == 1


def test_convergence_rerun_below_the_limit_names_the_given_width() -> None:
    from obturator.solve import refined_options

    lo = MIN_FRICTION_WIDTH["regularised"]
    with pytest.raises(InputError) as err:
        refined_options(SolverOptions(method="regularised", friction_width=lo))
    assert err.value.field == "friction_width"
    assert err.value.message.startswith(f"{lo:g} is checked at width / 10, and ")


# ----------------------------------------------- width against rtol, where case and options meet

#: The exact one line of the width-against-rtol rule (solve.limits.check_width_resolved).
WIDTH_BELOW_RTOL = (
    "friction_width: 1e-07 is below rtol 1e-06 for method {method!r}: the integrator cannot "
    "resolve slip speeds of order the width; use friction_width >= rtol, or method "
    "'set-valued' (no width)"
)


@pytest.mark.parametrize("method", sorted(WIDTH_BOUND_METHODS))
def test_width_below_rtol_is_refused_where_case_and_options_meet(method: str) -> None:
    case = rig_case(300.0, 0.5473)
    low = SolverOptions(method=method, rtol=1e-6, atol=1e-8)  # the default width 1e-7
    with pytest.raises(InputError) as err:
        integration_setup(case, low)
    assert str(err.value) == WIDTH_BELOW_RTOL.format(method=method)
    with pytest.raises(InputError):  # the lanes pack through the same door
        pack_points([case], low)
    # the boundary and above are carried: width == rtol, width > rtol
    integration_setup(case, SolverOptions(method=method, rtol=1e-7, atol=1e-9))
    integration_setup(case, replace(low, friction_width=1e-6))


@pytest.mark.parametrize("method", ["auto", "set-valued", "moreau-jean"])
def test_methods_the_width_does_not_bind_keep_every_rtol(method: str) -> None:
    integration_setup(rig_case(300.0, 0.5473), SolverOptions(method=method, rtol=1e-6, atol=1e-8))


@pytest.mark.parametrize("method", sorted(WIDTH_BOUND_METHODS))
def test_a_case_without_friction_has_no_width_to_resolve(method: str) -> None:
    opts = SolverOptions(method=method, rtol=1e-6, atol=1e-8)
    no_friction = rig_case(300.0, 0.5473)
    no_friction = replace(no_friction, torque=replace(no_friction.torque, friction=None))
    zero_mu = rig_case(300.0, 0.0)  # mu_s = 0: a friction term of magnitude zero
    assert not no_friction.torque.is_regularised and not zero_mu.torque.is_regularised
    integration_setup(no_friction, opts)
    integration_setup(zero_mu, opts)


def test_the_waiver_is_scoped_to_its_block() -> None:
    case, low = rig_case(300.0, 0.5473), SolverOptions(method="regularised", rtol=1e-6)
    with width_rule_waived():
        integration_setup(case, low)
    with width_rule_waived(False), pytest.raises(InputError):
        integration_setup(case, low)
    with pytest.raises(InputError):
        integration_setup(case, low)


@pytest.mark.parametrize("method", sorted(WIDTH_BOUND_METHODS))
def test_convergence_reruns_of_an_explicit_method_keep_its_width_to_rtol_ratio(method) -> None:
    """At width == rtol the three reruns (rtol / 10; width and rtol / 10; the other family)
    pass the rule too: a valid explicit choice is never refused in its own check."""
    case = rig_case(300.0, 0.5473)
    opts = SolverOptions(method=method, rtol=1e-7, atol=1e-9)
    for rerun in refined_options(opts):
        assert rerun.friction_width >= rerun.rtol
        integration_setup(case, rerun)


@pytest.mark.parametrize("method", ["auto", "set-valued"])
def test_convergence_check_of_a_width_free_choice_runs_at_any_rtol(method: str) -> None:
    """``auto`` and ``set-valued`` at rtol 1e-6 with the default width 1e-7: their check
    reruns the case on the regularised path at width 1e-8, rtol 1e-7 (narrower than
    rtol), which the rule does not bind (solve.limits.width_rule_waived)."""
    from obturator.solve import convergence_check, convergence_checks

    case = rig_case(300.0, 0.5473)  # slides from release: auto runs it regularised
    opts = SolverOptions(method=method, rtol=1e-6, atol=1e-8)
    narrow = refined_options(opts)[1]
    assert narrow.method == "regularised" and narrow.friction_width < narrow.rtol
    one = convergence_check(case, opts)
    assert math.isfinite(one.narrower_width) and math.isfinite(one.other_family)
    (batch,) = convergence_checks([case], opts)
    assert math.isfinite(batch.narrower_width)


def test_cli_refuses_width_below_rtol_in_one_line(tmp_path, capsys) -> None:
    from obturator.cli import main

    argv = ["sweep", "--method", "radau", "--rtol", "1e-6", "--spin-rate", "300,400",
            "--workers", "1", "--no-progress", "--out", str(tmp_path / "w.nc")]  # fmt: skip
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err == "obturator: error: " + WIDTH_BELOW_RTOL.format(method="radau") + "\n"
