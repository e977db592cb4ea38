"""scripts/reproduce/paper_tables.py: every table from the fixture's real records, against the
Markdown that paper_tables.py printed for them before it was split into figures, cells and
renderers (commit 0ecf5bb, golden/TABLE_MAXRES.md). After a deliberate change to a table,
accept the new text with SHADOWBENCH_UPDATE_GOLDEN=1 and review the diff."""

import argparse
import contextlib
import copy
import io
import json
import os
import re
import subprocess
import sys
import unittest

import support
from number_format import significant
from records import read_records
from scheme_registry import parse_schemes_json

import paper_tables
from cells import Cells, TableError

GOLDEN = support.HERE / "golden"
DISPLAYED_RECORDS = "tests/python/fixtures/records"  # as the golden tables name the folder
MIB = 1 << 20
MAX_RESOLUTIONS = {"1K": 1024, "64K": 64 * 1024}


def fixture_records(defaults=None):
    """The fixture's records, validated against the record schema where the checkout has it."""
    schema = None if support.RECORD_SCHEMA.is_file() else {}
    with contextlib.redirect_stderr(io.StringIO()) as stderr:
        files = read_records(support.FIXTURE_RECORDS, "test", schema)
    assert not files.skipped, stderr.getvalue()
    if defaults is None:
        defaults = parse_schemes_json(support.SCHEMES_JSON.read_text(encoding="utf-8"))
    return Cells(files, defaults, support.FIXTURE_RECORDS, "test")


def arguments(table, max_resolution):
    return argparse.Namespace(table=table, records=DISPLAYED_RECORDS,
                              max_resolution=MAX_RESOLUTIONS[max_resolution],
                              command=f"scripts/reproduce/{table}.sh --max-resolution "
                                      f"{max_resolution}")


class EveryTable(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.records = fixture_records()

    def test_every_table_renders_as_before(self):
        self.assertEqual(len(paper_tables.TABLES), 19)
        for table in sorted(paper_tables.TABLES):
            for max_resolution in MAX_RESOLUTIONS:
                with self.subTest(table=table, max_resolution=max_resolution):
                    got = paper_tables.render(table, self.records,
                                              arguments(table, max_resolution))
                    golden = GOLDEN / f"{table}_{max_resolution}.md"
                    if os.environ.get("SHADOWBENCH_UPDATE_GOLDEN") == "1":
                        golden.write_text(got, encoding="utf-8")
                    self.assertEqual(got, golden.read_text(encoding="utf-8"))

    def test_tables_hold_our_numbers(self):
        """Not only dashes: the fixture's cells appear (mh's city closed sizes: 0.593 MiB at 512²,
        1.30 MiB at 1K²)."""
        text = paper_tables.render("scandolo2016-table1", self.records,
                                   arguments("scandolo2016-table1", "1K"))
        self.assertIn("| mh city closed (MH) | 0.593 | 1.30 |\n", text)


class PartsCost(unittest.TestCase):

    def test_a_build_in_parts_beside_its_whole_build(self):
        schema = None if support.RECORD_SCHEMA.is_file() else {}
        folder = support.FIXTURES / "parts-records"
        with contextlib.redirect_stderr(io.StringIO()):
            files = read_records(folder, "test", schema)
        defaults = parse_schemes_json(support.SCHEMES_JSON.read_text(encoding="utf-8"))
        text = paper_tables.render("parts-cost", Cells(files, defaults, folder, "test"),
                                   arguments("parts-cost", "1K"))
        self.assertIn("| mh | city closed | 1K² | 256² | 1.30 | 1.30 | +0.00% | 0.165 | 0.182 | "
                      "0.154 | 0.154 | 0.146 | – | – | 0.0818 | – |\n", text)


class RegistryDefaults(unittest.TestCase):
    """The papers' rows are the cells at the registry's defaults, not at numbers of the script's
    own: other defaults pick other records."""

    def test_other_defaults_pick_other_cells(self):
        defaults = parse_schemes_json(support.SCHEMES_JSON.read_text(encoding="utf-8"))
        moved = copy.deepcopy(defaults)
        moved["mmh"]["search-distance"] = "100"
        table, args = "scandolo2016-table1", arguments("scandolo2016-table1", "1K")
        at_registry = paper_tables.render(table, fixture_records(defaults), args)
        at_moved = paper_tables.render(table, fixture_records(moved), args)
        size = {}
        for distance in ("1000", "100"):
            record = json.loads((support.FIXTURE_RECORDS / "city-size-36-seed-1_0_closed_mmh_"
                                 f"search-distance-{distance}_1024.json").read_text())
            size[distance] = f"{record['size_bytes']['total'] / (1 << 20):.3g}"
        row = r"\| mmh city closed \(MMH, search distance 1000\) \| [^|]+ \| {} \|\n"
        self.assertRegex(at_registry, row.format(re.escape(size["1000"])))
        self.assertRegex(at_moved, row.format(re.escape(size["100"])))
        self.assertNotEqual(size["1000"], size["100"])


class IntervalTests(support.TemporaryFolder):
    """Table 3 shows mmh's interval test both ways and Alg. 3's, each from its own cell."""

    def test_both_interval_tests_have_rows(self):
        name = "city-size-36-seed-1_0_closed_mmh_search-distance-1000_1024.json"
        ours = support.fixture_record(name)
        printed = copy.deepcopy(ours)
        printed["scheme"]["params"]["interval-test"] = "paper"
        counters = printed["counters"]
        moved = counters["rejected interval"] // 2
        counters["rejected interval"] -= moved
        counters["rejected full test"] += moved
        self.write(name, json.dumps(ours))
        self.write("paper.json", json.dumps(printed))
        with contextlib.redirect_stderr(io.StringIO()):
            files = read_records(self.folder, "test", {})
        defaults = parse_schemes_json(support.SCHEMES_JSON.read_text(encoding="utf-8"))
        text = paper_tables.render("scandolo2016-table3", Cells(files, defaults, self.folder,
                                                                "test"),
                                   arguments("scandolo2016-table3", "1K"))
        tested = ours["counters"]["pairs tested"]
        for label, record in (("both ways", ours), ("Alg. 3's test", printed)):
            share = 100 * record["counters"]["rejected interval"] / tested
            self.assertRegex(text, rf"\| mmh city closed, {re.escape(label)} \| 1K² \| [^|]+ \| "
                                   rf"{re.escape(f'{share:.3g}')} % \|")


class SkipLevelZero(support.TemporaryFolder):
    """The 2021 Table 1 twin shows dag-mh without its skip list as a row of its own, beside the
    default's, and its ratio to mmh from that cell."""

    def test_dag_mh_without_skip_list_has_its_rows(self):
        name = ("city-size-36-seed-1_0_closed_dag-mh_chunk-size-32_skip-level-6_treelet-height-4_"
                "1024.json")
        mmh_name = "city-size-36-seed-1_0_closed_mmh_search-distance-1000_1024.json"
        ours, mmh = support.fixture_record(name), support.fixture_record(mmh_name)
        flat = copy.deepcopy(ours)
        flat["scheme"]["params"]["skip-level"] = "0"
        sizes = flat["size_bytes"]
        sizes["total"] -= sizes["components"].pop("skip list")
        for file_name, record in ((name, ours), ("flat.json", flat), (mmh_name, mmh)):
            self.write(file_name, json.dumps(record))
        with contextlib.redirect_stderr(io.StringIO()):
            files = read_records(self.folder, "test", {})
        defaults = parse_schemes_json(support.SCHEMES_JSON.read_text(encoding="utf-8"))
        text = paper_tables.render("scandolo2021-table1",
                                   Cells(files, defaults, self.folder, "test"),
                                   arguments("scandolo2021-table1", "1K"))
        for record, label in ((ours, r"\(DAG-MH, treelets of 4, chunks of 32\)"),
                              (flat, r"\(skip level 0: no skip list\)")):
            size = significant(record["size_bytes"]["total"] / MIB)
            self.assertRegex(text, rf"\| dag-mh city closed {label} \| {re.escape(size)} \|")
        ratio = 100 * flat["size_bytes"]["total"] / mmh["size_bytes"]["total"]
        self.assertRegex(text, rf"\| city closed: dag-mh skip level 0 / mmh \| "
                               rf"{re.escape(significant(ratio))} \|")


class CoarseClassifications(support.TemporaryFolder):
    """Kämpe Table 2 shows cpvs-fast's coarse volumes classified both ways, each from its own
    cell, beside cpvs: a folder holding both variants is not refused as mixed."""

    def test_both_classifications_have_columns(self):
        prefix = "city-size-36-seed-1_0_closed_cpvs"
        old = support.fixture_record(f"{prefix}_grid-levels-0_leaf-layout-slab8_1024.json")
        masks = support.fixture_record(f"{prefix}-fast_culling-on_grid-levels-0_"
                                       "leaf-layout-slab8_transitions-aligned_1024.json")
        depth = copy.deepcopy(masks)
        depth["scheme"]["params"]["coarse-classification"] = "depth-hierarchy"
        depth["size_bytes"]["total"] = masks["size_bytes"]["total"] * 3 // 4
        for name, record in (("old", old), ("masks", masks), ("depth", depth)):
            self.write(f"{name}.json", json.dumps(record))
        with contextlib.redirect_stderr(io.StringIO()):
            files = read_records(self.folder, "test", {})
        defaults = parse_schemes_json(support.SCHEMES_JSON.read_text(encoding="utf-8"))
        text = paper_tables.render("kampe2015-table2", Cells(files, defaults, self.folder,
                                                             "test"),
                                   arguments("kampe2015-table2", "1K"))
        sizes = [r["size_bytes"]["total"] for r in (masks, depth, old)]
        cells = [f"{b / (1 << 20):.3g}" for b in sizes]
        cells += [f"{sizes[2] / b:.3g}" for b in sizes[:2]]
        self.assertIn(f"| 1K² | {' | '.join(cells)} | – | – | – |\n", text)


class Refusals(support.TemporaryFolder):

    def records_of(self, *names, edit=None):
        for name in names:
            record = support.fixture_record(name)
            if edit:
                edit(record)
            self.write(name, json.dumps(record))
        with contextlib.redirect_stderr(io.StringIO()):
            return read_records(self.folder, "test", {})

    def test_two_scenes_of_one_generator(self):
        name = "city-size-36-seed-1_0_closed_mh_1024.json"
        files = self.records_of(name, edit=lambda record: record["scene"].update(
            name="city:size=12,seed=2"))
        self.write("other.json", json.dumps(support.fixture_record(name)))
        with contextlib.redirect_stderr(io.StringIO()):
            files = read_records(self.folder, "test", {})
        with self.assertRaisesRegex(TableError, "several scenes of one generator"):
            Cells(files, {}, self.folder, "test")

    def test_variants_a_table_cannot_tell_apart(self):
        files = self.records_of(
            "city-size-36-seed-1_0_closed_mmh_search-distance-1000_1024.json",
            "city-size-36-seed-1_0_closed_mmh_search-distance-100_1024.json")
        records = Cells(files, {}, self.folder, "test")  # no defaults: both are mmh's cell
        with self.assertRaisesRegex(TableError, "mmh city closed 1024² has records with "
                                                "different parameters"):
            records.at_defaults("mmh", "city", "closed")


class CommandLine(support.TemporaryFolder):
    """`paper_tables.py TABLE RECORDS_DIR` as the reproduce scripts run it (from the repository
    root, the registry from ${SHADOWBENCH_BUILD:-build}/harness/shadowbench)."""

    def run_script(self, *args, build=None):
        env = support.environment(SHADOWBENCH_BUILD=build or self.registry_build())
        return subprocess.run([sys.executable, str(support.REPRODUCE / "paper_tables.py"), *args],
                              cwd=support.REPOSITORY, env=env, capture_output=True, text=True,
                              check=False)

    def test_a_table_as_the_scripts_make_it(self):
        support.require_record_schema(self)
        done = self.run_script("scandolo2021-table3", DISPLAYED_RECORDS, "--max-resolution", "1K",
                               "--command", "scripts/reproduce/scandolo2021-table3.sh "
                               "--max-resolution 1K")
        self.assertEqual((done.returncode, done.stderr), (0, ""))
        self.assertEqual(done.stdout,
                         (GOLDEN / "scandolo2021-table3_1K.md").read_text(encoding="utf-8"))

    def test_bad_records_are_named_and_the_table_still_made(self):
        support.require_record_schema(self)
        self.write("records/a.json", (support.FIXTURE_RECORDS /
                                      "city-size-36-seed-1_0_closed_mh_1024.json").read_text())
        self.write("records/b.json", "{\"format\": \"shadowbench-rec")
        done = self.run_script("compare-size", str(self.folder / "records"))
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertEqual(done.stderr.strip(),
                         f"paper_tables.py: skipped {self.folder / 'records/b.json'}: not JSON "
                         "(Unterminated string starting at: line 1 column 12 (char 11))")
        self.assertIn("| mh (Scandolo 2016a, multiresolution hierarchy) |", done.stdout)

    def test_no_registry_no_table(self):
        done = self.run_script("compare-size", DISPLAYED_RECORDS, build=self.folder / "none")
        self.assertEqual(done.returncode, 1)
        self.assertRegex(done.stderr, r"^paper_tables.py: the scheme defaults come from `.*"
                                      r"/none/harness/shadowbench schemes --json`")

    def test_an_empty_folder(self):
        support.require_record_schema(self)
        (self.folder / "empty").mkdir()
        done = self.run_script("compare-size", str(self.folder / "empty"))
        self.assertEqual(done.returncode, 1)
        self.assertIn("no complete shadowbench records", done.stderr)


class Duplicates(support.TemporaryFolder):

    def test_an_older_record_of_a_cell_is_named(self):
        name = "city-size-36-seed-1_0_closed_mh_1024.json"
        newer = support.fixture_record(name)
        older = dict(newer, created="2000-01-01T00:00:00Z")
        self.write(name, json.dumps(newer))
        path = self.write("older/copy.json", json.dumps(older))
        with contextlib.redirect_stderr(io.StringIO()):
            files = read_records(self.folder, "test", {})
        stderr = io.StringIO()
        with contextlib.redirect_stderr(stderr):
            records = Cells(files, {}, self.folder, "test")
        self.assertEqual(records.find("mh", "city", "closed")[1024]["created"], newer["created"])
        self.assertEqual(stderr.getvalue(),
                         f"test: '{path}' and '{self.folder / name}' are records of one cell (mh, "
                         "city, closed, 1024²): the first is not used (created "
                         f"2000-01-01T00:00:00Z, the used one {newer['created']})\n")
