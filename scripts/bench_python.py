"""Benchmark: `demsweep.run_batch` of 100 small scenes against `demsweep run` of the same study.

Both run the same 100 runs (one scene, placement seeds 1..100) on 2 worker threads. For each, the
wall time, the simulations' own time (the sum of the runs' `wall_time` column) and the per-run
overhead: (wall time x workers - simulation time) / runs, the core time per run spent outside the
simulations (scheduling, checking, writing, process start). Three repetitions each, medians
reported; writes results/bench/python.md (or --out).

    target/pyenv/bin/python scripts/bench_python.py [--out FILE] [--repeat N]

Needs the module installed (scripts/test.sh --python does it) and target/release/demsweep built.
"""

import argparse
import os
import pathlib
import platform
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


def overhead(wall: float, simulated: float) -> float:
    return (wall * JOBS - simulated) / RUNS


def python_batch(scene: dict) -> dict:
    scenes = [dict(scene, placement={"seed": seed}) for seed in range(1, RUNS + 1)]
    started = time.perf_counter()
    tables = demsweep.run_batch(scenes, jobs=JOBS)
    wall = time.perf_counter() - started
    simulated = sum(t["wall_time"].sum() for t in tables)
    return {"wall": wall, "simulated": simulated, "piles": pd.concat(tables)}


def command_run(scene: dict, folder: pathlib.Path) -> dict:
    study = folder / "bench.toml"
    study.write_text(demsweep.scene_study(scene, list(range(1, RUNS + 1))))
    out = folder / "out"
    command = [str(ROOT / "target" / "release" / "demsweep"), "run", str(study), "--out", str(out),
               "--jobs", str(JOBS), "--progress", "quiet", "--force"]
    started = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True)
    wall = time.perf_counter() - started
    piles = demsweep.open(out / "scene.h5").summary
    return {"wall": wall, "simulated": piles["wall_time"].sum(), "piles": piles}


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
        f"median of {args.repeat} repetitions ({platform.machine()}, {os.cpu_count()} cores, a machine "
        "shared with other builds: compare the two columns of a row, not rows across machines).",
        "Per-run overhead = (wall time x workers - the runs' own simulation time) / runs: core time per "
        "run outside the simulations. `demsweep run` includes starting the process, checking the study, "
        "writing the HDF5 file, CSV files and the report page; `run_batch` checks the scenes and returns "
        "DataFrames, writing nothing.",
        "",
        "| scene | call | wall (s) | simulations (s) | overhead per run (ms) | same piles |",
        "|---|---|---|---|---|---|",
    ]
    for name, scene in SIZES.items():
        with tempfile.TemporaryDirectory() as folder:
            batch = [python_batch(scene) for _ in range(args.repeat)]
            cli = [command_run(scene, pathlib.Path(folder)) for _ in range(args.repeat)]
        same = all(
            batch[0]["piles"][c].tolist() == cli[0]["piles"][c].tolist()
            for c in ["status", "steps", "packing_fraction", "coordination_number"]
        )
        for call, results in [("`run_batch`", batch), ("`demsweep run`", cli)]:
            wall, simulated = median_of(results, "wall"), median_of(results, "simulated")
            lines.append(f"| {name} | {call} | {wall:.3f} | {simulated:.3f} | "
                         f"{1000 * overhead(wall, simulated):.2f} | {'yes' if same else 'NO'} |")
    text = "\n".join(lines) + "\n"
    pathlib.Path(args.out).write_text(text)
    print(text)


if __name__ == "__main__":
    main()
