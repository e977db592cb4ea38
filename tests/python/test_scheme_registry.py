"""scripts/scheme_registry.py: the schemes' defaults from `shadowbench schemes --json`."""

import subprocess

import support
from scheme_registry import (RegistryUnavailable, parse_schemes_json, scheme_defaults,
                             shadowbench_binary)

# What `shadowbench schemes` prints (the registry's text output), written out independently of
# the JSON fixture: every scheme and the default of each parameter.
REGISTRY_DEFAULTS = {
    "compressed-sm": {"segment-span": "16384"}, "mh": {}, "openvdb": {}, "sm32": {},
    "cpvs": {"leaf-layout": "slab8", "grid-levels": "0"},
    "cpvs-fast": {"leaf-layout": "slab8", "grid-levels": "0", "culling": "on",
                  "transitions": "aligned", "coarse-classification": "masks"},
    "dag-mh": {"treelet-height": "4", "chunk-size": "32", "skip-level": "6"},
    "delta-dag": {"values": "simplest", "sharing": "dag", "addresses": "by-references",
                  "formats": "table", "symmetry": "mirrors", "copies": "cheaper",
                  "address-unit": "cheapest", "prediction": "plane", "address-widths": "each",
                  "skip-budget": "1024"},
    "mmh": {"search-distance": "1000", "interval-test": "both-ways",
            "relative-values": "key-deltas"},
    "sm-zstd": {"block": "64", "level": "3", "cache": "4"},
}


class Defaults(support.TemporaryFolder):

    def test_the_fixture_holds_the_registry_defaults(self):
        self.assertEqual(parse_schemes_json(support.SCHEMES_JSON.read_text(encoding="utf-8")),
                         REGISTRY_DEFAULTS)

    def test_read_from_the_binary_under_shadowbench_build(self):
        build = self.registry_build()
        with self.subTest("absolute"), support.patched_environment(SHADOWBENCH_BUILD=build):
            self.assertEqual(shadowbench_binary(), build / "harness" / "shadowbench")
            self.assertEqual(scheme_defaults(), REGISTRY_DEFAULTS)
        with self.subTest("relative: to the repository"), \
                support.patched_environment(SHADOWBENCH_BUILD="somewhere/build"):
            self.assertEqual(shadowbench_binary(),
                             support.REPOSITORY / "somewhere/build/harness/shadowbench")
        with self.subTest("unset or empty: build/"), \
                support.patched_environment(SHADOWBENCH_BUILD=""):
            self.assertEqual(shadowbench_binary(),
                             support.REPOSITORY / "build/harness/shadowbench")

    def test_a_missing_binary_says_how_to_get_one(self):
        with support.patched_environment(SHADOWBENCH_BUILD=self.folder / "nothing"):
            with self.assertRaises(RegistryUnavailable) as raised:
                scheme_defaults()
        said = str(raised.exception)
        self.assertIn(str(self.folder / "nothing/harness/shadowbench"), said)
        self.assertIn("SHADOWBENCH_BUILD", said)

    def test_a_failing_binary_passes_on_its_error(self):
        build = self.fake_build('echo "shadowbench: The following argument was not expected: '
                                '--json" >&2; exit 2')
        with support.patched_environment(SHADOWBENCH_BUILD=build):
            with self.assertRaises(RegistryUnavailable) as raised:
                scheme_defaults()
        self.assertIn("failed (exit status 2): shadowbench: The following argument was not "
                      "expected: --json", str(raised.exception))

    def test_output_that_is_not_the_agreed_json_is_refused(self):
        for text in ("compressed-sm depth scheme — …", '{"schemes": [{"name": "mmh"}]}',
                     '{"schemes": [{"name": "mmh", "params": [{"name": "search-distance", '
                     '"default": 1000}]}]}'):
            with self.subTest(text=text), self.assertRaises(RegistryUnavailable):
                parse_schemes_json(text)


class BuiltBinary(support.TemporaryFolder):
    """Where this checkout has a built shadowbench that exports its registry, the fixture must
    still say what it says."""

    def test_the_fixture_matches_the_built_registry(self):
        binary = shadowbench_binary()
        if not binary.is_file():
            self.skipTest(f"no built {binary}")
        done = subprocess.run([str(binary), "schemes", "--json"], capture_output=True, text=True,
                              check=False)
        if done.returncode != 0:
            self.skipTest(f"{binary} has no `schemes --json` yet: {done.stderr.strip()}")
        self.assertEqual(parse_schemes_json(done.stdout), REGISTRY_DEFAULTS)
