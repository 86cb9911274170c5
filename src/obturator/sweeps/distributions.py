"""Distributions of uncertain inputs and their per-sample draws (Monte Carlo).

Written ``name=kind:args`` (:func:`parse_distribution`); sample i draws from
its own generator ``default_rng(SeedSequence(seed).spawn(n)[i])``
(:func:`sample_inputs`), so it is the same whatever the worker count,
chunking or total sample count.

>>> parse_distribution("mu_s=normal:0.5473,0.03")
('mu_s', Distribution(kind='normal', params=(0.5473, 0.03)))
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import InputError
from ..params import SWEEP_PARAMS, Range
from ..vocab import DIST_KINDS, DistKind
from .grid import _is_number, _unit_after_list, canonical_name, parse_value
from .spec import SweepSpec

__all__ = [
    "Distribution",
    "MAX_SIGMA_LN",
    "parse_distribution",
    "parse_distribution_args",
    "support",
    "check_support",
    "SUPPORT_Z",
    "distributions",
    "sample_inputs",
    "check_samples",
    "check_sample_cases",
]

#: Largest log-normal SIGMA_LN. 5 already spreads the 1st-99th percentiles over a
#: factor exp(2 x 2.33 x 5) ~ 1e10, wider than any physical input's uncertainty;
#: larger values overflow floats in the tails (exp(sigma z) > 1.8e308 for sigma z > 709).
MAX_SIGMA_LN = 5.0
#: Standard deviations out to which draws must stay finite (a normal draw beyond
#: 10 sd has probability ~1e-23: no study reaches it).
_TAIL_Z = 10.0

#: Standard deviations (of a normal, or of ln X for a log-normal) out to which a
#: distribution must stay inside its parameter's physical range. A standard normal
#: draw lies beyond 8 sd with probability 1.2e-15, so a study of MAX_SAMPLES = 1e5
#: draws per input leaves the range with probability below 2e-10; the Sobol sampler
#: reaches 7.0 sd at most (u clipped to 1e-12, :mod:`obturator.envelope.uncertain`).
#: A normal whose 8-sd reach leaves the range has a physically impossible tail: the
#: user is told to truncate it (truncnormal) or, for a positive quantity, to use the
#: log-normal.
SUPPORT_Z = 8.0

_DIST_ARGS = dict(zip(DIST_KINDS, (2, 2, 2, 4), strict=True))
_DIST_HELP = (
    "normal:MEAN,SD | uniform:LO,HI | lognormal:MEDIAN,SIGMA_LN | truncnormal:MEAN,SD,LO,HI"
)
#: The names of each form's numbers, as the help writes them.
_ARG_NAMES = {
    "normal": ("MEAN", "SD"),
    "uniform": ("LO", "HI"),
    "lognormal": ("MEDIAN", "SIGMA_LN"),
    "truncnormal": ("MEAN", "SD", "LO", "HI"),
}
_TRAILING_UNIT = re.compile(r"^([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(\S.*)$")


@dataclass(frozen=True)
class Distribution:
    """Distribution of one uncertain input (values in the parameter's unit).

    Parameters
    ----------
    kind : {"normal", "uniform", "lognormal", "truncnormal"}
        ``normal``: (mean, sd), sd >= 0. ``uniform``: (lo, hi), lo < hi.
        ``lognormal``: (median, sigma_ln) with ln X ~ Normal(ln median,
        sigma_ln); median > 0, sigma_ln >= 0. ``truncnormal``: (mean, sd, lo,
        hi): a normal restricted to [lo, hi], sd > 0, lo < hi.
    params : tuple of float
    """

    kind: DistKind
    params: tuple[float, ...]

    def __post_init__(self) -> None:
        if self.kind not in _DIST_ARGS:
            raise InputError("distribution", f"{self.kind!r}; allowed: {_DIST_HELP}")
        p = tuple(float(x) for x in self.params)
        object.__setattr__(self, "params", p)
        if len(p) != _DIST_ARGS[self.kind]:
            raise InputError(
                "distribution", f"{self.kind} takes {_DIST_ARGS[self.kind]} numbers, got {len(p)}"
            )
        if not all(math.isfinite(x) for x in p):
            raise InputError("distribution", f"{self} has non-finite parameters")
        k = self.kind
        if k == "normal" and p[1] < 0:
            raise InputError("distribution", f"{self}: SD must be >= 0")
        if k == "uniform" and not p[0] < p[1]:
            raise InputError("distribution", f"{self}: needs LO < HI")
        if k == "lognormal" and (p[0] <= 0 or p[1] < 0):
            raise InputError("distribution", f"{self}: needs MEDIAN > 0 and SIGMA_LN >= 0")
        if k == "truncnormal" and (p[1] <= 0 or not p[2] < p[3]):
            raise InputError("distribution", f"{self}: needs SD > 0 and LO < HI")
        if k == "lognormal" and p[1] > MAX_SIGMA_LN:
            raise InputError(
                "distribution", f"{self}: SIGMA_LN must be <= {MAX_SIGMA_LN:g} (overflow guard)"
            )
        spread = p[1] * _TAIL_Z if k != "uniform" else 0.0
        reach = p[0] * math.exp(spread) if k == "lognormal" else max(abs(p[0]), abs(p[-1])) + spread
        if not math.isfinite(reach) or reach > 1e300:
            raise InputError(
                "distribution", f"{self}: draws {_TAIL_Z:g} sd out overflow floating point"
            )

    def __str__(self) -> str:
        return f"{self.kind}:{','.join(repr(x) for x in self.params)}"

    def draw(self, rng: np.random.Generator) -> float:
        """One value drawn with ``rng``."""
        p = self.params
        if self.kind == "normal":
            return p[0] + p[1] * float(rng.standard_normal())
        if self.kind == "uniform":
            return p[0] + (p[1] - p[0]) * float(rng.random())
        if self.kind == "lognormal":
            return p[0] * math.exp(p[1] * float(rng.standard_normal()))
        return _truncnormal(p[0], p[1], p[2], p[3], float(rng.random()))


def _truncnormal(mean: float, sd: float, lo: float, hi: float, u: float) -> float:
    """Inverse-CDF draw of a normal truncated to [lo, hi] from u in [0, 1).

    :func:`scipy.stats.truncnorm` works in log space in the tails, so a window many
    standard deviations away from the mean is sampled correctly (a plain
    ndtr/ndtri inversion underflows there and returns an end point every time).
    """
    from scipy.stats import truncnorm

    a, b = (lo - mean) / sd, (hi - mean) / sd
    z = float(truncnorm.ppf(u, a, b))
    return min(max(mean + sd * z, lo), hi)


def split_assignment(text: object, field: str, form: str, sep: str) -> tuple[str, str, str]:
    """Split ``NAME=LEFT<sep>RIGHT`` (a command-line item) into its three texts.

    Parameters
    ----------
    text : str
        The item as given.
    field : str
        Field named by the error.
    form : str
        The expected form, for the error (``"NAME=LO,HI"``).
    sep : str
        Separator of LEFT and RIGHT after the ``=``.

    Returns
    -------
    (str, str, str)
        NAME as written (the caller canonicalises it), LEFT, RIGHT.

    Raises
    ------
    InputError
        If `text` is not a string holding ``=`` with `sep` after it.
    """
    s = text.strip() if isinstance(text, str) else ""
    name, eq, rest = s.partition("=")
    if not eq or sep not in rest:
        raise InputError(field, f"malformed {text!r}: expected {form}")
    left, right = rest.split(sep, 1)
    return name, left, right


def parse_distribution_args(
    name: str, kind: str, args: str, unit: str, allowed: Range | None = None
) -> Distribution:
    """One distribution from its form and numbers, read as every flag reads quantities.

    Parameters
    ----------
    name : str
        The parameter (named by errors).
    kind : str
        ``normal``, ``uniform``, ``lognormal`` or ``truncnormal``.
    args : str
        The numbers, comma separated, in the parameter's unit unless written with
        one: each number may carry its own (``3000 rpm,50 rpm``), or one unit after
        the last number applies to every number (``3000,50 rpm``), as in a sweep
        axis (:func:`~.grid.parse_axis`); a list that mixes bare numbers and units
        any other way is refused. SIGMA_LN of the log-normal is a pure number (the
        spread of ln X does not depend on X's unit): a unit written after it
        applies to MEDIAN alone (``lognormal:3000,0.1 rpm``).
    unit : str
        The parameter's unit, pint syntax (``""`` for a pure number).
    allowed : Range, optional
        The parameter's physical range; when given, :func:`check_support` refuses
        a distribution that leaves it.

    Returns
    -------
    Distribution
        Numbers in `unit`.

    Raises
    ------
    InputError
        Naming `name`: an unknown form, a wrong count of numbers, a malformed,
        mixed or unconvertible number, invalid parameters, or a support outside
        `allowed`.
    """
    kind = kind.strip().lower()
    if kind not in _DIST_ARGS:
        raise InputError(name, f"unknown distribution {kind!r}; allowed: {_DIST_HELP}")
    arg_names = _ARG_NAMES[kind]
    parts = [p.strip() for p in args.split(",")]
    if len(parts) != len(arg_names):
        raise InputError(
            name,
            f"{kind} takes {len(arg_names)} numbers ({kind}:{','.join(arg_names)}), "
            f"got {len(parts)} in {args.strip()!r}",
        )
    pure = {1} if kind == "lognormal" else set()
    # a pure-number parameter takes the rule too: "0.5,0.03 percent" is 0.005, 0.0003
    if kind == "lognormal":
        m = _TRAILING_UNIT.match(parts[1])
        if _is_number(parts[0]) and m is not None and not _is_number(parts[1]):
            parts = [f"{parts[0]} {m.group(2)}", m.group(1)]
    else:
        parts = _unit_after_list(name, ",".join(parts), unit)
    numbers = [
        parse_value(name, p, f"{kind} {arg}", "" if i in pure else unit)
        for i, (p, arg) in enumerate(zip(parts, arg_names, strict=True))
    ]
    try:
        dist = Distribution(kind, tuple(numbers))  # type: ignore[arg-type]
    except InputError as exc:
        raise InputError(name, str(exc).split(": ", 1)[1]) from None
    if allowed is not None:
        check_support(name, dist, allowed, unit)
    return dist


def support(dist: Distribution) -> tuple[float, float]:
    """The values a study can draw from `dist`, [lo, hi], in its unit.

    ``uniform`` and ``truncnormal``: their window; ``normal``: MEAN +- :data:`SUPPORT_Z` SD;
    ``lognormal``: MEDIAN exp(+-SUPPORT_Z SIGMA_LN).
    """
    p = dist.params
    if dist.kind in ("uniform", "truncnormal"):
        return p[-2], p[-1]
    if dist.kind == "normal":
        return p[0] - SUPPORT_Z * p[1], p[0] + SUPPORT_Z * p[1]
    return p[0] * math.exp(-SUPPORT_Z * p[1]), p[0] * math.exp(SUPPORT_Z * p[1])


def check_support(name: str, dist: Distribution, allowed: Range, unit: str = "") -> None:
    """Refuse a distribution that draws values outside the parameter's physical range.

    The support is :func:`support` (out to :data:`SUPPORT_Z` standard deviations for
    the unbounded forms). The message names the range and a form that stays
    inside it: truncnormal with LO, HI in the range, or for a positive quantity
    the log-normal.

    Raises
    ------
    InputError
        Naming `name`, the distribution, the values it reaches and the range.
    """
    lo, hi = support(dist)
    if allowed.contains(lo) and allowed.contains(hi):
        return
    u = f" {unit}" if unit and unit != "1" else ""
    reach = (
        f"within {SUPPORT_Z:g} SD"
        if dist.kind == "normal"
        else (f"within {SUPPORT_Z:g} SIGMA_LN" if dist.kind == "lognormal" else "")
    )
    hints = ["truncnormal:MEAN,SD,LO,HI with LO, HI inside it"]
    if allowed.lo >= 0.0 and dist.kind == "normal":
        hints.append("lognormal:MEDIAN,SIGMA_LN (positive values)")
    if dist.kind == "uniform":
        hints = ["uniform:LO,HI with LO, HI inside it"]
    draws = f"draws values in [{lo:.6g}, {hi:.6g}]{u}" + (f" {reach}" if reach else "")
    raise InputError(
        name,
        f"{dist} {draws}, outside the allowed range {allowed}{u}; use " + " or ".join(hints),
    )


def parse_distribution(text: str) -> tuple[str, Distribution]:
    """Parse ``name=kind:args``, e.g. ``mu_s=normal:0.5473,0.03``.

    Parameters
    ----------
    text : str
        ``NAME=normal:MEAN,SD``, ``NAME=uniform:LO,HI``,
        ``NAME=lognormal:MEDIAN,SIGMA_LN`` or ``NAME=truncnormal:MEAN,SD,LO,HI``;
        NAME one of :data:`~obturator.params.SWEEP_PARAMS` (hyphens allowed), numbers in
        its unit or with units (:func:`parse_distribution_args`).

    Returns
    -------
    (str, Distribution)
        Checked against the parameter's range (:func:`check_support`).
    """
    name_text, kind, args = split_assignment(text, "vary", f"NAME=KIND:ARGS ({_DIST_HELP})", ":")
    name = canonical_name(name_text)
    par = SWEEP_PARAMS[name]
    return name, parse_distribution_args(name, kind, args, par.pint_unit, par.range)


def sample_inputs(
    distributions: Mapping[str, Distribution], samples: int, seed: int
) -> dict[str, np.ndarray]:
    """Draw the inputs of every sample.

    Sample i uses its own generator ``default_rng(SeedSequence(seed).spawn(n)[i])``
    and draws the parameters in :data:`~obturator.params.SWEEP_PARAMS` order, so it does not depend
    on the worker count, the chunking, the total ``samples`` or the order in
    which the distributions were given.

    Returns
    -------
    dict of str to numpy.ndarray
        name -> values, shape (samples,), in the parameter's unit.
    """
    n = int(samples)
    names = [k for k in SWEEP_PARAMS if k in distributions]
    out = {k: np.empty(n) for k in names}
    for i, child in enumerate(np.random.SeedSequence(int(seed)).spawn(n)):
        rng = np.random.default_rng(child)
        for k in names:
            out[k][i] = distributions[k].draw(rng)
    return out


def check_samples(values: Mapping[str, np.ndarray]) -> None:
    """Refuse sampled values outside each parameter's allowed range."""
    for name, x in values.items():
        par = SWEEP_PARAMS[name]
        bad = ~np.array([par.range.contains(float(v)) for v in x], dtype=bool)
        if np.any(bad):
            i = int(np.flatnonzero(bad)[0])
            raise InputError(
                name,
                f"{int(bad.sum())} sampled values fall outside the allowed range "
                f"{par.range} {par.unit} (first: sample {i}, "
                f"{x[i]:g}); narrow the distribution or use truncnormal",
            )


def check_sample_cases(spec: SweepSpec, values: Mapping[str, np.ndarray]) -> None:
    """Build every sample's case before any integration; refuse the study if any is invalid.

    Per-parameter ranges are checked by :func:`check_samples`; this catches the
    combined limits of the case factories (theta_0 above the opening angle
    beta_s, the hole inside the ball, ...), so a distribution whose support
    leaves the physical domain is an input error, not a study whose every
    sample is silently invalid.
    """
    names = list(values)
    n = len(values[names[0]]) if names else 0
    bad: list[int] = []
    first = ""
    for i in range(n):
        try:
            spec.build_case({k: float(values[k][i]) for k in names})
        except InputError as exc:
            bad.append(i)
            first = first or str(exc)
    if bad:
        raise InputError(
            "vary",
            f"{len(bad)} of {n} samples are not valid cases (first: sample {bad[0]}, {first}); "
            "narrow the distribution or use truncnormal",
        )


def distributions(vary: Any) -> dict[str, Distribution]:
    """Name -> Distribution from a mapping (Distribution or text), one text or a sequence."""
    dists: dict[str, Distribution] = {}
    items: list[tuple[str, Distribution]] = []
    if isinstance(vary, Mapping):
        for key, d in vary.items():
            name = canonical_name(key)
            if isinstance(d, str):
                _, d = parse_distribution(f"{name}={d}")
            if not isinstance(d, Distribution):
                raise InputError(name, f"expected a Distribution or text, got {d!r}")
            par = SWEEP_PARAMS[name]
            if par.range is not None:
                check_support(name, d, par.range, par.unit)
            items.append((name, d))
    elif isinstance(vary, str):
        items.append(parse_distribution(vary))
    else:
        items.extend(parse_distribution(v) for v in vary)
    for name, d in items:
        if name in dists:
            raise InputError(name, "is varied twice")
        dists[name] = d
    return dists
