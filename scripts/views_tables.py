#!/usr/bin/env python3
"""Tables of the view records (`shadowbench views`) under a folder, as Markdown on stdout.

    python3 scripts/views_tables.py RECORDS_DIR

Per camera path:
  * every technique's error (share of covered pixels shadowed wrongly, split into false lit and
    false shadow, and the same near a true shadow boundary), the memory it holds, and its median
    build and shade time per frame;
  * the issue's two questions against CSM with the thesis's setup (3 x 1024^2): the memory at which
    each precomputed scheme matches CSM's error, and each scheme's error at CSM's memory, both
    interpolated linearly in log memory between the resolutions built (never extrapolated);
  * IASM against CSM frame by frame, split by whether the camera sits near a point where four
    IASM tiles meet (Alecu Fig. 4.3-4.4: the thesis's weak case);
  * Alecu 2014 Table 4.1's stage costs beside ours. Ours run on a CPU and shade only the shadow
    lookups, so the columns compare in kind, not in value.
"""

import argparse
import json
import math
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent / "reproduce"))  # table_format

from table_format import markdown_table
from views import TABLE_HEADER, group_by_path, read_view_records, table_row

# Alecu 2014, Table 4.1 (GTX 660 Ti, ms): readback, shadows, scene, frame.
ALECU_TABLE_4_1 = [
    ("Trees (CSM)", None, 7.5, 2.7, 15.1),
    ("Trees (IASM)", 4.6, 6.4, 2.7, 18.8),
    ("Trees (deferred IASM)", 7.9, 6.5, 2.6, 22.6),
    ("Trees (deferred delayed IASM)", 0.9, 7.0, 2.7, 15.9),
    ("Village (CSM)", None, 5.5, 2.2, 12.5),
    ("Village (IASM)", 2.3, 28.6, 1.9, 38.1),
    ("Village (deferred IASM)", 8.5, 28.9, 2.0, 45.0),
    ("Village (deferred delayed IASM)", 0.0, 28.6, 1.9, 36.0),
]


def ms(value):
    return "–" if value is None else f"{value:.1f}"


def technique_table(records):
    return markdown_table(TABLE_HEADER, [table_row(r) for r in records]).splitlines()


def interpolate(points, x, xi, yi):
    """y at x on the polyline through points (sorted by xi), linear in log x; None outside."""
    for a, b in zip(points, points[1:]):
        lo, hi = sorted((a[xi], b[xi]))
        if lo <= x <= hi and a[xi] != b[xi]:
            t = (math.log(x) - math.log(a[xi])) / (math.log(b[xi]) - math.log(a[xi]))
            return a[yi] + t * (b[yi] - a[yi])
    return next((p[yi] for p in points if p[xi] == x), None)


def crossing_memory(points, error):
    """The least memory at which the error curve (sorted by memory) comes down to `error`."""
    for a, b in zip(points, points[1:]):
        if a[1] > error >= b[1]:
            t = (error - a[1]) / (b[1] - a[1])
            return math.exp(math.log(a[0]) + t * (math.log(b[0]) - math.log(a[0])))
    return points[0][0] if points and points[0][1] <= error else None


def thesis_csm(records):
    """The CSM record with the thesis's setup (3 x 1024^2), the baseline of the comparisons."""
    return next((r for r in records if r["technique"]["name"] == "csm"
                 and r["technique"]["params"].get("cascades") == "3"
                 and r["technique"]["params"].get("resolution") == "1024"), None)


def csm_questions(records):
    """Rows answering the issue's goals against CSM 3 x 1024^2, if it was run."""
    csm = thesis_csm(records)
    if csm is None:
        return []
    base = csm["totals"]
    error, memory = base["error_rate"], base["memory_bytes"]
    curves = {}
    for r in records:
        if r["technique"]["kind"] != "precomputed":
            continue
        s = r["technique"]["structure"]
        key = json.dumps([s["scheme"], s["params"], s["mode"]], sort_keys=True)
        curves.setdefault(key, (s["scheme"], s["mode"], []))[2].append(
            (r["totals"]["memory_bytes"], r["totals"]["error_rate"], s["resolution"]))
    lines = [f"Against {csm['technique']['label']}: error {100 * error:.3f} %, "
             f"memory {memory / 2**20:.2f} MiB.", ""]
    rows = []
    for scheme, mode, points in sorted(curves.values()):
        points.sort()
        match = crossing_memory(points, error)
        at = interpolate(points, memory, 0, 1)
        res = ", ".join(f"{p[2] // 1024}K" if p[2] >= 1024 else str(p[2]) for p in points)
        rows.append([scheme, mode, res,
                     "not within these" if match is None else f"{match / 2**20:.2f}",
                     "outside these" if at is None else f"{100 * at:.3f}"])
    header = ["scheme", "mode", "resolutions", "memory matching CSM's error (MiB)",
              "error at CSM's memory %"]
    return lines + markdown_table(header, rows, label_columns=3).splitlines()


def junction_distance(layout, grid):
    """The camera's distance to the nearest point where four IASM tiles meet, in tile sides."""
    x0, y0, side = layout["square"]
    tile = side / grid
    ex, ey = (layout["eye"][0] - x0) / tile, (layout["eye"][1] - y0) / tile
    inner = range(1, grid)
    return min((math.hypot(ex - i, ey - j) for i in inner for j in inner), default=math.inf)


def corner_table(records):
    """Alecu Fig. 4.3-4.4: IASM's error over CSM's, per frame, by how near the camera sits to a
    point where four tiles meet (there, four tiles need a high resolution at once). On the circle
    inscribed in a 4 x 4 grid the camera comes within 2 - sqrt(2) = 0.59 tile of a junction when
    it looks along a diagonal of the light frustum, and stays 1 tile away along an axis."""
    csm = thesis_csm(records)
    if csm is None:
        return []
    rows = []
    for r in records:
        if r["technique"]["name"] != "iasm" or r["technique"]["params"].get("placement") == "scene":
            continue
        grid = int(r["technique"]["params"].get("grid", "4"))
        near, far = [], []
        for frame, base in zip(r["frames"], csm["frames"]):
            wrong = frame["false_lit"] + frame["false_shadow"]
            base_wrong = base["false_lit"] + base["false_shadow"]
            if base_wrong == 0:
                continue
            group = near if junction_distance(frame["layout"], grid) < 0.75 else far
            group.append(wrong / base_wrong)

        def cell(ratios):
            return f"{statistics.median(ratios):.2f}× CSM" if ratios else "–"
        rows.append([r["technique"]["label"], cell(near), str(len(near)), cell(far), str(len(far))])
    header = ["IASM", "camera within 0.75 tile of a four-tile junction", "frames", "elsewhere",
              "frames"]
    return markdown_table(header, rows).splitlines() if rows else []


def stage_table(records):
    rows = [[f"paper: {name}", ms(readback), ms(shadows), ms(scene), ms(frame)]
            for name, readback, shadows, scene, frame in ALECU_TABLE_4_1]
    for r in records:
        if r["technique"]["kind"] != "view-dependent":
            continue
        t = r["totals"]
        build, shade = t["build_ms_median"], t["shade_ms_median"]
        rows.append([f"ours (CPU): {r['technique']['label']}", "–", ms(build), ms(shade),
                     ms(build + shade)])
    lines = markdown_table(["", "Readback", "Shadows", "Scene", "Frame"], rows).splitlines()
    lines += ["", "Ours: median per frame on this machine's CPU; Shadows = rendering the cascades or "
              "tiles with the light-space rasteriser, Scene = the shadow lookups of every pixel "
              "(no shading), Readback = none (the importance stays in memory)."]
    return lines


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("records", type=Path)
    args = parser.parse_args()
    groups = group_by_path(read_view_records(args.records, "views_tables.py"), "views_tables.py")
    if not groups:
        sys.exit(f"views_tables.py: no view records under {args.records}")
    out = []
    for name, entries in sorted(groups.items()):
        records = [record for record, _ in entries]
        first = records[0]
        out += [f"## {name}: {first['scene']['spec']}, {first['path']['frames']} frames at "
                f"{first['path']['width']}×{first['path']['height']}", ""]
        out += technique_table(records) + [""]
        questions = csm_questions(records)
        if questions:
            out += ["### Precomputed schemes against CSM 3 × 1024²", ""] + questions + [""]
        corners = corner_table(records)
        if corners:
            out += ["### IASM near a four-tile junction (Alecu Fig. 4.3-4.4)", "",
                    "Median over frames of IASM's wrongly shadowed pixels over CSM's "
                    f"({thesis_csm(records)['technique']['label']}).", ""] + corners + [""]
        out += ["### Stage costs beside Alecu 2014 Table 4.1 (ms)", ""] + stage_table(records) + [""]
    print("\n".join(out))


if __name__ == "__main__":
    main()
