"""The `demsweep` module against the `demsweep` command of the same build: same runs, same errors,
same files."""

import io
import json
import pathlib
import signal
import subprocess
import sys
import threading
import time
import warnings

import numpy as np
import pandas as pd
import pytest

import demsweep
from conftest import ROOT, TINY, dotted_toml, demsweep_command


def without_wall_time(frame: pd.DataFrame) -> pd.DataFrame:
    return frame.drop(columns=["wall_time", "cpu_time"])


def test_run_gives_what_the_command_gives_for_the_same_study(tiny, tmp_path):
    runs = demsweep.run(tiny, seeds=[3, 4])
    assert list(runs["placement.seed"]) == [3, 4]
    assert runs.attrs["units"]["settle_time"] == "s" and runs.attrs["units"]["pile_height"] == "m"
    study = tmp_path / "scene.toml"
    study.write_text(demsweep.scene_study(tiny, [3, 4]))
    ran = demsweep_command("run", study, "--out", tmp_path / "out", "--progress", "quiet")
    assert ran.returncode == 0, ran.stderr
    summary = tmp_path / "out" / "scene_summary.csv"
    command = pd.read_csv(summary, keep_default_na=False, na_values=[""], dtype={"message": str})
    columns = json.loads((tmp_path / "out" / "scene_summary.csv-metadata.json").read_text())["tableSchema"]["columns"]
    units = {c["titles"]: c.get("schema:unitText", "") for c in columns}
    assert {c: units[c] for c in runs.attrs["units"]} == runs.attrs["units"], "the CSV's sidecar units are the module's"
    command["message"] = command["message"].fillna("")  # an empty CSV field reads as missing
    assert list(command.columns) == list(runs.columns)
    pd.testing.assert_frame_equal(without_wall_time(runs), without_wall_time(command), check_dtype=False, check_exact=True)


def test_text_scenes_are_dict_scenes(tiny):
    text = dotted_toml(tiny)
    pd.testing.assert_frame_equal(without_wall_time(demsweep.run(text)), without_wall_time(demsweep.run(tiny)))


def test_run_batch_does_not_depend_on_jobs_and_runs_each_scene(tiny):
    scenes = [dict(tiny, material=dict(tiny["material"], friction=mu)) for mu in (0.0, 0.3, 0.6, 0.9)]
    one = demsweep.run_batch(scenes, seeds=2, jobs=1)
    two = demsweep.run_batch(scenes, seeds=2, jobs=2)
    assert len(one) == len(two) == 4
    for a, b, scene in zip(one, two, scenes):
        assert len(a) == 2
        pd.testing.assert_frame_equal(without_wall_time(a), without_wall_time(b))
        pd.testing.assert_frame_equal(without_wall_time(a), without_wall_time(demsweep.run(scene, seeds=2)))
    packing = [frame["packing_fraction"].mean() for frame in one]
    assert len(set(packing)) == 4, f"each scene's friction should change the pile: {packing}"


def check_errors(study: pathlib.Path) -> str:
    checked = demsweep_command("check", study)
    assert checked.returncode == 2, checked.stdout
    return "\n".join(checked.stderr.splitlines()[:-1])  # the last line counts the problems


def test_study_errors_carry_the_text_check_prints(tiny, tmp_path):
    bad = dict(tiny, material=dict(tiny["material"], frction=0.5), particles={"count": -3})
    with pytest.raises(demsweep.StudyError) as raised:
        demsweep.run(bad, seeds=2)
    error = raised.value
    keys = {p["key"] for p in error.problems}
    assert {"scene.material.frction", "scene.particles.count"} <= keys, error.problems
    study = tmp_path / "bad.toml"
    study.write_text(error.study_text)
    assert str(error).replace("<scene>", str(study)) == check_errors(study)


def test_errors_of_a_batch_name_the_scene(tiny):
    bad = dict(tiny, particles=dict(tiny["particles"], radius="big"))
    with pytest.raises(demsweep.StudyError) as raised:
        demsweep.run_batch([tiny, bad, tiny])
    assert {p["file"] for p in raised.value.problems} == {"<scenes[1]>"}
    assert "scene.particles.radius" in str(raised.value)


def test_toml_syntax_and_python_values_toml_cannot_hold(tiny):
    with pytest.raises(demsweep.StudyError) as raised:
        demsweep.run("[particles]\ncount = = 3\n")
    assert raised.value.problems[0]["line"] == 2 and "TOML syntax" in str(raised.value)
    with pytest.raises(demsweep.StudyError, match=r"<scene>: scene\.material\.friction: a Python complex"):
        demsweep.run(dict(tiny, material={"friction": 1j}))
    with pytest.raises(TypeError):
        demsweep.run(42)


def test_one_mistake_is_one_error(tiny):
    # 30 disks fit a 5 cm box; the default count that would stand in for the refused 30.0 does not.
    bad = dict(tiny, particles={"count": 30.0, "radius": 0.002}, domain={"width": 0.05, "height": 0.15})
    with pytest.raises(demsweep.StudyError) as raised:
        demsweep.run(bad)
    assert [p["key"] for p in raised.value.problems] == ["scene.particles.count"], raised.value.problems
    assert "expected a whole number" in str(raised.value)
    with pytest.raises(demsweep.StudyError, match=r"did you mean `friction`\?") as raised:
        demsweep.run(dict(tiny, material={"frictoin": 0.3}))
    assert len(raised.value.problems) == 1, raised.value.problems


def test_dotted_keys_in_a_dict_are_toml_dotted_keys(tiny):
    flat = {f"{table}.{key}": value for table, values in tiny.items() for key, value in values.items()}
    mixed = {table: values for table, values in tiny.items() if table != "material"}
    mixed["material"] = {"restitution": 0.5, "youngs_modulus": 5e10}
    mixed["material.friction"] = 0.5  # beside the table it goes into
    expected = without_wall_time(demsweep.run(tiny))
    for scene in (flat, mixed):
        pd.testing.assert_frame_equal(without_wall_time(demsweep.run(scene)), expected)
    with pytest.raises(demsweep.StudyError, match="given twice"):
        demsweep.run(dict(tiny, **{"material.friction": 0.2}))


def test_the_namespace_is_the_api_and_says_its_version():
    public = {name for name in dir(demsweep) if not name.startswith("_")}
    assert public == set(demsweep.__all__), public ^ set(demsweep.__all__)
    assert not {"np", "pd", "os", "json", "annotations"} & set(dir(demsweep))
    assert all(hasattr(demsweep, name) for name in demsweep.__all__)
    printed = demsweep_command("--version")
    assert printed.returncode == 0 and printed.stdout.split()[-1] == demsweep.__version__, printed.stdout


STUDY = f"""name = "tiny_sweep"
[scene]
{dotted_toml(TINY)}run.frame_times = [0.05, 0.1]
[sweep]
"material.friction" = [0.3, 0.6]
replicates = 2
"""


def test_open_reads_the_runs_of_the_summary_in_a_grown_file(tmp_path):
    """A study edited to drop a friction value keeps that run in its file, unplanned, under the id it
    had: `open` finds runs by the summary's ids, as the commands do, not the stored ones."""
    study = tmp_path / "tiny_sweep.toml"
    study.write_text(STUDY)
    out = tmp_path / "out"
    assert demsweep.run_study(study, out=out, jobs=2)["ran"] == 4
    study.write_text(STUDY.replace("[0.3, 0.6]", "[0.6]"))
    with pytest.warns(UserWarning, match="2 stored run.* no longer planned"):  # quiet, yet said
        again = demsweep.run_study(study, out=out, resume=True)
    assert (again["selected"], again["ran"]) == (2, 0)
    assert any("--drop-unplanned" in note for note in again["notes"]), again["notes"]
    results = demsweep.open(again["results"])
    assert list(results.summary["run_id"]) == ["r0000", "r0001"]
    for run in ("r0000", "r0001"):
        listed = demsweep_command("history", again["results"], run)
        assert listed.returncode == 0, listed.stderr
        command = pd.read_csv(io.StringIO(listed.stdout))
        assert np.array_equal(results.history(run)["potential"], command["potential"]), run
        assert results.scene(run)["material"]["friction"] == 0.6
    with pytest.raises(demsweep.ResultsError, match="no run `r0002`"):
        results.history("r0002")  # stored, but no longer planned


def test_run_study_and_open_read_what_the_command_reads(tmp_path):
    study = tmp_path / "tiny_sweep.toml"
    study.write_text(STUDY)
    out = tmp_path / "out"
    done = demsweep.run_study(study, out=out, jobs=2)
    assert (done["selected"], done["ran"], done["exit_code"]) == (4, 4, 0)
    assert pathlib.Path(done["report"]).exists()
    results = demsweep.open(done["results"])

    summary = results.summary
    printed = demsweep_command("summary", done["results"], "--csv", tmp_path / "s.csv")
    assert printed.returncode == 0, printed.stderr
    command = pd.read_csv(tmp_path / "s.csv", keep_default_na=False, na_values=[""])
    assert list(command.columns) == list(summary.columns), "one name per column in the CSV and the module"
    assert np.array_equal(summary["settle_time"], command["settle_time"], equal_nan=True)
    assert list(summary["material.friction"]) == [0.3, 0.3, 0.6, 0.6]
    assert len(results.points) == 2 and list(results.points["material.friction"]) == [0.3, 0.6]

    history = results.history("r0002")
    listed = demsweep_command("history", done["results"], "r0002")
    command = pd.read_csv(io.StringIO(listed.stdout))
    assert sorted(command.columns) == sorted(history), "the same series names"
    assert np.array_equal(history["t"], command["t"])
    assert np.array_equal(history["potential"], command["potential"])
    assert command["contacts"].dtype == np.int64, "numbers as numbers, with no options"
    assert (demsweep.UNITS["t"], demsweep.UNITS["potential"], demsweep.UNITS["contacts"]) == ("s", "J", "")

    final = results.final(3)
    assert final["x"].shape == (30,) and np.all(final["r"] == 0.005)
    assert final["time"] == pytest.approx(summary["simulated_time"][3])
    assert len(final["contacts"]["normal_force"]) == len(final["contacts"]["first"]) > 0
    assert [f["time"] for f in results.frames("r0001")] == pytest.approx([0.05, 0.1], abs=1e-5)
    assert results.scene("r0003")["material"]["friction"] == 0.6

    assert demsweep.open(out).path == pathlib.Path(done["results"])  # a folder, as the commands take
    with pytest.raises(demsweep.ResultsError, match="no results file"):
        demsweep.open(tmp_path)
    with pytest.raises(demsweep.ResultsError, match="no run `r0099`"):
        results.history("r0099")
    with pytest.raises(demsweep.ResultsError, match="results already exist"):
        demsweep.run_study(study, out=out)
    again = demsweep.run_study(study, out=out, resume=True)
    assert (again["already_done"], again["ran"]) == (4, 0)


def test_run_study_refuses_what_check_refuses(tmp_path):
    study = tmp_path / "broken.toml"
    study.write_text(STUDY.replace("particles.count = 30\n", "particles.count = 0\n"))
    with pytest.raises(demsweep.StudyError) as raised:
        demsweep.run_study(study, out=tmp_path / "out")
    assert str(raised.value) == check_errors(study)
    assert not (tmp_path / "out").exists()




def test_tune_does_what_the_command_does(tmp_path):
    path = tmp_path / "tiny_tune.toml"
    path.write_text((ROOT / "tests" / "data" / "tiny_tune.toml").read_text())
    done = demsweep.tune(path, out=tmp_path / "out", jobs=2)
    # The file's first line is demsweep's stamp (what it binds the file to), then the paragraph.
    note = (tmp_path / "out" / "tiny_tune_recommendation.txt").read_text()
    assert note.startswith("# written by demsweep") and done["recommendation"] == note.split("\n", 1)[1].strip()
    assert all(pathlib.Path(f).exists() for f in done["files"])
    runs = demsweep.open(done["results"]).summary
    assert len(runs) == done["ran"] and 10 <= len(runs) <= 40
    assert (done["recommended"] is None) == ("no recommendation" in done["recommendation"].lower())


def test_runs_release_the_interpreter(tiny):
    """Python threads go on while the engine runs: a loop in this thread counts while another runs."""
    slow = dict(tiny, run=dict(tiny["run"], stop_at_settle=False, duration=1.0))
    worker = threading.Thread(target=demsweep.run_batch, args=([slow] * 4,), kwargs={"jobs": 1})
    worker.start()
    turns = 0
    while worker.is_alive():
        turns += 1
        time.sleep(0.001)
    worker.join()
    assert turns > 50, f"this thread ran only {turns} times while the runs went on"


def test_ctrl_c_stops_the_runs_and_raises_keyboard_interrupt(tiny):
    endless = dict(tiny, run=dict(tiny["run"], stop_at_settle=False, duration=1e4))
    code = f"import demsweep\nprint('running', flush=True)\ndemsweep.run({endless!r}, seeds=2)\n"
    # A shell that runs the tests in the background ignores SIGINT, and a child started with SIGINT
    # ignored gets no KeyboardInterrupt: the child starts with the default action, as from a terminal.
    child = subprocess.Popen(
        [sys.executable, "-c", code],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    assert child.stdout.readline().strip() == "running"
    time.sleep(0.5)
    child.send_signal(signal.SIGINT)
    _, stderr = child.communicate(timeout=120)  # a guard against a hang, not a timing target
    assert child.returncode != 0 and "KeyboardInterrupt" in stderr, stderr


def test_the_commands_warnings_are_demsweep_warnings_a_notebook_can_make_errors(tiny, tmp_path):
    soft = dict(tiny, material=dict(tiny["material"], youngs_modulus=10.0))  # 10 Pa: "did you mean"
    study = tmp_path / "soft.toml"
    study.write_text(demsweep.scene_study(soft))
    checked = demsweep_command("check", study)
    assert checked.returncode == 0, checked.stderr
    said = {line.split("soft.toml:", 1)[1] for line in checked.stderr.splitlines() if line.startswith("warning: ")}
    assert any("youngs_modulus" in text for text in said), checked.stderr
    with pytest.warns(demsweep.DemsweepWarning) as caught:
        demsweep.run(soft)
    issued = {str(w.message).split("<scene>:", 1)[-1] for w in caught}
    assert said <= issued, f"the command's warnings {said} are not all issued: {issued}"
    assert all(issubclass(w.category, UserWarning) for w in caught)
    assert all(w.filename == __file__ for w in caught), "the warning points at the caller"
    with warnings.catch_warnings():
        warnings.simplefilter("error", demsweep.DemsweepWarning)
        with pytest.raises(demsweep.DemsweepWarning, match="Pa"):
            demsweep.run_batch([soft])


def test_runs_that_diverge_are_counted_in_a_warning(tiny):
    coarse = dict(tiny, integrator={"time_step": 1e-3}, run={"duration": 0.05})  # 100x the contact time
    with pytest.warns(demsweep.DemsweepWarning, match=r"2 of 2 runs failed \(2 diverged\)"):
        runs = demsweep.run(coarse, seeds=2)
    assert list(runs["status"]) == ["diverged", "diverged"]


def test_a_scene_with_stages_runs_its_protocol_first(tiny):
    fill = {"name": "fill", "until": {"time": 0.05}, "damping": {"local": 0.5}}
    runs = demsweep.run(dict(tiny, stages=[fill]), seeds=2)
    step = tiny["integrator"]["time_step"]
    assert list(runs["physics_start_time"]) == pytest.approx([0.05, 0.05], abs=step)
    assert (runs["settle_time"] >= 0.05).all()
    assert list(runs["stage_end_time.fill"]) == list(runs["physics_start_time"])
    assert runs.attrs["units"]["stage_end_time.fill"] == "s"
    plain = demsweep.run(tiny, seeds=2)
    assert list(plain["physics_start_time"]) == [0.0, 0.0]
    with pytest.raises(demsweep.StudyError, match="a stage needs a condition that ends it"):
        demsweep.run(dict(tiny, stages=[{"name": "fill", "damping": {"local": 0.5}}]))
