#!/usr/bin/env python3
"""The CPVS and MH-family paper tables from shadowbench records, the papers' figures beside ours,
and the tables that set every lossless scheme side by side.

    /usr/bin/python3 scripts/reproduce/paper_tables.py TABLE RECORDS_DIR
        [--max-resolution 64K] [--command "how the records were made"]

TABLE is one of sintorn2014-fig9, kampe2015-table1 … kampe2015-table4, cpvs-lookup (CPVS),
scandolo2016-table1 … table3, scandolo2016-fig8, scandolo2021-table1 … table4, mh-lookup (MH
family), compare-size, compare-lookup (every scheme, no paper); the Markdown goes to standard
output. Records are read as scripts/plot.py reads them (complete records only, the newest of a
cell). Columns are our resolutions and the paper's up to --max-resolution. The papers' figures
are data in this file, as printed (the CPVS papers' "KB"/"MB" are 10^3/10^6 bytes: Sintorn's
percentages of 2·R² bytes give Kämpe's "old" MB only in decimal MB; the MH papers' "MB" are
2^20 bytes, see their section below).
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
PAPER_TRIANGLES = {"ClosedCity": "613k", "FractalLandscape": "2.1M", "Necropolis": "2.1M",
                   # Scandolo et al. 2016 §4; Scandolo & Eisemann 2021 gives no counts
                   "CLOSED CITY": "613k", "CITYSCAPE": "11k", "VILLA": "89k", "SHIP": "810k"}
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

    def paper_scene(paper):
        count = PAPER_TRIANGLES.get(paper)
        return f"{paper} ({count} triangles)" if count else f"{paper} (triangles not given)"

    stands_for = {}  # generator → the paper scenes it stands in for, in the order given
    for paper, g in scenes:
        stands_for.setdefault(g, [])
        if paper:
            stands_for[g].append(paper_scene(paper))
    if not any(papers for papers in stands_for.values()):  # a table of ours alone
        ours = "; ".join(f"`{records.scene_names.get(g, g)}`{triangles(g)}" for g in stands_for)
        lines.append(f"- Scenes: {ours} (no paper figures in this table)")
    else:
        ours = "; ".join(f"`{records.scene_names.get(g, g)}`{triangles(g)} "
                         + (f"for {' and '.join(papers)}" if papers else
                            "(no counterpart in the paper)")
                         for g, papers in stands_for.items())
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


# --- Scandolo et al. 2016 (MMH) and Scandolo & Eisemann 2021 (DAG-MH) -------------------------
# Their "MB" is read as 2^20 bytes (MiB): the 2021 paper's Uncompressed row is 4·R² bytes / 2^20
# (64 at 4K², 1048576 at 512K²), and its Table 3 treelet sizes at 16K² are 12-byte treelets
# (§3.2) / 2^20 (21595 × 12 B = 0.247, 14666 × 44 B = 0.615); the 2016 paper, by the same
# authors, does not say and is read the same way. Cells are as printed ("-": not in the paper).

# Scandolo, Bauszat, Eisemann 2016, Merged Multiresolution Hierarchies, at 4K² 16K² 64K² 256K².
MMH_RESOLUTIONS = [4 * K, 16 * K, 64 * K, 256 * K]
# Table 1, size in MB: DAG [KSA13], MH [SBE16], MMH ("Ours", local search distance 1000).
MMH_TABLE1 = {
    "CLOSED CITY": {"DAG": "0.62 3.40 14.90 60.46", "MH": "0.41 2.10 9.33 38.43",
                    "MMH": "0.30 1.43 5.80 23.73"},
    "CITYSCAPE": {"DAG": "0.94 3.94 16.38 63.34", "MH": "0.60 2.73 11.53 47.07",
                  "MMH": "0.40 1.67 6.83 27.71"},
    "VILLA": {"DAG": "1.78 9.27 39.70 166.47", "MH": "0.88 5.01 23.61 101.52",
              "MMH": "0.63 3.62 17.36 74.11"},
    "SHIP": {"DAG": "2.01 8.66 35.57 153.67", "MH": "1.11 5.64 24.57 102.36",
             "MMH": "0.82 3.83 16.34 67.64"},
}
# Table 2, creation time in seconds: DAG [KSA15], MH, MMH.
MMH_TABLE2 = {
    "CLOSED CITY": {"DAG": "0.098 0.53 4.88 65.23", "MH": "0.27 1.24 5.80 56.17",
                    "MMH": "0.37 1.59 8.72 72.54"},
    "SHIP": {"DAG": "0.12 0.67 6.16 78.74", "MH": "0.31 1.59 7.08 69.30",
             "MMH": "0.54 3.1 15.6 109.9"},
}
# Table 3, early rejections as % of the node pairs tested: interval mismatch, offset too large,
# full test rejection (tested in that order).
MMH_TABLE3 = {
    "CLOSED CITY": {16 * K: "67.2 0.00 32.63", 64 * K: "64.8 0.28 34.76",
                    256 * K: "63.5 11.9 24.39"},
    "CITYSCAPE": {16 * K: "64.88 0.00 34.90", 64 * K: "62.15 1.49 36.21",
                  256 * K: "61.94 13.51 24.44"},
}
# Fig. 8 is a plot (size against merging time, CLOSED CITY and VILLA at 64K²) without printed
# numbers; the text calls 500–1000 a reasonable trade-off and uses 1000 throughout.
MMH_SEARCH_DISTANCES = [0, 10, 100, 250, 500, 1000, 2000, 5000, 10000]

# Scandolo, Eisemann 2021, DAG Encoding for Compressed Shadow Maps.
DAGMH_RESOLUTIONS = [4 * K << i for i in range(8)]  # 4K² … 512K²
# Table 1, size in MB: DAG [KSA15], MMH [SBE16b], DAG-MH.
DAGMH_TABLE1 = {
    "Citadel": {"DAG": "0.737 1.79 3.88 8.25 17.00 34.4 69.6 139.7",
                "MMH": "0.351 0.765 1.58 3.24 6.52 13.26 26.93 54.49",
                "DAG-MH": "0.252 0.571 1.21 2.43 4.68 8.84 16.59 31.16"},
    "City": {"DAG": "0.929 2.01 3.90 8.10 16.73 33.72 67.89 135.9",
             "MMH": "0.411 0.845 1.71 3.44 6.99 13.90 27.90 55.54",
             "DAG-MH": "0.329 0.663 1.29 2.47 4.70 8.83 16.73 31.45"},
    "Trees": {"DAG": "2.06 5.03 10.71 22.41 45.62 93.46 190.6 384.6",
              "MMH": "0.767 1.898 4.394 9.73 20.85 43.36 88.34 177.6",
              "DAG-MH": "0.480 1.23 2.96 6.54 13.66 27.53 54.19 104.9"},
    "Dinos": {"DAG": "1.82 3.67 7.29 15.21 31.93 67.24 139.1 281.4",
              "MMH": "0.875 1.79 3.69 7.65 15.90 32.41 65.41 131.2",
              "DAG-MH": "0.542 1.07 2.09 4.04 7.71 14.57 27.40 51.50"},
    "Hairball": {"DAG": "21.21 40.69 71.52 133.60 262.50 532.23 1086.56 -",
                 "MMH": "5.56 12.37 27.28 58.53 122.46 251.10 - -",
                 "DAG-MH": "3.73 8.66 18.01 35.33 67.32 127.09 239.9 -"},
}
DAGMH_UNCOMPRESSED = "64 256 1024 4096 16384 65536 262144 1048576"
# Table 2, compression time in seconds (Citadel) at 4K² 16K² 64K² 256K².
DAGMH_TABLE2_RESOLUTIONS = MMH_RESOLUTIONS
DAGMH_TABLE2 = {"DAG": "0.047 0.351 4.110 59.85", "MH": "0.251 0.774 5.488 59.30",
                "MMH": "0.257 1.465 10.67 84.42", "DAG-MH": "0.247 0.875 6.225 62.33"}
# §4.1: the dual shadow map is about 80% of DAG-MH's total creation time.
DAGMH_DEPTH_SHARE = 80
# Table 3 (Citadel), by treelet height 2 3 4 5: sizes in MB, counts.
DAGMH_TREELET_HEIGHTS = [2, 3, 4, 5]
DAGMH_TABLE3 = {
    16 * K: {"DAG structure size": "0.756 0.696 0.622 0.788",
             "Inner nodes": "52746 47086 26425 12452", "Nodes size": "0.756 0.668 0.375 0.172",
             "Treelets": "23 5683 21595 14666", "Treelets size": "<0.001 0.027 0.247 0.615"},
    64 * K: {"DAG structure size": "2.475 2.399 2.261 3.493",
             "Inner nodes": "177882 170726 124947 66475", "Nodes size": "2.475 1.585 0.831 0.704",
             "Treelets": "23 7179 47157 61164", "Treelets size": "<0.001 0.814 1.430 2.789"},
}
# Table 4 (Citadel), by values per chunk 16 32 64 128. The 64K² "chunks factors size" at 16 is
# printed 0.169, but the row's own sum (2.897 − 1.728) says 1.169.
DAGMH_CHUNK_SIZES = [16, 32, 64, 128]
DAGMH_TABLE4 = {
    16 * K: {"DAG values size": "0.688 0.588 0.578 0.592",
             "Chunks map size": "0.397 0.220 0.132 0.088",
             "Chunks factors size": "0.291 0.368 0.446 0.504",
             "Avg. factor qty": "57.6% 61.5% 64.6% 67.7%",
             "Avg. factor bits": "10.95 13.09 15.33 16.71"},
    64 * K: {"DAG values size": "2.897 2.423 2.362 2.388",
             "Chunks map size": "1.728 0.960 0.576 0.384",
             "Chunks factors size": "0.169 1.463 1.786 2.004",
             "Avg. factor qty": "52.6% 56.3% 59.5% 62.3%",
             "Avg. factor bits": "10.87 12.89 15.13 16.48"},
}
# Lookup cost, as the papers state it in words (GPU, a full HD view, hierarchical PCF):
# MMH 2016 §4: at 256K² below 1 ms per frame for single queries, 1–2.5 ms with 3×3 PCF, and no
# measurable difference to MH. DAG-MH 2021 §4.2 (Citadel, 64K²): about 0.5 ms single, 1 ms 3×3,
# 2.5 ms 5×5; single queries about as fast as MMH, 3×3 and 5×5 about half as fast.
DAGMH_LOOKUP_MS = {1: 0.5, 3: 1.0, 5: 2.5}

# The parameters the papers' rows are built with (each scheme's default): a table picks its
# records by them, so that variants of Fig. 8 and Tables 3 and 4 in the same folder stay apart.
MH_FAMILY_PARAMS = {
    "mh": None,
    "mmh": {"search-distance": "1000"},
    "dag-mh": {"treelet-height": "4", "chunk-size": "32", "skip-level": "6"},
    "cpvs": {"grid-levels": "0", "leaf-layout": "slab8"},
    "cpvs-fast": {"grid-levels": "0", "leaf-layout": "slab8", "culling": "on",
                  "transitions": "aligned"},
}
# The scripts build these (scheme, scene, mode) only up to a resolution (their budget, below).
CAPPED = {("cpvs", "tangle", "closed"): 16 * K,
          **{(scheme, "city", "open"): 8 * K for scheme in ("mh", "mmh", "dag-mh", "cpvs")}}
CAP_NOTE = ("Forest is in static mode (first and second surface, as the 2021 paper builds its "
            "dual maps): its trees and ground are open meshes, so in closed mode its intervals "
            "are points (mh 72 MiB at 4K², more than the float map). Caps, for the scripts' time "
            "and memory (those cells print –): `cpvs` (the papers' DAG) on tangle closed up to "
            "16K², as its voxel DAG grows fast there (forest open at 64K²: 18 minutes, 5.8 GiB); "
            "the MH family and cpvs on city open up to 8K². There the ground is a point "
            "interval whose depth changes from texel to texel, so the hierarchy keeps about a "
            "node per texel: `mh` is 70 MiB at 4K², ×4 per doubling from 1K² (more than the "
            "64 MiB float map), and `mmh` peaks at 1.3 GiB at 4K², so about 20 GiB at 16K². "
            "`cpvs-fast` (Kämpe 2015, the [KSA15] of the 2021 paper and of the 2016 paper's "
            "Table 2) is shown where the CPVS tables built it; these scripts do not build it.")


def cap_note(scheme, scene, mode, cells, columns, caps=None):
    """', not built above 8K²' where a cap (of CAPPED, or of `caps`) leaves columns of the row
    empty."""
    cap = (CAPPED if caps is None else caps).get((scheme, scene, mode))
    return (f", not built above {heading(cap)}"
            if cap and any(r > cap and r not in cells for r in columns) else "")


MH_TIME_UNITS = ("seconds of wall time, 3 significant digits. total = the whole build with the "
                 "dual depth map included (the record's time_s.total); without depth = total − "
                 "the depth-map time (time_s.depth, tracing thread-seconds / threads) — "
                 "approximate, as the map is traced while the encoder consumes earlier tiles. "
                 "Every cell traces its own depth map. Paper: GPU (CUDA) + CPU builds on an "
                 "i7-5820K with a Titan X (2016) / Titan V (2021), the dual shadow map included "
                 "(the 2021 paper: about 80% of DAG-MH's time); ours is CPU only, 2 cores.")


def mh_cells(records, scheme, scene, mode, params=None):
    """{resolution: record} of `scheme` with the papers' parameters (or `params` over them)."""
    base = MH_FAMILY_PARAMS.get(scheme)
    return records.find(scheme, scene, mode, {**(base or {}), **(params or {})} or None)


def mib(record):
    return size_bytes(record) / MIB


def component_bytes(record, *names):
    """The sum of the named size components, None if the record lacks one."""
    parts = (record.get("size_bytes") or {}).get("components") or {}
    values = [parts.get(name) for name in names]
    return None if any(not isinstance(v, (int, float)) for v in values) else sum(values)


def component_mib(record, *names):
    value = component_bytes(record, *names)
    return None if value is None else value / MIB


def count(record, name):
    return counter(record, name, 1)


def ratio_of(numerator, denominator, scale=1.0):
    return (scale * numerator / denominator
            if numerator is not None and denominator not in (None, 0) else None)


def without_depth(record):
    total, depth = total_seconds(record), depth_seconds(record)
    return total - depth if isinstance(total, (int, float)) and isinstance(depth,
                                                                            (int, float)) else None


def paper_mib(text, resolutions):
    """A printed row of MB (read as 2^20 bytes, i.e. MiB) as {resolution: MiB}."""
    return parse_row(text, resolutions, float)


def verbatim(text, columns):
    return text.split() if columns is None else dict(zip(columns, text.split()))


def mh_columns(records, schemes, builds, paper_resolutions, args):
    """Our resolutions of the MH-family schemes on the builds, and the paper's up to the maximum
    (the CPVS tables' 1K²… cells of cpvs do not add columns)."""
    ours = {r for scheme in schemes for scene, mode, *_ in builds
            for r in mh_cells(records, scheme, scene, mode)}
    return resolution_columns(ours, paper_resolutions, args.max_resolution)


def size_rows(records, scene, mode, schemes, columns):
    """A size row (MiB) per scheme; cpvs-fast only where built; cpvs over its cap is '–'."""
    rows = []
    for scheme, label in schemes:
        cells = mh_cells(records, scheme, scene, mode)
        if scheme == "cpvs-fast" and not cells:
            continue
        values = {r: mib(rec) for r, rec in cells.items()}
        note = cap_note(scheme, scene, mode, cells, columns)
        rows.append(row(f"{scheme} {scene} {mode} ({label}{note})", values, columns))
    return rows


def scandolo2016_table1(records, args):
    builds = [("city", "closed", ["CLOSED CITY", "CITYSCAPE"]), ("terrain", "closed", []),
              ("forest", "static", ["VILLA", "SHIP"]), ("city", "open", [])]
    schemes = [("cpvs", "DAG"), ("cpvs-fast", "DAG, Kämpe 2015"), ("mh", "MH"),
               ("mmh", "MMH, search distance 1000")]
    columns = mh_columns(records, ("mh", "mmh"), builds, MMH_RESOLUTIONS, args)
    lines = preamble(
        "Scandolo et al. 2016 (MMH), Table 1 — size of DAG, MH and MMH", args, records,
        [("CLOSED CITY", "city"), ("CITYSCAPE", "city"), (None, "terrain"), ("VILLA", "forest"),
         ("SHIP", "forest")],
        "MiB = 2^20 bytes, 3 significant digits. Paper: \"MB\", read as 2^20 bytes (the 2021 "
        "paper's Uncompressed row is 4·R²/2^20; this paper does not say), as printed. Schemes: "
        "mh = Scandolo 2016a (no merging), mmh = merged MH with the paper's local search distance "
        "1000, cpvs = Sintorn 2014's voxel DAG (the paper's DAG column). Mode closed, as in the "
        "paper (forest static: see below); the city open row has no paper counterpart (open: hi = lo wherever a ray hits, "
        "so subtrees merge only where their relative depths are equal).")
    lines += [CAP_NOTE + " – = not built / not in the paper.", ""]
    ratio_rows = []
    for scene, mode, papers in builds:
        rows = size_rows(records, scene, mode, schemes, columns)
        for paper in papers:
            for method in ("DAG", "MH", "MMH"):
                rows.append(row(f"paper: {paper} {method}",
                                paper_mib(MMH_TABLE1[paper][method], MMH_RESOLUTIONS), columns))
        stands = f" (stands in for {', '.join(papers)})" if papers else " (no paper counterpart)"
        lines += [f"## {scene} {mode}{stands}", "",
                  markdown_table(["build"] + [heading(r) for r in columns], rows)]
        mh, mmh, cpvs = (mh_cells(records, s, scene, mode) for s in ("mh", "mmh", "cpvs"))
        ratio_rows.append(row(f"{scene} {mode}: mmh / mh", {
            r: ratio_of(mib(mmh[r]), mib(mh[r]), 100) for r in columns if r in mh and r in mmh},
            columns))
        ratio_rows.append(row(f"{scene} {mode}: mmh / cpvs", {
            r: ratio_of(mib(mmh[r]), mib(cpvs[r]), 100) for r in columns
            if r in cpvs and r in mmh}, columns))
        for paper in papers:
            sizes = {m: paper_mib(MMH_TABLE1[paper][m], MMH_RESOLUTIONS) for m in ("DAG", "MH",
                                                                                   "MMH")}
            for other in ("MH", "DAG"):
                ratio_rows.append(row(f"paper: {paper} MMH / {other}", {
                    r: ratio_of(sizes["MMH"][r], sizes[other][r], 100) for r in sizes["MMH"]},
                    columns))
    lines += ["## MMH as % of MH and of the DAG", "",
              "The paper: MMH up to 40% smaller than MH and up to 60% smaller than the DAG; "
              "31.3% higher compression than MH on average over its scenes and resolutions.", "",
              markdown_table(["size ratio (%)"] + [heading(r) for r in columns], ratio_rows)]
    return lines


def time_rows(records, scene, mode, schemes, columns):
    rows = []
    for scheme, label in schemes:
        cells = mh_cells(records, scheme, scene, mode)
        if scheme == "cpvs-fast" and not cells:
            continue
        label += cap_note(scheme, scene, mode, cells, columns)
        rows.append(row(f"{scheme} ({label}): total",
                        {r: total_seconds(rec) for r, rec in cells.items()}, columns))
        rows.append(row(f"{scheme} ({label}): without depth",
                        {r: without_depth(rec) for r, rec in cells.items()}, columns))
    return rows


def scandolo2016_table2(records, args):
    builds = [("city", "closed", "CLOSED CITY"), ("forest", "static", "SHIP")]
    schemes = [("cpvs", "DAG"), ("cpvs-fast", "DAG, Kämpe 2015"), ("mh", "MH"), ("mmh", "MMH")]
    columns = mh_columns(records, ("mh", "mmh"), builds, MMH_RESOLUTIONS, args)
    lines = preamble(
        "Scandolo et al. 2016 (MMH), Table 2 — creation time of DAG, MH and MMH", args, records,
        [("CLOSED CITY", "city"), ("SHIP", "forest")],
        MH_TIME_UNITS + " The paper's DAG times are Kämpe 2015's GPU build ([KSA15]); our DAG "
        "row is `cpvs` (Sintorn 2014, CPU), with `cpvs-fast` where built.")
    lines += [CAP_NOTE + " – = not built / not in the paper.", ""]
    for scene, mode, paper in builds:
        rows = time_rows(records, scene, mode, schemes, columns)
        for method in ("DAG", "MH", "MMH"):
            rows.append(row(f"paper: {paper} {method}",
                            parse_row(MMH_TABLE2[paper][method], MMH_RESOLUTIONS, float), columns))
        mh, mmh = (mh_cells(records, s, scene, mode) for s in ("mh", "mmh"))
        for label, of in (("total", total_seconds), ("without depth", without_depth)):
            rows.append(row(f"mmh / mh ({label})", {
                r: ratio_of(of(mmh[r]), of(mh[r])) for r in columns if r in mh and r in mmh},
                columns))
        paper_mh, paper_mmh = (parse_row(MMH_TABLE2[paper][m], MMH_RESOLUTIONS, float)
                               for m in ("MH", "MMH"))
        rows.append(row(f"paper: {paper} MMH / MH",
                        {r: paper_mmh[r] / paper_mh[r] for r in paper_mh}, columns))
        lines += [f"## {scene} {mode} (stands in for {paper})", "",
                  markdown_table(["build"] + [heading(r) for r in columns], rows)]
    lines += ["The paper: MMH adds 30% to 150% to the creation time of MH and DAG at the higher "
              "resolutions.", ""]
    return lines


def scandolo2016_table3(records, args):
    found = mh_cells(records, "mmh", "city", "closed")
    paper_resolutions = sorted({r for rows in MMH_TABLE3.values() for r in rows})
    # ours from 16K² as in the paper, or every resolution in a quick run below 16K²
    resolutions = sorted({r for r in found if r >= 16 * K or args.max_resolution < 16 * K}
                         | {r for r in paper_resolutions if r <= args.max_resolution})
    header = ["build", "resolution", "pairs tested (M)", "interval mismatch",
              "offset too large", "full test rejection", "merged", "nodes removed (M)"]
    rows = []
    for r in resolutions:
        rec = found.get(r)
        if rec:
            tested = count(rec, "pairs tested")
            shares = [ratio_of(count(rec, name), tested, 100)
                      for name in ("rejected interval", "rejected offset", "rejected full test",
                                   "merges")]
            rows.append(["mmh city closed", heading(r), significant(counter(rec, "pairs tested"))]
                        + [significant(s) + (" %" if s is not None else "") for s in shares]
                        + [significant(counter(rec, "nodes removed"))])
        elif r in paper_resolutions:
            rows.append(["mmh city closed", heading(r)] + [MISSING] * 6)
        for paper, printed in MMH_TABLE3.items():
            if r in printed:
                rows.append([f"paper: {paper}", heading(r), MISSING]
                            + [f"{cell} %" for cell in printed[r].split()] + [MISSING, MISSING])
    lines = preamble(
        "Scandolo et al. 2016 (MMH), Table 3 — early rejection of subtree pairs (`mmh`)", args,
        records, [("CLOSED CITY", "city"), ("CITYSCAPE", "city")],
        "% of the subtree pairs tested (our counter \"pairs tested\"), 3 significant digits: "
        "interval mismatch = \"rejected interval\", offset too large = \"rejected offset\" (the "
        "24-bit offset bound), full test rejection = \"rejected full test\", merged = \"merges\" "
        "(ours only; the paper's three columns and its merges add up to 100%); M = millions. The "
        "tests run in "
        "that order: a pair rejected by one is not tested by the next. Search distance 1000, "
        "mode closed.")
    lines += ["The paper's rows are at 16K², 64K², 256K² (shown up to --max-resolution); our 4K² "
              "row appears only in a quick run. – = not built / not in the paper.", "",
              markdown_table(header, rows, label_columns=2)]
    return lines


def scandolo2016_fig8(records, args):
    lines = preamble(
        "Scandolo et al. 2016 (MMH), Fig. 8 — size against merging time by local search "
        "distance (`mmh`)", args, records, [("CLOSED CITY", "city")],
        "size in MiB = 2^20 bytes; match = the encoder's \"match\" phase (the pair matching "
        "and merging, the paper's \"subtree merging time\"), build = the whole build (depth map "
        "included), seconds; above smallest = size over the smallest size of the sweep, in %. "
        "3 significant digits. Mode closed.")
    mh = mh_cells(records, "mh", "city", "closed")
    swept = {}
    for distance in MMH_SEARCH_DISTANCES:
        for r, rec in mh_cells(records, "mmh", "city", "closed",
                               {"search-distance": str(distance)}).items():
            swept.setdefault(r, {})[distance] = rec
    resolutions = [r for r in sorted(swept) if len(swept[r]) > 1 and r <= args.max_resolution]
    lines += ["The paper plots CLOSED CITY and VILLA at 64K² without printed numbers: the size "
              "falls with diminishing returns while the merging time grows, and 500–1000 is "
              "called a reasonable trade-off (1000 is used throughout). Ours is at 16K² unless "
              "FIG8_RESOLUTION says otherwise (scandolo2016-fig8.sh says why). For scale, the "
              "paper's Table 1 sizes of CLOSED CITY at the same resolution (MH, and MMH at "
              "distance 1000) stand below ours. – = not built.", ""]
    if not resolutions:
        lines += ["No resolution has more than one search distance built yet.", ""]
    for r in resolutions:
        cells = swept[r]
        smallest = min(mib(rec) for rec in cells.values())
        rows = []
        for distance in MMH_SEARCH_DISTANCES:
            rec = cells.get(distance)
            if rec is None:
                rows.append([str(distance)] + [MISSING] * 6)
                continue
            above = 100 * (mib(rec) / smallest - 1)
            rows.append([str(distance), significant(mib(rec)), significant(phase(rec, "match")),
                         significant(total_seconds(rec)),
                         significant(above) if above > 0 else "0",
                         significant(counter(rec, "pairs tested")),
                         significant(counter(rec, "merges"))])
        if r in mh:
            rows.append(["mh (no merging)", significant(mib(mh[r])), MISSING,
                         significant(total_seconds(mh[r])),
                         significant(100 * (mib(mh[r]) / smallest - 1)), MISSING, MISSING])
        for method, label in (("MMH", "paper: CLOSED CITY MMH, 1000 (Table 1)"),
                              ("MH", "paper: CLOSED CITY MH (Table 1)")):
            printed = paper_mib(MMH_TABLE1["CLOSED CITY"][method], MMH_RESOLUTIONS)
            if r in printed:
                rows.append([label, significant(printed[r])] + [MISSING] * 5)
        lines += [f"## city closed, {heading(r)}", "",
                  markdown_table(["search distance", "size (MiB)", "match (s)", "build (s)",
                                  "above smallest (%)", "pairs tested (M)", "merges (M)"],
                                 rows)]
    return lines


def scandolo2021_table1(records, args):
    builds = [("city", "closed", ["Citadel", "City"]), ("terrain", "closed", []),
              ("forest", "static", ["Trees"]), ("tangle", "closed", ["Hairball"]),
              ("city", "open", [])]
    schemes = [("cpvs", "DAG"), ("cpvs-fast", "DAG, Kämpe 2015"),
               ("mmh", "MMH, search distance 1000"),
               ("dag-mh", "DAG-MH, treelets of 4, chunks of 32")]
    columns = mh_columns(records, ("mmh", "dag-mh"), builds, DAGMH_RESOLUTIONS, args)
    lines = preamble(
        "Scandolo & Eisemann 2021 (DAG-MH), Table 1 — size of DAG, MMH and DAG-MH", args,
        records, [("Citadel", "city"), ("City", "city"), (None, "terrain"), ("Trees", "forest"),
                  ("Hairball", "tangle")],
        "MiB = 2^20 bytes, 3 significant digits. Paper: \"MB\", read as 2^20 bytes — its "
        "Uncompressed row is exactly 4·R²/2^20 (64 at 4K²), as printed. Schemes: cpvs = the "
        "voxel DAG (the paper's DAG column), mmh = Scandolo 2016 with search distance 1000, "
        "dag-mh = this paper (treelet height 4, 32 values per chunk, skip list at level 6). Mode "
        "closed (forest static: see below); the city open row has no paper counterpart (open: hi = lo wherever a ray hits). "
        "Dinos has no stand-in.")
    lines += [CAP_NOTE + " – = not built / not in the paper.", ""]
    ratio_rows = []
    for scene, mode, papers in builds:
        rows = size_rows(records, scene, mode, schemes, columns)
        for paper in papers:
            for method in ("DAG", "MMH", "DAG-MH"):
                rows.append(row(f"paper: {paper} {method}",
                                paper_mib(DAGMH_TABLE1[paper][method], DAGMH_RESOLUTIONS),
                                columns))
        stands = f" (stands in for {', '.join(papers)})" if papers else " (no paper counterpart)"
        lines += [f"## {scene} {mode}{stands}", "",
                  markdown_table(["build"] + [heading(r) for r in columns], rows)]
        dag_mh, mmh, cpvs = (mh_cells(records, s, scene, mode) for s in ("dag-mh", "mmh", "cpvs"))
        for other, cells in (("mmh", mmh), ("cpvs", cpvs)):
            ratio_rows.append(row(f"{scene} {mode}: dag-mh / {other}", {
                r: ratio_of(mib(dag_mh[r]), mib(cells[r]), 100) for r in columns
                if r in dag_mh and r in cells}, columns))
        for paper in papers:
            sizes = {m: paper_mib(DAGMH_TABLE1[paper][m], DAGMH_RESOLUTIONS)
                     for m in ("DAG", "MMH", "DAG-MH")}
            for other in ("MMH", "DAG"):
                ratio_rows.append(row(f"paper: {paper} DAG-MH / {other}", {
                    r: ratio_of(sizes["DAG-MH"][r], sizes[other].get(r), 100)
                    for r in sizes["DAG-MH"]}, columns))
    lines += ["## Uncompressed", "",
              markdown_table(["build"] + [heading(r) for r in columns], [
                  row("32-bit float map, 4·R² bytes (analytic)",
                      {r: 4.0 * r * r / MIB for r in columns}, columns),
                  row("paper: Uncompressed", paper_mib(DAGMH_UNCOMPRESSED, DAGMH_RESOLUTIONS),
                      columns)]),
              "## DAG-MH as % of MMH and of the DAG", "",
              "The paper: DAG-MH 20% to 50% smaller than MMH, and half the memory in the best "
              "case (Hairball).", "",
              markdown_table(["size ratio (%)"] + [heading(r) for r in columns], ratio_rows)]
    return lines


def scandolo2021_table2(records, args):
    schemes = [("cpvs", "DAG"), ("cpvs-fast", "DAG, Kämpe 2015"), ("mh", "MH"), ("mmh", "MMH"),
               ("dag-mh", "DAG-MH")]
    columns = mh_columns(records, ("mh", "mmh", "dag-mh"), [("city", "closed")],
                         DAGMH_TABLE2_RESOLUTIONS, args)
    rows = time_rows(records, "city", "closed", schemes, columns)
    for method in ("DAG", "MH", "MMH", "DAG-MH"):
        rows.append(row(f"paper: Citadel {method}",
                        parse_row(DAGMH_TABLE2[method], DAGMH_TABLE2_RESOLUTIONS, float), columns))
    dag_mh = mh_cells(records, "dag-mh", "city", "closed")
    rows.append(row("dag-mh: depth map share of total (%)", {
        r: ratio_of(depth_seconds(rec), total_seconds(rec), 100) for r, rec in dag_mh.items()},
        columns))
    rows.append(["paper: Citadel DAG-MH dual shadow map share (%)"]
                + [f"≈ {DAGMH_DEPTH_SHARE}" for _ in columns])
    lines = preamble(
        "Scandolo & Eisemann 2021 (DAG-MH), Table 2 — compression time", args, records,
        [("Citadel", "city")],
        MH_TIME_UNITS + " Mode closed; DAG = `cpvs` (and `cpvs-fast` where built), the "
        "paper's DAG is [KSA15]'s GPU build. The paper's \"≈ 80%\" is stated for DAG-MH "
        "(§4.1), not per resolution.")
    lines += [CAP_NOTE + " – = not built / not in the paper.", "",
              "## city closed (stands in for Citadel)", "",
              markdown_table(["build"] + [heading(r) for r in columns], rows)]
    return lines


def variant_sections(records, table_resolutions, param, values, args):
    """{resolution: {value: record}} of dag-mh on city closed with `param` swept, the other
    parameters at their defaults; the paper's resolutions up to the maximum too."""
    found = {}
    for value in values:
        for r, rec in mh_cells(records, "dag-mh", "city", "closed",
                               {param: str(value)}).items():
            found.setdefault(r, {})[value] = rec
    shown = sorted({r for r, cells in found.items() if len(cells) > 1}
                   | {r for r in table_resolutions if r <= args.max_resolution})
    return found, shown


def paired_table(found, shown, values, paper_table, ours_rows, title_of):
    """One section per resolution: a row per quantity, a column pair (ours, paper) per value."""
    lines = [] if shown else ["No resolution has more than one variant built yet.", ""]
    header = ["row"]
    for value in values:
        header += [f"{value} ours", f"{value} paper"]
    for r in shown:
        cells = found.get(r, {})
        printed = paper_table.get(r, {})
        rows = []
        for label, paper_label, of in ours_rows:
            line = [label]
            paper_cells = printed[paper_label].split() if paper_label in printed else None
            for i, value in enumerate(values):
                rec = cells.get(value)
                got = of(rec) if rec else None  # counts as integers, the rest to 3 digits
                line += [str(got) if isinstance(got, int) else significant(got),
                         paper_cells[i] if paper_cells else MISSING]
            rows.append(line)
        lines += [f"## {title_of(r)}", "", markdown_table(header, rows)]
    return lines


def scandolo2021_table3(records, args):
    found, shown = variant_sections(records, sorted(DAGMH_TABLE3), "treelet-height",
                                    DAGMH_TREELET_HEIGHTS, args)
    ours_rows = [
        ("DAG structure size (MiB)", "DAG structure size",
         lambda rec: component_mib(rec, "inner nodes", "treelets")),
        ("inner nodes", "Inner nodes", lambda rec: count(rec, "inner nodes")),
        ("nodes size (MiB)", "Nodes size", lambda rec: component_mib(rec, "inner nodes")),
        ("treelets", "Treelets", lambda rec: count(rec, "treelets")),
        ("treelets size (MiB)", "Treelets size", lambda rec: component_mib(rec, "treelets")),
        ("total size (MiB, ours: all components)", None, mib),
    ]
    lines = preamble(
        "Scandolo & Eisemann 2021 (DAG-MH), Table 3 — DAG structure by treelet height "
        "(`dag-mh`)", args, records, [("Citadel", "city")],
        "MiB = 2^20 bytes (the paper's MB read as 2^20: 21595 treelets × 12 bytes = its 0.247 "
        "at 16K²), counts as numbers, 3 significant digits; paper cells as printed. DAG "
        "structure size = the size components \"inner nodes\" + \"treelets\"; inner nodes and "
        "treelets = our counters of the same names. Columns: treelet height (parameter "
        "treelet-height; 32 values per chunk, skip list at level 6). Mode closed.")
    lines += ["The paper's sections are 16K² and 64K² (shown up to --max-resolution). "
              "– = not built / not in the paper.", ""]
    lines += paired_table(found, shown, DAGMH_TREELET_HEIGHTS, DAGMH_TABLE3, ours_rows,
                          lambda r: f"city closed (stands in for Citadel), {heading(r)}")
    return lines


def scandolo2021_table4(records, args):
    found, shown = variant_sections(records, sorted(DAGMH_TABLE4), "chunk-size",
                                    DAGMH_CHUNK_SIZES, args)

    def factor_share(rec):
        return ratio_of(count(rec, "factor values"), count(rec, "values"), 100)

    ours_rows = [
        ("DAG values size (MiB)", "DAG values size",
         lambda rec: component_mib(rec, "chunk infos", "chunk factors")),
        ("chunks map size (MiB)", "Chunks map size",
         lambda rec: component_mib(rec, "chunk infos")),
        ("chunks factors size (MiB)", "Chunks factors size",
         lambda rec: component_mib(rec, "chunk factors")),
        ("avg. factor qty (%)", "Avg. factor qty", factor_share),
        ("avg. factor bits", "Avg. factor bits",
         lambda rec: ratio_of(count(rec, "factor bits"), count(rec, "factor values"))),
        ("values", None, lambda rec: count(rec, "values")),
        ("total size (MiB, ours: all components)", None, mib),
    ]
    lines = preamble(
        "Scandolo & Eisemann 2021 (DAG-MH), Table 4 — depth values by chunk size (`dag-mh`)",
        args, records, [("Citadel", "city")],
        "MiB = 2^20 bytes (the paper's MB read as 2^20), 3 significant digits; paper cells as "
        "printed. DAG values size = the size components \"chunk infos\" + \"chunk factors\"; "
        "chunks map = \"chunk infos\"; chunks factors = \"chunk factors\"; avg. factor qty = "
        "counter \"factor values\" / \"values\" (the values not covered by their chunk's "
        "representative); avg. factor bits = \"factor bits\" / \"factor values\". Columns: "
        "values per chunk (parameter chunk-size; treelet height 4, skip list at level 6). Mode "
        "closed.")
    lines += ["The paper's sections are 16K² and 64K² (shown up to --max-resolution). Its 64K² "
              "chunks factors size at 16 values per chunk is printed 0.169, but its own row "
              "sum (2.897 − 1.728) gives 1.169. – = not built / not in the paper.", ""]
    lines += paired_table(found, shown, DAGMH_CHUNK_SIZES, DAGMH_TABLE4, ours_rows,
                          lambda r: f"city closed (stands in for Citadel), {heading(r)}")
    return lines


def mh_lookup(records, args):
    filters = (1, 3, 5)
    sets = ("uniform", "view")
    schemes = ("mh", "mmh", "dag-mh", "cpvs", "sm32")
    family = ("mh", "mmh", "dag-mh")
    header = ["scheme", "scene", "mode", "resolution"]
    for s in sets:
        header += [f"{s} {k}×{k}" for k in filters] + [f"{s} {k}×{k}/1×1" for k in filters[1:]]
    # the scenes and modes of the MH family's records; other schemes only beside them
    builds = sorted({(scene, mode) for (name, _, scene, mode, _) in records.newest
                     if name in family})
    ns = {}  # (scheme, scene, mode, resolution, query set, k) → ns per query
    rows = []
    for scene, mode in builds:
        resolutions = {r for s in family for r in mh_cells(records, s, scene, mode)}
        for scheme in schemes:
            cells = mh_cells(records, scheme, scene, mode)
            for r in sorted(cells):
                rec = cells[r]
                if (scheme not in family and r not in resolutions) or not rec.get("lookup"):
                    continue
                line = [scheme, scene, mode, heading(r)]
                for s in sets:
                    for k in filters:
                        ns[(scheme, scene, mode, r, s, k)] = lookup_ns(rec, s, k)
                    line += [significant(ns[(scheme, scene, mode, r, s, k)]) for k in filters]
                    line += [significant(ratio_of(ns[(scheme, scene, mode, r, s, k)],
                                                  ns[(scheme, scene, mode, r, s, 1)]))
                             for k in filters[1:]]
                rows.append(line)
    lines = preamble(
        "MH family lookup cost by filter size (Scandolo 2016 §4, Scandolo & Eisemann 2021 §4.2)",
        args, records, [("CLOSED CITY", "city"), ("Citadel", "city"), (None, "terrain"),
                        ("Trees", "forest"), ("Hairball", "tangle")],
        "ns per query on one thread (median of 5 runs), 3 significant digits, by query set "
        "(uniform: random points; view: samples of a 1920×1080 view) and PCF filter k×k at the "
        "finest level; k×k/1×1 = the cost of a k×k filter over a point lookup. mmh at search "
        "distance 1000, dag-mh at its defaults; cpvs (voxel DAG) and sm32 (float32 map) where "
        "built, for reference. Records built with --no-bench (the parameter sweeps) have no "
        "timings and are left out.")
    lines += [markdown_table(header, rows, label_columns=4) if rows else
              "No records of mh, mmh or dag-mh with lookup timings.\n"]
    # ours: scheme A over scheme B, view queries, per filter
    compare = []
    for a, b in (("mmh", "mh"), ("dag-mh", "mmh")):
        for scene, mode in builds:
            for r in sorted({key[3] for key in ns if key[:3] == (a, scene, mode)}):
                got = [ratio_of(ns.get((a, scene, mode, r, "view", k)),
                                ns.get((b, scene, mode, r, "view", k))) for k in filters]
                if any(v is not None for v in got):
                    compare.append([f"{a} / {b}", f"{scene} {mode} {heading(r)}"]
                                   + [significant(v) for v in got])
    compare.append(["paper: MMH / MH", "all scenes, 256K²"] + ["≈ 1"] * len(filters))
    compare.append(["paper: DAG-MH / MMH", "Citadel 64K²", "≈ 1", "≈ 2", "≈ 2"])
    filter_ratios = [["paper: DAG-MH", "Citadel 64K²", "0.5 ms"] + [
        f"{DAGMH_LOOKUP_MS[k]} ms (≈ {DAGMH_LOOKUP_MS[k] / DAGMH_LOOKUP_MS[1]:g}×)"
        for k in filters[1:]],
        ["paper: MMH", "all scenes, 256K²", "< 1 ms", "1–2.5 ms", MISSING]]
    lines += ["## Relative cost, view queries", "",
              markdown_table(["ratio", "cell"] + [f"{k}×{k}" for k in filters], compare,
                             label_columns=2),
              "## The papers' times per full HD frame", "",
              markdown_table(["paper", "scene"] + [f"{k}×{k}" for k in filters], filter_ratios,
                             label_columns=2),
              "The papers time a GPU frame of a view with hierarchical PCF (the kernel at the "
              "level matching the pixel footprint, sharing the traversal to the samples' common "
              "ancestor); ours is one CPU thread per query, PCF at the finest level. Compare the "
              "ratios, not the times.", ""]
    return lines


# --- every lossless scheme side by side (issue 5: compressed-sm, openvdb, sm-zstd) -----------

# (scheme, what it is) in the tables' order: the float map, the map codecs, the voxel schemes,
# the MH family. Each at its registry defaults (the parameters below, as compare-size.sh passes
# them); a scheme without records keeps its row, with "–".
COMPARE_SCHEMES = [
    ("sm32", "float32 shadow map"),
    ("compressed-sm", "Arvo & Hirvikorpi 2005, piecewise-linear scanlines"),
    ("sm-zstd", "float32 map in 64×64 blocks, zstd level 3"),
    ("openvdb", "voxel shadow volume in an OpenVDB tree"),
    ("cpvs", "Sintorn 2014, voxel DAG"),
    ("cpvs-fast", "Kämpe 2015, voxel DAG, culling on"),
    ("mh", "Scandolo 2016a, multiresolution hierarchy"),
    ("mmh", "Scandolo 2016b, merged MH, search distance 1000"),
    ("dag-mh", "Scandolo & Eisemann 2021, treelets of 4, chunks of 32"),
]
COMPARE_PARAMS = {**MH_FAMILY_PARAMS, "sm-zstd": {"block": "64", "level": "3"}}
COMPARE_BUILDS = [("city", "closed"), ("city", "open"), ("terrain", "closed"),
                  ("terrain", "open")]
COMPARE_RESOLUTIONS = [4 * K << i for i in range(5)]  # 4K² … 64K²
COMPARE_LOOKUP_RESOLUTIONS = [4 * K, 16 * K, 64 * K]
COMPARE_FILTERS = (1, 9)
# compare-size.sh builds these (scheme, scene, mode) only up to a resolution, for memory.
COMPARE_CAPPED = {
    **{(scheme, s, m): 16 * K for scheme in ("sm32", "openvdb") for s, m in COMPARE_BUILDS},
    **{(scheme, s, "open"): 8 * K for scheme in ("mh", "mmh", "dag-mh")
       for s in ("city", "terrain")},
}
COMPARE_CAP_NOTE = (
    "Caps, for memory (2 cores, 24 GiB, shared: no cell may peak above about 16 GiB; those "
    "cells print –), estimated from the records below the cap: `sm32` up to 16K², as it holds "
    "4·R² bytes (16 GiB at 64K²), which is the analytic row. `mh`, `mmh`, "
    "`dag-mh` open up to 8K²: the ground is a point interval of changing depth, so the hierarchy "
    "keeps about a node per texel (mh 70 MiB at 4K², ×4 per doubling) and `mmh` peaks at "
    "5.3 GiB at 8K² on city (1.6 GiB at 4K² on terrain, as on city), over 20 GiB at 16K². "
    "`openvdb` up to 16K²: 3.7 GiB at 16K² on city closed and 4.5 GiB open, ×4.1 per doubling "
    "(no subtree is shared, and every lower node touched holds a dense 33 KiB table), so about "
    "15 and 18 GiB at 32K² and 60 GiB at 64K²; its encoder stops past 3/4 of the machine's "
    "memory.")


def compare_cells(records, scheme, scene, mode):
    """{resolution: record} of `scheme` at the parameters compare-size.sh builds."""
    return records.find(scheme, scene, mode, COMPARE_PARAMS.get(scheme))


def compare_columns(records, builds, wanted, args):
    """`wanted` up to --max-resolution (the maximum alone if all are above it), and every other
    resolution the schemes hold on the builds from the smallest of those up (cpvs's 1K² and 2K²
    cells of the CPVS tables add no columns, a quick run's do)."""
    shown = {r for r in wanted if r <= args.max_resolution} or {args.max_resolution}
    held = {r for scheme, _ in COMPARE_SCHEMES for scene, mode in builds
            for r in compare_cells(records, scheme, scene, mode)}
    return sorted(shown | {r for r in held if r >= min(shown)})


def compare_note(scheme, scene, mode, cells, columns):
    """What a row's empty cells mean: a cap of compare-size.sh, or no records at all."""
    if not cells:
        return "; no records"
    return cap_note(scheme, scene, mode, cells, columns, COMPARE_CAPPED).replace(", ", "; ", 1)


def compare_size(records, args):
    columns = compare_columns(records, COMPARE_BUILDS, COMPARE_RESOLUTIONS, args)
    lines = preamble(
        "Size of every lossless scheme — city and terrain, closed and open", args, records,
        [(None, "city"), (None, "terrain")],
        "MiB = 2^20 bytes (the record's size_bytes.total: every byte a lookup needs), 3 "
        "significant digits; % of float32 = the size over the uncompressed 32-bit map of the "
        "same resolution (4·R² bytes), at the row's largest cell. Every scheme at its registry "
        "defaults.")
    lines += ["Modes (DESIGN §3): closed = watertight casters, so each texel's interval "
              "[lo, hi] reaches to where its ray leaves the casters and a scheme may answer "
              "either way inside; open = no assumption, the interval is a point (hi = lo) "
              "wherever a ray hits. Lossless = every record verified against the reference "
              "(Verification above counts any mismatch).", "",
              COMPARE_CAP_NOTE + " – = not built.", ""]
    header = ["scheme"] + [heading(r) for r in columns] + ["% of float32 (largest cell)"]
    for scene, mode in COMPARE_BUILDS:
        rows = []
        for scheme, label in COMPARE_SCHEMES:
            cells = compare_cells(records, scheme, scene, mode)
            values = {r: mib(rec) for r, rec in cells.items()}
            largest = max((r for r in cells if r in columns), default=None)
            share = (f"{significant(100 * size_bytes(cells[largest]) / (4.0 * largest ** 2))} % "
                     f"at {heading(largest)}" if largest else MISSING)
            note = compare_note(scheme, scene, mode, cells, columns)
            rows.append(row(f"{scheme} ({label}{note})", values, columns) + [share])
        rows.append(row("uncompressed float32, 4·R² bytes (analytic)",
                        {r: 4.0 * r * r / MIB for r in columns}, columns) + ["100 %"])
        lines += [f"## {scene} {mode}", "", markdown_table(header, rows)]
    lines += ["`sm32` is the float32 map itself (its size is the analytic row); `sm-zstd` "
              "stores the same `lo` values, so it is the same in both modes. `compressed-sm` and "
              "the MH family fit the interval [lo, hi]: in closed mode they exploit the undefined "
              "space, open they must reproduce every depth. `openvdb`, `cpvs` and `cpvs-fast` "
              "store the shadow volume as voxels (R³), with undefined space resolved as in "
              "Sintorn 2014 (cpvs, openvdb) or Kämpe 2015 (cpvs-fast).", ""]
    return lines


def compare_lookup(records, args):
    sets = ("uniform", "view")
    primary = [("city", "closed"), ("terrain", "closed")]
    resolutions = sorted({r for r in COMPARE_LOOKUP_RESOLUTIONS if r <= args.max_resolution}
                         or {args.max_resolution})
    timing_header = [f"{k}×{k} {s}" for k in COMPARE_FILTERS for s in sets]

    def timings(rec):
        return [significant(lookup_ns(rec, s, k)) for k in COMPARE_FILTERS for s in sets]

    lines = preamble(
        "Lookup cost of every lossless scheme — point and 9×9 PCF, random and view queries",
        args, records, [(None, "city"), (None, "terrain")],
        "ns per query on one thread (the record's ns_per_query_1t, median of 5 runs), 3 "
        "significant digits; size in MiB = 2^20 bytes. 1×1 = a point lookup, 9×9 = exact PCF "
        "over 9×9 texels at the finest level (81 visibility tests, answered as a fraction). "
        "uniform = the issue's random queries (the harness's query set \"uniform\": points "
        "uniform in the light's unit cube, up to 4 M, as many as take about 0.1 s); view = the "
        "surface points two 1920×1080 views of the scene see, in light space (coherent: "
        "neighbouring queries hit neighbouring texels). Every scheme at its registry defaults; "
        "depth schemes are queried at the query depth, voxel schemes at the voxel centre.")
    lines += ["City closed is the primary scene, terrain closed the second, at 4K², 16K² and "
              "64K² (up to --max-resolution); every other cell with timings follows at the end. "
              + COMPARE_CAP_NOTE + " – = not built, or built without timings (--no-bench, "
              "said in the row).", ""]
    header = ["scheme", "size (MiB)"] + timing_header
    shown = set()
    for scene, mode in primary:
        for r in resolutions:
            rows = []
            for scheme, label in COMPARE_SCHEMES:
                cells = compare_cells(records, scheme, scene, mode)
                rec = cells.get(r)
                note = compare_note(scheme, scene, mode, cells, [r])
                if rec is None:
                    rows.append([f"{scheme} ({label}{note})"] + [MISSING] * (len(header) - 1))
                    continue
                shown.add((scheme, scene, mode, r))
                if not rec.get("lookup"):
                    note += "; built without timings"
                rows.append([f"{scheme} ({label}{note})", significant(mib(rec))]
                            + timings(rec))
            lines += [f"## {scene} {mode}, {heading(r)}", "", markdown_table(header, rows)]
    lines += ["## Every other cell with timings", "",
              "The other scenes, modes and resolutions the records hold, for completeness "
              "(open mode and the resolutions between from compare-size.sh; other scenes, such "
              "as forest and tangle, from the MH and CPVS tables).", ""]
    others = 0
    for scene in sorted(records.scene_names):
        for mode in sorted({key[3] for key in records.newest if key[2] == scene}):
            rows = []
            cells = {scheme: compare_cells(records, scheme, scene, mode)
                     for scheme, _ in COMPARE_SCHEMES}
            for r in sorted({key[4] for key in records.newest if key[2:4] == (scene, mode)}):
                for scheme, _ in COMPARE_SCHEMES:
                    rec = cells[scheme].get(r)
                    if rec and rec.get("lookup") and (scheme, scene, mode, r) not in shown:
                        rows.append([heading(r), scheme, significant(mib(rec))] + timings(rec))
            if rows:
                others += len(rows)
                lines += [f"### {scene} {mode}", "",
                          markdown_table(["resolution", "scheme", "size (MiB)"] + timing_header,
                                         rows, label_columns=2)]
    if not others:
        lines += ["None.", ""]
    lines += ["Timings are of one CPU thread with the scheme's own cache (sm-zstd decompresses "
              "a 64×64 block on a miss of its per-thread four-block cache); the machine is "
              "shared, so compare schemes within one table, and ratios rather than digits.", ""]
    return lines


TABLES = {
    "sintorn2014-fig9": sintorn2014_fig9,
    "kampe2015-table1": kampe2015_table1,
    "kampe2015-table2": kampe2015_table2,
    "kampe2015-table3": kampe2015_table3,
    "kampe2015-table4": kampe2015_table4,
    "cpvs-lookup": cpvs_lookup,
    "scandolo2016-table1": scandolo2016_table1,
    "scandolo2016-table2": scandolo2016_table2,
    "scandolo2016-table3": scandolo2016_table3,
    "scandolo2016-fig8": scandolo2016_fig8,
    "scandolo2021-table1": scandolo2021_table1,
    "scandolo2021-table2": scandolo2021_table2,
    "scandolo2021-table3": scandolo2021_table3,
    "scandolo2021-table4": scandolo2021_table4,
    "mh-lookup": mh_lookup,
    "compare-size": compare_size,
    "compare-lookup": compare_lookup,
}


def parse_resolution(text):
    value = int(text[:-1]) * K if text[-1:] in "kK" else int(text)
    if value < 8 or value & (value - 1):
        raise argparse.ArgumentTypeError(f"'{text}' is not a power of two such as 4K or 64K")
    return value


def main():
    parser = argparse.ArgumentParser(
        description="CPVS and MH-family paper tables and the comparison of every scheme, from "
        "shadowbench records.")
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
