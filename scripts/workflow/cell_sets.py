"""The sweep a workflow config describes: cell sets, their parts and their scheme cells, with the
command-line arguments of `shadowbench part`, `merge`, `build` and `estimate` for each
(/work/notes/parts.md, issue 12 items 2 and 5).

A cell set is one (scene, light, mode, resolution, tile, part size) and the schemes that share its
depth pass: each part of the set is one `shadowbench part` job encoding every scheme, each scheme
is one `shadowbench merge` job. The Snakefile and tests/workflow_test.sh read the config only
through this module, so that both agree on what a cell is.

    python3 scripts/workflow/cell_sets.py CONFIG.yaml whole-builds
prints a line per scheme cell: SET, SCHEME, RESOLUTION and PART_SIZE (texels) and then the
arguments of a whole `shadowbench build` of that cell, separated by tabs, for tests that compare
merged structures with whole builds.
"""

import re
import sys
from pathlib import Path

import yaml

K = 1024
# Names become file names and Snakemake wildcards.
SET_NAME = r"[A-Za-z0-9][A-Za-z0-9_.-]*"
SCHEME_NAME = r"[a-z0-9][a-z0-9-]*"


class ConfigError(ValueError):
    """A workflow config that cannot describe a sweep; the message names the key and value."""


def texels(text, key):
    """'2K' → 2048, '512' → 512, 2048 → 2048; a power of two from 8 to 1M."""
    spelled = str(text).strip()
    match = re.fullmatch(r"([0-9]{1,7})([kKmM]?)", spelled)
    if not match:
        raise ConfigError(f"{key}: '{text}' is not a resolution such as 512, 4K or 256K")
    value = int(match.group(1)) * {"": 1, "k": K, "m": K * K}[match.group(2).lower()]
    if value < 8 or value > K * K or value & (value - 1):
        raise ConfigError(f"{key}: '{text}' is not a power of two from 8 to 1M")
    return value


def spelled(value):
    """2048 → '2K', as the CLI reads it."""
    return f"{value // K}K" if value >= K and value % K == 0 else str(value)


class CellSet:
    """One entry of `cell_sets`: the cells sharing a depth pass."""

    def __init__(self, name, entry):
        where = f"cell_sets.{name}"
        if not re.fullmatch(SET_NAME, str(name)):
            raise ConfigError(f"cell_sets: the name '{name}' must be letters, digits, '_', '.', "
                              "'-'")
        if not isinstance(entry, dict):
            raise ConfigError(f"{where}: expected a mapping of scene, mode, resolution, …")
        known = {"scene", "light", "mode", "resolution", "tile", "part_size", "schemes", "params"}
        unknown = sorted(set(entry) - known)
        if unknown:
            raise ConfigError(f"{where}: unknown key '{unknown[0]}' "
                              f"(known: {', '.join(sorted(known))})")
        for key in ("scene", "mode", "resolution", "part_size", "schemes"):
            if key not in entry:
                raise ConfigError(f"{where}: '{key}' is missing")
        self.name = str(name)
        self.scene = str(entry["scene"])
        self.light = entry.get("light", 0)
        if not isinstance(self.light, int) or isinstance(self.light, bool) or self.light < 0:
            raise ConfigError(f"{where}.light: '{self.light}' is not a light index")
        self.mode = str(entry["mode"])
        if self.mode not in ("open", "closed", "static"):
            raise ConfigError(f"{where}.mode: '{self.mode}' is not open, closed or static")
        self.resolution = texels(entry["resolution"], f"{where}.resolution")
        self.part_size = texels(entry["part_size"], f"{where}.part_size")
        if self.part_size >= self.resolution:
            raise ConfigError(f"{where}.part_size: {spelled(self.part_size)} must be below the "
                              f"resolution {spelled(self.resolution)}")
        self.tile = entry.get("tile")
        if self.tile is not None:
            self.tile = texels(self.tile, f"{where}.tile")
            if self.tile > self.part_size:
                raise ConfigError(f"{where}.tile: {self.tile} is larger than the part size "
                                  f"{self.part_size}")
        schemes = entry["schemes"]
        if not isinstance(schemes, list) or not schemes:
            raise ConfigError(f"{where}.schemes: expected a non-empty list of scheme names")
        for scheme in schemes:
            if not isinstance(scheme, str) or not re.fullmatch(SCHEME_NAME, scheme):
                raise ConfigError(f"{where}.schemes: '{scheme}' is not a scheme name")
        if len(set(schemes)) != len(schemes):
            raise ConfigError(f"{where}.schemes: a scheme is listed twice ({', '.join(schemes)})")
        self.schemes = list(schemes)
        params = entry.get("params") or {}
        if not isinstance(params, dict):
            raise ConfigError(f"{where}.params: expected {{scheme: {{name: value}}}}")
        for scheme, assignments in params.items():
            if scheme not in self.schemes:
                raise ConfigError(f"{where}.params: '{scheme}' is not one of this set's schemes")
            if not isinstance(assignments, dict):
                raise ConfigError(f"{where}.params.{scheme}: expected {{name: value}}")
        self.params = {scheme: {str(k): str(v) for k, v in params.get(scheme, {}).items()}
                       for scheme in self.schemes}

    @property
    def part_count(self):
        return (self.resolution // self.part_size) ** 2

    def _map_args(self):
        args = ["--scene", self.scene, "--light", str(self.light), "--mode", self.mode,
                "--resolution", spelled(self.resolution)]
        if self.tile is not None:
            args += ["--tile", str(self.tile)]
        return args

    def _params_of(self, scheme, qualified=False):
        prefix = f"{scheme}:" if qualified else ""
        args = []
        for name, value in self.params[scheme].items():
            args += ["--param", f"{prefix}{name}={value}"]
        return args

    def part_args(self, index, parts_dir):
        """`shadowbench part` of part INDEX for every scheme of the set: one depth pass."""
        args = ["part", *self._map_args(), "--part-size", str(self.part_size),
                "--part", str(index)]
        for scheme in self.schemes:
            args += ["--scheme", scheme]
        for scheme in self.schemes:
            args += self._params_of(scheme, qualified=True)
        return args + ["--parts", str(parts_dir)]

    def merge_args(self, scheme, parts_dir):
        return ["merge", *self._map_args(), "--part-size", str(self.part_size),
                "--scheme", scheme, *self._params_of(scheme), "--parts", str(parts_dir)]

    def whole_build_args(self, scheme):
        """`shadowbench build` of one cell of the set in one piece (no parts)."""
        return ["build", *self._map_args(), "--scheme", scheme, *self._params_of(scheme)]

    def estimate_args(self, schemes):
        """`shadowbench estimate` of SCHEMES (some of the set's) as one depth pass feeds them."""
        args = ["estimate", "--mode", self.mode, "--resolution", spelled(self.resolution),
                "--part-size", str(self.part_size)]
        for scheme in schemes:
            args += ["--scheme", scheme]
        for scheme in schemes:
            args += self._params_of(scheme, qualified=len(schemes) > 1)
        if self.tile is not None:
            args += ["--tile", str(self.tile)]
        return args


TOP_LEVEL = {"shadowbench", "results", "cell_sets", "merge", "resources", "paper_tables"}
# What a config may leave out: the CI and example configs show each key.
MERGE_DEFAULTS = {"verify": True, "bench": True, "sampled_queries": None}
RESOURCE_DEFAULTS = {"part_threads": 2, "merge_threads": 1, "memory_margin": 1.5,
                     "base_mem_mb": 1024, "max_mem_mb": None, "part_runtime_min": 120,
                     "merge_runtime_min": 120}


def _section(config, key, defaults):
    given = config.get(key) or {}
    if not isinstance(given, dict):
        raise ConfigError(f"{key}: expected a mapping of {', '.join(defaults)}")
    for name, value in given.items():
        if name not in defaults:
            raise ConfigError(f"{key}: unknown key '{name}' (known: {', '.join(defaults)})")
        if isinstance(defaults[name], bool):
            if not isinstance(value, bool):
                raise ConfigError(f"{key}.{name}: '{value}' is not true or false")
        elif value is not None and (isinstance(value, bool) or not isinstance(value, (int, float))
                                    or value <= 0):
            raise ConfigError(f"{key}.{name}: '{value}' is not a positive number")
        elif value is not None and name != "memory_margin" and not isinstance(value, int):
            raise ConfigError(f"{key}.{name}: '{value}' is not a whole number")
    return {**defaults, **given}


def merge_settings(config):
    return _section(config, "merge", MERGE_DEFAULTS)


def resource_settings(config):
    return _section(config, "resources", RESOURCE_DEFAULTS)


def paper_tables(config):
    tables = config.get("paper_tables") or []
    if not isinstance(tables, list) or not all(isinstance(t, str) and re.fullmatch(r"[a-z0-9-]+", t)
                                               for t in tables):
        raise ConfigError(f"paper_tables: '{tables}' is not a list of table names such as "
                          "scandolo2021-table1 (scripts/reproduce/paper_tables.py)")
    return tables


def cell_sets(config):
    """Every cell set of a loaded config, checked; ConfigError names what is wrong."""
    unknown = sorted(set(config) - TOP_LEVEL)
    if unknown:
        raise ConfigError(f"unknown key '{unknown[0]}' (known: {', '.join(sorted(TOP_LEVEL))})")
    entries = config.get("cell_sets")
    if not isinstance(entries, dict) or not entries:
        raise ConfigError("cell_sets: expected a mapping of set names to cell sets")
    return [CellSet(name, entry) for name, entry in entries.items()]


def main(argv):
    if len(argv) != 3 or argv[2] != "whole-builds":
        print(__doc__, file=sys.stderr)
        return 2
    try:
        config = yaml.safe_load(Path(argv[1]).read_text())
        for cell_set in cell_sets(config):
            for scheme in cell_set.schemes:
                fields = [cell_set.name, scheme, cell_set.resolution, cell_set.part_size,
                          *cell_set.whole_build_args(scheme)]
                if any("\t" in str(field) or "\n" in str(field) for field in fields):
                    raise ConfigError(f"cell set {cell_set.name}: a tab or line break in {fields}")
                print(*fields, sep="\t")
    except (OSError, yaml.YAMLError, ConfigError) as error:
        print(f"cell_sets.py: {argv[1]}: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
