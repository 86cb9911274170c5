"""Configuration files and output paths at the edge (text in, plain SI floats out).

Users may write quantities with units ("7.899 mm", "115000 rpm", "87.25 deg")
in TOML config files; they are converted once (:func:`obturator.units.parse_quantity`)
and rejected with a message that names the field when the unit is wrong or the
text is not a quantity.

One schema serves ``simulate``, ``sweep``, ``montecarlo`` and ``calibrate``
(``--config FILE.toml``; command-line flags win over the file). Every key is
optional; bare numbers are in the SI unit shown. A spin-rig run, as it runs
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
    method = "auto"              # or "radau", "rosenbrock"
    formulation = "quaternion"   # or "euler"

A flight run (``case = "flight"``) takes ``[flight]`` instead of ``[rig]``, and
the Coulomb contact model a ``[contact]`` section::

    case = "flight"
    spin_rate = "115000 rpm"
    torque_model = "coulomb"

    [flight]
    mach = 3.0
    p1 = "0.099 MPa"             # Pa; or altitude = "1 km" (not both)
    n_contacts = 2               # torque_model = "coulomb" only

    [contact]
    patch_radius = "0.1 mm"      # m (default: the Hertz radius)

Spin-rig mechanisms beyond the thesis (see ``obturator validate``) go in
``[release]`` (``theta_dot = "0.5 rad/s"``, ``phase = "1 rad"``) and
``[friction]`` (``speed_law = "strengthening"``, ``speed_ratio = 0.3``,
``slip_speed = "0.12 m/s"``).
"""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Any

from .errors import InputError
from .params import config_schema
from .units import parse_quantity

__all__ = [
    "parse_quantity",
    "load_config",
    "read_text_file",
    "check_output_path",
    "study_settings",
    "CONFIG_SCHEMA",
    "SOLVER_KEYS",
    "MAX_FILE_BYTES",
]

#: section -> key -> (canonical field name, SI unit or None for words and whole
#: numbers), derived from :data:`obturator.params.PARAMS`.
CONFIG_SCHEMA: dict[str, dict[str, tuple[str, str | None]]] = config_schema()


#: Largest config or data file read [bytes].
MAX_FILE_BYTES = 1 << 20


def read_text_file(path: str | Path, field: str, max_bytes: int = MAX_FILE_BYTES) -> str:
    """The UTF-8 text of a regular file of at most `max_bytes`, or one clear InputError.

    Devices (``/dev/zero``), FIFOs and directories are refused before they are
    opened (reading them would block or never end); symlink loops, missing
    files, unreadable bytes and binary or Latin-1 content are reported with
    the path.
    """
    import stat

    p = Path(path)
    try:
        st = p.stat()
    except OSError as exc:
        raise InputError(field, f"cannot read {str(p)!r}: {exc.strerror or exc}") from None
    if not stat.S_ISREG(st.st_mode):
        raise InputError(field, f"{str(p)!r} is not a regular file")
    if st.st_size > max_bytes:
        raise InputError(field, f"{str(p)!r} is larger than {max_bytes} bytes")
    try:
        data = p.read_bytes()[: max_bytes + 1]
    except OSError as exc:
        raise InputError(field, f"cannot read {str(p)!r}: {exc.strerror or exc}") from None
    if b"\x00" in data:
        raise InputError(field, f"{str(p)!r} is binary, not text")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(
            field, f"{str(p)!r} is not UTF-8 text (byte {exc.start}); save it as UTF-8"
        ) from None


def check_output_path(
    field: str, path: str | None, suffixes: tuple[str, ...] | None = None
) -> Path | None:
    """Check, before any work, that `path` can be written; return it as a Path.

    Parameters
    ----------
    field : str
        Option name for messages (e.g. ``"--csv"``).
    path : str or None
        None passes through.
    suffixes : tuple of str, optional
        Allowed file suffixes without the dot (case-insensitive).
    """
    import os

    if path is None:
        return None
    if not isinstance(path, str) or not path.strip():
        raise InputError(field, "empty file name")
    p = Path(path)
    if suffixes is not None and p.suffix.lower().lstrip(".") not in suffixes:
        raise InputError(
            field, f"{path!r}: unsupported file type; allowed: .{', .'.join(sorted(suffixes))}"
        )
    parent = p.resolve().parent
    if not parent.is_dir():
        raise InputError(field, f"directory of {path!r} does not exist")
    if p.is_dir():
        raise InputError(field, f"{path!r} is a directory")
    if not os.access(parent, os.W_OK) or (p.exists() and not os.access(p, os.W_OK)):
        raise InputError(field, f"{path!r} is not writable")
    return p


#: Fields of the ``[solver]`` section (options of :class:`obturator.solve.SolverOptions`).
SOLVER_KEYS: tuple[str, ...] = tuple(field for field, _ in CONFIG_SCHEMA["solver"].values())


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
    raw = load_config(path)
    out: dict[str, Any] = {"solver": {}}
    for key, value in raw.items():
        if key in SOLVER_KEYS:
            out["solver"][key] = value
        elif key in allowed:
            out[key] = value
        else:
            raise InputError(key, f"is not used by 'obturator {command}' (see obturator.io)")
    return out


def _parse_toml(text: str, p: Path) -> dict[str, Any]:
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"config {p}", f"malformed TOML: {exc}") from None
    except RecursionError:
        raise InputError(f"config {p}", "nested too deeply") from None


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
    raw = _parse_toml(read_text_file(p, "config"), p)
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
