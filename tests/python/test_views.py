"""scripts/views.py and plot_views.py: which view records are shown, their labels and rows, the
frames picked, and the error-against-memory plot."""

import contextlib
import io
import json
import subprocess
import sys

import support
from views import frame_picks, group_by_path, read_view_records, table_row, technique_label

VIEWS = support.FIXTURES / "report-records" / "views"


def fixture_view(name="city-walk_csm-1024.json"):
    return json.loads((VIEWS / name).read_text(encoding="utf-8"))


class Reading(support.TemporaryFolder):

    def read(self, **options):
        stderr = io.StringIO()
        with contextlib.redirect_stderr(stderr):
            files = read_view_records(self.folder, "test", **options)
        return files, stderr.getvalue()

    def test_build_records_are_passed_over_and_a_broken_view_record_is_named(self):
        self.write("good.json", json.dumps(fixture_view()))
        self.write("build.json", json.dumps(support.fixture_record()))
        broken = fixture_view()
        del broken["totals"]
        self.write("broken.json", json.dumps(broken))
        self.write("cut.json", "{\"format\": \"shadowbench-view")
        files, said = self.read()
        self.assertEqual([p.name for p in files.paths], ["good.json"])
        self.assertIn("skipped view record", said)
        self.assertIn("broken.json: no totals", said)
        self.assertIn("cut.json: not JSON", said)
        _, said = self.read(name_unreadable=False)
        self.assertNotIn("cut.json", said)

    def test_the_newest_record_of_a_path_and_technique_is_shown(self):
        older = dict(fixture_view(), created="2000-01-01T00:00:00Z")
        self.write("a.json", json.dumps(older))
        self.write("b.json", json.dumps(fixture_view()))
        self.write("c.json", json.dumps(fixture_view("city-walk_mmh-1024.json")))
        files, _ = self.read()
        stderr = io.StringIO()
        with contextlib.redirect_stderr(stderr):
            groups = group_by_path(files, "test")
        self.assertEqual(list(groups), ["city-walk"])
        # By memory: the mmh structure is smaller than the 1024² cascades.
        self.assertEqual([path.name for _, path in groups["city-walk"]], ["c.json", "b.json"])
        self.assertIn("a.json' and", stderr.getvalue())


class Fields(support.TemporaryFolder):

    def test_a_precomputed_structure_s_resolution_joins_its_label(self):
        self.assertEqual(technique_label(fixture_view("city-walk_mmh-1024.json")),
                         "mmh (search-distance=1000) 1K²")
        self.assertEqual(technique_label(fixture_view()),
                         "csm (cascades=3, resolution=1024, lambda=0.5)")

    def test_a_table_row(self):
        self.assertEqual(table_row(fixture_view()),
                         ["csm (cascades=3, resolution=1024, lambda=0.5)", "0.0506", "270", "640",
                          "1.14", "12.0", "41.7", "12.8"])

    def test_frames_spread_from_first_to_last(self):
        self.assertEqual(frame_picks(24, 3), [0, 12, 23])
        self.assertEqual(frame_picks(2, 3), [0, 1])
        self.assertEqual(frame_picks(1, 3), [0])
        self.assertEqual(frame_picks(24, 1), [0])
        self.assertEqual(frame_picks(0, 3), [])

    def test_plot_views_writes_a_plot_per_path(self):
        done = subprocess.run([sys.executable, str(support.SCRIPTS / "plot_views.py"), str(VIEWS),
                               "--out", str(self.folder)], capture_output=True, text=True,
                              check=False)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertEqual(done.stdout.split(), [str(self.folder / "error-memory_city-walk.png")])

    def test_plot_views_without_view_records_says_so(self):
        done = subprocess.run([sys.executable, str(support.SCRIPTS / "plot_views.py"),
                               str(self.folder)], capture_output=True, text=True, check=False)
        self.assertNotEqual(done.returncode, 0)
        self.assertIn("no view records", done.stderr)
