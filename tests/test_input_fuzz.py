"""Fuzz of the inputs that enter by other doors than the flags (issue 46, item 9).

Generated from the registry (:data:`obturator.params.PARAMS`, the sampled inputs of
montecarlo and of the envelope studies) and from the data-file schema
(:data:`obturator.calibration.data.RUN_COLUMNS` and the fixed columns). The rule under
test: every input gives either the value its text means or one
:class:`~obturator.errors.InputError` naming the field, never another exception. The
expected values are computed here, apart from the parsers: unit factors written out
(1 mm = 1e-3 m, 1 rpm = 2 pi / 60 rad/s, ...), supports from their definitions
(MEAN +- 8 SD, MEDIAN exp(+-8 SIGMA_LN), [LO, HI]), the opening angle from Eq. 6 with
Table 1's radii, and the number grammar of a data file as a regular expression. No
case is solved: the suite runs in seconds.

Size per class (at most, examples per run, derandomised; hypothesis stops early where a
class has fewer distinct cases): distribution forms with units 300 for montecarlo's
inputs and 300 for the envelope's, a unit on some numbers only 100, free text 150 (each
through both parsers); column spellings 200, misspellings 150, cell numbers 300,
cross-column consistency 200.
"""

from __future__ import annotations

import math
import re
import string
from pathlib import Path

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from obturator.calibration.data import RUN_COLUMNS, load_spin_rig_csv
from obturator.envelope.model import INPUTS
from obturator.envelope.uncertain import parse_input_distribution
from obturator.errors import InputError
from obturator.params import PARAMS, SWEEP_PARAMS
from obturator.sweeps.distributions import Distribution, parse_distribution


def _fuzz(n: int) -> settings:
    return settings(
        max_examples=n,
        deadline=None,
        derandomize=True,
        suppress_health_check=[HealthCheck.function_scoped_fixture],
    )


#: Other units of each SI unit with their factor to SI, written out by hand.
ALT_UNITS: dict[str, list[tuple[str, float]]] = {
    "m": [("mm", 1e-3), ("um", 1e-6), ("cm", 1e-2), ("km", 1e3)],
    "rad/s": [("rpm", 2.0 * math.pi / 60.0), ("Hz", 2.0 * math.pi), ("deg/s", math.pi / 180)],
    "deg": [("rad", 180.0 / math.pi)],
    "kg/m^3": [("g/cm^3", 1000.0)],
    "Pa s": [("mPa*s", 1e-3)],
    "1": [("percent", 1e-2)],
    "m/s": [("mm/s", 1e-3), ("km/hour", 1.0 / 3.6)],
    "rad": [("deg", math.pi / 180.0)],
    "K": [],
}
SUPPORT_Z = 8.0  # issue 46's criterion, restated: 8 SD (probability 1.2e-15 per draw)
KINDS = {"normal": 2, "uniform": 2, "lognormal": 2, "truncnormal": 4}

#: (name, SI unit, allowed range or None) of every sampled input.
MC_INPUTS = [(k, p.unit, p.range) for k, p in SWEEP_PARAMS.items()]
ENVELOPE_INPUTS = [
    (k, PARAMS[k].unit if k in PARAMS else v.unit, PARAMS[k].range if k in PARAMS else None)
    for k, v in INPUTS.items()
]


def _expected(kind: str, si: list[float]) -> tuple[float, float] | None:
    """The support of a valid distribution, None when its numbers are invalid."""
    if kind == "normal":
        m, sd = si
        return None if sd < 0 else (m - SUPPORT_Z * sd, m + SUPPORT_Z * sd)
    if kind == "uniform":
        lo, hi = si
        return (lo, hi) if lo < hi else None
    if kind == "lognormal":
        med, s = si
        if med <= 0 or s < 0 or s > 5:
            return None
        return (med * math.exp(-SUPPORT_Z * s), med * math.exp(SUPPORT_Z * s))
    m, sd, lo, hi = si
    return (lo, hi) if sd > 0 and lo < hi else None


@st.composite
def _distribution_case(draw, inputs):
    name, unit, rng = draw(st.sampled_from(inputs))
    kind = draw(st.sampled_from(sorted(KINDS)))
    centre = draw(st.sampled_from([0.5, 1.0, 87.0, 5e-5, 4.7e-3, 300.0, 7669.6, -1.0, 0.0]))
    spread = draw(st.sampled_from([0.0, 1e-3, 0.01, 0.1, 0.5, 2.0]))
    si = [centre, abs(centre) * spread or spread]
    if kind == "uniform":
        si = [centre - si[1], centre + si[1]]
    if kind == "lognormal":
        si = [centre, spread]
    if kind == "truncnormal":
        width = draw(st.sampled_from([0.5, 1.0, 3.0]))
        si = [*si, centre - width * si[1], centre + width * si[1]]
    pure = {1} if kind == "lognormal" else set()
    alts = ALT_UNITS.get(unit, [])
    style = draw(st.sampled_from(["bare", "si_each", "alt_each", "alt_trailing"]))
    if style.startswith("alt") and not alts:
        style = "bare"
    sym, factor = draw(st.sampled_from(alts)) if style.startswith("alt") else (unit, 1.0)
    sym = sym.replace(" ", "*")
    words = []
    for i, x in enumerate(si):
        if i in pure or style == "bare" or unit == "1" and style == "si_each":
            words.append(repr(x))
        elif style == "alt_trailing":
            words.append(repr(x / factor))
        else:
            words.append(f"{x / factor!r} {sym}")
    if style == "alt_trailing" and words:
        dims = [i for i in range(len(si)) if i not in pure]
        words[-1] = words[-1] + f" {sym}" if dims[-1] == len(si) - 1 else words[-1]
        if kind == "lognormal":  # the unit after SIGMA_LN belongs to MEDIAN
            words[-1] = f"{words[-1]} {sym}"
    return name, kind, si, f"{name}={kind}:{','.join(words)}", rng, pure


def _check_distribution(parse, case) -> None:
    name, kind, si, text, rng, pure = case
    support = _expected(kind, si)
    ok = support is not None and (
        rng is None or (rng.contains(support[0]) and rng.contains(support[1]))
    )
    try:
        got_name, dist = parse(text)
    except InputError as exc:
        assert str(exc).startswith(f"{name}: "), (text, str(exc))
        if ok:  # a valid distribution may only fail on what the test cannot see
            assert "refuses" in str(exc) or "subnormal" in str(exc), (text, str(exc))
        return
    assert ok, (text, dist)
    assert got_name == name and dist.kind == kind
    assert dist.params == pytest.approx(tuple(si), rel=1e-9, abs=1e-300), text


@_fuzz(300)
@given(_distribution_case(MC_INPUTS))
def test_montecarlo_distribution_forms_with_units(case):
    _check_distribution(parse_distribution, case)


@_fuzz(300)
@given(_distribution_case(ENVELOPE_INPUTS))
def test_envelope_distribution_forms_with_units(case):
    _check_distribution(parse_input_distribution, case)


@_fuzz(100)
@given(
    st.sampled_from([(k, u) for k, u, _ in MC_INPUTS if ALT_UNITS.get(u) and u != "1"]),
    st.sampled_from(["normal", "uniform", "truncnormal"]),
    st.integers(0, 3),
)
def test_a_unit_on_some_numbers_only_is_refused(param, kind, where):
    name, unit = param
    sym = ALT_UNITS[unit][0][0]
    n = KINDS[kind]
    where = where % (n - 1)  # never the last alone: that one applies to all
    words = ["1" if i != where else f"1 {sym}" for i in range(n)]
    with pytest.raises(InputError, match=f"^{name}: .*mixes values with and without a unit"):
        parse_distribution(f"{name}={kind}:{','.join(words)}")


_TOKENS = st.sampled_from(
    ["mu_s", "gap", "spin_rate", "=", ":", ",", "normal", "uniform", "lognormal",
     "truncnormal", "1", "-1", "0", "1e308", "nan", "inf", " rpm", " mm", " deg", "3_00",
     "\u00b5m", " ", "", "x", "0.5", "1e-320"]
)  # fmt: skip


@_fuzz(150)
@given(st.one_of(st.lists(_TOKENS, max_size=12).map("".join), st.text(max_size=30)))
def test_free_text_gives_a_distribution_or_one_input_error(text):
    for parse in (parse_distribution, parse_input_distribution):
        try:
            name, d = parse(text)
        except InputError:
            continue
        assert isinstance(d, Distribution)
        assert all(math.isfinite(x) for x in d.params)


# --------------------------------------------------------------------------- data files

#: Documented unit of each optional column's bare header, and its SI factor, by hand.
BARE_FACTOR = {
    "theta0": 1.0,
    "hole_radius": 1e-3,
    "density": 1.0,
    "ball_mass": 1e-3,
    "theta_measured": 1.0,
    "t_measured": 1.0,
}
#: Header unit spellings of each SI unit with their factor to SI.
HEADER_UNITS = {
    "deg": [("deg", 1.0), ("rad", 180.0 / math.pi)],
    "m": [("mm", 1e-3), ("m", 1.0), ("um", 1e-6), ("cm", 1e-2)],
    "kg/m^3": [("kg/m^3", 1.0), ("g/cm^3", 1000.0)],
    "kg": [("g", 1e-3), ("kg", 1.0)],
    "s": [("s", 1.0), ("ms", 1e-3)],
}
#: A value inside each column's range, in SI.
INSIDE = {
    "theta0": 86.0,
    "hole_radius": 4.0e-3,
    "density": 7000.0,
    "ball_mass": 8e-3,
    "theta_measured": 60.0,
    "t_measured": 0.1,
}
KNOWN = {
    "t_cr_s", "readout_hz", "spin_rate_rad_s", "omega_p_printed_rad_s", "starred", "comment",
}  # fmt: skip


def _write(tmp: Path, header: list[str], row: list[str]) -> Path:
    p = tmp / "runs.csv"
    p.write_text(",".join(header) + "\n" + ",".join(row) + "\n")
    return p


@st.composite
def _spelling(draw):
    col = draw(st.sampled_from(sorted(RUN_COLUMNS)))
    si_unit = RUN_COLUMNS[col][0]
    unit, factor = draw(st.sampled_from(HEADER_UNITS[si_unit]))
    form = draw(st.sampled_from(["bare", "underscore", "brackets", "parentheses"]))
    if form == "bare":
        header, factor = col, BARE_FACTOR[col]
    elif form == "underscore":
        header = f"{col}_{unit.replace('/', '_').replace('^', '')}"
    elif form == "brackets":
        header = f"{col} [{unit}]"
    else:
        header = f"{col} ({unit})"
    return col, header, factor


@_fuzz(200)
@given(_spelling())
def test_every_documented_spelling_is_read_in_its_unit(tmp_path_factory, spelling):
    col, header, factor = spelling
    tmp = tmp_path_factory.mktemp("spell")
    value = INSIDE[col] / factor
    cols, row = ["spin_rate_rad_s", "t_cr_s", header], ["300", "0.3", repr(value)]
    if col in ("theta_measured", "t_measured"):  # they come together
        other = "t_measured_s" if col == "theta_measured" else "theta_measured_deg"
        cols.append(other)
        row.append(repr(INSIDE[other.rsplit("_", 1)[0]]))
    d = load_spin_rig_csv(_write(tmp, cols, row))
    key = {"theta0": "theta0_deg", "theta_measured": "theta_measured_deg"}.get(col, col)
    assert d.settings[key][0] == pytest.approx(INSIDE[col], rel=1e-12)


def _mutate(draw, name: str) -> str:
    how = draw(st.sampled_from(["upper", "drop", "swap", "insert", "space", "hyphen"]))
    i = draw(st.integers(0, len(name) - 1))
    if how == "upper":
        return name.upper()
    if how == "drop":
        return name[:i] + name[i + 1 :]
    if how == "swap" and i + 1 < len(name):
        return name[:i] + name[i + 1] + name[i] + name[i + 2 :]
    if how == "insert":
        return name[:i] + draw(st.sampled_from("xq9")) + name[i:]
    if how == "space":
        return name.replace("_", " ")
    return name.replace("_", "-")


@_fuzz(150)
@given(st.data())
def test_misspelt_columns_are_refused_naming_the_closest(tmp_path_factory, data):
    base = data.draw(st.sampled_from(sorted(KNOWN | {f"{c}_deg" for c in ("theta0",)})))
    header = _mutate(data.draw, base).strip()
    assume(header and header not in KNOWN and "," not in header and '"' not in header)
    assume(not any(header == c or header.startswith(c) for c in RUN_COLUMNS))
    cols = ["spin_rate_rad_s", "t_cr_s", header]
    assume(len(set(cols)) == 3)
    p = _write(tmp_path_factory.mktemp("typo"), cols, ["300", "0.3", "1"])
    with pytest.raises(InputError) as exc:
        load_spin_rig_csv(p)
    msg = str(exc.value)
    if "unknown column" in msg:
        closest = re.search(r"closest known: '([^']+)'", msg)
        assert closest is not None and "allowed: t_cr_s" in msg
    else:  # a misspelt required column leaves the header without one
        assert "missing column" in msg or "need exactly one" in msg, msg


#: The number grammar of a data file, restated: ASCII digits, sign, point, exponent.
NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?", re.ASCII)


@_fuzz(300)
@given(
    st.one_of(
        st.floats(1.0, 1e5).map(repr),
        st.floats(1.0, 1e5).map(lambda x: f"{x:_.3f}"),
        st.integers(1, 10**5).map(lambda n: f"{n:_}"),
        st.text(alphabet=string.digits + "+-.eE_ xXa\u0663\uff13", min_size=1, max_size=8),
        st.sampled_from(["inf", "nan", "1e999", "0x10", "3_00", " 300", "300 "]),
    )
)
def test_cells_are_read_only_as_plain_decimals(tmp_path_factory, cell):
    assume("," not in cell and '"' not in cell and "\n" not in cell and "\r" not in cell)
    p = _write(tmp_path_factory.mktemp("num"), ["spin_rate_rad_s", "t_cr_s"], [cell, "0.3"])
    text = cell.strip()  # cells are stripped (csv padding)
    try:
        d = load_spin_rig_csv(p)
    except InputError as exc:
        assert str(exc).startswith(("spin_rate_rad_s: ", "file: ")), str(exc)
        if NUMBER.fullmatch(text):  # a plain decimal may only be out of range
            x = float(text)
            assert not (0.0 < x <= 1e6), (cell, str(exc))
        return
    assert NUMBER.fullmatch(text), cell
    assert d.spin_rate[0] == float(text)


BETA_S = math.degrees(math.asin(4.72 / 7.899))  # Eq. 6, Table 1 radii


@_fuzz(200)
@given(
    theta0=st.sampled_from([30.0, 36.0, 40.0, 60.0, 87.25, 89.9, 90.0]),
    angle=st.sampled_from([20.0, 36.0, 37.0, 60.0, 87.25, 89.95]),
    t_measured=st.sampled_from([1e-3, 0.1, 0.275, 0.276, 0.3, 5.0]),
)
def test_a_runs_columns_agree(tmp_path_factory, theta0, angle, t_measured):
    t_cr = 0.276
    p = _write(
        tmp_path_factory.mktemp("cross"),
        ["spin_rate_rad_s", "t_cr_s", "theta0_deg", "theta_measured_deg", "t_measured_s"],
        ["446", repr(t_cr), repr(theta0), repr(angle), repr(t_measured)],
    )
    can_open = BETA_S < theta0 < 90.0
    ok = can_open and BETA_S < angle < theta0 and t_measured < t_cr
    try:
        load_spin_rig_csv(p)
    except InputError as exc:
        assert not ok, str(exc)
        field = str(exc).split(":", 1)[0]
        assert field in ("theta0", "theta_measured", "t_measured"), str(exc)
        return
    assert ok
