"""The scheme registry as the harness exports it (`shadowbench schemes --json`): the scripts
take every scheme's parameter defaults from there instead of keeping a copy.

The binary is ${SHADOWBENCH_BUILD:-build}/harness/shadowbench, a relative SHADOWBENCH_BUILD
being relative to the repository root (as scripts/reproduce/common.sh builds it).
"""

import json
import os
import subprocess
from pathlib import Path

REPOSITORY = Path(__file__).resolve().parent.parent


class RegistryUnavailable(RuntimeError):
    """The registry could not be read; the message says why and what to do."""


def shadowbench_binary():
    return REPOSITORY / (os.environ.get("SHADOWBENCH_BUILD") or "build") / "harness" / "shadowbench"


def parse_schemes_json(text, source="shadowbench schemes --json"):
    """{scheme: {parameter: default}} from the text of `shadowbench schemes --json`
    (/work/notes/interfaces.md); defaults are strings, as records store parameter values."""
    try:
        document = json.loads(text)
        defaults = {}
        for scheme in document["schemes"]:
            params = {}
            for param in scheme["params"]:
                if not isinstance(param["name"], str) or not isinstance(param["default"], str):
                    raise TypeError(f"parameter {param!r} of {scheme['name']}: name and default "
                                    "must be strings")
                params[param["name"]] = param["default"]
            defaults[scheme["name"]] = params
        return defaults
    except (ValueError, KeyError, TypeError) as error:
        raise RegistryUnavailable(f"{source} is not the registry's JSON "
                                  f"({type(error).__name__}: {error})") from error


def scheme_defaults(binary=None):
    """{scheme: {parameter: default}} of every scheme the shadowbench binary registers."""
    binary = Path(binary) if binary else shadowbench_binary()
    command = f"{binary} schemes --json"
    if not binary.is_file():
        raise RegistryUnavailable(
            f"the scheme defaults come from `{command}`, and {binary} does not exist: build it "
            "(cmake --build build --target shadowbench) or set SHADOWBENCH_BUILD to its build "
            "folder")
    try:
        done = subprocess.run([str(binary), "schemes", "--json"], capture_output=True, text=True,
                              check=False)
    except OSError as error:
        raise RegistryUnavailable(f"`{command}` could not run: {error}") from error
    if done.returncode != 0:
        said = done.stderr.strip().splitlines()
        raise RegistryUnavailable(f"`{command}` failed (exit status {done.returncode})"
                                  + (f": {said[-1]}" if said else ""))
    return parse_schemes_json(done.stdout, f"the output of `{command}`")
