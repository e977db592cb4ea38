"""scripts/plot.py: which records it plots (--schemes, --param, --defaults), and a run."""

import contextlib
import io
import subprocess
import sys

import support
from records import RecordFiles
from scheme_registry import parse_schemes_json

import plot

DAG_MH = ("city-size-36-seed-1_0_closed_dag-mh_chunk-size-{}_skip-level-6_treelet-height-{}_"
          "1024.json")


class Selection(support.TemporaryFolder):

    def setUp(self):
        super().setUp()
        self.defaults = parse_schemes_json(support.SCHEMES_JSON.read_text(encoding="utf-8"))
        self.at_defaults = support.fixture_record(DAG_MH.format(32, 4))
        self.variant = support.fixture_record(DAG_MH.format(32, 2))
        self.sm32 = support.fixture_record("city-size-36-seed-1_0_closed_sm32_1024.json")

    def test_defaults_keep_only_the_registry_cells(self):
        self.assertTrue(plot.selected(self.at_defaults, None, {}, self.defaults))
        self.assertTrue(plot.selected(self.sm32, None, {}, self.defaults))  # no parameters
        self.assertFalse(plot.selected(self.variant, None, {}, self.defaults))
        self.assertFalse(plot.selected(self.at_defaults, None, {}, {}))  # unknown to the registry
        self.assertTrue(plot.selected(self.variant, None, {}, None))

    def test_schemes_and_params(self):
        self.assertFalse(plot.selected(self.sm32, {"dag-mh"}, {}, None))
        self.assertTrue(plot.selected(self.variant, {"dag-mh"}, {"treelet-height": "2"}, None))
        self.assertFalse(plot.selected(self.variant, None, {"treelet-height": "4"}, None))
        self.assertTrue(plot.selected(self.sm32, None, {"treelet-height": "4"}, None))

    def test_the_newest_record_of_a_cell_is_plotted_and_the_other_named(self):
        older = dict(self.sm32, created="2000-01-01T00:00:00Z")
        for records in ([self.sm32, older], [older, self.sm32]):
            paths = [f"{record['created']}.json" for record in records]
            stderr = io.StringIO()
            with contextlib.redirect_stderr(stderr):
                groups = plot.group_records(RecordFiles(records, paths, []))
            self.assertEqual(list(groups), [("city:size=36,seed=1", 0, "closed")])
            self.assertIs(groups[("city:size=36,seed=1", 0, "closed")]["sm32"][1024], self.sm32)
            self.assertIn("plot.py: '2000-01-01T00:00:00Z.json' and", stderr.getvalue())
            self.assertIn("(city:size=36,seed=1, light 0, closed, sm32, 1K²)", stderr.getvalue())


class Run(support.TemporaryFolder):

    def test_plots_of_the_registry_cells(self):
        support.require_record_schema(self)
        done = subprocess.run(
            [sys.executable, str(support.SCRIPTS / "plot.py"), str(support.FIXTURE_RECORDS),
             "--out", str(self.folder), "--schemes", "sm32,mh,mmh,dag-mh", "--defaults"],
            cwd=support.REPOSITORY, capture_output=True, text=True, check=False,
            env=support.environment(SHADOWBENCH_BUILD=self.registry_build()))
        self.assertEqual(done.returncode, 0, done.stderr)
        written = sorted(p.name for p in self.folder.glob("*.png"))
        self.assertIn("size_city-size-36-seed-1_0_closed.png", written)
        self.assertIn("build-time_tangle-size-650-seed-1_0_closed.png", written)
        self.assertEqual(sorted(line.split("/")[-1] for line in done.stdout.split()), written)
