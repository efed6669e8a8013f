#!/usr/bin/env python3
"""Checks a demsweep results file with h5py (libhdf5) against a JSON description of what was written.

Usage: check_h5.py RESULTS.h5 EXPECTED.json

EXPECTED.json: {"groups": {path: {attr: value}}, "datasets": {path: {"attrs": {...}, "fields": [[name, [..]], ..]}
or {"attrs": {...}, "values": [..]}}}. Every group, dataset and attribute in the file must be listed and
equal (floats exactly; null means NaN, {"$float": "inf"} an infinity; {"$regex": ...} matches a string, {"$range": [lo, hi]} a number;
{"$json": ...} a string holding that JSON, null there being null or NaN). The batch groups holding run groups
(`/runs_00000`, `/runs_00001`, …: which one depends on when a run was committed) are listed as `/runs_*`.
Every non-empty dataset must carry a Fletcher-32 checksum, and frames must be arrays
over time in time order. Exits 1 listing every difference, 2 when h5py cannot be imported.
"""
import json
import math
import re
import sys

try:
    import h5py
    import numpy as np
except ImportError as error:  # CI installs h5py; a missing reader must fail the test, not skip it
    print(f"h5py is required: {error}", file=sys.stderr)
    sys.exit(2)


def plain(value):
    """numpy / bytes values as plain Python values."""
    if isinstance(value, bytes):
        return value.decode("utf-8")
    if isinstance(value, np.ndarray):
        return [plain(v) for v in value.tolist()]
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, np.generic):
        return plain(value.item())
    return value


def equal(found, expected):
    if isinstance(expected, dict) and "$json" in expected:
        try:
            return isinstance(found, str) and equal(json.loads(found), expected["$json"])
        except ValueError:
            return False
    if isinstance(expected, dict) and "$float" in expected:
        return isinstance(found, float) and found == float(expected["$float"])
    if isinstance(expected, dict) and "$regex" in expected:
        return isinstance(found, str) and re.fullmatch(expected["$regex"], found) is not None
    if isinstance(expected, dict) and "$range" in expected:
        low, high = expected["$range"]
        return isinstance(found, (int, float)) and low <= found <= high
    if expected is None:
        return found is None or (isinstance(found, float) and math.isnan(found))
    if isinstance(expected, dict):
        return isinstance(found, dict) and found.keys() == expected.keys() and all(equal(found[k], expected[k]) for k in expected)
    if isinstance(expected, list):
        return isinstance(found, list) and len(found) == len(expected) and all(map(equal, found, expected))
    if isinstance(expected, bool):
        return found == int(expected)
    if isinstance(expected, float) or isinstance(found, float):
        return isinstance(found, (int, float)) and float(found) == float(expected)
    return found == expected


def check_attrs(path, attrs, expected, problems):
    found = {name: plain(attrs[name]) for name in attrs.keys()}
    for name in sorted(set(found) ^ set(expected)):
        where = "unexpected in the file" if name in found else "missing from the file"
        problems.append(f"{path}: attribute {name} {where}")
    for name in sorted(set(found) & set(expected)):
        if not equal(found[name], expected[name]):
            problems.append(f"{path}: attribute {name} = {found[name]!r}, expected {expected[name]!r}")


def main(h5_path, json_path):
    with open(json_path) as f:
        expected = json.load(f)
    problems = []
    with h5py.File(h5_path, "r") as f:
        groups, datasets = {"/": f}, {}
        batch = lambda name: re.sub(r"^runs_\d+", "runs_*", name)
        f.visititems(lambda name, obj: (groups if isinstance(obj, h5py.Group) else datasets).__setitem__("/" + batch(name), obj))
        for kind, found, wanted in (("group", groups, expected["groups"]), ("dataset", datasets, expected["datasets"])):
            for path in sorted(set(found) ^ set(wanted)):
                problems.append(f"{kind} {path} {'unexpected in the file' if path in found else 'missing from the file'}")
        for path in sorted(set(groups) & set(expected["groups"])):
            check_attrs(path, groups[path].attrs, expected["groups"][path], problems)
        for path, group in groups.items():  # frames are arrays over time, in time order
            if path.endswith("/frames"):
                times = list(group["time"][()])
                if times != sorted(times) or any(group[name].shape[:1] != (len(times),) for name in group if name != "contacts"):
                    problems.append(f"{path}: frames not in time order, or arrays not (time, ...): {times}")
        for path, ds in datasets.items():  # stored data carries checksums that libhdf5 verifies
            if ds.size and not ds.fletcher32:
                problems.append(f"{path}: no Fletcher-32 checksum")
        for path in sorted(set(datasets) & set(expected["datasets"])):
            spec, ds = expected["datasets"][path], datasets[path]
            check_attrs(path, ds.attrs, spec["attrs"], problems)
            data = ds[()]
            if "fields" in spec:
                names, wanted = list(ds.dtype.names or []), [name for name, _ in spec["fields"]]
                if names != wanted:
                    problems.append(f"{path}: fields {names}, expected {wanted}")
                    continue
                for name, values in spec["fields"]:
                    if not equal(plain(data[name]), values):
                        problems.append(f"{path}: field {name} differs")
            elif not equal(plain(data), spec["values"]):
                problems.append(f"{path}: values {plain(data)!r}, expected {spec['values']!r}")
    for problem in problems:
        print(problem, file=sys.stderr)
    checked = len(expected["groups"]) + len(expected["datasets"])
    print(f"{h5_path}: {checked} objects checked, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
