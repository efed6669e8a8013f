"""`pip install .` gives the `demsweep` command too: the wheel's console entry point, installed
beside the interpreter, runs the same command-line interface as the `demsweep` binary."""

import pathlib
import subprocess
import sys

import demsweep
from conftest import ROOT, demsweep_command

#: The console script pip installed with the module (beside this environment's python).
SCRIPT = pathlib.Path(sys.executable).parent / "demsweep"


def console(*args, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run([str(SCRIPT), *map(str, args)], capture_output=True, text=True, cwd=cwd)


def test_the_wheel_installs_a_demsweep_command_of_its_own_build():
    assert SCRIPT.exists(), f"no console script at {SCRIPT}"
    assert SCRIPT.read_text().count("demsweep._command") == 1, "the entry point of pyproject.toml"
    printed = console("--version")
    assert printed.returncode == 0, printed.stderr
    assert printed.stdout.split() == ["demsweep", demsweep.__version__]


def test_the_console_command_is_the_binarys_cli(tmp_path):
    study = ROOT / "studies" / "damping_sweep.toml"
    for args in (("check", study), ("plan", study), ("keys", "--markdown")):
        ours, binary = console(*args), demsweep_command(*args)
        assert (ours.returncode, ours.stdout, ours.stderr) == (binary.returncode, binary.stdout, binary.stderr), args
    bad = tmp_path / "bad.toml"
    bad.write_text("[scene]\nmaterial.frictoin = 0.3\n")
    refused = console("check", bad)
    assert refused.returncode == 2 and "did you mean `friction`?" in refused.stderr, refused.stderr
    unknown = console("chek", study)
    assert unknown.returncode == 2 and "check" in unknown.stderr, unknown.stderr


def test_the_console_command_runs_a_study(tmp_path):
    study = tmp_path / "tiny.toml"
    study.write_text('[scene]\nparticles.count = 10\nparticles.radius = 0.004\ndomain.width = 0.06\ndomain.height = 0.08\nrun.duration = 0.02\n'
                     '[sweep]\nreplicates = 2\n')
    ran = console("run", study, "--out", tmp_path / "out", "--progress", "quiet")
    assert ran.returncode == 0, ran.stderr
    assert len(demsweep.open(tmp_path / "out").summary) == 2
    assert not (tmp_path / "out" / "tiny.h5.lock").exists(), "no lock left behind"
