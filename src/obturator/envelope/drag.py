"""Drag coefficient of the tubular projectile against Mach number.

Beyond the thesis. The point-mass flight model (:mod:`obturator.envelope.trajectory`)
needs the zero-yaw drag coefficient C_D(M) referred to the projectile's frontal
area S = pi R_p^2. Two built-in curves and a user-supplied CSV table are offered.

Provenance and caveat of the built-in curves
--------------------------------------------
No measured drag data of the ball-obturated tubular projectile (BOT) are
published in the thesis, and none were available to this package. The built-in
curves are therefore *illustrative engineering estimates*, not data:

``tubular-open`` (the bore open and the internal flow started)
    The shape of a conventional spin-stabilised 20 mm projectile's zero-yaw
    drag curve (C_D about 0.37 at M = 1.5 falling to 0.22 at M = 4; the usual
    shape of the curves tabulated in McCoy, *Modern Exterior Ballistics*, for
    20-30 mm shells) scaled by 0.4 above the choking Mach number, because the
    thesis (chapter I.B) reports tubular-projectile drag "approximately 1/2 to
    1/3 of conventional" (its Refs. 4, 5, 8). Below the choking Mach of the
    Table 1 bore (M about 1.44, thesis chapter I.B.4.c; :func:`obturator.
    gasdynamics.choking_mach`) the curve jumps back to the conventional values,
    because "the drag coefficient rises almost instantaneously at the Mach
    number at which the flow becomes choked" (thesis p. 22).

``tubular-closed`` (default; the obturator blocks the bore)
    Until the ball opens the bore is closed and a normal bow shock stands
    ahead of the inlet; this is exactly the phase that matters for the opening
    time. The closed-inlet curve adds to ``tubular-open`` the axial force of the
    thesis's own load model, the post-shock pressure on the blocked bore area
    (thesis Eqs. 1, 3, 43): Delta C_D = pi r_p^2 (P_2 - P_1) / (q S)
    = (r_p/R_p)^2 4 (M^2 - 1) / ((gamma + 1) M^2) (0.21 at M = 1.5, 0.33 at
    M = 3 for Table 1's r_p and R_p). Spillage drag around the blocked inlet
    is not included, so this curve more probably understates than overstates
    the deceleration.

A measured table (for example from range firings such as those of
Winchenbach, Daniel and Edgar, the thesis's Ref. 4) should replace these
curves for design work: ``--cd-table FILE.csv`` (columns ``mach,cd``) or
:meth:`DragTable.from_csv`. The coupled-minus-constant t_cr difference scales
about linearly with C_D.

Outside its Mach range a table holds its end values (the flight model
stops at M = 1, where the normal-shock load model ends, so only the
supersonic part is ever used for the obturator).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError, check_range
from ..model.cases import TABLE1

__all__ = [
    "DragTable",
    "ClosedInletDrag",
    "DragModel",
    "TUBULAR_OPEN",
    "DRAG_MODELS",
    "drag_model",
]


@dataclass(frozen=True)
class DragTable:
    """C_D(M) by linear interpolation in a table.

    Parameters
    ----------
    mach : tuple of float
        Mach numbers, strictly increasing, >= 0 [-].
    cd : tuple of float
        Drag coefficients referred to pi R_p^2, >= 0 [-].
    name : str
        Label carried into results.
    """

    mach: tuple[float, ...]
    cd: tuple[float, ...]
    name: str = "table"

    def __post_init__(self) -> None:
        m = tuple(float(x) for x in self.mach)
        c = tuple(float(x) for x in self.cd)
        if len(m) != len(c) or len(m) < 1:
            raise InputError(
                "cd_table", f"needs equally many Mach and C_D values, got {len(m)}, {len(c)}"
            )
        for x in m:
            check_range("cd_table.mach", x, 0.0, 50.0)
        for x in c:
            check_range("cd_table.cd", x, 0.0, 20.0)
        if any(b <= a for a, b in zip(m, m[1:], strict=False)):
            raise InputError("cd_table.mach", "Mach numbers must be strictly increasing")
        object.__setattr__(self, "mach", m)
        object.__setattr__(self, "cd", c)

    def __call__(self, mach: float) -> float:
        """C_D at Mach `mach` [-] (end values held outside the table)."""
        return float(np.interp(mach, self.mach, self.cd))

    @classmethod
    def constant(cls, cd: float) -> DragTable:
        """A Mach-independent C_D (used by the closed-form tests)."""
        return cls((0.0,), (check_range("cd", cd, 0.0, 20.0),), name=f"constant {cd:g}")

    @classmethod
    def from_csv(cls, path: str | Path) -> DragTable:
        """Read a table with a header row containing ``mach`` and ``cd`` columns.

        Parameters
        ----------
        path : str or Path
            CSV file; other columns are ignored; units: Mach [-], C_D [-]
            referred to the projectile's frontal area pi R_p^2.
        """
        import io

        from ..files import read_text_file

        p = Path(path)
        try:
            rows = list(csv.DictReader(io.StringIO(read_text_file(p, "cd_table"), newline="")))
        except csv.Error as exc:  # e.g. a cell beyond the csv module's field limit
            raise InputError("cd_table", f"{p}: not a CSV table ({exc})") from None
        if len(rows) > MAX_DRAG_ROWS:
            raise InputError("cd_table", f"{p}: more than {MAX_DRAG_ROWS} rows")
        if not rows:
            raise InputError("cd_table", f"{p}: no data rows")
        keys = {k.strip().lower(): k for k in rows[0] if k is not None}
        if "mach" not in keys or "cd" not in keys:
            raise InputError("cd_table", f"{p}: needs columns 'mach' and 'cd', got {list(keys)}")
        try:
            mach = [float(r[keys["mach"]]) for r in rows]
            cd = [float(r[keys["cd"]]) for r in rows]
        except (TypeError, ValueError):
            raise InputError("cd_table", f"{p}: non-numeric entry") from None
        return cls(tuple(mach), tuple(cd), name=p.name)


#: Illustrative open-bore tubular projectile (see the module docstring).
TUBULAR_OPEN = DragTable(
    # fmt: off
    mach=(0.0, 0.8, 0.95, 1.05, 1.2, 1.4, 1.45, 1.5, 1.75, 2.0, 2.5, 3.0, 3.5, 4.0, 5.0),
    cd=(
        0.20,
        0.20,
        0.30,
        0.42,
        0.41,
        0.39,
        0.15,
        0.148,
        0.138,
        0.128,
        0.116,
        0.104,
        0.096,
        0.088,
        0.080,
    ),
    # fmt: on
    name="tubular-open",
)


@dataclass(frozen=True)
class ClosedInletDrag:
    """Open-tube drag plus the normal-shock force on the blocked bore.

    C_D(M) = C_D,open(M) + (r_p/R_p)^2 4 (M^2 - 1) / ((gamma + 1) M^2) for M > 1
    (thesis Eqs. 1, 3, 43 divided by q pi R_p^2); no increment below M = 1.

    Parameters
    ----------
    open_drag : DragTable
        C_D of the projectile with its bore open [-].
    bore_radius : float
        r_p [m].
    projectile_radius : float
        R_p [m].
    gamma : float
        Ratio of specific heats [-].
    """

    open_drag: DragTable = TUBULAR_OPEN
    bore_radius: float = TABLE1["bore_radius"]
    projectile_radius: float = TABLE1["projectile_radius"]
    gamma: float = TABLE1["gamma"]
    name: str = "tubular-closed"

    def __post_init__(self) -> None:
        r = check_range("projectile_radius", self.projectile_radius, 0.0, lo_open=True, unit="m")
        check_range("bore_radius", self.bore_radius, 0.0, r, lo_open=True, hi_open=True, unit="m")
        check_range("gamma", self.gamma, 1.0, 3.0, lo_open=True)

    def __call__(self, mach: float) -> float:
        """C_D at Mach `mach` [-]."""
        cd = self.open_drag(mach)
        if mach > 1.0:
            g = self.gamma
            ratio = (self.bore_radius / self.projectile_radius) ** 2
            cd += ratio * 4.0 * (mach * mach - 1.0) / ((g + 1.0) * mach * mach)
        return cd


DragModel = DragTable | ClosedInletDrag

#: Names of the built-in drag curves.
DRAG_MODELS = ("tubular-closed", "tubular-open")
#: Most rows of a drag table: C_D(M) is interpolated linearly, and 10,000 points
#: resolve any curve far beyond the accuracy of a measured one (tens of points).
MAX_DRAG_ROWS = 10_000


def drag_model(
    name: str = "tubular-closed",
    *,
    bore_radius: float = TABLE1["bore_radius"],
    projectile_radius: float = TABLE1["projectile_radius"],
) -> DragModel:
    """A built-in drag curve by name, or a CSV table when `name` is a file path.

    Parameters
    ----------
    name : str
        ``"tubular-closed"`` (default), ``"tubular-open"`` or a CSV path.
    bore_radius, projectile_radius : float
        r_p and R_p [m] for the closed-inlet increment.
    """
    if name == "tubular-open":
        return TUBULAR_OPEN
    if name == "tubular-closed":
        return ClosedInletDrag(TUBULAR_OPEN, bore_radius, projectile_radius)
    p = Path(name)
    if p.suffix.lower() == ".csv" or p.exists():
        return DragTable.from_csv(p)
    raise InputError("drag", f"{name!r}; allowed: {', '.join(DRAG_MODELS)} or a CSV file")
