"""The Markdown of the paper tables: headings, rows of numbers, the preamble every table starts
with, and the units the tables share."""

from number_format import significant

from paper_figures import PAPER_TRIANGLES

MIB = 1 << 20
K = 1024


def shadow_map_16(resolution):
    """Bytes of a 16-bit shadow map, the CPVS papers' reference size."""
    return 2.0 * resolution * resolution


def ratio_of(numerator, denominator, scale=1.0):
    return (scale * numerator / denominator
            if numerator is not None and denominator not in (None, 0) else None)


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


def cap_note(scheme, scene, mode, cells, columns, caps):
    """', not built above 8K²' where a cap of `caps` ({(scheme, scene, mode): resolution}: what a
    script builds only up to a resolution) leaves columns of the row empty."""
    cap = caps.get((scheme, scene, mode))
    return (f", not built above {heading(cap)}"
            if cap and any(r > cap and r not in cells for r in columns) else "")


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

