"""scripts/views_tables.py: the interpolations that answer the issue's questions, on hand-made
curves, and the tables of a small folder of view records."""

import contextlib
import io
import json
import sys
from unittest import mock

import support

import views_tables


def view_record(label, kind, memory, error, name="csm", params=None, structure=None):
    return {"format": "shadowbench-view-record", "version": 1,
            "scene": {"spec": "city:full", "name": "city", "hash": "0" * 16, "triangles": 1},
            "path": {"name": "city-walk", "file": "scenes/paths/city-full.json", "frames": 2,
                     "width": 16, "height": 9},
            "technique": {"name": name, "kind": kind, "label": label, "params": params or {},
                          "structure": structure},
            "totals": {"covered": 100, "false_lit": 1, "false_shadow": 2, "boundary": 10,
                       "boundary_false_lit": 1, "boundary_false_shadow": 1, "error_rate": error,
                       "boundary_error_rate": 0.2, "memory_bytes": memory, "build_ms_median": 3.0,
                       "shade_ms_median": 2.0},
            "frames": [], "created": "2026-12-04T19:00:00Z"}


class Interpolation(support.TemporaryFolder):

    def test_error_at_a_memory_is_linear_in_log_memory(self):
        points = [(1.0, 0.4, 0), (100.0, 0.2, 1)]
        self.assertAlmostEqual(views_tables.interpolate(points, 10.0, 0, 1), 0.3)
        self.assertIsNone(views_tables.interpolate(points, 1000.0, 0, 1))  # never extrapolated
        self.assertEqual(views_tables.interpolate(points, 100.0, 0, 1), 0.2)

    def test_the_memory_that_matches_an_error(self):
        points = [(1.0, 0.4), (100.0, 0.2), (10000.0, 0.1)]
        self.assertAlmostEqual(views_tables.crossing_memory(points, 0.3), 10.0)
        self.assertAlmostEqual(views_tables.crossing_memory(points, 0.15), 1000.0)
        self.assertIsNone(views_tables.crossing_memory(points, 0.05))
        self.assertEqual(views_tables.crossing_memory(points, 0.5), 1.0)

    def test_tables_of_a_folder(self):
        csm = view_record("csm (cascades=3)", "view-dependent", 12 * 2**20, 0.01,
                          params={"cascades": "3", "resolution": "1024"})
        records = [csm]
        for resolution, memory, error in ((1024, 2**20, 0.04), (4096, 16 * 2**20, 0.005)):
            structure = {"scheme": "sm32", "params": {}, "mode": "closed", "resolution": resolution}
            records.append(view_record(f"sm32 {resolution}", "precomputed", memory, error, "sm32",
                                       structure=structure))
        for n, record in enumerate(records):
            (self.folder / f"{n}.json").write_text(json.dumps(record))
        (self.folder / "other.json").write_text(json.dumps({"format": "something else"}))
        out = io.StringIO()
        argv = ["views_tables.py", str(self.folder)]
        with contextlib.redirect_stdout(out), mock.patch.object(sys, "argv", argv):
            views_tables.main()
        text = out.getvalue()
        self.assertIn("## city-walk: city:full, 2 frames at 16×9", text)
        # 0.01 lies 6/7 of the way from 0.04 at 1 MiB to 0.005 at 16 MiB: 16^(6/7) MiB.
        self.assertIn(f"| sm32 | closed | 1K, 4K | {16 ** (6 / 7):.2f} |", text)
        self.assertIn("| paper: Village (IASM) | 2.3 | 28.6 | 1.9 | 38.1 |", text)
        self.assertIn("| ours (CPU): csm (cascades=3) | – | 3.0 | 2.0 | 5.0 |", text)
