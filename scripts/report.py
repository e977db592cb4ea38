#!/usr/bin/env python3
"""One static HTML report of a records folder: everything the folder's records say, in a page
that opens from disk with no network.

    python3 scripts/report.py RECORDS_DIR [--out DIR] [--shadowbench PATH] [--frames N]

Writes DIR/index.html (default RECORDS_DIR/report/) with its PNGs and images beside it, every
link relative. The page holds:
  - the machines and commits the records were made on;
  - the harness's tables of the build records (size, build time, lookup, verification), made by
    `shadowbench table` (--shadowbench, default build/harness/shadowbench as
    scripts/scheme_registry.py finds it), and every Markdown document under the folder (the
    paper twins of scripts/reproduce/, ablation tables), converted to HTML;
  - per scene, light and mode, plot.py's size and build-time plots, and size against point
    lookup time per query set, with the Pareto front (smaller and faster) of each resolution;
  - per camera path of the view records, a table of its techniques, error against memory with
    its Pareto front (views.py, as plot_views.py draws it), and the truth, mask and error
    images of N frames spread from the first to the last (default 3), copied into DIR.
A folder with only build records or only view records gives the page of what it has; a folder
with neither is an error. Files that are not records are named on standard error.
"""

import argparse
import html
import shutil
import subprocess
import sys
import tempfile
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent / "reproduce"))  # table_format

from plot import (file_name_part, group_records, plot_group, resolution_label, variant_label,
                  variant_order)
from plot_views import import_pyplot
from pareto import plot_front
from records import (SUPERSEDED_FOLDER, SchemaUnavailable, lookup_ns, read_records, size_bytes)
from scheme_registry import shadowbench_binary
from table_format import markdown_table
from views import (TABLE_HEADER, frame_picks, group_by_path, plot_error_memory,
                   read_view_records, table_row, technique_label)

PROGRAM = "report.py"
QUERY_SETS = ("uniform", "view")  # harness/query_sets.h: random texels, and texels a camera sees
POINT = 1  # the filter of a point lookup (k×k with k = 1)
HARNESS_TABLES = Path("tables") / "tables.md"  # what `shadowbench table` writes into a folder

# After the page has loaded, counts the images that loaded and outlines those that did not, so
# that a reader sees a broken image and a test can read the count from the DOM.
IMAGE_CHECK = """<script>
window.addEventListener("load", function () {
  var images = Array.prototype.slice.call(document.images);
  var loaded = images.filter(function (image) {
    return image.complete && image.naturalWidth > 0;
  });
  images.forEach(function (image) {
    if (loaded.indexOf(image) < 0) image.classList.add("broken");
  });
  document.body.dataset.imagesTotal = images.length;
  document.body.dataset.imagesOk = loaded.length;
});
</script>"""

STYLE = """<style>
body { font-family: sans-serif; margin: 2em; max-width: 100em; }
table { border-collapse: collapse; margin: 0.5em 0 1.5em; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.5em; }
td:not(:first-child) { text-align: right; }
img { max-width: 100%; }
img.frame { width: 24em; image-rendering: pixelated; }
img.broken { outline: 3px solid red; }
.missing { color: #b00; }
li.level3 { margin-left: 2em; font-size: 0.9em; }
</style>"""


def import_markdown():
    try:
        import markdown
    except ImportError:
        sys.exit(f"{PROGRAM}: the Python package markdown is needed by {sys.executable} (Debian's "
                 "python3-markdown serves /usr/bin/python3; scripts/install-deps.sh installs it)")
    return markdown


class Page:
    """The HTML of the page as it is written, section by section, with its table of contents."""

    def __init__(self, markdown):
        self.markdown = markdown
        self.parts, self.contents = [], []

    def heading(self, level, text):
        """A heading; those of levels 2 and 3 are listed in the contents."""
        anchor = f"s{len(self.parts) + 1}"
        if level in (2, 3):
            self.contents.append((level, anchor, text))
        self.parts.append(f'<h{level} id="{anchor}">{html.escape(text)}</h{level}>')

    def text(self, text):
        self.parts.append(f"<p>{html.escape(text)}</p>")

    def raw(self, markup):
        self.parts.append(markup)

    def from_markdown(self, text):
        """Markdown as HTML, its headings moved down three levels (h1 → h4) to sit inside the
        page's sections."""
        self.parts.append(self.markdown.markdown(
            text, extensions=["tables", "toc"], extension_configs={"toc": {"baselevel": 4}}))

    def image(self, relative, alt, css_class=None):
        klass = f' class="{css_class}"' if css_class else ""
        return f'<img src="{html.escape(relative)}" alt="{html.escape(alt)}"{klass}>'

    def html(self, title):
        contents = "".join(f'<li class="level{level}"><a href="#{anchor}">{html.escape(text)}</a>'
                           "</li>" for level, anchor, text in self.contents)
        return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                f"<title>{html.escape(title)}</title>\n{STYLE}\n</head>\n<body>\n"
                f"<h1>{html.escape(title)}</h1>\n<ul>{contents}</ul>\n"
                + "\n".join(self.parts) + f"\n{IMAGE_CHECK}\n</body>\n</html>\n")


def machine_text(machine):
    """'AMD EPYC, 2 cores, 23.5 GiB, Linux …' of a record's machine."""
    if not isinstance(machine, dict):
        return "unknown machine"
    words = [str(machine.get("cpu", "unknown CPU"))]
    if isinstance(machine.get("cores"), int):
        words.append(f"{machine['cores']} cores")
    if isinstance(machine.get("memory_bytes"), (int, float)):
        words.append(f"{machine['memory_bytes'] / (1 << 30):.1f} GiB")
    if machine.get("os"):
        words.append(str(machine["os"]))
    return ", ".join(words)


def write_provenance(page, records):
    """The distinct machines and commits, each with how many records it made."""
    page.heading(2, "Machines and commits")
    for what, counts in (("machine", Counter(machine_text(r.get("machine")) for r in records)),
                         ("commit", Counter(str(r.get("commit", "unknown")) for r in records))):
        rows = [[html.escape(name), str(count)] for name, count in sorted(counts.items())]
        page.from_markdown(markdown_table([what, "records"], rows))


def harness_tables(records_dir, binary):
    """The Markdown of `shadowbench table RECORDS_DIR`, or (None, why not). Its stderr, which
    names the files it leaves out (view records among them), is dropped: read_records has
    named the files that are not build records already."""
    if not Path(binary).is_file():
        return None, (f"{binary} does not exist: build it (cmake --build build --target "
                      "shadowbench) or give --shadowbench")
    with tempfile.TemporaryDirectory(prefix="shadowbench-report-") as out:
        done = subprocess.run([str(binary), "table", str(records_dir), "--out", out],
                              capture_output=True, text=True, check=False)
        tables = Path(out) / "tables.md"
        if done.returncode != 0 or not tables.is_file():
            said = done.stderr.strip().splitlines()
            return None, (f"`{binary} table` failed (exit status {done.returncode})"
                          + (f": {said[-1]}" if said else ""))
        return tables.read_text(encoding="utf-8"), None


def markdown_documents(records_dir, out_dir):
    """Every Markdown document under the folder — the paper twins, ablation tables — but for
    the harness's own tables/tables.md (the tables section renders them from every record),
    README.md files (notes about a folder) and anything in the report or a superseded folder."""
    found = []
    for path in sorted(records_dir.rglob("*.md")):
        relative = path.relative_to(records_dir)
        if (path.name == "README.md" or relative.parts[-2:] == HARNESS_TABLES.parts
                or SUPERSEDED_FOLDER in relative.parts or out_dir in path.parents):
            continue
        found.append(path)
    return found


def write_tables(page, records_dir, out_dir, builds, binary):
    documents = markdown_documents(records_dir, out_dir)
    if not builds.records and not documents:
        return
    page.heading(2, "Tables")
    if builds.records:
        tables, why_not = harness_tables(records_dir, binary)
        if tables is None:
            print(f"{PROGRAM}: no harness tables: {why_not}", file=sys.stderr)
            page.raw(f'<p class="missing">The harness\'s tables are missing: '
                     f'{html.escape(why_not)}</p>')
        else:
            page.heading(3, "The harness's tables of every build record")
            page.from_markdown(tables)
    for path in documents:
        page.heading(3, str(path.relative_to(records_dir)))
        page.from_markdown(path.read_text(encoding="utf-8"))


def plot_lookup_fronts(plt, key, variants, out_dir):
    """Size against one-thread point lookup time of one (scene, light, mode), every variant and
    resolution a point, one plot per query set. Each resolution has its own front (smaller and
    faster): maps of different resolutions answer different questions. Returns [(PNG path,
    title, {resolution: front labels})]."""
    scene, light, mode = key
    written = []
    for query_set in QUERY_SETS:
        points, labels, resolutions = [], [], []
        for label in sorted(variants, key=variant_order):
            for resolution, record in sorted(variants[label].items()):
                ns = lookup_ns(record, query_set, POINT)
                if ns:
                    points.append((size_bytes(record), ns))
                    labels.append(f"{label} {resolution_label(resolution)}²")
                    resolutions.append(resolution)
        if not points:
            continue
        title = f"{scene}, light {light}, {mode}, {query_set} queries"
        # Tall enough for the legend's line per point.
        figure, axes = plt.subplots(figsize=(11, max(5.5, 1.5 + 0.16 * len(points))))
        axes.set_xscale("log")
        axes.set_yscale("log")
        fronts = plot_front(axes, points, labels, resolutions)
        axes.set_xlabel("size (bytes)")
        axes.set_ylabel("point lookup, one thread (ns/query)")
        axes.set_title("Size against point lookup, a front per resolution (lower left is "
                       f"better)\n{title}")
        figure.tight_layout()
        path = out_dir / (f"lookup-front_{file_name_part(scene)}_{light}_"
                          f"{file_name_part(mode)}_{query_set}.png")
        figure.savefig(path, dpi=120)
        plt.close(figure)
        written.append((path, title, {resolution: [labels[i] for i in front]
                                      for resolution, front in sorted(fronts.items())}))
    return written


def write_build_plots(page, plt, builds, out_dir):
    """Per (scene, light, mode), plot.py's size and build time against resolution where some
    variant has two resolutions (a line; a single resolution is all in the tables, and the
    many-lights records alone make a group per light), and the lookup fronts."""
    from matplotlib.ticker import NullLocator
    plots = out_dir / "plots"
    plots.mkdir(parents=True, exist_ok=True)
    page.heading(2, "Plots of the build records")
    single = 0
    for key, variants in sorted(group_records(builds, PROGRAM).items()):
        lines = any(len(cells) > 1 for cells in variants.values())
        fronts = plot_lookup_fronts(plt, key, variants, plots)
        if not lines and not fronts:
            single += 1
            continue
        scene, light, mode = key
        page.heading(3, f"{scene}, light {light}, {mode}")
        for path in plot_group(plt, NullLocator, key, variants, plots) if lines else []:
            page.raw(f"<p>{page.image(path.relative_to(out_dir).as_posix(), path.stem)}</p>")
        for path, title, by_resolution in fronts:
            page.raw(f"<p>{page.image(path.relative_to(out_dir).as_posix(), title)}</p>")
            page.raw("<p>Pareto front (smaller and faster) per resolution:</p><ul>" + "".join(
                f"<li>{resolution_label(r)}²: {html.escape('; '.join(front))}</li>"
                for r, front in by_resolution.items()) + "</ul>")
    if single:
        page.text(f"{single} (scene, light, mode) groups of one resolution and no lookup "
                  "timings are not plotted: their figures are in the tables.")


def copy_image(records_dir, record_file, relative, out_dir):
    """The image `relative` (to its record's folder) copied into OUT/images at its place under
    the records folder, so that an image the techniques share (the truth) has one copy; the
    copy's path relative to OUT, or None (named on stderr) if the image is missing."""
    source = (Path(record_file).parent / relative).resolve()
    if not source.is_file():
        print(f"{PROGRAM}: {record_file}: image '{relative}' does not exist", file=sys.stderr)
        return None
    try:
        place = source.relative_to(records_dir.resolve())
    except ValueError:  # outside the folder: kept apart by its record's name
        place = Path("outside") / file_name_part(Path(record_file).stem) / source.name
    target = out_dir / "images" / place
    target.parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(source, target)
    return target.relative_to(out_dir).as_posix()


def write_views(page, plt, views, records_dir, out_dir, frames_wanted):
    plots = out_dir / "plots"
    plots.mkdir(parents=True, exist_ok=True)
    page.heading(2, "Views")
    for name, entries in sorted(group_by_path(views, PROGRAM).items()):
        records = [record for record, _ in entries]
        path = records[0]["path"]
        page.heading(3, f"Path {name}")
        scene = records[0].get("scene") or {}
        page.text(f"{scene.get('spec', '')} {path.get('file', '')}, "
                  f"{path.get('frames', '?')} frames of {path.get('width', '?')}×"
                  f"{path.get('height', '?')}; medians of the frames' times.")
        page.from_markdown(markdown_table(TABLE_HEADER, [[html.escape(cell) for cell in
                                                          table_row(r)] for r in records]))
        plot, front = plot_error_memory(plt, name, records, plots)
        page.raw(f"<p>{page.image(plot.relative_to(out_dir).as_posix(), plot.stem)}</p>")
        page.text("Pareto front (less error, less memory): " + "; ".join(front))
        write_frames(page, entries, records_dir, out_dir, frames_wanted)


def write_frames(page, entries, records_dir, out_dir, frames_wanted):
    """Per picked frame a row per technique: the truth, its mask and its error side by side."""

    def cell(record_file, frame, kind):
        relative = frame.get("images", {}).get(kind)
        copied = relative and copy_image(records_dir, record_file, relative, out_dir)
        if not copied:
            return f'<td class="missing">no {kind} image</td>'
        alt = f"{kind}, frame {frame.get('frame')}"
        return f"<td>{page.image(copied, alt, 'frame')}</td>"

    count = max(len(record["frames"]) for record, _ in entries)
    for index in frame_picks(count, frames_wanted):
        rows = [f"<tr><th>{html.escape(technique_label(record))}</th>"
                + "".join(cell(record_file, record["frames"][index], kind)
                          for kind in ("truth", "mask", "error")) + "</tr>"
                for record, record_file in entries if index < len(record["frames"])]
        page.heading(4, f"Frame {index}")
        page.raw("<table><tr><th></th><th>truth</th><th>mask</th><th>error</th></tr>"
                 + "".join(rows) + "</table>")


def main():
    parser = argparse.ArgumentParser(description="One static HTML report of a folder of "
                                                 "shadowbench build and view records.")
    parser.add_argument("records", type=Path, help="folder of JSON records (searched recursively)")
    parser.add_argument("--out", type=Path, help="folder of index.html (default: RECORDS/report)")
    parser.add_argument("--shadowbench", type=Path, default=None,
                        help="the shadowbench binary that renders the tables (default: "
                             "build/harness/shadowbench, or SHADOWBENCH_BUILD's)")
    parser.add_argument("--frames", type=int, default=3,
                        help="frames of each path shown, spread from first to last (default 3)")
    args = parser.parse_args()
    records_dir = args.records
    if not records_dir.is_dir():
        sys.exit(f"{PROGRAM}: '{records_dir}' is not a folder of records")
    out_dir = (args.out or records_dir / "report").resolve()
    markdown = import_markdown()
    try:
        builds = read_records(records_dir, PROGRAM)
    except SchemaUnavailable as error:
        sys.exit(f"{PROGRAM}: {error}")
    views = read_view_records(records_dir, PROGRAM, name_unreadable=False)
    if not builds.records and not views.records:
        sys.exit(f"{PROGRAM}: no records under '{records_dir}': neither build records "
                 "(\"format\": \"shadowbench-record/1\") nor view records "
                 "(\"format\": \"shadowbench-view-record\")")
    plt = import_pyplot(PROGRAM)
    out_dir.mkdir(parents=True, exist_ok=True)

    page = Page(markdown)
    page.text(f"{len(builds.records)} build records and {len(views.records)} view records "
              f"under {records_dir}.")
    write_provenance(page, builds.records + views.records)
    write_tables(page, records_dir.resolve(), out_dir, builds,
                 args.shadowbench or shadowbench_binary())
    if builds.records:
        write_build_plots(page, plt, builds, out_dir)
    if views.records:
        write_views(page, plt, views, records_dir, out_dir, args.frames)
    index = out_dir / "index.html"
    index.write_text(page.html(f"shadowbench report — {records_dir}"), encoding="utf-8")
    print(index)
    return 0


if __name__ == "__main__":
    sys.exit(main())
