"""Configuration files and output paths at the edge (text in, plain SI floats out).

Users may write quantities with units ("7.899 mm", "115000 rpm", "87.25 deg")
in TOML config files; they are converted once (:func:`obturator.units.parse_quantity`)
and rejected with a message that names the field when the unit is wrong or the
text is not a quantity.

One schema serves every command that takes ``--config FILE.toml``
(command-line flags win over the file). The keys that describe a case
(:data:`CASE_FIELDS`) are the base case of every command that runs that case:
the rig file below runs unchanged with ``simulate``, ``sweep``, ``montecarlo`` and
``calibrate`` (which replaces the spin by each run's and fits mu_s), the flight
file with ``simulate``, ``trajectory``, ``envelope``, ``probability``,
``sensitivity`` and ``optimize`` (whose ``--mach`` and ``--altitude-m`` grids
replace the file's launch point). A key a command cannot honour is refused
with the key's name and the reason: ``trajectory`` refuses ``case = "spin-rig"``,
``spin_mode`` (the trajectory sets the spin), ``[flight] p1`` (the altitude sets
the pressure) and the rig's ``[friction]``; ``calibrate`` refuses the flight keys.
Every key is optional; bare numbers are in the SI unit shown; values outside a parameter's
range (:data:`obturator.params.PARAMS`) are refused as on the command line.
The file is read by :func:`obturator.files.read_text_file` (regular UTF-8
file, at most 1 MiB; too deep nesting refused). A spin-rig run, as it runs
verbatim (``obturator simulate --config rig.toml``)::

    case = "spin-rig"
    spin_rate = "200 rad/s"      # rad/s (rpm, Hz, rev/s convert with 2 pi)
    mu_s = 0.5473
    theta0 = "87.25 deg"         # deg
    torque_model = "thesis"      # or "coulomb"
    spin_mode = "constant"       # or "free", "thesis-energy"
    t_max = "10 s"

    [ball]
    radius = "7.899 mm"          # m
    hole_radius = "4.72 mm"      # m
    density = "7669.6 kg/m^3"    # kg/m^3

    [gap]
    width = "0.0508 mm"          # m
    viscosity = "1.917e-5 Pa*s"  # Pa s

    [rig]
    weight = "0.07987 N"         # N

    [solver]
    rtol = 1e-8
    atol = 1e-10
    friction_width = 1e-7
    friction_family = "algebraic"  # or "tanh", "linear"
    method = "auto"              # or "regularised", "set-valued", "radau", "rosenbrock"
    formulation = "quaternion"   # or "euler"

A flight run (``case = "flight"``) takes ``[flight]`` instead of ``[rig]``, and
the Coulomb contact model a ``[contact]`` section::

    case = "flight"
    spin_rate = "115000 rpm"
    torque_model = "coulomb"

    [flight]
    mach = 3.0
    altitude = "1 km"            # m (1976 atmosphere); or p1 = "0.099 MPa" (simulate)
    n_contacts = 2               # torque_model = "coulomb" only

    [contact]
    patch_radius = "0.1 mm"      # m (default: the Hertz radius)

The flight-trajectory commands (``trajectory``, ``envelope``, ``probability``,
``sensitivity``, ``optimize``) also read ``[projectile]`` (``mass``,
``roll_damping``, ``drag``) and ``[launch]`` (``elevation``, ``spin_rate``,
``twist``, ``segment``).

Spin-rig mechanisms beyond the thesis (see ``obturator validate``) go in
``[release]`` (``theta_dot = "0.5 rad/s"``, ``phase = "1 rad"``) and
``[friction]`` (``speed_law = "strengthening"``, ``speed_ratio = 0.3``,
``slip_speed = "0.12 m/s"``).
"""

from __future__ import annotations

import tomllib
from collections.abc import Collection
from pathlib import Path
from typing import Any

from . import vocab
from .errors import InputError
from .files import MAX_FILE_BYTES, check_output_path, read_text_file
from .params import CONFIG_SECTIONS, PARAMS, config_schema
from .units import parse_quantity

__all__ = [
    "parse_quantity",
    "load_config",
    "read_text_file",
    "check_output_path",
    "study_settings",
    "CONFIG_SCHEMA",
    "SOLVER_KEYS",
    "CASE_FIELDS",
    "MAX_FILE_BYTES",
]

#: section -> key -> (canonical field name, SI unit or None for words and whole
#: numbers), derived from :data:`obturator.params.PARAMS`, plus the projectile and
#: launch sections of the flight-trajectory commands.
CONFIG_SCHEMA: dict[str, dict[str, tuple[str, str | None]]] = {
    **config_schema(),
    "projectile": {
        "mass": ("projectile_mass", "kg"),
        "roll_damping": ("roll_damping", ""),
        "drag": ("drag", None),
    },
    "launch": {
        "elevation": ("elevation_deg", "deg"),
        "spin_rate": ("launch_spin_rate", "rad/s"),
        "twist": ("twist", "m"),
        "segment": ("segment", "s"),
    },
}

#: The allowed words of the word-valued fields.
_WORDS: dict[str, tuple[str, ...]] = {
    "case": vocab.CASE_NAMES,
    "torque_model": vocab.TORQUE_MODELS,
    "spin_mode": vocab.SPIN_MODES,
    "speed_law": vocab.SPEED_LAWS,
    "friction_family": vocab.FRICTION_FAMILIES,
    "method": vocab.METHODS,
    "formulation": vocab.FORMULATIONS,
}

#: Fields of the ``[solver]`` section (options of :class:`obturator.solve.SolverOptions`).
SOLVER_KEYS: tuple[str, ...] = tuple(field for field, _ in CONFIG_SCHEMA["solver"].values())
#: Fields that describe a case (the top level and the ball, gap, rig, contact, release,
#: friction and flight sections): every command that runs a case takes them as its
#: base case, so that one file serves ``simulate`` and the studies of that case.
CASE_FIELDS: tuple[str, ...] = tuple(
    field for s in CONFIG_SECTIONS if s != "solver" for field, _ in CONFIG_SCHEMA[s].values()
)


def study_settings(
    path: str | Path | None, command: str, allowed: tuple[str, ...]
) -> dict[str, Any]:
    """Settings of a config file for a study command, refusing keys it cannot use.

    Parameters
    ----------
    path : str or Path or None
        The ``--config`` file (None: no settings).
    command : str
        Command name for messages (``"sweep"``, ``"calibrate"``, ...).
    allowed : tuple of str
        Canonical field names the command takes besides the solver options.

    Returns
    -------
    dict
        Canonical field name -> SI value; solver options under ``"solver"``.
    """
    if path is None:
        return {}
    raw = load_config(path, command, (*allowed, *SOLVER_KEYS))
    out: dict[str, Any] = {"solver": {}}
    for key, value in raw.items():
        if key in SOLVER_KEYS:
            out["solver"][key] = value
        else:
            out[key] = value
    if not out["solver"]:
        del out["solver"]
    return out


def _parse_toml(text: str, p: Path) -> dict[str, Any]:
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"config {p}", f"malformed TOML: {exc}") from None
    except RecursionError:
        raise InputError(f"config {p}", "nested too deeply") from None


def load_config(
    path: str | Path, command: str | None = None, used: Collection[str] | None = None
) -> dict[str, Any]:
    """Read a TOML run configuration into a flat dict of SI values.

    One schema (:data:`CONFIG_SCHEMA`) serves every command that takes
    ``--config``; each command names the fields it uses, and a key of the
    schema that the command would ignore is refused with its name.

    Parameters
    ----------
    path : str or Path
        TOML file (layout in the module docstring), read by
        :func:`obturator.files.read_text_file` (size, encoding, FIFO limits).
    command : str, optional
        Command name for messages.
    used : collection of str, optional
        Canonical field names the command uses (None: every field of the
        base sections, as ``simulate``).

    Returns
    -------
    dict
        Keys are the canonical field names of :data:`CONFIG_SCHEMA`
        (e.g. ``ball_radius`` [m], ``theta0_deg`` [deg]).

    Raises
    ------
    InputError
        Unreadable file, malformed or too deeply nested TOML, unknown
        sections or keys, keys the command does not use, wrong units.
    """
    p = Path(path)
    raw = _parse_toml(read_text_file(p, "config"), p)
    base = set(CONFIG_SECTIONS)
    out: dict[str, Any] = {}
    for key, value in raw.items():
        if isinstance(value, dict):
            if key not in CONFIG_SCHEMA or key == "":
                raise InputError(
                    f"config {p}",
                    f"unknown section [{key}]; allowed: "
                    + ", ".join(f"[{s}]" for s in CONFIG_SCHEMA if s),
                )
            section, items = key, value
        else:
            section, items = "", {key: value}
        for k, v in items.items():
            name = f"{section}.{k}" if section else k
            if k not in CONFIG_SCHEMA[section]:
                raise InputError(name, "unknown key; allowed: " + ", ".join(CONFIG_SCHEMA[section]))
            field, unit = CONFIG_SCHEMA[section][k]
            if (used is None and section not in base) or (used is not None and field not in used):
                raise InputError(name, f"is not used by 'obturator {command or 'simulate'}'")
            if unit is None:
                if field == "n_contacts":
                    if not isinstance(v, int) or isinstance(v, bool):
                        raise InputError(name, f"expected an integer, got {v!r}")
                elif not isinstance(v, str) or len(v) > 256:
                    raise InputError(name, f"expected a word, got {str(v)[:40]!r}")
                elif field in _WORDS and v not in _WORDS[field]:
                    raise InputError(name, f"{v[:40]!r}; allowed: {', '.join(_WORDS[field])}")
                out[field] = v
            else:
                out[field] = _in_range(name, field, parse_quantity(name, v, unit))
    return out


def _in_range(name: str, field: str, x: float) -> float:
    """`x` if it lies in the range of parameter `field` (the flags' own ranges)."""
    par = PARAMS.get(field)
    if par is not None and par.range is not None and not par.range.contains(x):
        u = f" {par.unit}" if par.unit != "1" else ""
        raise InputError(name, f"{x:g}{u} is outside the allowed range {par.range}{u}")
    return x
