#!/usr/bin/env python3
"""Compares two demsweep output folders (or two files) value for value, leaving out what differs
from run to run by nature: columns, datasets and attributes whose name holds `wall_time`,
`cpu_time`, `runs_per_hour` or `created`, and the report page's lines that carry them. Used to
show a refactor changes no result (issue 66 item 7).

Usage: scripts/compare_outputs.py OLD NEW   (folders: every file of OLD must be in NEW)
A report page holds the runs' wall times in its verdict tables, so folders are compared without
their .html pages; compare pages as two files, made by `demsweep report` of one results file with
each build (only the time of day is left out there).
Needs h5py (the test environment's target/pyenv has it). Exit 0 when equal, 1 otherwise.
"""
import csv
import math
import os
import re
import sys

TIMED = re.compile(r"wall_time|cpu_time|runs_per_hour|created|elapsed")
# The CSV metadata's size and checksum follow the timed columns.
FOLLOWS_TIMED = re.compile(r'"(bytes|crc32)"')
# Report-page text that carries a time of day or a measured time.
TIMED_TEXT = [
    re.compile(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ"),
    re.compile(r"<dt>(computing time|wall time)</dt><dd>[^<]*</dd>"),
]
# The commit group a run went into (`summary/group`) follows the order runs finish in.
SCHEDULED = re.compile(r"(^|/)group$")


def same_number(a, b):
    return a == b or (isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b))


def compare_csv(old, new):
    with open(old, newline="") as f:
        a = list(csv.reader(f))
    with open(new, newline="") as f:
        b = list(csv.reader(f))
    if not a or not b or a[0] != b[0]:
        return [f"{new}: header differs"]
    keep = [i for i, name in enumerate(a[0]) if not TIMED.search(name)]
    if len(a) != len(b):
        return [f"{new}: {len(a)} rows against {len(b)}"]
    out = []
    for r, (x, y) in enumerate(zip(a, b)):
        for i in keep:
            if x[i] != y[i]:
                out.append(f"{new}: row {r} column {a[0][i]}: {x[i]!r} against {y[i]!r}")
    return out[:20]


def compare_h5(old, new):
    import h5py
    import numpy as np

    out = []
    with h5py.File(old, "r") as a, h5py.File(new, "r") as b:
        objects_a, objects_b = _objects(a), _objects(b)
        if sorted(objects_a) != sorted(objects_b):
            out.append(f"{new}: object names differ: {sorted(set(objects_a) ^ set(objects_b))[:10]}")
        for name, oa in objects_a.items():
            ob = objects_b.get(name)
            if ob is None:
                continue
            for key in oa.attrs:
                if not TIMED.search(key) and not _equal(oa.attrs[key], ob.attrs.get(key)):
                    out.append(f"{new}: {name} attribute {key} differs")
            if isinstance(oa, h5py.Dataset) and not TIMED.search(name) and not SCHEDULED.search(name):
                if oa.dtype != ob.dtype or not _equal(oa[()], ob[()]):
                    out.append(f"{new}: dataset {name} differs")
    return out[:20]


def _objects(file):
    """Every group and dataset by name, a run's commit group (`runs_NNNNN/`) left out of its name:
    runs are committed in the order they finish, which the thread schedule decides."""
    objects = {"/": file}
    file.visititems(lambda name, obj: objects.__setitem__(re.sub(r"^runs_\d+(?=/|$)", "runs", name), obj))
    return objects


def _equal(a, b):
    import numpy as np

    if b is None:
        return False
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype.names:
        if a.dtype.names != b.dtype.names:
            return False
        return all(TIMED.search(f) or _equal(a[f], b[f]) for f in a.dtype.names)
    if a.shape != b.shape:
        return False
    if a.dtype.kind in "fc":
        return bool(np.array_equal(a, b, equal_nan=True))
    return bool(np.array_equal(a, b))


def compare_text(old, new):
    a, b = _untimed_lines(old), _untimed_lines(new)
    return [] if a == b else [f"{new}: text differs ({len(a)} against {len(b)} lines compared)"]


def _untimed_lines(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        lines = [l for l in f if not FOLLOWS_TIMED.search(l)]
    for pattern in TIMED_TEXT:
        lines = [pattern.sub("", l) for l in lines]
    return lines


def compare(old, new):
    if not os.path.exists(new):
        return [f"{new}: missing"]
    if old.endswith(".csv"):
        return compare_csv(old, new)
    if old.endswith(".h5"):
        return compare_h5(old, new)
    return compare_text(old, new)


def main():
    old, new = sys.argv[1:3]
    pairs = [(old, new)]
    if os.path.isdir(old):
        names = [f for f in sorted(os.listdir(old)) if not f.endswith(".html")]
        pairs = [(os.path.join(old, f), os.path.join(new, f)) for f in names]
    problems = [p for a, b in pairs for p in compare(a, b)]
    for p in problems:
        print(p)
    print(f"{len(pairs)} files compared, {'equal' if not problems else 'DIFFERENT'}")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
