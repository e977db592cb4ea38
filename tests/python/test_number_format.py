"""scripts/number_format.py against the vectors the harness's formatter is held to."""

import csv
import unittest

import support
from number_format import KINDS, MISSING, integer, significant

GOLDEN = support.REPOSITORY / "tests" / "golden" / "number_format.tsv"


class SharedVectors(unittest.TestCase):

    def test_the_shared_vectors(self):
        if not GOLDEN.is_file():
            self.skipTest(f"{GOLDEN.relative_to(support.REPOSITORY)} is absent: the shared number "
                          "vectors come with the records work of issue 11; run again once it is "
                          "merged")
        with GOLDEN.open(encoding="utf-8", newline="") as file:
            rows = [row for row in csv.reader(file, delimiter="\t", quoting=csv.QUOTE_NONE)
                    if row and not row[0].startswith("#")]
        if rows and rows[0][:2] == ["value", "kind"]:
            rows = rows[1:]
        checked = 0
        for number, (value, kind, expected, *_) in enumerate(rows, 1):
            if kind not in KINDS:  # a kind only the harness prints
                continue
            with self.subTest(row=number, value=value, kind=kind):
                self.assertEqual(KINDS[kind](float(value)), expected)
            checked += 1
        kinds = sorted({row[1] for row in rows})
        self.assertGreater(checked, 0, f"no vector of a kind the scripts format among {kinds}")


class Significant(unittest.TestCase):
    """The harness's own cases (harness/record_test.cpp) and the edges of its algorithm."""

    def test_cases(self):
        cases = [(0.125, "0.125"), (99.96, "100"), (131072, "131072"), (3.2, "3.20"),
                 (0, "0"), (-0.0, "0"), (0.0517, "0.0517"), (9.996, "10.0"), (-2.5, "-2.50"),
                 (0.00012345, "0.000123"), (1e-20, "0.000000000000000"), (999.5, "1000"),
                 (float("inf"), "?"), (float("nan"), "?"), (None, MISSING)]
        for value, text in cases:
            with self.subTest(value=value):
                self.assertEqual(significant(value), text)

    def test_integers(self):
        for value, text in ((22241, "22241"), (0, "0"), (2.0**53, "9007199254740992"),
                            (float("inf"), "?"), (None, MISSING)):
            with self.subTest(value=value):
                self.assertEqual(integer(value), text)

    def test_digits(self):
        self.assertEqual(significant(3.14159, 5), "3.1416")
        self.assertEqual(significant(31.4159, 1), "31")
