"""Docstring sections shared word for word by a family of functions.

Where several public functions take the same arguments with the same meaning (the
flow relations' ``mach`` and ``gamma``, the case constructors' physical inputs),
the numpydoc text for them is written once, as a fragment, and :func:`fill_doc`
puts it in place of a line ``{name}`` in each docstring when the module is
imported, so the descriptions cannot drift apart.

>>> @fill_doc(params="Parameters\\n----------\\nx : float\\n    Abscissa [m].")
... def f(x):
...     '''Identity.
...
...     {params}
...     '''
>>> [line.strip() for line in f.__doc__.splitlines()][2:5]
['Parameters', '----------', 'x : float']
"""

from __future__ import annotations

import re
import textwrap
from collections.abc import Callable
from typing import TypeVar

__all__ = ["fill_doc"]

_T = TypeVar("_T")
#: A placeholder: a line holding only ``{name}``; its indentation is the fragment's.
_PLACEHOLDER = re.compile(r"^([ \t]*)\{(\w+)\}[ \t]*$", re.MULTILINE)


def fill_doc(**fragments: str) -> Callable[[_T], _T]:
    """Decorator replacing each docstring line ``{name}`` by ``fragments[name]``.

    Parameters
    ----------
    **fragments : str
        Docstring text by placeholder name; dedented, then indented as its
        placeholder line.

    Returns
    -------
    callable
        The decorator; it returns the function or class it is given, with its
        ``__doc__`` filled (left ``None`` under ``python -OO``).

    Raises
    ------
    KeyError
        If the docstring names a placeholder without a fragment.
    """

    def fill(match: re.Match[str]) -> str:
        text = textwrap.dedent(fragments[match[2]]).strip("\n")
        return textwrap.indent(text, match[1], lambda line: bool(line.strip()))

    def decorate(obj: _T) -> _T:
        if obj.__doc__:
            obj.__doc__ = _PLACEHOLDER.sub(fill, obj.__doc__)
        return obj

    return decorate
