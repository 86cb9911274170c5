"""The input contract of every command, generated from the argument registry.

The parsers of all commands are walked (sub-commands such as ``gasdyn start``
included); every option that takes a value must be declared with one of the
kinds of :mod:`obturator.cli._kinds` or a list of choices, and gets, from its
kind alone, the extreme numbers, wrong units, wrong types and path cases below.
A new command or flag is therefore fuzzed without anyone writing its cases.

The rule under test: a value is either accepted or refused with exit code 2 and
one line ``obturator: error: <field>: ...``; never a traceback, never "internal
error". Every option is fuzzed at the parse stage (where its kind checks it,
before any work; in-process, a few milliseconds a call); the commands whose work
is short (gasdyn, simulate with a 5 ms horizon) are also run to the end.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import io
import os
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from obturator.cli import _COMMANDS, build_parser, main
from obturator.cli._kinds import (
    Axis,
    Count,
    InputFile,
    Kind,
    NameOrFile,
    OutputDir,
    OutputFile,
    Quantity,
    Text,
    kind_of,
)

#: Options that are owned elsewhere and not yet typed (reported, not silently skipped).
NOT_YET_TYPED: set[tuple[str, str]] = set()  # options allowed to lack a kind (none)


def command_parsers() -> dict[tuple[str, ...], argparse.ArgumentParser]:
    """Every (sub-)command path -> its parser, e.g. ("gasdyn", "start")."""
    top = build_parser()
    out: dict[tuple[str, ...], argparse.ArgumentParser] = {}

    def walk(path: tuple[str, ...], parser: argparse.ArgumentParser) -> None:
        subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
        if path:
            if not subs:
                out[path] = parser
        for sub in subs:
            for name, child in sub.choices.items():
                walk((*path, name), child)

    walk((), top)
    return out


PARSERS = command_parsers()


def value_options(parser: argparse.ArgumentParser) -> list[argparse.Action]:
    """The options and positionals that take a value."""
    skip = (argparse._HelpAction, argparse._VersionAction, argparse._SubParsersAction)
    return [a for a in parser._actions if a.nargs != 0 and not isinstance(a, skip)]


def test_all_commands_are_in_the_registry():
    assert {p[0] for p in PARSERS} == set(_COMMANDS)
    assert len(PARSERS) == 17  # 13 commands + gasdyn's 4 topics


@pytest.mark.parametrize("path", sorted(PARSERS), ids=" ".join)
def test_every_option_goes_through_the_argument_layer(path):
    """A command that bypasses the shared kinds (a bare string option) fails here."""
    bare = [
        a.option_strings[0] if a.option_strings else a.dest
        for a in value_options(PARSERS[path])
        if kind_of(a) is None and a.choices is None
    ]
    bare = [f for f in bare if (path[0], f) not in NOT_YET_TYPED]
    assert not bare, f"{' '.join(path)}: options without a kind: {bare}"


# --------------------------------------------------------------------------- cases by kind

NUMBERS = [
    "0", "-0", "-1", "nan", "inf", "-inf", "1e308", "-1e308", "1e-320", "1e999", "", " ",
    "abc", "1,5", "0x10", "1_000", "9**9**9", "1e300", "1e-300", "()", "'", "\u00b5", "1 2",
]  # fmt: skip
WRONG_UNITS = ["30 deg", "12 kg", "1 rad", "30 Hz", "2 m", "5 s", "1 bogusunit", "3 m/s^2"]
COUNTS = ["-1", "0", "1", "1.5", "1e3", "", "abc", "99999999999999999999999", "10**100", "-0"]
TEXTS = [
    "",
    " ",
    "\x01",
    "a" * 2000,
    "=",
    ":",
    "\u00e9\u00e8",
    "x=y:1,2",
    "mu_s=normal:1e308,1e308",
]


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict[str, str]:
    """Path cases: special files, loops, bad encodings, and valid examples."""
    d = tmp_path_factory.mktemp("paths")
    (d / "dir").mkdir()
    (d / "regular.txt").write_text("x\n", encoding="utf-8")
    (d / "latin1.csv").write_bytes("mach,cd\n3,\xe9\n".encode("latin-1"))
    (d / "nul.toml").write_bytes(b"a = 1\x00\n")
    (d / "big.csv").write_bytes(b"1," * (600 * 1024))
    (d / "deep.toml").write_text("a = " + "[" * 5000 + "]" * 5000 + "\n", encoding="utf-8")
    (d / "runs.csv").write_text("spin_rate_rad_s,t_cr_s\n300,0.2\n400,0.3\n", encoding="utf-8")
    (d / "input").write_text("", encoding="utf-8")
    os.mkfifo(d / "fifo")
    os.symlink(d / "loop", d / "loop")
    return {
        "dir": str(d / "dir"),
        "regular": str(d / "regular.txt"),
        "latin1": str(d / "latin1.csv"),
        "nul": str(d / "nul.toml"),
        "big": str(d / "big.csv"),
        "deep": str(d / "deep.toml"),
        "fifo": str(d / "fifo"),
        "loop": str(d / "loop"),
        "through_loop": str(d / "loop" / "x.nc"),
        "missing_dir": str(d / "nope" / "x.nc"),
        "missing": str(d / "nope.csv"),
        "bad_suffix": str(d / "x.xyz"),
        "new": str(d / "new.nc"),
        "root": str(d),
    }


def path_cases(files: dict[str, str]) -> list[str]:
    return [
        "", ".", "..", "/", "/dev/zero", "/dev/null", "\x00", files["dir"], files["regular"],
        files["latin1"], files["nul"], files["big"], files["deep"], files["fifo"],
        files["loop"], files["through_loop"], files["missing_dir"], files["missing"],
        files["bad_suffix"], files["new"],
    ]  # fmt: skip


def cases(kind: Kind | None, action: argparse.Action, files: dict[str, str]) -> list[str]:
    """The values every option of this kind gets."""
    if isinstance(kind, Quantity | Axis):
        rng = kind.range
        edges = [repr(x) for x in (rng.lo, rng.hi) if abs(x) < 1e300]
        edges += [repr(x * 10 + 1) for x in (rng.lo, rng.hi) if abs(x) < 1e300]
        extra = ["1,2,3", "1:2:3", "3:1:1", "1:2:1e9", "0,1 km", "1000,2000 rpm", "1 km,2"]
        return [
            kind.example,
            *NUMBERS,
            *WRONG_UNITS,
            *edges,
            *(extra if isinstance(kind, Axis) else []),
        ]
    if isinstance(kind, Count):
        return [kind.example, *COUNTS, str(kind.lo - 1), str(kind.hi), str(kind.hi + 1)]
    if isinstance(kind, OutputFile | OutputDir | InputFile | NameOrFile):
        return [kind.example, *path_cases(files)]
    if isinstance(kind, Text):
        return [kind.example, *TEXTS]
    return [*(action.choices or []), "bogus", "", "-1"]  # choices, or an untyped option


def minimal_argv(path: tuple[str, ...], files: dict[str, str], but: argparse.Action) -> list[str]:
    """The command with valid values for its required options (other than `but`)."""
    parser = PARSERS[path]
    argv = list(path)
    groups = [g for g in parser._mutually_exclusive_groups if g.required]
    needed = [a for a in parser._actions if a.required and a is not but]
    needed += [g._group_actions[0] for g in groups if but not in g._group_actions]
    for a in needed:
        kind = kind_of(a)
        value = example(kind, files) if kind else a.choices[0]
        argv += [value] if not a.option_strings else [a.option_strings[0], value]
    return argv


def example(kind: Kind, files: dict[str, str]) -> str:
    """A valid value of `kind`, paths in the test folder."""
    if isinstance(kind, OutputFile | OutputDir):
        return os.path.join(files["root"], "out", kind.example)  # a missing sub-folder
    if isinstance(kind, InputFile):
        return os.path.join(files["root"], kind.example)
    return kind.example


def call(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main(argv)
    return rc, out.getvalue(), err.getvalue()


@functools.cache
def _parser(command: str) -> argparse.ArgumentParser:
    return build_parser(command)  # parsing does not change a parser: one per command


def parse(path: tuple[str, ...], argv: list[str]) -> tuple[int, str]:
    """Parse only (the checks of the kinds, no work): exit code and stderr."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            _parser(path[0]).parse_args(argv)
            rc = 0
        except SystemExit as exc:
            rc = int(exc.code or 0)
    return rc, err.getvalue()


def check_refusal(rc: int, err: str, argv: list[str]) -> None:
    assert "Traceback" not in err, argv
    assert "internal error" not in err, (argv, err)
    assert rc in (0, 2, 3), (argv, rc, err)
    if rc == 2:
        assert err.startswith("obturator: error: ") and err.count("\n") == 1, (argv, err)
        field = err[len("obturator: error: ") :].split(":", 1)[0]
        assert field.strip(), (argv, err)  # names the field


def option_name(a: argparse.Action) -> str | None:
    return a.option_strings[0] if a.option_strings else None


#: Parse-stage values per (command, option): filled by the test, reported at the end.
COUNTED: dict[str, int] = {}


@pytest.mark.parametrize("path", sorted(PARSERS), ids=" ".join)
def test_every_option_every_case_at_the_parse_stage(path, files):
    """Each option of the command gets every case of its kind, deterministically."""
    parser = PARSERS[path]
    n = 0
    for action in value_options(parser):
        flag = option_name(action)
        if flag is None and kind_of(action) is None:
            continue
        for value in cases(kind_of(action), action, files):
            base = minimal_argv(path, files, action)
            argv = [*base, flag, value] if flag else [*base, value]
            if flag is None:  # a positional: put it right after the command
                argv = [*path, value, *base[len(path) :]]
            if "\x00" in value:
                continue  # the OS refuses NUL in argv before we ever see it
            rc, err = parse(path, argv)
            check_refusal(rc, err, argv)
            n += 1
    COUNTED[" ".join(path)] = n
    assert n > 0 or not value_options(parser)


FAST = settings(
    max_examples=40,
    deadline=None,
    derandomize=True,  # reproducible in CI
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)


@FAST
@given(data=st.data())
@pytest.mark.parametrize("path", sorted(PARSERS), ids=" ".join)
def test_random_values_at_the_parse_stage(path, files, data):
    options = [a for a in value_options(PARSERS[path]) if option_name(a)]
    if not options:
        return
    action = data.draw(st.sampled_from(options))
    value = data.draw(
        st.one_of(
            st.sampled_from(cases(kind_of(action), action, files)),
            st.floats(allow_nan=True, allow_infinity=True).map(repr),
            st.integers(min_value=-(10**30), max_value=10**30).map(str),
            st.text(max_size=30).filter(lambda t: "\x00" not in t),
            st.tuples(st.floats(-1e6, 1e6), st.sampled_from(WRONG_UNITS)).map(
                lambda t: f"{t[0]!r} {t[1].split(' ', 1)[1]}"
            ),
        )
    )
    argv = [*minimal_argv(path, files, action), option_name(action), value]
    rc, err = parse(path, argv)
    check_refusal(rc, err, argv)


# --------------------------------------------------------------------------- run to the end

RUNNABLE = {p: extra for p, extra in {
    ("gasdyn", "normal-shock"): [],
    ("gasdyn", "start"): [],
    ("gasdyn", "choke"): [],
    ("gasdyn", "atmosphere"): [],
    ("simulate",): ["--no-check", "--t-max", "0.005"],
}.items()}  # fmt: skip


#: Commands whose every case runs to the end in minutes (slow: CI's full run only).
RUNNABLE_SLOW = {
    ("trajectory",): ["--t-max", "0.002", "--no-convergence-check", "--segment", "1 ms"],
    ("calibrate",): ["--bootstrap", "0"],
    ("envelope",): ["--t-max", "0.002", "--no-convergence-check", "--workers", "1"],
}


@pytest.mark.parametrize("path", sorted(RUNNABLE), ids=" ".join)
def test_short_commands_run_to_the_end_with_every_case(path, files, tmp_path):
    """gasdyn and a 5 ms simulate: the whole command, not only the parse."""
    _run_every_case(path, RUNNABLE[path], files, tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("path", sorted(RUNNABLE_SLOW), ids=" ".join)
def test_study_commands_run_to_the_end_with_every_case(path, files, tmp_path):
    """trajectory, calibrate, envelope at a 2 ms horizon: the whole command."""
    _run_every_case(path, RUNNABLE_SLOW[path], files, tmp_path)


def _run_every_case(path, extra, files, tmp_path):
    parser = PARSERS[path]
    for action in value_options(parser):
        flag = option_name(action)
        if flag is None:
            continue
        for value in cases(kind_of(action), action, files):
            if "\x00" in value or value == "/dev/null":
                continue  # the device case runs on a stand-in (tests/cli/test_output_files.py)
            if isinstance(kind_of(action), OutputFile | OutputDir) and value == files["new"]:
                value = str(tmp_path / Path(value).name)
            if flag in extra or flag in ("--workers", "--scheduler"):
                continue  # the horizon and the in-process run stay as set
            argv = [*minimal_argv(path, files, action), flag, value, *extra]
            rc, out, err = call(argv)
            check_refusal(rc, err, argv)


def test_report_counts(capsys):
    """Prints the number of parse-stage cases per command (run with -s to see it)."""
    with capsys.disabled():
        for name, n in sorted(COUNTED.items()):
            print(f"contract cases {name}: {n}")
