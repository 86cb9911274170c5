"""Outputs never replace what they must not (obturator.files).

Run as root, an atomic writer (temporary file, then rename) pointed at
``/dev/null`` used to replace the device node with a regular file. A stand-in
device node (a character device made with mknod in the test folder, the same
major/minor as /dev/null) shows that every writer now writes a device in place
and leaves it a device; FIFOs and other special files are refused before any
work. Without the right to mknod the device tests are skipped; the FIFO tests
always run.
"""

from __future__ import annotations

import contextlib
import io
import os
import stat
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from obturator.cli import main
from obturator.errors import InputError
from obturator.files import atomic_write_text, check_output_dir, check_output_path


def _run(argv: list[str]) -> tuple[int, str]:
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        rc = main(argv)
    return rc, err.getvalue()


@pytest.fixture
def device(tmp_path: Path) -> Path:
    """A character device like /dev/null, in the test folder."""
    node = tmp_path / "null"
    try:
        os.mknod(node, stat.S_IFCHR | 0o666, os.makedev(1, 3))
        node.open("wb").close()
    except (PermissionError, OSError) as exc:
        pytest.skip(f"cannot make a device node here: {exc}")
    return node


def _still_a_device(node: Path) -> None:
    assert stat.S_ISCHR(node.lstat().st_mode), f"{node} was replaced"
    beside = [p.name for p in node.parent.iterdir() if p.name.startswith(f"{node.name}.")]
    leftovers = [p.name for p in node.parent.iterdir() if p.name.endswith(".tmp")]
    assert not leftovers and not beside, (leftovers, beside)  # no null.png, null.csv


def test_atomic_text_writer_writes_a_device_in_place(device):
    atomic_write_text(device, "hello\n")
    _still_a_device(device)


def test_netcdf_writer_writes_a_device_in_place(device):
    from obturator.sweeps import write_netcdf

    write_netcdf(xr.Dataset({"x": ("i", np.arange(3.0))}), device)
    _still_a_device(device)


@pytest.mark.parametrize(
    "argv",
    [
        ["sweep", "--spin-rate", "300", "--t-max", "0.01", "--workers", "1", "--out", "{dev}"],
        [
            "sweep",
            "--spin-rate",
            "300",
            "--t-max",
            "0.01",
            "--workers",
            "1",
            "--out",
            "{tmp}/s.nc",
            "--csv",
            "{dev}",
        ],
        [
            "montecarlo",
            "--samples",
            "2",
            "--vary",
            "mu_s=uniform:0.5,0.6",
            "--t-max",
            "0.01",
            "--workers",
            "1",
            "--no-check-convergence",
            "--out",
            "{dev}",
        ],
        ["simulate", "--t-max", "0.01", "--no-check", "--csv", "{dev}", "--plot", "{dev}"],
        [
            "trajectory",
            "--t-max",
            "0.01",
            "--no-convergence-check",
            "--segment",
            "5 ms",
            "--out",
            "{dev}",
        ],
    ],  # fmt: skip
    ids=["sweep-out", "sweep-csv", "montecarlo", "simulate-csv", "trajectory-out"],
)
def test_commands_write_a_device_in_place(argv, device, tmp_path):
    argv = [a.format(dev=device, tmp=tmp_path) for a in argv]
    rc, err = _run([*argv, "--no-progress"] if argv[0] in ("sweep", "montecarlo") else argv)
    assert rc == 0, err
    _still_a_device(device)


@pytest.mark.parametrize(
    "argv",
    [
        ["sweep", "--spin-rate", "300", "--out", "{fifo}"],
        ["sweep", "--spin-rate", "300", "--out", "{tmp}/s.nc", "--csv", "{fifo}"],
        ["montecarlo", "--samples", "2", "--vary", "mu_s=uniform:0.5,0.6", "--out", "{fifo}"],
        ["simulate", "--csv", "{fifo}"],
        ["simulate", "--plot", "{tmp}/x.xyz"],
        ["trajectory", "--out", "{fifo}"],
        ["trajectory", "--figure", "{tmp}/x.xyz"],
        ["envelope", "--mach", "3", "--altitude-m", "0", "--out", "{fifo}"],
        ["envelope", "--mach", "3", "--altitude-m", "0", "--out", "."],
        ["envelope", "--mach", "3", "--altitude-m", "0", "--figure", "{tmp}/x.xyz"],
        ["calibrate", "{fifo}"],
        ["calibrate", "{tmp}/runs.csv", "--plot", "{tmp}/x.xyz"],
        ["validate", "--plot", "{tmp}/x.xyz"],
        ["sensitivity", "--figure", "{tmp}/x.xyz"],
        ["probability", "--out", "{fifo}"],
        ["optimize", "--out", "{tmp}/loop/x.nc"],
        ["reproduce", "--out", ""],
        ["reproduce", "--out", "{tmp}/runs.csv"],
        ["sweep", "--spin-rate", "300", "--out", "{tmp}/loop/x.nc"],
        ["sweep", "--spin-rate", "300", "--out", ""],
    ],
)
def test_special_and_bad_outputs_are_refused_before_any_work(argv, tmp_path):
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    os.symlink(tmp_path / "loop", tmp_path / "loop")
    (tmp_path / "runs.csv").write_text("spin_rate_rad_s,t_cr_s\n300,0.2\n", encoding="utf-8")
    argv = [a.format(fifo=fifo, tmp=tmp_path) for a in argv]
    rc, err = _run(argv)
    assert rc == 2 and err.startswith("obturator: error: ") and err.count("\n") == 1, err
    assert stat.S_ISFIFO(fifo.lstat().st_mode)


@pytest.mark.parametrize("name", ["", " ", ".", ".."])
def test_empty_and_dot_names_are_not_files(name):
    with pytest.raises(InputError, match="not a file name"):
        check_output_path("--out", name)


def test_output_folder_checks(tmp_path):
    assert check_output_dir("--out", str(tmp_path / "a" / "b")) == tmp_path / "a" / "b"
    (tmp_path / "f").write_text("x")
    with pytest.raises(InputError, match="not a folder"):
        check_output_dir("--out", str(tmp_path / "f"))
    with pytest.raises(InputError, match="empty folder name"):
        check_output_dir("--out", "")
    os.symlink(tmp_path / "loop", tmp_path / "loop")
    with pytest.raises(InputError, match="symlink loop"):
        check_output_dir("--out", str(tmp_path / "loop"))
