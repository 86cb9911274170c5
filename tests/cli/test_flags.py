"""Options declared once (obturator.cli._flags): a command's change to a shared flag stays
its own, and a command's one-line help is the one of obturator.cli._COMMANDS."""

from __future__ import annotations

import argparse

import pytest

from obturator.cli import _COMMANDS, build_parser
from obturator.cli._flags import JSON, SEED_FLAG, add_command, add_flags


def _option(parser: argparse.ArgumentParser, flag: str) -> argparse.Action:
    return next(a for a in parser._actions if flag in a.option_strings)


def test_a_commands_change_leaves_the_shared_flag_as_declared():
    changed = SEED_FLAG.but(metavar="N", help="bootstrap seed")
    assert changed.settings["metavar"] == "N" and changed.settings["help"] == "bootstrap seed"
    assert SEED_FLAG.settings["metavar"] == "S" and SEED_FLAG.settings["help"].startswith("random")
    assert changed.names == SEED_FLAG.names
    with pytest.raises(TypeError):  # read-only: no command can edit it for the others
        SEED_FLAG.settings["default"] = "1"  # type: ignore[index]


def test_add_command_takes_the_help_of_the_command_table_and_the_flags_in_order():
    parser = argparse.ArgumentParser()
    sub = parser.add_subparsers(dest="command")
    p = add_command(sub, "warmup", lambda args: 0, "description", JSON)
    add_flags(p, SEED_FLAG.but(default="7"))
    assert sub._choices_actions[0].help == _COMMANDS["warmup"][1]
    assert [a.dest for a in p._actions] == ["help", "json", "seed"]
    args = parser.parse_args(["warmup", "--json"])
    assert args.json is True and args.seed == 7 and args.func(args) == 0  # default typed


def test_the_seed_of_calibrate_and_of_montecarlo_differ_only_where_declared():
    sub = next(a for a in build_parser()._actions if a.dest == "command")
    mc = _option(sub.choices["montecarlo"], "--seed")  # type: ignore[attr-defined]
    cal = _option(sub.choices["calibrate"], "--seed")  # type: ignore[attr-defined]
    assert mc.type is cal.type  # one kind (obturator.cli._args.SEED)
    # calibrate's default is unset (None, resolved to 0 after parsing) so that a seed given
    # with --bootstrap 0, which it would not act on, is refused
    assert (mc.metavar, mc.default, cal.metavar, cal.default) == ("S", "0", "N", None)
