"""The one progress reporter of every long run: a bar on a terminal, plain lines elsewhere.

:class:`Progress` has three modes:

* ``"bar"``: a rich progress bar on stderr (a terminal), with the tasks done,
  elapsed time and time left;
* ``"lines"``: output piped or redirected: one plain line on stderr at most every
  :data:`LINE_INTERVAL_S` seconds, ``obturator: sweep: 1234/10000 points (12 %),
  45 s elapsed, about 5.5 min left``; and within :meth:`Progress.heartbeat`, a line
  saying what still runs whenever nothing was printed for :data:`HEARTBEAT_S`
  seconds (a daemon thread whose lock a fork takes first, so a forked worker never
  inherits a half-written line);
* ``"off"``: nothing (``--no-progress`` and the Python API's default).

:meth:`Progress.plan` prints a long run's planned work and its estimated time before
the work starts (the runner estimates it from a timed probe). :meth:`Progress.phases`
makes a run of unequal phases (each one or more tracked runs) one display: the plain
lines' share done and time left are those of the whole run, from each phase's weight
(its relative cost, given by the study), and a line at each phase's end gives the
whole run's time left.
"""

from __future__ import annotations

import math
import os
import sys
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Literal

__all__ = [
    "HEARTBEAT_S",
    "LINE_INTERVAL_S",
    "PLAN_MIN_S",
    "PhasePlan",
    "Progress",
    "Tracker",
    "fmt_duration",
]

#: Seconds between two plain progress lines.
LINE_INTERVAL_S = 15.0
#: Longest silence of a piped run within :meth:`Progress.heartbeat` [s] before a line
#: says what still runs (the issue's bound is 30 s; the thread looks every second).
HEARTBEAT_S = 25.0
#: A run expected to take at least this long [s] announces its plan and estimate.
PLAN_MIN_S = 5.0

Mode = Literal["off", "bar", "lines"]

#: The last line printed (monotonic time) and what runs now, shared by every reporter of
#: this process; _LOCK is held while a line is written.
_LAST: dict[str, object] = {"t": time.monotonic(), "what": ""}
_LOCK = threading.Lock()
os.register_at_fork(
    before=_LOCK.acquire, after_in_parent=_LOCK.release, after_in_child=_LOCK.release
)


def _say(line: str, what: str | None = None) -> None:
    """Print `line` on stderr and note it (and what runs now) for the heartbeat."""
    with _LOCK:
        print(line, file=sys.stderr, flush=True)
        _LAST["t"] = time.monotonic()
        if what is not None:
            _LAST["what"] = what


#: The phase plan of the run now reported (:meth:`Progress.phases`), or None.
_PLAN: list[PhasePlan | None] = [None]


def _running(what: str) -> None:
    """Note what runs now (shown by the next heartbeat line)."""
    _LAST["what"] = what


def fmt_duration(seconds: float) -> str:
    """``"42 s"``, ``"5.5 min"`` or ``"1.2 h"``."""
    if seconds < 90:
        return f"{seconds:.2g} s" if seconds < 10 else f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.1f} min"
    return f"{seconds / 3600:.1f} h"


class Tracker:
    """``tracker(n)``: n more tasks done; :meth:`describe`: what runs now."""

    def __init__(self, advance: Callable[[int], None], describe: Callable[[str], None]):
        self._advance = advance
        self.describe = describe

    def __call__(self, n: int) -> None:
        self._advance(n)


class PhasePlan:
    """A run of weighted phases (:meth:`Progress.phases`): :meth:`start` begins the next
    one; tracked runs within a phase advance the whole run's share by that phase's weight.
    """

    def __init__(self, progress: Progress, label: str, weights: Sequence[tuple[str, float]]):
        self.progress = progress
        self.label = label
        self.names = [name for name, _ in weights]
        self.weights = [float(w) for _, w in weights]
        if not self.weights or min(self.weights) < 0.0 or sum(self.weights) <= 0.0:
            raise ValueError(f"phase weights must be >= 0 with a positive sum: {weights}")
        self.index = -1  # the phase now running
        self.part = 0.0  # the share of the current phase done, 0-1
        self.t0 = time.monotonic()

    def share(self, part: float | None = None) -> float:
        """The whole run's share done (0-1) with `part` of the current phase done."""
        k = self.index
        part = self.part if part is None else part
        done = sum(self.weights[:k]) + (self.weights[k] * part if k >= 0 else 0.0)
        return done / sum(self.weights)

    def left_s(self, share: float) -> float:
        """The whole run's time left [s] at `share` done (NaN before any work is done)."""
        elapsed = time.monotonic() - self.t0
        return elapsed * (1.0 - share) / share if share > 0.0 else math.nan

    @property
    def measured(self) -> bool:
        """Whether a phase of positive weight has ended: the time left is given from then
        on. Within the first, the share of its tasks done says little of its time (the
        studies' first phases fit candidates whose costs differ tenfold), and an estimate
        from it would swing as the issue's did."""
        return sum(self.weights[: max(self.index, 0)]) > 0.0

    def start(self, name: str, weight: float | None = None) -> None:
        """Begin a phase; the end of the previous one is reported with the whole run's
        time left.

        Parameters
        ----------
        name : str
            A phase after the current one (those between count as done).
        weight : float, optional
            Replaces the phase's planned weight (a count that the earlier phases
            decide, such as the profiled parameters of ``validate``).
        """
        k = self.names.index(name, self.index + 1)
        if weight is not None:
            if weight < 0.0:
                raise ValueError(f"phase weight {weight} < 0")
            self.weights[k] = float(weight)
        if self.index >= 0:
            self._report_end(self.index, k)
        self.index, self.part = k, 0.0

    def _report_end(self, done: int, nxt: int) -> None:
        self.index, self.part = done, 1.0
        share = self.share()
        left = self.left_s(share)
        eta = f", about {fmt_duration(left)} left" if left == left else ""
        self.progress.note(
            f"{self.label}: {self.names[done]} done ({100 * share:.0f} % of the run), "
            f"{fmt_duration(time.monotonic() - self.t0)} elapsed{eta}; "
            f"next: {self.names[nxt]}"
        )


@dataclass(frozen=True)
class Progress:
    """How a run reports: ``mode`` "bar", "lines" or "off" (see the module notes).

    Parameters
    ----------
    mode : {"off", "bar", "lines"}
    interval_s : float
        Seconds between two plain lines (mode "lines").
    """

    mode: Mode = "off"
    interval_s: float = LINE_INTERVAL_S

    @classmethod
    def auto(cls, enabled: bool = True) -> Progress:
        """A bar when stderr is a terminal, else plain lines; "off" unless `enabled`."""
        if not enabled:
            return cls("off")
        return cls("bar" if sys.stderr.isatty() else "lines")

    @property
    def enabled(self) -> bool:
        """Whether anything is reported."""
        return self.mode != "off"

    def note(self, text: str) -> None:
        """One line ``obturator: <text>`` on stderr (unless off)."""
        if self.enabled:
            _say(f"obturator: {text}")

    def plan(self, label: str, work: str, estimate_s: float | None = None) -> None:
        """Announce a run's work and estimated time (only if it is long, or unknown)."""
        if estimate_s is None:
            self.note(f"{label}: {work}")
        elif estimate_s >= PLAN_MIN_S:
            self.note(f"{label}: {work}; estimated {fmt_duration(estimate_s)} on idle cores")

    @contextmanager
    def phases(self, label: str, weights: Sequence[tuple[str, float]]) -> Iterator[PhasePlan]:
        """One display for a run of phases.

        Within the block the plain lines of every tracked run show the whole run's share
        done and, once the first phase has ended (:attr:`PhasePlan.measured`), its time
        left (the elapsed time over the weight done, times the weight left), so that the
        time left covers the phases still to come; the end of each phase is a line of
        its own, ``obturator: <label>: <phase> done (40 % of the run), 1.2 min elapsed,
        about 1.8 min left; next: <phase>``.

        Parameters
        ----------
        label : str
            The run's name in the lines.
        weights : sequence of (str, float)
            The phases in order, each with its relative cost (>= 0, any unit; the study
            states its basis).

        Yields
        ------
        PhasePlan
            Call its ``start(name)`` as each phase begins.
        """
        plan = PhasePlan(self, label, weights)
        outer = _PLAN[0]
        _PLAN[0] = plan if self.mode == "lines" else None
        try:
            yield plan
        finally:
            _PLAN[0] = outer

    @contextmanager
    def heartbeat(self, label: str, what: str = "") -> Iterator[Callable[[str], None]]:
        """Within this block a piped run (mode "lines") is never silent for more than
        :data:`HEARTBEAT_S` s: a daemon thread prints ``obturator: <label>: still
        running (<what>), <elapsed> elapsed`` when nothing else was printed for that
        long. Yields a function that sets what runs now (progress lines set it too)."""
        if self.mode != "lines":
            yield lambda text: None
            return
        _running(what)
        stop = threading.Event()
        t0 = time.monotonic()

        def beat() -> None:
            while not stop.wait(min(1.0, HEARTBEAT_S / 4)):
                now = time.monotonic()
                if now - float(_LAST["t"]) >= HEARTBEAT_S:  # type: ignore[arg-type]
                    running = f" ({_LAST['what']})" if _LAST["what"] else ""
                    _say(
                        f"obturator: {label}: still running{running}, "
                        f"{fmt_duration(now - t0)} elapsed"
                    )

        _LAST["t"] = time.monotonic()
        thread = threading.Thread(target=beat, name="obturator-heartbeat", daemon=True)
        thread.start()
        try:
            yield _running
        finally:
            stop.set()
            thread.join()

    @contextmanager
    def track(
        self,
        label: str,
        total: int,
        done: int = 0,
        unit: str = "points",
        weights: Sequence[float] | None = None,
    ) -> Iterator[Tracker]:
        """Yield a :class:`Tracker` that advances the display of `total` tasks.

        `weights` (one per task, in the order they finish: their relative costs) make
        the plain lines' time left that of the whole remaining work rather than of
        equal tasks (a run of unequal steps, such as ``reproduce``).
        """
        if self.mode == "bar":
            with _bar(label, total, done) as tracker:
                yield tracker
        elif self.mode == "lines":
            yield _lines(label, total, done, unit, self.interval_s, weights)
        else:
            yield Tracker(lambda n: None, lambda text: None)


@contextmanager
def _bar(label: str, total: int, done: int) -> Iterator[Tracker]:
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )
    from rich.progress import Progress as RichProgress

    with RichProgress(
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        TextColumn("eta"),
        TimeRemainingColumn(),
        console=Console(stderr=True),
        transient=True,
    ) as bar:
        task = bar.add_task(label, total=total, completed=done)
        yield Tracker(
            lambda n: bar.advance(task, n),
            lambda text: bar.update(task, description=f"{label}: {text}"),
        )


def _lines(
    label: str,
    total: int,
    done: int,
    unit: str,
    interval_s: float,
    weights: Sequence[float] | None = None,
) -> Tracker:
    cost = [0.0]  # cost[k]: the relative cost of the first k tasks
    for w in weights if weights is not None else [1.0] * total:
        cost.append(cost[-1] + float(w))
    if len(cost) != total + 1:
        raise ValueError(f"{len(cost) - 1} weights for {total} tasks")
    t0 = time.monotonic()
    state = {"done": done, "last": t0, "what": ""}
    _running(f"{label}: {done}/{total} {unit}")

    def advance(n: int) -> None:
        state["done"] += n
        _running(f"{label}: {state['done']}/{total} {unit}")
        now = time.monotonic()
        if now - state["last"] < interval_s or state["done"] >= total:
            return
        state["last"] = now
        elapsed = now - t0
        spent = cost[state["done"]] - cost[done]
        left = elapsed / spent * (cost[total] - cost[state["done"]]) if spent > 0 else math.nan
        share = cost[state["done"]] / cost[total] if cost[total] else 1.0
        of = ""
        plan = _PLAN[0]
        if plan is not None and plan.index >= 0:  # the whole run's share and time left
            plan.part = share
            share = plan.share()
            left = plan.left_s(share) if plan.measured else math.nan
            elapsed, of = now - plan.t0, " of the run"
        what = f" ({state['what']})" if state["what"] else ""
        eta = f", about {fmt_duration(left)} left" if left == left else ""
        _say(
            f"obturator: {label}: {state['done']}/{total} {unit} "
            f"({100 * share:.0f} %{of}){what}, "
            f"{fmt_duration(elapsed)} elapsed{eta}",
            f"{label}: {state['done']}/{total} {unit}{what}",
        )

    def describe(text: str) -> None:
        state["what"] = text
        _running(f"{label}: {text}")

    return Tracker(advance, describe)
