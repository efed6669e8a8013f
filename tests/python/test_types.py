"""The module's type information (``py.typed``, ``_native.pyi``) as an editor and mypy read it: the
stubs match the compiled module (mypy's stubtest), typed code using the API checks clean, and a
wrong argument type is caught."""

import subprocess
import sys
import textwrap

#: Code a user writes against the API (run, run_batch, open and its tables, errors, the version).
GOOD = """
import demsweep
import pandas as pd

scene: demsweep.Scene = {"particles.count": 30, "material": {"friction": 0.3}}
runs: pd.DataFrame = demsweep.run(scene, seeds=[1, 2], jobs=2)
batch: list[pd.DataFrame] = demsweep.run_batch([scene, "particles.count = 20"], seeds=3)
done = demsweep.run_study("study.toml", out="results", resume=True)
results: demsweep.Results = demsweep.open(done["results"])
history = results.history("r0001")
profile: pd.DataFrame | None = results.stress_profile("r0001")
done = demsweep.run_study("study.toml", checkpoint_every=None)
version: str = demsweep.__version__
units: dict[str, str] = demsweep.UNITS
try:
    demsweep.scene_study(scene, seeds=2)
except demsweep.StudyError as error:
    problems = error.problems
"""

#: The same calls with wrong argument types, one per line.
BAD = """
import demsweep

demsweep.run({"particles.count": 30}, seeds="three")
demsweep.run_study(42)
demsweep.open("r.h5").history(2.5)
demsweep.run_study("study.toml", checkpoint_every="10m")
"""


def mypy(tmp_path, code: str, *options: str) -> subprocess.CompletedProcess:
    script = tmp_path / "usage.py"
    script.write_text(textwrap.dedent(code))
    command = [sys.executable, "-m", "mypy", "--no-incremental", "--ignore-missing-imports", *options, str(script)]
    return subprocess.run(command, capture_output=True, text=True, cwd=tmp_path)


def test_the_stubs_match_the_compiled_module():
    checked = subprocess.run([sys.executable, "-m", "mypy.stubtest", "demsweep._native", "--ignore-missing-stub"],
                             capture_output=True, text=True)
    assert checked.returncode == 0, checked.stdout + checked.stderr


def test_typed_code_checks_clean_and_wrong_types_are_caught(tmp_path):
    good = mypy(tmp_path, GOOD, "--strict")
    assert good.returncode == 0, good.stdout + good.stderr
    bad = mypy(tmp_path, BAD)
    lines = sorted({int(line.split(":")[1]) for line in bad.stdout.splitlines() if ": error:" in line})
    assert lines == [4, 5, 6, 7], bad.stdout
