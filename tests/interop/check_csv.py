#!/usr/bin/env python3
"""Reads a `demsweep export --format csv` folder with `pandas.read_csv` as docs/results.md says
(no options for the values, the CSVW sidecar `<file>.csv-metadata.json` for the units) and compares
it with the results file read by h5py.

Usage: check_csv.py EXPORT_DIR RESULTS.h5 RUN_GROUP RUN_ID

For the run's final state: the disks' and the contacts' files open as tables whose columns and units
are the ones the JSON file beside them describes (each with a unit and a description), one row per disk and
per contact, every value equal to the results file's. Exits 1 listing every difference, 2 when pandas
or h5py is missing.
"""
import json
import sys

try:
    import h5py
    import numpy as np
    import pandas as pd
except ImportError as error:  # scripts/test.sh installs them; a missing reader must fail the test
    print(f"pandas and h5py are required: {error}", file=sys.stderr)
    sys.exit(2)


def compare(table, stored, names, what, problems):
    if len(table) != len(stored):
        problems.append(f"{what}: {len(table)} rows, expected {len(stored)}")
        return
    for name in names:
        if name not in table.columns:
            problems.append(f"{what}: no column {name!r} (columns: {list(table.columns)})")
        elif not np.array_equal(table[name].to_numpy(), stored[name]):
            problems.append(f"{what}: column {name} differs from the results file")


def main(folder, h5_path, group_path, run_id):
    problems = []
    with open(f"{folder}/{run_id}_final.json") as file:
        sidecar = json.load(file)
    for part in ("disks", "contacts"):
        columns = sidecar[part]["columns"]
        if not all({"name", "unit", "description"} <= set(c) for c in columns):
            problems.append(f"{part}: the JSON file's columns lack a unit or a description: {columns}")
    paths = {part: f"{folder}/{sidecar[part]['file']}" for part in ("disks", "contacts")}
    disks, contacts = (pd.read_csv(paths[part]) for part in ("disks", "contacts"))
    for table, part in ((disks, "disks"), (contacts, "contacts")):
        expected = [c["name"] for c in sidecar[part]["columns"]]
        if list(table.columns) != expected:
            problems.append(f"{part}: pandas reads the columns {list(table.columns)}, the JSON file says {expected}")
        with open(f"{paths[part]}-metadata.json") as file:
            csvw = json.load(file)["tableSchema"]["columns"]
        units = {c["titles"]: c.get("schema:unitText", "") for c in csvw}
        expected_units = {c["name"]: c["unit"] for c in sidecar[part]["columns"]}
        if units != expected_units:
            problems.append(f"{part}: the CSVW sidecar says {units}, the JSON file says {expected_units}")
        if len(table) != sidecar[part]["rows"]:
            problems.append(f"{part}: {len(table)} rows, the JSON file says {sidecar[part]['rows']}")
    with h5py.File(h5_path, "r") as f:
        run = f[group_path]
        final, network = run["final"][()], run["final_contacts"][()]
        if sidecar["time"] != float(run["final"].attrs["time"]):
            problems.append(f"time {sidecar['time']}, the results file says {run['final'].attrs['time']}")
    compare(disks, final, ["x", "y", "r", "vx", "vy", "omega", "angle", "contact_force"], "disks", problems)
    compare(contacts, network, ["first", "second", "tangential_spring", "law_state"], "contacts", problems)
    for problem in problems:
        print(problem, file=sys.stderr)
    print(f"{folder}: {run_id}: {len(disks)} disks and {len(contacts)} contacts read by pandas, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:5]))
