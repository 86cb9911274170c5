"""The last slips of many set-valued cases, together in the DOP853 lanes.

Past stick ratio kappa = |G_req| / M ~0.55 a ball on the rig no longer sticks: its last
slip runs to the opening (``docs/stick_slip.md`` sections 6 and 10), and at 100-218 rad/s
it is most of the trajectory (70-80 % of the steps at 175-200 rad/s). The slip phase of
:mod:`.stick_slip` integrates it one case at a time: Radau IIA while the slip is slow,
scalar DOP853 stretches once it is fast. Where the front door asks for it
(``Controls.hand_back``: opening times only, no recorded steps), the mode loop instead
stops in such a slip (status ``NONSTIFF``) once kappa >=
:data:`~.stick_slip_modes.HAND_OFF_KAPPA` and |omega_r| >=
:data:`~.stick_slip_modes.HAND_OFF_SLIP` (M / A) h_max, and :func:`finish_in_lanes`
continues all such cases together in the DOP853 lanes of :mod:`.lanes.dop853`:

* the same law at zero width (the thesis kernel with no regularisation: at omega_r != 0
  it is the law itself), the same DOP853 and tolerances as the solver's own stretches
  (the lanes are bit-equal to the scalar DOP853), so nothing is approximated that the
  one-case path does not approximate;
* a lane whose slip falls below :data:`~.stick_slip_modes.SLIP_FLOOR` (M / A) h_max at
  the end of an accepted step (the slip direction, singular at zero slip, then relaxes
  within a few largest steps), or that DOP853 finds stiff, ends there, and its case
  goes on in the mode loop from that state (stick, breakaway, ... as usual; no second
  hand-off);
* counters add up over both parts.

In the switch model (Leine and Nijmeijer 2004, ch. 2) a slip mode is a smooth ODE
between transitions, so any integrator of it may run it; here an explicit one runs the
non-stiff part, as the solver's own stretches do.
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
    """`runs` of the set-valued solver with those that stopped to hand their slip over
    (status ``NONSTIFF``) run on to their ends, in DOP853 lanes and, where a lane gives
    the slip back, in the mode loop (see the module).

    Parameters
    ----------
    problems, controls : sequence
        Each case's problem (as given to :func:`.stick_slip.integrate`) and controls.
    runs : sequence of RawSolution
        Each case's run so far.
    n_lanes : int
        Lanes advanced together.

    Returns
    -------
    list of RawSolution
        The runs, each ended (the others as given).
    """
    out = list(runs)
    handed = [k for k, run in enumerate(runs) if run.status == Status.NONSTIFF]
    groups: dict[tuple[float, float, float], list[int]] = {}
    for k in handed:  # the lanes take one set of tolerances
        groups.setdefault((controls[k].rtol, controls[k].atol, controls[k].event_tol), []).append(k)
    for (rtol, atol, event_tol), group in groups.items():
        finished = _in_lanes(problems, controls, runs, group, rtol, atol, event_tol, n_lanes)
        for k, run in zip(group, finished, strict=True):
            out[k] = run
    return out


def _in_lanes(problems, controls, runs, handed, rtol, atol, event_tol, n_lanes):
    """The runs `handed` (one set of tolerances) to their ends (see the module)."""
    zero = [at_zero_width(problems[k]) for k in handed]
    ctl = [controls[k] for k in handed]
    h_max = np.array([c.h_max for c in ctl])
    left = np.array(
        [max(c.max_steps - runs[k].n_steps, 1) for c, k in zip(ctl, handed, strict=True)]
    )
    st, t_ev, t_end, y_end, nfev, n_steps, n_rej = integrate_lanes(
        np.array([runs[k].y_end for k in handed]),
        np.array([runs[k].t_end for k in handed]),
        np.array([z.p for z in zero]),
        np.array([z.scale for z in zero]),
        np.array([c.t_max for c in ctl]),
        FIRST_STEP * h_max,
        h_max,
        left.astype(np.int64),
        np.argsort(-np.array([abs(z.y0[7]) for z in zero]), kind="stable"),
        rtol,
        atol,
        event_tol,
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
        status = Status(int(st[j]))
        if status == Status.STIFF and np.all(np.isfinite(y_end[j])):
            rest = ctl[j]._replace(hand_back=False, max_steps=max(int(left[j] - n_steps[j]), 1))
            last = loop(zero[j]._replace(y0=y_end[j].copy(), t0=float(t_end[j])), rest, math.inf)
            done.append(last._replace(
                nfev=counts[0] + last.nfev, njev=counts[1] + last.njev,
                n_steps=counts[2] + last.n_steps, n_rejected=counts[3] + last.n_rejected,
            ))  # fmt: skip
            continue
        if status == Status.STIFF:
            status = Status.FAILED
        opened = status == Status.OPENED
        done.append(RawSolution(
            status, float(t_ev[j]), y_end[j].copy() if opened else np.full(N_STATE, math.nan),
            np.empty(0), np.empty((0, N_STATE)), *counts, float(t_end[j]), y_end[j].copy(),
        ))  # fmt: skip
    return done
