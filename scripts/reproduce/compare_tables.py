"""Every lossless scheme side by side, no paper (issue 5: compressed-sm, openvdb, sm-zstd beside
the CPVS and MH schemes): size and lookup cost, each scheme at its registry defaults."""

from number_format import MISSING
from records import cache_hit_rate, lookup_ns, size_bytes

from cells import mib
from paper_figures import DAGMH_LOOKUP_MS, SINTORN_WORST_RATIO
from table_format import (K, MIB, cap_note, heading, markdown_table,
                          preamble, row, significant)

# (scheme, what it is) in the tables' order: the float map, the map codecs, the voxel schemes,
# the MH family. Each at its registry defaults (as compare-size.sh builds them); a scheme
# without records keeps its row, with "–".
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
    ("delta-dag", "this framework (issue 16), simplest relative values in a DAG of packs"),
]
COMPARE_BUILDS = [("city", "closed"), ("city", "open"), ("terrain", "closed"),
                  ("terrain", "open")]
COMPARE_RESOLUTIONS = [4 * K << i for i in range(5)]  # 4K² … 64K²
COMPARE_LOOKUP_RESOLUTIONS = [4 * K, 16 * K, 64 * K]
# compare-size.sh builds these (scheme, scene, mode) only up to a resolution, for memory.
COMPARE_CAPPED = {
    **{(scheme, s, m): 16 * K for scheme in ("sm32", "openvdb") for s, m in COMPARE_BUILDS},
    **{(scheme, s, "open"): cap for scheme in ("mh", "mmh", "dag-mh", "delta-dag")
       for s, cap in (("city", 16 * K), ("terrain", 8 * K))},
}
COMPARE_CAP_NOTE = (
    "Caps, for memory (2 cores, 24 GiB, shared: no cell may peak above about 16 GiB; those "
    "cells print –), estimated from the records below the cap: `sm32` up to 16K², as it holds "
    "4·R² bytes (16 GiB at 64K²), which is the analytic row. `mh`, `mmh`, "
    "`dag-mh`, `delta-dag` open up to 8K² on terrain and 16K² on city: the ground is a point "
    "interval of changing depth, so the hierarchy keeps about a node per texel (mh 70 MiB at "
    "4K², ×4 per doubling); `mmh` peaks at 1.6 GiB at 4K² on terrain, so over 20 GiB at 16K², "
    "while on city 16K² took 7.3 GiB (`delta-dag`) and 8.7 GiB (`dag-mh`), about 4× that at "
    "32K². "
    "`openvdb` up to 16K²: 3.7 GiB at 16K² on city closed and 4.5 GiB open, ×4.1 per doubling "
    "(no subtree is shared, and every lower node touched holds a dense 33 KiB table), so about "
    "15 and 18 GiB at 32K² and 60 GiB at 64K²; its encoder stops past 3/4 of the machine's "
    "memory.")


def compare_columns(records, builds, wanted, args):
    """`wanted` up to --max-resolution (the maximum alone if all are above it), and every other
    resolution the schemes hold on the builds from the smallest of those up (cpvs's 1K² and 2K²
    cells of the CPVS tables add no columns, a quick run's do)."""
    shown = {r for r in wanted if r <= args.max_resolution} or {args.max_resolution}
    held = {r for scheme, _ in COMPARE_SCHEMES for scene, mode in builds
            for r in records.at_defaults(scheme, scene, mode)}
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
            cells = records.at_defaults(scheme, scene, mode)
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


# compare-lookup.sh's cells (issue 13): the four scenes of the papers' lookup figures, each
# scheme up to a resolution for memory (compare-size.sh's caps; openvdb where compare-size has
# it).
LOOKUP_BUILDS = [("city", "closed"), ("terrain", "closed"), ("tangle", "closed"),
                 ("forest", "static")]
LOOKUP_FILTERS = (1, 3, 5, 9, 17)
LOOKUP_CAPPED = {
    **{("sm32", s, m): 16 * K for s, m in LOOKUP_BUILDS},
    **{("openvdb", s, m): 16 * K for s, m in LOOKUP_BUILDS[:2]},
}
LOOKUP_SCHEMES = {(scheme, s, m) for scheme, _ in COMPARE_SCHEMES for s, m in LOOKUP_BUILDS
                  if scheme != "openvdb" or (s, m) in LOOKUP_BUILDS[:2]}
# Issue 13's goals, benchmark figures: 9×9 and 17×17 PCF over the scheme's own point lookup.
LOOKUP_GOALS = {9: 3.0, 17: 5.0}
LOOKUP_GOAL_CELLS = {(scheme, "city", "closed")
                     for scheme in ("compressed-sm", "cpvs", "cpvs-fast", "mh", "mmh", "dag-mh")}
LOOKUP_GOAL_RESOLUTIONS = (16 * K, 64 * K)


def compare_lookup(records, args):
    sets = ("uniform", "view")
    resolutions = sorted({r for r in COMPARE_LOOKUP_RESOLUTIONS if r <= args.max_resolution}
                         or {args.max_resolution})
    header = ["scheme", "queries", "size (MiB)"] + [f"{k}×{k} ns (× 1×1)" for k in LOOKUP_FILTERS]

    def timings(rec, query_set):
        point = lookup_ns(rec, query_set, 1)
        cells = []
        for k in LOOKUP_FILTERS:
            ns = lookup_ns(rec, query_set, k)
            text = significant(ns)
            if k > 1 and ns is not None and point:
                text += f" ({ns / point:.1f}×)"
            if (hits := cache_hit_rate(rec, query_set, k)) is not None:
                text += f", {100 * hits:.0f} % hits"
            cells.append(text)
        return cells

    def misses_goal(rec, scheme, scene, mode, r):
        return (scheme, scene, mode) in LOOKUP_GOAL_CELLS and r in LOOKUP_GOAL_RESOLUTIONS and any(
            (ns := lookup_ns(rec, s, k)) is not None and (point := lookup_ns(rec, s, 1))
            and ns / point > goal for s in sets for k, goal in LOOKUP_GOALS.items())

    lines = preamble(
        "Lookup cost of every lossless scheme — point and PCF from 3×3 to 17×17, random and "
        "view queries", args, records,
        [(None, "city"), (None, "terrain"), (None, "tangle"), (None, "forest")],
        "ns per query on one thread (the record's ns_per_query_1t, median of 5 runs), 3 "
        "significant digits, and in brackets over the same scheme's point lookup (1×1) of the "
        "same queries; size in MiB = 2^20 bytes. k×k = exact PCF over k×k texels at the finest "
        "level (k² visibility tests, answered as a fraction). uniform = points uniform in the "
        "light's unit cube (the harness's query set \"uniform\", up to 4 M, as many as take "
        "about 0.1 s); view = the surface points two 1920×1080 views of the scene see, in light "
        "space (coherent: neighbouring queries hit neighbouring texels). Every scheme at its "
        "registry defaults; depth schemes are queried at the query depth, voxel schemes at the "
        "voxel centre. `sm-zstd` adds its cache's hit rate.")
    lines += [
        "Issue 13's goals (benchmark figures): 9×9 ≤ 3× and 17×17 ≤ 5× the point lookup for "
        "`compressed-sm`, `cpvs`, `cpvs-fast`, `mh`, `mmh`, `dag-mh` at 16K² and 64K² city "
        "closed, uniform and view; a row of those cells marked **goal missed** exceeds one of those ratios. "
        "The papers' figures, GPU frame times rather than ns per query: Sintorn 2014 §7, cpvs "
        f"at worst {SINTORN_WORST_RATIO[9]}× from one tap to 9×9 and "
        f"{SINTORN_WORST_RATIO[17]}× to 17×17; Scandolo & Eisemann 2021 §4.2 (Citadel, 64K², "
        f"hierarchical PCF), dag-mh about {DAGMH_LOOKUP_MS[1]} ms single, "
        f"{DAGMH_LOOKUP_MS[3]} ms 3×3 ({DAGMH_LOOKUP_MS[3] / DAGMH_LOOKUP_MS[1]:.0f}×), "
        f"{DAGMH_LOOKUP_MS[5]} ms 5×5 ({DAGMH_LOOKUP_MS[5] / DAGMH_LOOKUP_MS[1]:.0f}×), with "
        "mmh's 3×3 and 5×5 about twice as fast.", "",
        "The MH family, `compressed-sm` and `sm-zstd` walk their structure once per kernel "
        "(the lowest node holding the kernel, then each block of taps one stored value "
        "decides, tested once); `cpvs` and `cpvs-fast` walk each leafmask the kernel overlaps, "
        "resuming from the deepest node two walks share; `sm32` and `openvdb` read every tap. "
        + COMPARE_CAP_NOTE + " – = not built, or built without timings (--no-bench, said in the "
        "row).", ""]
    for scene, mode in LOOKUP_BUILDS:
        for r in resolutions:
            rows = []
            for scheme, label in COMPARE_SCHEMES:
                if (scheme, scene, mode) not in LOOKUP_SCHEMES:
                    continue
                cells = records.at_defaults(scheme, scene, mode)
                rec = cells.get(r)
                note = "; no records" if not cells else cap_note(
                    scheme, scene, mode, cells, [r], LOOKUP_CAPPED).replace(", ", "; ", 1)
                if rec is None:
                    rows.append([f"{scheme} ({label}{note})", MISSING]
                                + [MISSING] * (len(header) - 2))
                    continue
                if not rec.get("lookup"):
                    note += "; built without timings"
                if misses_goal(rec, scheme, scene, mode, r):
                    note += "; **goal missed**"
                for query_set in sets:
                    rows.append([f"{scheme} ({label}{note})" if query_set == sets[0] else "",
                                 query_set,
                                 significant(mib(rec)) if query_set == sets[0] else ""]
                                + timings(rec, query_set))
            lines += [f"## {scene} {mode}, {heading(r)}", "",
                      markdown_table(header, rows, label_columns=2)]
    lines += ["Timings are of one CPU thread with the scheme's own cache (sm-zstd keeps 4 MiB "
              "of decoded 64×64 blocks per thread and answers a batch in Morton order of its "
              "texels); compare schemes within one table, and ratios rather than digits.", ""]
    return lines
