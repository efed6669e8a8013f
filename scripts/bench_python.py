"""Benchmark: `demsweep.run_batch` of 100 small scenes against `demsweep run` of the same study.

Both run the same 100 runs (one scene, placement seeds 1..100) on 2 worker threads. For each, the
wall time, the CPU time (user + system, every thread; the command's as a child process), the
simulations' own time (the sum of the runs' `wall_time` column), and the difference per run between
the two calls: the command's per-run overhead against `run_batch` (CPU time is the fairer measure on
a machine shared with other work). Three repetitions each, medians reported; writes
results/bench/python.md (or --out).

    target/pyenv/bin/python scripts/bench_python.py [--out FILE] [--repeat N]

Needs the module installed (scripts/test.sh --python does it) and target/release/demsweep built.
"""

import argparse
import os
import pathlib
import platform
import resource
import statistics
import subprocess
import tempfile
import time

import pandas as pd

import demsweep

ROOT = pathlib.Path(__file__).resolve().parents[1]
RUNS, JOBS = 100, 2
SIZES = {
    "small (40 disks of 4 mm, until settled)": {
        "particles": {"count": 40, "radius": 0.004},
        "domain": {"width": 0.1, "height": 0.12},
        "material": {"youngs_modulus": 1e10, "restitution": 0.3},
        "integrator": {"contact_time_fraction": 0.03},
        "run": {"duration": 1.0},
    },
    "tiny (8 disks, 0.2 s simulated)": {
        "particles": {"count": 8, "radius": 0.005},
        "domain": {"width": 0.05, "height": 0.06},
        "material": {"youngs_modulus": 5e10},
        "integrator": {"time_step": 7e-6},
        "run": {"duration": 0.2, "stop_at_settle": False, "sample_interval": 2e-3},
    },
}


def cpu(who) -> float:
    usage = resource.getrusage(who)
    return usage.ru_utime + usage.ru_stime


def python_batch(scene: dict) -> dict:
    scenes = [dict(scene, placement={"seed": seed}) for seed in range(1, RUNS + 1)]
    started, cpu_started = time.perf_counter(), cpu(resource.RUSAGE_SELF)
    tables = demsweep.run_batch(scenes, jobs=JOBS)
    wall, cpu_time = time.perf_counter() - started, cpu(resource.RUSAGE_SELF) - cpu_started
    simulated = sum(t["wall_time"].sum() for t in tables)
    return {"wall": wall, "cpu": cpu_time, "simulated": simulated, "piles": pd.concat(tables)}


def command_run(scene: dict, folder: pathlib.Path) -> dict:
    study = folder / "bench.toml"
    study.write_text(demsweep.scene_study(scene, list(range(1, RUNS + 1))))
    out = folder / "out"
    command = [str(ROOT / "target" / "release" / "demsweep"), "run", str(study), "--out", str(out),
               "--jobs", str(JOBS), "--progress", "quiet", "--force"]
    started, cpu_started = time.perf_counter(), cpu(resource.RUSAGE_CHILDREN)
    subprocess.run(command, check=True, capture_output=True)
    wall, cpu_time = time.perf_counter() - started, cpu(resource.RUSAGE_CHILDREN) - cpu_started
    piles = demsweep.open(out / "scene.h5").summary
    return {"wall": wall, "cpu": cpu_time, "simulated": piles["wall_time"].sum(), "piles": piles}


def median_of(results: list, key: str) -> float:
    return statistics.median(r[key] for r in results)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default=str(ROOT / "results" / "bench" / "python.md"))
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    lines = [
        "# `demsweep.run_batch` against `demsweep run`: per-run overhead",
        "",
        f"{RUNS} runs of one scene (placement seeds 1..{RUNS}) on {JOBS} worker threads, both cores busy; "
        f"median of {args.repeat} repetitions ({platform.machine()}, {os.cpu_count()} cores, load average "
        f"{os.getloadavg()[0]:.1f} at the start: a machine shared with other builds; compare the two calls "
        "of a scene, not scenes across machines).",
        "`demsweep run` includes starting the process, checking the study, writing the HDF5 file, CSV "
        "files and the report page; `run_batch` checks the scenes and returns DataFrames, writing nothing. "
        "CPU time counts every thread (user + system); on a machine where other work takes cores, wall "
        "times and the runs' own `wall_time` (simulations) grow with it, CPU times much less.",
        "",
        "| scene | call | wall (s) | CPU (s) | simulations (s) | wall per run (ms) | CPU per run (ms) | same piles |",
        "|---|---|---|---|---|---|---|---|",
    ]
    differences = []
    for name, scene in SIZES.items():
        with tempfile.TemporaryDirectory() as folder:
            batch = [python_batch(scene) for _ in range(args.repeat)]
            cli = [command_run(scene, pathlib.Path(folder)) for _ in range(args.repeat)]
        same = all(
            batch[0]["piles"][c].tolist() == cli[0]["piles"][c].tolist()
            for c in ["status", "steps", "packing_fraction", "coordination_number"]
        )
        medians = {}
        for call, results in [("`run_batch`", batch), ("`demsweep run`", cli)]:
            wall, simulated, cpu_time = (median_of(results, k) for k in ("wall", "simulated", "cpu"))
            medians[call] = (wall, cpu_time)
            lines.append(f"| {name} | {call} | {wall:.3f} | {cpu_time:.3f} | {simulated:.3f} | "
                         f"{1000 * wall / RUNS:.2f} | {1000 * cpu_time / RUNS:.2f} | {'yes' if same else 'NO'} |")
        (batch_wall, batch_cpu), (cli_wall, cli_cpu) = medians.values()
        differences.append(f"- {name}: `demsweep run` takes {1000 * (cli_wall - batch_wall) / RUNS:+.2f} ms of wall "
                           f"time and {1000 * (cli_cpu - batch_cpu) / RUNS:+.2f} ms of CPU time per run more than "
                           "`run_batch`.")
    lines += ["", "Per-run overhead of the command against `run_batch`:", "", *differences]
    text = "\n".join(lines) + "\n"
    pathlib.Path(args.out).write_text(text)
    print(text)


if __name__ == "__main__":
    main()
