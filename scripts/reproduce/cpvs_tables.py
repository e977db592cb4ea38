"""The CPVS papers' tables: Sintorn et al. 2014 (Fig. 9, lookup cost §7) and Kämpe et al. 2015
(Tables 1-4), ours beside the papers' figures."""

from records import depth_seconds, lookup_ns, phase_seconds, size_bytes, total_seconds

from cells import millions
from paper_figures import (KAMPE_RESOLUTIONS, KAMPE_TABLE1, KAMPE_TABLE2, KAMPE_TABLE3,
                           KAMPE_TABLE3_RESOLUTIONS, KAMPE_TABLE4, SINTORN_FIG9,
                           SINTORN_FIG9_RESOLUTIONS, SINTORN_WORST_RATIO)
from printed import decimal_bytes, parse_row, seconds
from table_format import (MIB, heading, markdown_table, preamble, resolution_columns,
                          row, shadow_map_16, significant)

CULLING_ON = {"culling": "on"}  # cpvs-fast as Kämpe's Tables 2-4 measure it
# cpvs-fast's coarse volumes classified as the paper does (Kämpe §3, §3.4), beside the default
# (the masks' own pyramid); Table 2 shows both.
DEPTH_HIERARCHY = {"coarse-classification": "depth-hierarchy"}


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
         for r in records.at_defaults("cpvs-fast", "city", m, {"culling": c})},
        KAMPE_RESOLUTIONS, args.max_resolution)
    rows = []
    for paper_mode, mode in (("non-closed", "open"), ("closed", "closed")):
        for culling in ("off", "on"):
            found = records.at_defaults("cpvs-fast", "city", mode, {"culling": culling})
            total, insert_merge = KAMPE_TABLE1[(paper_mode, culling)]
            ours_im = {}
            for r, rec in found.items():
                parts = [phase_seconds(rec, "insert"), phase_seconds(rec, "merge")]
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
                            {r: millions(rec, "svo nodes inserted") for r, rec in found.items()},
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
        "§3.4: undefined resolved to minimise the visibility masks per 8×8 tile), culling on, "
        "with its coarse volumes classified two ways: masks = by the masks' own pyramid (the "
        "default), depth = by the min-max hierarchy of the enter and exit depth maps with "
        "Sintorn's parent rule, the masks only at the finest level (coarse-classification="
        "depth-hierarchy, as the paper does); ratio = old / new. Mode closed.")
    lines += ["– = not built / not in the paper.", ""]
    for paper_scene, scene in (("ClosedCity", "city"), ("FractalLandscape", "terrain")):
        old = {r: size_bytes(rec) for r, rec in records.find("cpvs", scene, "closed").items()}
        new = {classification: {r: size_bytes(rec) for r, rec in records.at_defaults(
                   "cpvs-fast", scene, "closed", {**CULLING_ON, **params}).items()}
               for classification, params in (("masks", {}), ("depth", DEPTH_HIERARCHY))}
        new_mb, old_mb, ratios = KAMPE_TABLE2[paper_scene]
        paper_new, paper_old = (parse_row(t, KAMPE_RESOLUTIONS, decimal_bytes)
                                for t in (new_mb, old_mb))
        paper_ratio = parse_row(ratios, KAMPE_RESOLUTIONS, float)
        columns = resolution_columns(set(old) | set(new["masks"]) | set(new["depth"]),
                                     KAMPE_RESOLUTIONS, args.max_resolution)

        def ratio(o, n, r):
            return o[r] / n[r] if r in o and r in n else None

        def mib(sizes, r):
            return significant(sizes.get(r) and sizes[r] / MIB)

        rows = [[heading(r), mib(new["masks"], r), mib(new["depth"], r), mib(old, r),
                 significant(ratio(old, new["masks"], r)),
                 significant(ratio(old, new["depth"], r)),
                 mib(paper_new, r), mib(paper_old, r), significant(paper_ratio.get(r))]
                for r in columns]
        lines += [f"## {scene} closed (stands in for {paper_scene})", "",
                  markdown_table(["resolution", "new, masks (MiB)", "new, depth (MiB)",
                                  "old (MiB)", "ratio, masks", "ratio, depth",
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
             ("visibility masks", lambda rec: phase_seconds(rec, "visibility masks"),
              ("visibility masks",)),
             ("min-max", lambda rec: phase_seconds(rec, "min-max"), ("min-max",)),
             ("transfer", None, ("transfer",)),
             ("insert", lambda rec: phase_seconds(rec, "insert"), ("insert nodes",)),
             ("merge", lambda rec: phase_seconds(rec, "merge"), ("merge nodes",))]
    for paper_mode, mode in (("non-closed", "open"), ("closed", "closed")):
        found = records.at_defaults("cpvs-fast", "city", mode, CULLING_ON)
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
                 (records.at_defaults(*b[:3], CULLING_ON) if b[0] == "cpvs-fast"
                  else records.find(*b[:3])).items()}
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


# The cells cpvs-lookup.sh builds, at the registry's defaults: a shared records folder holds
# other schemes and variants, which this table is not about.
CPVS_LOOKUP_CELLS = [("sm32", "city", "closed"), ("sm32", "city", "open")] + [
    (scheme, scene, mode) for scheme in ("cpvs", "cpvs-fast")
    for scene, mode in (("city", "closed"), ("city", "open"), ("forest", "open"))]


def cpvs_lookup(records, args):
    filters = (1, 9, 17)
    sets = ("uniform", "view")
    header = ["scheme", "scene", "mode", "resolution"]
    for s in sets:
        header += [f"{s} {k}×{k}" for k in filters] + [f"{s} {k}×{k}/1×1" for k in filters[1:]]
    rows, worst, held = [], {}, set()
    for scheme, scene, mode in CPVS_LOOKUP_CELLS:
        for r, rec in sorted(records.at_defaults(scheme, scene, mode).items()):
            held |= {t.get("filter") for t in rec.get("lookup") or []}
            cells = [scheme, scene, mode, heading(r)]
            for s in sets:
                ns = {k: lookup_ns(rec, s, k) for k in filters}
                cells += [significant(ns[k]) for k in filters]
                for k in filters[1:]:
                    ratio = ns[k] / ns[1] if ns[k] and ns[1] else None
                    cells.append(significant(ratio))
                    if ratio and scheme != "sm32":
                        worst[(scheme, k)] = max(worst.get((scheme, k), 0), ratio)
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

