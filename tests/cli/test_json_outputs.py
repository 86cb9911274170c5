"""Every ``--json`` object names the release that made it and the units of its keys."""

from __future__ import annotations

import json

import pytest

import obturator
from obturator.cli import main

CHEAP = [
    ["simulate", "--spin-rate", "300", "--no-check"],
    ["gasdyn", "normal-shock", "--mach", "3"],
    ["gasdyn", "start", "--mach", "3"],
    ["gasdyn", "choke", "--l-over-d", "8.07", "--reynolds", "5e5"],
    ["gasdyn", "atmosphere", "--altitude-m", "1000"],
    ["validate", "--list-models"],
]


@pytest.mark.parametrize("argv", CHEAP, ids=lambda a: " ".join(a[:2]))
def test_json_object_carries_the_version(argv, capsys):
    assert main([*argv, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert isinstance(out, dict) and out["obturator_version"] == obturator.__version__


def test_atmosphere_keys_carry_their_units(capsys):
    assert main(["gasdyn", "atmosphere", "--altitude-m", "0", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    # US 1976 sea level (NOAA-S/T 76-1562, Table I)
    assert d["temperature_K"] == 288.15 and d["pressure_Pa"] == 101325.0
    assert d["density_kg_m3"] == pytest.approx(1.2250, abs=1e-4)
    assert d["speed_of_sound_m_s"] == pytest.approx(340.29, abs=0.01)
    assert {"dynamic_viscosity_Pa_s", "kinematic_viscosity_m2_s"} <= set(d)


def test_list_models_json_lists_the_candidates(capsys):
    from obturator.validation.candidates import CANDIDATES

    assert main(["validate", "--list-models", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert [m["name"] for m in d["models"]] == list(CANDIDATES)
    assert d["models"][1]["parameters"] == {"mu_s": "1"}
