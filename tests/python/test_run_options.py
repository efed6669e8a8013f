"""`run_study`'s checkpoints (``checkpoint_every``, as ``--checkpoint-every``) and the pour's keys
from Python."""

import subprocess
import sys
import time

import numpy as np
import pytest

import demsweep

#: One run of 300 disks for 0.8 s: a few seconds, long enough to be killed midway.
STUDY = """name = "ckpt"
[scene]
particles.count = 300
particles.radius = 0.003
domain.width = 0.2
domain.height = 0.3
integrator.time_step = 2e-5
run.duration = 0.8
run.stop_at_settle = false
[output]
frames = false
"""


def test_a_study_killed_mid_run_resumes_from_its_checkpoint_to_the_same_bits(tmp_path, capfd):
    study = tmp_path / "ckpt.toml"
    study.write_text(STUDY)
    straight = demsweep.open(demsweep.run_study(study, out=tmp_path / "straight", checkpoint_every=None)["results"])
    out = tmp_path / "killed"
    code = f"import demsweep\ndemsweep.run_study({str(study)!r}, out={str(out)!r}, checkpoint_every=0.1)\n"
    child = subprocess.Popen([sys.executable, "-c", code], stderr=subprocess.DEVNULL)
    saved = out / "ckpt.checkpoints" / "r0000.checkpoint"
    waited = time.monotonic()
    while not saved.exists():
        assert child.poll() is None, "the run ended before its first checkpoint"
        assert time.monotonic() - waited < 120, "no checkpoint within two minutes"  # a guard against a hang
        time.sleep(0.005)
    child.kill()
    child.wait()
    assert saved.exists(), "the checkpoint of the run in progress is kept"
    capfd.readouterr()
    resumed = demsweep.open(demsweep.run_study(study, out=out, resume=True, checkpoint_every=0.1)["results"])
    assert "note: the run continues from" in capfd.readouterr().err
    assert not saved.parent.exists(), "the stored run's checkpoint is removed"
    for name, values in straight.history("r0000").items():
        assert np.array_equal(resumed.history("r0000")[name], values, equal_nan=True), name
    for name in ["x", "y", "vx", "vy", "omega"]:
        assert np.array_equal(resumed.final("r0000")[name], straight.final("r0000")[name]), name


@pytest.mark.parametrize("every", [0, -5.0, float("nan")])
def test_a_checkpoint_interval_that_is_no_positive_time_is_refused(tmp_path, every):
    study = tmp_path / "ckpt.toml"
    study.write_text(STUDY)
    with pytest.raises(ValueError, match="checkpoint_every must be > 0 seconds"):
        demsweep.run_study(study, out=tmp_path / "out", checkpoint_every=every)
    assert not (tmp_path / "out").exists(), "nothing is written"


def test_a_pour_runs_from_python_and_a_misspelt_pour_key_is_refused_by_name(tiny):
    pour = dict(tiny, placement={"kind": "pour", "pour": {"rate": 100.0, "y_min": 0.1}})
    runs = demsweep.run(pour, seeds=2)
    assert list(runs["poured_disks"]) == [30, 30] and list(runs["refused_disks"]) == [0, 0]
    assert (runs["simulated_time"] > 0.29).all(), "the 30th disk is due at 29 / 100 s"
    assert runs.attrs["units"]["poured_disks"] == ""
    dotted = demsweep.run({**tiny, "placement.kind": "pour", "placement.pour.rate": 100.0, "placement.pour.y_min": 0.1},
                          seeds=2)
    assert dotted.drop(columns=["wall_time", "cpu_time"]).equals(runs.drop(columns=["wall_time", "cpu_time"]))
    with pytest.raises(demsweep.StudyError, match=r"placement\.pour\.rat\b"):
        demsweep.run(dict(tiny, placement={"kind": "pour", "pour": {"rat": 100.0}}))
