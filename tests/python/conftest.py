"""Shared by the Python module's tests (run by scripts/test.sh with pytest, against the installed
`demsweep` module and the `demsweep` command of the same build)."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]

#: 30 disks falling 15 cm: about 50 ms of computing per run.
TINY = {
    "particles": {"count": 30, "radius": 0.005},
    "domain": {"width": 0.1, "height": 0.15},
    "material": {"youngs_modulus": 5e10, "restitution": 0.5, "friction": 0.5},
    "integrator": {"time_step": 7e-6},
    "run": {"duration": 1.0, "sample_interval": 2e-3},
    "settle": {"hold_time": 0.03},
}


def dotted_toml(scene: dict) -> str:
    """A scene as TOML lines of dotted keys (`particles.count = 30`), as under a study's [scene]."""
    return "".join(f"{table}.{key} = {value!r}\n" for table, values in scene.items() for key, value in values.items())


@pytest.fixture
def tiny():
    return {table: dict(values) for table, values in TINY.items()}


def command_path() -> pathlib.Path:
    """The `demsweep` command of this build: $DEMSWEEP_BIN (scripts/test.sh sets it), else
    target/release/demsweep."""
    path = pathlib.Path(os.environ.get("DEMSWEEP_BIN", ROOT / "target" / "release" / "demsweep"))
    assert path.exists(), f"no demsweep command at {path}: build it (cargo build --release) or run scripts/test.sh"
    return path


def demsweep_command(*args, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run([str(command_path()), *map(str, args)], capture_output=True, text=True, cwd=cwd)
