"""Shared fixtures of the satflock package tests."""

import os

import pytest


@pytest.fixture(scope="session")
def satflock_bin():
    """The `satflock` command-line binary named by SATFLOCK_BIN (the test is skipped without it)."""
    path = os.environ.get("SATFLOCK_BIN")
    if not path:
        pytest.skip("SATFLOCK_BIN is not set: no satflock binary to compare with")
    if not os.access(path, os.X_OK):
        pytest.fail(f"SATFLOCK_BIN={path} is not an executable file")
    return path
