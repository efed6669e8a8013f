"""`Results.stress_profile(run)`: the settled pile's stress per height band, as the command prints it."""

import io

import numpy as np
import pandas as pd
import pytest

import demsweep
from conftest import demsweep_command, dotted_toml

#: A narrow column of 40 disks with rough side walls (they carry part of the weight).
COLUMN = {
    "particles": {"count": 40, "radius": 0.005},
    "domain": {"width": 0.05, "height": 0.3},
    "material": {"youngs_modulus": 5e9, "restitution": 0.3, "friction": 0.5},
    "wall_material": {"friction": 0.5},
    "run": {"duration": 1.5},
}


def column_study(tmp_path, histories: bool):
    study = tmp_path / "column.toml"
    output = f"[output]\nframes = false\nhistories = {str(histories).lower()}\n"
    study.write_text('name = "column"\n[scene]\n' + dotted_toml(COLUMN) + output)
    done = demsweep.run_study(study, out=tmp_path / "out", jobs=1)
    assert done["exit_code"] == 0
    return done["results"]


def test_the_stress_profile_is_the_commands_per_band_table_with_units(tmp_path):
    results_path = column_study(tmp_path, histories=True)
    results = demsweep.open(results_path)
    profile = results.stress_profile("r0000")
    printed = demsweep_command("history", results_path, "r0000", "--stress-profile")
    assert printed.returncode == 0, printed.stderr
    command = pd.read_csv(io.StringIO(printed.stdout))
    assert list(profile.columns) == list(command.columns)
    assert len(profile) == len(command) > 1
    for column in command.columns:
        assert np.array_equal(profile[column], command[column]), column
    assert profile.equals(results.stress_profile(0)), "a run by its id or its index"
    # From the floor up to the pile's top, band after band; compressive, deepest at the floor.
    assert profile["bottom"].iloc[0] == 0.0
    assert np.array_equal(profile["bottom"].iloc[1:], profile["top"].iloc[:-1])
    assert profile["top"].iloc[-1] == pytest.approx(results.summary["pile_height"][0], rel=1e-12)
    assert profile["stress_yy"].iloc[0] > profile["stress_yy"].iloc[-1]
    pressure = (profile["stress_xx"] + profile["stress_yy"]) / 2
    assert np.allclose(profile["stress_pressure"], pressure, rtol=1e-12, atol=0)
    units = profile.attrs["units"]
    assert (units["bottom"], units["stress_deviatoric"], units["wall_shear_stress"]) == ("m", "Pa", "Pa")
    assert all(demsweep.UNITS[c] == units[c] for c in profile.columns), "UNITS knows every column"


def test_a_run_without_histories_has_no_stress_profile(tmp_path):
    results = demsweep.open(column_study(tmp_path, histories=False))
    assert results.stress_profile("r0000") is None
    with pytest.raises(demsweep.ResultsError, match="no run `r0009`"):
        results.stress_profile("r0009")
