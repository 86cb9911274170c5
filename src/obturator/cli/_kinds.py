"""What each command-line value is: the one argument layer of every command.

Every option that takes a value is declared with ``type=`` one of the kinds
below (or with ``choices``), so argparse converts and checks it while parsing,
before any work: quantities with units and a range, whole numbers with a
bound, sweep axes, output files and folders, input files, bounded free text.
A bad value ends the run with one line ``obturator: error: --flag: ...`` and
exit code 2 (``cli._Parser.error``). ``tests/cli/test_cli_contract.py`` fails when
an option bypasses this layer, and fuzzes every option of every command from
its kind, so a new command or flag is covered without writing its cases.
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass, field

from ..errors import InputError
from ..params import Range

__all__ = [
    "Kind",
    "Quantity",
    "Count",
    "Axis",
    "OutputFile",
    "OutputDir",
    "InputFile",
    "Text",
    "SchedulerAddress",
    "NameOrFile",
    "kind_of",
    "MAX_TEXT",
]

#: Longest free-text value (distribution specs, name lists, addresses) [characters].
MAX_TEXT = 1000


def _refuse(exc: InputError) -> argparse.ArgumentTypeError:
    """The message of `exc` without its field (argparse prefixes the flag)."""
    text = str(exc)
    prefix = f"{exc.field}: "
    return argparse.ArgumentTypeError(text[len(prefix) :] if text.startswith(prefix) else text)


def _outside(x: float, rng: Range, unit: str) -> str:
    u = f" {unit}" if unit else ""
    return f"{x:g}{u} is outside the allowed range {rng}{u}"


class Kind:
    """Base of the value kinds: ``kind(text)`` converts or raises ArgumentTypeError."""

    __name__ = "value"  # argparse names the type in some messages

    def convert(self, text: str) -> object:  # pragma: no cover - abstract
        raise NotImplementedError

    def __call__(self, text: str) -> object:
        if not isinstance(text, str):
            return text  # a default that is already converted
        if len(text) > MAX_TEXT:
            raise argparse.ArgumentTypeError(f"longer than {MAX_TEXT} characters")
        try:
            return self.convert(text)
        except InputError as exc:
            raise _refuse(exc) from None


@dataclass(eq=False)
class Quantity(Kind):
    """A number or quantity with a unit (``"11 km"``, ``"36089 ft"``) -> float in `unit`.

    `unit` is pint syntax (``""``: a pure number); `range` bounds the value in
    `unit`; `example` is a valid value (for the generated tests).
    """

    unit: str
    range: Range = field(default_factory=lambda: Range(-math.inf, math.inf, True, True))
    example: str = "1"

    def convert(self, text: str) -> float:
        from ..units import parse_quantity

        x = parse_quantity("value", text, self.unit)
        if not self.range.contains(x):
            raise InputError("value", _outside(x, self.range, self.unit))
        return x


@dataclass(eq=False)
class Count(Kind):
    """A whole number in [lo, hi] (the bound's reason is in the flag's help)."""

    lo: int = 1
    hi: int = 2**63 - 1
    example: str = "1"

    def convert(self, text: str) -> int:
        try:
            n = int(text.strip())
        except ValueError:
            raise InputError("value", f"expected a whole number, got {text!r}") from None
        if not self.lo <= n <= self.hi:
            raise InputError("value", f"{n} is outside the allowed range [{self.lo}, {self.hi}]")
        return n


@dataclass(eq=False)
class Axis(Kind):
    """A sweep axis ``START:STOP:COUNT`` or ``a,b,c`` with units; the text is kept.

    Every value must lie in `range` (in `unit`).
    """

    unit: str
    range: Range = field(default_factory=lambda: Range(-math.inf, math.inf, True, True))
    example: str = "1"

    def convert(self, text: str) -> str:
        from ..sweeps.grid import parse_axis

        values = parse_axis(text, "value", self.unit)
        bad = [float(v) for v in values if not self.range.contains(float(v))]
        if bad:
            raise InputError("value", _outside(bad[0], self.range, self.unit))
        return text


@dataclass(eq=False)
class OutputFile(Kind):
    """A file to write, checked before any work (:func:`obturator.files.check_output_path`).

    ``figure=True`` allows the formats matplotlib can write; `suffixes` others.
    """

    suffixes: tuple[str, ...] | None = None
    figure: bool = False
    example: str = "out.nc"

    def convert(self, text: str) -> str:
        from ..files import check_output_path

        suffixes = self.suffixes
        if self.figure:
            from ..plotting import figure_suffixes

            suffixes = figure_suffixes()
        check_output_path("value", text, suffixes)
        return text


@dataclass(eq=False)
class OutputDir(Kind):
    """A folder to write into (created), checked before any work."""

    example: str = "outdir"

    def convert(self, text: str) -> str:
        from ..files import check_output_dir

        check_output_dir("value", text)
        return text


@dataclass(eq=False)
class InputFile(Kind):
    """A text file to read (config, data CSV, drag table): the shared reader's checks."""

    example: str = "input"

    def convert(self, text: str) -> str:
        from ..files import read_text_file

        read_text_file(text, "value")
        return text


@dataclass(eq=False)
class NameOrFile(Kind):
    """One of `names`, or else a readable text file."""

    names: tuple[str, ...] = ()
    example: str = ""

    def convert(self, text: str) -> str:
        if text in self.names:
            return text
        from ..files import read_text_file

        if not text.strip():
            raise InputError("value", f"expected one of {', '.join(self.names)} or a file")
        read_text_file(text, "value")
        return text


@dataclass(eq=False)
class Text(Kind):
    """Free text checked by the command (distribution specs, names, addresses)."""

    example: str = "x"

    def convert(self, text: str) -> str:
        if not text.strip():
            raise InputError("value", "empty value")
        if any(ord(c) < 32 for c in text):
            raise InputError("value", "contains control characters")
        return text


@dataclass(eq=False)
class SchedulerAddress(Text):
    """A dask.distributed scheduler address: refused while parsing, before any work, when
    the ``cluster`` extra that connects to it is not installed."""

    def convert(self, text: str) -> str:
        from ..runs.cluster import needs_cluster_extra

        text = super().convert(text)
        needs_cluster_extra()
        return text


def kind_of(action: argparse.Action) -> Kind | None:
    """The kind of an option (None for flags without a value and choice lists)."""
    return action.type if isinstance(action.type, Kind) else None
