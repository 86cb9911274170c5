"""The last slips of set-valued points, continued in the DOP853 lanes.

Past stick ratio kappa = |G_req| / M ~0.55 a ball on the rig no longer sticks: its last
slip runs to the opening (``docs/stick_slip.md`` sections 6 and 10), and at 100-218 rad/s
it is most of the trajectory. The mode loop of :mod:`.stick_slip` integrates it one
point at a time (Radau IIA while the slip is slow, scalar DOP853 stretches once it is
fast). With ``Controls.last_slip_to_lanes`` (the front door's strategy ``slip_lanes``:
opening times only) the loop instead stops in such a slip (the hand-over signal
``NONSTIFF``) once kappa >= :data:`~.stick_slip_modes.HAND_OFF_KAPPA` and |omega_r| >=
:data:`~.stick_slip_modes.HAND_OFF_SLIP` (M / A) h_max, and :func:`finish_in_lanes`
continues every such point in the DOP853 lanes of :mod:`.lanes.dop853`:

* the same law at zero width (the thesis kernel with no regularisation: at omega_r != 0
  it is the law itself) and the tolerances of the loop's own DOP853 stretches, so
  nothing is approximated that the loop does not approximate;
* a lane whose slip falls below :data:`~.stick_slip_modes.SLIP_FLOOR` (M / A) h_max at
  the end of an accepted step (the slip direction, singular at zero slip, then relaxes
  within a few largest steps), or that DOP853 finds stiff, ends there, and its point
  goes on in the mode loop from that state (stick, breakaway, ... as usual; no second
  hand-off);
* counters add up over both parts.

Each lane runs the scalar arithmetic on its own point (:mod:`.lanes.dop853`), and the
hand-off is decided by the point's own state, so a point's t_cr is the same alone (one
lane) and in any batch. In the switch model (Leine and Nijmeijer 2004, ch. 2) a slip
mode is a smooth ODE between transitions, so any integrator of it may run it; an
explicit one runs the non-stiff part, as the loop's own stretches do.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ..layout import N_STATE
from .contract import Controls, Problem, RawSolution, Status
from .lanes.dop853 import integrate_lanes
from .stick_slip import at_zero_width, run_cycles
from .stick_slip_modes import slip_floor
from .switching import HandOff

__all__ = ["FIRST_STEP", "finish_in_lanes"]

#: First DOP853 step of a handed slip, in largest steps (its controller grows it 10x a
#: step at most).
FIRST_STEP = 0.1


def finish_in_lanes(
    problems: Sequence[Problem],
    controls: Sequence[Controls],
    runs: Sequence[RawSolution],
    n_lanes: int,
) -> list[RawSolution]:
    """`runs` of the set-valued solver, those that stopped to hand their last slip over
    (``NONSTIFF``) run on to their ends in the DOP853 lanes and, where a lane gives the
    slip back, in the mode loop (see the module).

    Parameters
    ----------
    problems, controls : sequence
        Each point's problem and controls (as given to :func:`.stick_slip.integrate`).
    runs : sequence of RawSolution
        Each point's run so far.
    n_lanes : int
        Lanes advanced together (1 to 16).

    Returns
    -------
    list of RawSolution
        The runs, each ended (the others as given).
    """
    out = list(runs)
    handed = [k for k, run in enumerate(runs) if run.status == HandOff.NONSTIFF]
    groups: dict[tuple[float, float, float], list[int]] = {}
    for k in handed:  # the lanes take one set of tolerances
        groups.setdefault((controls[k].rtol, controls[k].atol, controls[k].event_tol), []).append(k)
    for group in groups.values():
        finished = _in_lanes(problems, controls, runs, group, n_lanes)
        for k, run in zip(group, finished, strict=True):
            out[k] = run
    return out


def _in_lanes(
    problems: Sequence[Problem],
    controls: Sequence[Controls],
    runs: Sequence[RawSolution],
    handed: list[int],
    n_lanes: int,
) -> list[RawSolution]:
    """The runs `handed` (one set of tolerances) to their ends (see the module)."""
    zero = [at_zero_width(problems[k]) for k in handed]
    ctl = [controls[k] for k in handed]
    h_max = np.array([c.h_max for c in ctl])
    done_steps = [runs[k].n_steps for k in handed]
    left = np.array([max(c.max_steps - n, 1) for c, n in zip(ctl, done_steps, strict=True)])
    st, t_ev, t_end, y_end, nfev, n_steps, n_rej = integrate_lanes(
        np.array([runs[k].y_end for k in handed]),
        np.array([runs[k].t_end for k in handed]),
        np.array([z.p for z in zero]),
        np.array([z.scale for z in zero]),
        np.array([c.t_max for c in ctl]),
        FIRST_STEP * h_max,
        h_max,
        left.astype(np.int64),
        np.arange(len(handed)),
        ctl[0].rtol,
        ctl[0].atol,
        ctl[0].event_tol,
        n_lanes,
        np.array([slip_floor(z.p, c.h_max) for z, c in zip(zero, ctl, strict=True)]),
    )
    loop = run_cycles()
    done = []
    for j, k in enumerate(handed):
        run = runs[k]
        counts = (
            run.nfev + int(nfev[j]), run.njev, run.n_steps + int(n_steps[j]),
            run.n_rejected + int(n_rej[j]),
        )  # fmt: skip
        status = int(st[j])
        if status == HandOff.STIFF and np.all(np.isfinite(y_end[j])):
            rest = ctl[j]._replace(
                last_slip_to_lanes=False, max_steps=max(int(left[j] - n_steps[j]), 1)
            )
            last = loop(zero[j]._replace(y0=y_end[j].copy(), t0=float(t_end[j])), rest, math.inf)
            done.append(last._replace(
                nfev=counts[0] + last.nfev, njev=counts[1] + last.njev,
                n_steps=counts[2] + last.n_steps, n_rejected=counts[3] + last.n_rejected,
            ))  # fmt: skip
            continue
        if status == HandOff.STIFF:
            status = Status.FAILED
        opened = status == Status.OPENED
        done.append(RawSolution(
            status, float(t_ev[j]), y_end[j].copy() if opened else np.full(N_STATE, math.nan),
            np.empty(0), np.empty((0, N_STATE)), *counts, float(t_end[j]), y_end[j].copy(),
        ))  # fmt: skip
    return done
