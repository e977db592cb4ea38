"""Reading shadowbench records (DESIGN §6) for the Python scripts: which files count, and the
fields the scripts read.

A file counts when it is JSON, passes the harness's own completeness rule (isCompleteRecord in
harness/record.cpp, field for field) and validates against the record's JSON Schema
(harness/record.schema.json). Every file that does not count is named on standard error with
the reason, so that a table never hides a half-written or nonsense record.
"""

import json
import os
import sys
from pathlib import Path
from typing import NamedTuple

try:
    import jsonschema
except ImportError:  # said when records are to be read (record_validator), naming the package
    jsonschema = None

RECORD_FORMAT = "shadowbench-record/1"
# A record of a view (scripts/views.py): another kind of record in the same folders, which the
# build readers pass over without naming it, as it is neither broken nor theirs.
VIEW_RECORD_FORMAT = "shadowbench-view-record"
VIEW_RECORD = "a view record"
# Where a sweep moves the records of older versions of a cell (harness/record.h,
# kSupersededFolder): kept, never read as records.
SUPERSEDED_FOLDER = "superseded"
SCHEMA_PATH = Path(__file__).resolve().parent.parent / "harness" / "record.schema.json"


def _is_int(value):
    return isinstance(value, int) and not isinstance(value, bool)


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def completeness_problem(record):
    """Why `record` fails the harness's isCompleteRecord, or None if it passes."""
    if not isinstance(record, dict):
        return "not a JSON object"
    if record.get("format") != RECORD_FORMAT:
        return f"\"format\" is not \"{RECORD_FORMAT}\""
    if record.get("complete") is not True:
        return "\"complete\" is not true (the build did not finish)"
    scene, scheme, size = record.get("scene"), record.get("scheme"), record.get("size_bytes")
    if not (isinstance(scene, dict) and isinstance(scene.get("name"), str)):
        return "no scene name"
    if not (isinstance(scheme, dict) and isinstance(scheme.get("name"), str)):
        return "no scheme name"
    if not isinstance(record.get("mode"), str):
        return "no mode"
    if not (_is_int(record.get("resolution")) and record["resolution"] > 0):
        return "no positive integer resolution"
    if not (isinstance(size, dict) and _is_number(size.get("total"))):
        return "no size_bytes.total"
    return None


def is_complete_record(record):
    """The harness's isCompleteRecord."""
    return completeness_problem(record) is None


class SchemaUnavailable(RuntimeError):
    """The record schema or its validator cannot be had: nothing can be checked."""


def record_validator(schema=None):
    """A jsonschema validator of records; `schema` is the schema itself or the path of its file
    (None: SCHEMA_PATH)."""
    if jsonschema is None:
        raise SchemaUnavailable(f"jsonschema is needed by {sys.executable} to check records "
                                "(Debian's python3-jsonschema serves /usr/bin/python3)")
    if schema is None:
        schema = SCHEMA_PATH
    if not isinstance(schema, dict):
        try:
            schema = json.loads(Path(schema).read_text(encoding="utf-8"))
        except (OSError, ValueError) as error:
            raise SchemaUnavailable(f"cannot read the record schema '{schema}': {error}") from error
    validator_class = jsonschema.validators.validator_for(schema)
    try:
        validator_class.check_schema(schema)
    except jsonschema.exceptions.SchemaError as error:
        raise SchemaUnavailable(f"the record schema is not a valid JSON Schema: {error.message}"
                                ) from error
    return validator_class(schema)


def schema_problem(validator, record):
    """The first reason `record` breaks the schema, or None."""
    error = jsonschema.exceptions.best_match(validator.iter_errors(record))
    if error is None:
        return None
    return f"does not match the record schema at {error.json_path}: {error.message}"


def read_record(path, validator):
    """(record, None) if the file at `path` counts, else (None, why not): VIEW_RECORD for a
    view record."""
    try:
        data = Path(path).read_bytes()
    except OSError as error:
        return None, f"unreadable: {error.strerror or error}"
    if not data.strip():
        return None, "empty file"
    try:
        record = json.loads(data)
    except ValueError as error:  # a truncated file says where its text ends
        return None, f"not JSON ({error})"
    if isinstance(record, dict) and record.get("format") == VIEW_RECORD_FORMAT:
        return None, VIEW_RECORD
    problem = completeness_problem(record) or schema_problem(validator, record)
    return (None, problem) if problem else (record, None)


def record_paths(folder):
    """Every *.json file under `folder`, recursively and sorted, outside superseded folders (as
    the harness's readRecords: directory links are not followed)."""
    paths = []
    for root, folders, files in os.walk(folder):
        folders[:] = [name for name in folders if name != SUPERSEDED_FOLDER]
        paths += [Path(root) / name for name in files if name.endswith(".json")]
    return sorted(path for path in paths if path.is_file())


class RecordFiles(NamedTuple):
    records: list  # the records that count, in path order
    paths: list  # the file of each record
    skipped: list  # (path, why) of each file that does not count


def read_records(folder, program, schema=None):
    """The RecordFiles of `folder` (the files of record_paths); each file that does not count is
    also reported on standard error as "PROGRAM: skipped PATH: WHY", but for view records, which
    are left out unnamed. `schema` as for record_validator; raises SchemaUnavailable before
    reading any file."""
    validator = record_validator(schema)
    files = RecordFiles([], [], [])
    for path in record_paths(folder):
        record, problem = read_record(path, validator)
        if problem == VIEW_RECORD:
            continue
        if record is None:
            files.skipped.append((path, problem))
            print(f"{program}: skipped {path}: {problem}", file=sys.stderr)
        else:
            files.records.append(record)
            files.paths.append(path)
    return files


def _created(record):
    return str(record.get("created", ""))


def is_newer(record, kept):
    """Whether `record` replaces `kept` (None: nothing yet) as its cell's record: the newest
    ("created", ISO 8601 UTC) counts, and of equal ones the one read later (files are read in
    path order), as the harness's tables choose."""
    return kept is None or _created(kept) <= _created(record)


def newest_per_cell(files, cell_of, describe, program):
    """{cell: record}: of the records of `files` (RecordFiles) in one cell (`cell_of(record)`)
    the newest, as is_newer says. Each record left out is named on standard error beside the one
    used, with the cell (`describe(cell)`), as the harness's `table` names them."""
    used = {}  # cell → index of its record
    for index, record in enumerate(files.records):
        cell = cell_of(record)
        if cell not in used or is_newer(record, files.records[used[cell]]):
            used[cell] = index
    for index, record in enumerate(files.records):
        cell = cell_of(record)
        kept = used[cell]
        if index == kept:
            continue
        when = _created(record) or "at an unknown time"
        when_kept = _created(files.records[kept]) or "at an unknown time"
        why = (f"both created {when}; the later file is used" if when == when_kept
               else f"created {when}, the used one {when_kept}")
        print(f"{program}: '{files.paths[index]}' and '{files.paths[kept]}' are records of one "
              f"cell ({describe(cell)}): the first is not used ({why})", file=sys.stderr)
    return {cell: files.records[index] for cell, index in used.items()}


# --- fields ---------------------------------------------------------------------------------

def _number(value):
    return value if _is_number(value) else None


def _section(record, name):
    value = record.get(name)
    return value if isinstance(value, dict) else {}


def light_index(record):
    value = record.get("light_index", 0)
    return value if _is_int(value) and value >= 0 else 0


def scheme_params(record):
    """The record's scheme parameters, {name: value} (values as the record stores them)."""
    params = record["scheme"].get("params")
    return params if isinstance(params, dict) else {}


def size_bytes(record):
    return record["size_bytes"]["total"]


def component_bytes(record, *names):
    """The sum of the named size components, None if the record lacks one."""
    parts = _section(record, "size_bytes").get("components")
    values = [_number(parts.get(name)) for name in names] if isinstance(parts, dict) else [None]
    return None if None in values else sum(values)


def total_seconds(record):
    """The scheme's build time. Where its depth pass was shared with other schemes
    (time_s.depth_shared_with), the record's total is the wall time of the whole group, every
    scheme's encoders included, so the scheme's own time is the depth time plus its phases."""
    time = _section(record, "time_s")
    if not time.get("depth_shared_with"):
        return time.get("total")
    depth, phases = _number(time.get("depth")), time.get("phases")
    if depth is None or not isinstance(phases, dict):
        return None
    seconds = [_number(value) for value in phases.values()]
    return None if None in seconds else depth + sum(seconds)


def depth_seconds(record):
    return _section(record, "time_s").get("depth")


def phase_seconds(record, name):
    phases = _section(record, "time_s").get("phases")
    return _number(phases.get(name)) if isinstance(phases, dict) else None


def counter(record, name):
    return _number(_section(record, "counters").get(name))


def _lookup(record, query_set, k):
    for timing in record.get("lookup") or []:
        if timing.get("query_set") == query_set and timing.get("filter") == k:
            return timing
    return {}


def lookup_ns(record, query_set, k):
    """ns per query on one thread of `query_set` with filter k×k, None if not timed."""
    return _lookup(record, query_set, k).get("ns_per_query_1t")


def cache_hit_rate(record, query_set, k):
    """The share of block reads a decoder's cache answered in that timing, None if it has none."""
    return _lookup(record, query_set, k).get("cache_hit_rate")
