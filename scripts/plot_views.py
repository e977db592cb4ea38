#!/usr/bin/env python3
"""Plots shadowbench view records: error rate against memory, one PNG per camera path.

    python3 scripts/plot_views.py RECORDS_DIR [--out DIR]

Reads the view records (`"format": "shadowbench-view-record"`) under RECORDS_DIR, recursively
(build records are passed over; a view record that cannot be shown is named on standard
error), and writes error-memory_<path>.png for each path: every technique a point, memory on a
log axis, the Pareto front (less error and less memory) marked in red. Prints each PNG's path.
Of several records of one path and technique the newest ("created") counts.
"""

import argparse
import sys
from pathlib import Path

from views import group_by_path, plot_error_memory, read_view_records

PROGRAM = "plot_views.py"


def import_pyplot(program):
    """matplotlib's pyplot on the Agg backend (files only, no display), or exit naming the
    package."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.exit(f"{program}: matplotlib is needed by {sys.executable} (Debian's "
                 "python3-matplotlib serves /usr/bin/python3)")
    return plt


def main():
    parser = argparse.ArgumentParser(description="Plot error against memory per camera path "
                                                 "from shadowbench view records.")
    parser.add_argument("records", type=Path, help="folder of JSON records (searched recursively)")
    parser.add_argument("--out", type=Path, help="folder for the PNGs (default: RECORDS/plots)")
    args = parser.parse_args()
    if not args.records.is_dir():
        sys.exit(f"{PROGRAM}: '{args.records}' is not a folder of records")
    groups = group_by_path(read_view_records(args.records, PROGRAM), PROGRAM)
    if not groups:
        sys.exit(f"{PROGRAM}: no view records (\"format\": \"shadowbench-view-record\") under "
                 f"'{args.records}'")
    plt = import_pyplot(PROGRAM)
    out_dir = args.out or args.records / "plots"
    out_dir.mkdir(parents=True, exist_ok=True)
    for name, entries in sorted(groups.items()):
        path, _ = plot_error_memory(plt, name, [record for record, _ in entries], out_dir)
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
