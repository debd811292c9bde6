"""Shared fixtures of the Python package's tests: short scenarios and the CLI binary."""

import os
import pathlib

import pytest

import satflock

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture
def short_hold():
    """The built-in `hold` scenario cut to 300 s (20 satellites, sampled at 1 s, records every 10 s),
    with its law event removed and its thruster failure moved to t = 150 s."""
    scenario = satflock.Scenario.load("hold")
    scenario.update(
        {
            "duration_s": 300.0,
            "events": [
                {"time_s": 150.0, "action": "fail-thruster", "satellite": 3, "axis": "y"}
            ],
        }
    )
    return scenario


@pytest.fixture(scope="session")
def satflock_bin() -> pathlib.Path:
    """The CLI binary, an independent path to compare the package with: $SATFLOCK_BIN (CI sets it; a
    path that is not an executable fails), else target/release/satflock if built, else the test is
    skipped."""
    given = os.environ.get("SATFLOCK_BIN")
    if given:
        path = pathlib.Path(given)
        if not os.access(path, os.X_OK):
            pytest.fail(f"SATFLOCK_BIN={path} is not an executable file")
        return path
    path = ROOT / "target" / "release" / "satflock"
    if not os.access(path, os.X_OK):
        pytest.skip("no satflock binary: set SATFLOCK_BIN or run `cargo build --release`")
    return path
