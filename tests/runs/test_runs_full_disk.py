"""A full disk during any study: one line, finished work kept, a rerun resumes.

Every byte the resume store writes (lock, header, records, CSV) goes through
:func:`obturator.files._write`; here it writes half of the bytes of its k-th call
and then fails with ENOSPC, as a file system that fills up mid-write does, for every k
of a study's run. The NetCDF output (written by the HDF5 library) fails through its
writer. The rerun, without ``--restart``, must finish with the results of a run that
never failed (bit-identical: the stored values are the computed ones). The last test
repeats this on a real size-limited tmpfs where the machine allows mounting one.
"""

from __future__ import annotations

import errno
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import obturator.files as files
import obturator.runs.store as store
from obturator.cli import main

FAST = ["--rtol", "1e-6", "--atol", "1e-8"]

STUDIES = {
    "sweep": [
        "sweep", "--spin-rate", "300,400,500", "--mu-s", "0.5,0.6", "--chunk-size", "2",
    ],
    "montecarlo": [
        "montecarlo", "--vary", "mu_s=normal:0.5473,0.03", "--samples", "6", "--seed", "3",
        "--spin-rate", "450", "--chunk-size", "2", "--no-check-convergence",
    ],
    "envelope": [
        "envelope", "--mach", "2,3,4", "--altitude-m", "0", "--chunk-size", "1",
        "--no-convergence-check",
    ],
}  # fmt: skip
RESULT = {"sweep": "t_cr", "montecarlo": "t_cr", "envelope": "t_cr_coupled"}


def _run(study: str, out: Path) -> int:
    return main([*STUDIES[study], *FAST, "--workers", "1", "--no-progress", "--out", str(out)])


def _values(study: str, out: Path) -> np.ndarray:
    with xr.open_dataset(out) as ds:
        return np.asarray(ds[RESULT[study]].values)


def _count_writes(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    calls: list[int] = []
    real = files._write

    def counting(fd: int, data: memoryview) -> int:
        calls.append(len(data))
        return real(fd, data)

    monkeypatch.setattr(files, "_write", counting)
    return calls


def _fail_at(monkeypatch: pytest.MonkeyPatch, k: int) -> None:
    """The k-th write (from 0) writes half its bytes, then the disk is full."""
    real = files._write
    seen = [0]

    def full(fd: int, data: memoryview) -> int:
        seen[0] += 1
        if seen[0] - 1 < k:
            return real(fd, data)
        if seen[0] - 1 == k and len(data) > 1:
            real(fd, data[: len(data) // 2])
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(files, "_write", full)


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> dict[str, np.ndarray]:
    """Each study once, on a disk that does not fill up."""
    ref = {}
    for study in STUDIES:
        out = tmp_path_factory.mktemp(study) / "ref.nc"
        assert _run(study, out) == 0
        ref[study] = _values(study, out)
    return ref


@pytest.mark.parametrize("study", list(STUDIES))
def test_enospc_at_every_store_write_then_resume(
    study: str,
    reference: dict[str, np.ndarray],
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    with monkeypatch.context() as m:
        writes = _count_writes(m)
        assert _run(study, tmp_path / "count.nc") == 0
    n_writes = len(writes)
    assert n_writes >= 4  # lock, header and at least two records
    capsys.readouterr()
    for k in range(n_writes):
        out = tmp_path / f"k{k}.nc"
        with monkeypatch.context() as m:
            _fail_at(m, k)
            assert _run(study, out) == 2, k
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("obturator: error: out: cannot write")
        assert "No space left on device" in err and "free space and rerun" in err
        assert not out.with_name(out.name + ".lock").exists()  # released
        assert not list(tmp_path.glob(".*.tmp"))  # no temporary left behind
        assert _run(study, out) == 0, k  # no --restart
        assert capsys.readouterr().err.count("different study") == 0
        np.testing.assert_array_equal(_values(study, out), reference[study])
        assert not store.sidecar_path(out).exists()


@pytest.mark.parametrize("study", list(STUDIES))
def test_enospc_writing_the_netcdf_keeps_every_point(
    study: str,
    reference: dict[str, np.ndarray],
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    import obturator.sweeps as sweeps
    import obturator.sweeps.export as export

    def full(*args: object, **kwargs: object) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    out = tmp_path / "o.nc"
    with monkeypatch.context() as m:
        m.setattr(export, "write_netcdf", full)
        m.setattr(sweeps, "write_netcdf", full)
        assert _run(study, out) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "finished points are kept in" in err
    assert _run(study, out) == 0
    assert "resumed" in capsys.readouterr().out or study == "montecarlo"
    np.testing.assert_array_equal(_values(study, out), reference[study])


def _mount_tmpfs(where: Path, size_kb: int) -> bool:
    if sys.platform != "linux" or os.geteuid() != 0 or shutil.which("mount") is None:
        return False
    where.mkdir()
    done = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", f"size={size_kb}k", "tmpfs", str(where)],
        capture_output=True,
    )
    return done.returncode == 0


#: Study, arguments replaced, kB left: enough work that the records outgrow the space.
#: Size of the test's tmpfs [kB]: the outputs of the sweep below (3,000 points with their
#: routes in the store, the NetCDF and the CSV) fit in it, so only the filler fills it.
TMPFS_KB = 1024
ON_TMPFS = {
    "sweep": ({"--spin-rate": "100:700:1500"}, 40),
    "montecarlo": ({"--samples": "2000"}, 40),
    "envelope": ({}, 4),  # 3 points, 0.4 kB records: a nearly full disk
}


@pytest.mark.slow
@pytest.mark.parametrize("study", list(STUDIES))
def test_real_full_tmpfs(study: str, reference: dict[str, np.ndarray], tmp_path: Path) -> None:
    """On a 1 MB tmpfs (room for every study's outputs, routes included) with little space
    left (40 kB: where ``montecarlo`` hung and ``envelope`` later refused its own store):
    one line, no hang, no traceback, the lock released; with the space freed the same
    command, without ``--restart``, resumes and finishes with the results of a run that
    never failed."""
    disk = tmp_path / "disk"
    if not _mount_tmpfs(disk, TMPFS_KB):
        pytest.skip("cannot mount a tmpfs here (needs root on Linux)")
    try:
        changes, left_kb = ON_TMPFS[study]
        filler = disk / "filler"
        filler.write_bytes(b"\0" * ((TMPFS_KB - left_kb) * 1024))
        out = disk / "o.nc"
        argv = [*STUDIES[study], *FAST, "--workers", "2", "--no-progress", "--out", str(out)]
        for flag, value in changes.items():
            argv[argv.index(flag) + 1] = value
        cmd = [sys.executable, "-m", "obturator", *argv]
        first = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
        assert first.returncode == 2, first.stderr
        assert first.stderr.count("\n") == 1 and "No space left" in first.stderr, first.stderr
        assert not out.with_name(out.name + ".lock").exists()
        filler.unlink()
        again = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
        assert again.returncode == 0, again.stderr
        if not changes:
            np.testing.assert_array_equal(_values(study, out), reference[study])
    finally:
        subprocess.run(["umount", str(disk)], check=False)


def _validation_models(out: Path) -> str:
    """validation.json's models, without the wall-clock times."""
    import json

    def drop_times(x: object) -> object:
        if isinstance(x, dict):
            return {k: drop_times(v) for k, v in x.items() if "elapsed" not in k}
        return [drop_times(v) for v in x] if isinstance(x, list) else x

    models = json.loads((out / "validation.json").read_text())["models"]
    return json.dumps(drop_times(models), sort_keys=True)


def test_validate_enospc_at_every_write_then_resume(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """validate keeps its finished fits in validation.partial.jsonl: a full disk at any
    write (lock, header, a fit's record, validation.txt or .json) is one line, and the
    same command without --restart resumes and writes what a run that never failed
    writes."""
    data = tmp_path / "runs.csv"
    w = [150.0, 151.0, 180.0, 230.0, 231.0, 300.0, 302.0, 400.0]
    t = [0.62, 0.61, 0.52, 0.41, 0.42, 0.33, 0.33, 0.26]  # rough rig t_cr [s]
    rows = [f"{a},{b},{int(a > 200)}" for a, b in zip(w, t, strict=True)]
    data.write_text("spin_rate_rad_s,t_cr_s,starred\n" + "\n".join(rows) + "\n")

    def validate(out: Path) -> int:
        argv = ["validate", "--data", str(data), "--models", "mu", "--jobs", "1"]
        return main([*argv, "--no-profile", "--no-progress", "--out", str(out)])

    with monkeypatch.context() as m:
        writes = _count_writes(m)
        assert validate(tmp_path / "reference") == 0
    reference = _validation_models(tmp_path / "reference")
    assert len(writes) >= 6  # lock, header, fit records, validation.txt and .json
    capsys.readouterr()
    for k in range(len(writes)):
        out = tmp_path / f"k{k}"
        with monkeypatch.context() as m:
            _fail_at(m, k)
            assert validate(out) == 2, k
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("obturator: error: out: cannot write")
        assert "No space left on device" in err and "free space and rerun" in err
        assert not list(out.glob("*.lock")) and not list(out.glob(".*.tmp"))
        assert validate(out) == 0, k  # no --restart
        assert "different study" not in capsys.readouterr().err
        assert _validation_models(out) == reference
        assert not list(out.glob("*.partial.jsonl"))
