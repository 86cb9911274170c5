"""``python -m benchmarks report``: measure, then rewrite the measured sections of
``docs/benchmarks.md``.

    python -m benchmarks report                        # every section (long: tens of minutes)
    python -m benchmarks report --quick                # fewer spins, sizes and repeats
    python -m benchmarks report --only imports,dispatch_crossover
    python -m benchmarks report --dry-run              # print the sections, leave the file

The document holds one block per section of :data:`SECTIONS`, between the lines
``<!-- measured: NAME -->`` and ``<!-- /measured: NAME -->``; a run replaces the blocks
of the sections it measured (each block says when, at which commit, on which CPU and by
which command) and leaves every other line as it is: the text around the blocks and the
tuning history below ``<!-- history -->``, which no command rewrites. A block found
below that line, or a section without its block, is an error and the file is left
unchanged.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "benchmarks.md"
HISTORY = "<!-- history -->"
_OPEN = "<!-- measured: {name} -->"
_CLOSE = "<!-- /measured: {name} -->"


@dataclass(frozen=True)
class Column:
    """One column of a section's table: the row key, its header and its format."""

    key: str
    header: str
    #: "text", "int", "num" (three significant digits), "ms" (seconds shown in ms, three
    #: significant digits), "ratio" (shown as 1.23x),
    #: "error" (1.2e-07), "yes/no"
    kind: str = "text"


@dataclass(frozen=True)
class Section:
    """A measured section: what it shows, the command behind it, how to measure it."""

    title: str
    command: str
    what: str
    #: measure(quick) -> rows (flat dicts keyed as the columns)
    measure: Callable[[bool], list[dict[str, Any]]]
    columns: tuple[Column, ...]


def format_value(value: Any, kind: str) -> str:
    """`value` as its column shows it (``-`` for a missing or non-finite number)."""
    if value is None:
        return "-"
    if kind == "text":
        return str(value)
    if kind == "yes/no":
        return "yes" if value else "no"
    x = float(value)
    if not math.isfinite(x):
        return "-"
    if kind == "int":
        return f"{int(round(x)):,}"
    if kind == "ms":
        return _significant(x * 1e3)
    if kind == "num":
        return _significant(x)
    if kind == "ratio":
        return f"{x:.2f}x"
    if kind == "error":
        return "0" if x == 0.0 else f"{x:.1e}"
    raise ValueError(f"unknown column kind {kind!r}")


def _significant(x: float) -> str:
    """Three significant digits, no exponent for the magnitudes a timing has."""
    if x == 0.0:
        return "0"
    digits = max(0, 2 - int(math.floor(math.log10(abs(x)))))
    return f"{x:.{digits}f}"


def markdown_table(rows: Sequence[Mapping[str, Any]], columns: Sequence[Column]) -> str:
    """A GitHub markdown table of `rows` (text left-aligned, numbers right-aligned)."""
    head = "| " + " | ".join(c.header for c in columns) + " |"
    rule = "|" + "|".join(":---" if c.kind == "text" else "---:" for c in columns) + "|"
    body = [
        "| " + " | ".join(format_value(r.get(c.key), c.kind) for c in columns) + " |" for r in rows
    ]
    return "\n".join([head, rule, *body])


def render(name: str, section: Section, rows: Sequence[Mapping[str, Any]], meta: dict) -> str:
    """The block of section `name`, markers included."""
    commit = meta.get("git_commit") or "an unknown commit"
    stamp = (
        f"*Measured {meta['date']} at {commit} on {meta['cpu']} "
        f"({meta['cpus_available']} CPUs available; Python {meta['python']}, "
        f"numba {meta['numba']}){' with --quick' if meta.get('quick') else ''}: "
        f"`{section.command}`.*"
    )
    return "\n".join(
        [
            _OPEN.format(name=name),
            stamp,
            "",
            section.what,
            "",
            markdown_table(rows, section.columns),
            _CLOSE.format(name=name),
        ]
    )


def rewrite(text: str, blocks: Mapping[str, str]) -> str:
    """`text` with the block of each section in `blocks` replaced; nothing else changes.

    Markers and the history line count only as whole lines. Raises ValueError when a
    section has no block (or more than one), or its block lies in the history (below
    the line ``<!-- history -->``)."""
    for name, block in blocks.items():
        history = re.search("^" + re.escape(HISTORY) + "$", text, re.MULTILINE)
        history_at = history.start() if history else len(text)
        pattern = re.compile(
            "^"
            + re.escape(_OPEN.format(name=name))
            + "$.*?^"
            + re.escape(_CLOSE.format(name=name))
            + "$",
            re.DOTALL | re.MULTILINE,
        )
        found = list(pattern.finditer(text))
        if len(found) != 1:
            raise ValueError(f"{len(found)} blocks of section {name!r} in the document (need 1)")
        match = found[0]
        if match.start() > history_at:
            raise ValueError(f"the block of section {name!r} is in the history")
        text = text[: match.start()] + block + text[match.end() :]
    return text


# ---------------------------------------------------------------- the sections


def _machine(quick: bool) -> list[dict[str, Any]]:
    from benchmarks.run import _meta

    meta = _meta()
    return [{"field": k, "value": v} for k, v in meta.items() if k != "date"]


def _imports(quick: bool) -> list[dict[str, Any]]:
    from benchmarks import imports

    return imports.cost(repeat=1 if quick else 5)


def _trajectory(quick: bool) -> list[dict[str, Any]]:
    from benchmarks.run import MU_S, trajectory
    from obturator.model.cases import rig_case

    rec = trajectory("rig 300 rad/s", rig_case(300.0, MU_S), *((5, 1) if quick else (30, 3)))
    b = rec["baseline"]
    rows = [
        {
            "solver": "baseline: scipy LSODA, NumPy right-hand side",
            "wall_s": b["wall_s"],
            "speed_up": 1.0,
            "nfev": b["nfev"],
            "error": abs(b["error_vs_reference"]),
        }
    ]
    for label, p in rec["package"].items():
        rows.append(
            {
                "solver": label,
                "wall_s": p["wall_s"],
                "speed_up": p["speedup_vs_baseline"],
                "nfev": p["nfev"],
                "error": abs(p["error_vs_reference"]),
            }
        )
    return rows


def _dispatch_crossover(quick: bool) -> list[dict[str, Any]]:
    from benchmarks import dispatch_crossover as dc
    from obturator.model.case import initial_state
    from obturator.model.cases import rig_case
    from obturator.solve import SolverOptions
    from obturator.solve.dispatch import stick_ratio
    from obturator.solve.setup import pack_parameters

    rows = []
    for law in dc.LAWS:
        for r in dc.crossover(dc.SPINS_QUICK if quick else dc.SPINS, law, 2 if quick else 3):
            case = rig_case(r["spin_rad_s"], dc.MU_S, torque_model=law)
            y0 = initial_state(case.theta0, case.spin_rate)
            p = pack_parameters(case, SolverOptions(), y0)
            rows.append(r | {"kappa": stick_ratio(p, y0)})
    return rows


def _small_groups(quick: bool) -> list[dict[str, Any]]:
    from benchmarks import small_groups

    sizes = small_groups.SIZES_QUICK if quick else small_groups.SIZES
    return small_groups.cost(sizes, 2 if quick else 5)


def _speed_law_kernel(quick: bool) -> list[dict[str, Any]]:
    from benchmarks import speed_law_kernel

    return speed_law_kernel.cost(2 if quick else 5)


def _stick_slip(quick: bool) -> list[dict[str, Any]]:
    from benchmarks import stick_slip

    rows = stick_slip.cost(stick_slip.SPINS_QUICK if quick else stick_slip.SPINS, 2 if quick else 5)
    return [
        {
            "case": r["case"],
            "t_cr_s": r["t_cr_reference_s"],
            "regularised_s": r["regularised"]["wall_s"],
            "set_valued_s": r["set-valued"]["wall_s"],
            "ratio": r["ratio"].get("set-valued"),
            "regularised_error": r["regularised"]["rel_error"],
            "set_valued_error": r["set-valued"]["rel_error"],
        }
        for r in rows
    ]


def _cli_latency(quick: bool) -> list[dict[str, Any]]:
    from benchmarks import latency

    rec = latency.cli_latency(2 if quick else 5)
    labels = (
        ("python -c 'import numpy, scipy.integrate'", "python_import_numpy_scipy_s"),
        ("obturator --help", "obturator_help_s"),
        ("obturator simulate --case spin-rig", "simulate_s"),
        ("obturator sweep, 20 points (NetCDF + CSV)", "sweep_20_s"),
        ("python: LSODA loop over the same 20 points", "lsoda_loop_20_s"),
    )
    return [{"command": label, "wall_s": rec[key]} for label, key in labels]


def _rhs_floor(quick: bool) -> list[dict[str, Any]]:
    from benchmarks import rhs_floor

    rec = rhs_floor.measure(500 if quick else 2000, (40.0, 1000.0), 40 if quick else 200)
    floor = rec["floor"]
    rows = [dict(r) for r in rec["bands"]]
    points = sum(r["points"] for r in rows)
    rows.append(
        {
            "band": "40-1000 (all)",
            "points": points,
            "cpu_s": rec["cpu_s"],
            "ms_per_point": 1e3 * rec["cpu_s"] / points,
            "rhs_per_point": rec["median_rhs_per_point"],
            "routes": f"RHS/point: median of {len(rec['rhs_per_point_sample'])} points alone",
        }
    )
    rows.append(
        {
            "band": "floor",
            "ns_per_rhs": floor.get("ns_per_lane_rhs"),
            "routes": f"thesis kernel, {floor.get('lanes')} lanes; scalar "
            f"{floor.get('ns_per_scalar_rhs', float('nan')):.1f} ns",
        }
    )
    return rows


def _sweeps(quick: bool) -> list[dict[str, Any]]:
    from benchmarks import sweeps

    grids = ((40.0, 1000.0, 2000), (100.0, 700.0, 4000)) if quick else sweeps.SWEEPS
    rec = sweeps.measure([sweeps.ROOT], grids, workers=2, rounds=1 if quick else 3)
    return rec["rows"]


def _envelope_following(quick: bool) -> list[dict[str, Any]]:
    from benchmarks import envelope_following as ef

    rows = []
    for spin in (700.0,) if quick else (700.0, 1000.0):
        rec = ef.study(spin, (1e-8, 1e-6, 1e-4), (3,) if quick else (3, 4))
        rows.append(
            {
                "spin": spin,
                "strategy": f"every revolution ({rec['revolutions']})",
                "nfev": rec["full"]["nfev"],
                "fewer": 1.0,
                "error": abs(rec["full"]["rel_error"]),
            }
        )
        for e in rec["envelope"]:
            rows.append(
                {
                    "spin": spin,
                    "strategy": f"envelope, {e['pairs']} pairs, tol {e['tol']:.0e} "
                    f"({e['jumps']} jumps)",
                    "nfev": e["nfev"],
                    "fewer": e["fewer"],
                    "error": abs(e["rel_error"]),
                }
            )
    return rows


def _time_scales(quick: bool) -> list[dict[str, Any]]:
    from benchmarks import envelope_following as ef

    rows = []
    for spin in (520.0, 1000.0) if quick else (300.0, 520.0, 700.0, 1000.0):
        scales = ef.time_scales(spin)
        for r in ef.per_revolution(spin):
            rows.append({"spin": spin} | scales | r)
    return rows


_MS = "ms per point"
#: The sections, in the document's order.
SECTIONS: dict[str, Section] = {
    "machine": Section(
        "Machine",
        "python -m benchmarks report --only machine",
        "The machine and versions of the last run of this section.",
        _machine,
        (Column("field", "field"), Column("value", "value")),
    ),
    "imports": Section(
        "Import costs",
        "python -m benchmarks.imports",
        "Wall time of one import in a fresh interpreter after numpy, best of repeats: why "
        "scipy.optimize, scipy.integrate, scipy.stats and xarray are imported on first use.",
        _imports,
        (Column("module", "module"), Column("import_s", "import [ms]", "ms")),
    ),
    "trajectory": Section(
        "One trajectory against the baseline",
        "python -m benchmarks",
        "Rig at 300 rad/s, mu_s 0.5473: best wall time to t_cr after warm-up, against the "
        "plain-Python LSODA baseline (`benchmarks/baseline.py`); error against Radau IIA "
        "at rtol 1e-11.",
        _trajectory,
        (
            Column("solver", "solver"),
            Column("wall_s", "wall [ms]", "ms"),
            Column("speed_up", "speed-up", "ratio"),
            Column("nfev", "nfev", "int"),
            Column("error", "t_cr error", "error"),
        ),
    ),
    "dispatch_crossover": Section(
        "Dispatch crossover (`solve.dispatch.SET_VALUED_BELOW`)",
        "python -m benchmarks.dispatch_crossover",
        f"Rig, mu_s 0.5473, default rtol 1e-8: {_MS} of the set-valued solver one by one, the "
        "regularised path one by one and in lanes (a band of 32 points over +-5 rad/s), and "
        "each path's worst t_cr error against the set-valued solver at rtol 1e-12 (the "
        "width-free limit). kappa: the stick ratio at release.",
        _dispatch_crossover,
        (
            Column("law", "law"),
            Column("spin_rad_s", "spin [rad/s]", "num"),
            Column("kappa", "kappa", "num"),
            Column("set_valued_ms", "set-valued [ms]", "num"),
            Column("regularised_ms", "regularised 1x1 [ms]", "num"),
            Column("lanes_ms", "regularised lanes [ms]", "num"),
            Column("set_valued_err", "error set-valued", "error"),
            Column("regularised_err", "error regularised", "error"),
        ),
    ),
    "small_groups": Section(
        "Small batches (`solve.many.lanes_pay_from`)",
        "python -m benchmarks.small_groups",
        "Rig points over 250-440 rad/s: time of the lanes forced and of the front door's "
        "rule, as ratios to a loop over `opening_time` in the same run, and whether all "
        "three give the same bits.",
        _small_groups,
        (
            Column("kernel", "kernel"),
            Column("rtol", "rtol", "error"),
            Column("points", "points", "int"),
            Column("one_by_one_s", "loop [ms]", "ms"),
            Column("lanes_ratio", "lanes forced", "ratio"),
            Column("rule_ratio", "the rule", "ratio"),
            Column("rule_takes_lanes", "rule takes lanes", "yes/no"),
            Column("same_bits", "same bits", "yes/no"),
        ),
    ),
    "speed_law_kernel": Section(
        "Slip-speed laws in the thesis kernel (`core.specialised`)",
        "python -m benchmarks.speed_law_kernel",
        "The 54 Appendix B spins at the validation tolerances (rtol 1e-9): the thesis "
        "kernel's variant against the generic right-hand side, and the t_cr difference.",
        _speed_law_kernel,
        (
            Column("law", "law"),
            Column("vectors", "parameter vectors", "int"),
            Column("points", "points", "int"),
            Column("variant_s", "variant [ms]", "ms"),
            Column("generic_s", "generic [ms]", "ms"),
            Column("speed_up", "speed-up", "ratio"),
            Column("max_rel_t_cr_diff", "max t_cr difference", "error"),
        ),
    ),
    "stick_slip": Section(
        "Set-valued against regularised, per trajectory",
        "python -m benchmarks.stick_slip",
        "Best wall time of `opening_time` per path and each t_cr's error against the "
        "set-valued solver at rtol 1e-12.",
        _stick_slip,
        (
            Column("case", "case"),
            Column("t_cr_s", "t_cr [s]", "num"),
            Column("regularised_s", "regularised [ms]", "ms"),
            Column("set_valued_s", "set-valued [ms]", "ms"),
            Column("ratio", "set-valued / regularised", "ratio"),
            Column("regularised_error", "error regularised", "error"),
            Column("set_valued_error", "error set-valued", "error"),
        ),
    ),
    "rhs_floor": Section(
        "Cost across the operating range, and the right-hand-side floor",
        "python -m benchmarks.rhs_floor",
        "Rig, mu_s 0.5473, a linear grid of spins as `obturator sweep` runs it (shared "
        "return maps), per band in one process: CPU time and right-hand-side evaluations "
        "per point (a shared map's nodes included), CPU ns per evaluation, and that over the "
        "floor: the thesis kernel's right-hand side alone in its vector loop over the "
        "lanes, per lane, in a tight loop of the same run.",
        _rhs_floor,
        (
            Column("band", "band [rad/s]"),
            Column("points", "points", "int"),
            Column("ms_per_point", "CPU per point [ms]", "num"),
            Column("rhs_per_point", "RHS per point", "int"),
            Column("ns_per_rhs", "ns per RHS", "num"),
            Column("over_floor", "over the floor", "ratio"),
            Column("routes", "routes"),
        ),
    ),
    "sweeps": Section(
        "Whole sweeps",
        "python -m benchmarks.sweeps",
        "`obturator sweep --case spin-rig --mu-s 0.5473 --workers 2` as a user runs it, in a "
        "fresh process: median wall time of the rounds with process start, the part the "
        "workers computed (the summary line's time) and the rest outside it (imports, the "
        "probe, the outputs, what the parent does after the workers), and the processor "
        "time of the whole process tree (parent, workers, helpers). `--against TREE` "
        "runs other source trees back to back in the same rounds.",
        _sweeps,
        (
            Column("sweep", "sweep"),
            Column("wall_s", "wall [s]", "num"),
            Column("compute_s", "compute [s]", "num"),
            Column("outside_s", "outside compute [s]", "num"),
            Column("cpu_s", "CPU [s]", "num"),
        ),
    ),
    "envelope_following": Section(
        "Envelope following over the revolutions (not a route)",
        "python -m benchmarks.envelope_following",
        "Rig, mu_s 0.5473, the package's right-hand side under scipy's DOP853 at rtol "
        "1e-10: every revolution integrated, against revolutions integrated from states "
        "extrapolated over the sections psi = 0 (mod 2 pi) (the module's docstring); "
        "evaluations and the t_cr error against rtol 1e-12. Why no envelope route: the "
        "evaluations saved at errors below 1e-6.",
        _envelope_following,
        (
            Column("spin", "spin [rad/s]", "num"),
            Column("strategy", "strategy"),
            Column("nfev", "evaluations", "int"),
            Column("fewer", "fewer", "ratio"),
            Column("error", "t_cr error", "error"),
        ),
    ),
    "time_scales": Section(
        "Time scales of an opening, and what a revolution costs",
        "python -m benchmarks.envelope_following --time-scales",
        "Rig, mu_s 0.5473, the default regularised run: the socket's revolutions to t_cr, "
        "the ball's turns relative to its socket meanwhile (the integral of |omega_r| dt "
        "over 2 pi), the median of each revolution's smallest moment arm sqrt(1 - u_X^2) "
        "(thesis Eq. 61; the arm dips to about |u_Z| twice a revolution), and the "
        "right-hand sides per revolution of a full integration through the front door at "
        "four settings (width max(1e-7, rtol)), with the t_cr error against rtol 1e-11. "
        "The floor of integrating every revolution, and the scale separation that skipping "
        "revolutions would need (``docs/performance.md``).",
        _time_scales,
        (
            Column("spin", "spin [rad/s]", "num"),
            Column("revolutions", "revolutions to t_cr", "num"),
            Column("turns", "turns in the socket", "num"),
            Column("smallest_arm", "smallest arm per revolution", "num"),
            Column("setting", "full integration"),
            Column("rhs_per_revolution", "RHS per revolution", "int"),
            Column("rel_error", "t_cr error", "error"),
        ),
    ),
    "cli_latency": Section(
        "Command-line latency",
        "python -m benchmarks.latency (part of python -m benchmarks)",
        "Fresh process each, warm numba cache, best of repeats, process start included.",
        _cli_latency,
        (Column("command", "command"), Column("wall_s", "wall [s]", "num")),
    ),
}


def measure(names: Sequence[str], quick: bool) -> dict[str, str]:
    """Measure the sections `names`; their blocks, ready for :func:`rewrite`."""
    from benchmarks.run import _meta

    blocks = {}
    for name in names:
        section = SECTIONS[name]
        print(f"measuring {name} ...", file=sys.stderr, flush=True)
        rows = section.measure(quick)
        blocks[name] = render(name, section, rows, _meta() | {"quick": quick})
    return blocks


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m benchmarks report``; returns the exit code."""
    ap = argparse.ArgumentParser(
        prog="python -m benchmarks report", description=__doc__.splitlines()[0]
    )
    ap.add_argument("--only", default="", help="comma-separated sections: " + ", ".join(SECTIONS))
    ap.add_argument("--quick", action="store_true", help="fewer spins, sizes and repeats")
    ap.add_argument("--doc", type=Path, default=DOC, help="the document (docs/benchmarks.md)")
    ap.add_argument("--dry-run", action="store_true", help="print the blocks only")
    args = ap.parse_args(argv)
    names = [n for n in args.only.split(",") if n] or list(SECTIONS)
    unknown = [n for n in names if n not in SECTIONS]
    if unknown:
        ap.error(f"unknown section(s) {', '.join(unknown)}; known: {', '.join(SECTIONS)}")
    text = args.doc.read_text(encoding="utf-8")
    try:
        rewrite(text, {n: "" for n in names})  # every block present, before measuring
    except ValueError as exc:
        print(f"python -m benchmarks report: {args.doc}: {exc}", file=sys.stderr)
        return 2
    blocks = measure(names, args.quick)
    if args.dry_run:
        print("\n\n".join(blocks.values()))
        return 0
    args.doc.write_text(rewrite(text, blocks), encoding="utf-8")
    print(f"rewrote {len(blocks)} section(s) of {args.doc}", file=sys.stderr)
    return 0
