"""The regularisation widths the Radau IIA paths cannot carry are refused in one line.

Refused: ``friction_width`` below ``MIN_FRICTION_WIDTH`` for the methods that integrate
stick phases with Radau IIA (measured by ``python -m benchmarks.regularised_limits``:
t_cr against the set-valued solver at rtol 1e-12); the methods that do not use the
width, or carry it, keep the whole allowed range.
"""

from __future__ import annotations

import pytest

from obturator import SolverOptions
from obturator.errors import InputError
from obturator.solve.limits import MIN_FRICTION_WIDTH


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
