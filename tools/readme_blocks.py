"""Every console block of README.md and the docs pages, produced by the code: run, check,
rewrite.

Each ``console`` block in the README or a page under ``docs/`` (:func:`pages`) follows a
marker line ``<!-- readme-block: NAME -->``; each NAME appears on exactly one page, and
:data:`BLOCKS` says, for each NAME, the commands
(as the README shows them), which output lines the README keeps (an excerpt: the
lines left out are one ``...`` line) and how its output may differ from machine to
machine (timings masked; near-stick digits compared to a stated relative tolerance).

    python tools/readme_blocks.py --write            # rerun every block, rewrite its page
    python tools/readme_blocks.py --write --only sweep
    python tools/readme_blocks.py --check --fast     # compare; exit 1 on a difference
    python tools/readme_blocks.py --list             # names, costs
    python tools/readme_blocks.py --write --only validate --keep /tmp/blocks  # keep files

``tests/test_readme.py`` checks each block against a fresh run (the expensive ones
are marked slow). Commands run in a temporary folder holding a copy of ``examples/``,
with ``python -m obturator`` standing for ``obturator``.
"""

from __future__ import annotations

import argparse
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
DOCS = ROOT / "docs"
MARKER = re.compile(r"^<!-- readme-block: ([\w-]+) -->$")
ELLIPSIS = "..."

#: Wall-clock times and rates ("in 2.9 s", "(7.17 s)"): they depend on the machine and
#: its load. Results with a unit of time (t_cr 0.2 s) are compared, not masked.
TIMES = (
    (r"\bin \d+(\.\d+)? (s|min)\b", "in <t>"),
    (r"\(\d+(\.\d+)? s\)", "(<t> s)"),
    (r"[\d,]+(\.\d+)? points/s", "<n> points/s"),
    (r"on \d+ workers?", "on <n> workers"),
)


@dataclass(frozen=True)
class Block:
    """One console block of the README.

    Attributes
    ----------
    commands : tuple of str
        Command lines as the README shows them (``obturator ...``; a trailing
        ``# comment`` is shown, not run; ``\\`` continues a line).
    keep : tuple of str
        Regular expressions of the output lines the README keeps (empty: all).
    masks : tuple of (str, str)
        Substitutions applied to both sides before comparing (machine-dependent text).
    rtol : float
        Relative tolerance on numbers (0: digit for digit).
    slow : bool
        Too expensive for the fast test subset.
    cost : str
        What one run cost on the development machine (2-core AMD EPYC Zen 4, shared by
        several jobs: load ~13, so several times an idle machine's time).
    """

    commands: tuple[str, ...]
    keep: tuple[str, ...] = ()
    masks: tuple[tuple[str, str], ...] = TIMES
    rtol: float = 0.0
    slow: bool = False
    cost: str = ""


BLOCKS: dict[str, Block] = {
    "simulate": Block(
        ("obturator simulate --case spin-rig --spin-rate 150 --mu-s 0.5473",),
        # 150 rad/s sticks and slips after release: rounding differences between CPUs
        # move t_cr in the 6th digit and the step counts by a few
        masks=(
            *TIMES,
            (r"relative change .*", "relative change <small>"),
            (r"\d+ / \d+", "<steps> / <rhs>"),
        ),
        rtol=1e-4,
        cost="3 s",
    ),
    "reproduce": Block(
        ("obturator reproduce --out report",),
        slow=True,
        cost="5.0 min, nearly idle (the 54-run validation study inside)",
    ),
    "calibrate": Block(
        ("obturator calibrate examples/rig_runs.csv --bootstrap 0 --figure residuals.png",),
        keep=(r"^\s+mu_s\s+=",),
        rtol=1e-3,
        cost="8 s",
    ),
    "validate": Block(
        ("obturator validate --out validation",),
        # the ranking table and the recommended model's parameters (two-space indent)
        keep=(
            r"^Models ranked",
            r"^\s+(#|replicate floor|\d+ (?!rad/s)\S)",
            r"^  k counts",
            r"^Predictive scores",
            r"^  model\s+AIC\s+LOCO",
            r"^  [\w+-]+\*?\s+-?\d+\.\d\d\s+\d+\.\d{4}\s",
            r"^Recommended: ",
            r"^  (mu_s|theta0_deg|theta_dot0|speed_ratio|slip_speed|sigma) ",
        ),
        # near-stick runs: fitted values and out-of-band rms move in the 4th digit from
        # run to run; a rounding-level change of the kernels moves the out-of-band rms of
        # the ill-determined subset fits far more (regenerate the block then)
        rtol=2e-3,
        slow=True,
        cost="4.3 min, nearly idle",
    ),
    "envelope": Block(
        (
            "obturator trajectory --mach 1.5 --altitude-m 8000",
            "obturator envelope --mach 1.5:4:11 --altitude-m 0:10000:6 --out envelope.nc "
            "--figure envelope.png",
        ),
        keep=(r"^(M0|t_cr|difference)", r"^envelope:"),
        rtol=1e-4,
        slow=True,
        cost="11 s",
    ),
    "start": Block(
        ("obturator trajectory --mach 2.5",),
        keep=(r"^(M0|t_cr|t_start|inlet)",),
        rtol=1e-4,
        slow=True,
        cost="2 s",
    ),
    "design": Block(
        ("obturator design-experiment --out design.nc --figure design.png",),
        keep=(
            r"^Recommended campaign",
            r"^\s+\d+\s+\d+\s+[\d.]+ rad/s",
            r"^\s+N\s+designed",
            r"^\s+(5|10|20)\s+\d\.\d\d\s",
            r"^\s+runs for P",
            r"^Feasibility",
            r"^\s+\d+-run plan (without|on the)",
            r"^Can the",
            r"^\s+truth outside",
        ),
        rtol=0.02,  # seeded campaigns: a decision at the edge may move a rate by 1/200
        slow=True,
        cost="21 s",
    ),
    "probability": Block(
        (
            "obturator probability --mach 1.75 --altitude-m 6000 --method both --samples 2000",
            "obturator probability --mach 2.5 --altitude-m 6000 --method is",
        ),
        keep=(r"p = ", r"IS inside"),
        slow=True,
        cost="88 s",
    ),
    "optimize": Block(
        (
            "obturator optimize --mach 1.5,2.5,4 --altitude-m 0,5000 --popsize 8 --maxiter 10 "
            "--load constant --pareto 4",
        ),
        keep=(r"^ball mass", r"^bore blocked", r"^max:"),
        rtol=1e-4,
        slow=True,
        cost="4 s",
    ),
    "sweep": Block(
        (
            "obturator sweep --case spin-rig --spin-rate 40:700:20 --mu-s 0.5473 --out sweep.nc",
            "obturator montecarlo --case spin-rig --spin-rate 300 --samples 200 --seed 1 \\\n"
            "      --vary mu_s=normal:0.5473,0.03 --vary theta0_deg=uniform:86.25,88.25",
            "obturator gasdyn choke --l-over-d 8.07 --reynolds 5e5",
        ),
        # the sweep's 40 rad/s point sticks for 43 s: its t_cr varies in the 6th digit
        rtol=1e-4,
        cost="21 s",
    ),
}


def argv_of(command: str) -> list[str]:
    """The arguments of a README command line (``obturator`` dropped, comment cut)."""
    words = shlex.split(command.replace("\\\n", " "), comments=True)
    assert words[0] == "obturator", command
    return words[1:]


def run_commands(block: Block, cwd: Path) -> str:
    """Run `block`'s commands in `cwd`; return the block's text as the README shows it."""
    out: list[str] = []
    env = dict(os.environ, COLUMNS="200", PYTHONUNBUFFERED="1")
    for command in block.commands:
        res = subprocess.run(
            [sys.executable, "-m", "obturator", *argv_of(command)],
            cwd=cwd,
            env=env,
            capture_output=True,
            text=True,
            check=False,
        )
        if res.returncode != 0:
            raise RuntimeError(f"{command!r} exited {res.returncode}: {res.stderr[-2000:]}")
        out.append(f"$ {command}")
        out += excerpt(res.stdout.rstrip("\n").splitlines(), block.keep)
    return "\n".join(out)


def excerpt(lines: list[str], keep: tuple[str, ...]) -> list[str]:
    """The lines matching any of `keep` (all if empty); each gap becomes one ``...``."""
    if not keep:
        return [line.rstrip() for line in lines]
    out: list[str] = []
    for line in lines:
        if any(re.search(k, line) for k in keep):
            out.append(line.rstrip())
        elif not out or out[-1] != ELLIPSIS:
            out.append(ELLIPSIS)
    return out


def readme_blocks(text: str) -> dict[str, tuple[int, int]]:
    """NAME -> (first, last) line index of its block's content in the README `text`."""
    lines = text.splitlines()
    found: dict[str, tuple[int, int]] = {}
    for i, line in enumerate(lines):
        m = MARKER.match(line)
        if not m:
            continue
        if not lines[i + 1].startswith("```console"):
            raise ValueError(f"README line {i + 2}: a console block must follow {line}")
        end = next(j for j in range(i + 2, len(lines)) if lines[j].startswith("```"))
        found[m.group(1)] = (i + 2, end)
    return found


def pages() -> list[Path]:
    """The README and every Markdown page of the docs (not the built site)."""
    docs = sorted(p for p in DOCS.rglob("*.md") if "_build" not in p.parts)
    return [README, *docs]


def page_blocks() -> dict[str, Path]:
    """NAME -> the page that holds block NAME (each name on exactly one page)."""
    found: dict[str, Path] = {}
    for page in pages():
        for name in readme_blocks(page.read_text(encoding="utf-8")):
            if name in found:
                raise ValueError(f"block {name!r} is on two pages: {found[name]} and {page}")
            found[name] = page
    return found


def page_of(name: str) -> Path:
    """The page (README or docs) that holds block NAME."""
    return page_blocks()[name]


def block_text(text: str, name: str) -> str:
    """The content of block NAME in a page's `text`."""
    first, end = readme_blocks(text)[name]
    return "\n".join(text.splitlines()[first:end])


_NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")


def differences(readme: str, fresh: str, block: Block) -> list[str]:
    """How the README's block differs from a fresh run (empty: they agree)."""

    def norm(text: str) -> list[str]:
        for pattern, repl in block.masks:
            text = re.sub(pattern, repl, text)
        return text.splitlines()

    a, b = norm(readme), norm(fresh)
    if len(a) != len(b):
        return [f"{len(a)} lines in the README, {len(b)} in a fresh run"]
    out = []
    for x, y in zip(a, b, strict=True):
        if x == y:
            continue
        if _NUMBER.sub("#", x) == _NUMBER.sub("#", y):
            nx = [float(v) for v in _NUMBER.findall(x)]
            ny = [float(v) for v in _NUMBER.findall(y)]
            if all(
                abs(p - q) <= block.rtol * max(abs(p), abs(q)) for p, q in zip(nx, ny, strict=True)
            ):
                continue
        out.append(f"README: {x}\n fresh: {y}")
    return out


def fresh_output(name: str, keep: Path | None = None) -> str:
    """Run block NAME in a temporary folder holding a copy of examples/ (in ``keep/NAME``,
    left in place with the block's output files, where `keep` is given)."""
    if keep is not None:
        cwd = keep / name
        shutil.rmtree(cwd, ignore_errors=True)
        shutil.copytree(ROOT / "examples", cwd / "examples")
        return run_commands(BLOCKS[name], cwd)
    with tempfile.TemporaryDirectory(prefix="readme-") as tmp:
        shutil.copytree(ROOT / "examples", Path(tmp) / "examples")
        return run_commands(BLOCKS[name], Path(tmp))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--write", action="store_true", help="rerun and rewrite each page")
    mode.add_argument("--check", action="store_true", help="rerun and compare")
    mode.add_argument("--list", action="store_true", help="list the blocks and their cost")
    parser.add_argument("--only", action="append", metavar="NAME", help="these blocks only")
    parser.add_argument("--fast", action="store_true", help="skip the slow blocks")
    parser.add_argument(
        "--keep", type=Path, metavar="DIR", help="run each block in DIR/NAME and keep its files"
    )
    args = parser.parse_args(argv)
    names = args.only or [n for n, b in BLOCKS.items() if not (args.fast and b.slow)]
    present = page_blocks()
    if set(present) != set(BLOCKS):
        print(f"blocks on the pages {sorted(present)} != BLOCKS {sorted(BLOCKS)}", file=sys.stderr)
        return 1
    if args.list:
        for n, b in BLOCKS.items():
            print(f"{n:<12} {'slow' if b.slow else 'fast'}  {b.cost}")
        return 0
    failed = 0
    for name in names:
        t0 = time.perf_counter()
        fresh = fresh_output(name, args.keep)
        took = time.perf_counter() - t0
        page = present[name]
        text = page.read_text(encoding="utf-8")
        if args.write:
            first, end = readme_blocks(text)[name]
            lines = text.splitlines()
            lines[first:end] = fresh.splitlines()
            page.write_text("\n".join(lines) + "\n", encoding="utf-8")
            print(f"{name}: rewritten in {page.relative_to(ROOT)} ({took:.1f} s)")
        else:
            diff = differences(block_text(text, name), fresh, BLOCKS[name])
            failed += bool(diff)
            print(f"{name}: {'differs' if diff else 'agrees'} ({took:.1f} s)")
            for d in diff:
                print(f"  {d}")
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
