"""View records (`"format": "shadowbench-view-record"`, version 1): one shadowing technique
rendered along one camera path, judged frame by frame against the exact shadows. This module
reads them and makes what the report (report.py) and plot_views.py show of them: a table of
techniques per path and the error-against-memory plot with its Pareto front.

A view record lives in the same folders as the build records; records.py leaves it to this
reader. Its image paths are relative to the record file's folder.
"""

import json
import sys
from pathlib import Path

from number_format import integer, significant
from pareto import plot_front
from plot import file_name_part, resolution_label
from records import VIEW_RECORD_FORMAT, RecordFiles, newest_per_cell, record_paths

VIEW_RECORD_VERSION = 1
MIB = 1 << 20


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def view_problem(record):
    """Why a record of the view format cannot be shown, or None: the fields the report reads."""
    if record.get("version") != VIEW_RECORD_VERSION:
        return f"\"version\" is not {VIEW_RECORD_VERSION}"
    path, technique = record.get("path"), record.get("technique")
    totals, frames = record.get("totals"), record.get("frames")
    if not (isinstance(path, dict) and isinstance(path.get("name"), str)):
        return "no path name"
    if not (isinstance(technique, dict) and isinstance(technique.get("label"), str)):
        return "no technique label"
    if not isinstance(totals, dict):
        return "no totals"
    for name in ("error_rate", "memory_bytes"):
        if not _is_number(totals.get(name)):
            return f"no number totals.{name}"
    if not (isinstance(frames, list) and all(isinstance(f, dict) for f in frames)):
        return "no list of frames"
    return None


def read_view_records(folder, program, name_unreadable=True):
    """The view records under `folder` (records.RecordFiles; files as records.record_paths
    lists them). A view record that cannot be shown is named on standard error, as is, with
    `name_unreadable`, a file that is not JSON (the report leaves that to the build reader,
    which names it already); other JSON files are build records, not this reader's."""
    files = RecordFiles([], [], [])
    for path in record_paths(folder):
        try:
            record = json.loads(Path(path).read_bytes())
        except (OSError, ValueError) as error:
            if name_unreadable:
                files.skipped.append((path, f"not JSON ({error})"))
                print(f"{program}: skipped {path}: not JSON ({error})", file=sys.stderr)
            continue
        if not isinstance(record, dict) or record.get("format") != VIEW_RECORD_FORMAT:
            continue
        problem = view_problem(record)
        if problem:
            files.skipped.append((path, problem))
            print(f"{program}: skipped view record {path}: {problem}", file=sys.stderr)
        else:
            files.records.append(record)
            files.paths.append(path)
    return files


def technique_label(record):
    """The technique's label, with the structure's resolution where the label lacks it."""
    technique = record["technique"]
    label, structure = technique["label"], technique.get("structure")
    if isinstance(structure, dict) and isinstance(structure.get("resolution"), int):
        resolution = structure["resolution"]
        if str(resolution) not in label and resolution_label(resolution) not in label:
            label += f" {resolution_label(resolution)}²"
    return label


def group_by_path(files, program):
    """{path name: [(record, file)]} of `files`, the newest record per (path, technique), each
    sorted by memory; every record left out is named."""
    # newest_per_cell answers with the records themselves: their files by identity.
    file_of = {id(record): path for record, path in zip(files.records, files.paths)}
    newest = newest_per_cell(files, lambda r: (r["path"]["name"], technique_label(r)),
                             lambda cell: f"path {cell[0]}, {cell[1]}", program)
    groups = {}
    for (name, _), record in newest.items():
        groups.setdefault(name, []).append((record, file_of[id(record)]))
    for entries in groups.values():
        entries.sort(key=lambda entry: (entry[0]["totals"]["memory_bytes"],
                                        technique_label(entry[0])))
    return groups


TABLE_HEADER = ["technique", "error rate (%)", "false lit", "false shadow",
                "boundary error rate (%)", "memory (MiB)", "build (ms)", "shade (ms)"]


def table_row(record):
    """The cells of one technique in TABLE_HEADER's order (medians of the frames' times)."""
    totals = record["totals"]

    def number(name):
        value = totals.get(name)
        return value if _is_number(value) else None

    def percent(name):
        value = number(name)
        return None if value is None else 100 * value

    return [technique_label(record), significant(percent("error_rate")),
            integer(number("false_lit")), integer(number("false_shadow")),
            significant(percent("boundary_error_rate")),
            significant(totals["memory_bytes"] / MIB),
            significant(number("build_ms_median")), significant(number("shade_ms_median"))]


def frame_picks(count, wanted):
    """Indices of `wanted` frames spread evenly from the first to the last of `count` (3: the
    first, middle and last), each once."""
    if count <= 0 or wanted <= 0:
        return []
    if wanted == 1:
        return [0]
    return sorted({round(i * (count - 1) / (wanted - 1)) for i in range(wanted)})


def plot_file_name(path_name):
    return f"error-memory_{file_name_part(path_name)}.png"


def plot_error_memory(plt, path_name, records, out_dir):
    """Writes the error-against-memory plot of one path's techniques (records) into `out_dir`:
    every technique a point, memory on a log axis, the Pareto front (less error and less memory)
    marked. Returns (the PNG's path, the labels of the front in memory order)."""
    points = [(r["totals"]["memory_bytes"], 100 * r["totals"]["error_rate"]) for r in records]
    labels = [technique_label(r) for r in records]
    figure, axes = plt.subplots(figsize=(11, 5.5))
    axes.set_xscale("log")
    front = plot_front(axes, points, labels)[None]
    axes.set_xlabel("memory (bytes)")
    axes.set_ylabel("error rate (% of covered pixels)")
    axes.set_title(f"Error against memory — path {path_name} (lower left is better)")
    figure.tight_layout()
    out = Path(out_dir) / plot_file_name(path_name)
    figure.savefig(out, dpi=120)
    plt.close(figure)
    return out, [labels[i] for i in front]
