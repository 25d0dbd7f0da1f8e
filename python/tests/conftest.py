"""Fixtures and hooks of the Python tests (helpers.py holds the plain functions).

Skips are said as the Rust tests say them (tests/common/skip.rs): each is appended
to ``$NFFRT_SKIP_LOG`` as ``SKIPPED: <test>: <reason>`` for the summary of
``scripts/test-all.sh``, and with ``NFFRT_REQUIRE_SHARED=1`` (``.ci/run``) a skip
for want of ``../shared`` is a failure: a check CI expects to run cannot pass by
not running.
"""

from __future__ import annotations

import os
import shutil

import pytest

from helpers import REPO, SHARED_ABSENT


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


def _skip_reason(report: pytest.TestReport) -> str:
    """The reason a skipped report gives (pytest keeps it as (file, line, reason))."""
    longrepr = report.longrepr
    reason = longrepr[2] if isinstance(longrepr, tuple) else str(longrepr)
    return reason.removeprefix("Skipped: ")


def _is_shared_skip(reason: str) -> bool:
    return reason == SHARED_ABSENT or reason.endswith("is absent from ../shared")


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    report = outcome.get_result()
    if not report.skipped:
        return
    reason = _skip_reason(report)
    if os.environ.get("NFFRT_REQUIRE_SHARED") == "1" and _is_shared_skip(reason):
        report.outcome = "failed"
        report.longrepr = f"NFFRT_REQUIRE_SHARED=1 but this test skipped: {reason}"
        return
    log = os.environ.get("NFFRT_SKIP_LOG")
    if log:
        test = "python::" + item.nodeid.replace(" ", "_")
        with open(log, "a", encoding="utf-8") as f:
            f.write(f"SKIPPED: {test}: {reason}\n")
