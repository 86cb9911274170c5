"""The small helpers several packages share: docstring fragments, field docs, checked
dataclass copies, ``NAME=A<sep>B`` items, JSON numbers."""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import math
import pkgutil
from dataclasses import dataclass
from typing import NamedTuple

import pytest

import obturator
from obturator._docs import field_docs, fill_doc
from obturator.errors import InputError, replace_fields
from obturator.json_values import finite_or_none
from obturator.sweeps.distributions import split_assignment


def test_fill_doc_indents_the_fragment_as_its_placeholder() -> None:
    @fill_doc(params="x : float\n    Abscissa [m].")
    def f(x: float) -> float:
        """Identity.

        Parameters
        ----------
        {params}
        """
        return x

    lines = f.__doc__.splitlines()
    i = next(k for k, line in enumerate(lines) if line.strip() == "x : float")
    indent = len(lines[i]) - len(lines[i].lstrip())
    assert lines[i + 1] == " " * (indent + 4) + "Abscissa [m]."
    assert lines[i - 1].strip() == "----------"
    assert "{params}" not in f.__doc__


def test_fill_doc_leaves_braces_that_are_not_placeholders() -> None:
    @fill_doc()
    def f() -> None:
        """Choice {"a", "b"} and a set ``{x}`` in running text."""

    assert f.__doc__ == 'Choice {"a", "b"} and a set ``{x}`` in running text.'


def test_fill_doc_names_a_missing_fragment() -> None:
    with pytest.raises(KeyError, match="absent"):

        @fill_doc()
        def f() -> None:
            """Text.

            {absent}
            """


def test_the_case_constructors_share_the_input_docs() -> None:
    from obturator.calibration.rig_model import rig_model_case
    from obturator.model.cases import flight_case, rig_case

    for fn in (rig_case, flight_case, rig_model_case):
        assert "Sliding friction coefficient [-]." in fn.__doc__
        assert "{case_inputs}" not in fn.__doc__


@field_docs
@dataclass(frozen=True)
class _Documented:
    """A result.

    Prose that stays.
    """

    #: Times [s].
    t: float
    #: Nutation angle theta [rad], a description long enough to be wrapped over two
    #: comment lines in the source.
    theta: float = 0.0
    undocumented: int = 0

    def method(self) -> None:
        local: int = 1  # not a field: not listed
        del local


@field_docs
class _Row(NamedTuple):
    """A row."""

    #: Spin rate [rad/s].
    spin_rate: float


class _Holder:
    class _Shadowed:  # same name as the top-level class below, and before it
        x: int = 0

    @field_docs
    @dataclass(frozen=True)
    class Inner:
        """Nested."""

        #: The nested class's own field.
        z: int = 0


@field_docs
@dataclass(frozen=True)
class _Shadowed:
    """Top level."""

    #: The top-level class's field.
    y: int = 0


def test_field_docs_finds_the_class_by_its_qualified_name() -> None:
    assert _Shadowed.__field_docs__ == {"y": "The top-level class's field."}  # type: ignore[attr-defined]
    assert _Holder.Inner.__field_docs__ == {"z": "The nested class's own field."}  # type: ignore[attr-defined]


def test_field_docs_lists_the_commented_fields_in_order() -> None:
    doc = inspect.cleandoc(_Documented.__doc__ or "")
    assert doc.startswith("A result.\n\nProse that stays.\n\nAttributes\n----------\n")
    section = doc.split("----------\n", 1)[1].splitlines()
    assert section[0] == "t : float"
    assert section[1] == "    Times [s]."
    assert section[2] == "theta : float"
    # the two comment lines are one description, wrapped anew
    assert " ".join(x.strip() for x in section[3:]).startswith("Nutation angle theta [rad], a")
    assert "undocumented" not in doc and "local" not in doc
    assert _Documented.__field_docs__ == {  # type: ignore[attr-defined]
        "t": "Times [s].",
        "theta": "Nutation angle theta [rad], a description long enough to be wrapped over two "
        "comment lines in the source.",
    }
    assert "spin_rate : float\n    Spin rate [rad/s]." in (_Row.__doc__ or "")


def _documented_classes() -> list[type]:
    out = []
    for info in pkgutil.walk_packages(obturator.__path__, "obturator."):
        if info.name.startswith("obturator.__main__"):
            continue
        module = importlib.import_module(info.name)
        for obj in vars(module).values():
            if isinstance(obj, type) and obj.__module__ == module.__name__:
                if "__field_docs__" in vars(obj):
                    out.append(obj)
    return out


def test_every_field_of_a_documented_class_has_its_comment() -> None:
    """A class with ``@field_docs`` documents every field (a new field without a ``#:``
    comment fails here), and its docstring names each one; private fields are exempt."""
    classes = _documented_classes()
    assert len(classes) >= 50  # the package's result and settings classes
    for cls in classes:
        if dataclasses.is_dataclass(cls):
            names = [f.name for f in dataclasses.fields(cls)]
        else:
            names = list(cls._fields)  # type: ignore[attr-defined]
        names = [n for n in names if not n.startswith("_")]  # private fields need none
        documented = [n for n in cls.__field_docs__ if not n.startswith("_")]  # type: ignore[attr-defined]
        assert documented == names, cls.__qualname__  # type: ignore[attr-defined]
        for name in names:
            assert f"\n{name} : " in inspect.cleandoc(cls.__doc__ or ""), (cls, name)


@dataclass(frozen=True)
class _Pair:
    a: float
    b: float = 1.0

    def __post_init__(self) -> None:
        if self.b <= 0:
            raise InputError("b", "must be > 0")


def test_replace_fields_copies_and_checks_again() -> None:
    assert replace_fields(_Pair(1.0), "pair", {"b": 2.0}) == _Pair(1.0, 2.0)
    with pytest.raises(InputError, match="b: must be > 0"):
        replace_fields(_Pair(1.0), "pair", {"b": -1.0})


def test_replace_fields_names_the_unknown_field_and_the_allowed_ones() -> None:
    with pytest.raises(InputError, match=r"pair: unknown field 'c'; allowed: a, b"):
        replace_fields(_Pair(1.0), "pair", {"c": 2.0})


@pytest.mark.parametrize(
    "text,expected",
    [
        ("mu_s=0.3,0.4", ("mu_s", "0.3", "0.4")),
        ("  spin-rate=1,2,3 ", ("spin-rate", "1", "2,3")),
    ],
)
def test_split_assignment(text: str, expected: tuple[str, str, str]) -> None:
    assert split_assignment(text, "--bound", "NAME=LO,HI", ",") == expected


@pytest.mark.parametrize("text", ["mu_s", "mu_s=0.3", "a,b=1", "", None])
def test_split_assignment_names_the_expected_form(text: object) -> None:
    with pytest.raises(InputError, match=r"--bound: malformed .*: expected NAME=LO,HI"):
        split_assignment(text, "--bound", "NAME=LO,HI", ",")


def test_finite_or_none() -> None:
    import numpy as np

    assert finite_or_none(np.float64(2.5)) == 2.5
    assert type(finite_or_none(np.float64(2.5))) is float
    assert finite_or_none(math.inf) is None
    assert finite_or_none(-math.inf) is None
    assert finite_or_none(math.nan) is None
