"""Configuration files and units at the edge (pint in, plain SI floats out).

The numeric core takes SI floats only. Users may write quantities with units
("7.899 mm", "115000 rpm", "87.25 deg") in TOML config files and on the
command line; they are converted here, once, and rejected with a message that
names the field when the unit is wrong or the text is not a quantity.

Config file layout (every key optional; bare numbers are in the SI unit shown)::

    case = "spin-rig"            # or "flight"
    spin_rate = "200 rad/s"      # rad/s
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

    [contact]                    # torque_model = "coulomb" only
    patch_radius = "0.279 mm"    # m (default: Hertz radius)

    [flight]
    mach = 3.0
    p1 = "0.099 MPa"             # Pa (or altitude = "1 km")
    n_contacts = 2

    [solver]
    rtol = 1e-8
    atol = 1e-10
    friction_width = 1e-7
    friction_family = "algebraic"  # or "tanh", "linear"
    method = "auto"
    formulation = "quaternion"
"""

from __future__ import annotations

import math
import tomllib
from functools import lru_cache
from pathlib import Path
from typing import Any

from .errors import InputError

__all__ = ["parse_quantity", "load_config", "CONFIG_SCHEMA"]

# section -> key -> (canonical field name, SI unit or None for plain values)
CONFIG_SCHEMA: dict[str, dict[str, tuple[str, str | None]]] = {
    "": {
        "case": ("case", None),
        "spin_rate": ("spin_rate", "rad/s"),
        "mu_s": ("mu_s", ""),
        "theta0": ("theta0_deg", "deg"),
        "torque_model": ("torque_model", None),
        "spin_mode": ("spin_mode", None),
        "t_max": ("t_max", "s"),
    },
    "ball": {
        "radius": ("ball_radius", "m"),
        "hole_radius": ("hole_radius", "m"),
        "density": ("density", "kg/m^3"),
    },
    "gap": {"width": ("gap", "m"), "viscosity": ("viscosity", "Pa*s")},
    "rig": {"weight": ("weight", "N")},
    "contact": {"patch_radius": ("patch_radius", "m")},
    "flight": {
        "mach": ("mach", ""),
        "p1": ("p1", "Pa"),
        "altitude": ("altitude_m", "m"),
        "n_contacts": ("n_contacts", None),
        "bore_radius": ("bore_radius", "m"),
    },
    "solver": {
        "rtol": ("rtol", ""),
        "atol": ("atol", ""),
        "friction_width": ("friction_width", ""),
        "friction_family": ("friction_family", None),
        "method": ("method", None),
        "formulation": ("formulation", None),
    },
}


@lru_cache(maxsize=1)
def _registry():
    import pint

    return pint.UnitRegistry()


def parse_quantity(field: str, value: Any, unit: str) -> float:
    """Convert a number or a quantity string to a float in `unit`.

    Parameters
    ----------
    field : str
        Name used in error messages.
    value : float or str
        A bare number (taken to be in `unit` already) or text such as
        ``"7.899 mm"`` or ``"115000 rpm"``.
    unit : str
        Target unit (pint syntax); ``""`` for dimensionless.

    Returns
    -------
    float
        Magnitude in `unit`.

    Raises
    ------
    InputError
        If the text is not a quantity or has incompatible dimensions.
    """
    if isinstance(value, bool):
        raise InputError(field, f"expected a number or a quantity, got {value!r}")
    if isinstance(value, int | float):
        return float(value)
    if not isinstance(value, str):
        raise InputError(field, f"expected a number or a quantity string, got {value!r}")
    text = value.strip()
    try:
        return float(text)
    except ValueError:
        pass
    import pint

    ureg = _registry()
    try:
        q = ureg.Quantity(text)
        out = q.to(unit or "dimensionless").magnitude
    except pint.DimensionalityError:
        raise InputError(
            field, f"{text!r} cannot be converted to {unit or 'a pure number'}"
        ) from None
    except Exception:  # pint raises several types for unparsable text
        raise InputError(field, f"{text!r} is not a number or a quantity with units") from None
    out = float(out)
    if not math.isfinite(out):
        raise InputError(field, f"{text!r} is not finite")
    return out


def load_config(path: str | Path) -> dict[str, Any]:
    """Read a TOML run configuration into a flat dict of SI values.

    Parameters
    ----------
    path : str or Path
        TOML file (layout in the module docstring).

    Returns
    -------
    dict
        Keys are the canonical field names of :data:`CONFIG_SCHEMA`
        (e.g. ``ball_radius`` [m], ``theta0_deg`` [deg]).

    Raises
    ------
    InputError
        Unknown sections or keys, malformed TOML, wrong units.
    FileNotFoundError
        If the file does not exist.
    """
    p = Path(path)
    try:
        raw = tomllib.loads(p.read_text())
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"config {p}", f"malformed TOML: {exc}") from None
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
            if unit is None:
                if field == "n_contacts":
                    if not isinstance(v, int) or isinstance(v, bool):
                        raise InputError(name, f"expected an integer, got {v!r}")
                elif not isinstance(v, str):
                    raise InputError(name, f"expected a string, got {v!r}")
                out[field] = v
            else:
                out[field] = parse_quantity(name, v, unit)
    return out
