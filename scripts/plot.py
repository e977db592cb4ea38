#!/usr/bin/env python3
"""Plots shadowbench build records: size and build time against resolution.

    python3 scripts/plot.py RECORDS_DIR [--out DIR] [--schemes a,b] [--param NAME=VALUE ...]

Reads every complete record (*.json, recursively) under RECORDS_DIR — the same validity rule
as the harness: "format" is "shadowbench-record/1", "complete" is true, and the fields the
tables need are there — and writes, for each (scene, light index, mode), two log-log PNGs:
size in bytes and build time in seconds against resolution, one line per scheme with its
parameters, with the analytic 16- and 32-bit shadow maps dashed on the size plot. Of several
records of one cell the newest ("created") counts, as in the tables.
"""

import argparse
import json
import re
import sys
from pathlib import Path

RECORD_FORMAT = "shadowbench-record/1"
BASELINE = "sm32"


def is_complete_record(record):
    """The harness's isCompleteRecord, field for field."""

    def is_int(value):
        return isinstance(value, int) and not isinstance(value, bool)

    def is_number(value):
        return isinstance(value, (int, float)) and not isinstance(value, bool)

    if not isinstance(record, dict):
        return False
    scene, scheme, size = record.get("scene"), record.get("scheme"), record.get("size_bytes")
    return (
        record.get("format") == RECORD_FORMAT
        and record.get("complete") is True
        and isinstance(scene, dict) and isinstance(scene.get("name"), str)
        and isinstance(scheme, dict) and isinstance(scheme.get("name"), str)
        and isinstance(record.get("mode"), str)
        and is_int(record.get("resolution")) and record["resolution"] > 0
        and isinstance(size, dict) and is_number(size.get("total"))
    )


def read_records(folder):
    """(records, skipped paths): every complete record under `folder`, sorted by path."""
    records, skipped = [], []
    for path in sorted(p for p in Path(folder).rglob("*.json") if p.is_file()):
        try:
            record = json.loads(path.read_bytes())
        except (OSError, ValueError):
            record = None
        if is_complete_record(record):
            records.append(record)
        else:
            skipped.append(path)
    return records, skipped


def light_index(record):
    value = record.get("light_index", 0)
    return value if isinstance(value, int) and value >= 0 else 0


def variant_label(record):
    """'mmh (height=3, search=1000)', as the tables name a scheme with its parameters."""
    scheme = record["scheme"]
    params = scheme.get("params") or {}
    if not isinstance(params, dict) or not params:
        return scheme["name"]
    text = ", ".join(f"{name}={value if isinstance(value, str) else json.dumps(value)}"
                     for name, value in sorted(params.items()))
    return f"{scheme['name']} ({text})"


def natural_key(text):
    """'search=200' before 'search=1000'."""
    return [(0, int(part), "") if part.isdigit() else (1, 0, part) for part in re.split(r"(\d+)", text)]


def variant_order(label):
    name = label.split(" (", 1)[0]
    return (name != BASELINE, name, natural_key(label))


def selected(record, schemes, params):
    """Whether --schemes and --param keep `record`: its scheme is listed (or none are), and each
    given parameter it has holds the given value."""
    scheme = record["scheme"]
    if schemes is not None and scheme["name"] not in schemes:
        return False
    have = scheme.get("params") or {}
    if not isinstance(have, dict):
        return True
    return all(str(have[name]) == value for name, value in params.items() if name in have)


def group_records(records):
    """{(scene, light, mode): {variant label: {resolution: record}}}, newest record per cell."""
    groups = {}
    for record in records:
        key = (record["scene"]["name"], light_index(record), record["mode"])
        cells = groups.setdefault(key, {}).setdefault(variant_label(record), {})
        resolution = record["resolution"]
        kept = cells.get(resolution)
        if kept is None or str(kept.get("created", "")) <= str(record.get("created", "")):
            cells[resolution] = record
    return groups


def resolution_label(resolution):
    return f"{resolution // 1024}K" if resolution >= 1024 and resolution % 1024 == 0 else str(resolution)


def file_name_part(text):
    """Lower case [a-z0-9.-] for a file name; the exact mapping need not match the harness."""
    part = re.sub(r"[^a-z0-9.]+", "-", text.lower()).strip("-.")
    return part or "x"


def build_seconds(record):
    time = record.get("time_s")
    value = time.get("total") if isinstance(time, dict) else None
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
        axes.plot(xs, [cells[r]["size_bytes"]["total"] for r in xs], marker="o", label=label)
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
    records, skipped = read_records(args.records)
    if skipped:
        print(f"plot.py: skipped {len(skipped)} file(s) that are not complete records", file=sys.stderr)
    records = [r for r in records if selected(r, wanted_schemes, wanted_params)]
    if not records:
        sys.exit(f"plot.py: no complete shadowbench records (*.json) under '{args.records}'"
                 + (" of the selected schemes and parameters" if args.schemes or args.param else ""))

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
    for key, variants in sorted(group_records(records).items()):
        for path in plot_group(plt, NullLocator, key, variants, out_dir):
            print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
