"""One vocabulary for every command (issue 48): each concept has one spelling in every
command's help, the former spellings are hidden aliases that still parse, and every
option shown has a help text. The walk covers every sub-command and nested sub-command
(``gasdyn choke``), so a new option without help or with a second spelling fails here.
"""

from __future__ import annotations

import argparse

import pytest

from obturator.cli import _COMMANDS, build_parser

#: concept -> (the one spelling shown in help, former spellings accepted hidden).
VOCABULARY: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "convergence check": (
        ("--no-convergence-check", "--convergence-check"),  # off where on by default, or on
        ("--no-check", "--no-check-convergence", "--check-convergence"),
    ),
    "figure": (("--figure",), ("--plot",)),
    "workers": (("--workers",), ("--jobs",)),
    "progress": (("--no-progress",), ()),
    "output": (("--out",), ()),
    "drag curve": (("--drag",), ("--cd-table",)),
}
HIDDEN = {old for _, olds in VOCABULARY.values() for old in olds}
#: Other spellings of these concepts that must not come back, shown or hidden.
NEVER = ("--check", "--plot-file", "--fig", "--jobs-n", "--n-workers", "--progress", "--output")


def _parsers() -> list[tuple[str, argparse.ArgumentParser]]:
    """(name, parser) of every command and nested sub-command."""
    root = build_parser()
    todo = [("", root)]
    out = []
    while todo:
        name, p = todo.pop()
        for a in p._actions:
            if isinstance(a, argparse._SubParsersAction):
                todo.extend((f"{name} {k}".strip(), v) for k, v in a.choices.items())
        if name:
            out.append((name, p))
    return sorted(out, key=lambda x: x[0])


PARSERS = _parsers()


def _shown(p: argparse.ArgumentParser) -> list[argparse.Action]:
    return [a for a in p._actions if a.option_strings and a.help is not argparse.SUPPRESS]


def test_the_walk_reaches_every_command():
    assert {n.split()[0] for n, _ in PARSERS} == set(_COMMANDS)
    assert any(" " in n for n, _ in PARSERS)  # nested sub-commands too (gasdyn)


@pytest.mark.parametrize(("name", "parser"), PARSERS, ids=[n for n, _ in PARSERS])
def test_every_option_shown_has_help_and_one_spelling(name, parser):
    for a in _shown(parser):
        if a.dest == "help":
            continue
        assert a.help and a.help.strip(), f"{name} {a.option_strings[0]}: no help text"
        assert len(a.option_strings) == 1, f"{name}: {a.option_strings} shown for one option"
        assert not set(a.option_strings) & HIDDEN, f"{name}: former spelling {a.option_strings}"
    shown = [s for a in _shown(parser) for s in a.option_strings]
    assert len(shown) == len(set(shown))
    every = {s for a in parser._actions for s in a.option_strings}
    assert not every & set(NEVER), f"{name}: {sorted(every & set(NEVER))}"


@pytest.mark.parametrize(("name", "parser"), PARSERS, ids=[n for n, _ in PARSERS])
def test_one_spelling_per_concept_and_former_ones_are_hidden_aliases(name, parser):
    by_string = {s: a for a in parser._actions for s in a.option_strings}
    for concept, (spellings, olds) in VOCABULARY.items():
        shown = [s for s in spellings if s in by_string and by_string[s].help != argparse.SUPPRESS]
        if concept == "convergence check":  # exactly one of the pair is shown
            assert len(shown) <= 1, f"{name}: both {shown}"
        for old in olds:
            if old not in by_string:
                continue
            action = by_string[old]
            assert action.help == argparse.SUPPRESS, f"{name} {old}: former spelling shown"
            assert shown, f"{name} {old}: an alias without the spelling it stands for"
            assert action.dest == by_string[shown[0]].dest, f"{name} {old}: other destination"


@pytest.mark.parametrize(
    ("command", "old", "new"),
    [
        ("simulate", ["--no-check"], ["--no-convergence-check"]),
        ("montecarlo", ["--no-check-convergence"], ["--no-convergence-check"]),
        ("sweep", ["--check-convergence"], ["--convergence-check"]),
        ("simulate", ["--plot", "t.png"], ["--figure", "t.png"]),
        ("calibrate", ["--plot", "t.png"], ["--figure", "t.png"]),
        ("validate", ["--plot", "t.png", "--jobs", "3"], ["--figure", "t.png", "--workers", "3"]),
        ("warmup", ["--jobs", "3"], ["--workers", "3"]),
        ("trajectory", ["--cd-table", "tubular-open"], ["--drag", "tubular-open"]),
    ],
)
def test_a_former_spelling_parses_as_the_new_one(command, old, new, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    extra = {
        "sweep": ["--out", "s.nc"],
        "montecarlo": ["--vary", "mu_s=uniform:0.3,0.4", "--samples", "4"],
        "calibrate": ["runs.csv"],
    }
    (tmp_path / "runs.csv").write_text("t_cr_s,spin_rate_rad_s\n0.5,300\n")
    base = [command, *extra.get(command, [])]
    parser = build_parser(command)
    a, b = vars(parser.parse_args([*base, *old])), vars(parser.parse_args([*base, *new]))
    a.pop("func"), b.pop("func")
    assert a == b
    defaults = vars(parser.parse_args(base))
    assert any(defaults[k] != v for k, v in a.items())  # the flag changed something


@pytest.mark.parametrize(
    ("command", "default"),
    [
        ("simulate", True),
        ("montecarlo", True),
        ("sweep", False),
        ("trajectory", True),
        ("envelope", True),
        ("probability", True),
        ("sensitivity", True),
        ("optimize", True),
    ],
)
def test_the_convergence_check_is_one_destination_with_the_documented_default(command, default):
    extra = {
        "sweep": ["--out", "s.nc"],
        "montecarlo": ["--vary", "mu_s=uniform:0.3,0.4", "--samples", "4"],
        "envelope": ["--mach", "3", "--altitude-m", "0"],
    }
    parser = build_parser(command)
    args = parser.parse_args([command, *extra.get(command, [])])
    assert args.convergence_check is default
    flip = "--no-convergence-check" if default else "--convergence-check"
    assert parser.parse_args([command, *extra.get(command, []), flip]).convergence_check is (
        not default
    )


def _quantity_options() -> list[tuple[str, str, object]]:
    """(command, flag, kind) of every option that takes a quantity or an axis with a
    unit, found by walking the parsers (the one argument layer types them,
    ``cli/_kinds.py``)."""
    from obturator.cli._kinds import Axis, Quantity

    out = []
    for name, parser in PARSERS:
        for a in _shown(parser):
            if isinstance(a.type, Quantity | Axis) and a.type.unit not in ("", "1"):
                out.append((name, a.option_strings[-1], a.type))
    return out


QUANTITY_OPTIONS = _quantity_options()


def test_the_walk_finds_quantity_options_in_every_kind_of_command():
    commands = {n.split()[0] for n, _, _ in QUANTITY_OPTIONS}
    assert {"simulate", "sweep", "envelope", "optimize", "probability", "trajectory"} <= commands


@pytest.mark.parametrize(
    ("name", "flag", "kind"), QUANTITY_OPTIONS, ids=[f"{n} {f}" for n, f, _ in QUANTITY_OPTIONS]
)
def test_every_quantity_and_axis_option_accepts_units(name, flag, kind):
    """The option's example value written in the SI base unit (pint's conversion, an
    independent computation) gives the same value as the bare example in the option's
    unit: every such option reads units, as the README promises."""
    from obturator.cli._kinds import Axis
    from obturator.sweeps.grid import parse_axis
    from obturator.units import _registry

    ureg = _registry()
    if isinstance(kind, Axis):
        bare = float(parse_axis(kind(kind.example), "value", kind.unit)[0])
    else:
        bare = float(kind(kind.example))
    q = ureg.Quantity(bare, kind.unit).to_base_units()
    text = f"{q.magnitude!r} {q.units:~}"
    if isinstance(kind, Axis):
        got = float(parse_axis(kind(text), "value", kind.unit)[0])
    else:
        got = float(kind(text))
    assert got == pytest.approx(bare, rel=1e-12, abs=1e-12), (name, flag, text)
