"""Docstring sections shared word for word, and the fields of a class documented once.

Where several public functions take the same arguments with the same meaning (the
flow relations' ``mach`` and ``gamma``, the case constructors' physical inputs),
the numpydoc text for them is written once, as a fragment, and :func:`fill_doc`
puts it in place of a line ``{name}`` in each docstring when the module is
imported, so the descriptions cannot drift apart.

A result or settings class documents each field where it is declared, in a ``#:``
comment (the convention Sphinx autodoc reads); :func:`field_docs` turns those
comments into the numpydoc ``Attributes`` section of the class docstring, so
``help()`` shows them and the field list is written once, not again in prose.

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

import inspect
import linecache
import re
import sys
import textwrap
from collections.abc import Callable
from typing import TypeVar

__all__ = ["field_docs", "fill_doc"]

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


def field_docs(cls: type[_T]) -> type[_T]:
    """Class decorator: the ``#:`` comments above its fields become ``Attributes``.

    Each annotated field of the class body (``name: type``, with or without a
    default) that has one or more ``#:`` comment lines directly above it is listed
    as ``name : type`` with the comment as its description, in the order of
    declaration; the section is appended to the class docstring. The comments
    themselves are the ones Sphinx autodoc reads. Private fields (``_name``) may
    carry comments for the reader of the source; they are not listed.

    Parameters
    ----------
    cls : type
        A class whose body declares annotated fields (a dataclass, a NamedTuple).

    Returns
    -------
    type
        `cls`, with ``__field_docs__`` (field name -> description) set and its
        ``__doc__`` extended (left as is under ``python -OO`` or without source).
    """
    lines = _class_lines(cls)
    if lines is None:  # no source (frozen app, REPL): keep the docstring
        return cls
    docs: dict[str, str] = {}
    entries: list[str] = []
    comment: list[str] = []
    indent = None
    for line in lines:
        text = line.strip()
        if not text:
            continue
        depth = len(line) - len(line.lstrip())
        indent = depth if indent is None else indent
        if depth != indent:  # inside a docstring, a method or a bracket
            comment = []
        elif text.startswith("#:"):
            comment.append(text[2:].strip())
        else:
            field = _FIELD.match(text)
            if comment and field and not field[1].startswith("_"):  # private: source only
                docs[field[1]] = " ".join(comment)
                entries.append(f"{field[1]} : {field[2]}")
                entries += textwrap.wrap(
                    docs[field[1]], 84, initial_indent=" " * 4, subsequent_indent=" " * 4
                )
            comment = []
    cls.__field_docs__ = docs  # type: ignore[attr-defined]
    if cls.__doc__ and entries:
        section = "\n".join(["Attributes", "----------", *entries])
        cls.__doc__ = inspect.cleandoc(cls.__doc__) + "\n\n" + section + "\n"
    return cls


#: A field declaration ``name: annotation`` (a default, if any, after `` = ``).
_FIELD = re.compile(r"^([A-Za-z_]\w*)\s*:\s*(.+?)(?:\s+=\s.*)?$")
#: A class statement: its indentation and name.
_CLASS = re.compile(r"^([ \t]*)class\s+(\w+)\b")


def _class_lines(cls: type) -> list[str] | None:
    """The body lines of `cls`, found by its qualified name in its module's source.

    A text scan, not :func:`inspect.getsource` or :mod:`ast`: both parse the whole
    module, a cost every command's import pays for each decorated class (measured:
    ``docs/benchmarks.md``, history).
    """
    try:
        module = sys.modules[cls.__module__]
        lines = linecache.getlines(inspect.getsourcefile(module) or "")
    except (KeyError, TypeError):
        return None
    start, depth = 0, -1  # the enclosing class's indentation (-1: the module)
    for name in cls.__qualname__.split("."):
        for i in range(start, len(lines)):
            line = lines[i]
            indent = len(line) - len(line.lstrip())
            if depth >= 0 and line.strip() and indent <= depth:
                return None  # past the parent's block
            m = _CLASS.match(line)
            # a top-level class at column 0, a nested one inside its parent's block
            if m and m[2] == name and (indent > depth if depth >= 0 else indent == 0):
                start, depth = i + 1, indent
                break
        else:
            return None
    end = start
    while end < len(lines) and (
        not lines[end].strip() or len(lines[end]) - len(lines[end].lstrip()) > depth
    ):
        end += 1
    return [line.rstrip("\n") for line in lines[start:end]]
