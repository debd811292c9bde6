"""Shared fixtures of the Python package's tests."""

import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def satflock_bin() -> pathlib.Path:
    """The CLI binary, an independent path to compare the package with: $SATFLOCK_BIN, or
    target/release/satflock (.ci/run builds it first)."""
    path = pathlib.Path(os.environ.get("SATFLOCK_BIN", ROOT / "target" / "release" / "satflock"))
    if not path.exists():
        pytest.fail(f"no satflock binary at {path}: run `cargo build --release` or set SATFLOCK_BIN")
    return path
