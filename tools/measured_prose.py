"""Count the prose lines of ``src/`` that quote measured figures (issue 44, item 5).

Code comments and docstrings state contracts, reasons and references; what a machine
measured on a day (timings, speed-ups, the machine, the date) belongs in
``docs/benchmarks.md``, which ``python -m benchmarks report`` regenerates. This tool
counts the prose lines that still quote such figures::

    python tools/measured_prose.py                 # total and per top-level folder
    python tools/measured_prose.py --files         # per file too
    python tools/measured_prose.py --list          # every counted line, with its rules
    python tools/measured_prose.py --list --only solve/dispatch.py

Prose is every comment (``# ...``, ``#: ...``) and every string-literal statement
(module, class and function docstrings, attribute docstrings); code, including string
literals that are values (messages, help texts), is not prose. A rule of :data:`RULES`
(regular expressions, case-insensitive) marks a figure:

* ``timing``: a cost in time: ``ms``/``us``/``ns`` next to a cost word (per, each,
  against, took, costs, measured, ...), ``points/s``, ``s per point``, or seconds next
  to ``wall``, ``took``, ``costs``, ``compile``, ``cold``, ``warm``, ``workers``,
  ``start-up``, ``import``;
* ``speed-up``: ``1.4x``, ``3-4.6x``, ``speed-up``, ``faster``/``slower``/``cheaper``
  within 40 characters of a number, ``17 % fewer``/``% of the time``, or ``A against
  B`` between two numbers;
* ``machine``: a CPU or machine (EPYC, Zen, Xeon, Ryzen, Intel, AMD, AVX, vCPU, ``N
  cores``, ``N-core``, a reference/development/idle/loaded machine);
* ``date``: a calendar date ``20YY-MM`` or ``20YY-MM-DD``;
* ``measured``: ``measured``/``benchmark``/``timed`` within 60 characters of a figure
  (not "measured runs", "measured t_cr", "Table 1's measured W": the thesis's data);
* ``accuracy``: a measured error, an exponent figure that is not a round contract
  (``2.4e-9``, ``5e-8``; not ``1e-6``) next to ``error``, ``off``, ``apart``,
  ``within``, ``differ``, ``agree``, ``worst``, ``moved``;
* ``sample``: the size of a benchmark run (``10,000-point``, ``on 1,855 points``);
* ``commit``: ``against``/``at``/``since`` a hex commit.

A figure is a number that is not an equation, table, figure or appendix reference. A
line counts if a rule matches it, or if it lies in a sentence that a rule matches: a
measurement written over several lines counts on each (sentences end at ``. `` before
a capital, at a blank line, a list item or a numpydoc entry; comments and docstrings,
and a comment after code, are never one sentence). A rule matched only by a pointer to
the record (``docs/benchmarks.md``, ``python -m benchmarks...``) does not count.

At c47836d this gives 367 lines (solve/ 137, core/ 112, sweeps/ 33, runs/ 22,
validation/ 17, top-level modules 15, cli/ 11, model/ 10, calibration/ 4, flow/ 4,
fitting/ 2); issue 44 counted 403 by rules it did not publish. The rules are regular
expressions on purpose: reproducible and reviewable (``--list`` shows what matched and
by which rules); ``tests/test_measured_prose.py`` pins what must and must not count.
"""

from __future__ import annotations

import argparse
import ast
import io
import re
import sys
import tokenize
from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src" / "obturator"

_NUM = r"(?<![\w.])\d+(?:[.,]\d+)?(?:e-?\d+)?"
#: A figure: a number that is not an equation, table, figure or appendix reference.
_FIGURE = (
    r"(?<![\w.(])(?<!Eq\. )(?<!Eqs\. )(?<!Table )(?<!Fig\. )(?<!Figs\. )(?<!Appendix )"
    r"(?<!issue )(?<!item )\d"
)
_RANGE = rf"{_NUM}(?:\s*(?:-|\.\.|to|–)\s*{_NUM})?"

#: rule name -> pattern; a prose line counts once if any matches (case-insensitive).
RULES: dict[str, re.Pattern[str]] = {
    "timing": re.compile(
        rf"(?:\b(?:per|each|against|took|takes|costs?|in|measured|vs)\b[^.;]{{0,25}}?)"
        rf"{_RANGE}\s*(?:ms|us|µs|ns)\b(?!\")"
        rf"|{_RANGE}\s*(?:ms|us|µs|ns)\b(?!\")[^.;]{{0,25}}?"
        rf"\b(?:per|each|against|took|takes|costs?|in (?:lanes|this)|measured|vs)\b"
        rf"|{_NUM}\s*(?:k\s*)?points?\s*/\s*s\b"
        r"|\bpoints?/s\b"
        rf"|{_RANGE}\s*s\s*(?:/|per)\s*(?:point|trajectory|call|case)\b"
        rf"|{_RANGE}\s*(?:s|seconds|min|minutes)\b[^.;]{{0,40}}?\b(?:wall|cold|warm|compil\w*)"
        rf"|\b(?:wall(?:-clock)?|takes?|took|costs?|compil\w*|cold|warm|first run|"
        rf"workers?|start-up|import)\b[^.;]{{0,30}}?{_RANGE}\s*(?:s|seconds|min|minutes)\b"
        r"(?!\s*(?:t_cr|apart))",
        re.IGNORECASE,
    ),
    "speed-up": re.compile(
        rf"{_RANGE}x\b"
        r"|\bspeed-?ups?\b"
        r"|\d[^.;]{0,40}\b(?:faster|slower|cheaper)\b"
        r"|\b(?:faster|slower|cheaper)\b[^.;]{0,40}\d"
        rf"|{_RANGE}\s*%\s*(?:fewer|less|more|of (?:the|one|a|its) (?:\w+ )?"
        r"(?:time|load|work|cost|trajectory|lanes|steps|sweep|run)s?\b)"
        rf"|{_NUM}\s*(?:[a-z%-]+\s+){{0,3}}against\s+~?{_NUM}",
        re.IGNORECASE,
    ),
    "machine": re.compile(
        r"\b(?:EPYC|Zen\s*\d?|Xeon|Ryzen|Intel|AMD|AVX2?|vCPUs?|\d+-vCPU|\d+\s*cores|\d+-core)\b"
        r"|\b(?:reference|development|idle|loaded)\s+machine\b",
        re.IGNORECASE,
    ),
    "date": re.compile(r"(?<!\d)20\d\d-(?:0[1-9]|1[0-2])(?:-\d\d)?(?!\d)"),
    "measured": re.compile(
        rf"(?<!`)\b(?:measured|benchmark(?:ed|s)?|timed)\b(?!`)"
        rf"(?!\*?\s+(?:runs?|t_cr|opening|weight|w\b|angle|data|values?|table|them|[\d.-]+\s*n\b))"
        rf"[^.;]{{0,60}}?{_FIGURE}"
        rf"|{_FIGURE}[^.;]{{0,40}}?\bmeasured\b(?!\*?\s+(?:runs?|t_cr|opening|weight))",
        re.IGNORECASE,
    ),
    "accuracy": re.compile(
        r"\b(?:errors?|off|apart|within|differ\w*|agree\w*|worst|outliers?|moved)\b[^;]{0,40}?"
        r"(?<![\w.])(?:\d\.\d+|[2-9])e-\d+"
        r"|(?<![\w.])(?:\d\.\d+|[2-9])e-\d+[^;]{0,25}?\b(?:off|apart|error)\b",
        re.IGNORECASE,
    ),
    "sample": re.compile(
        r"(?<![\w.])\d{1,3}(?:,\d{3})+-point\b"
        r"|\b(?:on|of|over|all)\s+(?:the\s+)?\d{1,3}(?:,\d{3})+\s+(?:\w+\s+){0,2}points\b",
        re.IGNORECASE,
    ),
    "commit": re.compile(r"\b(?:against|at|since|from|than)\s+[0-9a-f]{7,40}\b"),
}

#: A line that only points at the benchmark record is a reference, not a figure.
_POINTER = re.compile(r"docs/benchmarks\.md|python -m benchmarks[\w.]*")


@dataclass(frozen=True)
class Hit:
    """One counted prose line."""

    path: str  # relative to src/obturator
    line: int
    text: str
    rules: tuple[str, ...]


def prose_lines(source: str) -> Iterator[tuple[int, str]]:
    """(line number, text) of every comment and string-statement line of `source`."""
    seen: set[int] = set()
    for tok in _comments(source):
        seen.add(tok.start[0])
        yield tok.start[0], tok.string
    lines = source.splitlines()
    for node in ast.walk(ast.parse(source)):
        if (
            isinstance(node, ast.Expr)
            and isinstance(node.value, ast.Constant)
            and isinstance(node.value.value, str)
        ):
            end = node.end_lineno or node.lineno
            for n in range(node.lineno, end + 1):
                if n not in seen:
                    yield n, lines[n - 1]


def _comments(source: str) -> Iterator[tokenize.TokenInfo]:
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type == tokenize.COMMENT:
            yield tok


#: What every rule needs somewhere in the text (a cheap test before the rules).
_ANY = re.compile(r"\d|epyc|zen|xeon|ryzen|intel|amd|avx|vcpu|machine|speed-?up|points?/s", re.I)


def matched_rules(text: str) -> tuple[str, ...]:
    """The rules of :data:`RULES` that `text` matches (none for a pure pointer)."""
    if not _ANY.search(text):
        return ()
    hits = tuple(name for name, pattern in RULES.items() if pattern.search(text))
    if hits and _POINTER.search(text):
        stripped = _POINTER.sub("", text)
        hits = tuple(name for name in hits if RULES[name].search(stripped))
    return hits


_MARKER = re.compile(r"^\s*(?:#:?|\"\"\"|\'\'\'|[rbuf]*\"\"\")?\s?")
_SENTENCE_END = re.compile(r"(?<=[.!?])\s+(?=[A-Z`*(\"':])")
#: A line that opens a list item, a numpydoc parameter or section starts a new sentence.
_BULLET = re.compile(
    r"^(?:[*-]|\d+\.)\s|^-{3,}$|^[\w*]+(?:\s*,\s*[\w*]+)*\s:\s"
    r"|^(?:Parameters|Returns|Yields|Raises|Notes|Examples|See Also|Attributes|References)$"
)


def _blocks(
    lines: list[tuple[int, str]], alone: frozenset[int] = frozenset()
) -> Iterator[list[tuple[int, str]]]:
    """Runs of consecutive, non-empty prose lines of one kind (a paragraph of a comment or
    of a docstring; a list item or a numpydoc entry starts a new one). The lines in
    `alone` (comments after code) are blocks of their own."""
    block: list[tuple[int, str]] = []
    comment = False
    for n, text in sorted(lines):
        body = _MARKER.sub("", text, count=1).strip()
        is_comment = text.lstrip().startswith("#")
        if block and (
            n != block[-1][0] + 1
            or not body
            or _BULLET.match(body)
            or is_comment != comment
            or n in alone
            or block[-1][0] in alone
        ):
            yield block
            block = []
        comment = is_comment
        if body:
            block.append((n, body))
    if block:
        yield block


def measured_lines(source: str) -> Iterator[tuple[int, str, tuple[str, ...]]]:
    """(line, text, rules) of each prose line of `source` that quotes a measured figure.

    A line counts if a rule matches it, or if it carries a figure and lies in a sentence
    that a rule matches (a measured sentence spread over lines counts on each line
    that holds its numbers)."""
    raw = dict(prose_lines(source))
    inline = frozenset(t.start[0] for t in _comments(source) if t.line[: t.start[1]].strip())
    for block in _blocks(list(raw.items()), inline):
        text = ""
        starts = []
        for n, body in block:
            starts.append((len(text), n))
            text += body + " "
        marked: dict[int, set[str]] = {}
        pos = 0
        for sentence in _SENTENCE_END.split(text):
            begin = text.index(sentence, pos)
            end = begin + len(sentence)
            pos = end
            rules = matched_rules(sentence)
            if not rules:
                continue
            for i, (offset, n) in enumerate(starts):
                stop = starts[i + 1][0] if i + 1 < len(starts) else len(text)
                if offset < end and stop > begin:
                    marked.setdefault(n, set()).update(rules)
        for n, body in block:
            own = matched_rules(body)
            if own:
                marked.setdefault(n, set()).update(own)
            if n in marked:
                yield n, raw[n], tuple(r for r in RULES if r in marked[n])


def scan(root: Path = SRC) -> list[Hit]:
    """Every prose line under `root` that quotes a measured figure, in path order."""
    out = []
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root).as_posix()
        for n, text, rules in measured_lines(path.read_text(encoding="utf-8")):
            out.append(Hit(rel, n, text.strip(), rules))
    return out


def folder(rel: str) -> str:
    """The top-level folder of a path under src/obturator (``.`` for a top module)."""
    return rel.split("/", 1)[0] if "/" in rel else "."


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--list", action="store_true", help="print every counted line")
    ap.add_argument("--files", action="store_true", help="count per file too")
    ap.add_argument("--only", default="", help="only paths containing this text")
    args = ap.parse_args(argv)
    hits = [h for h in scan() if args.only in h.path]
    if args.list:
        for h in hits:
            print(f"{h.path}:{h.line}: [{','.join(h.rules)}] {h.text}")
        print()
    by_rule = Counter(rule for h in hits for rule in h.rules)
    print(f"measured prose lines in src/obturator: {len(hits)}")
    print("  by rule: " + ", ".join(f"{name} {by_rule[name]}" for name in RULES))
    for name, count in sorted(Counter(folder(h.path) for h in hits).items()):
        print(f"  {name + '/' if name != '.' else '(top-level modules)'}: {count}")
    if args.files:
        for name, count in sorted(Counter(h.path for h in hits).items()):
            print(f"    {name}: {count}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
