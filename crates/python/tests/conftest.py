"""Shared helpers: the repository root, the `trueaxis` command line and comparisons of JSON documents.

The command line is the reference of every binding: the tests run the built binary (the one of
`cargo build`, or TRUEAXIS_BIN) on the shipped examples and compare its --json output and its
error messages with the Python package's.
"""

import json
import math
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]


def trueaxis_binary() -> Path:
    given = os.environ.get("TRUEAXIS_BIN")
    if given:
        return Path(given)
    for profile in ("debug", "release"):
        path = ROOT / "target" / profile / "trueaxis"
        if path.exists():
            return path
    subprocess.run(["cargo", "build", "-p", "trueaxis-cli"], cwd=ROOT, check=True)
    return ROOT / "target" / "debug" / "trueaxis"


BIN = trueaxis_binary()


def pandas():
    """pandas (the optional dependency of the tables), skipping the test where it is not installed,
    unless TRUEAXIS_REQUIRE_PANDAS is set (CI, once installed)."""
    if os.environ.get("TRUEAXIS_REQUIRE_PANDAS"):
        import pandas as pd

        return pd
    return pytest.importorskip("pandas")


def run_cli(*args, cwd=ROOT):
    """Runs `trueaxis ARGS` in the repository root: (exit status, stdout, stderr)."""
    p = subprocess.run([str(BIN), *map(str, args)], cwd=cwd, capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def cli_json(*args, cwd=ROOT):
    code, out, err = run_cli(*args, "--json", cwd=cwd)
    assert code == 0, f"trueaxis {' '.join(map(str, args))}: exit {code}: {err}"
    return json.loads(out)


def cli_error(*args, cwd=ROOT):
    """(exit status, message) of a command that fails; the message without `trueaxis: error: `."""
    code, _, err = run_cli(*args, cwd=cwd)
    assert code != 0, f"trueaxis {' '.join(map(str, args))} succeeded"
    lines = [l for l in err.splitlines() if l.startswith("trueaxis: error: ")]
    assert len(lines) == 1, err
    return code, lines[0][len("trueaxis: error: "):]


def assert_same(a, b, rel=1e-9, path="$"):
    """Same keys, same strings, numbers equal to `rel` (relative, absolute below 1)."""
    if isinstance(a, dict):
        assert isinstance(b, dict), path
        assert set(a) == set(b), f"{path}: keys {sorted(set(a) ^ set(b))} differ"
        for k in a:
            assert_same(a[k], b[k], rel, f"{path}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), f"{path}: lengths differ"
        for i, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, rel, f"{path}[{i}]")
    elif isinstance(a, (int, float)) and not isinstance(a, bool) and isinstance(b, (int, float)):
        assert math.isclose(a, b, rel_tol=rel, abs_tol=rel), f"{path}: {a} != {b}"
    else:
        assert a == b, f"{path}: {a!r} != {b!r}"


@pytest.fixture
def root():
    return ROOT


@pytest.fixture(scope="session")
def small_campaign(tmp_path_factory):
    """The KX8-Five CapBall campaign on every 20th pose (41 records): a candidate set small enough
    for the exchange algorithm in a debug build."""
    src = ROOT / "examples" / "campaigns" / "kx8five"
    lines = (src / "capball.csv").read_text().splitlines()
    rows = [l for l in lines if not l.startswith("#")]
    d = tmp_path_factory.mktemp("small_campaign")
    (d / "capball.csv").write_text("\n".join([rows[0]] + rows[1::20]) + "\n")
    (d / "campaign.toml").write_text((src / "campaign.toml").read_text())
    return d / "campaign.toml"
