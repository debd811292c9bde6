"""Fixtures of the Python end-to-end tests: the satflock binary built by `cargo build --release`, and a
run directory made by it."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def satflock_bin() -> pathlib.Path:
    """The satflock binary: $SATFLOCK_BIN, or target/release/satflock (built by .ci/run first)."""
    path = pathlib.Path(os.environ.get("SATFLOCK_BIN", ROOT / "target" / "release" / "satflock"))
    if not path.exists():
        pytest.fail(f"no satflock binary at {path}: run `cargo build --release` or set SATFLOCK_BIN")
    return path


def run_satflock(binary: pathlib.Path, *args: str) -> subprocess.CompletedProcess:
    """Runs satflock with arguments; fails the test with its stderr if it exits non-zero."""
    done = subprocess.run([str(binary), *args], capture_output=True, text=True)
    if done.returncode != 0:
        pytest.fail(f"satflock {' '.join(args)} exited {done.returncode}:\n{done.stderr}")
    return done
