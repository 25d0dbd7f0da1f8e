"""Fixtures of the Python tests (helpers.py holds the plain functions)."""

from __future__ import annotations

import os
import shutil

import pytest

from helpers import REPO


@pytest.fixture(scope="session")
def nffrt_bin() -> str:
    """The nffrt binary: $NFFRT_BIN, else target/release/nffrt or
    target/test-release/nffrt, else one on PATH."""
    candidates = [
        os.environ.get("NFFRT_BIN"),
        str(REPO / "target" / "release" / "nffrt"),
        str(REPO / "target" / "test-release" / "nffrt"),
    ]
    for c in candidates:
        if c and os.access(c, os.X_OK):
            return c
    found = shutil.which("nffrt")
    if found:
        return found
    pytest.skip("no nffrt binary: build it (cargo build --release) or set NFFRT_BIN")
