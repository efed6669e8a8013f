"""docs/python.md's Python snippets, run in order in one namespace (as a reader pastes them into a
notebook), in a fresh folder; and examples/calibrate.py, whose calibration must reproduce its target."""

import json
import os
import re
import subprocess
import sys

from conftest import ROOT

GUIDE = ROOT / "docs" / "python.md"


def snippets(text: str) -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)


def test_every_python_snippet_of_the_guide_runs(tmp_path, monkeypatch, capsys):
    code = snippets(GUIDE.read_text())
    assert len(code) >= 6, "the guide's Python snippets were not found"
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__guide__"}
    for k, snippet in enumerate(code):
        exec(compile(snippet, f"{GUIDE}:snippet {k + 1}", "exec"), namespace)
    printed = capsys.readouterr().out
    assert "scene.material.frction" in printed and "scene.particles.count" in printed, printed
    assert "4 runs into" in printed and "4 already done, 0 run now" in printed, printed
    assert (tmp_path / "results" / "friction" / "friction.h5").exists()


def test_the_calibration_example_reproduces_its_target_pile(tmp_path):
    out = tmp_path / "calibration.json"
    ran = subprocess.run([sys.executable, str(ROOT / "examples" / "calibrate.py"), "--json", str(out)],
                         capture_output=True, text=True, env=dict(os.environ))
    assert ran.returncode == 0, ran.stderr
    result = json.loads(out.read_text())
    for metric, target in result["target"].items():
        found = result["calibrated_pile"][metric]["mean"]
        assert abs(found - target["mean"]) < 0.03 * target["mean"], (metric, found, target)
    assert result["misfit"] < 1e-3, result
    assert 0.05 <= result["calibrated"]["restitution"] <= 0.95 and 0.0 <= result["calibrated"]["friction"] <= 1.0
    assert "calibrated: restitution" in ran.stdout
