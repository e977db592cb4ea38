#!/usr/bin/env python3
"""The CPVS paper tables from shadowbench records, the papers' figures beside ours.

    /usr/bin/python3 scripts/reproduce/paper_tables.py TABLE RECORDS_DIR
        [--max-resolution 64K] [--command "how the records were made"]

TABLE is one of sintorn2014-fig9, kampe2015-table1 … kampe2015-table4, cpvs-lookup; the
Markdown goes to standard output. Records are read as scripts/plot.py reads them (complete
records only, the newest of a cell). Columns are our resolutions and the paper's up to
--max-resolution. The papers' figures are data in this file, as printed (their "KB"/"MB" are
10^3/10^6 bytes: Sintorn's percentages of 2·R² bytes give Kämpe's "old" MB only in decimal MB).
"""

import argparse
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from plot import read_records  # noqa: E402  (the one reader of records in scripts/)

MIB = 1 << 20
K = 1024
MISSING = "–"

# --- the papers' figures, as printed -------------------------------------------------------

# Sintorn et al. 2014, Fig. 9 "Compression results": per scene and build, the size and the size
# as % of a 16-bit shadow map, at 1K² 4K² 16K² 32K² 128K² 256K² ("-": not built).
SINTORN_FIG9_RESOLUTIONS = [1 * K, 4 * K, 16 * K, 32 * K, 128 * K, 256 * K]
SINTORN_FIG9 = {
    "ClosedCity closed": ("202KB 1MB 6MB 13MB 50MB 100MB", "9.61 3.53 1.16 0.60 0.14 0.07"),
    "ClosedCity not closed": ("489KB 4MB 36MB 96MB 639MB 1638MB",
                              "23.32 12.41 6.69 4.48 1.86 1.19"),
    "FractalLandscape closed": ("164KB 759KB 3MB 7MB 29MB 61MB", "7.81 2.26 0.62 0.33 0.09 0.04"),
    "FractalLandscape not closed": ("490KB 5MB 50MB 146MB 1155MB -",
                                    "23.37 14.34 9.29 6.81 3.36 -"),
    "Necropolis not closed": ("539KB 5MB 37MB 100MB 657MB -", "25.72 13.66 6.94 4.66 1.91 -"),
    "Necropolis static geometry": ("444KB 3MB 14MB 31MB 144MB -", "21.19 8.43 2.69 1.46 0.42 -"),
    # EpicCitadel not closed (585KB … 727MB) has no stand-in among our scenes.
}

# Kämpe et al. 2015 reports 4K³ … 256K³ (Tables 1, 2, 4) and 4K³ 16K³ 64K³ 256K³ (Table 3).
KAMPE_RESOLUTIONS = [4 * K, 8 * K, 16 * K, 32 * K, 64 * K, 128 * K, 256 * K]
KAMPE_TABLE3_RESOLUTIONS = [4 * K, 16 * K, 64 * K, 256 * K]

# Kämpe Table 1, ClosedCity: (total, insert/merge) without and with culling of identical nodes.
# The row labels are lost in the text; the culled rows are Table 4's ClosedCity times, and the
# insert/merge saved by culling is the same in absolute terms open and closed (Kämpe §5.1).
KAMPE_TABLE1 = {
    ("non-closed", "off"): ("434ms 1.7s 6.5s 24.1s 92.7s 357.9s 1398.8s",
                            "417ms 1.7s 6.4s 23.5s 90.3s 348.6s 1362.4s"),
    ("closed", "off"): ("235ms 695ms 2.5s 9.1s 35.8s 139.5s 550.5s",
                        "146ms 580ms 2.3s 8.4s 33.2s 130.1s 515.2s"),
    ("non-closed", "on"): ("300ms 1.2s 4.5s 16.3s 61.5s 235.4s 906.4s",
                           "283ms 1.2s 4.4s 15.7s 59.2s 226.1s 870.1s"),
    ("closed", "on"): ("113ms 185ms 377ms 1.1s 3.3s 10.9s 38.1s",
                       "25ms 72ms 151ms 347ms 763ms 1.6s 3.3s"),
}

# Kämpe Table 2, closed object optimisation: (new MB, old MB, ratio old/new).
KAMPE_TABLE2 = {
    "ClosedCity": ("0.83 1.89 3.96 7.70 14.28 26.15 48.04",
                   "1.18 2.82 6.25 12.87 25.43 49.72 100.05",
                   "1.43 1.49 1.58 1.67 1.78 1.90 2.08"),
    "FractalLandscape": ("0.44 0.84 1.60 3.05 5.76 10.85 20.35",
                         "0.76 1.59 3.34 6.98 14.36 29.30 60.99",
                         "1.72 1.90 2.08 2.29 2.49 2.70 3.00"),
}

# Kämpe Table 3, ClosedCity, at 4K³ 16K³ 64K³ 256K³: the total, then each step.
KAMPE_TABLE3 = {
    "non-closed": {
        "total": "300ms 4.5s 61.5s 906.4s",
        "enter depth map": "4ms 20ms 291ms 4.5s",
        "visibility masks": "2ms 29ms 482ms 7.8s",
        "min-max": "1ms 1ms 7ms 119ms",
        "transfer": "7ms 90ms 1.4s 22.6s",
        "insert nodes": "107ms 1.7s 22.1s 339.8s",
        "merge nodes": "176ms 2.7s 37.2s 530.4s",
    },
    "closed": {
        "total": "113ms 377ms 3.3s 38.1s",
        "enter depth map": "5ms 19ms 271ms 4.4s",
        "exit depth map": "78ms 176ms 1.8s 23.0s",
        "visibility masks": "1ms 12ms 181ms 2.9s",
        "min-max": "1ms 1ms 7ms 111ms",
        "transfer": "2ms 16ms 245ms 3.9s",
        "insert nodes": "10ms 63ms 312ms 1.4s",
        "merge nodes": "15ms 88ms 451ms 2.0s",
    },
}

# Kämpe Table 4, total construction times. The last row is Sintorn 2014's own build-time table
# (§7), which is of FractalLandscape, closed; Kämpe prints its 18.0s under 8K³ and nothing under
# 16K³, where Sintorn's table has it (Sintorn built no 8K³), so it stands at 16K³ here.
KAMPE_TABLE4 = {
    "Necropolis non-closed": "209ms 720ms 2.6s 9.6s 34.5s 126.6s 470.4s",
    "ClosedCity non-closed": "300ms 1.2s 4.5s 16.3s 61.5s 235.4s 906.4s",
    "ClosedCity closed": "113ms 185ms 377ms 1.1s 3.3s 10.9s 38.1s",
    "FractalLandscape non-closed": "264ms 1.0s 4.0s 15.2s 57.6s 220.7s 874.2s",
    "FractalLandscape closed": "56ms 91ms 192ms 570ms 2.0s 7.1s 25.3s",
    "Sintorn 2014 closed (FractalLandscape)": "2.0s - 18.0s 68.0s 256.0s 1055.0s 5520.0s",
}

# Sintorn 2014 §7 "Evaluation performance": GPU shading time per frame of the fly-throughs, at
# worst 2.5× from 1 tap to 9×9 and 4.5× to 17×17.
SINTORN_WORST_RATIO = {9: 2.5, 17: 4.5}

# Triangles of the papers' scenes (Sintorn 2014 §7; Kämpe 2015 uses the same scenes and light).
PAPER_TRIANGLES = {"ClosedCity": "613k", "FractalLandscape": "2.1M", "Necropolis": "2.1M"}
CULLING_ON = {"culling": "on"}  # cpvs-fast as Kämpe's Tables 2-4 measure it


def parse_row(text, resolutions, unit):
    """{resolution: value} from a printed row; `unit` converts one printed cell."""
    cells = text.split()
    assert len(cells) == len(resolutions), text
    return {r: unit(c) for r, c in zip(resolutions, cells) if c != "-"}


def seconds(cell):
    return float(cell[:-2]) / 1000 if cell.endswith("ms") else float(cell.rstrip("s"))


def decimal_bytes(cell):
    for suffix, scale in (("KB", 1e3), ("MB", 1e6), ("GB", 1e9)):
        if cell.endswith(suffix):
            return float(cell[:-2]) * scale
    return float(cell) * 1e6  # Kämpe's cells are MB


def sintorn_fig9_bytes(build):
    """{resolution: bytes} from whichever of the printed size and percentage is more precise:
    "1MB" is ±50%, "0.07%" is ±7%."""
    sizes, percents = SINTORN_FIG9[build]
    out = {}
    for r, size, percent in zip(SINTORN_FIG9_RESOLUTIONS, sizes.split(), percents.split()):
        if size == "-":
            continue
        digits = size.rstrip("KMGB")
        last_place = 10.0 ** -(len(digits.split(".")[1]) if "." in digits else 0)
        size_error = last_place / 2 / float(digits)
        percent_error = 0.005 / float(percent)
        out[r] = (decimal_bytes(size) if size_error < percent_error
                  else float(percent) / 100 * shadow_map_16(r))
    return out


# --- records --------------------------------------------------------------------------------

def shadow_map_16(resolution):
    return 2.0 * resolution * resolution


def generator(record):
    return record["scene"]["name"].split(":", 1)[0]


def params_of(record):
    """The record's parameters as a sorted tuple of (name, value)."""
    return tuple(sorted((record["scheme"].get("params") or {}).items()))


class Records:
    """The newest record of each cell, found by scheme, scene generator, mode and parameters."""

    def __init__(self, folder):
        self.all, _ = read_records(folder)
        names = {}
        for record in self.all:
            names.setdefault(generator(record), set()).add(record["scene"]["name"])
        several = {g: sorted(n) for g, n in names.items() if len(n) > 1}
        if several:
            sys.exit(f"paper_tables.py: records of several scenes of one generator in {folder}: "
                     f"{several}; keep one scene per generator in a records folder")
        self.scene_names = {g: next(iter(n)) for g, n in names.items()}
        self.triangles = {generator(rec): rec["scene"].get("triangles") for rec in self.all}
        # (scheme, parameters, scene generator, mode, resolution) → the newest record
        self.newest = {}
        for record in self.all:
            key = (record["scheme"]["name"], params_of(record), generator(record),
                   record["mode"], record["resolution"])
            kept = self.newest.get(key)
            if kept is None or str(kept.get("created", "")) <= str(record.get("created", "")):
                self.newest[key] = record

    def find(self, scheme, scene, mode, params=None):
        """{resolution: record}; `params` must be a subset of the record's parameters."""
        cells = {}
        for (name, given, gen, at_mode, r), record in self.newest.items():
            if ((name, gen, at_mode) != (scheme, scene, mode)
                    or any(dict(given).get(k) != v for k, v in (params or {}).items())):
                continue
            if r in cells:
                sys.exit(f"paper_tables.py: {scheme} {scene} {mode} {r}² has records with "
                         f"different parameters ({params_of(cells[r])} and {given}): the "
                         "folder mixes variants, or the scheme's parameters changed since; "
                         "remove the stale records or use a fresh folder")
            cells[r] = record
        return cells


def phase(record, name):
    value = record.get("time_s", {}).get("phases", {}).get(name)
    return value if isinstance(value, (int, float)) else None


def counter(record, name, scale=1e-6):
    value = (record.get("counters") or {}).get(name)
    return value * scale if isinstance(value, (int, float)) else None


def total_seconds(record):
    return record.get("time_s", {}).get("total")


def depth_seconds(record):
    return record.get("time_s", {}).get("depth")


def size_bytes(record):
    return record["size_bytes"]["total"]


def lookup_ns(record, query_set, k):
    for timing in record.get("lookup") or []:
        if timing.get("query_set") == query_set and timing.get("filter") == k:
            return timing.get("ns_per_query_1t")
    return None


# --- formatting -----------------------------------------------------------------------------

def significant(value, digits=3):
    """3 significant digits, no exponent (like the harness's formatSignificant)."""
    if value is None:
        return MISSING
    if value == 0:
        return "0"

    def decimals(v):
        return max(0, digits - 1 - math.floor(math.log10(abs(v))))

    places = decimals(value)
    rounded = round(value, places)  # 9.996 → 10.0: one decimal fewer
    return f"{value:.{min(places, decimals(rounded)) if rounded else places}f}"


def heading(resolution):
    return f"{resolution // K}K²" if resolution >= K and resolution % K == 0 else f"{resolution}²"


def markdown_table(header, rows, label_columns=1):
    """Label columns left-aligned, numbers right-aligned."""
    align = [" --- "] * label_columns + [" ---: "] * (len(header) - label_columns)
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join(align) + "|"]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def resolution_columns(ours, paper, max_resolution):
    """Every resolution we built, and the paper's up to the largest the command asked for."""
    return sorted(set(ours) | {r for r in paper if r <= max_resolution})


def row(label, values, columns):
    return [label] + [significant(values.get(r)) for r in columns]


def preamble(title, args, records, scenes, units):
    machines = sorted({(m.get("cpu", "unknown"), m.get("cores", 0),
                        m.get("memory_bytes", 0) / (1 << 30), m.get("os", "unknown"))
                       for rec in records.all if isinstance(m := rec.get("machine"), dict)})
    commits = sorted({str(rec.get("commit", "unknown")) for rec in records.all})
    failed = [rec for rec in records.all
              if (rec.get("verification") or {}).get("mismatches", 0) > 0]
    verified = [rec for rec in records.all if rec.get("verification")]
    lines = [f"# {title}", ""]
    lines.append(f"- Command: `{args.command}`" if args.command else
                 f"- Records: `{args.records}`")
    for cpu, cores, gib, os_name in machines or [("unknown", 0, 0, "unknown")]:
        lines.append(f"- Machine: {cpu}, {cores} cores, {gib:.1f} GiB, {os_name}")
    lines.append(f"- Commit: {', '.join(commits) or 'unknown'}; {len(records.all)} records "
                 f"in `{args.records}`")
    lines.append(f"- Verification: {len(verified)} of {len(records.all)} records verified, "
                 + (f"**{len(failed)} with mismatches (not lossless)**" if failed
                    else "none with mismatches"))
    def triangles(g):
        count = records.triangles.get(g)
        return f", {count / 1e6:.2f}M triangles" if isinstance(count, int) else ""

    ours = "; ".join(f"`{records.scene_names.get(g, g)}`{triangles(g)} for {paper} "
                     f"({PAPER_TRIANGLES[paper]} triangles)" for paper, g in scenes)
    lines.append(f"- Scenes: {ours} (our generator stands in for the paper's scene; the "
                 "scenes are not the same geometry, so compare trends, not digits)")
    lines.append(f"- Units: {units}")
    lines.append("")
    return lines


# --- the tables -----------------------------------------------------------------------------

def sintorn2014_fig9(records, args):
    builds = [("ClosedCity closed", "city", "closed"), ("ClosedCity not closed", "city", "open"),
              ("FractalLandscape closed", "terrain", "closed"),
              ("FractalLandscape not closed", "terrain", "open"),
              ("Necropolis not closed", "forest", "open"),
              ("Necropolis static geometry", "forest", "static")]
    ours = {b: {r: size_bytes(rec) for r, rec in records.find("cpvs", s, m).items()}
            for b, s, m in builds}
    paper = {b: sintorn_fig9_bytes(b) for b, _, _ in builds}
    columns = resolution_columns({r for v in ours.values() for r in v},
                                 SINTORN_FIG9_RESOLUTIONS, args.max_resolution)
    lines = preamble(
        "Sintorn et al. 2014, Fig. 9 — CPVS size (`cpvs`)", args, records,
        [("ClosedCity", "city"), ("FractalLandscape", "terrain"), ("Necropolis", "forest")],
        "MiB = 2^20 bytes; % of a 16-bit shadow map of the same resolution (2·R² bytes); "
        "3 significant digits. Paper rows: the paper's printed KB/MB are 10^3/10^6 bytes, taken "
        "from the printed size or the printed percentage, whichever is more precise. Modes: "
        "closed = closed-geometry optimisation, open = not closed, static = static-geometry "
        "optimisation (two first layers).")
    lines += ["Paper resolutions are 1K², 4K², 16K², 32K², 128K², 256K² (Necropolis up to 128K²); "
              "EpicCitadel has no stand-in. – = not built / not in the paper.", ""]
    for title, fmt in (("Size (MiB)", lambda b, r: b / MIB),
                       ("Size (% of a 16-bit shadow map)", lambda b, r: 100 * b / shadow_map_16(r))):
        rows = []
        for build, scene, mode in builds:
            rows.append(row(f"cpvs {scene} {mode}",
                            {r: fmt(b, r) for r, b in ours[build].items()}, columns))
            rows.append(row(f"paper: {build}",
                            {r: fmt(b, r) for r, b in paper[build].items()}, columns))
        if title.startswith("Size (MiB)"):
            rows.append(row("16-bit shadow map (analytic)",
                            {r: shadow_map_16(r) / MIB for r in columns}, columns))
        lines += [f"## {title}", "", markdown_table(["build"] + [heading(r) for r in columns],
                                                     rows)]
    return lines


def kampe2015_table1(records, args):
    columns = resolution_columns(
        {r for m in ("open", "closed") for c in ("on", "off")
         for r in records.find("cpvs-fast", "city", m, {"culling": c})},
        KAMPE_RESOLUTIONS, args.max_resolution)
    rows = []
    for paper_mode, mode in (("non-closed", "open"), ("closed", "closed")):
        for culling in ("off", "on"):
            found = records.find("cpvs-fast", "city", mode, {"culling": culling})
            total, insert_merge = KAMPE_TABLE1[(paper_mode, culling)]
            ours_im = {}
            for r, rec in found.items():
                parts = [phase(rec, "insert"), phase(rec, "merge")]
                ours_im[r] = None if None in parts else sum(parts)
            label = f"city {mode}, culling={culling}"
            paper_label = (f"paper: ClosedCity {paper_mode}, "
                           f"{'with' if culling == 'on' else 'without'} culling")
            rows.append(row(f"{label}: total",
                            {r: total_seconds(rec) for r, rec in found.items()}, columns))
            rows.append(row(f"{paper_label}: total",
                            parse_row(total, KAMPE_RESOLUTIONS, seconds), columns))
            rows.append(row(f"{label}: insert+merge", ours_im, columns))
            rows.append(row(f"{paper_label}: insert/merge",
                            parse_row(insert_merge, KAMPE_RESOLUTIONS, seconds), columns))
            rows.append(row(f"{label}: nodes inserted (millions)",
                            {r: counter(rec, "svo nodes inserted") for r, rec in found.items()},
                            columns))
    lines = preamble(
        "Kämpe et al. 2015, Table 1 — construction time with and without culling (`cpvs-fast`)",
        args, records, [("ClosedCity", "city")],
        "seconds of wall time, 3 significant digits. total = the whole build, depth map "
        "included; insert+merge = our encoder's \"insert\" and \"merge\" phases; nodes "
        "inserted = our counter \"svo nodes inserted\" (ours only). culling=on|off is "
        "`cpvs-fast`'s culling of identical nodes (Kämpe §3.2). Paper: a GPU (depth, masks, "
        "min-max) + CPU (insert, merge) build on an i5-2500K and a GTX Titan; ours is CPU only.")
    lines += ["– = not built / not in the paper.", "",
              markdown_table(["build"] + [heading(r) for r in columns], rows)]
    return lines


def kampe2015_table2(records, args):
    lines = preamble(
        "Kämpe et al. 2015, Table 2 — size with the closed-object optimisation, new vs old",
        args, records, [("ClosedCity", "city"), ("FractalLandscape", "terrain")],
        "MiB = 2^20 bytes (the paper's MB are 10^6 bytes, converted), 3 significant digits; "
        "old = `cpvs` (Sintorn 2014: undefined resolved to shadowed), new = `cpvs-fast` (Kämpe "
        "§3.4: undefined resolved to minimise the visibility masks per 8×8 tile); ratio = "
        "old / new. Mode closed.")
    lines += ["– = not built / not in the paper.", ""]
    for paper_scene, scene in (("ClosedCity", "city"), ("FractalLandscape", "terrain")):
        old = {r: size_bytes(rec) for r, rec in records.find("cpvs", scene, "closed").items()}
        new = {r: size_bytes(rec)
               for r, rec in records.find("cpvs-fast", scene, "closed", CULLING_ON).items()}
        new_mb, old_mb, ratios = KAMPE_TABLE2[paper_scene]
        paper_new, paper_old = (parse_row(t, KAMPE_RESOLUTIONS, decimal_bytes)
                                for t in (new_mb, old_mb))
        paper_ratio = parse_row(ratios, KAMPE_RESOLUTIONS, float)
        columns = resolution_columns(set(old) | set(new), KAMPE_RESOLUTIONS, args.max_resolution)

        def ratio(o, n, r):
            return o[r] / n[r] if r in o and r in n else None

        rows = [[heading(r),
                 significant(new.get(r) and new[r] / MIB), significant(old.get(r) and old[r] / MIB),
                 significant(ratio(old, new, r)),
                 significant(paper_new.get(r) and paper_new[r] / MIB),
                 significant(paper_old.get(r) and paper_old[r] / MIB),
                 significant(paper_ratio.get(r))] for r in columns]
        lines += [f"## {scene} closed (stands in for {paper_scene})", "",
                  markdown_table(["resolution", "new (MiB)", "old (MiB)", "ratio",
                                  f"paper: {paper_scene} new", f"paper: {paper_scene} old",
                                  "paper: ratio"], rows)]
    return lines


def kampe2015_table3(records, args):
    lines = preamble(
        "Kämpe et al. 2015, Table 3 — construction time by step (`cpvs-fast`)",
        args, records, [("ClosedCity", "city")],
        "seconds, 3 significant digits. depth map = the harness's dual depth map (tracing "
        "thread-seconds / threads), which computes enter and exit depth in one pass: the paper "
        "row is enter + exit depth map. Our depth map is traced in parallel while the encoder "
        "consumes earlier tiles, so our steps overlap and add up to more than the total (wall "
        "time); the paper's add up to theirs. transfer (GPU → host) has no counterpart in our "
        "CPU build.")
    lines += ["– = not built / not in the paper.", ""]
    # (our row, how a record gives it, the paper's steps it stands for)
    steps = [("depth map", depth_seconds, ("enter depth map", "exit depth map")),
             ("visibility masks", lambda rec: phase(rec, "visibility masks"),
              ("visibility masks",)),
             ("min-max", lambda rec: phase(rec, "min-max"), ("min-max",)),
             ("transfer", None, ("transfer",)),
             ("insert", lambda rec: phase(rec, "insert"), ("insert nodes",)),
             ("merge", lambda rec: phase(rec, "merge"), ("merge nodes",))]
    for paper_mode, mode in (("non-closed", "open"), ("closed", "closed")):
        found = records.find("cpvs-fast", "city", mode, CULLING_ON)
        paper = {step: parse_row(text, KAMPE_TABLE3_RESOLUTIONS, seconds)
                 for step, text in KAMPE_TABLE3[paper_mode].items()}
        columns = resolution_columns(found, KAMPE_TABLE3_RESOLUTIONS, args.max_resolution)
        header = ["step"]
        for r in columns:
            header += [f"{heading(r)} ours", f"{heading(r)} paper"]

        def cells(ours, theirs):
            out = []
            for r in columns:
                out += [significant(ours.get(r)), significant(theirs.get(r))]
            return out

        rows = []
        for label, ours_of, paper_steps in steps:
            ours = {r: ours_of(rec) for r, rec in found.items()} if ours_of else {}
            present = [step for step in paper_steps if step in paper]  # open: no exit depth
            theirs = {r: sum(paper[step][r] for step in present)
                      for r in KAMPE_TABLE3_RESOLUTIONS}
            if len(paper_steps) > 1:
                label += f" (paper: {' + '.join(present)})"
            rows.append([label] + cells(ours, theirs))
        total = {r: total_seconds(rec) for r, rec in found.items()}
        rows.append(["total"] + cells(total, paper["total"]))
        lines += [f"## city {mode} (stands in for ClosedCity {paper_mode})", "",
                  markdown_table(header, rows)]
    return lines


def kampe2015_table4(records, args):
    builds = [("cpvs-fast", "forest", "open", "Necropolis non-closed"),
              ("cpvs-fast", "city", "open", "ClosedCity non-closed"),
              ("cpvs-fast", "city", "closed", "ClosedCity closed"),
              ("cpvs-fast", "terrain", "open", "FractalLandscape non-closed"),
              ("cpvs-fast", "terrain", "closed", "FractalLandscape closed"),
              ("cpvs", "city", "closed", None),
              ("cpvs", "terrain", "closed", "Sintorn 2014 closed (FractalLandscape)")]
    found = {b: {r: total_seconds(rec) for r, rec in
                 records.find(*b[:3], CULLING_ON if b[0] == "cpvs-fast" else None).items()}
             for b in builds}
    columns = resolution_columns({r for v in found.values() for r in v}, KAMPE_RESOLUTIONS,
                                 args.max_resolution)
    rows = []
    for build in builds:
        scheme, scene, mode, paper = build
        rows.append(row(f"{scheme} {scene} {mode}", found[build], columns))
        if paper:
            rows.append(row(f"paper: {paper}",
                            parse_row(KAMPE_TABLE4[paper], KAMPE_RESOLUTIONS, seconds), columns))
    lines = preamble(
        "Kämpe et al. 2015, Table 4 — total construction time", args, records,
        [("ClosedCity", "city"), ("FractalLandscape", "terrain"), ("Necropolis", "forest")],
        "seconds of wall time for the whole build (depth map included), 3 significant digits. "
        "cpvs-fast = Kämpe 2015 (culling on), cpvs = Sintorn 2014. Paper: GPU + CPU build "
        "(Kämpe), CPU build (Sintorn); ours is CPU only.")
    lines += ["The paper's last row is Sintorn 2014's build-time table, which is of "
              "FractalLandscape closed (Kämpe's row does not name the scene and prints its 16K³ "
              "time, 18.0 s, under 8K³); it stands beside `cpvs terrain closed`. – = not built / "
              "not in the paper.", "",
              markdown_table(["build"] + [heading(r) for r in columns], rows)]
    return lines


def cpvs_lookup(records, args):
    filters = (1, 9, 17)
    sets = ("uniform", "view")
    header = ["scheme", "scene", "mode", "resolution"]
    for s in sets:
        header += [f"{s} {k}×{k}" for k in filters] + [f"{s} {k}×{k}/1×1" for k in filters[1:]]
    rows, worst, held = [], {}, set()
    # (scheme, parameters, scene, mode); parameters are named only for a scheme built with several
    variants = sorted({key[:4] for key in records.newest}, key=lambda v: (v[0] != "sm32", v))
    for scheme, params, scene, mode in variants:
        label = scheme
        if len({v[1] for v in variants if v[0] == scheme}) > 1:
            label += f" ({', '.join(f'{k}={v}' for k, v in params)})"
        for r in sorted(k[4] for k in records.newest if k[:4] == (scheme, params, scene, mode)):
            rec = records.newest[(scheme, params, scene, mode, r)]
            held |= {t.get("filter") for t in rec.get("lookup") or []}
            cells = [label, scene, mode, heading(r)]
            for s in sets:
                ns = {k: lookup_ns(rec, s, k) for k in filters}
                cells += [significant(ns[k]) for k in filters]
                for k in filters[1:]:
                    ratio = ns[k] / ns[1] if ns[k] and ns[1] else None
                    cells.append(significant(ratio))
                    if ratio and scheme != "sm32":
                        worst[(label, k)] = max(worst.get((label, k), 0), ratio)
            rows.append(cells)
    lines = preamble(
        "CPVS lookup cost by filter size (Sintorn et al. 2014 §7)", args, records,
        [("ClosedCity", "city"), ("Necropolis", "forest")],
        "ns per query on one thread (median of 5 runs), 3 significant digits, by query set "
        "(uniform: random points; view: samples of a 1920×1080 view) and PCF filter k×k; "
        "k×k/1×1 = the cost of a k×k filter over a point lookup. sm32 = the float32 shadow map, "
        "for reference.")
    held.discard(None)
    lines += [f"Filter sizes timed in these records: {', '.join(f'{k}×{k}' for k in sorted(held))}"
              " (the harness times 1, 3, 5, 9 and 17).", "",
              markdown_table(header, rows, label_columns=4), "## Worst ratios", ""]
    worst_rows = [[scheme] + [significant(worst.get((scheme, k))) for k in filters[1:]]
                  for scheme in sorted({s for s, _ in worst})]
    worst_rows.append(["paper: Sintorn 2014 (GPU shading time per frame, Fig. 8)"]
                      + [f"≤ {SINTORN_WORST_RATIO[k]}" for k in filters[1:]])
    lines += [markdown_table(["scheme", "9×9/1×1", "17×17/1×1"], worst_rows),
              "Sintorn's ratios are of a frame's shading time on a GPU (view samples, "
              "warp-coherent traversal), ours of one CPU thread's time per query; the ratio, not "
              "the time, is what compares.", ""]
    return lines


TABLES = {
    "sintorn2014-fig9": sintorn2014_fig9,
    "kampe2015-table1": kampe2015_table1,
    "kampe2015-table2": kampe2015_table2,
    "kampe2015-table3": kampe2015_table3,
    "kampe2015-table4": kampe2015_table4,
    "cpvs-lookup": cpvs_lookup,
}


def parse_resolution(text):
    value = int(text[:-1]) * K if text[-1:] in "kK" else int(text)
    if value < 8 or value & (value - 1):
        raise argparse.ArgumentTypeError(f"'{text}' is not a power of two such as 4K or 64K")
    return value


def main():
    parser = argparse.ArgumentParser(description="CPVS paper tables from shadowbench records.")
    parser.add_argument("table", choices=sorted(TABLES))
    parser.add_argument("records", type=Path, help="folder of JSON records")
    parser.add_argument("--max-resolution", type=parse_resolution, default=64 * K,
                        help="largest resolution shown (default 64K)")
    parser.add_argument("--command", help="the command that made the records, for the table")
    args = parser.parse_args()
    records = Records(args.records)
    if not records.all:
        sys.exit(f"paper_tables.py: no complete shadowbench records under '{args.records}'")
    print("\n".join(TABLES[args.table](records, args)), end="")
    return 0


if __name__ == "__main__":
    sys.exit(main())
