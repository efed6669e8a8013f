#!/usr/bin/env python3
"""Reads CSV files demsweep wrote with `pandas.read_csv(path)` and no options, as a new user would,
and checks them against their CSVW sidecars (`<file>.csv-metadata.json`).

Usage: check_plain_csv.py FILE.csv...

For each file: the columns pandas reads are the sidecar's `titles`, in order; every `integer` or
`double` column reads as numbers, every `boolean` one as booleans or numbers (an empty column
reads as NaN); every unit is text. Exits 1 listing every difference, 2 when pandas is missing.
"""
import json
import sys

try:
    import pandas as pd
    from pandas.api import types
except ImportError as error:  # scripts/test.sh installs it; a missing reader must fail the test
    print(f"pandas is required: {error}", file=sys.stderr)
    sys.exit(2)


def check(path, problems):
    table = pd.read_csv(path)
    with open(f"{path}-metadata.json") as file:
        meta = json.load(file)
    if meta.get("@context") != "http://www.w3.org/ns/csvw" or not path.endswith(meta.get("url", "?")):
        problems.append(f"{path}: the sidecar is not CSVW metadata of this file: {meta.get('url')}")
    columns = meta["tableSchema"]["columns"]
    titles = [c["titles"] for c in columns]
    if list(table.columns) != titles:
        problems.append(f"{path}: pandas reads the columns {list(table.columns)}, the sidecar says {titles}")
        return
    for column in columns:
        values, kind = table[column["titles"]], column["datatype"]
        numeric = types.is_numeric_dtype(values) or types.is_bool_dtype(values)
        if kind in ("integer", "double", "boolean") and not numeric:
            problems.append(f"{path}: column {column['titles']} ({kind}) reads as {values.dtype}: {list(values[:3])}")
        if kind == "integer" and values.notna().all() and not types.is_integer_dtype(values):
            problems.append(f"{path}: column {column['titles']} (integer) reads as {values.dtype}")
        if not isinstance(column.get("schema:unitText", ""), str):
            problems.append(f"{path}: column {column['titles']}: unit {column['schema:unitText']!r} is not text")
    return len(table)


def main(paths):
    problems = []
    rows = [check(path, problems) for path in paths]
    for problem in problems:
        print(problem, file=sys.stderr)
    print(f"{len(paths)} files ({rows} rows) read by pandas with no options, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
