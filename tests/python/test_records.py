"""scripts/records.py: which files count as records, and why the others are named."""

import contextlib
import io
import json

import support
from cells import without_depth
from records import (RecordFiles, SchemaUnavailable, cache_hit_rate, component_bytes,
                     is_complete_record, is_newer, lookup_ns, newest_per_cell, read_records,
                     total_seconds)

# A schema of the test's own, so that the validation path is tested whether or not the checkout
# has harness/record.schema.json: sizes must be integers of at least 0.
SIZE_SCHEMA = {"type": "object",
               "properties": {"size_bytes": {"type": "object", "properties": {
                   "total": {"type": "integer", "minimum": 0}}}}}


class ReadRecords(support.TemporaryFolder):

    def read(self, schema=SIZE_SCHEMA):
        """(records, skipped, stderr) of reading self.folder."""
        stderr = io.StringIO()
        with contextlib.redirect_stderr(stderr):
            files = read_records(self.folder, "test", schema)
        self.assertEqual(len(files.paths), len(files.records))
        return files.records, files.skipped, stderr.getvalue()

    def good(self):
        return support.fixture_record()

    def test_a_good_record_counts_and_nothing_is_reported(self):
        self.write("a/good.json", json.dumps(self.good()))
        records, skipped, said = self.read()
        self.assertEqual([r["scheme"]["name"] for r in records], ["mh"])
        self.assertEqual((skipped, said), ([], ""))

    def test_a_half_written_record_is_named_as_not_json(self):
        text = json.dumps(self.good())
        path = self.write("half.json", text[: len(text) // 2])
        records, skipped, said = self.read()
        self.assertEqual(records, [])
        self.assertEqual([p for p, _ in skipped], [path])
        self.assertIn(f"test: skipped {path}: not JSON", said)

    def test_an_empty_record_is_named(self):
        path = self.write("empty.json", "")
        self.write("blank.json", " \n")
        _, skipped, said = self.read()
        self.assertEqual(sorted(why for _, why in skipped), ["empty file", "empty file"])
        self.assertIn(f"test: skipped {path}: empty file", said)

    def test_a_record_of_a_build_that_stopped_is_named(self):
        record = self.good()
        record["complete"] = False
        path = self.write("stopped.json", json.dumps(record))
        _, _, said = self.read()
        self.assertIn(f"test: skipped {path}: \"complete\" is not true", said)

    def test_a_record_against_the_schema_is_named_with_the_field(self):
        record = self.good()
        record["size_bytes"]["total"] = -5  # the "negative size"
        path = self.write("negative.json", json.dumps(record))
        records, _, said = self.read()
        self.assertEqual(records, [])
        self.assertIn(f"test: skipped {path}: does not match the record schema at "
                      "$.size_bytes.total: -5 is less than the minimum of 0", said)

    def test_each_bad_file_is_named_and_the_good_ones_still_count(self):
        self.write("1.json", json.dumps(self.good()))
        self.write("2.json", "")
        self.write("3.json", "[1, 2]")
        self.write("4.json", json.dumps(self.good()))
        self.write("notes.txt", "not a record, not a .json file")
        records, skipped, said = self.read()
        self.assertEqual(len(records), 2)
        self.assertEqual([p.name for p, _ in skipped], ["2.json", "3.json"])
        self.assertEqual(len(said.splitlines()), 2)

    def test_superseded_records_are_not_read(self):
        """A sweep moves the records of an older version of a cell into superseded/ (at any depth,
        as the harness's readRecords skips it)."""
        self.write("a/good.json", json.dumps(self.good()))
        self.write("superseded/old.json", json.dumps(self.good()))
        self.write("a/superseded/older.json", "")
        self.write("a/superseded.json", json.dumps(self.good()))  # a file, not the folder
        records, skipped, said = self.read()
        self.assertEqual((len(records), skipped, said), (2, [], ""))

    def test_view_records_are_left_to_their_reader_unnamed(self):
        """A view record (scripts/views.py) shares the folders; it is not a broken record."""
        self.write("a/good.json", json.dumps(self.good()))
        view = support.FIXTURES / "report-records" / "views" / "city-walk_csm-1024.json"
        self.write("a/view.json", view.read_text(encoding="utf-8"))
        records, skipped, said = self.read()
        self.assertEqual((len(records), skipped, said), (1, [], ""))

    def test_a_missing_schema_stops_before_any_file_is_read(self):
        self.write("1.json", json.dumps(self.good()))
        missing = self.folder / "no-such.schema.json"
        with self.assertRaises(SchemaUnavailable) as raised:
            self.read(missing)
        self.assertIn(str(missing), str(raised.exception))


class RealSchema(support.TemporaryFolder):
    """The records of the fixture against harness/record.schema.json (the records helper's)."""

    def setUp(self):
        super().setUp()
        support.require_record_schema(self)

    def test_every_fixture_record_is_valid(self):
        stderr = io.StringIO()
        with contextlib.redirect_stderr(stderr):
            files = read_records(support.FIXTURE_RECORDS, "test")
        self.assertEqual((files.skipped, stderr.getvalue()), ([], ""))
        self.assertEqual(files.paths, sorted(support.FIXTURE_RECORDS.glob("*.json")))

    def test_nonsense_values_are_refused(self):
        for field, value in ((("size_bytes", "total"), -1), (("resolution",), 1000),
                             (("scheme", "params"), {"treelet-height": 4}),
                             (("mode",), "half-open")):
            with self.subTest(field=field):
                record = support.fixture_record()
                target = record
                for key in field[:-1]:
                    target = target[key]
                target[field[-1]] = value
                self.write("r.json", json.dumps(record))
                stderr = io.StringIO()
                with contextlib.redirect_stderr(stderr):
                    files = read_records(self.folder, "test")
                self.assertEqual(files.records, [])
                self.assertIn("does not match the record schema", stderr.getvalue())


class Completeness(support.TemporaryFolder):
    """The harness's isCompleteRecord (harness/record.cpp), field for field."""

    def test_the_fields_the_tables_need(self):
        good = support.fixture_record()
        self.assertTrue(is_complete_record(good))
        broken = [("format", "shadowbench-record/2"), ("complete", 1), ("mode", None),
                  ("resolution", 0), ("resolution", True), ("resolution", 1024.0),
                  ("size_bytes", {"total": "12"}), ("scene", {"spec": "city"}),
                  ("scheme", {"params": {}})]
        for key, value in broken:
            with self.subTest(key=key, value=value):
                self.assertFalse(is_complete_record({**good, key: value}))
        self.assertFalse(is_complete_record([good]))


class Fields(support.TemporaryFolder):

    def test_the_newest_of_a_cell_counts_and_a_tie_goes_to_the_later(self):
        old, new = {"created": "2026-01-01T00:00:00Z"}, {"created": "2026-02-01T00:00:00Z"}
        self.assertTrue(is_newer(old, None))
        self.assertTrue(is_newer(new, old))
        self.assertFalse(is_newer(old, new))
        self.assertTrue(is_newer(dict(old), old))

    def test_components_and_lookups(self):
        record = support.fixture_record("city-size-36-seed-1_0_closed_dag-mh_chunk-size-32_"
                                        "skip-level-6_treelet-height-4_1024.json")
        parts = record["size_bytes"]["components"]
        self.assertEqual(component_bytes(record, "inner nodes", "treelets"),
                         parts["inner nodes"] + parts["treelets"])
        self.assertIsNone(component_bytes(record, "inner nodes", "no such part"))
        timing = next(t for t in record["lookup"] if t["query_set"] == "view" and t["filter"] == 9)
        self.assertEqual(lookup_ns(record, "view", 9), timing["ns_per_query_1t"])
        self.assertIsNone(lookup_ns(record, "view", 2))
        self.assertIsNone(cache_hit_rate(record, "view", 9))
        self.assertEqual(cache_hit_rate({"lookup": [{**timing, "cache_hit_rate": 0.5}]}, "view", 9),
                         0.5)

    def test_a_shared_depth_pass_counts_the_depth_and_the_scheme_s_own_phases(self):
        alone = {"time_s": {"total": 30.0, "depth": 10.0, "phases": {"insert": 5.0}}}
        self.assertEqual(total_seconds(alone), 30.0)
        # Six schemes from one depth pass: the total is the whole group's wall time.
        shared = {"time_s": {"total": 3168.0, "depth": 557.0, "depth_shared_with": ["cpvs"],
                             "phases": {"insert": 22.0, "merge": 49.0}}}
        self.assertEqual(total_seconds(shared), 557.0 + 22.0 + 49.0)
        self.assertEqual(without_depth(shared), 22.0 + 49.0)
        self.assertIsNone(total_seconds({"time_s": {**shared["time_s"], "phases": {"x": "1"}}}))


class Duplicates(support.TemporaryFolder):
    """Of several records of one cell the newest is used and each other one is named."""

    def newest(self, *created):
        records = [{"cell": "c", "created": when, "file": i} for i, when in enumerate(created)]
        paths = [f"{i}.json" for i in range(len(records))]
        stderr = io.StringIO()
        with contextlib.redirect_stderr(stderr):
            newest = newest_per_cell(RecordFiles(records, paths, []), lambda r: r["cell"],
                                     lambda cell: f"cell {cell}", "test")
        return newest["c"], stderr.getvalue().splitlines()

    def test_an_older_record_is_named_beside_the_one_used(self):
        used, said = self.newest("2026-02-01T00:00:00Z", "2026-01-01T00:00:00Z")
        self.assertEqual(used["created"], "2026-02-01T00:00:00Z")
        self.assertEqual(said, ["test: '1.json' and '0.json' are records of one cell (cell c): "
                                "the first is not used (created 2026-01-01T00:00:00Z, the used "
                                "one 2026-02-01T00:00:00Z)"])

    def test_of_equal_times_the_later_file(self):
        used, said = self.newest("2026-01-01T00:00:00Z", "2026-01-01T00:00:00Z", "")
        self.assertEqual(used["file"], 1)
        self.assertEqual(len(said), 2)
        self.assertIn("test: '0.json' and '1.json' are records of one cell (cell c): the first "
                      "is not used (both created 2026-01-01T00:00:00Z; the later file is used)",
                      said)
        self.assertIn("test: '2.json' and '1.json' are records of one cell (cell c): the first "
                      "is not used (created at an unknown time, the used one "
                      "2026-01-01T00:00:00Z)", said)

    def test_one_record_per_cell_says_nothing(self):
        used, said = self.newest("2026-01-01T00:00:00Z")
        self.assertEqual(said, [])
