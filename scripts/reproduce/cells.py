"""The records of a folder as the paper tables look them up: the newest record of each cell,
found by scheme, scene generator, mode and parameters; and the quantities the tables derive
from a record."""

from records import (component_bytes, counter, depth_seconds, newest_per_cell, scheme_params,
                     size_bytes, total_seconds)

from table_format import MIB


class TableError(RuntimeError):
    """The records cannot make a table; the message says why and what to do."""


def generator(record):
    return record["scene"]["name"].split(":", 1)[0]


def params_of(record):
    """The record's parameters as a sorted tuple of (name, value)."""
    return tuple(sorted(scheme_params(record).items()))


def cell_of(record):
    return (record["scheme"]["name"], params_of(record), generator(record), record["mode"],
            record["resolution"])


def describe_cell(cell):
    scheme, params, scene, mode, resolution = cell
    named = f" ({', '.join(f'{k}={v}' for k, v in params)})" if params else ""
    return f"{scheme}{named}, {scene}, {mode}, {resolution}²"


class Cells:
    """The newest record of each cell, found by scheme, scene generator, mode and parameters;
    `defaults` ({scheme: {parameter: default}}, the registry's) picks the cells the papers' rows
    are built with, so that the variants of Fig. 8 and Tables 3 and 4 in one folder stay apart.
    `files` are records.RecordFiles; a record left out for a newer one of its cell is named on
    standard error, after `program`."""

    def __init__(self, files, defaults, folder, program):
        self.all = files.records
        self.defaults = defaults
        names = {}
        for record in self.all:
            names.setdefault(generator(record), set()).add(record["scene"]["name"])
        several = {g: sorted(n) for g, n in names.items() if len(n) > 1}
        if several:
            raise TableError(f"records of several scenes of one generator in {folder}: "
                             f"{several}; keep one scene per generator in a records folder")
        self.scene_names = {g: next(iter(n)) for g, n in names.items()}
        self.triangles = {generator(rec): rec["scene"].get("triangles") for rec in self.all}
        # (scheme, parameters, scene generator, mode, resolution) → the newest record
        self.newest = newest_per_cell(files, cell_of, describe_cell, program)

    def find(self, scheme, scene, mode, params=None):
        """{resolution: record}; `params` must be a subset of the record's parameters."""
        cells = {}
        for (name, given, gen, at_mode, r), record in self.newest.items():
            if ((name, gen, at_mode) != (scheme, scene, mode)
                    or any(dict(given).get(k) != v for k, v in (params or {}).items())):
                continue
            if r in cells:
                raise TableError(
                    f"{scheme} {scene} {mode} {r}² has records with different parameters "
                    f"({params_of(cells[r])} and {given}): the folder mixes variants, or the "
                    "scheme's parameters changed since; remove the stale records or use a fresh "
                    "folder")
            cells[r] = record
        return cells

    def at_defaults(self, scheme, scene, mode, params=None):
        """{resolution: record} of `scheme` at the registry's defaults, or `params` over them."""
        return self.find(scheme, scene, mode, {**self.defaults.get(scheme, {}), **(params or {})})


def mib(record):
    return size_bytes(record) / MIB


def component_mib(record, *names):
    value = component_bytes(record, *names)
    return None if value is None else value / MIB


def millions(record, name):
    """A counter in millions."""
    value = counter(record, name)
    return None if value is None else value * 1e-6


def without_depth(record):
    total, depth = total_seconds(record), depth_seconds(record)
    return total - depth if isinstance(total, (int, float)) and isinstance(depth,
                                                                            (int, float)) else None
