"""``obturator warmup``: compile the integrators once, after installation."""

from __future__ import annotations

import argparse

from . import _json
from ._flags import JSON, NO_PROGRESS, alias, command, count, switch

__all__ = ["register"]

_WORKERS = (
    count(
        "--workers",
        1,
        64,
        "processes compiling at once (2; at most 64: one per integrator is all it uses)",
        example=2,
        default=2,
        dest="jobs",
    ),
)
_WORKERS += (alias(_WORKERS[0], "--jobs"),)


def _run(args: argparse.Namespace) -> int:
    from ..runs import Progress
    from ..warmup import WARMUP_TARGETS, warm_up

    progress = Progress.auto(not args.no_progress and not args.json)

    targets = [m for m in WARMUP_TARGETS if args.all or m != "rosenbrock"]
    left = list(targets)
    progress.note(
        f"warmup: {len(targets)} integrators ({', '.join(targets)}), {args.jobs} at a time "
        "in fresh processes"
    )

    with progress.heartbeat("warmup", "compiling or loading " + ", ".join(left)) as running:

        def report(target: str, seconds: float, compiled: bool, done: int, total: int) -> None:
            verb = "compiled" if compiled else "loaded from the cache"
            progress.note(f"warmup: {target} {verb} in {seconds:.1f} s ({done}/{total})")
            left.remove(target)
            running("compiling or loading " + ", ".join(left))

        res = warm_up(jobs=args.jobs, everything=args.all, report=report)  # checked by kind
    if args.json:
        keys = {"seconds": "time_s", "directory": "cache_directory"}  # unit-suffixed keys
        print(_json.dumps({keys.get(k, k): v for k, v in res.items()}))
        return 0
    compiled: dict[str, bool] = res["compiled"]  # type: ignore[assignment]
    each = ", ".join(
        f"{m} {'compiled' if compiled[m] else 'loaded'} {s:.1f} s"
        for m, s in res["seconds"].items()  # type: ignore[union-attr]
    )
    verb = "compiled" if any(compiled.values()) else "loaded from the cache"
    print(f"{verb} in {res['wall_s']:.1f} s ({each}); cache: {res['directory']}")
    return 0


register = command(
    "warmup",
    _run,
    "Compile the five integrators (DOP853 and Radau IIA, the set-valued stick-slip "
    "solver, and the sweeps' DOP853 and Radau IIA lanes; with --all also Rosenbrock) "
    "side by side in fresh processes and store the machine code in numba's cache, so "
    "that the first simulation or sweep starts warm. Says whether each was compiled or "
    "loaded from the cache, and where the cache is.",
    *_WORKERS,
    switch("--all", "also the Rosenbrock method"),
    NO_PROGRESS.but(help="no line as each integrator finishes"),
    JSON,
)
