"""Help texts say what the README and the behaviour say (issue 32: they contradicted
each other on units, the near-stick accuracy and what ``warmup`` compiles)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from obturator.cli import _COMMANDS, build_parser, main
from obturator.warmup import WARMUP_TARGETS

_ROOT = Path(__file__).resolve().parents[2]
# the README and the docs pages its reference moved to
README = "\n".join(
    p.read_text(encoding="utf-8")
    for p in [_ROOT / "README.md", *sorted((_ROOT / "docs").rglob("*.md"))]
    if "_build" not in p.parts
)


def _help(command: str) -> str:
    parser = build_parser(command, full=True)
    sub = next(a for a in parser._actions if a.dest == "command")
    return " ".join(sub.choices[command].format_help().split())  # type: ignore[attr-defined]


def _options(command: str) -> set[str]:
    """Every option of `command`, its own sub-commands' included (gasdyn choke ...)."""
    parser = build_parser(command, full=True)
    sub = next(a for a in parser._actions if a.dest == "command")
    todo, out = [sub.choices[command]], set()  # type: ignore[attr-defined]
    while todo:
        p = todo.pop()
        for a in p._actions:
            out.update(a.option_strings)
            if a.choices and isinstance(a.choices, dict):
                todo.extend(v for v in a.choices.values() if hasattr(v, "_actions"))
    return out


def test_readme_lists_every_command():
    # the list itself: backquoted command names only (a benchmark note's "Commands:
    # `python -m ...`" must not be mistaken for it)
    listed = re.search(r"Commands: ((?:`[\w-]+`,?\s*(?:and\s+)?)+)", README)
    assert listed
    names = set(re.findall(r"`([\w-]+)`", listed.group(1)))
    assert names == set(_COMMANDS)


def _readme_command_lines() -> list[tuple[str, str]]:
    """(command, rest) of every ``obturator COMMAND ...`` the README shows."""
    spans = re.findall(r"`obturator ([\w-]+)([^`]*)`", README)
    spans += re.findall(r"^\$ obturator ([\w-]+)(.*(?:\\\n.*)*)$", README, re.M)
    return [(c, r) for c, r in spans if c in _COMMANDS]


@pytest.mark.parametrize("command", sorted({c for c, _ in _readme_command_lines()}))
def test_every_flag_the_readme_shows_exists(command):
    """e.g. the README gave ``--density`` as a units example, which simulate lacks."""
    options = _options(command)
    used = {
        f
        for c, rest in _readme_command_lines()
        if c == command
        for f in re.findall(r"(?<![\w-])--[a-z][\w-]*", rest.split("#")[0])
    }
    assert used <= options, sorted(used - options)


def test_sweep_help_says_values_take_units_and_they_do(tmp_path, capsys):
    text = _help("sweep")
    assert "SI units." not in text and "take units" in text
    out = tmp_path / "s.nc"
    spec = "2864.789:3819.719:2 rpm"  # 300 and 400 rad/s
    assert main(["sweep", "--spin-rate", spec, "--out", str(out), "--workers", "1"]) == 0
    import xarray as xr

    with xr.open_dataset(out) as ds:
        assert ds["spin_rate"].values == pytest.approx([300.0, 400.0], rel=1e-6)


def test_tcr_rtol_help_states_the_readmes_near_stick_accuracy():
    """The one-trajectory path's worst error below 100 rad/s at the default rtol (README,
    measured by benchmarks.dense_accuracy) is what the --tcr-rtol help promises."""
    readme = re.search(r"one-trajectory path's \*\*([\d.e-]+)\*\*", README)
    helped = re.search(r"<= ([\d.e-]+) below\)", _help("sweep"))
    assert readme and helped
    assert float(helped.group(1)) == float(readme.group(1))


def test_warmup_help_names_every_integrator_it_compiles():
    text = _help("warmup")
    assert "lanes" in text and "loaded" in text
    assert len(WARMUP_TARGETS) - 1 == 5 and "five integrators" in text  # + rosenbrock
