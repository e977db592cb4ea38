"""The MH family's paper tables: Scandolo et al. 2016 (MMH: Tables 1-3, Fig. 8) and Scandolo &
Eisemann 2021 (DAG-MH: Tables 1-4), and the family's lookup cost, ours beside the papers'
figures. The papers' rows are our cells at the registry's defaults (the papers' settings)."""

from number_format import MISSING, integer
from records import counter, depth_seconds, lookup_ns, phase_seconds, total_seconds

from cells import component_mib, mib, millions, without_depth
from paper_figures import (DAGMH_CHUNK_SIZES, DAGMH_DEPTH_SHARE, DAGMH_LOOKUP_MS,
                           DAGMH_RESOLUTIONS, DAGMH_TABLE1, DAGMH_TABLE2,
                           DAGMH_TABLE2_RESOLUTIONS, DAGMH_TABLE3, DAGMH_TABLE4,
                           DAGMH_TREELET_HEIGHTS, DAGMH_UNCOMPRESSED, MMH_RESOLUTIONS,
                           MMH_SEARCH_DISTANCES, MMH_TABLE1, MMH_TABLE2, MMH_TABLE3)
from printed import paper_mib, parse_row
from table_format import (K, MIB, cap_note, heading, markdown_table,
                          preamble, ratio_of, resolution_columns, row, significant)

# The scripts build these (scheme, scene, mode) only up to a resolution (their budget, below).
CAPPED = {**{(scheme, "tangle", "closed"): 16 * K for scheme in ("cpvs", "cpvs-fast")},
          **{(scheme, "city", "open"): 8 * K
             for scheme in ("mh", "mmh", "dag-mh", "cpvs", "cpvs-fast")}}
CAP_NOTE = ("Forest is in static mode (first and second surface, as the 2021 paper builds its "
            "dual maps): its trees and ground are open meshes, so in closed mode its intervals "
            "are points (mh 72 MiB at 4K², more than the float map). Caps, for the scripts' time "
            "and memory (those cells print –): `cpvs` and `cpvs-fast` (the papers' DAG) on tangle closed up to "
            "16K², as its voxel DAG grows fast there (forest open at 64K²: 18 minutes, 5.8 GiB); "
            "the MH family and cpvs on city open up to 8K². There the ground is a point "
            "interval whose depth changes from texel to texel, so the hierarchy keeps about a "
            "node per texel: `mh` is 70 MiB at 4K², ×4 per doubling from 1K² (more than the "
            "64 MiB float map), and `mmh` peaks at 1.3 GiB at 4K², so about 20 GiB at 16K². "
            "`cpvs-fast` (Kämpe 2015, the [KSA15] of the 2021 paper and of the 2016 paper's "
            "Table 2) is built beside `cpvs` in every cell.")


MH_TIME_UNITS = ("seconds of wall time, 3 significant digits. total = the whole build with the "
                 "dual depth map included (the record's time_s.total); without depth = total − "
                 "the depth-map time (time_s.depth, tracing thread-seconds / threads) — "
                 "approximate, as the map is traced while the encoder consumes earlier tiles. "
                 "Every cell traces its own depth map. Paper: GPU (CUDA) + CPU builds on an "
                 "i7-5820K with a Titan X (2016) / Titan V (2021), the dual shadow map included "
                 "(the 2021 paper: about 80% of DAG-MH's time); ours is CPU only, 2 cores.")


def mh_columns(records, schemes, builds, paper_resolutions, args):
    """Our resolutions of the MH-family schemes on the builds, and the paper's up to the maximum
    (the CPVS tables' 1K²… cells of cpvs do not add columns)."""
    ours = {r for scheme in schemes for scene, mode, *_ in builds
            for r in records.at_defaults(scheme, scene, mode)}
    return resolution_columns(ours, paper_resolutions, args.max_resolution)


def size_rows(records, scene, mode, schemes, columns):
    """A size row (MiB) per scheme; cpvs over its cap is '–'."""
    rows = []
    for scheme, label in schemes:
        cells = records.at_defaults(scheme, scene, mode)
        values = {r: mib(rec) for r, rec in cells.items()}
        note = cap_note(scheme, scene, mode, cells, columns, CAPPED)
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
        "paper (forest static: see below); the city open row has no paper counterpart (open: "
        "hi = lo wherever a ray hits, so subtrees merge only where their relative depths are "
        "equal).")
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
        mh, mmh, cpvs = (records.at_defaults(s, scene, mode) for s in ("mh", "mmh", "cpvs"))
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
        cells = records.at_defaults(scheme, scene, mode)
        label += cap_note(scheme, scene, mode, cells, columns, CAPPED)
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
        "row is `cpvs` (Sintorn 2014, CPU), with `cpvs-fast` (Kämpe 2015, CPU) beside it.")
    lines += [CAP_NOTE + " – = not built / not in the paper.", ""]
    for scene, mode, paper in builds:
        rows = time_rows(records, scene, mode, schemes, columns)
        for method in ("DAG", "MH", "MMH"):
            rows.append(row(f"paper: {paper} {method}",
                            parse_row(MMH_TABLE2[paper][method], MMH_RESOLUTIONS, float), columns))
        mh, mmh = (records.at_defaults(s, scene, mode) for s in ("mh", "mmh"))
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


# Table 3's interval mismatch as we test it and as Alg. 3 prints it: (row label, parameters).
MMH_INTERVAL_TESTS = [("mmh city closed, both ways", {}),
                      ("mmh city closed, Alg. 3's test", {"interval-test": "paper"})]


def scandolo2016_table3(records, args):
    found = {label: records.at_defaults("mmh", "city", "closed", params)
             for label, params in MMH_INTERVAL_TESTS}
    paper_resolutions = sorted({r for rows in MMH_TABLE3.values() for r in rows})
    # ours from 16K² as in the paper, or every resolution in a quick run below 16K²
    resolutions = sorted({r for cells in found.values() for r in cells
                          if r >= 16 * K or args.max_resolution < 16 * K}
                         | {r for r in paper_resolutions if r <= args.max_resolution})
    header = ["build", "resolution", "pairs tested (M)", "interval mismatch",
              "offset too large", "full test rejection", "merged", "nodes removed (M)"]
    rows = []
    for r in resolutions:
        for label, _ in MMH_INTERVAL_TESTS:
            rec = found[label].get(r)
            if rec:
                tested = counter(rec, "pairs tested")
                shares = [ratio_of(counter(rec, name), tested, 100)
                          for name in ("rejected interval", "rejected offset",
                                       "rejected full test", "merges")]
                rows.append([label, heading(r), significant(millions(rec, "pairs tested"))]
                            + [significant(s) + (" %" if s is not None else "") for s in shares]
                            + [significant(millions(rec, "nodes removed"))])
            elif r in paper_resolutions:
                rows.append([label, heading(r)] + [MISSING] * 6)
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
              "Two interval tests (§3.2, Fig. 6): some node of a subtree lies above every "
              "interval of the other (highest minimum above highest maximum) or below every one "
              "(lowest maximum below lowest minimum). Both ways (`interval-test=both-ways`, the "
              "default) tests each subtree against the other; Alg. 3's test "
              "(`interval-test=paper`) only the earlier subtree of the collision list against "
              "the later, (n1.lMax < n2.lMin) || (n1.hMin > n2.hMax). Both reject only pairs the "
              "full test rejects, so the merges are the same; the pairs only one way rejects go "
              "to the full test under Alg. 3's.", "",
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
    mh = records.at_defaults("mh", "city", "closed")
    swept = {}
    for distance in MMH_SEARCH_DISTANCES:
        for r, rec in records.at_defaults("mmh", "city", "closed",
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
            rows.append([str(distance), significant(mib(rec)),
                         significant(phase_seconds(rec, "match")),
                         significant(total_seconds(rec)),
                         significant(above) if above > 0 else "0",
                         significant(millions(rec, "pairs tested")),
                         significant(millions(rec, "merges"))])
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
        "closed (forest static: see below); the city open row has no paper counterpart (open: "
        "hi = lo wherever a ray hits). Dinos has no stand-in.")
    lines += [CAP_NOTE + " – = not built / not in the paper.", ""]
    ratio_rows = []
    for scene, mode, papers in builds:
        rows = size_rows(records, scene, mode, schemes, columns)
        # The paper's skip list is "a few KB"; ours is 64 KiB at level 6, level 0 has none.
        skip0 = records.at_defaults("dag-mh", scene, mode, {"skip-level": "0"})
        if skip0:
            rows.append(row(f"dag-mh {scene} {mode} (skip level 0: no skip list)",
                            {r: mib(rec) for r, rec in skip0.items()}, columns))
        for paper in papers:
            for method in ("DAG", "MMH", "DAG-MH"):
                rows.append(row(f"paper: {paper} {method}",
                                paper_mib(DAGMH_TABLE1[paper][method], DAGMH_RESOLUTIONS),
                                columns))
        stands = f" (stands in for {', '.join(papers)})" if papers else " (no paper counterpart)"
        lines += [f"## {scene} {mode}{stands}", "",
                  markdown_table(["build"] + [heading(r) for r in columns], rows)]
        dag_mh, mmh, cpvs = (records.at_defaults(s, scene, mode)
                             for s in ("dag-mh", "mmh", "cpvs"))
        dags = [("dag-mh", dag_mh)] + ([("dag-mh skip level 0", skip0)] if skip0 else [])
        for name, dag_cells in dags:
            for other, cells in (("mmh", mmh), ("cpvs", cpvs)):
                ratio_rows.append(row(f"{scene} {mode}: {name} / {other}", {
                    r: ratio_of(mib(dag_cells[r]), mib(cells[r]), 100) for r in columns
                    if r in dag_cells and r in cells}, columns))
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


# The calibrated stand-ins (README, "Calibrated stand-ins"): per generator, the paper's scene
# (as the 2021 paper names it, and as the scenes line names it) whose DAG row `cpvs` was fitted
# to, the other printings of that row, and the rows the other
# schemes predict ((label, printed, resolutions) or None where the papers have none).
CALIBRATED = [
    ("city", "City", "City (2021) = CITYSCAPE (2016)", DAGMH_TABLE1["City"]["DAG"],
     [("paper: CITYSCAPE DAG (2016 Table 1)", MMH_TABLE1["CITYSCAPE"]["DAG"], MMH_RESOLUTIONS)],
     {"mh": ("CITYSCAPE MH (2016)", MMH_TABLE1["CITYSCAPE"]["MH"], MMH_RESOLUTIONS),
      "mmh": ("City MMH (2021)", DAGMH_TABLE1["City"]["MMH"], DAGMH_RESOLUTIONS),
      "dag-mh": ("City DAG-MH (2021)", DAGMH_TABLE1["City"]["DAG-MH"], DAGMH_RESOLUTIONS)}),
    ("tangle", "Hairball", "Hairball", DAGMH_TABLE1["Hairball"]["DAG"], [],
     {"mmh": ("Hairball MMH (2021)", DAGMH_TABLE1["Hairball"]["MMH"], DAGMH_RESOLUTIONS),
      "dag-mh": ("Hairball DAG-MH (2021)", DAGMH_TABLE1["Hairball"]["DAG-MH"],
                 DAGMH_RESOLUTIONS)}),
]


def calibration(records, args):
    """The fit of each calibrated stand-in (README, "Calibrated stand-ins"): `cpvs` closed
    against the DAG row it was fitted to, its growth per doubling against the paper's, and every
    other scheme on the same cells as a prediction beside the paper's row."""
    columns = mh_columns(records, ("cpvs",), [(g, "closed") for g, *_ in CALIBRATED],
                         DAGMH_RESOLUTIONS, args)

    def growth(sizes):
        return {r: sizes[r] / sizes[r // 2] for r in sizes if r // 2 in sizes}

    def sizes(scheme, generator):
        return {r: mib(rec) for r, rec in records.at_defaults(scheme, generator, "closed").items()}

    lines = preamble(
        "Calibrated stand-ins: `cpvs` fitted to the papers' DAG column", args, records,
        [(named, generator) for generator, _, named, *_ in CALIBRATED],
        "MiB = 2^20 bytes (the papers' \"MB\", read as in the tables), 3 significant digits; "
        "ours / paper in %; growth = size over the size one doubling below. The fit targets are "
        "Scandolo & Eisemann 2021 Table 1's DAG rows (City, Hairball), within 25% at every "
        "resolution and growth within 15% (issue 14); the 2016 paper's CITYSCAPE DAG row is the "
        "City's curve within 2%. Every other row is a prediction of the preset, not fitted.")
    for generator, paper, _, fitted, printings, predicted in CALIBRATED:
        dag = paper_mib(fitted, DAGMH_RESOLUTIONS)
        cpvs = sizes("cpvs", generator)
        fit = [row("cpvs closed (fitted)", cpvs, columns),
               row(f"paper: {paper} DAG (2021 Table 1)", dag, columns)]
        fit += [row(label, paper_mib(printed, resolutions), columns)
                for label, printed, resolutions in printings]
        fit += [row(f"cpvs / {paper} DAG (%)",
                    {r: ratio_of(cpvs[r], dag.get(r), 100) for r in cpvs}, columns),
                row("cpvs growth", growth(cpvs), columns),
                row(f"paper: {paper} DAG growth", growth(dag), columns)]
        predictions = []
        for scheme in ("cpvs-fast", "mh", "mmh", "dag-mh"):
            ours = sizes(scheme, generator)
            predictions.append(row(f"{scheme} closed", ours, columns))
            if scheme in predicted:
                label, printed, resolutions = predicted[scheme]
                paper_sizes = paper_mib(printed, resolutions)
                predictions.append(row(f"paper: {label}", paper_sizes, columns))
                predictions.append(row(f"{scheme} / paper (%)",
                                       {r: ratio_of(ours[r], paper_sizes.get(r), 100)
                                        for r in ours}, columns))
        lines += [f"## {generator}: the fit", "",
                  markdown_table(["row"] + [heading(r) for r in columns], fit),
                  f"## {generator}: predictions on the same cells", "",
                  markdown_table(["row"] + [heading(r) for r in columns], predictions)]
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
    dag_mh = records.at_defaults("dag-mh", "city", "closed")
    rows.append(row("dag-mh: depth map share of total (%)", {
        r: ratio_of(depth_seconds(rec), total_seconds(rec), 100) for r, rec in dag_mh.items()},
        columns))
    rows.append(["paper: Citadel DAG-MH dual shadow map share (%)"]
                + [f"≈ {DAGMH_DEPTH_SHARE}" for _ in columns])
    lines = preamble(
        "Scandolo & Eisemann 2021 (DAG-MH), Table 2 — compression time", args, records,
        [("Citadel", "city")],
        MH_TIME_UNITS + " Mode closed; DAG = `cpvs` and `cpvs-fast`, the "
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
        for r, rec in records.at_defaults("dag-mh", "city", "closed",
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
                line += [integer(got) if isinstance(got, int) else significant(got),
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
        ("inner nodes", "Inner nodes", lambda rec: counter(rec, "inner nodes")),
        ("nodes size (MiB)", "Nodes size", lambda rec: component_mib(rec, "inner nodes")),
        ("treelets", "Treelets", lambda rec: counter(rec, "treelets")),
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
        return ratio_of(counter(rec, "factor values"), counter(rec, "values"), 100)

    ours_rows = [
        ("DAG values size (MiB)", "DAG values size",
         lambda rec: component_mib(rec, "chunk infos", "chunk factors")),
        ("chunks map size (MiB)", "Chunks map size",
         lambda rec: component_mib(rec, "chunk infos")),
        ("chunks factors size (MiB)", "Chunks factors size",
         lambda rec: component_mib(rec, "chunk factors")),
        ("avg. factor qty (%)", "Avg. factor qty", factor_share),
        ("avg. factor bits", "Avg. factor bits",
         lambda rec: ratio_of(counter(rec, "factor bits"), counter(rec, "factor values"))),
        ("values", None, lambda rec: counter(rec, "values")),
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
        resolutions = {r for s in family for r in records.at_defaults(s, scene, mode)}
        for scheme in schemes:
            cells = records.at_defaults(scheme, scene, mode)
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

