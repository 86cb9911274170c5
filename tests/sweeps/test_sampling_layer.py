"""The one sampling layer of montecarlo, probability, sensitivity and optimize (issue 46).

Distribution numbers are read as a sweep axis reads its values (a unit after the last
number applies to all; a mixed list is refused), and a distribution that draws outside
its parameter's physical range (:data:`obturator.params.PARAMS`) is refused before any
work, in one line with exit 2. Reference values: unit conversions written out by hand
(1 rpm = 2 pi / 60 rad/s, 1 um = 1e-6 m), and the supports computed from the
definitions (MEAN +- 8 SD; MEDIAN exp(+-8 SIGMA_LN)).
"""

from __future__ import annotations

import math

import pytest

from obturator.cli import main
from obturator.envelope.uncertain import parse_input_distribution
from obturator.errors import InputError
from obturator.params import PARAMS
from obturator.sweeps.distributions import Distribution, check_support, parse_distribution

RPM = 2.0 * math.pi / 60.0


def _one_line_exit_2(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    assert main(argv) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith("obturator: error: ")
    return lines[0]


@pytest.mark.parametrize(
    "text",
    ["spin_rate=normal:3000,50 rpm", "spin_rate=normal:3000 rpm,50 rpm"],
)
def test_a_trailing_unit_applies_to_every_number(text: str) -> None:
    name, d = parse_distribution(text)
    assert name == "spin_rate" and d.kind == "normal"
    assert d.params == pytest.approx((3000 * RPM, 50 * RPM), rel=1e-15)


def test_mixed_units_are_refused_as_in_a_sweep() -> None:
    with pytest.raises(InputError, match="mixes values with and without a unit"):
        parse_distribution("spin_rate=normal:3000 rpm,50")


def test_lognormal_sigma_is_a_pure_number() -> None:
    # the trailing unit belongs to MEDIAN: SIGMA_LN, the SD of ln X, has no unit
    _, d = parse_distribution("spin_rate=lognormal:3000,0.1 rpm")
    assert d.params == pytest.approx((3000 * RPM, 0.1), rel=1e-15)
    with pytest.raises(InputError, match="SIGMA_LN"):
        parse_distribution("spin_rate=lognormal:3000 rpm,0.1 rpm")


def test_envelope_inputs_take_units_too() -> None:
    name, d = parse_input_distribution("gap=normal:50.8,2.5 um")
    assert name == "gap" and d.params == pytest.approx((50.8e-6, 2.5e-6), rel=1e-12)
    _, t = parse_input_distribution("theta0_deg=uniform:86.25,88.25")
    assert t.params == (86.25, 88.25)


@pytest.mark.parametrize(
    ("name", "dist", "ok"),
    [
        # mu_s in [0, 2]: 0.5 -+ 8 x 0.03 = [0.26, 0.74] inside, 0.5 -+ 8 x 0.1 reaches -0.3
        ("mu_s", Distribution("normal", (0.5, 0.03)), True),
        ("mu_s", Distribution("normal", (0.5, 0.1)), False),
        # 0.35 exp(+-8 x 0.1) = [0.157, 0.779] inside; exp(8 x 0.25) x 0.35 = 2.59 > 2
        ("mu_s", Distribution("lognormal", (0.35, 0.1)), True),
        ("mu_s", Distribution("lognormal", (0.35, 0.25)), False),
        # gap in (0, R_s): a uniform from 0 draws 0 itself
        ("gap", Distribution("uniform", (0.0, 1e-4)), False),
        ("gap", Distribution("truncnormal", (5.08e-5, 1e-4, 1e-5, 1e-4)), True),
    ],
)
def test_support_against_the_registry(name: str, dist: Distribution, ok: bool) -> None:
    rng = PARAMS[name].range
    assert rng is not None
    if ok:
        check_support(name, dist, rng)
    else:
        with pytest.raises(InputError, match=f"^{name}: .*outside the allowed range"):
            check_support(name, dist, rng)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["probability", "--vary", "mu_s=uniform:-1,1"],
            "obturator: error: mu_s: uniform:-1.0,1.0 draws values in [-1, 1], outside the "
            "allowed range [0, 2]; use uniform:LO,HI with LO, HI inside it",
        ),
        (
            ["probability", "--vary", "gap=normal:5.08e-5,1e-4"],
            "obturator: error: gap: normal:5.08e-05,0.0001 draws values in [-0.0007492, "
            "0.0008508] m within 8 SD, outside the allowed range (0, 0.007899) m; use "
            "truncnormal:MEAN,SD,LO,HI with LO, HI inside it or lognormal:MEDIAN,SIGMA_LN "
            "(positive values)",
        ),
        (
            ["montecarlo", "--case", "spin-rig", "--samples", "2", "--vary", "mu_s=uniform:-1,1"],
            "obturator: error: mu_s: uniform:-1.0,1.0 draws values in [-1, 1], outside the "
            "allowed range [0, 2]; use uniform:LO,HI with LO, HI inside it",
        ),
        (
            ["sensitivity", "--case", "spin-rig", "--vary", "gap=normal:5.08e-5,1e-4"],
            "obturator: error: gap: normal:5.08e-05,0.0001 draws values in",
        ),
        (
            ["montecarlo", "--case", "spin-rig", "--samples", "2", "--vary",
             "spin_rate=normal:3000 rpm,50"],
            "obturator: error: spin_rate: list '3000 rpm,50' mixes values with and without a "
            "unit",
        ),
        (
            # the registry's range holds; the trajectory's own limit (Mach <= 10) refuses
            ["probability", "--vary", "mach=uniform:2,30"],
            "obturator: error: mach: uniform:2.0,30.0 draws 30, which the model refuses "
            "(mach: 30 is outside the allowed range (1, 10])",
        ),
        (
            ["sensitivity", "--case", "spin-rig", "--mach", "2"],
            "obturator: error: --mach: applies to --case flight only",
        ),
        (
            ["optimize", "--figure", "front.png"],
            "obturator: error: --figure: draws the Pareto front: give --pareto N with it",
        ),
    ],
)  # fmt: skip
def test_examples_are_one_line_exit_2(
    capsys: pytest.CaptureFixture[str], tmp_path, monkeypatch, argv: list[str], message: str
) -> None:
    monkeypatch.chdir(tmp_path)
    line = _one_line_exit_2(capsys, argv)
    assert line.startswith(message)
    assert not (tmp_path / "front.png").exists()


class _Stop(Exception):
    pass


def test_launch_axes_read_units(capsys, monkeypatch) -> None:
    """``--altitude-m '0,1 km'`` is 0 m and 1000 m in probability, optimize and envelope,
    as in a sweep (each study is stopped where it first uses the values)."""
    import obturator.cli.robust as robust
    import obturator.envelope.envelope as envelope_mod
    import obturator.envelope.optimize as optimize_mod

    seen: dict[str, list[float]] = {}

    def launch(model, mach, altitude):
        seen.setdefault("probability", []).append(altitude)
        raise InputError("probe", "stop")

    monkeypatch.setattr(robust, "_launch", launch)
    assert main(["probability", "--altitude-m", "0,1 km", "--mach", "3"]) == 2
    assert seen["probability"] == [0.0]  # the first point, in m

    def problem(model, conditions, *a, **k):
        seen["optimize"] = [c["altitude_m"] for c in conditions]
        raise InputError("probe", "stop")

    monkeypatch.setattr(optimize_mod, "DesignProblem", problem)
    assert main(["optimize", "--altitude-m", "0,1 km", "--mach", "3"]) == 2
    assert seen["optimize"] == [0.0, 1000.0]

    def spec(machs, alts, temps, **k):
        seen["envelope"] = list(alts)
        raise InputError("probe", "stop")

    monkeypatch.setattr(envelope_mod, "EnvelopeSpec", spec)
    assert main(["envelope", "--altitude-m", "2 km", "--mach", "3"]) == 2
    assert seen["envelope"] == [2000.0]
    capsys.readouterr()


@pytest.mark.parametrize(
    ("bound", "message"),
    [
        # 40 m would have been read for LO before (its unit was HI's alone)
        ("gap=40 um,60", "obturator: error: gap: list '40 um,60' mixes values with and without"),
        ("mu_s=-1,0.4", "obturator: error: mu_s: bound -1 is outside the allowed range [0, 2]"),
        ("mu_s=0.4,0.3", "obturator: error: mu_s: bounds 0.4, 0.3 are empty (LO < HI)"),
    ],
)
def test_optimize_bounds_read_units_as_axes(capsys, bound: str, message: str) -> None:
    line = _one_line_exit_2(capsys, ["optimize", "--variables", "gap,mu_s", "--bound", bound])
    assert line.startswith(message)


def test_optimize_bound_with_a_trailing_unit(monkeypatch) -> None:
    import obturator.envelope.optimize as optimize_mod

    seen = {}

    def problem(model, conditions, bounds, **k):
        seen.update(bounds)
        raise InputError("probe", "stop")

    monkeypatch.setattr(optimize_mod, "DesignProblem", problem)
    assert main(["optimize", "--variables", "gap", "--bound", "gap=40,60 um"]) == 2
    assert seen["gap"] == pytest.approx((40e-6, 60e-6), rel=1e-12)
