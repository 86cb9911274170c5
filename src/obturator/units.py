"""Units at the edge: quantities such as "7.899 mm" or "115000 rpm" to SI floats.

The numeric core takes SI floats only. Users may write quantities with units
in config files, on the command line and as :class:`pint.Quantity` arguments
of the case factories; :func:`parse_quantity` converts them, once, and rejects
them with a message naming the field when the unit is wrong or the text is not
a quantity. The radian is a dimension of its own here, so angles never pass
for pure numbers and frequencies in cycles convert with 2 pi rad per cycle.

>>> parse_quantity("spin_rate", "60 rpm", "rad/s")  # doctest: +ELLIPSIS
6.283185307179...
"""

from __future__ import annotations

import math
import re
from functools import lru_cache
from typing import Any

from .errors import InputError

__all__ = ["parse_quantity", "MAX_QUANTITY_TEXT"]

#: Longest quantity text accepted [characters].
MAX_QUANTITY_TEXT = 64
_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d{1,3})?"
_UNIT_TOKEN = r"[A-Za-z\u00b5\u03bc\u00b0\u03a9_%]+(?:\s*(?:\^|\*\*)\s*[-+]?\d)?"
_UNIT = rf"{_UNIT_TOKEN}(?:\s*(?:\*|/|\u00b7|\s)\s*{_UNIT_TOKEN})*"
_QUANTITY = re.compile(rf"^\s*({_NUMBER})\s*({_UNIT})?\s*$")


@lru_cache(maxsize=1)
def _registry():
    """pint registry in which the radian is a dimension of its own ([angle]).

    pint's default makes the radian dimensionless, so "30 Hz" converts to
    30 rad/s (not 2 pi 30) and "30 deg" to the pure number 0.52. With [angle]
    a dimension, angles never pass for pure numbers and a frequency in cycles
    (1/[time]) is recognised and converted with 2 pi rad per cycle.
    """
    import shutil
    import tempfile
    from pathlib import Path as _Path

    import pint

    src = _Path(pint.__file__).parent
    tmp = _Path(tempfile.mkdtemp(prefix="obturator-pint-"))
    for f in src.glob("*.txt"):
        shutil.copy(f, tmp / f.name)
    default = tmp / "default_en.txt"
    text = default.read_text(encoding="utf-8")
    if "radian = [] = rad" not in text:  # pragma: no cover - a pint we do not know
        raise RuntimeError("unexpected pint definitions: radian is not 'radian = [] = rad'")
    default.write_text(text.replace("radian = [] = rad", "radian = [angle] = rad", 1))
    ureg = pint.UnitRegistry(str(default), cache_folder=None)
    ureg.define("rev = revolution")
    shutil.rmtree(tmp, ignore_errors=True)
    return ureg


def parse_quantity(field: str, value: Any, unit: str) -> float:
    """Convert a number or a quantity string to a float in `unit`.

    Parameters
    ----------
    field : str
        Name used in error messages.
    value : float or str or pint.Quantity
        A bare number (taken to be in `unit` already), a :class:`pint.Quantity`,
        or text "NUMBER UNIT" such as ``"7.899 mm"`` or ``"115000 rpm"``. The
        text is parsed as one number and one unit expression (no arithmetic is
        evaluated; at most :data:`MAX_QUANTITY_TEXT` characters).
    unit : str
        Target unit (pint syntax); ``""`` for dimensionless. A frequency given
        in cycles (Hz, 1/s) for an angular rate (``"rad/s"``) is converted with
        2 pi rad per cycle; revolutions (rpm, rev/s) likewise.

    Returns
    -------
    float
        Magnitude in `unit`.

    Raises
    ------
    InputError
        If the text is not a quantity, is too long, has incompatible
        dimensions (an angle for a pure number, say), or is not finite.
    """
    if isinstance(value, bool):
        raise InputError(field, f"expected a number or a quantity, got {value!r}")
    if isinstance(value, int | float):
        if not math.isfinite(float(value)):
            raise InputError(field, f"{value!r} is not finite")
        return _normal(field, float(value))
    if hasattr(value, "magnitude") and hasattr(value, "units"):  # a pint.Quantity
        value = f"{float(value.magnitude)!r} {value.units:~}"
    if not isinstance(value, str):
        raise InputError(field, f"expected a number or a quantity string, got {value!r}")
    text = value.strip()
    if len(text) > MAX_QUANTITY_TEXT:
        raise InputError(field, f"quantity text longer than {MAX_QUANTITY_TEXT} characters")
    m = _QUANTITY.match(text)
    if m is None:
        raise InputError(
            field, f"{text!r} is not a number or a number with a unit (e.g. '7.899 mm')"
        )
    number = float(m.group(1))
    if not math.isfinite(number):
        raise InputError(field, f"{text!r} is not finite")
    if m.group(2) is None:
        return _normal(field, number)
    import pint

    ureg = _registry()
    try:
        q = ureg.Quantity(number, ureg.parse_units(m.group(2).replace("\u00b7", "*")))
    except (pint.UndefinedUnitError, pint.DefinitionSyntaxError, ValueError, AttributeError):
        raise InputError(field, f"{text!r}: unknown unit {m.group(2)!r}") from None
    target = ureg.parse_units(unit) if unit else ureg.dimensionless
    if (
        target.dimensionality == ureg.parse_units("rad/s").dimensionality
        and q.dimensionality == ureg.parse_units("1/s").dimensionality
    ):
        q = q * ureg.Quantity(2.0 * math.pi, "rad")  # cycles per time -> rad per time
    try:
        out = float(q.to(target).magnitude)
    except pint.DimensionalityError:
        what = unit if unit else "a pure number (no unit)"
        raise InputError(field, f"{text!r} cannot be converted to {what}") from None
    if not math.isfinite(out):
        raise InputError(field, f"{text!r} is not finite in {unit or 'pure numbers'}")
    return _normal(field, out)


def _normal(field: str, x: float) -> float:
    if x != 0.0 and abs(x) < 2.2250738585072014e-308:
        raise InputError(field, f"{x:g} is subnormal; use 0 or a normal number")
    return x
