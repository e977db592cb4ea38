"""scripts/report.py: the page of a records folder, checked as a reader gets it — every link
resolves to a file of the report, and, in Debian's headless chromium, every image loads and
nothing is logged to the console. Each check is shown to catch what it looks for."""

import re
import shutil
import subprocess
import sys
import tempfile
import unittest
from html.parser import HTMLParser
from pathlib import Path

import support
from scheme_registry import shadowbench_binary

RECORDS = support.FIXTURES / "report-records"  # build records, view records, a paper twin
CHROMIUM = shutil.which("chromium")


class Links(HTMLParser):
    """The href and src values of a page, and the ids it defines."""

    def __init__(self, text):
        super().__init__()
        self.links, self.ids = [], set()
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if name in ("href", "src"):
                self.links.append(value)
            elif name == "id":
                self.ids.add(value)


def broken_links(index):
    """The links of the page `index` that do not resolve: an anchor it lacks, a file that does
    not exist in its folder, or anything absolute (the report must open from disk alone)."""
    page = Links(index.read_text(encoding="utf-8"))
    broken = []
    for link in page.links:
        if link.startswith("#"):
            ok = link[1:] in page.ids
        else:
            ok = (not re.match(r"^[a-z]+:|^/", link)
                  and (index.parent / link).resolve().is_file())
        if not ok:
            broken.append(link)
    return broken


def browse(page):
    """(DOM after loading, console lines) of `page` in headless chromium. The page logs nothing
    when all is well, so any console line is a fault."""
    with tempfile.TemporaryDirectory(prefix="shadowbench-chromium-") as profile:
        done = subprocess.run(
            [CHROMIUM, "--headless", "--disable-gpu", "--no-sandbox", f"--user-data-dir={profile}",
             "--enable-logging=stderr", "--v=0", "--virtual-time-budget=5000", "--dump-dom",
             page.resolve().as_uri()],
            capture_output=True, text=True, timeout=120, check=False)
    console = [line for line in done.stderr.splitlines() if ":CONSOLE" in line]
    return done.stdout, console


def images_loaded(dom):
    """(images loaded, images) as the page's own check counted them after loading."""
    counts = [re.search(rf'data-images-{name}="(\d+)"', dom) for name in ("ok", "total")]
    if None in counts:
        raise AssertionError("the page's image check did not run:\n" + dom[-2000:])
    return tuple(int(match.group(1)) for match in counts)


class ReportCase(support.TemporaryFolder):
    """Runs report.py on records into self.folder/report."""

    def setUp(self):
        super().setUp()
        support.require_record_schema(self)
        # `shadowbench table RECORDS --out OUT` of a small fixed table: the page is tested, not
        # the harness's tables (harness/table_test.cpp).
        self.binary = self.fake_build(
            '[ "$1 $3" = "table --out" ] || { echo "unexpected: $*" >&2; exit 2; }\n'
            'printf "# shadowbench tables\\n\\n## Size\\n\\n| scheme | 1K² |\\n| --- | ---: |\\n'
            '| mh | 1.30 |\\n" > "$4/tables.md"') / "harness" / "shadowbench"

    def report(self, records, *options):
        out = self.folder / "report"
        done = subprocess.run(
            [sys.executable, str(support.SCRIPTS / "report.py"), str(records), "--out", str(out),
             "--shadowbench", str(self.binary), *options],
            capture_output=True, text=True, check=False)
        return done, out / "index.html"

    def part_of_fixture(self, *names):
        folder = self.folder / "records"
        for name in names:
            shutil.copytree(RECORDS / name, folder / name)
        return folder


class Report(ReportCase):
    """Reports of the fixture folder, of its build records alone and of its views alone."""

    def test_the_whole_folder(self):
        done, index = self.report(RECORDS)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertEqual(done.stdout.strip(), str(index))
        text = index.read_text(encoding="utf-8")
        for expected in ("Machines and commits", "6fe871c0ffee", "Intel(R) Xeon(R) Processor",
                         "example-table.md", "paper: CITY MMH",  # the paper twin
                         "<td>mh</td>",  # the harness's table
                         "size_city-size-36-seed-1_0_closed.png",
                         "lookup-front_city-size-36-seed-1_0_closed_view.png",
                         "error-memory_city-walk.png", "Path city-walk",
                         "csm (cascades=3, resolution=1024, lambda=0.5)", "Frame 0", "Frame 1"):
            self.assertIn(expected, text)
        self.assertEqual(broken_links(index), [])
        # Per frame the truth, and each of the three techniques' mask and error, copied.
        self.assertEqual(len(list((index.parent / "images").rglob("*.png"))), 2 * 7)

    def test_the_harness_tables_from_the_built_binary(self):
        binary = shadowbench_binary()
        if not binary.is_file():
            self.skipTest(f"{binary} is not built: the page's wiring is tested with a stand-in")
        self.binary = binary
        done, index = self.report(self.part_of_fixture("builds"))
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertIn("Size — city:size=36,seed=1, light 0, closed",
                      index.read_text(encoding="utf-8"))

    def test_build_records_alone(self):
        done, index = self.report(self.part_of_fixture("builds"))
        self.assertEqual(done.returncode, 0, done.stderr)
        text = index.read_text(encoding="utf-8")
        self.assertIn("Plots of the build records", text)
        self.assertNotIn("Views", text)
        self.assertEqual(broken_links(index), [])

    def test_view_records_alone(self):
        done, index = self.report(self.part_of_fixture("views"), "--frames", "1")
        self.assertEqual(done.returncode, 0, done.stderr)
        text = index.read_text(encoding="utf-8")
        self.assertIn("Path city-walk", text)
        self.assertNotIn("Plots of the build records", text)
        self.assertNotIn("Tables", text)
        self.assertIn("Frame 0", text)
        self.assertNotIn("Frame 1", text)
        self.assertEqual(broken_links(index), [])

    def test_a_folder_without_records_is_an_error(self):
        (self.folder / "empty").mkdir()
        done, index = self.report(self.folder / "empty")
        self.assertNotEqual(done.returncode, 0)
        self.assertIn("no records under", done.stderr)
        self.assertFalse(index.exists())

    def test_a_missing_frame_image_is_named_and_not_linked(self):
        records = self.part_of_fixture("views")
        (records / "views" / "images" / "city-walk" / "truth-001.png").unlink()
        done, index = self.report(records)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertIn("image 'images/city-walk/truth-001.png' does not exist", done.stderr)
        self.assertIn("no truth image", index.read_text(encoding="utf-8"))
        self.assertEqual(broken_links(index), [])

    def test_the_link_check_finds_a_broken_link(self):
        done, index = self.report(self.part_of_fixture("views"))
        self.assertEqual(done.returncode, 0, done.stderr)
        (index.parent / "plots" / "error-memory_city-walk.png").unlink()
        with index.open("a", encoding="utf-8") as page:
            page.write('<a href="#nowhere">x</a><a href="https://example.org/">y</a>')
        self.assertEqual(broken_links(index),
                         ["plots/error-memory_city-walk.png", "#nowhere", "https://example.org/"])


@unittest.skipIf(CHROMIUM is None, "chromium is not installed (scripts/install-deps.sh installs "
                                   "it): the report is not checked in a browser")
class InABrowser(ReportCase):

    def test_every_image_loads_and_nothing_is_logged(self):
        done, index = self.report(RECORDS)
        self.assertEqual(done.returncode, 0, done.stderr)
        dom, console = browse(index)
        self.assertEqual(console, [])
        loaded, images = images_loaded(dom)
        self.assertEqual(loaded, images)
        self.assertEqual(images, len(re.findall("<img ", index.read_text(encoding="utf-8"))))
        self.assertGreater(images, 14)

    def test_a_broken_image_is_counted(self):
        done, index = self.report(RECORDS)
        self.assertEqual(done.returncode, 0, done.stderr)
        (index.parent / "plots" / "error-memory_city-walk.png").unlink()
        dom, _ = browse(index)
        loaded, images = images_loaded(dom)
        self.assertEqual(loaded, images - 1)
        self.assertIn('class="broken"', dom)

    def test_a_script_error_is_seen_on_the_console(self):
        page = self.write("broken.html", "<!DOCTYPE html><html><body><p>x</p>"
                                         "<script>undefinedFunction();</script></body></html>")
        _, console = browse(page)
        self.assertEqual(len(console), 1, console)
        self.assertIn("undefinedFunction is not defined", console[0])


if __name__ == "__main__":
    unittest.main()
