#!/usr/bin/env python3
"""Issue 64's cases run against one demsweep binary, each several ways, and their outcomes counted.

    python3 scripts/hostile_counts.py BINARY [ITEM ...]

Each case sets up a scratch folder (a tiny study, its results, a user's own files), runs commands
and judges the outcome:
  right     the command did what it should: kept the user's file and refused clearly, ran correctly
  wrong     exit 0 (or an error) where the results or the message misstate what happened
  replaced  a file the user made was changed or removed
  panic     exit 101
  slow      a signal not answered within 1 s, or a command past the 60 s limit
Items are issue 64's numbers (1-14); with none given, every case runs.
"""
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

BIN = str(Path(sys.argv[1]).resolve())
ONLY = {int(a) for a in sys.argv[2:]}
ROOT = Path(__file__).resolve().parent.parent
TINY_STUDY = (ROOT / "tests/data/paths.toml").read_text()
TINY_TUNE = (ROOT / "tests/data/tiny_tune.toml").read_text()
CRLF_CSV = b"sample,comment\r\nA1,looks fine\r\n"
SMALL_SCENE = """[scene]
particles.count = 12
domain.width = 0.12
domain.height = 0.2
run.duration = 0.03
run.sample_interval = 2e-3
"""
LAMMPS_DATA = """LAMMPS data file from demsweep

2 atoms
1 atom types

0 0.1 xlo xhi
0 0.2 ylo yhi
-0.01 0.01 zlo zhi

Atoms # sphere

2 1 0.004 2500 0.05 0.03 0 0 0 0
1 1 0.01 2500 0.02 0.005 0
"""
COUNTS = {k: 0 for k in ("right", "wrong", "replaced", "panic", "slow")}
CASES = []


def case(item, label):
    def register(fn):
        CASES.append((item, label, fn))
        return fn

    return register


def run(cwd, *args, timeout=60):
    """Runs the binary in cwd; returns (exit status, stdout + stderr)."""
    try:
        p = subprocess.run([BIN, *args], cwd=cwd, capture_output=True, text=True, timeout=timeout)
        return p.returncode, p.stdout + p.stderr
    except subprocess.TimeoutExpired:
        return 124, "timeout"


def scratch():
    d = Path(tempfile.mkdtemp(prefix="hostile-"))
    (d / "paths.toml").write_text(TINY_STUDY)
    return d


def results(d):
    """The tiny study run into d/results; returns the results file."""
    rc, out = run(d, "run", "paths.toml", "--out", "results", "--progress", "quiet")
    assert rc == 0, out
    return "results/paths.h5"


def kept(path, content):
    return path.exists() and path.read_bytes() == content


def refused_and_kept(rc, out, path, content):
    if rc == 101:
        return "panic"
    if not kept(path, content):
        return "replaced"
    return "right" if rc != 0 else "wrong"


# 1. A user's CRLF CSV at an output path.
@case(1, "summary --csv over a user's CRLF CSV")
def _(d):
    h5 = results(d)
    (d / "mine.csv").write_bytes(CRLF_CSV)
    rc, out = run(d, "summary", h5, "--csv", "mine.csv")
    return refused_and_kept(rc, out, d / "mine.csv", CRLF_CSV)


@case(1, "compare --csv over a user's CRLF CSV")
def _(d):
    h5 = results(d)
    (d / "mine.csv").write_bytes(CRLF_CSV)
    rc, out = run(d, "compare", h5, "--reference", "r0000", "--csv", "mine.csv")
    return refused_and_kept(rc, out, d / "mine.csv", CRLF_CSV)


@case(1, "a fresh run over a user's CRLF <name>_summary.csv")
def _(d):
    (d / "out").mkdir()
    (d / "out/paths_summary.csv").write_bytes(CRLF_CSV)
    rc, out = run(d, "run", "paths.toml", "--out", "out", "--progress", "quiet")
    return refused_and_kept(rc, out, d / "out/paths_summary.csv", CRLF_CSV)


def tune_over(d, name):
    """tune tiny_tune.toml into out/ where out/NAME is a user's file; the user's file is kept?"""
    (d / "tiny_tune.toml").write_text(TINY_TUNE)
    (d / "out").mkdir()
    content = CRLF_CSV if name.endswith(".csv") else b"# mine\nx = 1\r\n"
    (d / "out" / name).write_bytes(content)
    rc, out = run(d, "tune", "tiny_tune.toml", "--out", "out", "--quiet", timeout=300)
    return refused_and_kept(rc, out, d / "out" / name, content)


@case(1, "tune over a user's CRLF _candidates.csv")
def _(d):
    return tune_over(d, "tiny_tune_candidates.csv")


# 2. tune's other outputs.
for suffix in ("_best.toml", "_scene_change.toml", "_recommendation.txt", "_tune.json"):
    case(2, f"tune over a user's {suffix}")(lambda d, s=suffix: tune_over(d, "tiny_tune" + s))


# 3. Ownership that a user's file cannot have by accident.
@case(3, "summary --csv over a user's CSV beside an old demsweep sidecar")
def _(d):
    h5 = results(d)
    shutil.copy(d / "results/paths_summary.csv-metadata.json", d / "mine.csv-metadata.json")
    (d / "mine.csv").write_bytes(b"a,b\n1,2\n")
    rc, out = run(d, "summary", h5, "--csv", "mine.csv")
    return refused_and_kept(rc, out, d / "mine.csv", b"a,b\n1,2\n")


@case(3, "summary --csv beside a user's own X.csv-metadata.json")
def _(d):
    h5 = results(d)
    mine = b'{"my": "notes"}\n'
    (d / "X.csv-metadata.json").write_bytes(mine)
    rc, out = run(d, "summary", h5, "--csv", "X.csv")
    return refused_and_kept(rc, out, d / "X.csv-metadata.json", mine)


@case(3, "report --out over a user's page quoting the generator tag")
def _(d):
    h5 = results(d)
    rc, _ = run(d, "report", h5, "--out", "theirs.html")
    tag = re.search(r'<meta name="generator"[^>]*>', (d / "theirs.html").read_text()).group(0)
    mine = f"<html><body><p>demsweep writes {tag} in its pages</p></body></html>\n".encode()
    (d / "notes.html").write_bytes(mine)
    rc, out = run(d, "report", h5, "--out", "notes.html")
    return refused_and_kept(rc, out, d / "notes.html", mine)


@case(3, "run --resume over a user's CSV beside the old sidecar")
def _(d):
    results(d)
    mine = b"a,b\n1,2\n"
    (d / "results/paths_summary.csv").write_bytes(mine)
    rc, out = run(d, "run", "paths.toml", "--out", "results", "--resume", "--progress", "quiet")
    return refused_and_kept(rc, out, d / "results/paths_summary.csv", mine)


# 4. A resume recognises its own interrupted outputs.
@case(4, "run --resume with the summary CSV's sidecar missing")
def _(d):
    results(d)
    (d / "results/paths_summary.csv-metadata.json").unlink()
    rc, out = run(d, "run", "paths.toml", "--out", "results", "--resume", "--progress", "quiet")
    partial = list((d / "results").glob("*.partial"))
    if rc == 101:
        return "panic"
    return "right" if rc == 0 and not partial and "--force" not in out else "wrong"


# 5. A stage that changes nothing.
POUR = """name = "noop"
[scene]
particles.count = 60
particles.radius = 0.004
domain.width = 0.12
domain.height = 0.3
run.duration = 1.2
run.sample_interval = 2e-3
damping.local = 0.0
[sweep]
replicates = 2
"""
NOOP_STAGE = '[[scene.stages]]\nname = "fill"\nuntil.time = 0.3003\ndamping.local = 0.0\n'


def summary_columns(d, out_dir, names):
    text = next((d / out_dir).glob("*_summary.csv")).read_text().splitlines()
    header = text[0].split(",")
    return [[row.split(",")[header.index(n)] for n in names] for row in text[1:]]


@case(5, "a no-op stage's settle times and packing")
def _(d):
    (d / "a.toml").write_text(POUR)
    (d / "b.toml").write_text(POUR.replace("[sweep]", NOOP_STAGE + "[sweep]"))
    for study, out in (("a.toml", "a"), ("b.toml", "b")):
        rc, text = run(d, "run", study, "--out", out, "--progress", "quiet", timeout=120)
        if rc == 101:
            return "panic"
    names = ["settle_time", "packing_fraction_interior"]
    return "right" if summary_columns(d, "a", names) == summary_columns(d, "b", names) else "wrong"


# 6. Radius keys with a placement file without radii.
@case(6, "x,y placement file + size_distribution / radius_max / radii")
def _(d):
    (d / "xy.csv").write_text("x,y\n0.02,0.02\n0.06,0.02\n0.1,0.02\n")
    base = SMALL_SCENE.replace("particles.count = 12", "particles.count = 3")
    base += 'placement.kind = "file"\nplacement.file = "xy.csv"\n'
    outcomes = []
    for extra in (
        '[scene.particles.size_distribution]\nkind = "uniform"\nmin = 0.002\nmax = 0.004\n',
        "particles.radius = 0.002\nparticles.radius_max = 0.004\n",
        "particles.radii = [0.002, 0.004]\n",
    ):
        (d / "f.toml").write_text(base + extra)
        rc, out = run(d, "check", "f.toml")
        outcomes.append("panic" if rc == 101 else "right" if rc != 0 and "placement.file" in out else "wrong")
    return outcomes


# 7. A stage's own time step.
STEP_STAGE = SMALL_SCENE + '[[scene.stages]]\nname = "fill"\nuntil.time = 0.01\nintegrator.time_step = 0.01\n'


@case(7, "a stage step of 0.01 s: check --strict and run --strict")
def _(d):
    (d / "s.toml").write_text(STEP_STAGE)
    rc1, _ = run(d, "check", "s.toml", "--strict")
    rc2, _ = run(d, "run", "s.toml", "--out", "o", "--strict", "--progress", "quiet")
    return ["panic" if rc == 101 else "right" if rc != 0 else "wrong" for rc in (rc1, rc2)]


# 8. Replicates of a seed-independent placement.
@case(8, "replicates of a monodisperse lattice and of a placement file")
def _(d):
    (d / "xy.csv").write_text("x,y\n0.02,0.02\n0.06,0.02\n0.1,0.02\n")
    lattice = SMALL_SCENE + 'placement.kind = "lattice"\n[sweep]\nreplicates = 3\n'
    placed = SMALL_SCENE.replace("count = 12", "count = 3") + 'placement.kind = "file"\nplacement.file = "xy.csv"\n[sweep]\nreplicates = 3\n'
    outcomes = []
    for text in (lattice, placed):
        (d / "r.toml").write_text(text)
        rc, out = run(d, "check", "r.toml")
        outcomes.append("panic" if rc == 101 else "right" if "warning" in out and "identical" in out else "wrong")
    return outcomes


# 9. merge's CSV sidecars.
@case(9, "merge: sidecars under the final name, no stray files")
def _(d):
    for k in (1, 2):
        rc, out = run(d, "run", "paths.toml", "--out", "shards", "--shard", f"{k}/2", "--progress", "quiet")
    rc, out = run(d, "merge", "merged", "shards")
    names = sorted(p.name for p in (d / "merged").iterdir())
    ok = rc == 0 and "paths_summary.csv-metadata.json" in names and not any("merging" in n for n in names)
    return "panic" if rc == 101 else "right" if ok else "wrong"


# 10. Counts and readers.
@case(10, "fractions = [1e308, 1e308] on 16 disks: check's counts")
def _(d):
    text = SMALL_SCENE.replace("count = 12", "count = 16")
    text += '[scene.particles.size_distribution]\nkind = "discrete"\nradii = [0.003, 0.004]\nfractions = [1e308, 1e308]\n'
    (d / "f.toml").write_text(text)
    rc, out = run(d, "check", "f.toml")
    if rc == 101:
        return "panic"
    listed = sum(int(n) for n in re.findall(r"(\d+) of radius", out))
    return "right" if rc != 0 or listed == 16 else "wrong"


def lammps_check(d, data):
    (d / "pile.data").write_text(data)
    text = SMALL_SCENE.replace("count = 12", "count = 2") + 'placement.kind = "lammps"\nplacement.file = "pile.data"\n'
    (d / "l.toml").write_text(text)
    return run(d, "check", "l.toml")


@case(10, "LAMMPS: '2.5 atoms', a triclinic box, a title starting with Atoms")
def _(d):
    outcomes = []
    for data, should_refuse in (
        (LAMMPS_DATA.replace("2 atoms", "2.5 atoms"), True),
        (LAMMPS_DATA.replace("zlo zhi\n", "zlo zhi\n0.05 0 0 xy xz yz\n"), True),
        (LAMMPS_DATA.replace("LAMMPS data file from demsweep", "Atoms # atomic, by hand"), False),
    ):
        rc, out = lammps_check(d, data)
        outcomes.append("panic" if rc == 101 else "right" if (rc != 0) == should_refuse else "wrong")
    return outcomes


# 11. A stage name swept before the stage's other keys.
@case(11, "axes stages.fill.name before stages.fill.damping.local: check, plan, run")
def _(d):
    text = SMALL_SCENE + '[[scene.stages]]\nname = "fill"\nuntil.time = 0.01\ndamping.local = 0.3\n'
    text += '[sweep]\n"stages.fill.name" = ["a", "z"]\n"stages.fill.damping.local" = [0.1, 0.2]\n'
    (d / "n.toml").write_text(text)
    outcomes = []
    for args in (("check", "n.toml"), ("plan", "n.toml"), ("run", "n.toml", "--out", "o", "--progress", "quiet")):
        rc, _ = run(d, *args)
        outcomes.append("panic" if rc == 101 else "right" if rc == 0 else "wrong")
    return outcomes


# 12. SIGTERM.
def stop_time(d, text):
    """Seconds from SIGTERM (sent 4 s into the run) to the process's exit."""
    (d / "long.toml").write_text(text)
    p = subprocess.Popen([BIN, "run", "long.toml", "--out", "o", "--progress", "quiet"], cwd=d,
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(4)
    t0 = time.monotonic()
    p.send_signal(signal.SIGTERM)
    try:
        p.wait(timeout=30)
    except subprocess.TimeoutExpired:
        p.kill()
        return 99.0
    return time.monotonic() - t0


LONG = """name = "long"
[scene]
particles.count = 2000
particles.radius = 0.002
domain.width = 0.4
domain.height = 0.4
run.duration = 20
run.sample_interval = 1
"""


@case(12, "SIGTERM: 2 000 disks sampled every second; a stage at contact_time_fraction 1e-9")
def _(d):
    stage = LONG.replace("run.sample_interval = 1", "run.sample_interval = 0.01")
    stage += '[[scene.stages]]\nname = "tiny"\nuntil.time = 1\nintegrator.contact_time_fraction = 1e-9\n'
    return ["right" if stop_time(d, text) < 1.0 else "slow" for text in (LONG, stage)]


# 13. Limits and readers.
@case(13, "3 000 stages refused at check")
def _(d):
    text = SMALL_SCENE + "".join(f'[[scene.stages]]\nname = "s{k}"\nuntil.time = 1e-5\n' for k in range(3000))
    (d / "m.toml").write_text(text)
    rc, out = run(d, "check", "m.toml")
    return "panic" if rc == 101 else "right" if rc != 0 and "scene.stages" in out else "wrong"


@case(13, "NaN in an unused contact model's table refused at check")
def _(d):
    (d / "n.toml").write_text(SMALL_SCENE + "[scene.contact.linear]\nnormal_stiffness = nan\n")
    rc, out = run(d, "check", "n.toml")
    return "panic" if rc == 101 else "right" if rc != 0 and "normal_stiffness" in out else "wrong"


@case(13, "a folder at the summary's sidecar path refused before the sweep")
def _(d):
    (d / "out/paths_summary.csv-metadata.json").mkdir(parents=True)
    rc, out = run(d, "run", "paths.toml", "--out", "out", "--progress", "quiet")
    simulated = (d / "out/paths.h5").exists()
    return "panic" if rc == 101 else "right" if rc != 0 and not simulated else "wrong"


@case(13, "merging two complete studies with different axes")
def _(d):
    results(d)
    other = TINY_STUDY.replace('name = "paths"', 'name = "other"').replace("material.restitution", "material.friction")
    (d / "other.toml").write_text(other)
    run(d, "run", "other.toml", "--out", "other", "--progress", "quiet")
    rc, out = run(d, "merge", "joined", "results/paths.h5", "other/other.h5")
    return "panic" if rc == 101 else "right" if rc == 0 else "wrong"


# 14. A new user's units.
@case(14, "lengths written in mm: the hint beside the error")
def _(d):
    outcomes = []
    for extra in ("particles.radius = 7\n",
                  '[scene.particles.size_distribution]\nkind = "lognormal"\nmean = 4\nstd = 1\n'):
        (d / "u.toml").write_text(SMALL_SCENE + extra)
        rc, out = run(d, "check", "u.toml")
        outcomes.append("panic" if rc == 101 else "right" if rc != 0 and "mm" in out else "wrong")
    return outcomes


def main():
    for item, label, fn in CASES:
        if ONLY and item not in ONLY:
            continue
        d = scratch()
        try:
            outcome = fn(d)
        except Exception as e:  # a setup step the binary failed: the case did not work
            outcome = f"wrong ({type(e).__name__}: {str(e)[:80]})"
        finally:
            shutil.rmtree(d, ignore_errors=True)
        outcomes = outcome if isinstance(outcome, list) else [outcome]
        for o in outcomes:
            COUNTS[o.split(" ")[0]] += 1
        print(f"{item:>2} {label}: {', '.join(outcomes)}", flush=True)
    print("cases " + str(sum(COUNTS.values())) + ": " + ", ".join(f"{k} {v}" for k, v in COUNTS.items()))


if __name__ == "__main__":
    main()
