#!/usr/bin/env python3
"""Plots shadowbench build records: size and build time against resolution.

    python3 scripts/plot.py RECORDS_DIR [--out DIR] [--schemes a,b] [--param NAME=VALUE ...]
        [--defaults]

Reads the records under RECORDS_DIR as scripts/records.py reads them (*.json, recursively; each
file that is not a complete, valid record is named on standard error) and writes, for each
(scene, light index, mode), two log-log PNGs: size in bytes and build time in seconds against
resolution, one line per scheme with its parameters, with the analytic 16- and 32-bit shadow
maps dashed on the size plot. Of several records of one cell the newest ("created") counts, as
in the tables. --defaults keeps only the records built with their scheme's registry defaults
(`shadowbench schemes --json`, see scripts/scheme_registry.py).
"""

import argparse
import json
import re
import sys
from pathlib import Path

from records import (RecordFiles, SchemaUnavailable, light_index, newest_per_cell, read_records,
                     scheme_params, size_bytes, total_seconds)
from scheme_registry import RegistryUnavailable, scheme_defaults

BASELINE = "sm32"


def variant_label(record):
    """'mmh (height=3, search=1000)', as the tables name a scheme with its parameters."""
    name, params = record["scheme"]["name"], scheme_params(record)
    if not params:
        return name
    text = ", ".join(f"{key}={value if isinstance(value, str) else json.dumps(value)}"
                     for key, value in sorted(params.items()))
    return f"{name} ({text})"


def natural_key(text):
    """'search=200' before 'search=1000'."""
    return [(0, int(part), "") if part.isdigit() else (1, 0, part) for part in re.split(r"(\d+)", text)]


def variant_order(label):
    name = label.split(" (", 1)[0]
    return (name != BASELINE, name, natural_key(label))


def selected(record, schemes, params, defaults):
    """Whether --schemes, --param and --defaults keep `record`: its scheme is listed (or none
    are), each given parameter it has holds the given value, and with `defaults` ({scheme:
    {parameter: default}}, None: any parameters) its parameters are its scheme's defaults."""
    name = record["scheme"]["name"]
    if schemes is not None and name not in schemes:
        return False
    have = {key: str(value) for key, value in scheme_params(record).items()}
    if defaults is not None and have != defaults.get(name):
        return False
    return all(have[key] == value for key, value in params.items() if key in have)


def cell_of(record):
    """(scene, light, mode, variant label, resolution): a point of the plots."""
    return (record["scene"]["name"], light_index(record), record["mode"], variant_label(record),
            record["resolution"])


def describe_cell(cell):
    scene, light, mode, label, resolution = cell
    return f"{scene}, light {light}, {mode}, {label}, {resolution_label(resolution)}²"


def group_records(files, program="plot.py"):
    """{(scene, light, mode): {variant label: {resolution: record}}} of `files`
    (records.RecordFiles), the newest record per cell; each one left out is named, by
    `program`."""
    groups = {}
    newest = newest_per_cell(files, cell_of, describe_cell, program)
    for (scene, light, mode, label, resolution), record in newest.items():
        groups.setdefault((scene, light, mode), {}).setdefault(label, {})[resolution] = record
    return groups


def resolution_label(resolution):
    return f"{resolution // 1024}K" if resolution >= 1024 and resolution % 1024 == 0 else str(resolution)


def file_name_part(text):
    """Lower case [a-z0-9.-] for a file name; the exact mapping need not match the harness."""
    part = re.sub(r"[^a-z0-9.]+", "-", text.lower()).strip("-.")
    return part or "x"


def build_seconds(record):
    value = total_seconds(record)
    return value if isinstance(value, (int, float)) and value > 0 else None


def plot_group(plt, NullLocator, key, variants, out_dir):
    """Writes the size and build-time plots of one (scene, light, mode); returns their paths."""
    scene, light, mode = key
    resolutions = sorted({r for cells in variants.values() for r in cells})
    stem = f"{file_name_part(scene)}_{light}_{file_name_part(mode)}"
    written = []

    def new_axes(title, ylabel):
        figure, axes = plt.subplots(figsize=(11, 5.5))
        axes.set_xscale("log", base=2)
        axes.set_yscale("log")
        axes.set_xticks(resolutions)
        axes.set_xticklabels([resolution_label(r) for r in resolutions])
        axes.xaxis.set_minor_locator(NullLocator())  # only the resolutions measured
        axes.set_xlabel("resolution (texels per side)")
        axes.set_ylabel(ylabel)
        axes.set_title(f"{title} — {scene}, light {light}, {mode}")
        axes.grid(True, which="major", alpha=0.3)
        return figure, axes

    def save(figure, axes, name):
        # Beside the axes: with many schemes a legend inside hides lines.
        axes.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.02, 1))
        figure.tight_layout()
        path = out_dir / f"{name}_{stem}.png"
        figure.savefig(path, dpi=120)
        plt.close(figure)
        written.append(path)

    ordered = sorted(variants, key=variant_order)

    figure, axes = new_axes("Size", "size (bytes)")
    for label in ordered:
        cells = variants[label]
        xs = sorted(cells)
        axes.plot(xs, [size_bytes(cells[r]) for r in xs], marker="o", label=label)
    for bytes_per_texel in (2, 4):
        axes.plot(resolutions, [r * r * bytes_per_texel for r in resolutions], linestyle="--",
                  color="grey" if bytes_per_texel == 2 else "black", linewidth=1,
                  label=f"{8 * bytes_per_texel}-bit shadow map (analytic)")
    save(figure, axes, "size")

    timed = {label: {r: s for r, rec in variants[label].items() if (s := build_seconds(rec))}
             for label in ordered}
    if any(timed.values()):
        figure, axes = new_axes("Build time", "build time (s)")
        for label in ordered:
            if timed[label]:
                xs = sorted(timed[label])
                axes.plot(xs, [timed[label][r] for r in xs], marker="o", label=label)
        save(figure, axes, "build-time")
    return written


def main():
    parser = argparse.ArgumentParser(description="Plot size and build time against resolution "
                                                 "from shadowbench build records.")
    parser.add_argument("records", type=Path, help="folder of JSON records (searched recursively)")
    parser.add_argument("--out", type=Path, help="folder for the PNGs (default: RECORDS/plots)")
    parser.add_argument("--schemes", help="comma-separated schemes to plot (default: all)")
    parser.add_argument("--param", "-p", action="append", default=[], metavar="NAME=VALUE",
                        help="keep a record only if its scheme, where it has parameter NAME, "
                             "has VALUE (repeatable; as 'shadowbench sweep --param' selects)")
    parser.add_argument("--defaults", action="store_true",
                        help="keep only records built with their scheme's registry defaults")
    args = parser.parse_args()
    wanted_params = {}
    for text in args.param:
        name, equals, value = text.partition("=")
        if not equals or not name:
            sys.exit(f"plot.py: --param '{text}' is not NAME=VALUE")
        wanted_params[name] = value
    wanted_schemes = set(args.schemes.split(",")) if args.schemes else None

    if not args.records.is_dir():
        sys.exit(f"plot.py: '{args.records}' is not a folder of records")
    try:
        defaults = scheme_defaults() if args.defaults else None
        files = read_records(args.records, "plot.py")
    except (RegistryUnavailable, SchemaUnavailable) as error:
        sys.exit(f"plot.py: {error}")
    kept = [i for i, r in enumerate(files.records)
            if selected(r, wanted_schemes, wanted_params, defaults)]
    files = RecordFiles([files.records[i] for i in kept], [files.paths[i] for i in kept],
                        files.skipped)
    if not files.records:
        narrowed = args.schemes or args.param or args.defaults
        sys.exit(f"plot.py: no complete shadowbench records (*.json) under '{args.records}'"
                 + (" of the selected schemes and parameters" if narrowed else ""))

    # Imported here so that a missing matplotlib reports itself after the cheap checks.
    try:
        import matplotlib
        matplotlib.use("Agg")  # files only: no display needed
        import matplotlib.pyplot as plt
        from matplotlib.ticker import NullLocator
    except ImportError:
        sys.exit(f"plot.py: matplotlib is needed by {sys.executable} (Debian's python3-matplotlib "
                 "serves /usr/bin/python3)")

    out_dir = args.out or args.records / "plots"
    out_dir.mkdir(parents=True, exist_ok=True)
    for key, variants in sorted(group_records(files).items()):
        for path in plot_group(plt, NullLocator, key, variants, out_dir):
            print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
