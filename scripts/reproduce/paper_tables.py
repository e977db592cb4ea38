#!/usr/bin/env python3
"""The CPVS and MH-family paper tables from shadowbench records, the papers' figures beside ours,
and the tables that set every lossless scheme side by side.

    /usr/bin/python3 scripts/reproduce/paper_tables.py TABLE RECORDS_DIR
        [--max-resolution 256K] [--command "how the records were made"]

TABLE is one of sintorn2014-fig9, kampe2015-table1 … kampe2015-table4, cpvs-lookup (CPVS),
scandolo2016-table1 … table3, scandolo2016-fig8, scandolo2021-table1 … table4, mh-lookup (MH
family), compare-size, compare-lookup (every scheme, no paper), parts-cost (builds whole and in parts); the Markdown goes to standard
output. Records are read as scripts/records.py reads them (files that do not count are named on
standard error; of a cell's records the newest counts, the others named), the schemes' default
parameters come from `shadowbench schemes --json` (scripts/scheme_registry.py). Columns are our
resolutions and the paper's up to --max-resolution. The papers' figures are in
paper_figures.py; the renderers are cpvs_tables.py, mh_tables.py and compare_tables.py.
"""

import argparse
import sys
from pathlib import Path

# scripts/ (records, scheme_registry, number_format), for this script and the renderers it imports
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from records import SchemaUnavailable, read_records  # noqa: E402
from scheme_registry import RegistryUnavailable, scheme_defaults  # noqa: E402

import compare_tables  # noqa: E402
import parts_tables  # noqa: E402
import cpvs_tables  # noqa: E402
import mh_tables  # noqa: E402
from cells import Cells, TableError  # noqa: E402
from table_format import K  # noqa: E402

TABLES = {
    "sintorn2014-fig9": cpvs_tables.sintorn2014_fig9,
    "kampe2015-table1": cpvs_tables.kampe2015_table1,
    "kampe2015-table2": cpvs_tables.kampe2015_table2,
    "kampe2015-table3": cpvs_tables.kampe2015_table3,
    "kampe2015-table4": cpvs_tables.kampe2015_table4,
    "cpvs-lookup": cpvs_tables.cpvs_lookup,
    "scandolo2016-table1": mh_tables.scandolo2016_table1,
    "scandolo2016-table2": mh_tables.scandolo2016_table2,
    "scandolo2016-table3": mh_tables.scandolo2016_table3,
    "scandolo2016-fig8": mh_tables.scandolo2016_fig8,
    "scandolo2021-table1": mh_tables.scandolo2021_table1,
    "calibration": mh_tables.calibration,
    "scandolo2021-table2": mh_tables.scandolo2021_table2,
    "scandolo2021-table3": mh_tables.scandolo2021_table3,
    "scandolo2021-table4": mh_tables.scandolo2021_table4,
    "mh-lookup": mh_tables.mh_lookup,
    "compare-size": compare_tables.compare_size,
    "compare-lookup": compare_tables.compare_lookup,
    "parts-cost": parts_tables.parts_cost,
}


def parse_resolution(text):
    value = int(text[:-1]) * K if text[-1:] in "kK" else int(text)
    if value < 8 or value & (value - 1):
        raise argparse.ArgumentTypeError(f"'{text}' is not a power of two such as 4K or 64K")
    return value


def render(table, records, args):
    """The Markdown of `table` (a key of TABLES) from `records` (a cells.Cells)."""
    return "\n".join(TABLES[table](records, args))


def main():
    parser = argparse.ArgumentParser(
        description="CPVS and MH-family paper tables and the comparison of every scheme, from "
        "shadowbench records.")
    parser.add_argument("table", choices=sorted(TABLES))
    parser.add_argument("records", type=Path, help="folder of JSON records")
    parser.add_argument("--max-resolution", type=parse_resolution, default=256 * K,
                        help="largest resolution shown (default 256K)")
    parser.add_argument("--command", help="the command that made the records, for the table")
    args = parser.parse_args()
    try:
        defaults = scheme_defaults()
        files = read_records(args.records, "paper_tables.py")
        records = Cells(files, defaults, args.records, "paper_tables.py")
        if not records.all:
            sys.exit(f"paper_tables.py: no complete shadowbench records under '{args.records}'")
        print(render(args.table, records, args), end="")
    except (RegistryUnavailable, SchemaUnavailable, TableError) as error:
        sys.exit(f"paper_tables.py: {error}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
