"""Paths and helpers shared by the tests of the Python scripts (scripts/, scripts/reproduce/).

Run with Debian's interpreter, which has matplotlib and jsonschema:
    /usr/bin/python3 -m unittest discover -s tests/python
"""

import contextlib
import json
import os
import shutil
import stat
import sys
import tempfile
import unittest
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPOSITORY = HERE.parent.parent
SCRIPTS = REPOSITORY / "scripts"
REPRODUCE = SCRIPTS / "reproduce"
for folder in (REPRODUCE, SCRIPTS):  # scripts/ first, as paper_tables.py puts it
    if str(folder) not in sys.path:
        sys.path.insert(0, str(folder))

FIXTURES = HERE / "fixtures"
FIXTURE_RECORDS = FIXTURES / "records"  # real records: 1K² (and some 512²) cells of every table
SCHEMES_JSON = FIXTURES / "schemes.json"  # `shadowbench schemes --json` of the registry's values
RECORD_SCHEMA = REPOSITORY / "harness" / "record.schema.json"


def require_record_schema(test):
    """Skips `test` (a TestCase) where the checkout has no record schema to validate against."""
    if not RECORD_SCHEMA.is_file():
        test.skipTest(f"{RECORD_SCHEMA.relative_to(REPOSITORY)} is absent: the record schema "
                      "comes with the records work of issue 11; run again once it is merged")


def fixture_record(name="city-size-36-seed-1_0_closed_mh_1024.json"):
    return json.loads((FIXTURE_RECORDS / name).read_text(encoding="utf-8"))


class TemporaryFolder(unittest.TestCase):
    """A TestCase with a fresh folder, self.folder, removed afterwards."""

    def setUp(self):
        self.folder = Path(tempfile.mkdtemp(prefix="shadowbench-py-test-"))
        self.addCleanup(shutil.rmtree, self.folder)

    def write(self, relative, text):
        path = self.folder / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        return path

    def fake_build(self, script_body):
        """A build folder whose harness/shadowbench runs `script_body` (sh), for
        SHADOWBENCH_BUILD."""
        binary = self.write("build/harness/shadowbench", "#!/bin/sh\n" + script_body + "\n")
        binary.chmod(binary.stat().st_mode | stat.S_IXUSR)
        return binary.parent.parent

    def registry_build(self):
        """A build folder whose shadowbench answers `schemes --json` with the fixture."""
        return self.fake_build(f'[ "$1 $2" = "schemes --json" ] && exec cat "{SCHEMES_JSON}"\n'
                               'echo "shadowbench: unexpected arguments: $*" >&2; exit 2')


def environment(**overrides):
    env = dict(os.environ)
    env.update({k: str(v) for k, v in overrides.items()})
    return env


@contextlib.contextmanager
def patched_environment(**values):
    """os.environ with `values` set (as strings) for the duration of the block."""
    saved = {k: os.environ.get(k) for k in values}
    os.environ.update({k: str(v) for k, v in values.items()})
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
